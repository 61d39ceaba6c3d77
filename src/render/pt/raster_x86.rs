//! The rasterizer's rows in explicit AVX2 (also compiled for AVX-512): each row's covered run goes into the lanes of a batch held in registers, and (Sf, Sb, l) come from the same operations as `raster::fragments`, in its order, so the bits are the same.

use std::arch::x86_64::*;

use super::raster::{CoverEdges, Draw, Rows};
use super::setup::TetSetup;
use super::shade::{Drawn, Lanes, Shade, WideLanes, LANES, WIDE_LANES};

/// A batch of up to [`LANES`] pixels in registers (the lanes past the count hold stale pixels
/// whose results are not used).
struct Batch {
    /// Pixel centre relative to vertex 0.
    dx: __m256,
    dy: __m256,
    /// World length of the view ray per unit of depth.
    st: __m256,
    /// Index of the pixel in the tile buffer.
    at: __m256i,
}

/// `max_of(a, b)` of `raster`, lane by lane: `b` where `a` is NaN or `b > a`, else `a`.
#[inline(always)]
unsafe fn max_of(a: __m256, b: __m256) -> __m256 {
    _mm256_blendv_ps(_mm256_max_ps(b, a), b, _mm256_cmp_ps::<_CMP_UNORD_Q>(a, a))
}

/// `min_of(a, b)` of `raster`, lane by lane: `b` where `a` is NaN or `b < a`, else `a`.
#[inline(always)]
unsafe fn min_of(a: __m256, b: __m256) -> __m256 {
    _mm256_blendv_ps(_mm256_min_ps(b, a), b, _mm256_cmp_ps::<_CMP_UNORD_Q>(a, a))
}

/// `clamp_to(x, lo, hi)` of `raster`, lane by lane.
#[inline(always)]
unsafe fn clamp_to(x: __m256, lo: __m256, hi: __m256) -> __m256 {
    let x = _mm256_blendv_ps(x, lo, _mm256_cmp_ps::<_CMP_LT_OQ>(x, lo));
    _mm256_blendv_ps(x, hi, _mm256_cmp_ps::<_CMP_GT_OQ>(x, hi))
}

/// Plane `p` over the lanes of `b`: `(c + ay dy) + ax dx`.
#[inline(always)]
unsafe fn ev(p: &[f32; 3], b: &Batch) -> __m256 {
    _mm256_add_ps(
        _mm256_add_ps(
            _mm256_set1_ps(p[0]),
            _mm256_mul_ps(_mm256_set1_ps(p[2]), b.dy),
        ),
        _mm256_mul_ps(_mm256_set1_ps(p[1]), b.dx),
    )
}

/// Depth offset `z - z0 = -d / (w0 (w0 + d))` of a perspective plane value `d`, the negation
/// first as the scalar `-df / (...)`.
#[inline(always)]
unsafe fn persp(d: __m256, w0: __m256) -> __m256 {
    _mm256_div_ps(
        _mm256_xor_ps(d, _mm256_set1_ps(-0.0)),
        _mm256_mul_ps(w0, _mm256_add_ps(w0, d)),
    )
}

