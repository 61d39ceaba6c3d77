//! Fragment shading: the three integration modes behind one [`Shader`], and the lane-wise [`Shade`] the rasterizer calls.

use super::raster::raster;
use super::setup::TetSetup;
use super::tiles::Tile;
use super::OPAQUE;
use crate::render::integrate::{FastTf, Integration, PreintTable};

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

    /// Whether every fragment of a tet whose vertex scalars span `[lo, hi]` is exactly zero,
    /// so the tet can be left out without changing any pixel's bits: where the transfer
    /// function draws nothing over the whole range, as the pre-integrated table or the
    /// per-fragment modes' node arrays find it.
    #[inline(always)]
    pub fn draws_nothing(&self, lo: f32, hi: f32) -> bool {
        match self {
            Shader::Pre(tab) => tab.draws_nothing(lo, hi),
            Shader::Average(tf) | Shader::Linear(tf) => tf.draws_nothing(lo, hi),
        }
    }

    /// Colour and opacity of one fragment.
    #[inline(always)]
    pub fn shade(&self, sf: f32, sb: f32, l: f32) -> [f32; 4] {
        match self {
            Shader::Pre(tab) => tab.segment(sf, sb, l),
            Shader::Average(tf) => tf.average(sf, sb, l),
            Shader::Linear(tf) => tf.linear(sf, sb, l),
        }
    }

    /// Rasterizes one set-up tet into `buf` covering `tile` (front to back) with this
    /// integration: fragments and newly opaque pixels.
    #[inline(always)]
    pub(crate) fn draw(
        &self,
        setup: &TetSetup,
        parallel: bool,
        tile: Tile,
        buf: &mut [[f32; 4]],
        stretch: &[f32],
        w: usize,
    ) -> (u64, usize) {
        match self {
            Shader::Pre(tab) => raster(setup, parallel, tile, buf, stretch, w, tab),
            Shader::Average(tf) => raster(
                setup,
                parallel,
                tile,
                buf,
                stretch,
                w,
                &TfShade::<false>(tf),
            ),
            Shader::Linear(tf) => {
                raster(setup, parallel, tile, buf, stretch, w, &TfShade::<true>(tf))
            }
        }
    }
}

/// Pixels of the batched fragment math: fixed-size loops over them vectorize (one AVX2
/// register; the rasterizer fills the lanes from several rows of a tet, so few stay idle).
pub(crate) const LANES: usize = 8;

/// (Sf, Sb, l) of [`LANES`] fragments.
pub(crate) type Lanes = [[f32; LANES]; 3];

/// Pixels of the AVX-512 rasterizer's batch: one 512-bit register of `f32`.
pub(crate) const WIDE_LANES: usize = 16;

/// (Sf, Sb, l) of [`WIDE_LANES`] fragments.
pub(crate) type WideLanes = [[f32; WIDE_LANES]; 3];

/// What a tet's drawing counts: fragments drawn and pixels that became opaque.
#[derive(Default)]
pub(crate) struct Drawn {
    pub(crate) frags: u64,
    pub(crate) opaque: usize,
}

/// Colour and opacity of fragments for the rasterizer: per-lane arithmetic for [`LANES`]
/// fragments at once (it vectorizes), then per-pixel reads for the lanes that are drawn.
pub(crate) trait Shade {
    type Prep;
    fn prep(&self, f: &Lanes) -> Self::Prep;
    fn at(&self, p: &Self::Prep, i: usize) -> [f32; 4];

    /// Shades lanes `0..n` of `f` and composites each behind what `buf[at[i]]` holds (a pixel
    /// past [`OPAQUE`] takes nothing). Lanes `0..n` are distinct pixels.
    #[inline(always)]
    fn composite(
        &self,
        f: &Lanes,
        at: &[usize; LANES],
        n: usize,
        buf: &mut [[f32; 4]],
        d: &mut Drawn,
    ) {
        composite_lanes(self, f, at, n, buf, d)
    }

    /// [`Shade::composite`] as the explicit-SIMD rows call it: inlined there, so a shade with
    /// an AVX2 path of its own runs it without a call or a feature check.
    ///
    /// # Safety
    /// The CPU has AVX2.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn composite_avx2(
        &self,
        f: &Lanes,
        at: &[usize; LANES],
        n: usize,
        buf: &mut [[f32; 4]],
        d: &mut Drawn,
    ) {
        self.composite(f, at, n, buf, d)
    }

    /// [`Shade::composite_avx2`] as the AVX-512 rows call it.
    ///
    /// # Safety
    /// The CPU has AVX2, AVX-512F and AVX-512VL.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn composite_avx512(
        &self,
        f: &Lanes,
        at: &[usize; LANES],
        n: usize,
        buf: &mut [[f32; 4]],
        d: &mut Drawn,
    ) {
        // SAFETY: the caller's promise includes AVX2.
        unsafe { self.composite_avx2(f, at, n, buf, d) }
    }

    /// [`Shade::composite_avx512`] for the [`WIDE_LANES`] lanes of the AVX-512 rasterizer's
    /// batch: by default its two halves in turn (lanes are distinct pixels, so the order does
    /// not change a bit).
    ///
    /// # Safety
    /// The CPU has AVX2, AVX-512F and AVX-512VL.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn composite_wide(
        &self,
        f: &WideLanes,
        at: &[usize; WIDE_LANES],
        n: usize,
        buf: &mut [[f32; 4]],
        d: &mut Drawn,
    ) {
        for_halves(f, at, n, |half, at, m| {
            // SAFETY: the caller's promise.
            unsafe { self.composite_avx512(half, at, m, buf, d) }
        });
    }
}

