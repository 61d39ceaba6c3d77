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

// Negated comparisons are deliberate: they also catch NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::field::Field;
use super::image::Image;
use super::integrate::{FastTf, Integration, PreintTable};
use crate::camera::Camera;
use rayon::prelude::*;

/// Tile side in pixels.
pub const TILE: usize = 32;
/// Sub-pixel bits of the fixed-point rasterizer.
pub(crate) const SUB: i64 = 256;
/// Vertices farther than this from the image (in fixed point) are not rasterized.
const GUARD: f64 = (1i64 << 28) as f64;
/// A pixel whose opacity passed this takes no more fragments (error below 1/2048).
pub(crate) const OPAQUE: f32 = 1.0 - 1.0 / 2048.0;

/// The camera reduced to what projection needs.
#[derive(Clone, Copy, Debug)]
pub struct View {
    pub width: u32,
    pub height: u32,
    pub eye: [f64; 3],
    pub r: [f64; 3],
    pub u: [f64; 3],
    pub f: [f64; 3],
    pub parallel: bool,
    /// tan(half view angle) (perspective) or parallel scale.
    pub scale: f64,
    pub aspect: f64,
}

impl View {
    pub fn new(cam: &Camera, width: u32, height: u32) -> View {
        let (r, u, f) = cam.frame();
        View {
            width,
            height,
            eye: cam.position,
            r,
            u,
            f,
            parallel: cam.parallel,
            scale: if cam.parallel {
                cam.parallel_scale
            } else {
                (0.5 * cam.view_angle).to_radians().tan()
            },
            aspect: width as f64 / height as f64,
        }
    }

    /// View coordinates (right, up, forward depth) of a world point.
    #[inline]
    pub fn to_view(&self, p: &[f64; 3]) -> [f64; 3] {
        let d = [p[0] - self.eye[0], p[1] - self.eye[1], p[2] - self.eye[2]];
        let dot = |a: &[f64; 3]| d[0] * a[0] + d[1] * a[1] + d[2] * a[2];
        [dot(&self.r), dot(&self.u), dot(&self.f)]
    }

    /// Screen x of view coordinates (pixels, y down).
    #[inline]
    fn screen(&self, v: &[f64; 3]) -> (f64, f64) {
        let (sx, sy) = if self.parallel {
            (v[0] / self.scale, v[1] / self.scale)
        } else {
            (v[0] / (v[2] * self.scale), v[1] / (v[2] * self.scale))
        };
        (
            (sx / self.aspect + 1.0) * 0.5 * self.width as f64,
            (1.0 - sy) * 0.5 * self.height as f64,
        )
    }

    /// Screen-plane coordinates (xs, ys) of a pixel position, in units of `scale`: the view ray
    /// is (scale xs, scale ys, 1) (perspective) or starts at (scale xs, scale ys, 0) (parallel).
    #[inline]
    pub fn screen_plane(&self, px: f64, py: f64) -> (f64, f64) {
        (
            (2.0 * px / self.width as f64 - 1.0) * self.aspect,
            1.0 - 2.0 * py / self.height as f64,
        )
    }

    /// World length of the view ray per unit of depth through a pixel position.
    pub fn stretch(&self, px: f64, py: f64) -> f64 {
        if self.parallel {
            1.0
        } else {
            let (xs, ys) = self.screen_plane(px, py);
            (1.0 + (self.scale * xs).powi(2) + (self.scale * ys).powi(2)).sqrt()
        }
    }
}

/// A mesh point after projection.
#[derive(Clone, Copy, Debug, Default)]
pub struct Projected {
    pub view: [f64; 3],
    pub px: f64,
    pub py: f64,
    /// Fixed-point screen position (1/256 pixel).
    pub fx: i64,
    pub fy: i64,
    /// Usable: in front of the eye and inside the guard band.
    pub ok: bool,
}

/// Projects every point (in parallel).
pub fn project_points(view: &View, points: &[[f64; 3]]) -> Vec<Projected> {
    let near = 1e-9;
    points
        .par_iter()
        .map(|p| {
            let v = view.to_view(p);
            if !view.parallel && !(v[2] > near) {
                return Projected {
                    view: v,
                    ..Default::default()
                };
            }
            let (px, py) = view.screen(&v);
            let (sx, sy) = (px * SUB as f64, py * SUB as f64);
            let ok = sx.abs() < GUARD && sy.abs() < GUARD && v.iter().all(|c| c.is_finite());
            Projected {
                view: v,
                px,
                py,
                fx: if ok { sx.round() as i64 } else { 0 },
                fy: if ok { sy.round() as i64 } else { 0 },
                ok,
            }
        })
        .collect()
}

/// Shirley-Tuchman projection class of a tet.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProjClass {
    /// 3 + 1: one vertex projects inside the triangle of the other three.
    One,
    /// 2 + 2: two edges cross at the thick point; the silhouette is a quadrilateral.
    Two,
    /// 2 + 1 + one flat face: a vertex on the opposite edge.
    Three,
    /// 1 + 1 + two flat faces: two vertices coincide.
    Four,
    /// Zero projected area.
    Flat,
}

/// Face `i` is opposite vertex `i`; vertex orders make the four faces consistently oriented.
pub const FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];

#[inline]
fn orient2(a: (i64, i64), b: (i64, i64), c: (i64, i64)) -> i64 {
    (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
}

/// Projected signed areas of the four faces (twice the area, 1/256-pixel units squared).
#[inline]
pub fn face_areas(p: &[(i64, i64); 4]) -> [i64; 4] {
    FACES.map(|f| orient2(p[f[0]], p[f[1]], p[f[2]]))
}

pub fn classify(d: &[i64; 4]) -> ProjClass {
    let pos = d.iter().filter(|&&v| v > 0).count();
    let neg = d.iter().filter(|&&v| v < 0).count();
    match (pos, neg) {
        (3, 1) | (1, 3) => ProjClass::One,
        (2, 2) => ProjClass::Two,
        (2, 1) | (1, 2) => ProjClass::Three,
        (1, 1) => ProjClass::Four,
        _ => ProjClass::Flat,
    }
}

/// Per-pixel shading of a fragment.
pub enum Shader {
    Average(FastTf),
    Linear(FastTf),
    Pre(PreintTable),
}

impl Shader {
    pub fn mode(&self) -> Integration {
        match self {
            Shader::Average(_) => Integration::Average,
            Shader::Linear(_) => Integration::Linear,
            Shader::Pre(_) => Integration::Preintegrated,
        }
    }
}

/// An edge of the silhouette: inside where `a x + b y + c > 0`, or `== 0` when `own`.
#[derive(Clone, Copy)]
pub(crate) struct Edge {
    pub(crate) a: i64,
    pub(crate) b: i64,
    pub(crate) c: i64,
    pub(crate) bias: i64,
}

impl TetSetup {
    /// The silhouette's edges: the first [`TetSetup::nedges`] entries.
    #[inline(always)]
    pub(crate) fn edges(&self) -> [Edge; 4] {
        let n = self.nedges as usize;
        let p = |k: usize| {
            let q = self.poly[k % n];
            (q[0] as i64, q[1] as i64)
        };
        [0, 1, 2, 3].map(|e| Edge::new(p(e), p(e + 1)))
    }

    /// Pixel bounds (x0, x1, y0, y1), inclusive, clipped to `tile` (x0, y0, x1, y1); `None`
    /// when they miss it.
    #[inline(always)]
    pub(crate) fn clip(&self, tile: (i64, i64, i64, i64)) -> Option<(i64, i64, i64, i64)> {
        let (tx0, ty0, tx1, ty1) = tile;
        let b = (
            (self.x0 as i64).max(tx0),
            (self.x1 as i64).min(tx1),
            (self.y0 as i64).max(ty0),
            (self.y1 as i64).min(ty1),
        );
        (b.0 <= b.1 && b.2 <= b.3).then_some(b)
    }
}

impl Edge {
    /// Edge from `p` to `q` of a positively oriented polygon.
    #[inline]
    fn new(p: (i64, i64), q: (i64, i64)) -> Edge {
        let (dx, dy) = (q.0 - p.0, q.1 - p.1);
        // E(x, y) = dx (y - py) - dy (x - px); owner rule is antisymmetric in the direction, so a
        // pixel centre on an edge shared by two silhouettes lies in exactly one of them.
        let own = dy < 0 || (dy == 0 && dx > 0);
        Edge {
            a: -dy,
            b: dx,
            c: dy * p.0 - dx * p.1,
            bias: if own { 0 } else { -1 },
        }
    }
}

/// Everything one tet needs per pixel, set up once per frame from its projected vertices and
/// kept compact (f32, fixed-point corners), since a frame holds one per drawn tet.
#[derive(Clone, Copy)]
pub(crate) struct TetSetup {
    /// Silhouette corners (fixed point), positively oriented: `nedges` of them.
    pub(crate) poly: [[i32; 2]; 4],
    pub(crate) nedges: u32,
    /// Pixel bounds, inclusive.
    pub(crate) x0: i32,
    pub(crate) x1: i32,
    pub(crate) y0: i32,
    pub(crate) y1: i32,
    pub(crate) ox: f32,
    pub(crate) oy: f32,
    /// Face depth planes relative to vertex 0: delta = c + ax dx + ay dy. Unused slots repeat
    /// a used plane, so min and max may take all three.
    pub(crate) front: [[f32; 3]; 3],
    pub(crate) back: [[f32; 3]; 3],
    pub(crate) w0: f32,
    /// Scalar at vertex 0's depth along the pixel's ray, and its change per unit of depth.
    pub(crate) sref: [f32; 3],
    pub(crate) h: [f32; 3],
    pub(crate) smin: f32,
    pub(crate) smax: f32,
}

/// Counts of what the rasterizer saw, for reports.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PtStats {
    pub class: [u64; 5],
    /// Tets with a vertex behind the eye (perspective) or outside the guard band, drawn by the
    /// per-pixel clipping path instead of the rasterizer.
    pub clipped: u64,
    pub fragments: u64,
}