/// (Sf, Sb, l) of a batch: `raster::fragments`, operation for operation.
#[inline(always)]
unsafe fn fragments(t: &TetSetup, parallel: bool, b: &Batch) -> [__m256; 3] {
    let (zf, zb);
    if parallel {
        zf = max_of(
            max_of(ev(&t.front[0], b), ev(&t.front[1], b)),
            ev(&t.front[2], b),
        );
        zb = min_of(
            min_of(ev(&t.back[0], b), ev(&t.back[1], b)),
            ev(&t.back[2], b),
        );
    } else {
        let df = min_of(
            min_of(ev(&t.front[0], b), ev(&t.front[1], b)),
            ev(&t.front[2], b),
        );
        let db = max_of(
            max_of(ev(&t.back[0], b), ev(&t.back[1], b)),
            ev(&t.back[2], b),
        );
        let w0 = _mm256_set1_ps(t.w0);
        zf = persp(df, w0);
        zb = persp(db, w0);
    }
    let sref = ev(&t.sref, b);
    let h = ev(&t.h, b);
    let (lo, hi) = (_mm256_set1_ps(t.smin), _mm256_set1_ps(t.smax));
    let sf = clamp_to(_mm256_add_ps(sref, _mm256_mul_ps(zf, h)), lo, hi);
    let sb = clamp_to(_mm256_add_ps(sref, _mm256_mul_ps(zb, h)), lo, hi);
    let li = max_of(
        _mm256_mul_ps(_mm256_sub_ps(zb, zf), b.st),
        _mm256_setzero_ps(),
    );
    // `is_finite`: |li| below infinity (false for NaN), else 0.
    let abs = _mm256_andnot_ps(_mm256_set1_ps(-0.0), li);
    let finite = _mm256_cmp_ps::<_CMP_LT_OQ>(abs, _mm256_set1_ps(f32::INFINITY));
    [sf, sb, _mm256_and_ps(li, finite)]
}

/// Shades the first `n` lanes of `b` and composites them behind what `buf` holds, with the
/// shade's AVX-512 path when `WIDE`.
#[inline(always)]
unsafe fn flush<S: Shade, const WIDE: bool>(
    t: &TetSetup,
    parallel: bool,
    b: &Batch,
    n: usize,
    buf: &mut [[f32; 4]],
    shade: &S,
    d: &mut Drawn,
) {
    let v = fragments(t, parallel, b);
    let mut f: Lanes = [[0.0; LANES]; 3];
    let mut at = [0usize; LANES];
    // SAFETY: each store writes 32 bytes into an array of that size (`f[k]`: 8 floats; `at`:
    // 8 `usize` of 8 bytes, two stores of four).
    unsafe {
        for (k, lane) in f.iter_mut().enumerate() {
            _mm256_storeu_ps(lane.as_mut_ptr(), v[k]);
        }
        // Tile indices are never negative: widening as unsigned is `as usize`.
        let p = at.as_mut_ptr().cast::<__m256i>();
        _mm256_storeu_si256(p, _mm256_cvtepu32_epi64(_mm256_castsi256_si128(b.at)));
        _mm256_storeu_si256(
            p.add(1),
            _mm256_cvtepu32_epi64(_mm256_extracti128_si256::<1>(b.at)),
        );
    }
    if WIDE {
        // SAFETY: the CPU has AVX-512F and VL when `WIDE` (the caller's promise).
        unsafe { shade.composite_avx512(&f, &at, n, buf, d) };
    } else {
        // SAFETY: the CPU has AVX2 (the caller's promise).
        unsafe { shade.composite_avx2(&f, &at, n, buf, d) };
    }
}

/// `Draw::rows` in explicit AVX2.
///
/// # Safety
/// The CPU has AVX2.
#[target_feature(enable = "avx2")]
pub(super) unsafe fn rows<S: Shade, R: Rows>(
    draw: &Draw<S>,
    rows: R,
    y0: i64,
    y1: i64,
    buf: &mut [[f32; 4]],
) -> Drawn {
    // SAFETY: the caller's promise.
    unsafe { rows_body::<S, R, false>(draw, rows, y0, y1, buf) }
}

/// [`rows`] compiled for AVX-512 (F and VL) too: the same operations, but with 32 vector
/// registers the plane coefficients stay in registers. No fused multiply-add: the same bits.
///
/// # Safety
/// The CPU has AVX2, AVX-512F and AVX-512VL.
#[target_feature(enable = "avx2,avx512f,avx512vl")]
pub(super) unsafe fn rows512<S: Shade, R: Rows>(
    draw: &Draw<S>,
    rows: R,
    y0: i64,
    y1: i64,
    buf: &mut [[f32; 4]],
) -> Drawn {
    // SAFETY: the caller's promise.
    unsafe { rows_body::<S, R, true>(draw, rows, y0, y1, buf) }
}