/// Calls `each` with the lanes `0..8` and then `8..16` of a wide batch whose first `n` lanes
/// are used (and with how many of each half are), skipping a half with none.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn for_halves(
    f: &WideLanes,
    at: &[usize; WIDE_LANES],
    n: usize,
    mut each: impl FnMut(&Lanes, &[usize; LANES], usize),
) {
    for lo in [0, LANES] {
        if n <= lo {
            break;
        }
        let half: Lanes = std::array::from_fn(|k| std::array::from_fn(|i| f[k][lo + i]));
        let at: [usize; LANES] = std::array::from_fn(|i| at[lo + i]);
        each(&half, &at, (n - lo).min(LANES));
    }
}

/// [`Shade::composite`] one lane at a time: the definition every faster path matches bit for bit.
#[inline(always)]
pub(crate) fn composite_lanes<S: Shade + ?Sized>(
    shade: &S,
    f: &Lanes,
    at: &[usize; LANES],
    n: usize,
    buf: &mut [[f32; 4]],
    d: &mut Drawn,
) {
    let prep = shade.prep(f);
    for i in 0..n.min(LANES) {
        let slot = &mut buf[at[i]];
        if slot[3] >= OPAQUE {
            continue;
        }
        let c = shade.at(&prep, i);
        let k = 1.0 - slot[3];
        slot[0] += k * c[0];
        slot[1] += k * c[1];
        slot[2] += k * c[2];
        slot[3] += k * c[3];
        d.frags += 1;
        if slot[3] >= OPAQUE {
            d.opaque += 1;
        }
    }
}

/// Table corners and weights of [`LANES`] lookups; lanes longer than the table's length axis
/// (bit `i` of `long`) take [`PreintTable::segment`] of their fragment instead.
pub(crate) struct TableLanes {
    base: [usize; LANES],
    w: [[f32; LANES]; 3],
    long: u32,
    f: Lanes,
}

impl Shade for PreintTable {
    type Prep = TableLanes;
    #[inline(always)]
    fn prep(&self, f: &Lanes) -> TableLanes {
        let top = (self.ns - 1) as f32;
        let ltop = (self.nl - 1) as f32;
        let (mut base, mut w) = ([0usize; LANES], [[0f32; LANES]; 3]);
        let (ns, nl) = (self.ns as i32, self.nl as i32);
        let mut long = 0u32;
        for i in 0..LANES {
            // max then min (not clamp): NaN becomes 0, so every value is in [0, top].
            let xf = ((f[0][i] - self.s0) * self.inv_ds).max(0.0).min(top);
            let xb = ((f[1][i] - self.s0) * self.inv_ds).max(0.0).min(top);
            let ql = f[2][i] * self.inv_dl;
            long |= ((ql > ltop) as u32) << i;
            let xl = ql.max(0.0).min(ltop);
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
        TableLanes {
            base,
            w,
            long,
            f: *f,
        }
    }
    #[inline(always)]
    fn at(&self, p: &TableLanes, i: usize) -> [f32; 4] {
        if p.long >> i & 1 != 0 {
            return self.segment(p.f[0][i], p.f[1][i], p.f[2][i]);
        }
        self.corners(p.base[i], p.w[0][i], p.w[1][i], p.w[2][i])
    }
    #[inline(always)]
    fn composite(
        &self,
        f: &Lanes,
        at: &[usize; LANES],
        n: usize,
        buf: &mut [[f32; 4]],
        d: &mut Drawn,
    ) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") && x86::fits(self) {
            // SAFETY: the CPU has AVX2 and the table is one `x86::composite_pre` takes, both
            // checked just above.
            unsafe { x86::composite_pre(self, f, at, n, buf, d) };
            return;
        }
        composite_lanes(self, f, at, n, buf, d)
    }
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn composite_avx2(
        &self,
        f: &Lanes,
        at: &[usize; LANES],
        n: usize,
        buf: &mut [[f32; 4]],
        d: &mut Drawn,
    ) {
        if x86::fits(self) {
            // SAFETY: the CPU has AVX2 (the caller's promise) and the table fits.
            unsafe { x86::composite_pre_body(self, f, at, n, buf, d) };
            return;
        }
        composite_lanes(self, f, at, n, buf, d)
    }
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn composite_avx512(
        &self,
        f: &Lanes,
        at: &[usize; LANES],
        n: usize,
        buf: &mut [[f32; 4]],
        d: &mut Drawn,
    ) {
        if x86::fits(self) {
            // SAFETY: the CPU has AVX-512F and VL (the caller's promise) and the table fits.
            unsafe { x86::composite_pre_pairs(self, f, at, n, buf, d) };
            return;
        }
        composite_lanes(self, f, at, n, buf, d)
    }
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn composite_wide(
        &self,
        f: &WideLanes,
        at: &[usize; WIDE_LANES],
        n: usize,
        buf: &mut [[f32; 4]],
        d: &mut Drawn,
    ) {
        if x86::fits(self) {
            // SAFETY: the CPU has AVX-512F and VL (the caller's promise) and the table fits.
            unsafe { x86::composite_pre_wide(self, f, at, n, buf, d) };
            return;
        }
        for_halves(f, at, n, |half, at, m| {
            composite_lanes(self, half, at, m, buf, d)
        });
    }
}