impl PtStats {
    fn add(&mut self, o: &PtStats) {
        for k in 0..5 {
            self.class[k] += o.class[k];
        }
        self.clipped += o.clipped;
        self.fragments += o.fragments;
    }
}

fn class_index(c: ProjClass) -> usize {
    match c {
        ProjClass::One => 0,
        ProjClass::Two => 1,
        ProjClass::Three => 2,
        ProjClass::Four => 3,
        ProjClass::Flat => 4,
    }
}

/// Linear function through three screen points: value at `(ox, oy)` and slopes.
#[inline(always)]
fn plane_fit(p: [(f64, f64); 3], v: [f64; 3], ox: f64, oy: f64) -> Option<[f64; 3]> {
    let (e1x, e1y) = (p[1].0 - p[0].0, p[1].1 - p[0].1);
    let (e2x, e2y) = (p[2].0 - p[0].0, p[2].1 - p[0].1);
    let det = e1x * e2y - e1y * e2x;
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let (d1, d2) = (v[1] - v[0], v[2] - v[0]);
    let ax = (d1 * e2y - d2 * e1y) / det;
    let ay = (d2 * e1x - d1 * e2x) / det;
    let c = v[0] + ax * (ox - p[0].0) + ay * (oy - p[0].1);
    (ax.is_finite() && ay.is_finite() && c.is_finite()).then_some([c, ax, ay])
}

