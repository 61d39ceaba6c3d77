//! The rasterizer: each row's exactly covered pixels of a tet's silhouette, batched across rows into lanes for (Sf, Sb, l), shaded and composited front to back.

use super::setup::TetSetup;
use super::shade::{Drawn, Lanes, Shade, LANES};
use super::tiles::Tile;
use super::SUB;

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

/// The silhouette's edge functions over the lanes `x0 .. x0 + L` of one row in `i32`, for a tet
/// small enough that no value there can overflow: a row's covered pixels come from one
/// vectorized sign test instead of a search for each bound. `L` is 8 or 16.
struct Cover<const L: usize> {
    /// Edge values at the current row.
    row: [[i32; L]; 4],
    /// Change of each edge value from one row to the next.
    step: [i32; 4],
    /// Lanes inside the clipped box.
    lanes: u32,
    /// Pixel of lane 0.
    x0: i64,
}

/// Largest silhouette extent (fixed point) on either axis that [`Cover`] takes: every edge
/// value it evaluates is then below `2^30` in magnitude (see [`Cover::new`]).
const EXTENT: i64 = 1 << 14;

/// The silhouette's edge functions in `i32` at the first pixel of a clipped box at most 16
/// pixels wide: what [`Cover`] fills its lanes from (and the AVX-512 rows their registers).
pub(super) struct CoverEdges {
    /// Value of each edge at the box's first pixel centre.
    pub(super) e0: [i32; 4],
    /// Change of each edge value from one pixel to the next along a row.
    pub(super) ea: [i32; 4],
    /// Change of each edge value from one row to the next.
    pub(super) step: [i32; 4],
    /// Lanes inside the clipped box.
    pub(super) lanes: u32,
    /// Pixel of lane 0.
    pub(super) x0: i64,
}

impl CoverEdges {
    /// The edges of the clipped box starting at pixel `(x0, y0)`, `w <= 16` pixels wide;
    /// `None` when the silhouette is too large for `i32`.
    #[inline(always)]
    pub(super) fn new(t: &TetSetup, x0: i64, y0: i64, w: i64) -> Option<CoverEdges> {
        debug_assert!((1..=16).contains(&w));
        // Edge k runs from corner k to the next; a triangle's unused slot repeats its first
        // edge, so the minimum over all four is unchanged.
        let p = &t.poly;
        let tri = t.nedges != 4;
        let from = [p[0], p[1], p[2], if tri { p[0] } else { p[3] }];
        let to = [
            p[1],
            p[2],
            if tri { p[0] } else { p[3] },
            if tri { p[1] } else { p[0] },
        ];
        let (mut xmin, mut xmax, mut ymin, mut ymax) = (i32::MAX, i32::MIN, i32::MAX, i32::MIN);
        for c in &from {
            xmin = xmin.min(c[0]);
            xmax = xmax.max(c[0]);
            ymin = ymin.min(c[1]);
            ymax = ymax.max(c[1]);
        }
        // Edge vectors are then at most `2^14` on each axis, and a lane's centre at most `2^14`
        // from every corner vertically and `2^14 + 16 * 256` horizontally (the box's first
        // centre is not left of the silhouette's bounds): `|a X + b Y + c| < 2^29 + 2^26 + 1`.
        if (xmax as i64 - xmin as i64) > EXTENT || (ymax as i64 - ymin as i64) > EXTENT {
            return None;
        }
        // The box's first pixel centre, inside the silhouette's bounds: within `2^14` of
        // every corner on each axis.
        let (cx, cy) = (x0 * SUB + SUB / 2, y0 * SUB + SUB / 2);
        let sub = SUB as i32;
        let (mut e0, mut ea, mut step) = ([0i32; 4], [0i32; 4], [0i32; 4]);
        for k in 0..4 {
            // E(X, Y) = dx (Y - py) - dy (X - px), with the owner rule of [`Edge::new`]: the
            // same integer as the `i64` edge function, every term bounded as above, so `i32`
            // holds it exactly and the four edges go side by side.
            let (dx, dy) = (to[k][0] - from[k][0], to[k][1] - from[k][1]);
            let own = dy < 0 || (dy == 0 && dx > 0);
            let (rx, ry) = (
                (cx - from[k][0] as i64) as i32,
                (cy - from[k][1] as i64) as i32,
            );
            e0[k] = dx * ry - dy * rx - (!own) as i32;
            ea[k] = -dy * sub;
            step[k] = dx * sub;
        }
        Some(CoverEdges {
            e0,
            ea,
            step,
            lanes: (1u32 << w) - 1,
            x0,
        })
    }
}