/// `Draw::rows` with the batch in registers: each row's run fills lanes `n ..` at once (a
/// lane's pixel is `x - n + lane`), with no per-pixel loop or scalar stores. Inlined into the
/// functions above, which give the instruction set; this and the helpers above have none of
/// their own, so they compile once per set.
///
/// # Safety
/// The CPU has AVX2, and AVX-512F and VL when `WIDE`.
#[inline(always)]
unsafe fn rows_body<S: Shade, R: Rows, const WIDE: bool>(
    draw: &Draw<S>,
    mut rows: R,
    y0: i64,
    y1: i64,
    buf: &mut [[f32; 4]],
) -> Drawn {
    let (t, parallel, shade) = (draw.t, draw.parallel, draw.shade);
    let (tx0, ty0, tx1, _) = draw.tile;
    let tw = tx1 - tx0 + 1;
    let mut d = Drawn::default();
    let zero = _mm256_setzero_ps();
    let mut b = Batch {
        dx: zero,
        dy: zero,
        st: zero,
        at: _mm256_setzero_si256(),
    };
    let mut n = 0i64;
    let lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    let (half, ox) = (_mm256_set1_ps(0.5), _mm256_set1_ps(t.ox));
    for y in y0..=y1 {
        let Some((xa, xb)) = rows.next_row() else {
            continue;
        };
        let dy = _mm256_set1_ps(y as f32 + 0.5 - t.oy);
        let row = (y - ty0) * tw;
        let s0 = y as usize * draw.width;
        // The run's stretch values, bounds checked once as `Draw::rows` does.
        let run = &draw.stretch[s0 + xa as usize..=s0 + xb as usize];
        let mut x = xa;
        loop {
            let take = (xb - x + 1).min(LANES as i64 - n);
            // Lanes `n .. n + take` take pixels `x ..`: lane `i` has pixel `x - n + i`.
            let first = x - n;
            let px = _mm256_add_epi32(_mm256_set1_epi32(first as i32), lane);
            let m = _mm256_andnot_si256(
                _mm256_cmpgt_epi32(_mm256_set1_epi32(n as i32), lane),
                _mm256_cmpgt_epi32(_mm256_set1_epi32((n + take) as i32), lane),
            );
            let mf = _mm256_castsi256_ps(m);
            let dx = _mm256_sub_ps(_mm256_add_ps(_mm256_cvtepi32_ps(px), half), ox);
            b.dx = _mm256_blendv_ps(b.dx, dx, mf);
            b.dy = _mm256_blendv_ps(b.dy, dy, mf);
            // Lane `i` wants `stretch[s0 + x - n + i]`; the lanes in `m` are
            // `run[x - xa ..= x - xa + take - 1]`, inside the run (`x + take - 1 <= xb`).
            let start = s0 as i64 + first;
            let st = if start >= 0 && start as usize + LANES <= draw.stretch.len() {
                // SAFETY: the 8 floats from `start` lie inside `stretch`, checked just above
                // (the lanes outside `m` read other pixels, which the blend drops).
                unsafe { _mm256_loadu_ps(draw.stretch.as_ptr().add(start as usize)) }
            } else {
                let from = run.as_ptr().wrapping_offset((x - xa - n) as isize);
                // SAFETY: a masked load touches only the lanes in its mask, all inside `run`
                // (see above); the CPU has AVX2 (the caller's promise).
                unsafe { _mm256_maskload_ps(from, m) }
            };
            b.st = _mm256_blendv_ps(b.st, st, mf);
            let at = _mm256_add_epi32(_mm256_set1_epi32((row - tx0) as i32), px);
            b.at = _mm256_blendv_epi8(b.at, at, m);
            n += take;
            x += take;
            if n == LANES as i64 {
                flush::<S, WIDE>(t, parallel, &b, LANES, buf, shade, &mut d);
                n = 0;
            }
            if x > xb {
                break;
            }
        }
    }
    if n > 0 {
        flush::<S, WIDE>(t, parallel, &b, n as usize, buf, shade, &mut d);
    }
    d
}