#[inline(always)]
pub(crate) fn setup_tet(
    view: &View,
    pv: [&Projected; 4],
    s: [f64; 4],
    stats: &mut PtStats,
) -> Option<TetSetup> {
    if pv.iter().any(|p| !p.ok) {
        stats.clipped += 1;
        return None;
    }
    let fp = pv.map(|p| (p.fx, p.fy));
    let d = face_areas(&fp);
    let class = classify(&d);
    stats.class[class_index(class)] += 1;
    if class == ProjClass::Flat {
        return None;
    }
    // Silhouette, positively oriented.
    let (mut pos, mut np) = ([0usize; 4], 0);
    let (mut neg, mut nn) = ([0usize; 4], 0);
    for (i, &di) in d.iter().enumerate() {
        if di > 0 {
            pos[np] = i;
            np += 1;
        } else if di < 0 {
            neg[nn] = i;
            nn += 1;
        }
    }
    let mut poly = [(0i64, 0i64); 4];
    let nedges;
    if np == 1 || nn == 1 {
        let lone = if np == 1 { pos[0] } else { neg[0] };
        let f = FACES[lone];
        let tri = if d[lone] > 0 {
            [fp[f[0]], fp[f[1]], fp[f[2]]]
        } else {
            [fp[f[0]], fp[f[2]], fp[f[1]]]
        };
        poly[..3].copy_from_slice(&tri);
        nedges = 3;
    } else {
        // 2 + 2: the positive faces i, j share edge k-l; diagonals i-j and k-l cross.
        let (i, j) = (pos[0], pos[1]);
        let (k, l) = (neg[0], neg[1]);
        let q = if orient2(fp[i], fp[k], fp[j]) > 0 {
            [i, k, j, l]
        } else {
            [i, l, j, k]
        };
        for (n, &v) in q.iter().enumerate() {
            poly[n] = fp[v];
        }
        nedges = 4;
    }
    let (mut xmin, mut xmax, mut ymin, mut ymax) = (i64::MAX, i64::MIN, i64::MAX, i64::MIN);
    for p in &fp {
        xmin = xmin.min(p.0);
        xmax = xmax.max(p.0);
        ymin = ymin.min(p.1);
        ymax = ymax.max(p.1);
    }
    // Pixel centres at 256 i + 128 inside [min, max].
    let lo = |v: i64| (v - SUB / 2 + SUB - 1).div_euclid(SUB);
    let hi = |v: i64| (v - SUB / 2).div_euclid(SUB);
    let (x0, x1, y0, y1) = (
        lo(xmin).max(0),
        hi(xmax).min(view.width as i64 - 1),
        lo(ymin).max(0),
        hi(ymax).min(view.height as i64 - 1),
    );
    if x0 > x1 || y0 > y1 {
        return None;
    }

    // Depth planes: w = 1/z (perspective) or z (parallel), relative to vertex 0.
    let w = |p: &Projected| {
        if view.parallel {
            p.view[2]
        } else {
            1.0 / p.view[2]
        }
    };
    let w0 = w(pv[0]);
    let (ox, oy) = (pv[0].px, pv[0].py);
    // Which sign group faces the eye: decided in 3-D on the face with the largest projection.
    let big = (0..4).max_by_key(|&i| d[i].abs()).unwrap_or(0);
    let fv = FACES[big].map(|k| pv[k].view);
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cr = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let dt = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let n = cr(sub(fv[1], fv[0]), sub(fv[2], fv[0]));
    let vside = dt(n, sub(pv[big].view, fv[0]));
    let eside = if view.parallel { -n[2] } else { -dt(n, fv[0]) };
    // Front when the eye and the opposite vertex are on different sides of the face plane.
    let big_front = (vside > 0.0) != (eside > 0.0);
    let big_pos = d[big] > 0;
    let mut front = [[0f32; 3]; 3];
    let mut back = [[0f32; 3]; 3];
    let (mut nf, mut nb) = (0, 0);
    for (i, f) in FACES.iter().enumerate() {
        if d[i] == 0 {
            continue;
        }
        let pts = f.map(|k| (pv[k].px, pv[k].py));
        let vals = f.map(|k| w(pv[k]) - w0);
        let Some(pl) = plane_fit(pts, vals, ox, oy) else {
            continue;
        };
        let pl = pl.map(|x| x as f32);
        // Front or back by the unsnapped projection the plane was fitted to: a face seen nearly
        // edge-on can change sign on the fixed-point grid, and a flipped steep plane would cut
        // the whole tet away.
        let (a, b, c) = (pts[0], pts[1], pts[2]);
        let area = (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
        if (area > 0.0) == (big_pos == big_front) {
            front[nf] = pl;
            nf += 1;
        } else {
            back[nb] = pl;
            nb += 1;
        }
    }
    if nf == 0 || nb == 0 {
        return None;
    }

    // Scalar gradient in view coordinates.
    let e = [1, 2, 3].map(|k| sub(pv[k].view, pv[0].view));
    let ds = [1, 2, 3].map(|k| s[k] - s[0]);
    let det = dt(e[0], cr(e[1], e[2]));
    let g = if det != 0.0 && det.is_finite() {
        let (c0, c1, c2) = (cr(e[1], e[2]), cr(e[2], e[0]), cr(e[0], e[1]));
        [0, 1, 2].map(|a| (ds[0] * c0[a] + ds[1] * c1[a] + ds[2] * c2[a]) / det)
    } else {
        [0.0; 3]
    };
    let v0 = pv[0].view;
    let (wd, hd) = (view.width as f64, view.height as f64);
    // xs = (2 px / W - 1) aspect, ys = 1 - 2 py / H.
    let (dxs, dys) = (2.0 * view.aspect / wd, -2.0 / hd);
    let (xs0, ys0) = view.screen_plane(ox, oy);
    let (sref, h) = if view.parallel {
        // P = (scale xs, scale ys, z): S = s0 + g.(P - v0).
        let sr0 = s[0] + g[0] * (view.scale * xs0 - v0[0]) + g[1] * (view.scale * ys0 - v0[1]);
        (
            [sr0, g[0] * view.scale * dxs, g[1] * view.scale * dys],
            [g[2], 0.0, 0.0],
        )
    } else {
        // P = z (scale xs, scale ys, 1): S = s0 - g.v0 + z H, H = g.(scale xs, scale ys, 1).
        let h0 = g[0] * view.scale * xs0 + g[1] * view.scale * ys0 + g[2];
        let (hx, hy) = (g[0] * view.scale * dxs, g[1] * view.scale * dys);
        let z0 = v0[2];
        let d0 = [view.scale * xs0 * z0, view.scale * ys0 * z0, z0];
        let sr0 = s[0] + dt(g, sub(d0, v0));
        ([sr0, z0 * hx, z0 * hy], [h0, hx, hy])
    };
    let smin = s.iter().copied().fold(f64::INFINITY, f64::min);
    let smax = s.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    // Unused plane slots repeat the first plane, so the rasterizer takes the min and max over
    // all three without branching (a repeat changes neither).
    for k in nf..3 {
        front[k] = front[0];
    }
    for k in nb..3 {
        back[k] = back[0];
    }
    Some(TetSetup {
        poly: poly.map(|p| [p.0 as i32, p.1 as i32]),
        nedges: nedges as u32,
        x0: x0 as i32,
        x1: x1 as i32,
        y0: y0 as i32,
        y1: y1 as i32,
        ox: ox as f32,
        oy: oy as f32,
        front,
        back,
        w0: w0 as f32,
        sref: sref.map(|x| x as f32),
        h: h.map(|x| x as f32),
        smin: smin as f32,
        smax: smax as f32,
    })
}

/// A fragment's entry and exit depths relative to vertex 0's depth, and its scalar as
/// `sref + h * depth` (unclamped), at pixel centre `(cx, cy)`: what a scene splits at body
/// crossings.
#[inline(always)]
pub(crate) fn fragment_span(t: &TetSetup, parallel: bool, x: i64, y: i64) -> (f32, f32, f32, f32) {
    // Evaluated exactly as [`fragments`] does, so a fragment the scene does not split matches
    // the plain rasterizer's bit for bit.
    let rp = RowPlanes::new(t, y as f32 + 0.5 - t.oy);
    let dx = x as f32 + 0.5 - t.ox;
    let ev = |p: &[f32; 2]| p[0] + p[1] * dx;
    let (zf, zb) = if parallel {
        let f = rp.front.map(|p| ev(&p));
        let b = rp.back.map(|p| ev(&p));
        (f[0].max(f[1]).max(f[2]), b[0].min(b[1]).min(b[2]))
    } else {
        let f = rp.front.map(|p| ev(&p));
        let b = rp.back.map(|p| ev(&p));
        let df = f[0].min(f[1]).min(f[2]);
        let db = b[0].max(b[1]).max(b[2]);
        // z - z0 = 1/(w0 + d) - 1/w0 = -d / (w0 (w0 + d)).
        let w0 = t.w0;
        (-df / (w0 * (w0 + df)), -db / (w0 * (w0 + db)))
    };
    (zf, zb, ev(&rp.sref), ev(&rp.h))
}

/// Pixels of the batched fragment math: fixed-size loops over them vectorize (spans of small
/// tets are short, so more lanes would mostly compute pixels outside the span).
pub(crate) const LANES: usize = 4;

/// (Sf, Sb, l) of [`LANES`] fragments.
pub(crate) type Lanes = [[f32; LANES]; 3];

/// Colour and opacity of fragments for the rasterizer: per-lane arithmetic for [`LANES`]
/// fragments at once (it vectorizes), then per-pixel reads for the lanes that are drawn.
pub(crate) trait Shade {
    type Prep;
    fn prep(&self, f: &Lanes) -> Self::Prep;
    fn at(&self, p: &Self::Prep, i: usize) -> [f32; 4];
}

/// Table corners and weights of [`LANES`] lookups.
pub(crate) struct TableLanes {
    base: [usize; LANES],
    w: [[f32; LANES]; 3],
}

impl Shade for PreintTable {
    type Prep = TableLanes;
    #[inline(always)]
    fn prep(&self, f: &Lanes) -> TableLanes {
        let top = (self.ns - 1) as f32;
        let ltop = (self.nl - 1) as f32;
        let (mut base, mut w) = ([0usize; LANES], [[0f32; LANES]; 3]);
        let (ns, nl) = (self.ns as i32, self.nl as i32);
        for i in 0..LANES {
            // max then min (not clamp): NaN becomes 0, so every value is in [0, top].
            let xf = ((f[0][i] - self.s0) * self.inv_ds).max(0.0).min(top);
            let xb = ((f[1][i] - self.s0) * self.inv_ds).max(0.0).min(top);
            let xl = (f[2][i] * self.inv_dl).max(0.0).min(ltop);
            // SAFETY: each value is finite and in [0, ns - 1] or [0, nl - 1] (table sizes are
            // far below i32::MAX), where truncation to i32 is defined; the checked cast would
            // not vectorize.
            let (a, b, c) = unsafe {
                (
                    xf.to_int_unchecked::<i32>().min(ns - 2),
                    xb.to_int_unchecked::<i32>().min(ns - 2),
                    xl.to_int_unchecked::<i32>().min(nl - 2),
                )
            };
            w[0][i] = xf - a as f32;
            w[1][i] = xb - b as f32;
            w[2][i] = xl - c as f32;
            base[i] = ((c * ns + b) * ns + a) as usize;
        }
        TableLanes { base, w }
    }
    #[inline(always)]
    fn at(&self, p: &TableLanes, i: usize) -> [f32; 4] {
        self.corners(p.base[i], p.w[0][i], p.w[1][i], p.w[2][i])
    }
}

/// VTK's averaged integration ([`FastTf::average`]) as a [`Shade`].
pub(crate) struct AverageShade<'a>(pub(crate) &'a FastTf);
/// Linear integration ([`FastTf::linear`]) as a [`Shade`].
pub(crate) struct LinearShade<'a>(pub(crate) &'a FastTf);

impl Shade for AverageShade<'_> {
    type Prep = Lanes;
    #[inline(always)]
    fn prep(&self, f: &Lanes) -> Lanes {
        *f
    }
    #[inline(always)]
    fn at(&self, f: &Lanes, i: usize) -> [f32; 4] {
        self.0.average(f[0][i], f[1][i], f[2][i])
    }
}

impl Shade for LinearShade<'_> {
    type Prep = Lanes;
    #[inline(always)]
    fn prep(&self, f: &Lanes) -> Lanes {
        *f
    }
    #[inline(always)]
    fn at(&self, f: &Lanes, i: usize) -> [f32; 4] {
        self.0.linear(f[0][i], f[1][i], f[2][i])
    }
}

/// An edge prepared for [`span`]: its value at pixel `x` of row `y` is `ea x + k0 + k1 y`.
#[derive(Clone, Copy)]
pub(crate) struct SpanEdge {
    ea: i64,
    k0: i64,
    k1: i64,
    /// `1 / ea` for the floating-point estimate of the bound.
    inv: f64,
}

/// The silhouette's edges prepared for [`span`]: `n` of them.
pub(crate) struct SpanEdges {
    e: [SpanEdge; 4],
    n: usize,
}