impl<const L: usize> Cover<L> {
    /// The cover of the clipped box starting at pixel `(x0, y0)`, at most `L` pixels wide (`w`);
    /// `None` when the silhouette is too large for `i32`.
    #[inline(always)]
    fn new(t: &TetSetup, x0: i64, y0: i64, w: i64) -> Option<Cover<L>> {
        debug_assert!(w as usize <= L && L <= 16);
        let e = CoverEdges::new(t, x0, y0, w)?;
        let mut row = [[0i32; L]; 4];
        for (k, r) in row.iter_mut().enumerate() {
            for (i, v) in r.iter_mut().enumerate() {
                *v = e.e0[k] + e.ea[k] * i as i32;
            }
        }
        Some(Cover {
            row,
            step: e.step,
            lanes: e.lanes,
            x0: e.x0,
        })
    }
}

/// The covered run of each row of a tet's clipped box, top to bottom.
pub(super) trait Rows {
    /// The covered pixels `[xa, xb]` of the next row, `None` when it has none.
    fn next_row(&mut self) -> Option<(i64, i64)>;
}

impl<const L: usize> Rows for Cover<L> {
    #[inline(always)]
    fn next_row(&mut self) -> Option<(i64, i64)> {
        let mut m = [0i32; L];
        for (i, v) in m.iter_mut().enumerate() {
            *v = self.row[0][i]
                .min(self.row[1][i])
                .min(self.row[2][i])
                .min(self.row[3][i]);
        }
        for k in 0..4 {
            let s = self.step[k];
            for v in self.row[k].iter_mut() {
                // Past the last row the values are not used, so wrapping is harmless.
                *v = v.wrapping_add(s);
            }
        }
        let bits = !negative_lanes(&m) & self.lanes;
        (bits != 0).then(|| {
            (
                self.x0 + bits.trailing_zeros() as i64,
                self.x0 + 31 - bits.leading_zeros() as i64,
            )
        })
    }
}

/// Rows of a box too wide or a silhouette too large for [`Cover`]: each bound searched.
struct Search {
    edges: SpanEdges,
    y: i64,
    x0: i64,
    x1: i64,
}

impl Rows for Search {
    #[inline(always)]
    fn next_row(&mut self) -> Option<(i64, i64)> {
        let s = self.edges.span(self.y, self.x0, self.x1);
        self.y += 1;
        s
    }
}