/// Whether [`wide_rows`] can draw rows up to `y1`, pixels up to `x1`, of `draw`: the CPU has
/// AVX2, AVX-512F, AVX-512VL, POPCNT and BMI1 (every AVX-512 CPU has the last two; without
/// them each count of lanes was a dozen instructions), and the stretch map holds those pixels.
#[inline(always)]
pub(super) fn wide_rows_fit<S>(draw: &Draw<S>, x1: i64, y1: i64) -> bool {
    use std::arch::is_x86_feature_detected as has;
    x1 >= 0
        && y1 >= 0
        && (x1 as usize) < draw.width
        && (y1 as usize + 1)
            .checked_mul(draw.width)
            .is_some_and(|n| n <= draw.stretch.len())
        && has!("avx2")
        && has!("avx512f")
        && has!("avx512vl")
        && has!("popcnt")
        && has!("bmi1")
}

/// A batch of up to [`WIDE_LANES`] pixels in 512-bit registers, as [`Batch`].
struct WideBatch {
    dx: __m512,
    dy: __m512,
    st: __m512,
    at: __m512i,
}

/// `max_of`, `min_of` and `clamp_to` of `raster` in 512 bits (mask blends pick `b` where set).
#[inline(always)]
unsafe fn max_of16(a: __m512, b: __m512) -> __m512 {
    let nan = _mm512_cmp_ps_mask::<_CMP_UNORD_Q>(a, a);
    _mm512_mask_blend_ps(nan, _mm512_max_ps(b, a), b)
}

#[inline(always)]
unsafe fn min_of16(a: __m512, b: __m512) -> __m512 {
    let nan = _mm512_cmp_ps_mask::<_CMP_UNORD_Q>(a, a);
    _mm512_mask_blend_ps(nan, _mm512_min_ps(b, a), b)
}

#[inline(always)]
unsafe fn clamp_to16(x: __m512, lo: __m512, hi: __m512) -> __m512 {
    let x = _mm512_mask_blend_ps(_mm512_cmp_ps_mask::<_CMP_LT_OQ>(x, lo), x, lo);
    _mm512_mask_blend_ps(_mm512_cmp_ps_mask::<_CMP_GT_OQ>(x, hi), x, hi)
}

/// Plane `p` over the lanes of `b`: `(c + ay dy) + ax dx`.
#[inline(always)]
unsafe fn ev16(p: &[f32; 3], b: &WideBatch) -> __m512 {
    _mm512_add_ps(
        _mm512_add_ps(
            _mm512_set1_ps(p[0]),
            _mm512_mul_ps(_mm512_set1_ps(p[2]), b.dy),
        ),
        _mm512_mul_ps(_mm512_set1_ps(p[1]), b.dx),
    )
}

/// `persp` in 512 bits; the sign flip as an integer XOR (AVX-512F has no float XOR).
#[inline(always)]
unsafe fn persp16(d: __m512, w0: __m512) -> __m512 {
    let neg = _mm512_castsi512_ps(_mm512_xor_si512(
        _mm512_castps_si512(d),
        _mm512_set1_epi32(i32::MIN),
    ));
    _mm512_div_ps(neg, _mm512_mul_ps(w0, _mm512_add_ps(w0, d)))
}