impl SpanEdges {
    #[inline(always)]
    pub(crate) fn new(t: &TetSetup) -> SpanEdges {
        let e = t.edges().map(|e| SpanEdge {
            ea: e.a * SUB,
            k0: e.a * (SUB / 2) + e.b * (SUB / 2) + e.c + e.bias,
            k1: e.b * SUB,
            inv: if e.a != 0 {
                1.0 / (e.a * SUB) as f64
            } else {
                0.0
            },
        });
        SpanEdges {
            e,
            n: t.nedges as usize,
        }
    }

    /// The run of pixels `x` in `[lo, hi]` of row `y` whose centres lie inside every edge. The
    /// silhouette is convex, so the run is contiguous; each edge's bound comes from a
    /// floating-point estimate corrected by the exact integer test, so the run is exactly the
    /// pixels the per-pixel edge test takes.
    #[inline(always)]
    pub(crate) fn span(&self, y: i64, lo: i64, hi: i64) -> Option<(i64, i64)> {
        let (mut a, mut b) = (lo, hi);
        for e in &self.e[..self.n] {
            let (ea, eb) = (e.ea, e.k0 + e.k1 * y);
            // The estimate truncates and saturates; the integer loops make the bound exact.
            let est = || ((-(eb as f64) * e.inv) as i64).clamp(lo - 1, hi + 1);
            if ea > 0 {
                let mut x = est();
                while x > a && ea * (x - 1) + eb >= 0 {
                    x -= 1;
                }
                while x <= b && ea * x + eb < 0 {
                    x += 1;
                }
                a = a.max(x);
            } else if ea < 0 {
                let mut x = est();
                while x < b && ea * (x + 1) + eb >= 0 {
                    x += 1;
                }
                while x >= a && ea * x + eb < 0 {
                    x -= 1;
                }
                b = b.min(x);
            } else if eb < 0 {
                return None;
            }
            if a > b {
                return None;
            }
        }
        Some((a, b))
    }
}

/// One row's depth and scalar planes with the row's offset folded in: `[value at dx = 0, slope]`.
struct RowPlanes {
    front: [[f32; 2]; 3],
    back: [[f32; 2]; 3],
    sref: [f32; 2],
    h: [f32; 2],
}

impl RowPlanes {
    #[inline(always)]
    fn new(t: &TetSetup, dy: f32) -> RowPlanes {
        let r = |p: &[f32; 3]| [p[0] + p[2] * dy, p[1]];
        RowPlanes {
            front: [r(&t.front[0]), r(&t.front[1]), r(&t.front[2])],
            back: [r(&t.back[0]), r(&t.back[1]), r(&t.back[2])],
            sref: r(&t.sref),
            h: r(&t.h),
        }
    }
}

/// (Sf, Sb, l) of [`LANES`] consecutive pixels of a row, the first at `dx0` from the tet's
/// origin: all three plane slots evaluated (the unused ones repeat a used plane), so no branch
/// depends on the tet's class.
#[inline(always)]
fn fragments(
    t: &TetSetup,
    rp: &RowPlanes,
    parallel: bool,
    x: i64,
    stretch: &[f32; LANES],
) -> Lanes {
    let mut dx = [0f32; LANES];
    for (i, d) in dx.iter_mut().enumerate() {
        *d = (x as i32 + i as i32) as f32 + 0.5 - t.ox;
    }
    let ev = |p: &[f32; 2], d: f32| p[0] + p[1] * d;
    let (mut zf, mut zb) = ([0f32; LANES], [0f32; LANES]);
    if parallel {
        for i in 0..LANES {
            let d = dx[i];
            zf[i] = ev(&rp.front[0], d)
                .max(ev(&rp.front[1], d))
                .max(ev(&rp.front[2], d));
            zb[i] = ev(&rp.back[0], d)
                .min(ev(&rp.back[1], d))
                .min(ev(&rp.back[2], d));
        }
    } else {
        let w0 = t.w0;
        for i in 0..LANES {
            let d = dx[i];
            let df = ev(&rp.front[0], d)
                .min(ev(&rp.front[1], d))
                .min(ev(&rp.front[2], d));
            let db = ev(&rp.back[0], d)
                .max(ev(&rp.back[1], d))
                .max(ev(&rp.back[2], d));
            // z - z0 = 1/(w0 + d) - 1/w0 = -d / (w0 (w0 + d)).
            zf[i] = -df / (w0 * (w0 + df));
            zb[i] = -db / (w0 * (w0 + db));
        }
    }
    let (mut sf, mut sb, mut l) = ([0f32; LANES], [0f32; LANES], [0f32; LANES]);
    for i in 0..LANES {
        let d = dx[i];
        let sref = ev(&rp.sref, d);
        let h = ev(&rp.h, d);
        sf[i] = (sref + zf[i] * h).clamp(t.smin, t.smax);
        sb[i] = (sref + zb[i] * h).clamp(t.smin, t.smax);
        let li = ((zb[i] - zf[i]) * stretch[i]).max(0.0);
        l[i] = if li.is_finite() { li } else { 0.0 };
    }
    [sf, sb, l]
}

/// Rasterizes one tet into a tile buffer (front to back). Returns fragments drawn and how many
/// pixels became opaque.
#[inline(always)]
pub(crate) fn raster<S: Shade>(
    t: &TetSetup,
    parallel: bool,
    tile: (i64, i64, i64, i64),
    buf: &mut [[f32; 4]],
    stretch: &[f32],
    width: usize,
    shade: &S,
) -> (u64, usize) {
    let (tx0, ty0, tx1, _) = tile;
    let Some((x0, x1, y0, y1)) = t.clip(tile) else {
        return (0, 0);
    };
    let tw = (tx1 - tx0 + 1) as usize;
    let mut frags = 0u64;
    let mut newly_opaque = 0usize;
    let edges = SpanEdges::new(t);
    for y in y0..=y1 {
        let Some((xa, xb)) = edges.span(y, x0, x1) else {
            continue;
        };
        let rp = RowPlanes::new(t, y as f32 + 0.5 - t.oy);
        let row = &mut buf[(y - ty0) as usize * tw..][..tw];
        let srow = &stretch[y as usize * width..][..width];
        let mut x = xa;
        while x <= xb {
            let n = ((xb - x + 1) as usize).min(LANES);
            let xs = x as usize;
            let st: [f32; LANES] = match srow.get(xs..xs + LANES) {
                Some(s) => s.try_into().unwrap_or([0.0; LANES]),
                None => std::array::from_fn(|i| srow.get(xs + i).copied().unwrap_or(0.0)),
            };
            let f = fragments(t, &rp, parallel, x, &st);
            let prep = shade.prep(&f);
            let out = &mut row[(x - tx0) as usize..][..n];
            for (i, slot) in out.iter_mut().enumerate() {
                if slot[3] >= OPAQUE {
                    continue;
                }
                let c = shade.at(&prep, i);
                let k = 1.0 - slot[3];
                slot[0] += k * c[0];
                slot[1] += k * c[1];
                slot[2] += k * c[2];
                slot[3] += k * c[3];
                frags += 1;
                if slot[3] >= OPAQUE {
                    newly_opaque += 1;
                }
            }
            x += LANES as i64;
        }
    }
    (frags, newly_opaque)
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

/// Rasterizes one set-up tet into a buffer covering `tile`, with the shader's integration.
#[inline(always)]
fn draw(
    setup: &TetSetup,
    parallel: bool,
    tile: (i64, i64, i64, i64),
    buf: &mut [[f32; 4]],
    stretch: &[f32],
    w: usize,
    shader: &Shader,
) -> (u64, usize) {
    match shader {
        Shader::Pre(tab) => raster(setup, parallel, tile, buf, stretch, w, tab),
        Shader::Average(tf) => raster(setup, parallel, tile, buf, stretch, w, &AverageShade(tf)),
        Shader::Linear(tf) => raster(setup, parallel, tile, buf, stretch, w, &LinearShade(tf)),
    }
}

/// Pixel box (x0, y0, x1, y1), inclusive.
type PixelBox = (i64, i64, i64, i64);

/// Pixel box (inclusive) of a tet's projection clipped to the image, if it is drawable.
#[inline]
fn pixel_box(view: &View, p: &[&Projected; 4], w: usize, h: usize) -> Option<(i64, i64, i64, i64)> {
    if p.iter().any(|q| !q.ok) {
        return clip_box(view, p, w, h);
    }
    let (mut xmin, mut xmax, mut ymin, mut ymax) = (p[0].fx, p[0].fx, p[0].fy, p[0].fy);
    for q in &p[1..] {
        xmin = xmin.min(q.fx);
        xmax = xmax.max(q.fx);
        ymin = ymin.min(q.fy);
        ymax = ymax.max(q.fy);
    }
    let lo = |v: i64| (v - SUB / 2 + SUB - 1).div_euclid(SUB);
    let hi = |v: i64| (v - SUB / 2).div_euclid(SUB);
    let (x0, x1) = (lo(xmin).max(0), hi(xmax).min(w as i64 - 1));
    let (y0, y1) = (lo(ymin).max(0), hi(ymax).min(h as i64 - 1));
    (x0 <= x1 && y0 <= y1).then_some((x0, y0, x1, y1))
}

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
    let t0 = std::time::Instant::now();
    let proj = project_points(view, points);
    let (w, h) = (view.width as usize, view.height as usize);
    let stretch: Vec<f32> = (0..w * h)
        .into_par_iter()
        .map(|i| view.stretch((i % w) as f64 + 0.5, (i / w) as f64 + 0.5) as f32)
        .collect();
    let t1 = std::time::Instant::now();
    let ctx = Ctx {
        view,
        tets,
        field,
        proj: &proj,
        stretch: &stretch,
        shader,
    };
    let (img, stats, bin_s) = match schedule {
        Schedule::Tiles => render_tiles(&ctx, order),
        Schedule::Chunks => render_chunks(&ctx, order),
    };
    let t3 = std::time::Instant::now();
    (
        img,
        stats,
        PtTimes {
            project: (t1 - t0).as_secs_f64(),
            bin: bin_s,
            raster: (t3 - t1).as_secs_f64() - bin_s,
        },
    )
}