/// Bit `i` set when `m[i] < 0`, for 8 or 16 lanes.
#[inline(always)]
fn negative_lanes<const L: usize>(m: &[i32; L]) -> u32 {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::*;
        // SAFETY: SSE2 is part of x86_64, and the unaligned loads read `m`'s lanes: two 4-lane
        // vectors when L is 8, four when 16. Saturating packs keep each lane's sign, so the byte
        // mask is the lanes' sign mask.
        unsafe {
            let p = m.as_ptr() as *const __m128i;
            let a = _mm_packs_epi32(_mm_loadu_si128(p), _mm_loadu_si128(p.add(1)));
            if L == 8 {
                (_mm_movemask_epi8(_mm_packs_epi16(a, a)) & 0xff) as u32
            } else {
                let b = _mm_packs_epi32(_mm_loadu_si128(p.add(2)), _mm_loadu_si128(p.add(3)));
                _mm_movemask_epi8(_mm_packs_epi16(a, b)) as u32
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let mut bits = 0u32;
        for (i, v) in m.iter().enumerate() {
            bits |= ((*v < 0) as u32) << i;
        }
        bits
    }
}

/// One row's depth and scalar planes with the row's offset folded in: `[value at dx = 0, slope]`.
pub(crate) struct RowPlanes {
    pub(crate) front: [[f32; 2]; 3],
    pub(crate) back: [[f32; 2]; 3],
    pub(crate) sref: [f32; 2],
    pub(crate) h: [f32; 2],
}

impl RowPlanes {
    #[inline(always)]
    pub(crate) fn new(t: &TetSetup, dy: f32) -> RowPlanes {
        let r = |p: &[f32; 3]| [p[0] + p[2] * dy, p[1]];
        RowPlanes {
            front: [r(&t.front[0]), r(&t.front[1]), r(&t.front[2])],
            back: [r(&t.back[0]), r(&t.back[1]), r(&t.back[2])],
            sref: r(&t.sref),
            h: r(&t.h),
        }
    }
}

/// Pixels waiting for the fragment math: up to [`LANES`] covered pixels of one tet, from any
/// rows, so short rows do not leave lanes idle.
struct Batch {
    /// Pixel centre relative to vertex 0, per lane.
    dx: [f32; LANES],
    dy: [f32; LANES],
    /// World length of the view ray per unit of depth, per lane.
    st: [f32; LANES],
    /// Index of each lane's pixel in the tile buffer.
    at: [usize; LANES],
    n: usize,
}

/// `a.max(b)` with the choices `f32::max` leaves open made: `b` when `a` is NaN or `b > a`, else
/// `a` (so `max(-0, +0)` is `-0`), as x86's `maxps(b, a)` plus a NaN select computes it.
#[inline(always)]
pub(super) fn max_of(a: f32, b: f32) -> f32 {
    if a.is_nan() || b > a {
        b
    } else {
        a
    }
}

/// `a.min(b)` made definite as [`max_of`]: `b` when `a` is NaN or `b < a`, else `a`.
#[inline(always)]
pub(super) fn min_of(a: f32, b: f32) -> f32 {
    if a.is_nan() || b < a {
        b
    } else {
        a
    }
}

/// `x.clamp(lo, hi)` without its check that `lo <= hi`: NaN passes through.
#[inline(always)]
pub(super) fn clamp_to(x: f32, lo: f32, hi: f32) -> f32 {
    let x = if x < lo { lo } else { x };
    if x > hi {
        hi
    } else {
        x
    }
}

/// (Sf, Sb, l) of the [`LANES`] pixels of a batch: all three plane slots evaluated (the unused
/// ones repeat a used plane), so no branch depends on the tet's class. Each plane is evaluated
/// as `(c + ay dy) + ax dx`, the order of [`RowPlanes`], so every path gives the same bits (the
/// explicit-SIMD one in `raster_x86` does these operations in this order).
#[inline(always)]
fn fragments(t: &TetSetup, parallel: bool, b: &Batch) -> Lanes {
    let ev = |p: &[f32; 3], i: usize| (p[0] + p[2] * b.dy[i]) + p[1] * b.dx[i];
    let (mut zf, mut zb) = ([0f32; LANES], [0f32; LANES]);
    if parallel {
        for i in 0..LANES {
            zf[i] = max_of(
                max_of(ev(&t.front[0], i), ev(&t.front[1], i)),
                ev(&t.front[2], i),
            );
            zb[i] = min_of(
                min_of(ev(&t.back[0], i), ev(&t.back[1], i)),
                ev(&t.back[2], i),
            );
        }
    } else {
        let w0 = t.w0;
        for i in 0..LANES {
            let df = min_of(
                min_of(ev(&t.front[0], i), ev(&t.front[1], i)),
                ev(&t.front[2], i),
            );
            let db = max_of(
                max_of(ev(&t.back[0], i), ev(&t.back[1], i)),
                ev(&t.back[2], i),
            );
            // z - z0 = 1/(w0 + d) - 1/w0 = -d / (w0 (w0 + d)).
            zf[i] = -df / (w0 * (w0 + df));
            zb[i] = -db / (w0 * (w0 + db));
        }
    }
    let (mut sf, mut sb, mut l) = ([0f32; LANES], [0f32; LANES], [0f32; LANES]);
    for i in 0..LANES {
        let sref = ev(&t.sref, i);
        let h = ev(&t.h, i);
        sf[i] = clamp_to(sref + zf[i] * h, t.smin, t.smax);
        sb[i] = clamp_to(sref + zb[i] * h, t.smin, t.smax);
        let li = max_of((zb[i] - zf[i]) * b.st[i], 0.0);
        l[i] = if li.is_finite() { li } else { 0.0 };
    }
    [sf, sb, l]
}

/// Shades the first `b.n` lanes of a batch and composites them behind what `buf` holds.
#[inline(always)]
fn flush<S: Shade>(
    t: &TetSetup,
    parallel: bool,
    b: &Batch,
    buf: &mut [[f32; 4]],
    shade: &S,
    d: &mut Drawn,
) {
    let f = fragments(t, parallel, b);
    shade.composite(&f, &b.at, b.n, buf, d);
}

/// Rasterizes one tet into a tile buffer (front to back). Returns fragments drawn and how many
/// pixels became opaque.
#[inline(always)]
pub(crate) fn raster<S: Shade>(
    t: &TetSetup,
    parallel: bool,
    tile: Tile,
    buf: &mut [[f32; 4]],
    stretch: &[f32],
    width: usize,
    shade: &S,
) -> (u64, usize) {
    raster_with(t, parallel, tile, buf, stretch, width, shade, Path::Best)
}

/// Which rows [`raster_with`] may take: every path gives the same bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Path {
    /// The portable rows.
    Scalar,
    /// Explicit AVX2 where the CPU has it (the tests hold it to the others' bits).
    #[cfg_attr(not(test), allow(dead_code))]
    Avx2,
    /// The widest the CPU has (AVX-512, AVX2, or the portable rows).
    Best,
}

