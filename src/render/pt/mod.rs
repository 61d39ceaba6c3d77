//! Projected tetrahedra (Shirley and Tuchman 1990) on the CPU: classify each projected tet,
//! rasterize its silhouette exactly in fixed point, and composite (Sf, Sb, l) fragments front to
//! back in parallel screen tiles that each honour the global visibility order.
//!
//! Classification: the four faces' projected signed areas `D_i` (exact, on the 1/256-pixel grid)
//! split into a positive and a negative group (they sum to zero). Class 1 is 3+1 (one vertex inside
//! the triangle of the others), class 2 is 2+2 (two edges cross: the thick point), class 3 is
//! 2+1+one zero (a vertex on an edge: a face seen edge-on), class 4 is 1+1+two zeros (two vertices
//! coincide: an edge seen end-on); all-zero is a flat projection that covers no area. Each
//! Shirley-Tuchman triangle pairs one front face with one back face, and the thick point is where
//! the pairing changes; rather than cut triangles at a rounded thick point (which would leave
//! hairline gaps or double hits inside a tet), each pixel of the exactly rasterized silhouette takes
//! its entry depth from the farthest front-face plane and its exit from the nearest back-face
//! plane, which is the same pairing with no rounding. Depth is carried as `1/z` (perspective) or
//! `z` (parallel), both linear in screen space, and the scalar as a linear function plus depth
//! times a linear function, so (Sf, Sb, l) are exact under perspective too.

mod chunks;
mod classify;
mod clip;
mod exact;
mod raster;
#[cfg(target_arch = "x86_64")]
mod raster_x86;
mod setup;
mod shade;
#[cfg(test)]
mod tests;
mod tiles;
mod view;

pub use classify::{classify, face_areas, ProjClass, FACES};
pub(crate) use clip::{pixel_ray, ClipSetup};
pub(crate) use setup::{fragment_span, TetSetup};
pub use shade::Shader;
pub(crate) use tiles::{render_tiles, Frame, PrepKind, Run, Tile, TileDraw};
pub(crate) use view::stretch_map;
pub use view::{project_points, Projected, View};

use super::field::Field;
use super::image::Image;
pub(crate) use crate::mem::{collapse_huge, huge_pages};
use chunks::render_chunks;
use tiles::PlainDraw;

/// Tile side in pixels.
pub const TILE: usize = 64;
/// Sub-pixel bits of the fixed-point rasterizer.
pub(crate) const SUB: i64 = 256;
/// Vertices farther than this from the image (in fixed point) are not rasterized.
const GUARD: f64 = (1i64 << 28) as f64;
/// A pixel whose opacity passed this takes no more fragments (error below 1/2048).
pub(crate) const OPAQUE: f32 = 1.0 - 1.0 / 2048.0;

/// Asks the CPU to start loading the cache line holding `p` into all cache levels: a hint that
/// never faults, whatever the address.
#[inline(always)]
pub(crate) fn prefetch<T>(p: *const T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch reads nothing the program sees and never faults.
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        _mm_prefetch::<_MM_HINT_T0>(p.cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

/// Pixel box (x0, y0, x1, y1), inclusive.
pub(crate) type PixelBox = (i64, i64, i64, i64);

/// Counts of what the rasterizer saw, for reports.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PtStats {
    pub class: [u64; 5],
    /// Tets with a vertex behind the eye (perspective) or outside the guard band, drawn by the
    /// per-pixel clipping path instead of the rasterizer.
    pub clipped: u64,
    /// Tets the rasterizer could take but the clipping path draws, since a face seen nearly
    /// edge-on lies on a pixel centre (see `setup::snapped_sliver`); also counted in `class`.
    pub per_pixel: u64,
    pub fragments: u64,
    /// Tets not set up because every pixel they could cover was already opaque (the tile
    /// schedule's early termination; 0 elsewhere).
    pub hidden: u64,
    /// Tets left out before set-up because the transfer function draws nothing over their
    /// whole scalar range (every fragment exactly zero; not classified).
    pub clear: u64,
}

impl PtStats {
    pub(crate) fn add(&mut self, o: &PtStats) {
        for k in 0..5 {
            self.class[k] += o.class[k];
        }
        self.clipped += o.clipped;
        self.per_pixel += o.per_pixel;
        self.fragments += o.fragments;
        self.hidden += o.hidden;
        self.clear += o.clear;
    }
}

/// Per-frame timings of the PT stages, in seconds.
#[derive(Clone, Copy, Debug, Default)]
pub struct PtTimes {
    pub project: f64,
    pub bin: f64,
    pub raster: f64,
}

/// How the CPU's threads share a PT frame. Both give the same image up to float rounding, and
/// each is deterministic under any thread count.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Schedule {
    /// Screen tiles in parallel, each walking the tets binned to it in the global order; a tile
    /// stops once all its pixels are opaque.
    #[default]
    Tiles,
    /// The order cut into [`CHUNKS`] consecutive runs (a K-D tree's leaves are such runs; any
    /// cut of a visibility order is one), each rendered in parallel into its own buffer over its
    /// screen box, the buffers then composited front to back.
    Chunks,
}