/// Counts tet `p`'s projection class (or that it takes the clipping path), once per tet.
#[inline]
fn count_class(st: &mut PtStats, p: &[&Projected; 4]) {
    if p.iter().any(|q| !q.ok) {
        st.clipped += 1;
    } else {
        let c = classify(&face_areas(&p.map(|q| (q.fx, q.fy))));
        st.class[class_index(c)] += 1;
    }
}

/// What every schedule reads.
struct Ctx<'a> {
    view: &'a View,
    tets: &'a [[u32; 4]],
    field: &'a Field,
    proj: &'a [Projected],
    stretch: &'a [f32],
    shader: &'a Shader,
}

impl Ctx<'_> {
    /// Sets up tet `t` and draws it into `buf` over `tile`: fragments and newly opaque pixels.
    #[inline]
    fn tet(&self, t: u32, tile: (i64, i64, i64, i64), buf: &mut [[f32; 4]]) -> (u64, usize) {
        let tet = &self.tets[t as usize];
        let pv = tet.map(|v| &self.proj[v as usize]);
        let s = self.field.at(t as usize, tet);
        if pv.iter().any(|p| !p.ok) {
            let (w, h) = (self.view.width as usize, self.view.height as usize);
            let (Some(c), Some(b)) = (ClipSetup::new(pv, s), clip_box(self.view, &pv, w, h)) else {
                return (0, 0);
            };
            let part = (
                tile.0.max(b.0),
                tile.1.max(b.1),
                tile.2.min(b.2),
                tile.3.min(b.3),
            );
            if part.0 > part.2 || part.1 > part.3 {
                return (0, 0);
            }
            return draw_clipped(&c, self.view, tile, part, buf, self.shader);
        }
        let mut scratch = PtStats::default();
        let Some(setup) = setup_tet(self.view, pv, s, &mut scratch) else {
            return (0, 0);
        };
        draw(
            &setup,
            self.view.parallel,
            tile,
            buf,
            self.stretch,
            self.view.width as usize,
            self.shader,
        )
    }
}

/// The per-pixel path for tets the rasterizer cannot take: a vertex behind the eye (the eye
/// inside or beside the tet, in perspective) or projected beyond the guard band. Each pixel's
/// ray is clipped against the tet's four face planes in view coordinates, and, in perspective,
/// starts at the eye, as the ray-cast reference's rays do.
struct ClipSetup {
    /// Inside where `n . P <= c`, per face.
    planes: [([f64; 3], f64); 4],
    /// Scalar at vertex 0 and its gradient, in view coordinates.
    v0: [f64; 3],
    s0: f64,
    g: [f64; 3],
    smin: f64,
    smax: f64,
}

/// Depth below which a point counts as at the eye when bounding a clipped tet on screen.
const CLIP_NEAR: f64 = 1e-9;

impl ClipSetup {
    fn new(pv: [&Projected; 4], s: [f64; 4]) -> Option<ClipSetup> {
        let v = pv.map(|p| p.view);
        let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        let cr = |a: [f64; 3], b: [f64; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let dt = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let e = [1, 2, 3].map(|k| sub(v[k], v[0]));
        let det = dt(e[0], cr(e[1], e[2]));
        if !(det != 0.0 && det.is_finite()) {
            return None;
        }
        let mut planes = [([0.0; 3], 0.0); 4];
        for (f, fv) in FACES.iter().enumerate() {
            let a = v[fv[0]];
            let mut n = cr(sub(v[fv[1]], a), sub(v[fv[2]], a));
            if dt(n, sub(v[f], a)) > 0.0 {
                n = [-n[0], -n[1], -n[2]];
            }
            planes[f] = (n, dt(n, a));
        }
        let ds = [1, 2, 3].map(|k| s[k] - s[0]);
        let (c0, c1, c2) = (cr(e[1], e[2]), cr(e[2], e[0]), cr(e[0], e[1]));
        let g = [0, 1, 2].map(|a| (ds[0] * c0[a] + ds[1] * c1[a] + ds[2] * c2[a]) / det);
        Some(ClipSetup {
            planes,
            v0: v[0],
            s0: s[0],
            g,
            smin: s.iter().copied().fold(f64::INFINITY, f64::min),
            smax: s.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        })
    }

    /// (Sf, Sb, l) of the ray `A + z B` (z the view depth), from `zmin` on.
    #[inline]
    fn segment(&self, a: [f64; 3], b: [f64; 3], zmin: f64) -> Option<(f64, f64, f64)> {
        let dt = |p: [f64; 3], q: [f64; 3]| p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
        let (mut z0, mut z1) = (zmin, f64::INFINITY);
        for (n, c) in &self.planes {
            let na = dt(*n, a);
            let nb = dt(*n, b);
            // n.A + z n.B <= c.
            if nb > 0.0 {
                z1 = z1.min((c - na) / nb);
            } else if nb < 0.0 {
                z0 = z0.max((c - na) / nb);
            } else if na > *c {
                return None;
            }
        }
        if !(z1 > z0) || !z0.is_finite() || !z1.is_finite() {
            return None;
        }
        let at = |z: f64| {
            let p = [a[0] + z * b[0], a[1] + z * b[1], a[2] + z * b[2]];
            (self.s0
                + dt(
                    self.g,
                    [p[0] - self.v0[0], p[1] - self.v0[1], p[2] - self.v0[2]],
                ))
            .clamp(self.smin, self.smax)
        };
        Some((at(z0), at(z1), (z1 - z0) * dt(b, b).sqrt()))
    }
}

/// Screen box of a tet with a vertex behind the eye or beyond the guard band: the box of its
/// part in front of `CLIP_NEAR` (edges cut there), clamped to the image.
fn clip_box(view: &View, p: &[&Projected; 4], w: usize, h: usize) -> Option<(i64, i64, i64, i64)> {
    let near = if view.parallel {
        f64::NEG_INFINITY
    } else {
        CLIP_NEAR
    };
    let mut pts: Vec<[f64; 3]> = Vec::with_capacity(8);
    for i in 0..4 {
        let a = p[i].view;
        if a[2] >= near {
            pts.push(a);
        }
        for q in &p[i + 1..] {
            let b = q.view;
            if (a[2] < near) != (b[2] < near) {
                let t = (near - a[2]) / (b[2] - a[2]);
                pts.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), near]);
            }
        }
    }
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for v in &pts {
        let (px, py) = view.screen(v);
        if !(px.is_finite() && py.is_finite()) {
            // Too close to the eye plane to place: the whole image.
            (x0, x1, y0, y1) = (
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
            );
            break;
        }
        x0 = x0.min(px);
        x1 = x1.max(px);
        y0 = y0.min(py);
        y1 = y1.max(py);
    }
    if pts.is_empty() {
        return None;
    }
    // Pixel centres i + 0.5 in [min, max], widened by a pixel against rounding.
    let lo = |v: f64| (v - 1.5).ceil().clamp(0.0, 1e9) as i64;
    let hi = |v: f64, n: usize| (v + 0.5).floor().clamp(-1.0, n as f64 - 1.0) as i64;
    let b = (lo(x0), lo(y0), hi(x1, w), hi(y1, h));
    (b.0 <= b.2 && b.1 <= b.3).then_some(b)
}