/// [`raster`] with the rows of path `simd` (or the widest below it the CPU has).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn raster_with<S: Shade>(
    t: &TetSetup,
    parallel: bool,
    tile: Tile,
    buf: &mut [[f32; 4]],
    stretch: &[f32],
    width: usize,
    shade: &S,
    simd: Path,
) -> (u64, usize) {
    let Some((x0, x1, y0, y1)) = t.clip(tile) else {
        return (0, 0);
    };
    let w = x1 - x0 + 1;
    let draw = Draw {
        t,
        parallel,
        tile,
        stretch,
        width,
        shade,
    };
    #[cfg(target_arch = "x86_64")]
    if simd == Path::Best && w <= 16 && super::raster_x86::wide_rows_fit(&draw, x1, y1) {
        if let Some(c) = CoverEdges::new(t, x0, y0, w) {
            // SAFETY: the CPU has AVX2, AVX-512F, AVX-512VL, POPCNT and BMI1, and the stretch map holds
            // every pixel of rows `y0 ..= y1` up to `x1` (both checked by `wide_rows_fit`).
            let d = unsafe { super::raster_x86::wide_rows(&draw, &c, y0, y1, buf) };
            return (d.frags, d.opaque);
        }
    }
    let d = if w <= 8 {
        Cover::<8>::new(t, x0, y0, w).map(|c| draw.run_with(c, y0, y1, buf, simd))
    } else if w <= 16 {
        Cover::<16>::new(t, x0, y0, w).map(|c| draw.run_with(c, y0, y1, buf, simd))
    } else {
        None
    };
    let d = d.unwrap_or_else(|| {
        let s = Search {
            edges: SpanEdges::new(t),
            y: y0,
            x0,
            x1,
        };
        draw.run_with(s, y0, y1, buf, simd)
    });
    (d.frags, d.opaque)
}

/// What drawing a tet into one tile reads besides its rows.
pub(super) struct Draw<'a, S> {
    pub(super) t: &'a TetSetup,
    pub(super) parallel: bool,
    pub(super) tile: Tile,
    pub(super) stretch: &'a [f32],
    pub(super) width: usize,
    pub(super) shade: &'a S,
}

