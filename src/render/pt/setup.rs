//! Per-tet set-up of the rasterizer: the exact silhouette, the front and back face depth planes and the scalar along each pixel's ray, stored as a 128-byte record since a frame holds one per drawn tet.

// Negated comparisons are deliberate: they also catch NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::classify::{class_index, classify, face_areas, orient2, silhouette, ProjClass, FACES};
use super::raster::RowPlanes;
use super::tiles::Tile;
use super::{PixelBox, Projected, PtStats, View, SUB};
use crate::geom;

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
    pub(crate) fn clip(&self, tile: Tile) -> Option<(i64, i64, i64, i64)> {
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

/// Everything one tet needs per pixel, unfolded from its [`Prepared`] record where a tile draws
/// it.
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

/// Linear functions through the three screen points of each of four faces (lane `i` is face
/// `i`, point `j` at `(x[j][i], y[j][i])` with value `v[j][i]`): value at `(ox, oy)`, slopes,
/// twice the signed area, whether the fit is usable (a non-degenerate, finite plane), and
/// whether any face [`snapped_sliver`] (`d`: the faces' snapped areas), for
/// [`sliver_at_a_pixel`] to look closer. The lanes run the same operations side by
/// side, so they compile to vector instructions.
#[inline(always)]
#[allow(clippy::type_complexity)]
fn plane_fits(
    x: &[[f64; 4]; 3],
    y: &[[f64; 4]; 3],
    v: &[[f64; 4]; 3],
    d: &[i64; 4],
    ox: f64,
    oy: f64,
) -> ([[f64; 4]; 3], [f64; 4], [bool; 4], bool) {
    let (mut c, mut ax, mut ay) = ([0f64; 4], [0f64; 4], [0f64; 4]);
    let (mut det, mut ok) = ([0f64; 4], [false; 4]);
    let mut slivers = false;
    for i in 0..4 {
        let (e1x, e1y) = (x[1][i] - x[0][i], y[1][i] - y[0][i]);
        let (e2x, e2y) = (x[2][i] - x[0][i], y[2][i] - y[0][i]);
        let dt = e1x * e2y - e1y * e2x;
        let (d1, d2) = (v[1][i] - v[0][i], v[2][i] - v[0][i]);
        ax[i] = (d1 * e2y - d2 * e1y) / dt;
        ay[i] = (d2 * e1x - d1 * e2x) / dt;
        c[i] = v[0][i] + ax[i] * (ox - x[0][i]) + ay[i] * (oy - y[0][i]);
        det[i] = dt;
        let span = e1x.abs() + e1y.abs() + e2x.abs() + e2y.abs();
        // An area within rounding of zero is a face seen exactly edge-on (see `sliver_bound`):
        // a plane fitted to it is rounding, as steep as it is wrong.
        ok[i] = (dt.abs() > EDGE_ON * span * span)
            & dt.is_finite()
            & ax[i].is_finite()
            & ay[i].is_finite()
            & c[i].is_finite();
        slivers |= sliver_bound(span, dt) | ((dt.abs() <= EDGE_ON * span * span) & (d[i] != 0));
    }
    ([c, ax, ay], det, ok, slivers)
}

/// The true screen positions of the faces' corners, as [`plane_fits`] takes them: point `j` of
/// face `i` at `(x[j][i], y[j][i])`.
#[inline(always)]
fn face_xy(pv: &[&Projected; 4]) -> ([[f64; 4]; 3], [[f64; 4]; 3]) {
    let (mut x, mut y) = ([[0f64; 4]; 3], [[0f64; 4]; 3]);
    for (i, f) in FACES.iter().enumerate() {
        for j in 0..3 {
            x[j][i] = pv[f[j]].px;
            y[j][i] = pv[f[j]].py;
        }
    }
    (x, y)
}

/// A tet's set-up as a frame stores it between binning and drawing: 128 bytes on two cache
/// lines, since every drawn tet's record is written once and read back by each tile it touches.
/// [`Prepared::setup`] unfolds it into the [`TetSetup`] the rasterizer reads, value for value.
#[derive(Clone, Copy)]
#[repr(C, align(64))]
pub(crate) struct Prepared {
    /// Silhouette corners (fixed point), positively oriented; a triangle repeats corner 0 as
    /// corner 3. For a clipped tet, `poly[0][0]` is its index in the run's clipped list.
    poly: [[i32; 2]; 4],
    /// Face depth planes as in [`TetSetup`]: the `nf` front ones, then the `nb` back ones.
    planes: [[f32; 3]; 4],
    sref: [f32; 3],
    h: [f32; 3],
    ox: f32,
    oy: f32,
    w0: f32,
    smin: f32,
    smax: f32,
    /// Silhouette corners, or 0 for a tet drawn by the clipping path.
    nedges: u8,
    nf: u8,
    nb: u8,
}

const _: () = assert!(std::mem::size_of::<Prepared>() == 128);

/// Pixel bounds (x0, y0, x1, y1), inclusive, of the pixel centres in a silhouette's box,
/// clipped to a `w` x `h` image; `None` when empty.
#[inline(always)]
fn pixel_bounds(poly: &[[i32; 2]; 4], w: i64, h: i64) -> Option<PixelBox> {
    box_pixels(poly.map(|p| (p[0] as i64, p[1] as i64)), w, h)
}

/// [`pixel_bounds`] of the box of four fixed-point points.
#[inline(always)]
fn box_pixels(p: [(i64, i64); 4], w: i64, h: i64) -> Option<PixelBox> {
    let xmin = p[0].0.min(p[1].0).min(p[2].0.min(p[3].0));
    let xmax = p[0].0.max(p[1].0).max(p[2].0.max(p[3].0));
    let ymin = p[0].1.min(p[1].1).min(p[2].1.min(p[3].1));
    let ymax = p[0].1.max(p[1].1).max(p[2].1.max(p[3].1));
    // Pixel centres at 256 i + 128 inside [min, max].
    let lo = |v: i64| (v - SUB / 2 + SUB - 1).div_euclid(SUB);
    let hi = |v: i64| (v - SUB / 2).div_euclid(SUB);
    let b = (
        lo(xmin).max(0),
        lo(ymin).max(0),
        hi(xmax).min(w - 1),
        hi(ymax).min(h - 1),
    );
    (b.0 <= b.2 && b.1 <= b.3).then_some(b)
}

impl Prepared {
    /// The record of a tet drawn by the clipping path: entry `k` of its run's clipped list.
    pub(crate) fn clipped(k: u32) -> Prepared {
        Prepared {
            poly: [[k as i32, 0]; 4],
            planes: [[0.0; 3]; 4],
            sref: [0.0; 3],
            h: [0.0; 3],
            ox: 0.0,
            oy: 0.0,
            w0: 0.0,
            smin: 0.0,
            smax: 0.0,
            nedges: 0,
            nf: 0,
            nb: 0,
        }
    }

    /// The index in the run's clipped list of a tet drawn by the clipping path, else `None`.
    #[inline(always)]
    pub(crate) fn clip_index(&self) -> Option<usize> {
        (self.nedges == 0).then_some(self.poly[0][0] as u32 as usize)
    }

    /// The rasterizer's set-up, for a `w` x `h` image (not for a clipped tet).
    #[inline(always)]
    pub(crate) fn setup(&self, w: i64, h: i64) -> TetSetup {
        let (x0, y0, x1, y1) = pixel_bounds(&self.poly, w, h).unwrap_or((0, 0, -1, -1));
        let (nf, nb) = (self.nf as usize, self.nb as usize);
        // Unused slots repeat the first plane of their side, as [`setup_tet`] left them. Each
        // slot is picked by index straight into the set-up: building the sides as arrays first
        // left them on the stack in 4- and 8-byte pieces that a wide copy then read back, which
        // stalls store forwarding on every drawn tet.
        let pl = &self.planes;
        let (f1, f2) = ((nf > 1) as usize, 2 * (nf > 2) as usize);
        let (b1, b2) = (
            (nf + (nb > 1) as usize) & 3,
            (nf + 2 * (nb > 2) as usize) & 3,
        );
        let mut su = TetSetup {
            poly: self.poly,
            nedges: self.nedges as u32,
            x0: x0 as i32,
            x1: x1 as i32,
            y0: y0 as i32,
            y1: y1 as i32,
            ox: self.ox,
            oy: self.oy,
            front: [[0.0; 3]; 3],
            back: [[0.0; 3]; 3],
            w0: self.w0,
            sref: self.sref,
            h: self.h,
            smin: self.smin,
            smax: self.smax,
        };
        // Slot by slot: an array expression here was still built on the stack and copied wide.
        su.front[0] = pl[0];
        su.front[1] = pl[f1];
        su.front[2] = pl[f2];
        su.back[0] = pl[nf & 3];
        su.back[1] = pl[b1];
        su.back[2] = pl[b2];
        su
    }
}

/// Sets up a tet whose vertices all project inside the guard band: writes its record into `out`
/// and returns its pixel bounds (x0, y0, x1, y1), or `None` (with `out` partly written) when it
/// covers no pixel centre; counts its class. The record is written in place since a returned
/// one went through stack copies on its way into the run.
#[inline(always)]
pub(crate) fn setup_tet(
    view: &View,
    pv: &[&Projected; 4],
    s: [f64; 4],
    stats: &mut PtStats,
    out: &mut Prepared,
) -> Option<SetUp> {
    setup_tet_unless(view, pv, s, scalar_range(&s), stats, out, |_| false)
}

/// The tet's scalar range `[min, max]` of its vertex values, as the set-up stores it in f32
/// (`TetSetup::smin`, `smax`); NaN where a value is NaN.
#[inline(always)]
pub(crate) fn scalar_range(s: &[f64; 4]) -> (f32, f32) {
    let smin = s.iter().copied().fold(f64::INFINITY, f64::min);
    let smax = s.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (smin as f32, smax as f32)
}

/// [`setup_tet`], but a tet whose pixel bounds `hidden` calls hidden (every pixel there already
/// opaque) is counted in [`PtStats::hidden`] and not set up: its class is still counted, so the
/// counts do not depend on how soon pixels turn opaque.
#[inline(always)]
pub(crate) fn setup_tet_unless(
    view: &View,
    pv: &[&Projected; 4],
    s: [f64; 4],
    (smin, smax): (f32, f32),
    stats: &mut PtStats,
    out: &mut Prepared,
    hidden: impl Fn(PixelBox) -> bool,
) -> Option<SetUp> {
    let fp = pv.map(|p| (p.fx, p.fy));
    let d = face_areas(&fp);
    let class = classify(&d);
    stats.class[class_index(class)] += 1;
    if class == ProjClass::Flat {
        // Flat on the fixed-point grid, but maybe not in truth: a tet seen nearly edge-on as a
        // whole still has a chord along the line it projects to.
        let (fx, fy) = face_xy(pv);
        let (_, area, _, _) = plane_fits(&fx, &fy, &[[0.0; 4]; 3], &d, 0.0, 0.0);
        return sliver_at_a_pixel(&fx, &fy, &area, &d, view).then_some(SetUp::PerPixel);
    }
    // The silhouette holds all four vertices, so its box is theirs: taken from the vertices,
    // which are at hand, before the silhouette is built.
    let bounds = box_pixels(fp, view.width as i64, view.height as i64)?;
    if hidden(bounds) {
        stats.hidden += 1;
        return None;
    }
    // Silhouette, positively oriented.
    let (corners, nedges) = silhouette(d.map(|x| x.signum() as i8), |a, b, c| {
        orient2(fp[a], fp[b], fp[c]) > 0
    })?;
    // Fixed-point positions lie within the guard band (2^28), so they fit i32.
    let poly = corners.map(|v| [fp[v].0 as i32, fp[v].1 as i32]);

    // Depth planes: w = zunit/z (perspective) or z (parallel), relative to vertex 0; depth
    // offsets then come out in units of zunit (see `View::zunit`).
    let wv = pv.map(|p| {
        if view.parallel {
            p.view[2]
        } else {
            view.zunit / p.view[2]
        }
    });
    let w0 = wv[0];
    let (ox, oy) = (pv[0].px, pv[0].py);
    // Which sign group faces the eye: decided in 3-D on the face with the largest projection.
    let big = (0..4).max_by_key(|&i| d[i].abs()).unwrap_or(0);
    let fb = FACES[big];
    let fv = [pv[fb[0]].view, pv[fb[1]].view, pv[fb[2]].view];
    let sub = |a: [f64; 3], b: [f64; 3]| geom::sub(&a, &b);
    let cr = |a: [f64; 3], b: [f64; 3]| geom::cross(&a, &b);
    let dt = |a: [f64; 3], b: [f64; 3]| geom::dot(&a, &b);
    let n = cr(sub(fv[1], fv[0]), sub(fv[2], fv[0]));
    let vside = dt(n, sub(pv[big].view, fv[0]));
    let eside = if view.parallel { -n[2] } else { -dt(n, fv[0]) };
    // Front when the eye and the opposite vertex are on different sides of the face plane.
    let big_front = (vside > 0.0) != (eside > 0.0);
    let big_pos = d[big] > 0;
    let (mut nf, mut nb) = (0, 0);
    let (fx, fy) = face_xy(pv);
    let mut fw = [[0f64; 4]; 3];
    for (i, f) in FACES.iter().enumerate() {
        for j in 0..3 {
            fw[j][i] = wv[f[j]] - w0;
        }
    }
    let (pl, area, fit, slivers) = plane_fits(&fx, &fy, &fw, &d, ox, oy);
    if slivers && sliver_at_a_pixel(&fx, &fy, &area, &d, view) {
        return Some(SetUp::PerPixel);
    }
    // Per face: 0 unused, 1 front, 2 back.
    let mut side = [0u8; 4];
    for i in 0..4 {
        if d[i] == 0 || !fit[i] {
            continue;
        }
        // Front or back by the unsnapped projection the plane was fitted to: a face seen nearly
        // edge-on can change sign on the fixed-point grid, and a flipped steep plane would cut
        // the whole tet away.
        if (area[i] > 0.0) == (big_pos == big_front) {
            side[i] = 1;
            nf += 1;
        } else {
            side[i] = 2;
            nb += 1;
        }
    }
    if nf == 0 || nb == 0 {
        return None;
    }
    // At most four faces are fitted, so the two sides fill the record's four plane slots: the
    // front ones, then the back ones, written straight into the record (built on the stack
    // first, they were read back wide from narrow stores, which stalls).
    let mut k = 0;
    for want in [1, 2] {
        for i in 0..4 {
            if side[i] == want {
                out.planes[k & 3] = [pl[0][i] as f32, pl[1][i] as f32, pl[2][i] as f32];
                k += 1;
            }
        }
    }
    for slot in out.planes.iter_mut().skip(k) {
        *slot = [0.0; 3];
    }

    // Scalar gradient in view coordinates.
    let e = [
        sub(pv[1].view, pv[0].view),
        sub(pv[2].view, pv[0].view),
        sub(pv[3].view, pv[0].view),
    ];
    let ds = [s[1] - s[0], s[2] - s[0], s[3] - s[0]];
    let det = dt(e[0], cr(e[1], e[2]));
    let g = if det != 0.0 && det.is_finite() {
        let (c0, c1, c2) = (cr(e[1], e[2]), cr(e[2], e[0]), cr(e[0], e[1]));
        let ga = |a: usize| (ds[0] * c0[a] + ds[1] * c1[a] + ds[2] * c2[a]) / det;
        [ga(0), ga(1), ga(2)]
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
    out.poly = poly;
    out.sref = sref.map(|x| x as f32);
    // Per unit of depth offset, which is `zunit` (exact: a power of two).
    out.h = h.map(|x| (x * view.zunit) as f32);
    out.ox = ox as f32;
    out.oy = oy as f32;
    out.w0 = w0 as f32;
    out.smin = smin;
    out.smax = smax;
    out.nedges = nedges;
    out.nf = nf as u8;
    out.nb = nb as u8;
    Some(SetUp::Raster(bounds))
}

/// What the set-up made of a tet that draws something.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SetUp {
    /// A record for the rasterizer, and its pixel bounds (x0, y0, x1, y1), inclusive.
    Raster(PixelBox),
    /// The per-pixel clipping path must draw it: see [`snapped_sliver`].
    PerPixel,
}

/// Whether face `i` (twice its signed area `area[i]`, from the unsnapped corners
/// `(x[j][i], y[j][i])`) is a sliver the fixed-point grid may misdraw: its orientation could
/// change sign, or vanish, there, or it is within a few times that of doing so ([`SLIVER`]).
/// Each corner moves by at most half a fixed-point unit per axis on the grid, which changes
/// twice the area by at most `span / SUB + 2 / SUB^2`. Such a face is seen nearly edge-on, so a ray close to its line
/// runs along it for a long way, and the snapped silhouettes may hand that ray to the tet on the
/// face's other side, whose planes give it no chord (the chord was lost: a vertex on a pixel
/// centre with a face 0.1 degrees off edge-on, `fixtures/newuser/vertex_ray.vtu`). An area
/// within rounding of zero ([`EDGE_ON`] of the squared span; an axis-aligned grid's faces seen
/// along an axis come out so) is a face exactly edge-on: its plane bounds nothing, and it is
/// left to the fixed-point grid, whose owner rule gives a ray in its plane to one side only,
/// unless the grid made it a sliver (snapped area `d[i]` not zero). A pixel centre in that
/// sliver was covered by both tets that share the face, each drawing the whole stretch along it
/// (an eye on a grid node: 35/255 too bright).
#[inline(always)]
fn snapped_sliver(
    x: &[[f64; 4]; 3],
    y: &[[f64; 4]; 3],
    area: &[f64; 4],
    d: &[i64; 4],
    i: usize,
) -> bool {
    let span = (x[1][i] - x[0][i]).abs()
        + (y[1][i] - y[0][i]).abs()
        + (x[2][i] - x[0][i]).abs()
        + (y[2][i] - y[0][i]).abs();
    sliver_bound(span, area[i]) || (area[i].abs() <= EDGE_ON * span * span && d[i] != 0)
}

/// [`snapped_sliver`] of a face whose edges from its first corner have the summed absolute
/// components `span`, and twice its signed area `area`.
#[inline(always)]
fn sliver_bound(span: f64, area: f64) -> bool {
    let u = 1.0 / SUB as f64;
    let bound = SLIVER * (span * u + 2.0 * u * u);
    (area.abs() > EDGE_ON * span * span) & (area.abs() <= bound)
}

/// How many times the largest change snapping can make to twice a face's area (see
/// [`snapped_sliver`]) still marks the face as a sliver for the per-pixel path. Twice would catch
/// the faces whose orientation can flip, with room for rounding in the areas themselves; but a
/// face that does not flip and is only a few fixed-point units thin on screen still has its
/// chord rise from 0 to the tet's thickness across those few units, so a pixel centre that
/// snapping moves across its edge went to the neighbour, whose chord there is about 0: a Gmsh
/// box with a spherical cavity had a pixel 4/255 dark (a face 4 units thin, the centre 0.4 units
/// from its edge, a 0.024 chord lost). Four times leaves at most about a fifth of a thickness to
/// the snapped edges, where the face is thin enough for that to be small; sixteen times sent 5x
/// as many tets to the per-pixel path and made 200k-tet frames 7 % slower.
const SLIVER: f64 = 4.0;

/// Twice a face's projected area, over its squared span (see [`snapped_sliver`]), at or below
/// which the face is seen exactly edge-on: the area is rounding (an eye in the face's plane, or
/// an axis-aligned grid seen along an axis, gives a few 1e-17).
const EDGE_ON: f64 = 1e-10;

/// Whether a pixel centre of a `view` lies near a face that [`snapped_sliver`] picks: within the
/// face's thickness plus two fixed-point units of its longest edge's line, along that edge.
/// Elsewhere the snapped silhouettes lose at most the sliver between snapped and true edges,
/// where the chord is small.
fn sliver_at_a_pixel(
    x: &[[f64; 4]; 3],
    y: &[[f64; 4]; 3],
    area: &[f64; 4],
    d: &[i64; 4],
    view: &View,
) -> bool {
    (0..4).any(|i| {
        snapped_sliver(x, y, area, d, i)
            && near_a_pixel_centre(
                [0, 1, 2].map(|j| (x[j][i], y[j][i])),
                area[i].abs(),
                view.width as i64,
                view.height as i64,
            )
    })
}

/// Whether a pixel centre `(k + 0.5, l + 0.5)` of a `w` x `h` image lies within the rectangle
/// around triangle `p` (twice its area `area2`): along its longest edge, widened by `2 / SUB`
/// pixels each way, and across it by the third corner's distance plus `2 / SUB`.
fn near_a_pixel_centre(p: [(f64, f64); 3], area2: f64, w: i64, h: i64) -> bool {
    let r = 2.0 / SUB as f64;
    let len2 = |a: (f64, f64), b: (f64, f64)| (b.0 - a.0).powi(2) + (b.1 - a.1).powi(2);
    let edges = [(0, 1), (1, 2), (2, 0)];
    let (ia, ib) = edges
        .into_iter()
        .max_by(|e, f| len2(p[e.0], p[e.1]).total_cmp(&len2(p[f.0], p[f.1])))
        .unwrap_or((0, 1));
    let (a, b) = (p[ia], p[ib]);
    let len = len2(a, b).sqrt();
    if !(len.is_finite() && area2.is_finite()) {
        return false;
    }
    if len < r {
        // All three corners within `r` of each other: a box around them.
        let q = |v: f64| v - 0.5;
        let (x0, x1) = (q(a.0 - 2.0 * r).ceil(), q(a.0 + 2.0 * r).floor());
        let (y0, y1) = (q(a.1 - 2.0 * r).ceil(), q(a.1 + 2.0 * r).floor());
        return x0 <= x1 && y0 <= y1 && x1 >= 0.0 && y1 >= 0.0 && x0 < w as f64 && y0 < h as f64;
    }
    // Unit direction `u` along the edge, normal `n`; the band is |n.(c - a)| <= across and
    // -r <= u.(c - a) <= len + r.
    let u = ((b.0 - a.0) / len, (b.1 - a.1) / len);
    let n = (-u.1, u.0);
    let across = area2 / len + r;
    // Walk the axis the edge runs along most, so each step is one pixel column (or row).
    let (a, u, n, w, h) = if u.0.abs() >= u.1.abs() {
        (a, u, n, w, h)
    } else {
        ((a.1, a.0), (u.1, u.0), (n.1, n.0), h, w)
    };
    let lo = (a.0 + (-r * u.0).min((len + r) * u.0) - across * n.0.abs() - 0.5)
        .ceil()
        .max(0.0);
    let hi = (a.0 + (-r * u.0).max((len + r) * u.0) + across * n.0.abs() - 0.5)
        .floor()
        .min(w as f64 - 1.0);
    let mut k = lo;
    while k <= hi {
        let cx = k + 0.5 - a.0;
        // Each condition is `lo <= c * t + d <= hi` in the column's other coordinate `t`.
        let mut t0 = f64::NEG_INFINITY;
        let mut t1 = f64::INFINITY;
        for (c, d, l, hh) in [
            (n.1, n.0 * cx, -across, across),
            (u.1, u.0 * cx, -r, len + r),
        ] {
            if c == 0.0 {
                if d < l || d > hh {
                    t0 = f64::INFINITY;
                }
            } else {
                let (e0, e1) = ((l - d) / c, (hh - d) / c);
                t0 = t0.max(e0.min(e1));
                t1 = t1.min(e0.max(e1));
            }
        }
        // Pixel centres t = m + 0.5 - a.1 with 0 <= m < h.
        let m0 = (t0 + a.1 - 0.5).ceil().max(0.0);
        let m1 = (t1 + a.1 - 0.5).floor().min(h as f64 - 1.0);
        if m0 <= m1 {
            return true;
        }
        k += 1.0;
    }
    false
}

/// A fragment's entry and exit depths relative to vertex 0's depth (in units of
/// [`View::zunit`]), and its scalar as
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Camera;
    use crate::render::pt::project_points;
    use proptest::prelude::*;

    /// Pixel box of all four projected vertices, clamped to the image: what the set-up used to
    /// bound a tet before the record kept only its silhouette.
    fn vertex_box(p: &[Projected], w: i64, h: i64) -> Option<PixelBox> {
        let xs = p.iter().map(|q| q.fx);
        let ys = p.iter().map(|q| q.fy);
        let (xmin, xmax) = (xs.clone().min()?, xs.max()?);
        let (ymin, ymax) = (ys.clone().min()?, ys.max()?);
        let lo = |v: i64| (v - SUB / 2 + SUB - 1).div_euclid(SUB);
        let hi = |v: i64| (v - SUB / 2).div_euclid(SUB);
        let b = (
            lo(xmin).max(0),
            lo(ymin).max(0),
            hi(xmax).min(w - 1),
            hi(ymax).min(h - 1),
        );
        (b.0 <= b.2 && b.1 <= b.3).then_some(b)
    }

    proptest! {
        /// A record's box is the box of all four vertices (the silhouette holds them in every
        /// class, the degenerate ones included), and it unfolds into the set-up the rasterizer
        /// reads: the fitted front planes, then the back ones, unused slots repeating a side's
        /// first plane.
        #[test]
        fn record_unfolds_to_the_setup(
            pts in prop::array::uniform4(prop::array::uniform3(-1.0f64..1.0)),
            s in prop::array::uniform4(0.0f64..1.0),
            snap in 0usize..3,
            parallel in any::<bool>(),
        ) {
            // A face seen exactly edge-on needs exact screen positions: a parallel view where
            // multiples of 1/32 land on whole pixels, and vertex 3 above the middle of edge 0-1.
            let exact = snap == 2;
            let cam = Camera {
                position: if exact { [0.0, 0.0, 4.0] } else { [0.3, -0.2, 4.0] },
                parallel: parallel || exact,
                parallel_scale: if exact { 1.0 } else { 1.5 },
                ..Camera::default()
            };
            let (w, h) = if exact { (64u32, 64u32) } else { (97, 64) };
            let view = View::new(&cam, w, h);
            let mut pts = pts.to_vec();
            match snap {
                // Vertex 3 on vertex 2's view ray: an edge seen end-on.
                1 => {
                    let d = if parallel {
                        [0.0, 0.0, -1.0]
                    } else {
                        geom::sub(&pts[2], &cam.position)
                    };
                    pts[3] = [0, 1, 2].map(|k| pts[2][k] + 0.1 * d[k]);
                }
                2 => {
                    for p in &mut pts[..2] {
                        p[0] = (p[0] * 32.0).round() / 32.0;
                        p[1] = (p[1] * 32.0).round() / 32.0;
                    }
                    pts[3][0] = 0.5 * (pts[0][0] + pts[1][0]);
                    pts[3][1] = 0.5 * (pts[0][1] + pts[1][1]);
                }
                _ => {}
            }
            let proj = project_points(&view, &pts);
            let pv = [&proj[0], &proj[1], &proj[2], &proj[3]];
            let mut st = PtStats::default();
            let mut rec = Prepared::clipped(0);
            if let Some(SetUp::Raster(b)) = setup_tet(&view, &pv, s, &mut st, &mut rec) {
                prop_assert_eq!(Some(b), vertex_box(&proj, w as i64, h as i64));
                prop_assert_eq!(rec.clip_index(), None);
                let su = rec.setup(w as i64, h as i64);
                let sb = (su.x0 as i64, su.y0 as i64, su.x1 as i64, su.y1 as i64);
                prop_assert_eq!(sb, b);
                let (nf, nb) = (rec.nf as usize, rec.nb as usize);
                prop_assert!(nf >= 1 && nb >= 1 && nf + nb <= 4);
                for k in 0..3 {
                    let f = rec.planes[if k < nf { k } else { 0 }];
                    let bk = rec.planes[nf + if k < nb { k } else { 0 }];
                    prop_assert_eq!(su.front[k].map(f32::to_bits), f.map(f32::to_bits));
                    prop_assert_eq!(su.back[k].map(f32::to_bits), bk.map(f32::to_bits));
                }
                prop_assert_eq!(su.nedges, rec.nedges as u32);
                prop_assert!(su.nedges == 3 || su.nedges == 4);
            }
        }
    }

    proptest! {
        /// The band walk finds a pixel centre exactly when one lies in the band (checked by
        /// trying every pixel centre), for thin triangles at any slope, near and across the
        /// image's edges; cases with a centre within 1e-9 of the band's border are skipped.
        #[test]
        fn the_band_walk_finds_the_pixel_centres_in_the_band(
            a in prop::array::uniform2(-3.0f64..15.0),
            dir in 0.0f64..std::f64::consts::TAU,
            len in 0.0f64..9.0,
            along in 0.0f64..1.0,
            off in -0.05f64..0.05,
        ) {
            let (w, h) = (12i64, 9i64);
            let b = (a[0] + len * dir.cos(), a[1] + len * dir.sin());
            // The third corner beside the edge a-b, `off` pixels off its line.
            let c = (
                a[0] + along * (b.0 - a[0]) - off * dir.sin(),
                a[1] + along * (b.1 - a[1]) + off * dir.cos(),
            );
            let p = [(a[0], a[1]), b, c];
            let area2 = ((b.0 - a[0]) * (c.1 - a[1]) - (b.1 - a[1]) * (c.0 - a[0])).abs();
            let got = near_a_pixel_centre(p, area2, w, h);
            // The band as the walk defines it, tried at every pixel centre.
            let r = 2.0 / SUB as f64;
            let len2 = |p: (f64, f64), q: (f64, f64)| (q.0 - p.0).powi(2) + (q.1 - p.1).powi(2);
            let (ia, ib) = [(0, 1), (1, 2), (2, 0)]
                .into_iter()
                .max_by(|e, f| len2(p[e.0], p[e.1]).total_cmp(&len2(p[f.0], p[f.1])))
                .unwrap_or((0, 1));
            let (pa, pb) = (p[ia], p[ib]);
            let l = len2(pa, pb).sqrt();
            let mut want = false;
            for y in 0..h {
                for x in 0..w {
                    let q = (x as f64 + 0.5 - pa.0, y as f64 + 0.5 - pa.1);
                    // Distances outside the band (negative inside), each way.
                    let slack = if l < r {
                        (q.0.abs() - 2.0 * r).max(q.1.abs() - 2.0 * r)
                    } else {
                        let u = ((pb.0 - pa.0) / l, (pb.1 - pa.1) / l);
                        let s = q.0 * u.0 + q.1 * u.1;
                        let t = -q.0 * u.1 + q.1 * u.0;
                        (t.abs() - (area2 / l + r)).max(-r - s).max(s - l - r)
                    };
                    prop_assume!(slack.abs() > 1e-9);
                    want |= slack < 0.0;
                }
            }
            prop_assert_eq!(got, want);
        }
    }

    #[test]
    fn records_are_two_cache_lines() {
        assert_eq!(std::mem::size_of::<Prepared>(), 128);
        assert_eq!(std::mem::align_of::<Prepared>(), 64);
    }

    #[test]
    fn a_clipped_record_names_its_entry() {
        assert_eq!(Prepared::clipped(7).clip_index(), Some(7));
    }
}