/// Draws a clipped tet pixel by pixel over `part` of the buffer covering `tile` (front to back).
fn draw_clipped(
    c: &ClipSetup,
    view: &View,
    tile: (i64, i64, i64, i64),
    part: (i64, i64, i64, i64),
    buf: &mut [[f32; 4]],
    shader: &Shader,
) -> (u64, usize) {
    let (tx0, ty0, tx1, _) = tile;
    let tw = (tx1 - tx0 + 1) as usize;
    let zmin = if view.parallel {
        f64::NEG_INFINITY
    } else {
        0.0
    };
    let (mut frags, mut newly) = (0u64, 0usize);
    for y in part.1..=part.3 {
        for x in part.0..=part.2 {
            let slot = &mut buf[(y - ty0) as usize * tw + (x - tx0) as usize];
            if slot[3] >= OPAQUE {
                continue;
            }
            let (xs, ys) = view.screen_plane(x as f64 + 0.5, y as f64 + 0.5);
            let (a, b) = if view.parallel {
                ([view.scale * xs, view.scale * ys, 0.0], [0.0, 0.0, 1.0])
            } else {
                ([0.0; 3], [view.scale * xs, view.scale * ys, 1.0])
            };
            let Some((sf, sb, l)) = c.segment(a, b, zmin) else {
                continue;
            };
            let (sf, sb, l) = (sf as f32, sb as f32, l as f32);
            let col = match shader {
                Shader::Pre(tab) => tab.lookup(sf, sb, l),
                Shader::Average(tf) => tf.average(sf, sb, l),
                Shader::Linear(tf) => tf.linear(sf, sb, l),
            };
            let k = 1.0 - slot[3];
            for ch in 0..4 {
                slot[ch] += k * col[ch];
            }
            frags += 1;
            if slot[3] >= OPAQUE {
                newly += 1;
            }
        }
    }
    (frags, newly)
}

/// A tet of one frame, set up once for all the tiles it touches.
enum Prepared {
    Tet(TetSetup),
    /// Drawn by the per-pixel clipping path, over its pixel box.
    Clipped(Box<ClipSetup>, PixelBox),
}

impl Ctx<'_> {
    /// Sets up tet `t` (counting its class): what its tiles draw and its pixel box.
    #[inline(always)]
    fn prepare(&self, t: u32, st: &mut PtStats) -> Option<(Prepared, PixelBox)> {
        let tet = &self.tets[t as usize];
        let pv = tet.map(|v| &self.proj[v as usize]);
        let s = self.field.at(t as usize, tet);
        if pv.iter().any(|p| !p.ok) {
            st.clipped += 1;
            let (w, h) = (self.view.width as usize, self.view.height as usize);
            let c = ClipSetup::new(pv, s)?;
            let b = clip_box(self.view, &pv, w, h)?;
            return Some((Prepared::Clipped(Box::new(c), b), b));
        }
        let su = setup_tet(self.view, pv, s, st)?;
        let b = (su.x0 as i64, su.y0 as i64, su.x1 as i64, su.y1 as i64);
        Some((Prepared::Tet(su), b))
    }

    /// Draws a prepared tet into `buf` over `tile`: fragments and newly opaque pixels.
    #[inline(always)]
    fn draw_prepared(
        &self,
        p: &Prepared,
        tile: (i64, i64, i64, i64),
        buf: &mut [[f32; 4]],
    ) -> (u64, usize) {
        match p {
            Prepared::Tet(su) => draw(
                su,
                self.view.parallel,
                tile,
                buf,
                self.stretch,
                self.view.width as usize,
                self.shader,
            ),
            Prepared::Clipped(c, b) => {
                let part = (
                    tile.0.max(b.0),
                    tile.1.max(b.1),
                    tile.2.min(b.2),
                    tile.3.min(b.3),
                );
                if part.0 > part.2 || part.1 > part.3 {
                    return (0, 0);
                }
                draw_clipped(c, self.view, tile, part, buf, self.shader)
            }
        }
    }
}

/// Set-up tets of a run of the order, their indices binned per tile, and their counts.
type Binned = (Vec<Prepared>, Vec<Vec<u32>>, PtStats);

/// Sets up a run of the order and bins it per tile (`ntx` tiles a row, `ntiles` in all).
#[inline(always)]
fn bin(ctx: &Ctx, chunk: &[u32], ntx: usize, ntiles: usize) -> Binned {
    let mut recs = Vec::with_capacity(chunk.len());
    let mut lists: Vec<Vec<u32>> = vec![Vec::new(); ntiles];
    let mut st = PtStats::default();
    for &t in chunk {
        let Some((rec, (x0, y0, x1, y1))) = ctx.prepare(t, &mut st) else {
            continue;
        };
        let k = recs.len() as u32;
        recs.push(rec);
        for ty in (y0 as usize / TILE)..=(y1 as usize / TILE) {
            for tx in (x0 as usize / TILE)..=(x1 as usize / TILE) {
                lists[ty * ntx + tx].push(k);
            }
        }
    }
    (recs, lists, st)
}

/// [`bin`] compiled for AVX2 (bit for bit the same, as [`draw_tile_avx2`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn bin_avx2(ctx: &Ctx, chunk: &[u32], ntx: usize, ntiles: usize) -> Binned {
    bin(ctx, chunk, ntx, ntiles)
}

/// [`bin`] with the widest instruction set the CPU has.
fn bin_best(ctx: &Ctx, chunk: &[u32], ntx: usize, ntiles: usize) -> Binned {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, checked just above.
        return unsafe { bin_avx2(ctx, chunk, ntx, ntiles) };
    }
    bin(ctx, chunk, ntx, ntiles)
}

/// Draws tile `ti` (pixel box `tile`) from the binned runs in order: its buffer and fragments.
#[inline(always)]
fn draw_tile(
    ctx: &Ctx,
    bins: &[Binned],
    ti: usize,
    tile: (i64, i64, i64, i64),
) -> (Vec<[f32; 4]>, u64) {
    let npix = ((tile.2 - tile.0 + 1) * (tile.3 - tile.1 + 1)) as usize;
    let mut buf = vec![[0f32; 4]; npix];
    let mut frags = 0u64;
    let mut opaque = 0usize;
    'outer: for (recs, lists, _) in bins {
        for &k in &lists[ti] {
            let (f, o) = ctx.draw_prepared(&recs[k as usize], tile, &mut buf);
            frags += f;
            opaque += o;
            if opaque == npix {
                break 'outer;
            }
        }
    }
    (buf, frags)
}

/// [`draw_tile`] compiled for AVX2: the per-pixel lanes vectorize far better than with the
/// baseline SSE2. No fused multiply-add is enabled, so the image is bit for bit the same.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn draw_tile_avx2(
    ctx: &Ctx,
    bins: &[Binned],
    ti: usize,
    tile: (i64, i64, i64, i64),
) -> (Vec<[f32; 4]>, u64) {
    draw_tile(ctx, bins, ti, tile)
}

/// [`draw_tile`] with the widest instruction set the CPU has.
fn draw_tile_best(
    ctx: &Ctx,
    bins: &[Binned],
    ti: usize,
    tile: (i64, i64, i64, i64),
) -> (Vec<[f32; 4]>, u64) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, checked just above.
        return unsafe { draw_tile_avx2(ctx, bins, ti, tile) };
    }
    draw_tile(ctx, bins, ti, tile)
}