/// The pre-integrated lookup and composite in explicit AVX2: a fragment's entries `if_` and
/// `if_ + 1` (adjacent in the table) are one 32-byte load, RGBA in each half, so its four such
/// pairs blend along Sb and l in three steps for both and the halves blend along Sf last. Every
/// operation is the scalar path's, in its order, on the same operands: the same bits.
#[cfg(target_arch = "x86_64")]
mod x86 {
    use super::{Drawn, Lanes, WideLanes, LANES, OPAQUE, WIDE_LANES};
    use crate::render::integrate::PreintTable;
    use std::arch::x86_64::*;

    /// Whether `t` is a table [`composite_pre`] can take: well formed (at least two entries
    /// on each axis, `data` exactly `ns * ns * nl` long) and indexable in `i32`.
    #[inline(always)]
    pub(super) fn fits(t: &PreintTable) -> bool {
        t.ns >= 2
            && t.nl >= 2
            && t.ns.checked_mul(t.ns).and_then(|a| a.checked_mul(t.nl)) == Some(t.data.len())
            && t.data.len() <= i32::MAX as usize
    }

    /// `a + t (b - a)`, each lane as [`PreintTable::corners`] computes it.
    #[inline(always)]
    unsafe fn lerp(a: __m256, b: __m256, t: __m256) -> __m256 {
        _mm256_add_ps(a, _mm256_mul_ps(t, _mm256_sub_ps(b, a)))
    }

    /// `x.max(0.0).min(hi)` as the scalar path computes it (NaN becomes 0, -0 stays -0).
    #[inline(always)]
    unsafe fn clamp0(x: __m256, hi: __m256) -> __m256 {
        let m = _mm256_and_ps(
            _mm256_max_ps(_mm256_setzero_ps(), x),
            _mm256_cmp_ps::<_CMP_ORD_Q>(x, x),
        );
        _mm256_min_ps(hi, m)
    }