impl<S: Shade> Draw<'_, S> {
    /// [`Draw::rows`] by `simd`'s path, or the widest below it the CPU has (the same bits).
    #[inline(always)]
    fn run_with<R: Rows>(
        &self,
        rows: R,
        y0: i64,
        y1: i64,
        buf: &mut [[f32; 4]],
        simd: Path,
    ) -> Drawn {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::is_x86_feature_detected as has;
            if simd == Path::Best && has!("avx2") && has!("avx512f") && has!("avx512vl") {
                // SAFETY: the CPU has AVX2, AVX-512F and AVX-512VL, checked just above.
                return unsafe { super::raster_x86::rows512(self, rows, y0, y1, buf) };
            }
            if simd != Path::Scalar && has!("avx2") {
                // SAFETY: the CPU has AVX2, checked just above.
                return unsafe { super::raster_x86::rows(self, rows, y0, y1, buf) };
            }
        }
        let _ = simd;
        self.rows(rows, y0, y1, buf)
    }

    /// Draws rows `y0 ..= y1` of the tet, the covered run of each from `rows`, batching pixels
    /// of consecutive rows into the lanes of the fragment math.
    #[inline(always)]
    fn rows<R: Rows>(&self, mut rows: R, y0: i64, y1: i64, buf: &mut [[f32; 4]]) -> Drawn {
        let (t, parallel, shade) = (self.t, self.parallel, self.shade);
        let (tx0, ty0, tx1, _) = self.tile;
        let tw = (tx1 - tx0 + 1) as usize;
        let mut d = Drawn::default();
        let mut b = Batch {
            dx: [0.0; LANES],
            dy: [0.0; LANES],
            st: [0.0; LANES],
            at: [0; LANES],
            n: 0,
        };
        for y in y0..=y1 {
            let Some((xa, xb)) = rows.next_row() else {
                continue;
            };
            let dy = y as f32 + 0.5 - t.oy;
            let row = (y - ty0) as usize * tw;
            let s0 = y as usize * self.width;
            let run = &self.stretch[s0 + xa as usize..=s0 + xb as usize];
            for (x, &st) in (xa..=xb).zip(run) {
                // `b.n < LANES` always; the modulo only spares the bounds checks.
                let n = b.n % LANES;
                b.dx[n] = x as i32 as f32 + 0.5 - t.ox;
                b.dy[n] = dy;
                b.st[n] = st;
                b.at[n] = row + (x - tx0) as usize;
                b.n = n + 1;
                if b.n == LANES {
                    flush(t, parallel, &b, buf, shade, &mut d);
                    b.n = 0;
                }
            }
        }
        if b.n > 0 {
            flush(t, parallel, &b, buf, shade, &mut d);
        }
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Marks every pixel it shades: alpha 1/2 on an empty buffer.
    struct Mark;
    impl Shade for Mark {
        type Prep = ();
        fn prep(&self, _: &Lanes) {}
        fn at(&self, _: &(), _: usize) -> [f32; 4] {
            [0.0, 0.0, 0.0, 0.5]
        }
    }

    /// A silhouette as set-up leaves it, with flat planes: only coverage matters here.
    fn setup(poly: &[(i64, i64)], w: i64, h: i64) -> Option<TetSetup> {
        let lo = |v: i64| (v - SUB / 2 + SUB - 1).div_euclid(SUB);
        let hi = |v: i64| (v - SUB / 2).div_euclid(SUB);
        let xs = poly.iter().map(|p| p.0);
        let ys = poly.iter().map(|p| p.1);
        let (x0, x1) = (lo(xs.clone().min()?).max(0), hi(xs.max()?).min(w - 1));
        let (y0, y1) = (lo(ys.clone().min()?).max(0), hi(ys.max()?).min(h - 1));
        if x0 > x1 || y0 > y1 {
            return None;
        }
        let mut p = [[0i32; 2]; 4];
        for k in 0..4 {
            let q = poly[k % poly.len()];
            p[k] = [q.0 as i32, q.1 as i32];
        }
        let plane = [[0.0, 0.0, 0.0]; 3];
        Some(TetSetup {
            poly: p,
            nedges: poly.len() as u32,
            x0: x0 as i32,
            x1: x1 as i32,
            y0: y0 as i32,
            y1: y1 as i32,
            ox: 0.0,
            oy: 0.0,
            front: plane,
            back: [[0.1, 0.0, 0.0]; 3],
            w0: 1.0,
            sref: [0.0; 3],
            h: [0.0; 3],
            smin: 0.0,
            smax: 1.0,
        })
    }

    /// The per-pixel definition of coverage: every edge's exact integer test with the owner rule.
    fn inside(t: &TetSetup, x: i64, y: i64) -> bool {
        let (cx, cy) = (x * SUB + SUB / 2, y * SUB + SUB / 2);
        let e = t.edges();
        e[..t.nedges as usize]
            .iter()
            .all(|e| e.a * cx + e.b * cy + e.c + e.bias >= 0)
    }

    /// Positively oriented convex hull of up to four points (fewer corners when some are
    /// inside or collinear); `None` when it has no area.
    fn hull(p: [(i64, i64); 4]) -> Option<Vec<(i64, i64)>> {
        let cr = |o: (i64, i64), a: (i64, i64), b: (i64, i64)| {
            (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
        };
        let mut pts = p.to_vec();
        pts.sort();
        pts.dedup();
        let mut h: Vec<(i64, i64)> = Vec::new();
        for pass in 0..2 {
            let start = h.len();
            let it: Vec<_> = if pass == 0 {
                pts.clone()
            } else {
                pts.iter().rev().copied().collect()
            };
            for q in it {
                while h.len() >= start + 2 && cr(h[h.len() - 2], h[h.len() - 1], q) <= 0 {
                    h.pop();
                }
                h.push(q);
            }
            h.pop();
        }
        (h.len() >= 3).then_some(h)
    }

    #[test]
    fn drawn_pixels_are_exactly_those_the_edge_test_takes() {
        let (w, h) = (96i64, 80i64);
        let tiles = [(0, 0, 31, 31), (32, 32, 63, 63), (64, 64, 95, 79)];
        let mut seed = 0x2545f4914f6cdd1du64;
        let mut rnd = |n: i64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % n as u64) as i64
        };
        let (mut cases, mut small) = (0, 0);
        for case in 0..6000 {
            // Small tets (the mask path), ones just past its limit, and huge ones; corners on
            // pixel centres and on shared edges often, so the owner rule decides.
            let span = [6, 20, 70, 4000][case % 4] * SUB;
            let (cx, cy) = (rnd(w * SUB), rnd(h * SUB));
            let mut p = [(0i64, 0i64); 4];
            for q in &mut p {
                *q = (cx + rnd(span) - span / 2, cy + rnd(span) - span / 2);
                if rnd(3) == 0 {
                    *q = (q.0 / SUB * SUB + SUB / 2, q.1 / SUB * SUB + SUB / 2);
                }
            }
            let Some(poly) = hull(p) else { continue };
            let Some(t) = setup(&poly, w, h) else {
                continue;
            };
            cases += 1;
            for &tile in &tiles {
                let (tx0, ty0, tx1, ty1) = tile;
                let tw = (tx1 - tx0 + 1) as usize;
                let mut buf = vec![[0f32; 4]; tw * (ty1 - ty0 + 1) as usize];
                let stretch = vec![1f32; (w * h) as usize];
                if let Some((x0, x1, y0, _)) = t.clip(tile) {
                    let w = x1 - x0 + 1;
                    small += (w <= 16 && Cover::<16>::new(&t, x0, y0, w).is_some()) as usize;
                }
                let (frags, _) = raster(&t, false, tile, &mut buf, &stretch, w as usize, &Mark);
                let mut want = 0;
                for y in ty0..=ty1 {
                    for x in tx0..=tx1 {
                        let got = buf[(y - ty0) as usize * tw + (x - tx0) as usize][3];
                        let inn = inside(&t, x, y);
                        want += inn as u64;
                        assert_eq!(got == 0.5, inn, "pixel ({x}, {y}) of {poly:?}");
                    }
                }
                assert_eq!(frags, want);
            }
        }
        assert!(
            cases > 3000 && small > 1000,
            "{cases} cases, {small} on the mask path"
        );
    }

    /// Passes all bits of each fragment's (Sf, Sb, l) into the buffer (mixed, as three
    /// integers a float holds exactly; alpha 1/4), signed zeros included. NaNs count as one
    /// value: which NaN an operation gives depends on the order the compiler picks for the
    /// operands of a commutative one, and every use of a fragment treats all NaNs alike.
    struct Record;
    impl Shade for Record {
        type Prep = Lanes;
        fn prep(&self, f: &Lanes) -> Lanes {
            *f
        }
        fn at(&self, f: &Lanes, i: usize) -> [f32; 4] {
            let b = |x: f32| if x.is_nan() { f32::NAN } else { x }.to_bits();
            let m = b(f[0][i]) ^ b(f[1][i]).rotate_left(11) ^ b(f[2][i]).rotate_left(22);
            [
                (m & 0xfff) as f32,
                (m >> 12 & 0xfff) as f32,
                (m >> 24) as f32,
                0.25,
            ]
        }
    }

    /// Draws into a buffer, by the explicit-SIMD rows or not: fragments and newly opaque pixels.
    type DrawFn<'a> = dyn Fn(&mut [[f32; 4]], Path) -> (u64, usize) + 'a;

    /// The explicit-SIMD rows against the scalar ones on random tets with random planes (now
    /// and then ones that overflow to infinity or NaN), parallel and perspective, with a
    /// recording shade and with pre-integrated tables: the same bits and counts.
    #[test]
    fn simd_rows_give_the_same_bits() {
        let (w, h) = (80i64, 72i64);
        let tiles = [(0, 0, 31, 31), (32, 32, 63, 63), (64, 32, 79, 71)];
        let mut seed = 0x5851_f42d_4c95_7f2du64;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let tables = super::super::shade::tests::tables();
        let stretch: Vec<f32> = (0..w * h).map(|i| 1.0 + (i % 7) as f32 * 0.125).collect();
        let mut compared = 0;
        for case in 0..3000 {
            // Boxes up to 16 pixels wide take the AVX-512 batch of 16 (rows split across it), wider
            // ones the searched rows.
            let span = [6, 14, 20, 70, 400][case % 5] * SUB;
            let (cx, cy) = (
                (rnd() % (w * SUB) as u64) as i64,
                (rnd() % (h * SUB) as u64) as i64,
            );
            let mut p = [(0i64, 0i64); 4];
            for q in &mut p {
                *q = (
                    cx + (rnd() % span as u64) as i64 - span / 2,
                    cy + (rnd() % span as u64) as i64 - span / 2,
                );
            }
            let Some(poly) = hull(p) else { continue };
            let Some(mut t) = setup(&poly, w, h) else {
                continue;
            };
            // Now and then a value the min, max, clamps and finiteness test must agree on.
            const ODD: [f32; 6] = [0.0, -0.0, f32::INFINITY, f32::NEG_INFINITY, f32::NAN, 1e38];
            let mut val = |scale: f32| {
                let u = (rnd() >> 40) as f32 / (1u64 << 24) as f32 - 0.5;
                match rnd() % 24 {
                    0..=5 => ODD[(rnd() % 6) as usize],
                    _ => u * scale,
                }
            };
            for k in 0..3 {
                t.front[k] = [val(2.0), val(0.05), val(0.05)];
                t.back[k] = [val(2.0) + 1.0, val(0.05), val(0.05)];
            }
            t.sref = [val(2.0), val(0.1), val(0.1)];
            t.h = [val(2.0), val(0.1), val(0.1)];
            t.w0 = 2.0 + val(1.0);
            t.ox = val(40.0);
            t.oy = val(40.0);
            (t.smin, t.smax) = (-1.0 + val(1.0), 2.0 + val(1.0));
            let parallel = case % 2 == 0;
            for &tile in &tiles {
                let npix = ((tile.2 - tile.0 + 1) * (tile.3 - tile.1 + 1)) as usize;
                let run = |shade: &DrawFn| {
                    let (mut a, mut b) = (vec![[0f32; 4]; npix], vec![[0f32; 4]; npix]);
                    // Some pixels already part or fully opaque.
                    for (k, (x, y)) in a.iter_mut().zip(b.iter_mut()).enumerate() {
                        if k % 5 == 0 {
                            *x = [0.1, 0.2, 0.3, if k % 3 == 0 { 1.0 } else { 0.5 }];
                            *y = *x;
                        }
                    }
                    let ra = shade(&mut a, Path::Scalar);
                    // Bits, with every NaN as one: Rust leaves a NaN's sign and payload open
                    // (an add may take either operand's), so paths may differ only there.
                    let bits = |v: &[[f32; 4]]| {
                        v.iter()
                            .map(|p| p.map(|x| if x.is_nan() { u32::MAX } else { x.to_bits() }))
                            .collect::<Vec<_>>()
                    };
                    for path in [Path::Avx2, Path::Best] {
                        let mut c = b.clone();
                        let rc = shade(&mut c, path);
                        assert_eq!(bits(&a), bits(&c), "case {case} tile {tile:?} {path:?}");
                        assert_eq!(ra, rc, "case {case} {path:?}");
                    }
                };
                let sw = w as usize;
                run(&|buf, simd| raster_with(&t, parallel, tile, buf, &stretch, sw, &Record, simd));
                let tab = &tables[case % tables.len()];
                run(&|buf, simd| raster_with(&t, parallel, tile, buf, &stretch, sw, tab, simd));
                compared += 1;
            }
        }
        assert!(compared > 3000, "{compared}");
    }
}