/// [`Schedule::Tiles`]: image, counts, seconds spent setting up and binning.
fn render_tiles(ctx: &Ctx, order: &[u32]) -> (Image, PtStats, f64) {
    let t1 = std::time::Instant::now();
    let (w, h) = (ctx.view.width as usize, ctx.view.height as usize);
    // Set up and bin the ordered tets per tile: chunks of the order in parallel, each chunk
    // keeping its tets in order, so a tile that walks the chunks in turn sees the global order.
    // Each tet is set up once, however many tiles it touches.
    let (ntx, nty) = (w.div_ceil(TILE), h.div_ceil(TILE));
    let ntiles = ntx * nty;
    const CHUNK: usize = 1 << 15;
    let bins: Vec<Binned> = order
        .par_chunks(CHUNK)
        .map(|chunk| bin_best(ctx, chunk, ntx, ntiles))
        .collect();
    let mut stats = PtStats::default();
    for (_, _, st) in &bins {
        stats.add(st);
    }
    let bin_s = t1.elapsed().as_secs_f64();

    let tiles: Vec<(Vec<[f32; 4]>, u64)> = (0..ntiles)
        .into_par_iter()
        .map(|ti| {
            let (tx, ty) = (ti % ntx, ti / ntx);
            let (px0, py0) = ((tx * TILE) as i64, (ty * TILE) as i64);
            let (px1, py1) = (
                ((tx + 1) * TILE).min(w) as i64 - 1,
                ((ty + 1) * TILE).min(h) as i64 - 1,
            );
            draw_tile_best(ctx, &bins, ti, (px0, py0, px1, py1))
        })
        .collect();
    let mut img = Image::new(ctx.view.width, ctx.view.height);
    for (ti, (buf, f)) in tiles.iter().enumerate() {
        stats.fragments += f;
        let (tx, ty) = (ti % ntx, ti / ntx);
        let (px0, py0) = (tx * TILE, ty * TILE);
        let tw = (TILE).min(w - px0);
        for (r, row) in buf.chunks(tw).enumerate() {
            let y = py0 + r;
            img.pixels[y * w + px0..y * w + px0 + tw].copy_from_slice(row);
        }
    }
    (img, stats, bin_s)
}