/// (Sf, Sb, l) of a wide batch: [`fragments`] on sixteen lanes, operation for operation.
#[inline(always)]
unsafe fn fragments16(t: &TetSetup, parallel: bool, b: &WideBatch) -> [__m512; 3] {
    let (zf, zb);
    if parallel {
        zf = max_of16(
            max_of16(ev16(&t.front[0], b), ev16(&t.front[1], b)),
            ev16(&t.front[2], b),
        );
        zb = min_of16(
            min_of16(ev16(&t.back[0], b), ev16(&t.back[1], b)),
            ev16(&t.back[2], b),
        );
    } else {
        let df = min_of16(
            min_of16(ev16(&t.front[0], b), ev16(&t.front[1], b)),
            ev16(&t.front[2], b),
        );
        let db = max_of16(
            max_of16(ev16(&t.back[0], b), ev16(&t.back[1], b)),
            ev16(&t.back[2], b),
        );
        let w0 = _mm512_set1_ps(t.w0);
        zf = persp16(df, w0);
        zb = persp16(db, w0);
    }
    let sref = ev16(&t.sref, b);
    let h = ev16(&t.h, b);
    let (lo, hi) = (_mm512_set1_ps(t.smin), _mm512_set1_ps(t.smax));
    let sf = clamp_to16(_mm512_add_ps(sref, _mm512_mul_ps(zf, h)), lo, hi);
    let sb = clamp_to16(_mm512_add_ps(sref, _mm512_mul_ps(zb, h)), lo, hi);
    let li = max_of16(
        _mm512_mul_ps(_mm512_sub_ps(zb, zf), b.st),
        _mm512_setzero_ps(),
    );
    // `is_finite`: |li| below infinity (false for NaN), else +0 as the AND of the 256-bit path.
    let finite = _mm512_cmp_ps_mask::<_CMP_LT_OQ>(_mm512_abs_ps(li), _mm512_set1_ps(f32::INFINITY));
    [sf, sb, _mm512_maskz_mov_ps(finite, li)]
}

/// Shades the first `n` lanes of a wide batch and composites them behind what `buf` holds.
#[inline(always)]
unsafe fn flush16<S: Shade>(
    t: &TetSetup,
    parallel: bool,
    b: &WideBatch,
    n: usize,
    buf: &mut [[f32; 4]],
    shade: &S,
    d: &mut Drawn,
) {
    let v = fragments16(t, parallel, b);
    let mut f: WideLanes = [[0.0; WIDE_LANES]; 3];
    let mut at = [0usize; WIDE_LANES];
    // SAFETY: each store writes 64 bytes into an array of that size (`f[k]`: 16 floats; `at`:
    // 16 `usize` of 8 bytes, two stores of eight).
    unsafe {
        for (k, lane) in f.iter_mut().enumerate() {
            _mm512_storeu_ps(lane.as_mut_ptr(), v[k]);
        }
        // Tile indices are never negative: widening as unsigned is `as usize`.
        let p = at.as_mut_ptr().cast::<__m512i>();
        _mm512_storeu_si512(
            p.cast(),
            _mm512_cvtepu32_epi64(_mm512_castsi512_si256(b.at)),
        );
        _mm512_storeu_si512(
            p.add(1).cast(),
            _mm512_cvtepu32_epi64(_mm512_extracti64x4_epi64::<1>(b.at)),
        );
        shade.composite_wide(&f, &at, n, buf, d);
    }
}