    /// [`super::composite_lanes`] for a [`PreintTable`].
    ///
    /// # Safety
    /// The CPU has AVX2, and [`fits`] holds for `t`.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn composite_pre(
        t: &PreintTable,
        f: &Lanes,
        at: &[usize; LANES],
        n: usize,
        buf: &mut [[f32; 4]],
        d: &mut Drawn,
    ) {
        // SAFETY: the caller's promise.
        unsafe { composite_pre_body(t, f, at, n, buf, d) }
    }

    /// [`composite_pre`] with no instruction set of its own: inlined into a caller that has
    /// AVX2 (the explicit-SIMD rows), the fragments go from the rows' registers to the lookup
    /// without a call.
    ///
    /// # Safety
    /// As [`composite_pre`].
    #[inline(always)]
    pub(super) unsafe fn composite_pre_body(
        t: &PreintTable,
        f: &Lanes,
        at: &[usize; LANES],
        n: usize,
        buf: &mut [[f32; 4]],
        d: &mut Drawn,
    ) {
        // SAFETY: the caller's promise (AVX2).
        let w = unsafe { weights(t, f) };
        let out = buf.as_mut_ptr();
        // Drawn and newly opaque lanes as two counters of one word, kept scalar.
        let mut counts = 0u64;
        // An index loop: `at.iter().enumerate().take(n)` kept more counters in the loop (AVX2
        // rows 10 % slower).
        #[allow(clippy::needless_range_loop)]
        for i in 0..n.min(LANES) {
            let a = at[i];
            if a >= buf.len() {
                // Never: the rasterizer only hands pixels of the tile.
                continue;
            }
            // SAFETY: `a` is inside `buf`, checked just above.
            let p = unsafe { out.add(a) };
            // SAFETY: `p` points into `buf`.
            let s = unsafe { *p };
            // `!(alpha >= OPAQUE)`: NaN takes fragments too, as the scalar path.
            if s[3] >= OPAQUE {
                continue;
            }
            // SAFETY: the caller's promises; `p` points into `buf` and holds `s`.
            counts += unsafe { over(p, s, entry(t, &w, f, i)) };
        }
        d.frags += counts & 0xffff_ffff;
        d.opaque += (counts >> 32) as usize;
    }

    /// [`composite_pre`] in AVX-512, for CPUs that have it.
    ///
    /// # Safety
    /// The CPU has AVX2, AVX-512F and AVX-512VL, and [`fits`] holds for `t`.
    #[cfg(test)]
    #[target_feature(enable = "avx2,avx512f,avx512vl")]
    pub(super) unsafe fn composite_pre512(
        t: &PreintTable,
        f: &Lanes,
        at: &[usize; LANES],
        n: usize,
        buf: &mut [[f32; 4]],
        d: &mut Drawn,
    ) {
        // SAFETY: the caller's promise.
        unsafe { composite_pre_pairs(t, f, at, n, buf, d) }
    }

    /// [`composite_pre_body`] two fragments at a time where the CPU has AVX-512: a pair's
    /// eight entries (four adjacent pairs each) are blended along Sb and l in one 512-bit
    /// register, along Sf and over the two pixels in one 256-bit one. Lanes are distinct pixels,
    /// so the order they are taken in does not matter; every value is computed by the same
    /// operations on the same operands as one at a time, so the bits are the same.
    ///
    /// # Safety
    /// The CPU has AVX2, AVX-512F and AVX-512VL, and [`fits`] holds for `t`.
    #[inline(always)]
    pub(super) unsafe fn composite_pre_pairs(
        t: &PreintTable,
        f: &Lanes,
        at: &[usize; LANES],
        n: usize,
        buf: &mut [[f32; 4]],
        d: &mut Drawn,
    ) {
        // SAFETY: the caller's promise (AVX2).
        let w = unsafe { weights(t, f) };
        // SAFETY: the caller's promises; `w` is `weights` of `f`.
        unsafe { pairs(t, &w, f, at, n, buf, d) }
    }

    /// [`composite_pre_pairs`] for the [`WIDE_LANES`] lanes of the AVX-512 rasterizer's batch:
    /// the weights of all sixteen from one 512-bit register each.
    ///
    /// # Safety
    /// The CPU has AVX2, AVX-512F and AVX-512VL, and [`fits`] holds for `t`.
    #[inline(always)]
    pub(super) unsafe fn composite_pre_wide(
        t: &PreintTable,
        f: &WideLanes,
        at: &[usize; WIDE_LANES],
        n: usize,
        buf: &mut [[f32; 4]],
        d: &mut Drawn,
    ) {
        // SAFETY: the caller's promise (AVX-512F).
        let w = unsafe { weights_wide(t, f) };
        // SAFETY: the caller's promises; `w` is `weights_wide` of `f`.
        unsafe { pairs(t, &w, f, at, n, buf, d) }
    }

    /// The pixel loop of [`composite_pre_pairs`] over `L` lanes (8 or 16) with weights `w`
    /// of `f`.
    ///
    /// # Safety
    /// As [`composite_pre_pairs`]; `w` holds the weights of `f`.
    #[inline(always)]
    unsafe fn pairs<const L: usize>(
        t: &PreintTable,
        w: &Weights<L>,
        f: &[[f32; L]; 3],
        at: &[usize; L],
        n: usize,
        buf: &mut [[f32; 4]],
        d: &mut Drawn,
    ) {
        // The lanes that take a fragment: in the tile (always) and not yet opaque.
        let mut todo = 0u32;
        for (i, &a) in at.iter().enumerate().take(n.min(L)) {
            // `!(alpha >= OPAQUE)`: NaN takes fragments too, as the scalar path.
            if buf.get(a).is_some_and(|s| !(s[3] >= OPAQUE)) {
                todo |= 1 << i;
            }
        }
        let out = buf.as_mut_ptr();
        // The pairs' alpha comparisons, or-ed: a pixel that turned opaque sets bit 3 or 7.
        let mut reached = 0u8;
        let mut counts = 0u64;
        let mut twos = todo & !(w.long as u32);
        let (data, o1, o2) = (w.data, w.o1, w.o2);
        // Per lane, the byte offsets of its table entry and of its pixel, eight lanes to a
        // register: the loop below then adds one of each to a base, where it sign-extended,
        // shifted and added per lane.
        let (mut qo, mut po) = ([0usize; L], [0usize; L]);
        // SAFETY: the CPU has AVX-512F and VL (the caller's promise); `L` is 8 or 16, so each
        // eighth of `bases` (32 bytes), `at`, `qo` and `po` (64 bytes each) is in its array.
        unsafe {
            for h in 0..L / 8 {
                let b = _mm256_loadu_si256(w.bases.as_ptr().add(8 * h).cast());
                let q = _mm512_slli_epi64::<4>(_mm512_cvtepi32_epi64(b));
                _mm512_storeu_si512(qo.as_mut_ptr().add(8 * h).cast(), q);
                let a = _mm512_loadu_si512(at.as_ptr().add(8 * h).cast());
                // Wrapping for a lane past `buf`, whose offset is never used.
                let p = _mm512_slli_epi64::<4>(a);
                _mm512_storeu_si512(po.as_mut_ptr().add(8 * h).cast(), p);
            }
        }
        while twos.count_ones() >= 2 {
            let i = twos.trailing_zeros() as usize;
            twos &= twos - 1;
            let j = twos.trailing_zeros() as usize;
            twos &= twos - 1;
            debug_assert!(i < L && j < L);
            // SAFETY: the CPU has AVX-512F and VL (the caller's promise). `i` and `j` are lanes
            // of `todo`, below `L`. Both bases are in the table as in [`entry`], so every
            // 32-byte read from `q + o` lies in it; `at[i]` and `at[j]` are distinct pixels
            // inside `buf` (checked above), `po` their byte offsets.
            unsafe {
                let (qi, qj) = (
                    data.byte_add(*qo.get_unchecked(i)),
                    data.byte_add(*qo.get_unchecked(j)),
                );
                // Entries `a` and `a + 1` of lane `i`, then of lane `j`.
                let c = |o: usize| {
                    let lo = _mm512_castps256_ps512(_mm256_loadu_ps(qi.add(o).cast()));
                    let hi = _mm256_castps_pd(_mm256_loadu_ps(qj.add(o).cast()));
                    _mm512_castpd_ps(_mm512_insertf64x4::<1>(_mm512_castps_pd(lo), hi))
                };
                let two = |v: &[f32; L]| {
                    _mm512_mask_broadcastss_ps(
                        _mm512_set1_ps(*v.get_unchecked(i)),
                        0xff00,
                        _mm_set_ss(*v.get_unchecked(j)),
                    )
                };
                let (tb, tl) = (two(&w.wb), two(&w.wl));
                let lerp = |a: __m512, b: __m512, t: __m512| {
                    _mm512_add_ps(a, _mm512_mul_ps(t, _mm512_sub_ps(b, a)))
                };
                let v = lerp(lerp(c(0), c(o1), tb), lerp(c(o2), c(o2 + o1), tb), tl);
                // Quarters (i: a, a + 1, j: a, a + 1) to (i: a, j: a, i: a + 1, j: a + 1).
                let v = _mm512_shuffle_f32x4::<0b11_01_10_00>(v, v);
                let lo = _mm512_castps512_ps256(v);
                let hi = _mm256_castpd_ps(_mm512_extractf64x4_pd::<1>(_mm512_castps_pd(v)));
                let wf = _mm256_mask_broadcastss_ps(
                    _mm256_set1_ps(*w.wf.get_unchecked(i)),
                    0xf0,
                    _mm_set_ss(*w.wf.get_unchecked(j)),
                );
                let v = _mm256_add_ps(lo, _mm256_mul_ps(wf, _mm256_sub_ps(hi, lo)));
                let (pi, pj) = (
                    out.byte_add(*po.get_unchecked(i)).cast::<f32>(),
                    out.byte_add(*po.get_unchecked(j)).cast::<f32>(),
                );
                let sv = _mm256_loadu2_m128(pj, pi);
                let k = _mm256_sub_ps(_mm256_set1_ps(1.0), _mm256_permute_ps::<0xff>(sv));
                let new = _mm256_add_ps(sv, _mm256_mul_ps(k, v));
                _mm256_storeu2_m128(pj, pi, new);
                reached |= _mm256_cmp_ps_mask::<_CMP_GE_OQ>(new, _mm256_set1_ps(OPAQUE));
            }
        }
        if reached & 0x88 != 0 {
            // Some paired pixel turned opaque (rare: once per pixel). Every paired lane was
            // below `OPAQUE` (or NaN) before, so those at or past it now are the new ones.
            let mut p = todo & !(w.long as u32) & !twos;
            while p != 0 {
                let i = p.trailing_zeros() as usize;
                p &= p - 1;
                // SAFETY: `at[i]` is inside `buf` (a lane of `todo`).
                let a = unsafe { (*out.add(at[i]))[3] };
                counts += ((a >= OPAQUE) as u64) << 32;
            }
        }
        counts += (todo & !(w.long as u32) & !twos).count_ones() as u64;
        // Long lanes and an odd one left: one at a time.
        let mut single = (todo & w.long as u32) | twos;
        while single != 0 {
            let i = single.trailing_zeros() as usize;
            single &= single - 1;
            // SAFETY: `at[i]` is inside `buf` (checked above); the caller's promises.
            unsafe {
                let p = out.add(at[i]);
                counts += over(p, *p, entry(t, w, f, i));
            }
        }
        d.frags += counts & 0xffff_ffff;
        d.opaque += (counts >> 32) as usize;
    }

    /// Table corner bases and weights of [`LANES`] lookups, as `PreintTable::prep` computes
    /// them, in registers (calling `prep` here, with its `usize` bases, made 200k-tet frames'
    /// tiles 13 % slower); bit `i` of `long` marks a lane past the length axis.
    struct Weights<const L: usize> {
        /// The table's entries and the offsets of the next Sb and l, read from the table
        /// once per batch rather than in the pixel loop, where a store to a pixel could make
        /// the compiler read them again.
        data: *const [f32; 4],
        o1: usize,
        o2: usize,
        bases: [i32; L],
        wf: [f32; L],
        wb: [f32; L],
        wl: [f32; L],
        long: i32,
    }

    /// The [`Weights`] of fragments `f`.
    ///
    /// # Safety
    /// The CPU has AVX2.
    #[inline(always)]
    unsafe fn weights(t: &PreintTable, f: &Lanes) -> Weights<LANES> {
        let load = |v: &[f32; LANES]| {
            // SAFETY: `v` holds 8 floats, and the CPU has AVX (implied by AVX2, which this
            // closure's caller promises).
            unsafe { _mm256_loadu_ps(v.as_ptr()) }
        };
        let (sf, sb, l) = (load(&f[0]), load(&f[1]), load(&f[2]));
        let s0 = _mm256_set1_ps(t.s0);
        let inv_ds = _mm256_set1_ps(t.inv_ds);
        let top = _mm256_set1_ps((t.ns - 1) as f32);
        let xf = clamp0(_mm256_mul_ps(_mm256_sub_ps(sf, s0), inv_ds), top);
        let xb = clamp0(_mm256_mul_ps(_mm256_sub_ps(sb, s0), inv_ds), top);
        let ql = _mm256_mul_ps(l, _mm256_set1_ps(t.inv_dl));
        let ltop = _mm256_set1_ps((t.nl - 1) as f32);
        // Lanes past the length axis: `PreintTable::segment` replaces their lookup.
        let long = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_GT_OQ>(ql, ltop));
        let xl = clamp0(ql, ltop);
        let (ns, nl) = (t.ns as i32, t.nl as i32);
        // Truncation of values in [0, ns - 1] or [0, nl - 1], as `to_int_unchecked`.
        let a = _mm256_min_epi32(_mm256_cvttps_epi32(xf), _mm256_set1_epi32(ns - 2));
        let b = _mm256_min_epi32(_mm256_cvttps_epi32(xb), _mm256_set1_epi32(ns - 2));
        let c = _mm256_min_epi32(_mm256_cvttps_epi32(xl), _mm256_set1_epi32(nl - 2));
        let nsv = _mm256_set1_epi32(ns);
        let base = _mm256_add_epi32(
            _mm256_mullo_epi32(_mm256_add_epi32(_mm256_mullo_epi32(c, nsv), b), nsv),
            a,
        );
        let mut w = Weights {
            data: t.data.as_ptr(),
            o1: t.ns,
            o2: t.ns * t.ns,
            bases: [0; LANES],
            wf: [0.0; LANES],
            wb: [0.0; LANES],
            wl: [0.0; LANES],
            long,
        };
        // SAFETY: `bases` holds 8 `i32`, each weight array 8 floats.
        unsafe {
            _mm256_storeu_si256(w.bases.as_mut_ptr().cast(), base);
            _mm256_storeu_ps(w.wf.as_mut_ptr(), _mm256_sub_ps(xf, _mm256_cvtepi32_ps(a)));
            _mm256_storeu_ps(w.wb.as_mut_ptr(), _mm256_sub_ps(xb, _mm256_cvtepi32_ps(b)));
            _mm256_storeu_ps(w.wl.as_mut_ptr(), _mm256_sub_ps(xl, _mm256_cvtepi32_ps(c)));
        }
        w
    }

    /// [`weights`] of [`WIDE_LANES`] fragments in AVX-512: the same operations on each lane,
    /// so the same bits.
    ///
    /// # Safety
    /// The CPU has AVX-512F.
    #[inline(always)]
    unsafe fn weights_wide(t: &PreintTable, f: &WideLanes) -> Weights<WIDE_LANES> {
        let load = |v: &[f32; WIDE_LANES]| {
            // SAFETY: `v` holds 16 floats, and the CPU has AVX-512F (this closure's caller's
            // promise).
            unsafe { _mm512_loadu_ps(v.as_ptr()) }
        };
        // `clamp0` in 512 bits: NaN lanes become +0 (as the AND with the ordered mask).
        let clamp0 = |x: __m512, hi: __m512| {
            let ord = _mm512_cmp_ps_mask::<_CMP_ORD_Q>(x, x);
            _mm512_min_ps(hi, _mm512_maskz_max_ps(ord, _mm512_setzero_ps(), x))
        };
        let (sf, sb, l) = (load(&f[0]), load(&f[1]), load(&f[2]));
        let s0 = _mm512_set1_ps(t.s0);
        let inv_ds = _mm512_set1_ps(t.inv_ds);
        let top = _mm512_set1_ps((t.ns - 1) as f32);
        let xf = clamp0(_mm512_mul_ps(_mm512_sub_ps(sf, s0), inv_ds), top);
        let xb = clamp0(_mm512_mul_ps(_mm512_sub_ps(sb, s0), inv_ds), top);
        let ql = _mm512_mul_ps(l, _mm512_set1_ps(t.inv_dl));
        let ltop = _mm512_set1_ps((t.nl - 1) as f32);
        let long = _mm512_cmp_ps_mask::<_CMP_GT_OQ>(ql, ltop) as i32;
        let xl = clamp0(ql, ltop);
        let (ns, nl) = (t.ns as i32, t.nl as i32);
        let a = _mm512_min_epi32(_mm512_cvttps_epi32(xf), _mm512_set1_epi32(ns - 2));
        let b = _mm512_min_epi32(_mm512_cvttps_epi32(xb), _mm512_set1_epi32(ns - 2));
        let c = _mm512_min_epi32(_mm512_cvttps_epi32(xl), _mm512_set1_epi32(nl - 2));
        let nsv = _mm512_set1_epi32(ns);
        let base = _mm512_add_epi32(
            _mm512_mullo_epi32(_mm512_add_epi32(_mm512_mullo_epi32(c, nsv), b), nsv),
            a,
        );
        let mut w = Weights {
            data: t.data.as_ptr(),
            o1: t.ns,
            o2: t.ns * t.ns,
            bases: [0; WIDE_LANES],
            wf: [0.0; WIDE_LANES],
            wb: [0.0; WIDE_LANES],
            wl: [0.0; WIDE_LANES],
            long,
        };
        // SAFETY: `bases` holds 16 `i32`, each weight array 16 floats.
        unsafe {
            _mm512_storeu_si512(w.bases.as_mut_ptr().cast(), base);
            _mm512_storeu_ps(w.wf.as_mut_ptr(), _mm512_sub_ps(xf, _mm512_cvtepi32_ps(a)));
            _mm512_storeu_ps(w.wb.as_mut_ptr(), _mm512_sub_ps(xb, _mm512_cvtepi32_ps(b)));
            _mm512_storeu_ps(w.wl.as_mut_ptr(), _mm512_sub_ps(xl, _mm512_cvtepi32_ps(c)));
        }
        w
    }

    /// Colour and opacity (premultiplied) of lane `i`: its table entry, or
    /// `PreintTable::segment` for a long lane.
    ///
    /// # Safety
    /// The CPU has AVX2, and [`fits`] holds for `t`; `w` is [`weights`] of `f`.
    #[inline(always)]
    unsafe fn entry<const L: usize>(
        t: &PreintTable,
        w: &Weights<L>,
        f: &[[f32; L]; 3],
        i: usize,
    ) -> __m128 {
        if w.long >> i & 1 != 0 {
            // SAFETY: 16 bytes.
            return unsafe { _mm_loadu_ps(t.segment(f[0][i], f[1][i], f[2][i]).as_ptr()) };
        }
        let (o1, o2) = (w.o1, w.o2);
        // SAFETY: the base is `(c ns + b) ns + a` with `a, b` in [0, ns - 2] and `c` in
        // [0, nl - 2] (clamped in `weights`; `fits` makes the products exact in i32), so
        // `base + ns ns + ns + 1 <= nl ns ns - 1 < data.len()`: every pair of entries read
        // below (from `q + o` to `q + o + 1`) lies in the table.
        unsafe {
            let q = w.data.add(w.bases[i] as usize);
            let c = |o: usize| _mm256_loadu_ps(q.add(o).cast());
            let (tb, tl) = (_mm256_set1_ps(w.wb[i]), _mm256_set1_ps(w.wl[i]));
            // Entries `a` and `a + 1` side by side: blended along Sb, then l, then (the two
            // halves) along Sf, as `PreintTable::corners`.
            let v = lerp(lerp(c(0), c(o1), tb), lerp(c(o2), c(o2 + o1), tb), tl);
            let (lo, hi) = (_mm256_castps256_ps128(v), _mm256_extractf128_ps::<1>(v));
            _mm_add_ps(lo, _mm_mul_ps(_mm_set1_ps(w.wf[i]), _mm_sub_ps(hi, lo)))
        }
    }

    /// Composites `v` behind pixel `p`, which holds `s`: the count word of one drawn fragment
    /// (bit 32 set when the pixel turned opaque).
    ///
    /// # Safety
    /// The CPU has AVX; `p` points to a pixel that holds `s`.
    #[inline(always)]
    unsafe fn over(p: *mut [f32; 4], s: [f32; 4], v: __m128) -> u64 {
        // SAFETY: 16 bytes each.
        let sv = unsafe { _mm_loadu_ps(s.as_ptr()) };
        let new = _mm_add_ps(
            sv,
            _mm_mul_ps(_mm_sub_ps(_mm_set1_ps(1.0), _mm_set1_ps(s[3])), v),
        );
        let mut r = [0f32; 4];
        // SAFETY: 16 bytes each; `p` points to a pixel (the caller's promise).
        unsafe {
            _mm_storeu_ps(r.as_mut_ptr(), new);
            *p = r;
        }
        1 | ((r[3] >= OPAQUE) as u64) << 32
    }
}