/// [`Schedule::Chunks`]: image, counts, seconds spent finding the chunks' screen boxes.
fn render_chunks(ctx: &Ctx, order: &[u32]) -> (Image, PtStats, f64) {
    let t1 = std::time::Instant::now();
    let (w, h) = (ctx.view.width as usize, ctx.view.height as usize);
    let per = order.len().div_ceil(CHUNKS).max(1);
    let runs: Vec<&[u32]> = order.chunks(per).collect();
    // Each run's screen box, so a buffer covers only what its run can touch.
    let boxed: Vec<(Option<PixelBox>, PtStats)> = runs
        .par_iter()
        .map(|run| {
            let mut bb: Option<PixelBox> = None;
            let mut st = PtStats::default();
            for &t in run.iter() {
                let p = ctx.tets[t as usize].map(|v| &ctx.proj[v as usize]);
                count_class(&mut st, &p);
                if let Some(b) = pixel_box(ctx.view, &p, w, h) {
                    bb = Some(match bb {
                        None => b,
                        Some(a) => (a.0.min(b.0), a.1.min(b.1), a.2.max(b.2), a.3.max(b.3)),
                    });
                }
            }
            (bb, st)
        })
        .collect();
    let mut stats = PtStats::default();
    for (_, st) in &boxed {
        stats.add(st);
    }
    let boxes: Vec<Option<PixelBox>> = boxed.iter().map(|b| b.0).collect();
    let box_s = t1.elapsed().as_secs_f64();
    let bufs: Vec<(Vec<[f32; 4]>, u64)> = runs
        .par_iter()
        .zip(&boxes)
        .map(|(run, bb)| {
            let Some(tile) = *bb else {
                return (Vec::new(), 0);
            };
            let npix = ((tile.2 - tile.0 + 1) * (tile.3 - tile.1 + 1)) as usize;
            let mut buf = vec![[0f32; 4]; npix];
            let mut frags = 0;
            for &t in run.iter() {
                frags += ctx.tet(t, tile, &mut buf).0;
            }
            (buf, frags)
        })
        .collect();
    // Front to back: out += (1 - out.a) * run, rows in parallel.
    let mut img = Image::new(ctx.view.width, ctx.view.height);
    img.pixels
        .par_chunks_mut(w)
        .enumerate()
        .for_each(|(y, row)| {
            let y = y as i64;
            for ((buf, _), bb) in bufs.iter().zip(&boxes) {
                let Some((x0, y0, x1, y1)) = *bb else {
                    continue;
                };
                if y < y0 || y > y1 {
                    continue;
                }
                let bw = (x1 - x0 + 1) as usize;
                let src = &buf[(y - y0) as usize * bw..][..bw];
                for (d, s) in row[x0 as usize..=x1 as usize].iter_mut().zip(src) {
                    let k = 1.0 - d[3];
                    for c in 0..4 {
                        d[c] += k * s[c];
                    }
                }
            }
        });
    stats.fragments = bufs.iter().map(|b| b.1).sum();
    (img, stats, box_s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::locate::{GridParams, Topology};
    use crate::mesh::generate::{jitter, structured_grid};
    use crate::render::integrate::PreintTable;
    use crate::render::raycast::RayCaster;
    use crate::render::transfer::{named_colormap, OpacitySpec, TransferFunction};

    fn tf() -> TransferFunction {
        TransferFunction::build(
            &named_colormap("viridis").unwrap(),
            Some(&OpacitySpec::parse("0:0.2,0.5:0.7,1:0.4").unwrap()),
            [0.0, 1.0],
            0.5,
            9,
        )
        .unwrap()
    }

    /// PT against the ray caster on the same view: max channel error, and that every pixel the
    /// reference covers is covered (no holes) and nothing is NaN.
    fn compare(
        points: &[[f64; 3]],
        tets: &[[u32; 4]],
        s: &[f64],
        cam: &Camera,
        n: u32,
    ) -> (f64, PtStats) {
        compare_with(points, tets, s, cam, n, &tf())
    }

    fn compare_with(
        points: &[[f64; 3]],
        tets: &[[u32; 4]],
        s: &[f64],
        cam: &Camera,
        n: u32,
        tf: &TransferFunction,
    ) -> (f64, PtStats) {
        let field = Field::Point(s.to_vec());
        let tf = tf.clone();
        let topo = Topology::build(tets);
        let rc = RayCaster::new(points, tets, &field, &topo, GridParams::default());
        let (reference, _) = rc.render(&tf, cam, n, n);
        let lmax = 3.0;
        let shader = Shader::Pre(PreintTable::build(&tf, 129, 65, lmax));
        let order: Vec<u32> = (0..tets.len() as u32).collect();
        let (img, stats, _) = render(&View::new(cam, n, n), points, tets, &field, &order, &shader);
        assert!(!img.has_nan());
        let mut worst = 0.0f64;
        for (i, (a, b)) in img.pixels.iter().zip(&reference.pixels).enumerate() {
            if b[3] > 1e-3 {
                assert!(a[3] > 0.0, "hole at pixel {i}: reference {b:?}");
            }
            for k in 0..4 {
                worst = worst.max((a[k] - b[k]).abs() as f64);
            }
        }
        (worst, stats)
    }

    fn cams() -> Vec<Camera> {
        let par = Camera {
            position: [0.0, 0.0, 10.0],
            parallel: true,
            parallel_scale: 1.0,
            ..Camera::default()
        };
        let persp = Camera {
            position: [0.0, 0.0, 4.0],
            view_angle: 30.0,
            ..Camera::default()
        };
        vec![par, persp]
    }

    #[test]
    fn every_projection_class_matches_the_ray_caster() {
        let base = [[-0.8, -0.6, 0.0], [0.8, -0.6, 0.0], [0.0, 0.8, 0.0]];
        let cases: [([f64; 3], usize); 3] = [
            ([0.0, 0.0, 0.7], 0),  // class 1: apex inside the base
            ([0.0, -0.6, 0.7], 2), // class 3 (parallel): apex over an edge, a face seen edge-on
            ([0.0, 0.8, 0.7], 3),  // class 4 (parallel): apex over a vertex, an edge seen end-on
        ];
        for (apex, class) in cases {
            let pts = vec![base[0], base[1], base[2], apex];
            let tets = [[0u32, 1, 2, 3]];
            let s = [0.1, 0.9, 0.5, 0.3];
            for (ci, cam) in cams().iter().enumerate() {
                let (err, st) = compare(&pts, &tets, &s, cam, 48);
                if ci == 0 {
                    assert_eq!(st.class[class], 1, "apex {apex:?}: {st:?}");
                }
                assert!(err < 0.01, "apex {apex:?} camera {ci}: error {err}");
            }
        }
        // Class 2: two edges cross.
        let pts = vec![
            [-0.8, 0.0, 0.0],
            [0.8, 0.0, 0.0],
            [0.0, -0.8, 0.7],
            [0.0, 0.8, 0.7],
        ];
        for (ci, cam) in cams().iter().enumerate() {
            let (err, st) = compare(&pts, &[[0, 1, 2, 3]], &[0.0, 1.0, 0.2, 0.6], cam, 48);
            assert_eq!(st.class[1], 1, "{st:?}");
            assert!(err < 0.01, "class 2 camera {ci}: error {err}");
        }
        // Flat: all four points on one line of sight plane (a tet seen exactly edge-on in both
        // directions collapses to a segment): nothing drawn, nothing NaN.
        let flat = vec![
            [0.0, -0.5, 0.0],
            [0.0, 0.5, 0.0],
            [0.0, -0.2, 0.7],
            [0.0, 0.3, 0.4],
        ];
        let (_, st) = compare(
            &flat,
            &[[0, 1, 2, 3]],
            &[0.0, 1.0, 0.2, 0.6],
            &cams()[0],
            32,
        );
        assert_eq!(st.class[4], 1);
    }

    #[test]
    fn face_flipped_by_snapping_keeps_its_tet() {
        // Face [0, 3, 2] is seen nearly edge-on: its projected area is +282 (1/256 px)^2 unsnapped
        // but -1023 on the fixed-point grid. From a Gmsh mesh (fixtures/gmsh/cavity.vtk, tet 420).
        let pts = vec![
            [0.8588713258240279, 0.0, 0.2507062282134793],
            [1.0, 0.1220084679281462, 0.1220084679281462],
            [0.8779915320718535, 0.0, 0.1220084679281463],
            [0.7853681295419649, 0.2159403721809315, 0.2454360734388493],
        ];
        let c = [0.5, 0.5, 0.5];
        let d = 3f64.sqrt();
        let cam = Camera {
            position: [c[0] - 0.4 * d, c[1] + 0.3 * d, c[2] + 2.0 * d],
            focal: c,
            up: [0.0, 1.0, 0.0],
            parallel: true,
            parallel_scale: 0.6 * d,
            ..Camera::default()
        };
        let proj = project_points(&View::new(&cam, 64, 64), &pts);
        let d = face_areas(&[0, 1, 2, 3].map(|k| (proj[k].fx, proj[k].fy)));
        assert!(d[1] < 0, "the snapped face must flip for this test: {d:?}");
        let (err, _) = compare(&pts, &[[0, 1, 2, 3]], &[0.2, 0.9, 0.4, 0.7], &cam, 64);
        assert!(err < 0.01, "error {err}");
    }

    #[test]
    fn axis_aligned_grid_has_no_cracks() {
        // Every face of this grid is parallel or perpendicular to the view, every vertical edge
        // is seen end-on: classes 3 and 4 everywhere, and shared edges lie on pixel centres.
        let m = structured_grid([4, 4, 3], [-0.75, -0.75, -0.5], [0.75, 0.75, 0.5]);
        let s: Vec<f64> = m.point_data.get("scalar").unwrap().data.to_f64_vec();
        // One colour, varying opacity: compositing then commutes, so the mesh order is as good
        // as a visibility order and only coverage and per-fragment values are tested.
        let c = [0.9, 0.5, 0.2];
        let tf = TransferFunction::build(
            &crate::render::transfer::ColorSource::Relative(vec![(0.0, c), (1.0, c)]),
            Some(&OpacitySpec::parse("0:0.1,1:0.8").unwrap()),
            [0.0, 1.0],
            0.5,
            9,
        )
        .unwrap();
        for cam in cams() {
            let (err, st) = compare_with(&m.points, &m.tets, &s, &cam, 40, &tf);
            assert!(err < 0.01, "grid error {err} {st:?}");
        }
    }

    /// PT of `m` from `cam` in the MPVO order, with a schedule, against the ray caster.
    fn against_reference(
        m: &crate::mesh::TetMesh,
        cam: &Camera,
        n: u32,
        schedule: Schedule,
    ) -> (f64, PtStats, Image) {
        use crate::sort::{Direction, Method, Sorter};
        let s: Vec<f64> = m.point_data.get("scalar").unwrap().data.to_f64_vec();
        let field = Field::Point(s);
        let tf = tf();
        let topo = Topology::build(&m.tets);
        let rc = RayCaster::new(&m.points, &m.tets, &field, &topo, GridParams::default());
        let (reference, _) = rc.render(&tf, cam, n, n);
        let sorter = Sorter::new(m, None).unwrap();
        let order = sorter
            .order(cam, Method::Mpvo, Direction::FrontToBack)
            .order;
        let lmax = crate::render::prepare::longest_edge(m) * 1.0001;
        let shader = Shader::Pre(PreintTable::build(&tf, 257, 65, lmax));
        let view = View::new(cam, n, n);
        let (img, stats, _) =
            render_with(&view, &m.points, &m.tets, &field, &order, &shader, schedule);
        assert!(!img.has_nan());
        let mut worst = 0.0f64;
        for (i, (a, b)) in img.pixels.iter().zip(&reference.pixels).enumerate() {
            if b[3] > 1e-3 {
                assert!(a[3] > 0.0, "hole at pixel {i}: reference {b:?}");
            }
            for k in 0..4 {
                worst = worst.max((a[k] - b[k]).abs() as f64);
            }
        }
        (worst, stats, img)
    }

    #[test]
    fn eye_inside_the_mesh_matches_the_ray_caster() {
        // The eye inside a tet of a jittered grid, looking along a generic direction: the tets
        // around the eye reach behind it and take the per-pixel clipping path; the whole image
        // is covered and matches the reference.
        let mut m = structured_grid([3, 3, 3], [0.0; 3], [1.0; 3]);
        jitter(&mut m, [3, 3, 3], 0.15, 11);
        let cam = Camera {
            position: [0.47, 0.52, 0.45],
            focal: [0.9, 0.7, -0.3],
            view_angle: 70.0,
            ..Camera::default()
        };
        for schedule in [Schedule::Tiles, Schedule::Chunks] {
            let (err, st, img) = against_reference(&m, &cam, 40, schedule);
            assert!(st.clipped > 0, "{st:?}");
            assert!(
                img.pixels.iter().all(|p| p[3] > 0.0),
                "the eye is inside: every pixel sees the mesh"
            );
            assert!(err < 0.005, "{schedule:?}: error {err} {st:?}");
        }
    }

    #[test]
    fn schedules_agree() {
        let mut m = structured_grid([4, 4, 4], [0.0; 3], [1.0; 3]);
        jitter(&mut m, [4, 4, 4], 0.2, 3);
        let mut cam = Camera::default();
        cam.reset_to(&m.bounds());
        cam.azimuth(25.0);
        cam.elevation(15.0);
        let (e1, _, a) = against_reference(&m, &cam, 48, Schedule::Tiles);
        let (e2, _, b) = against_reference(&m, &cam, 48, Schedule::Chunks);
        assert!(e1 < 0.02 && e2 < 0.02, "{e1} {e2}");
        for (p, q) in a.pixels.iter().zip(&b.pixels) {
            for k in 0..4 {
                assert!((p[k] - q[k]).abs() < 1e-5, "{p:?} {q:?}");
            }
        }
    }
}