/// The rows of a tet whose clipped box is at most [`WIDE_LANES`] pixels wide, in AVX-512: each
/// row's cover is one 16-lane sign test, its covered pixels are packed (`vcompress`) and
/// appended to the batch (`vexpand`), so no per-row search or per-pixel loop is left. The
/// pixels and their values are those of [`rows_body`], so the bits are the same.
///
/// # Safety
/// The CPU has AVX2, AVX-512F, AVX-512VL, POPCNT and BMI1; `draw.stretch` holds every pixel of rows
/// `y0 ..= y1` in the box of `c` ([`wide_rows_fit`]).
#[target_feature(enable = "avx2,avx512f,avx512vl,popcnt,bmi1")]
pub(super) unsafe fn wide_rows<S: Shade>(
    draw: &Draw<S>,
    c: &CoverEdges,
    y0: i64,
    y1: i64,
    buf: &mut [[f32; 4]],
) -> Drawn {
    let (t, parallel, shade) = (draw.t, draw.parallel, draw.shade);
    let (tx0, ty0, tx1, _) = draw.tile;
    let tw = tx1 - tx0 + 1;
    let mut d = Drawn::default();
    let lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    let zero = _mm512_setzero_si512();
    // Edge `k` at lane `i` of the first row: `e0 + ea i`, the integers `Cover` holds.
    let first = |k: usize| {
        _mm512_add_epi32(
            _mm512_set1_epi32(c.e0[k]),
            _mm512_mullo_epi32(_mm512_set1_epi32(c.ea[k]), lane),
        )
    };
    let mut row = [first(0), first(1), first(2), first(3)];
    let step = [
        _mm512_set1_epi32(c.step[0]),
        _mm512_set1_epi32(c.step[1]),
        _mm512_set1_epi32(c.step[2]),
        _mm512_set1_epi32(c.step[3]),
    ];
    let lanes = c.lanes as u16;
    let x0 = c.x0;
    // Lane `i`'s pixel is `x0 + i` in every row: its offset from vertex 0 as `rows_body` has it.
    let px = _mm512_add_epi32(_mm512_set1_epi32(x0 as i32), lane);
    let dx_row = _mm512_sub_ps(
        _mm512_add_ps(_mm512_cvtepi32_ps(px), _mm512_set1_ps(0.5)),
        _mm512_set1_ps(t.ox),
    );
    let fz = _mm512_setzero_ps();
    let mut b = WideBatch {
        dx: fz,
        dy: fz,
        st: fz,
        at: zero,
    };
    let mut n = 0u32;
    for y in y0..=y1 {
        let m = _mm512_min_epi32(
            _mm512_min_epi32(row[0], row[1]),
            _mm512_min_epi32(row[2], row[3]),
        );
        for k in 0..4 {
            // Past the last row the values are not used, so wrapping is harmless.
            row[k] = _mm512_add_epi32(row[k], step[k]);
        }
        let m = !_mm512_cmplt_epi32_mask(m, zero) & lanes;
        if m == 0 {
            continue;
        }
        let dy = _mm512_set1_ps(y as f32 + 0.5 - t.oy);
        // SAFETY: the row's covered pixels lie in `[x0, x1]` of row `y`, all in the stretch
        // map (the caller's promise); the masked load touches only those lanes.
        let st = unsafe {
            _mm512_maskz_loadu_ps(
                m,
                draw.stretch
                    .as_ptr()
                    .wrapping_add(y as usize * draw.width + x0 as usize),
            )
        };
        let at = _mm512_add_epi32(_mm512_set1_epi32(((y - ty0) * tw - tx0) as i32), px);
        // The row's covered pixels packed into lanes `0 .. c`, then appended at lane `n`.
        let (pdx, pst, pat) = (
            _mm512_maskz_compress_ps(m, dx_row),
            _mm512_maskz_compress_ps(m, st),
            _mm512_maskz_compress_epi32(m, at),
        );
        let count = m.count_ones();
        let take = count.min(WIDE_LANES as u32 - n);
        let dest = (((1u32 << take) - 1) << n) as u16;
        b.dx = _mm512_mask_expand_ps(b.dx, dest, pdx);
        b.dy = _mm512_mask_mov_ps(b.dy, dest, dy);
        b.st = _mm512_mask_expand_ps(b.st, dest, pst);
        b.at = _mm512_mask_expand_epi32(b.at, dest, pat);
        n += take;
        if n == WIDE_LANES as u32 {
            flush16(t, parallel, &b, WIDE_LANES, buf, shade, &mut d);
            // The rest of the row moves down to lane 0.
            let rest = _mm512_add_epi32(lane, _mm512_set1_epi32(take as i32));
            b.dx = _mm512_permutexvar_ps(rest, pdx);
            b.dy = dy;
            b.st = _mm512_permutexvar_ps(rest, pst);
            b.at = _mm512_permutexvar_epi32(rest, pat);
            n = count - take;
        }
    }
    if n > 0 {
        flush16(t, parallel, &b, n as usize, buf, shade, &mut d);
    }
    d
}