/// Runs of the order for [`Schedule::Chunks`]: fixed, so the image does not depend on the
/// thread count.
pub const CHUNKS: usize = 16;

/// Renders tets in the given front-to-back order (any order is accepted; only a visibility order
/// gives a correct image), with the default [`Schedule`].
pub fn render(
    view: &View,
    points: &[[f64; 3]],
    tets: &[[u32; 4]],
    field: &Field,
    order: &[u32],
    shader: &Shader,
) -> (Image, PtStats, PtTimes) {
    render_with(
        view,
        points,
        tets,
        field,
        order,
        shader,
        Schedule::default(),
    )
}

/// [`render`] with a chosen [`Schedule`].
pub fn render_with(
    view: &View,
    points: &[[f64; 3]],
    tets: &[[u32; 4]],
    field: &Field,
    order: &[u32],
    shader: &Shader,
    schedule: Schedule,
) -> (Image, PtStats, PtTimes) {
    let (proj, stretch, project) = projected(view, points);
    draw_projected(
        view, tets, field, order, shader, schedule, &proj, &stretch, project,
    )
}

/// The points projected for `view`, the view's stretch map, and the seconds both took.
fn projected(view: &View, points: &[[f64; 3]]) -> (Vec<Projected>, Vec<f32>, f64) {
    let t0 = std::time::Instant::now();
    let proj = project_points(view, points);
    let stretch = stretch_map(view);
    (proj, stretch, t0.elapsed().as_secs_f64())
}

/// [`render_with`] for an order that `sort` makes while the points are projected: a sort
/// has stretches one core runs alone (a leaf's peel), which the projection fills. Returns
/// what `sort` returned besides the order, too.
pub fn render_sorting<T: Send>(
    view: &View,
    points: &[[f64; 3]],
    tets: &[[u32; 4]],
    field: &Field,
    shader: &Shader,
    schedule: Schedule,
    sort: impl FnOnce() -> (Vec<u32>, T) + Send,
) -> (Image, PtStats, PtTimes, T) {
    let ((order, extra), (proj, stretch, project)) = rayon::join(sort, || projected(view, points));
    let (img, stats, times) = draw_projected(
        view, tets, field, &order, shader, schedule, &proj, &stretch, project,
    );
    (img, stats, times, extra)
}

/// Draws the tets in `order` from their projected points; `project` is the seconds the
/// projection took, for the times returned.
#[allow(clippy::too_many_arguments)]
fn draw_projected(
    view: &View,
    tets: &[[u32; 4]],
    field: &Field,
    order: &[u32],
    shader: &Shader,
    schedule: Schedule,
    proj: &[Projected],
    stretch: &[f32],
    project: f64,
) -> (Image, PtStats, PtTimes) {
    collapse_huge(tets);
    let t1 = std::time::Instant::now();
    let frame = Frame {
        view,
        tets,
        field,
        proj,
        stretch,
    };
    let (img, stats, bin_s) = match schedule {
        Schedule::Tiles => {
            let (img, stats, bin_s, _) = render_tiles(
                &frame,
                order,
                &PlainDraw {
                    frame: &frame,
                    shader,
                },
            );
            (img, stats, bin_s)
        }
        Schedule::Chunks => render_chunks(&frame, shader, order),
    };
    let t3 = std::time::Instant::now();
    (
        img,
        stats,
        PtTimes {
            project,
            bin: bin_s,
            raster: (t3 - t1).as_secs_f64() - bin_s,
        },
    )
}