/// A transfer function evaluated at both ends of each fragment as a [`Shade`]: VTK's averaged
/// integration ([`FastTf::average`]), or linear integration ([`FastTf::linear`]) when `LINEAR`.
struct TfShade<'a, const LINEAR: bool>(&'a FastTf);

impl<const LINEAR: bool> Shade for TfShade<'_, LINEAR> {
    type Prep = Lanes;
    #[inline(always)]
    fn prep(&self, f: &Lanes) -> Lanes {
        *f
    }
    #[inline(always)]
    fn at(&self, f: &Lanes, i: usize) -> [f32; 4] {
        if LINEAR {
            self.0.linear(f[0][i], f[1][i], f[2][i])
        } else {
            self.0.average(f[0][i], f[1][i], f[2][i])
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::render::transfer::{named_colormap, OpacitySpec, TransferFunction};

    /// A xorshift stream of floats in [0, 1).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f32 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    /// A value around `[lo, hi]`, now and then one the clamps must catch.
    fn value(r: &mut Rng, lo: f32, hi: f32) -> f32 {
        const ODD: [f32; 8] = [
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            -0.0,
            0.0,
            1e30,
            -1e30,
            f32::MIN_POSITIVE,
        ];
        if r.next() < 0.1 {
            ODD[(r.next() * 8.0) as usize % 8]
        } else {
            lo + (hi - lo) * (r.next() * 1.4 - 0.2)
        }
    }

    /// A random batch of `L` fragments for `table` over `npix` pixels, `stride` apart (so
    /// distinct), some already (nearly) opaque, one now and then NaN.
    #[allow(clippy::type_complexity)]
    fn random_batch<const L: usize>(
        r: &mut Rng,
        table: &PreintTable,
        npix: usize,
        stride: usize,
    ) -> ([[f32; L]; 3], [usize; L], Vec<[f32; 4]>) {
        let mut f = [[0f32; L]; 3];
        for (k, lanes) in f.iter_mut().enumerate() {
            // Lengths up to three times the table's axis: long lanes take `segment`.
            let hi = if k < 2 { 3.0 } else { 3.0 * table.lmax as f32 };
            for v in lanes.iter_mut() {
                *v = value(r, if k < 2 { -1.0 } else { 0.0 }, hi);
            }
        }
        let mut at = [0usize; L];
        let start = (r.next() * npix as f32) as usize;
        for (i, a) in at.iter_mut().enumerate() {
            *a = (start + stride * i) % npix;
        }
        let mut buf = vec![[0f32; 4]; npix];
        for p in buf.iter_mut() {
            let a = match (r.next() * 6.0) as usize {
                0 => 0.0,
                1 => OPAQUE,
                2 => 1.0,
                3 if r.next() < 0.05 => f32::NAN,
                // Just below opaque: a fragment can take it past.
                4 => OPAQUE - r.next() * 0.01,
                _ => r.next(),
            };
            *p = [r.next() * a, r.next() * a, r.next() * a, a];
        }
        (f, at, buf)
    }

    /// Runs `run` and `reference` on the same 20,000 random batches of `L` lanes (`n` from 0
    /// to `L`): `run` must leave the bits and counts `reference` leaves.
    #[allow(clippy::type_complexity)]
    fn same_bits<const L: usize>(
        table: &PreintTable,
        (seed, npix, stride): (u64, usize, usize),
        reference: impl Fn(&[[f32; L]; 3], &[usize; L], usize, &mut [[f32; 4]], &mut Drawn),
        run: impl Fn(&PreintTable, &[[f32; L]; 3], &[usize; L], usize, &mut [[f32; 4]], &mut Drawn),
    ) {
        let mut r = Rng(seed);
        for case in 0..20_000 {
            let (f, at, buf) = random_batch::<L>(&mut r, table, npix, stride);
            let n = case % (L + 1);
            let (mut want, mut got) = (buf.clone(), buf);
            let (mut dw, mut dg) = (Drawn::default(), Drawn::default());
            reference(&f, &at, n, &mut want, &mut dw);
            run(table, &f, &at, n, &mut got, &mut dg);
            let bits = |b: &[[f32; 4]]| b.iter().map(|p| p.map(f32::to_bits)).collect::<Vec<_>>();
            assert_eq!(bits(&got), bits(&want), "case {case}: {f:?} n {n}");
            assert_eq!((dg.frags, dg.opaque), (dw.frags, dw.opaque), "case {case}");
        }
    }

    /// Runs `run` on the same random batches as [`composite_lanes`] for `table`: every path
    /// must leave the same bits in the buffer and the same counts.
    fn same_as_lanes(
        table: &PreintTable,
        run: impl Fn(&PreintTable, &Lanes, &[usize; LANES], usize, &mut [[f32; 4]], &mut Drawn),
    ) {
        same_bits::<LANES>(
            table,
            (0x9e37_79b9_7f4a_7c15, 64, 7),
            |f, at, n, buf, d| composite_lanes(table, f, at, n, buf, d),
            run,
        );
    }

    /// [`same_as_lanes`] for the 16-lane batches of the AVX-512 rows: `run` must leave the
    /// bits and counts that [`composite_lanes`] leaves on each half in turn.
    #[cfg(target_arch = "x86_64")]
    fn wide_same_as_lanes(
        table: &PreintTable,
        run: impl Fn(&PreintTable, &WideLanes, &[usize; WIDE_LANES], usize, &mut [[f32; 4]], &mut Drawn),
    ) {
        same_bits::<WIDE_LANES>(
            table,
            (0x2545_f491_4f6c_dd1d, 96, 5),
            |f, at, n, buf, d| {
                for_halves(f, at, n, |half, at, m| {
                    composite_lanes(table, half, at, m, buf, d)
                })
            },
            run,
        );
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn the_wide_composite_gives_the_same_bits() {
        if !(std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512vl"))
        {
            eprintln!("no AVX-512 here: the 16-lane composite is not used");
            return;
        }
        for t in tables() {
            // SAFETY: the CPU has AVX-512F and VL, checked just above.
            wide_same_as_lanes(&t, |t, f, at, n, buf, d| unsafe {
                t.composite_wide(f, at, n, buf, d)
            });
        }
    }

    pub(crate) fn tables() -> Vec<PreintTable> {
        let tf = TransferFunction::build(
            &named_colormap("viridis").unwrap(),
            Some(&OpacitySpec::parse("0:0.1,0.5:0.9,1:0.3").unwrap()),
            [0.0, 2.0],
            0.5,
            17,
        )
        .unwrap();
        vec![
            PreintTable::build(&tf, 33, 9, 2.0),
            PreintTable::build(&tf, 2, 2, 1.0),
        ]
    }

    #[test]
    fn every_composite_path_gives_the_same_bits() {
        let mut paths = 0;
        for t in tables() {
            // The dispatching entry point, whatever path it takes on this CPU.
            same_as_lanes(&t, |t, f, at, n, buf, d| t.composite(f, at, n, buf, d));
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") {
                assert!(x86::fits(&t));
                // SAFETY: the CPU has AVX2 and `fits` holds, both checked just above.
                same_as_lanes(&t, |t, f, at, n, buf, d| unsafe {
                    x86::composite_pre(t, f, at, n, buf, d)
                });
                paths += 1;
            }
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx512f")
                && std::arch::is_x86_feature_detected!("avx512vl")
            {
                // SAFETY: the CPU has AVX-512F and VL (so AVX2), checked just above, and
                // `fits` holds (asserted above).
                same_as_lanes(&t, |t, f, at, n, buf, d| unsafe {
                    x86::composite_pre512(t, f, at, n, buf, d)
                });
                paths += 1;
            }
        }
        eprintln!("explicit SIMD paths checked: {paths}");
    }
}
