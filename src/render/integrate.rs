//! Ray integration of one segment through a tet: exact, linear, VTK's average, and the 3-D
//! pre-integration table (Engel et al. 2001) built in parallel.
//!
//! Model: emission-absorption with colour `c(s)` and extinction `tau(s)` from the transfer
//! function; a segment of length `l` whose scalar goes linearly from `sf` (entry) to `sb` (exit)
//! contributes premultiplied `C = int_0^l tau c exp(-int_0^t tau) dt` and `A = 1 - exp(-int tau)`.

// Negated comparisons are deliberate: they also catch NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::transfer::TransferFunction;
use rayon::prelude::*;

/// How a PT fragment turns (Sf, Sb, l) into colour and opacity.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Integration {
    /// VTK's projected-tetrahedra mapper: mean colour and extinction of both ends,
    /// `A = 1 - exp(-tau l)`.
    Average,
    /// Colour and extinction linear between the two ends, integrated exactly (exact when the
    /// transfer function is linear over [Sf, Sb]).
    Linear,
    /// Exact integral through every transfer-function node, from a 3-D (Sf, Sb, l) table.
    Preintegrated,
}

impl Integration {
    pub const ALL: [Integration; 3] = [
        Integration::Average,
        Integration::Linear,
        Integration::Preintegrated,
    ];
    pub fn name(self) -> &'static str {
        match self {
            Integration::Average => "average",
            Integration::Linear => "linear",
            Integration::Preintegrated => "preintegrated",
        }
    }
}

/// Gauss-Legendre nodes and weights on [0, 1], 4 points.
const GL_X: [f64; 4] = [
    0.069_431_844_202_973_71,
    0.330_009_478_207_571_9,
    0.669_990_521_792_428_1,
    0.930_568_155_797_026_3,
];
const GL_W: [f64; 4] = [
    0.173_927_422_568_726_9,
    0.326_072_577_431_273_1,
    0.326_072_577_431_273_1,
    0.173_927_422_568_726_9,
];

/// Gauss-Legendre nodes and weights on [0, 1], 8 points (for pieces of large optical depth).
const GL8_X: [f64; 8] = [
    0.019_855_071_751_231_912,
    0.101_666_761_293_186_64,
    0.237_233_795_041_835_5,
    0.408_282_678_752_175_1,
    0.591_717_321_247_824_8,
    0.762_766_204_958_164_5,
    0.898_333_238_706_813_4,
    0.980_144_928_248_768_1,
];
const GL8_W: [f64; 8] = [
    0.050_614_268_145_188_344,
    0.111_190_517_226_687_17,
    0.156_853_322_938_943_52,
    0.181_341_891_689_180_88,
    0.181_341_891_689_180_88,
    0.156_853_322_938_943_52,
    0.111_190_517_226_687_17,
    0.050_614_268_145_188_344,
];

/// Taylor coefficients of `exp(-x)`, `(-1)^n / n!`, as constants so that no division is left.
const EXP_NEG_TAYLOR: [f64; 14] = [
    1.0,
    -1.0,
    1.0 / 2.0,
    -1.0 / 6.0,
    1.0 / 24.0,
    -1.0 / 120.0,
    1.0 / 720.0,
    -1.0 / 5040.0,
    1.0 / 40320.0,
    -1.0 / 362880.0,
    1.0 / 3628800.0,
    -1.0 / 39916800.0,
    1.0 / 479001600.0,
    -1.0 / 6227020800.0,
];

/// `exp(-x)` for `x` in [0, 0.5] (the optical depth of almost every piece): Taylor polynomial
/// of degree 13, relative error below 1e-14, inlined and free of libm calls. Estrin's scheme:
/// four dependent steps instead of Horner's thirteen (the latency is what a piece waits on).
#[inline(always)]
fn exp_neg_small(x: f64) -> f64 {
    let c = &EXP_NEG_TAYLOR;
    let x2 = x * x;
    let x4 = x2 * x2;
    let x8 = x4 * x4;
    let p = |i: usize| c[i] + c[i + 1] * x;
    let q0 = p(0) + p(2) * x2;
    let q1 = p(4) + p(6) * x2;
    let q2 = p(8) + p(10) * x2;
    let r0 = q0 + q1 * x4;
    let r1 = q2 + p(12) * x4;
    r0 + r1 * x8
}

/// `exp(-x)` for `x` in [0, 1/16]: degree 7 (error `x^8 / 8!` below 1.4e-14).
#[inline(always)]
fn exp_neg_tiny(x: f64) -> f64 {
    let c = &EXP_NEG_TAYLOR;
    let x2 = x * x;
    let a = (c[0] + c[1] * x) + (c[2] + c[3] * x) * x2;
    let b = (c[4] + c[5] * x) + (c[6] + c[7] * x) * x2;
    a + b * (x2 * x2)
}

/// `exp(-x)` for an optical depth `x >= 0`.
#[inline(always)]
fn exp_neg(x: f64) -> f64 {
    if (0.0..=1.0 / 16.0).contains(&x) {
        exp_neg_tiny(x)
    } else if x <= 0.5 {
        exp_neg_small(x)
    } else {
        (-x).exp()
    }
}

/// `int_0^1 exp(-(p u + q u^2)) du` for `p >= 0`, `p + 2q >= 0` (optical depth increasing in u),
/// given `trans = exp(-(p + q))`, for pieces beyond [`piece_integrals`]' series. Constant
/// extinction (`q = 0`) in closed form; otherwise Gauss-Legendre: 4 points while the slope is
/// <= 0.5 and `|q| <= 1/16` (with [`exp_neg_small`]), else composite
/// 8-point on intervals of optical depth <= 4, stopping where the depth passes 40 (the rest is
/// below 4e-18). The quadrature error grows with the curvature `q` as much as with the depth, hence
/// both limits; measured over each tier's corners (mpmath), the relative error is below 2e-10.
fn depth_integral(p: f64, q: f64, trans: f64) -> f64 {
    let t1 = p + q;
    if !(t1 > 1e-300) {
        return 1.0;
    }
    if q == 0.0 {
        // (1 - e^-p) / p; its series where the difference would lose digits (error p^4/120).
        return if p < 1e-3 {
            1.0 - p * (0.5 - p * (1.0 / 6.0 - p * (1.0 / 24.0)))
        } else {
            (1.0 - trans) / p
        };
    }
    let depth = |u: f64| u * (p + q * u);
    let mut umax = 1.0;
    if t1 > 40.0 {
        // Root of q u^2 + p u - 40 in [0, 1], stable form.
        let disc = (p * p + 160.0 * q).max(0.0);
        umax = (80.0 / (p + disc.sqrt())).clamp(0.0, 1.0);
    }
    let slope = p.max(p + 2.0 * q * umax).max(0.0);
    let total = slope * umax;
    let mut sum = 0.0;
    let curv = q.abs() * umax * umax;
    if total <= 0.5 && curv <= 1.0 / 16.0 {
        // Every depth here is in [0, total].
        for (x, w) in GL_X.iter().zip(GL_W) {
            sum += w * exp_neg_small(depth(x * umax).max(0.0));
        }
        return sum * umax;
    }
    // At least 1 and at most 100 intervals (total < 80 * slope / p <= 400 here); the cast is
    // the floor for the positive quotient.
    let m = ((total / 4.0) as usize + 1).clamp(1, 100);
    let h = umax / m as f64;
    for k in 0..m {
        let a = k as f64 * h;
        for (x, w) in GL8_X.iter().zip(GL8_W) {
            sum += w * (-depth(a + x * h)).exp();
        }
    }
    sum * h
}

/// Transmittance `exp(-(p + q))` and, when `need_i`, `int_0^1 exp(-(p u + q u^2)) du` of a
/// piece of optical depth `p u + q u^2`. While the depth's slope is <= 1/16 and `|q| <= 1/256`
/// (almost every piece) both come from one exponential: a Taylor series about the middle,
/// `phi(1/2 + v) = pm + s v + q v^2`, gives the integral as
/// `exp(-pm) int_{-1/2}^{1/2} exp(-(s v + q v^2)) dv` (odd powers of v drop out; terms up to s^6
/// and q^3, the first left out below 1e-14 relative), and the transmittance is
/// `exp(-pm)^2 exp(-q/2)`. Other pieces go to [`depth_integral`].
#[inline(always)]
fn piece_integrals(p: f64, q: f64, need_i: bool) -> (f64, f64) {
    let slope = p.max(p + 2.0 * q);
    if slope <= 1.0 / 16.0 && q.abs() <= 1.0 / 256.0 {
        let pm = 0.5 * p + 0.25 * q;
        let e = exp_neg_tiny(pm);
        // exp(-q/2) for |q/2| <= 1/512: the degree-4 Taylor polynomial (error below 1e-17).
        let h = 0.5 * q;
        let eh = 1.0 - h * (1.0 - h * (0.5 - h * (1.0 / 6.0 - h * (1.0 / 24.0))));
        let trans = e * e * eh;
        if !need_i {
            return (trans, 0.0);
        }
        let s = p + q;
        let (s2, q2) = (s * s, q * q);
        // Coefficients as constant reciprocals (multiplications, not divisions).
        const K: [f64; 9] = [
            1.0 / 12.0,
            1.0 / 24.0,
            1.0 / 160.0,
            1.0 / 160.0,
            1.0 / 2688.0,
            1.0 / 1920.0,
            1.0 / 1792.0,
            1.0 / 10752.0,
            1.0 / 322_560.0,
        ];
        let series = 1.0 - q * K[0] + s2 * K[1] + q2 * K[2] - s2 * q * K[3] - q2 * q * K[4]
            + s2 * s2 * K[5]
            + s2 * q2 * K[6]
            - s2 * s2 * q * K[7]
            + s2 * s2 * s2 * K[8];
        return (trans, e * series);
    }
    let trans = exp_neg(p + q);
    let i = if need_i {
        depth_integral(p, q, trans)
    } else {
        0.0
    };
    (trans, i)
}

/// One piece with colour and extinction linear in the ray parameter: premultiplied colour and
/// transmittance.
#[inline(always)]
fn linear_piece(c0: [f64; 3], t0: f64, c1: [f64; 3], t1: f64, len: f64) -> ([f64; 3], f64) {
    let p = len * t0;
    let q = 0.5 * len * (t1 - t0);
    // Integration by parts: int c tau e^-T = c0 - c1 e^-T1 + (c1 - c0) int e^-T.
    let (trans, i) = piece_integrals(p, q, c0 != c1);
    // Written out: `[0, 1, 2].map` here is left as a call in some builds.
    (
        [
            c0[0] - c1[0] * trans + (c1[0] - c0[0]) * i,
            c0[1] - c1[1] * trans + (c1[1] - c0[1]) * i,
            c0[2] - c1[2] * trans + (c1[2] - c0[2]) * i,
        ],
        trans,
    )
}

/// Largest integer below `x`, for `x > 0` (truncation is the floor there; no libm call).
#[inline]
fn int_below(x: f64) -> usize {
    let t = x as usize;
    if t as f64 == x {
        t - 1
    } else {
        t
    }
}

/// Exact integral of a segment (premultiplied RGB, alpha); see [`ExactTf::segment`].
pub fn exact_segment(tf: &TransferFunction, sf: f64, sb: f64, len: f64) -> [f64; 4] {
    ExactTf::new(tf).segment(sf, sb, len)
}

/// A transfer function prepared for many exact segment integrals (a frame's worth): what
/// [`exact_segment`] would work out again for every segment.
#[derive(Clone, Copy, Debug)]
pub struct ExactTf<'a> {
    tf: &'a TransferFunction,
    r0: f64,
    /// Node units per scalar unit (unused for a zero-width range).
    inv: f64,
    last: usize,
    step: bool,
}

impl<'a> ExactTf<'a> {
    pub fn new(tf: &'a TransferFunction) -> ExactTf<'a> {
        let (r0, r1) = (tf.range[0], tf.range[1]);
        let last = tf.nodes() - 1;
        let step = !(r1 > r0);
        ExactTf {
            tf,
            r0,
            inv: if step { 0.0 } else { last as f64 / (r1 - r0) },
            last,
            step,
        }
    }

    /// Exact integral of a segment (premultiplied RGB, alpha): split at every transfer-function
    /// node between `sf` and `sb` (and where the scalar leaves the range, beyond which the
    /// function is constant), each piece integrated in closed form up to the exponential
    /// integral. Pieces end on nodes, so their colour and extinction are the nodes' own values.
    pub fn segment(&self, sf: f64, sb: f64, len: f64) -> [f64; 4] {
        self.acc(sf, sb, len).rgba()
    }

    /// [`Self::segment`] as premultiplied colour and transmittance (so that segments compose
    /// without losing a transmittance close to 0).
    fn acc(&self, sf: f64, sb: f64, len: f64) -> Acc {
        let mut acc = Acc::EMPTY;
        if !(len > 0.0) {
            return acc;
        }
        let tf = self.tf;
        let (r0, last) = (self.r0, self.last);
        let k = last as f64;
        if self.step || sf == sb {
            // Constant over the segment, or (a zero-width range) a step at r0 from node 0 to the
            // last node: at most two constant pieces.
            let (cf, tf0) = tf.eval(sf);
            let (cb, tb) = tf.eval(sb);
            let u = if cf == cb && tf0 == tb {
                1.0
            } else {
                ((r0 - sf) / (sb - sf)).clamp(0.0, 1.0)
            };
            acc.add(cf, tf0, cf, tf0, len * u);
            acc.add(cb, tb, cb, tb, len * (1.0 - u));
            return acc;
        }
        let (xf, xb) = ((sf - r0) * self.inv, (sb - r0) * self.inv);
        let dx = xb - xf;
        let (mut c0, mut t0) = tf.at_pos(xf.max(0.0).min(k));
        let mut u0 = 0.0f64;
        let up = dx > 0.0 && xb > 0.0 && xf < k;
        let down = dx < 0.0 && xf > 0.0 && xb < k;
        if up || down {
            let rdx = 1.0 / dx;
            // Nodes strictly between xf and xb within [0, k], in ray order.
            let (first, count) = if up {
                let lo = if xf < 0.0 { 0 } else { xf as usize + 1 };
                let hi = if xb > k { last } else { int_below(xb) };
                (lo, (hi + 1).saturating_sub(lo))
            } else {
                let hi = if xf > k { last } else { int_below(xf) };
                let lo = if xb < 0.0 { 0 } else { xb as usize + 1 };
                (hi, (hi + 1).saturating_sub(lo))
            };
            for j in 0..count {
                let n = if up { first + j } else { first - j };
                let u = ((n as f64 - xf) * rdx).max(u0).min(1.0);
                let (c1, t1) = (tf.rgb[n], tf.tau[n]);
                acc.add(c0, t0, c1, t1, len * (u - u0));
                (c0, t0, u0) = (c1, t1, u);
            }
        }
        let (c1, t1) = tf.at_pos(xb.max(0.0).min(k));
        acc.add(c0, t0, c1, t1, len * (1.0 - u0));
        acc
    }
}

/// Premultiplied colour and transmittance of the pieces so far.
#[derive(Clone, Copy, Debug)]
struct Acc {
    color: [f64; 3],
    trans: f64,
}

impl Acc {
    /// Nothing yet: no colour, full transmittance.
    const EMPTY: Acc = Acc {
        color: [0.0; 3],
        trans: 1.0,
    };

    /// `self` in front of `back` along the ray (the emission-absorption "over").
    #[inline(always)]
    fn then(&self, back: &Acc) -> Acc {
        Acc {
            color: [
                self.color[0] + self.trans * back.color[0],
                self.color[1] + self.trans * back.color[1],
                self.color[2] + self.trans * back.color[2],
            ],
            trans: self.trans * back.trans,
        }
    }

    #[inline(always)]
    fn add(&mut self, c0: [f64; 3], t0: f64, c1: [f64; 3], t1: f64, l: f64) {
        if l > 0.0 && self.trans >= 1e-30 {
            let (c, tr) = linear_piece(c0, t0, c1, t1, l);
            for (a, ck) in self.color.iter_mut().zip(c) {
                *a += self.trans * ck;
            }
            self.trans *= tr;
        }
    }

    #[inline(always)]
    fn rgba(&self) -> [f64; 4] {
        [
            self.color[0],
            self.color[1],
            self.color[2],
            1.0 - self.trans,
        ]
    }
}

/// Colour and extinction linear between the ends (the transfer function sampled at Sf and Sb
/// only), integrated exactly.
pub fn linear_segment(tf: &TransferFunction, sf: f64, sb: f64, len: f64) -> [f64; 4] {
    if !(len > 0.0) {
        return [0.0; 4];
    }
    let (c0, t0) = tf.eval(sf);
    let (c1, t1) = tf.eval(sb);
    let (c, tr) = linear_piece(c0, t0, c1, t1, len);
    [c[0], c[1], c[2], 1.0 - tr]
}

/// VTK's projected-tetrahedra integration: the mean of both ends' colour and extinction.
pub fn average_segment(tf: &TransferFunction, sf: f64, sb: f64, len: f64) -> [f64; 4] {
    if !(len > 0.0) {
        return [0.0; 4];
    }
    let (c0, t0) = tf.eval(sf);
    let (c1, t1) = tf.eval(sb);
    let a = 1.0 - (-0.5 * (t0 + t1) * len).exp();
    [
        0.5 * (c0[0] + c1[0]) * a,
        0.5 * (c0[1] + c1[1]) * a,
        0.5 * (c0[2] + c1[2]) * a,
        a,
    ]
}

/// The transfer function as f32 node arrays, for the per-fragment average and linear modes.
#[derive(Clone, Debug)]
pub struct FastTf {
    pub s0: f32,
    pub inv_ds: f32,
    pub last: f32,
    /// Per node: r, g, b, tau.
    pub nodes: Vec<[f32; 4]>,
    /// Per interval between nodes: its first node and the difference to the next (the f32
    /// subtraction the interpolation would do), so that [`Self::eval`] reads one 32-byte entry.
    steps: Vec<[f32; 8]>,
    /// Per interval `a`: the last interval `b` such that intervals `a..=b` all have zero
    /// extinction at both ends and finite colours, or `a - 1` (see [`Self::draws_nothing`]).
    clear_to: Vec<i32>,
}

impl FastTf {
    pub fn new(tf: &TransferFunction) -> FastTf {
        let k = tf.nodes() - 1;
        let span = tf.range[1] - tf.range[0];
        let nodes: Vec<[f32; 4]> = (0..=k)
            .map(|i| {
                let c = tf.rgb[i];
                [c[0] as f32, c[1] as f32, c[2] as f32, tf.tau[i] as f32]
            })
            .collect();
        // At least one interval (a transfer function has two nodes or more).
        let steps = nodes
            .windows(2)
            .map(|w| {
                let (a, b) = (w[0], w[1]);
                [
                    a[0],
                    a[1],
                    a[2],
                    a[3],
                    b[0] - a[0],
                    b[1] - a[1],
                    b[2] - a[2],
                    b[3] - a[3],
                ]
            })
            .collect::<Vec<[f32; 8]>>();
        // Zero extinction at both ends interpolates to exactly zero (`0 + t * 0`); finite
        // colours keep the premultiplied products zero.
        let clear = |e: &[f32; 8]| e[3] == 0.0 && e[7] == 0.0 && e.iter().all(|x| x.is_finite());
        let mut clear_to = vec![0i32; steps.len()];
        let mut to = steps.len() as i32 - 1;
        for (a, e) in steps.iter().enumerate().rev() {
            if !clear(e) {
                to = a as i32 - 1;
            }
            clear_to[a] = to;
        }
        FastTf {
            s0: tf.range[0] as f32,
            inv_ds: if span > 0.0 {
                (k as f64 / span) as f32
            } else {
                0.0
            },
            last: k as f32,
            nodes,
            steps,
            clear_to,
        }
    }

    /// Whether every fragment whose scalars lie in `[lo, hi]` is exactly transparent black in
    /// both [`Self::average`] and [`Self::linear`] (zero extinction gives an opacity of exactly
    /// 0 and a premultiplied colour of exactly 0), so a tet whose scalar range it is draws
    /// nothing. No margin: [`Self::eval`] finds its interval by the same monotone arithmetic,
    /// so every scalar in the range falls in an interval between those of `lo` and `hi`. NaN
    /// draws something.
    #[inline]
    pub fn draws_nothing(&self, lo: f32, hi: f32) -> bool {
        if !(lo <= hi) {
            return false;
        }
        let (a, b) = (self.locate(lo).0, self.locate(hi).0);
        self.clear_to.get(a).is_some_and(|&to| to >= b as i32)
    }

    /// The interval scalar `s` falls in and its position there, as [`Self::eval`] finds them.
    #[inline(always)]
    fn locate(&self, s: f32) -> (usize, f32) {
        let x = ((s - self.s0) * self.inv_ds).clamp(0.0, self.last);
        let i = (x as usize).min(self.steps.len() - 1);
        (i, x - i as f32)
    }

    /// Colour and extinction at scalar `s`: `a + t (b - a)` between the nodes around it.
    #[inline]
    pub fn eval(&self, s: f32) -> [f32; 4] {
        let (i, t) = self.locate(s);
        let e = &self.steps[i];
        [
            e[0] + t * e[4],
            e[1] + t * e[5],
            e[2] + t * e[6],
            e[3] + t * e[7],
        ]
    }

    #[inline]
    pub fn average(&self, sf: f32, sb: f32, l: f32) -> [f32; 4] {
        let (a, b) = (self.eval(sf), self.eval(sb));
        let alpha = 1.0 - (-0.5 * (a[3] + b[3]) * l).exp();
        let h = 0.5 * alpha;
        [
            (a[0] + b[0]) * h,
            (a[1] + b[1]) * h,
            (a[2] + b[2]) * h,
            alpha,
        ]
    }

    #[inline]
    pub fn linear(&self, sf: f32, sb: f32, l: f32) -> [f32; 4] {
        let (a, b) = (self.eval(sf), self.eval(sb));
        let (c, tr) = linear_piece(
            [a[0] as f64, a[1] as f64, a[2] as f64],
            a[3] as f64,
            [b[0] as f64, b[1] as f64, b[2] as f64],
            b[3] as f64,
            l as f64,
        );
        [c[0] as f32, c[1] as f32, c[2] as f32, (1.0 - tr) as f32]
    }
}

/// Pre-integrated (Sf, Sb, l) table: exact segment integrals on a regular grid, trilinear lookup.
#[derive(Clone, Debug)]
pub struct PreintTable {
    pub ns: usize,
    pub nl: usize,
    pub s0: f32,
    pub inv_ds: f32,
    pub inv_dl: f32,
    pub lmax: f64,
    /// Index `(il * ns + ib) * ns + if_`.
    pub data: Vec<[f32; 4]>,
    /// Per scalar bin `a`: the last bin `b` such that every entry with both scalar bins in
    /// `[a, b]` (any length) is exactly zero, or `a - 1` (see [`Self::draws_nothing`]).
    clear_to: Vec<i32>,
}

impl PreintTable {
    /// Builds an `ns x ns x nl` table for lengths in [0, lmax], in parallel (rayon) over the
    /// reduced fractions below, then over l-slices. Peak memory is about twice the table's: the
    /// composed runs wait in their own buffers until the slices take them.
    ///
    /// Entries are composed from short ones rather than integrated one by one: at a length
    /// `l` and a scalar difference of `m` grid steps, every segment is the ray-order composite
    /// of `m` consecutive one-step segments of length `l / m`, so each (l, m) integrates its
    /// `ns - 1` one-step segments exactly ([`ExactTf`]) and composes the `ns - m` runs of `m` of
    /// them with the van Herk / Gil-Werman sliding window (three composites per run whatever
    /// `m` is); the one-step segments of (l, m) and (k l, k m) are the same, integrated once.
    /// The composite is exact, so entries differ from integrating each segment at once
    /// only by f64 rounding before the f32 store (tests hold them to 2e-7; measured 3e-8).
    pub fn build(tf: &TransferFunction, ns: usize, nl: usize, lmax: f64) -> PreintTable {
        let ns = ns.max(2);
        let nl = nl.max(2);
        let lmax = if lmax > 0.0 && lmax.is_finite() {
            lmax
        } else {
            1.0
        };
        let span = tf.range[1] - tf.range[0];
        let s_at = |i: usize| tf.range[0] + span * i as f64 / (ns - 1) as f64;
        let l_at = |il: usize| lmax * il as f64 / (nl - 1) as f64;
        let ex = ExactTf::new(tf);
        let rgba = |a: &Acc| a.rgba().map(|x| x as f32);
        let mut data = vec![[0f32; 4]; ns * ns * nl];
        if !(span > 0.0) {
            // Every grid scalar is the same: constant segments, cheap one by one.
            data.par_chunks_mut(ns * ns)
                .enumerate()
                .for_each(|(il, slice)| {
                    for (k, o) in slice.iter_mut().enumerate() {
                        *o = rgba(&ex.acc(s_at(k % ns), s_at(k / ns), l_at(il)));
                    }
                });
        } else {
            // The one-step segments of length l / m depend on l / m only: integrated once per
            // reduced fraction p / q, they serve every (l, m) = (k p, k q).
            let fractions: Vec<(usize, usize)> = (1..nl)
                .flat_map(|p| {
                    (1..ns)
                        .filter(move |&q| gcd(p, q) == 1)
                        .map(move |q| (p, q))
                })
                .collect();
            // Per (il, m): the runs up (Sf < Sb) and down, as stored.
            type Diag = (usize, usize, Vec<[f32; 4]>, Vec<[f32; 4]>);
            let diags: Vec<Vec<Diag>> = fractions
                .par_iter()
                .map(|&(p, q)| {
                    let h = l_at(p) / q as f64;
                    let up: Vec<Acc> = (0..ns - 1)
                        .map(|j| ex.acc(s_at(j), s_at(j + 1), h))
                        .collect();
                    let down: Vec<Acc> = (0..ns - 1)
                        .map(|j| ex.acc(s_at(j + 1), s_at(j), h))
                        .collect();
                    (1..)
                        .map(|k| (k * p, k * q))
                        .take_while(|&(il, m)| il < nl && m < ns)
                        .map(|(il, m)| {
                            let f = |v: Vec<Acc>| v.iter().map(rgba).collect();
                            (il, m, f(runs(&up, m, false)), f(runs(&down, m, true)))
                        })
                        .collect()
                })
                .collect();
            let mut at = vec![None; nl * ns];
            for (il, m, up, down) in diags.iter().flatten() {
                at[il * ns + m] = Some((up.as_slice(), down.as_slice()));
            }
            data.par_chunks_mut(ns * ns)
                .enumerate()
                .skip(1)
                .for_each(|(il, slice)| {
                    for i in 0..ns {
                        slice[i * ns + i] = rgba(&ex.acc(s_at(i), s_at(i), l_at(il)));
                    }
                    for m in 1..ns {
                        // Every (il, m) with il, m >= 1 has its fraction, so this always holds.
                        if let Some((up, down)) = at[il * ns + m] {
                            for (i, (u, d)) in up.iter().zip(down).enumerate() {
                                // Up: Sf at grid i, Sb at i + m; down: the other way round.
                                slice[(i + m) * ns + i] = *u;
                                slice[i * ns + i + m] = *d;
                            }
                        }
                    }
                });
        }
        PreintTable {
            ns,
            nl,
            s0: tf.range[0] as f32,
            inv_ds: if span > 0.0 {
                ((ns - 1) as f64 / span) as f32
            } else {
                0.0
            },
            inv_dl: ((nl - 1) as f64 / lmax) as f32,
            lmax,
            clear_to: clear_runs(&data, ns, nl),
            data,
        }
    }

    /// A fragment of any length: the lookup when `l` is within the table's length axis,
    /// otherwise the front-to-back composite of `n` equal pieces that are (the scalar is
    /// linear along the ray, so the pieces are exactly the fragment's parts). The table covers
    /// the tets' typical longest edge rather than the longest ([`crate::render::prepare::table_length`]),
    /// so a few slivers do not coarsen every fragment's steps.
    #[inline]
    pub fn segment(&self, sf: f32, sb: f32, l: f32) -> [f32; 4] {
        let top = (self.nl - 1) as f32;
        let x = l * self.inv_dl;
        if !(x > top) {
            return self.lookup(sf, sb, l);
        }
        self.pieces(sf, sb, l, x / top)
    }

    /// [`Self::segment`] past the length axis: `ceil(steps)` pieces (at most 2^16, so a
    /// fragment too long for any table still costs a bounded time).
    #[cold]
    #[inline(never)]
    pub(crate) fn pieces(&self, sf: f32, sb: f32, l: f32, steps: f32) -> [f32; 4] {
        let n = steps.ceil().min(65536.0);
        let (dl, ds) = (l / n, (sb - sf) / n);
        let mut acc = [0f32; 4];
        for k in 0..n as u32 {
            let a = sf + ds * k as f32;
            let c = self.lookup(a, a + ds, dl);
            let t = 1.0 - acc[3];
            for ch in 0..4 {
                acc[ch] += t * c[ch];
            }
        }
        acc
    }

    /// Whether every fragment of a tet whose vertex scalars span `[lo, hi]` is exactly zero
    /// (colour and opacity), so that drawing it would change no pixel's bits: the transfer
    /// function draws nothing over that range. Fragments take `Sf` and `Sb` clamped to
    /// `[lo, hi]`, so their lookups read only entries whose scalar bins lie from `lo`'s bin to
    /// one past `hi`'s ([`Self::locate`]'s arithmetic is monotone); one more bin on each side
    /// covers the pieces of a fragment past the length axis, whose ends can round out of the
    /// range. NaN draws something.
    #[inline]
    pub fn draws_nothing(&self, lo: f32, hi: f32) -> bool {
        if !(lo <= hi) {
            return false;
        }
        let bin = |s: f32| (self.scalar_pos(s) as usize).min(self.ns - 2);
        let (a, b) = (bin(lo).saturating_sub(1), (bin(hi) + 2).min(self.ns - 1));
        self.clear_to.get(a).is_some_and(|&to| to >= b as i32)
    }

    /// Trilinear lookup (lengths clamped to the table's axis: see [`Self::segment`]).
    #[inline(always)]
    pub fn lookup(&self, sf: f32, sb: f32, l: f32) -> [f32; 4] {
        let (base, wf, wb, wl) = self.locate(sf, sb, l);
        self.corners(base, wf, wb, wl)
    }

    /// Position of scalar `s` on the table's scalar axis, in bins, clamped to it (monotone in
    /// `s`, which [`Self::draws_nothing`] relies on).
    #[inline(always)]
    fn scalar_pos(&self, s: f32) -> f32 {
        ((s - self.s0) * self.inv_ds).clamp(0.0, (self.ns - 1) as f32)
    }

    /// The `base` of [`Self::corners`] and the weights for a lookup.
    #[inline(always)]
    fn locate(&self, sf: f32, sb: f32, l: f32) -> (usize, f32, f32, f32) {
        let (xf, xb) = (self.scalar_pos(sf), self.scalar_pos(sb));
        let xl = (l * self.inv_dl).clamp(0.0, (self.nl - 1) as f32);
        let (i, j, k) = (
            (xf as usize).min(self.ns - 2),
            (xb as usize).min(self.ns - 2),
            (xl as usize).min(self.nl - 2),
        );
        let base = (k * self.ns + j) * self.ns + i;
        (base, xf - i as f32, xb - j as f32, xl - k as f32)
    }

    /// Trilinear blend of the eight entries from `base` (`(il * ns + ib) * ns + if_` with
    /// `il <= nl - 2`, `ib, if_ <= ns - 2`) with weights along (Sf, Sb, l): along Sb, then l,
    /// then Sf, so that the two entries side by side in memory (`if_` and `if_ + 1`) are
    /// blended together last (the explicit-SIMD lookup holds them in one register).
    #[inline(always)]
    pub fn corners(&self, base: usize, tf: f32, tb: f32, tl: f32) -> [f32; 4] {
        let ns = self.ns;
        // One bounds check for the eight corners (indices 0 to ns * ns + ns + 1 of `d`).
        let d = &self.data[base..base + ns * ns + ns + 2];
        // SAFETY: every index below is at most `ns * ns + ns + 1`, inside `d`.
        let at = |k: usize| unsafe { *d.get_unchecked(k) };
        let o1 = ns * ns;
        // Entry `if_ + e` blended along Sb and then l.
        let side = |e: usize| {
            lerp4(
                lerp4(at(e), at(e + ns), tb),
                lerp4(at(o1 + e), at(o1 + ns + e), tb),
                tl,
            )
        };
        lerp4(side(0), side(1), tf)
    }
}

/// [`PreintTable`]'s `clear_to` for its entries `data` (`ns x ns x nl`): the square of bins
/// `[a, b]^2` is all zero when `(a, a)` is, row `a` and column `a` are zero from `a` to `b`,
/// and `[a + 1, b]^2` is all zero, so one pass from the last bin down finds every run.
fn clear_runs(data: &[[f32; 4]], ns: usize, nl: usize) -> Vec<i32> {
    // Whether the entries at scalar bins (Sf = i, Sb = j) are zero at every length.
    let zero: Vec<bool> = (0..ns * ns)
        .into_par_iter()
        .map(|k| (0..nl).all(|il| data.get(il * ns * ns + k) == Some(&[0.0; 4])))
        .collect();
    let z = |i: usize, j: usize| zero[j * ns + i];
    let mut to = vec![0i32; ns];
    let mut next = ns as i32 - 1;
    for a in (0..ns).rev() {
        let run = |along: &dyn Fn(usize) -> bool| {
            (a..ns)
                .take_while(|&b| along(b))
                .last()
                .map_or(a as i32 - 1, |b| b as i32)
        };
        to[a] = if !z(a, a) {
            a as i32 - 1
        } else {
            let inner = if next > a as i32 { next } else { a as i32 };
            run(&|b| z(a, b)).min(run(&|b| z(b, a))).min(inner)
        };
        next = to[a];
    }
    to
}

/// Greatest common divisor.
fn gcd(mut a: usize, mut b: usize) -> usize {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// Composites of the runs of `m` consecutive pieces of `e` (`e[i..i + m]` for each `i`), in
/// ray order: `e[i]` first, or `e[i + m - 1]` first when `down`. Van Herk / Gil-Werman: in
/// blocks of `m`, each run is a block's suffix composite followed by the next block's prefix.
fn runs(e: &[Acc], m: usize, down: bool) -> Vec<Acc> {
    // `op(a, b)`: the pieces of `a` then those of `b` in index order, composited in ray order.
    let op = |a: &Acc, b: &Acc| if down { b.then(a) } else { a.then(b) };
    let n = e.len();
    let mut suf = e.to_vec();
    let mut pre = e.to_vec();
    for j in (0..n.saturating_sub(1)).rev() {
        if (j + 1) % m != 0 {
            suf[j] = op(&e[j], &suf[j + 1]);
        }
    }
    for j in 1..n {
        if j % m != 0 {
            pre[j] = op(&pre[j - 1], &e[j]);
        }
    }
    (0..(n + 1).saturating_sub(m))
        .map(|i| {
            if i % m == 0 {
                suf[i]
            } else {
                op(&suf[i], &pre[i + m - 1])
            }
        })
        .collect()
}

#[inline(always)]
fn lerp4(a: [f32; 4], b: [f32; 4], t: f32) -> [f32; 4] {
    [
        a[0] + t * (b[0] - a[0]),
        a[1] + t * (b[1] - a[1]),
        a[2] + t * (b[2] - a[2]),
        a[3] + t * (b[3] - a[3]),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::transfer::{named_colormap, OpacitySpec, TransferFunction};

    fn build(
        cmap: &str,
        opacity: &str,
        range: [f64; 2],
        unit: f64,
        nodes: usize,
    ) -> TransferFunction {
        TransferFunction::build(
            &named_colormap(cmap).unwrap(),
            Some(&OpacitySpec::parse(opacity).unwrap()),
            range,
            unit,
            nodes,
        )
        .unwrap()
    }

    fn tf() -> TransferFunction {
        build("viridis", "0:0.1,0.5:0.9,1:0.3", [0.0, 2.0], 0.5, 33)
    }

    /// Riemann sum with exact per-step attenuation (independent of the piecewise formulas).
    fn brute(tf: &TransferFunction, sf: f64, sb: f64, len: f64) -> [f64; 4] {
        let n = 200_000;
        let dt = len / n as f64;
        let (mut c, mut tr) = ([0.0; 3], 1.0);
        for i in 0..n {
            let s = sf + (sb - sf) * (i as f64 + 0.5) / n as f64;
            let (rgb, tau) = tf.eval(s);
            let a = 1.0 - (-tau * dt).exp();
            for k in 0..3 {
                c[k] += tr * a * rgb[k];
            }
            tr *= 1.0 - a;
        }
        [c[0], c[1], c[2], 1.0 - tr]
    }

    #[test]
    fn exact_matches_brute_force() {
        // Also constant opacity (constant extinction in every piece: the closed form, colour
        // still changing) and a zero-width range (node 0 below 0.5, the last node from 0.5 on).
        let flat = build("cool-to-warm", "0.4", [0.0, 1.0], 0.3, 9);
        let step = build("viridis", "0:0.1,1:0.8", [0.5, 0.5], 0.5, 5);
        let wide: &[(f64, f64, f64)] = &[
            (0.1, 1.9, 0.7),
            (1.9, 0.1, 0.7),
            (0.5, 0.5, 3.0),
            (-1.0, 0.7, 0.4),
            (2.5, 1.2, 5.0),
            (0.3, 0.31, 1e-4),
            (0.0, 2.0, 40.0),
        ];
        let unit: &[(f64, f64, f64)] = &[
            (0.1, 0.9, 0.7),
            (0.9, 0.05, 2.0),
            (-0.5, 1.5, 0.3),
            (0.2, 0.2, 0.5),
            (0.3, 0.3000001, 1e-5),
            (0.0, 1.0, 60.0),
        ];
        for (tf, cases) in [(&tf(), wide), (&flat, unit), (&step, unit)] {
            for &(sf, sb, l) in cases {
                let e = exact_segment(tf, sf, sb, l);
                let b = brute(tf, sf, sb, l);
                for k in 0..4 {
                    assert!((e[k] - b[k]).abs() < 1e-6, "{sf} {sb} {l}: {e:?} vs {b:?}");
                }
            }
        }
    }

    #[test]
    fn small_depth_exponential() {
        for i in 0..=500 {
            let x = i as f64 / 1000.0;
            let (a, b) = (exp_neg_small(x), (-x).exp());
            assert!(((a - b) / b).abs() < 1e-14, "{x}: {a} vs {b}");
            let (a, b) = (exp_neg(x), (-x).exp());
            assert!(((a - b) / b).abs() < 2e-14, "{x}: {a} vs {b}");
        }
    }

    #[test]
    fn piece_integrals_match_a_fine_sum() {
        // Against a fine midpoint sum (error ~1e-13): the series tier's corners and inside to
        // 1e-12, then across the 4-point and 8-point tiers and their corners (q of both signs)
        // to 3e-10 relative.
        let series = [
            (1.0 / 16.0, -1.0 / 256.0),
            (1.0 / 16.0 - 2.0 / 256.0, 1.0 / 256.0),
            (1e-4, -5e-5),
            (0.0, 1e-3),
            (1e-12, 1e-12),
        ];
        let beyond = [
            (0.03, -0.01),
            (0.5, -1.0 / 16.0),
            (0.5, -0.25),
            (0.01, 0.02),
            (0.05, -0.02),
            (0.2, 0.25),
            (0.4, -0.19),
            (3.0, 2.0),
            (0.0, 30.0),
        ];
        for (p, q, tol) in series
            .iter()
            .map(|&(p, q)| (p, q, 1e-12))
            .chain(beyond.iter().map(|&(p, q)| (p, q, 3e-10)))
        {
            let n = 200_000;
            let fine: f64 = (0..n)
                .map(|i| {
                    let u = (i as f64 + 0.5) / n as f64;
                    (-(p * u + q * u * u)).exp()
                })
                .sum::<f64>()
                / n as f64;
            let (tr, i) = piece_integrals(p, q, true);
            assert!((i - fine).abs() < tol * fine, "{p} {q}: {i} vs {fine}");
            let e = (-(p + q)).exp();
            assert!((tr - e).abs() < 1e-14, "{p} {q}: {tr} vs {e}");
        }
    }

    #[test]
    fn composed_table_matches_direct_integration() {
        // Every entry against integrating its segment at once: both are exact up to f64
        // rounding (and the pieces' 2e-10 quadrature), so they agree to about an f32 ulp
        // (3e-8 measured). Also deep segments (opacity near 1), a node count unrelated to the
        // grid, a range wider than the colour map's and a zero-width range.
        let cases = [
            (tf(), 33, 9, 2.0),
            (
                build("cool-to-warm", "0:0,1:1", [-1.0, 3.0], 0.05, 7),
                17,
                5,
                3.0,
            ),
            (build("inferno", "0.4", [0.0, 1.0], 0.3, 64), 20, 4, 1.5),
            (
                build("viridis", "0:0.1,1:0.8", [0.5, 0.5], 0.5, 5),
                6,
                3,
                1.0,
            ),
        ];
        for (tf, ns, nl, lmax) in cases {
            let t = PreintTable::build(&tf, ns, nl, lmax);
            let span = tf.range[1] - tf.range[0];
            let s_at = |i: usize| tf.range[0] + span * i as f64 / (ns - 1) as f64;
            let mut worst = 0f64;
            for il in 0..nl {
                let l = lmax * il as f64 / (nl - 1) as f64;
                for ib in 0..ns {
                    for i in 0..ns {
                        let x = exact_segment(&tf, s_at(i), s_at(ib), l);
                        let v = t.data[(il * ns + ib) * ns + i];
                        for k in 0..4 {
                            worst = worst.max((v[k] as f64 - x[k]).abs());
                        }
                    }
                }
            }
            assert!(worst < 2e-7, "{ns}x{nl}: worst {worst:e}");
        }
    }

    #[test]
    fn segments_past_the_length_axis_are_split_in_order() {
        let tf = tf();
        let t = PreintTable::build(&tf, 65, 33, 0.25);
        // Within the axis: the lookup itself, bit for bit.
        for (sf, sb, l) in [(0.1f32, 1.9f32, 0.0f32), (1.2, 0.3, 0.1), (0.5, 0.5, 0.25)] {
            assert_eq!(t.segment(sf, sb, l), t.lookup(sf, sb, l));
        }
        // Past it: close to the exact integral (the lookup clamps the length to 0.25 and is far
        // off), and the composite of the two halves' segments where the pieces line up.
        for (sf, sb, l) in [(0.1f32, 1.9f32, 0.9f32), (1.7, 0.2, 2.0), (1.0, 1.0, 0.6)] {
            let want = exact_segment(&tf, sf as f64, sb as f64, l as f64);
            let got = t.segment(sf, sb, l);
            let clamped = t.lookup(sf, sb, l);
            let err = |v: [f32; 4]| {
                (0..4)
                    .map(|k| (v[k] as f64 - want[k]).abs())
                    .fold(0.0, f64::max)
            };
            assert!(err(got) < 2e-3, "{sf} {sb} {l}: {got:?} vs {want:?}");
            assert!(err(clamped) > 10.0 * err(got), "{sf} {sb} {l}");
        }
        // Any length ends (at most 2^16 pieces) with a finite colour.
        let v = t.segment(0.0, 2.0, 1e30);
        assert!(v.iter().all(|x| x.is_finite()) && v[3] > 0.99, "{v:?}");
    }

    /// The lookup with checked indexing: eight corners, lerps along Sf, Sb, l.
    fn reference_lookup(t: &PreintTable, sf: f32, sb: f32, l: f32) -> [f32; 4] {
        let lerp4 = |a: [f32; 4], b: [f32; 4], w: f32| {
            [
                a[0] + w * (b[0] - a[0]),
                a[1] + w * (b[1] - a[1]),
                a[2] + w * (b[2] - a[2]),
                a[3] + w * (b[3] - a[3]),
            ]
        };
        let top = (t.ns - 1) as f32;
        let xf = ((sf - t.s0) * t.inv_ds).clamp(0.0, top);
        let xb = ((sb - t.s0) * t.inv_ds).clamp(0.0, top);
        let xl = (l * t.inv_dl).clamp(0.0, (t.nl - 1) as f32);
        let (i, j, k) = (
            (xf as usize).min(t.ns - 2),
            (xb as usize).min(t.ns - 2),
            (xl as usize).min(t.nl - 2),
        );
        let (wf, wb, wl) = (xf - i as f32, xb - j as f32, xl - k as f32);
        let ns = t.ns;
        let d = &t.data;
        let at = |k: usize, j: usize, i: usize| d[(k * ns + j) * ns + i];
        // Along Sb, then l, then Sf (the order `corners` documents).
        let side = |i: usize| {
            lerp4(
                lerp4(at(k, j, i), at(k, j + 1, i), wb),
                lerp4(at(k + 1, j, i), at(k + 1, j + 1, i), wb),
                wl,
            )
        };
        lerp4(side(i), side(i + 1), wf)
    }

    #[test]
    fn lookup_matches_checked_trilinear() {
        let tf = tf();
        for (ns, nl) in [(65, 33), (2, 2), (7, 3)] {
            let t = PreintTable::build(&tf, ns, nl, 2.0);
            // A fixed pseudo-random walk over (and beyond) the table's box, and its corners.
            let mut x = 0x2545_f491_4f6c_dd1du64;
            let mut next = || {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                (x >> 40) as f32 / (1u64 << 24) as f32
            };
            for n in 0..20_000 {
                let (sf, sb, l) = if n < 8 {
                    let e = |b: usize, v: f32| if n >> b & 1 == 1 { v } else { 0.0 };
                    (e(0, 2.0), e(1, 2.0), e(2, 2.0))
                } else {
                    (next() * 2.4 - 0.2, next() * 2.4 - 0.2, next() * 2.4 - 0.1)
                };
                let (a, b) = (t.lookup(sf, sb, l), reference_lookup(&t, sf, sb, l));
                assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits), "{sf} {sb} {l}");
            }
        }
    }

    #[test]
    fn fast_tf_steps_interpolate_as_the_nodes() {
        // The stored differences are the subtraction the interpolation did, so the same bits.
        for tf in [tf(), build("viridis", "0:0.1,1:0.8", [0.5, 0.5], 0.5, 2)] {
            let f = FastTf::new(&tf);
            for n in 0..=4000 {
                let s = n as f32 / 1000.0 - 1.0;
                let x = ((s - f.s0) * f.inv_ds).clamp(0.0, f.last);
                let i = (x as usize).min(f.nodes.len() - 2);
                let t = x - i as f32;
                let (a, b) = (f.nodes[i], f.nodes[i + 1]);
                let want: [f32; 4] = std::array::from_fn(|k| a[k] + t * (b[k] - a[k]));
                assert_eq!(f.eval(s).map(f32::to_bits), want.map(f32::to_bits), "{s}");
            }
        }
    }

    #[test]
    fn modes_agree_on_constant_scalar_and_table_close() {
        let tf = tf();
        let (a, l, e) = (
            average_segment(&tf, 0.8, 0.8, 0.3),
            linear_segment(&tf, 0.8, 0.8, 0.3),
            exact_segment(&tf, 0.8, 0.8, 0.3),
        );
        for k in 0..4 {
            assert!((a[k] - e[k]).abs() < 1e-12 && (l[k] - e[k]).abs() < 1e-12);
        }
        let t = PreintTable::build(&tf, 65, 33, 2.0);
        let v = t.lookup(0.25, 1.5, 1.0);
        let x = exact_segment(&tf, 0.25, 1.5, 1.0);
        for k in 0..4 {
            assert!((v[k] as f64 - x[k]).abs() < 0.02, "{v:?} {x:?}");
        }
        // Exact grid points are reproduced.
        let g = t.lookup(0.5, 1.0, 1.0);
        let x = exact_segment(&tf, 0.5, 1.0, 1.0);
        for k in 0..4 {
            assert!((g[k] as f64 - x[k]).abs() < 1e-6);
        }
    }

    /// A xorshift stream of floats in [0, 1) from `seed` (not 0).
    fn xorshift(seed: u64) -> impl FnMut() -> f32 {
        let mut r = seed;
        move || {
            r ^= r << 13;
            r ^= r >> 7;
            r ^= r << 17;
            (r >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    /// Fragment ends a tet with scalar range `[lo, hi]` can have (clamped to it, as the set-up
    /// does): the range both ways for `k` 0 and 1, random points in it after.
    fn ends_in(lo: f32, hi: f32, k: usize, rnd: &mut impl FnMut() -> f32) -> (f32, f32) {
        let mut pick = || (lo + (hi - lo) * rnd()).clamp(lo, hi);
        match k {
            0 => (lo, hi),
            1 => (hi, lo),
            _ => (pick(), pick()),
        }
    }

    #[test]
    fn a_range_drawn_as_nothing_gives_exact_zeros() {
        // Opacity zero up to 40 % of [0, 2] (to 0.78125 after resampling to 65 nodes), a
        // ramp after it.
        let gap = build("viridis", "0:0,0.4:0,1:1", [0.0, 2.0], 0.5, 65);
        let mut rnd = xorshift(0x9e37_79b9_7f4a_7c15);
        for (ns, nl) in [(128, 32), (33, 9), (2, 2)] {
            let t = PreintTable::build(&gap, ns, nl, 1.5);
            let lmax = t.lmax as f32;
            let mut clear = 0;
            for case in 0..20_000 {
                let lo = rnd() * 2.2 - 0.1;
                let hi = if case % 5 == 0 { lo } else { lo + rnd() * 0.4 };
                if !t.draws_nothing(lo, hi) {
                    continue;
                }
                clear += 1;
                assert!(hi <= 0.78125, "{ns}x{nl}: [{lo}, {hi}] drawn as nothing");
                // Any fragment a tet with this range can have: ends in the range (clamped to
                // it, as the set-up does), any length, past the table's axis too.
                for k in 0..40 {
                    let (sf, sb) = ends_in(lo, hi, k, &mut rnd);
                    let l = rnd() * 3.0 * lmax;
                    assert_eq!(
                        t.segment(sf, sb, l).map(f32::to_bits),
                        [0; 4],
                        "{ns}x{nl}: ({sf}, {sb}, {l}) of [{lo}, {hi}]"
                    );
                }
            }
            if ns >= 33 {
                assert!(clear > 1000, "{ns}x{nl}: {clear} ranges drawn as nothing");
                assert!(t.draws_nothing(0.1, 0.5) && t.draws_nothing(0.0, 0.0));
                assert!(!t.draws_nothing(0.5, 1.0) && !t.draws_nothing(1.5, 1.6));
            } else {
                // Two bins span the whole range, which is drawn.
                assert_eq!(clear, 0);
            }
            assert!(!t.draws_nothing(f32::NAN, 0.5) && !t.draws_nothing(0.1, f32::NAN));
            assert!(!t.draws_nothing(0.3, 0.1), "an empty range is not a tet's");
        }
        // A function that draws everywhere leaves nothing out.
        let t = PreintTable::build(&tf(), 65, 9, 1.0);
        assert!(!(0..100).any(|i| t.draws_nothing(i as f32 * 0.02, i as f32 * 0.02)));
    }

    #[test]
    fn a_range_the_node_arrays_draw_as_nothing_gives_exact_zeros() {
        // As above for the per-fragment modes: zero extinction up to node 25 of 65 (0.78125).
        let gap = build("viridis", "0:0,0.4:0,1:1", [0.0, 2.0], 0.5, 65);
        let f = FastTf::new(&gap);
        let mut rnd = xorshift(0x2545_f491_4f6c_dd1d);
        let mut clear = 0;
        for case in 0..20_000 {
            let lo = rnd() * 2.2 - 0.1;
            let hi = if case % 5 == 0 { lo } else { lo + rnd() * 0.4 };
            if !f.draws_nothing(lo, hi) {
                // The interval after the last clear one draws: nothing clear is missed.
                assert!(hi >= 0.78125 || lo > hi, "[{lo}, {hi}] drawn");
                continue;
            }
            clear += 1;
            assert!(hi < 0.78125, "[{lo}, {hi}] drawn as nothing");
            for k in 0..40 {
                let (sf, sb) = ends_in(lo, hi, k, &mut rnd);
                let l = rnd() * 10.0;
                for v in [f.average(sf, sb, l), f.linear(sf, sb, l)] {
                    assert_eq!(
                        v.map(f32::to_bits),
                        [0; 4],
                        "({sf}, {sb}, {l}) of [{lo}, {hi}]"
                    );
                }
            }
        }
        assert!(clear > 1000, "{clear} ranges drawn as nothing");
        assert!(!f.draws_nothing(f32::NAN, 0.5) && !f.draws_nothing(0.1, f32::NAN));
        assert!(!f.draws_nothing(0.3, 0.1), "an empty range is not a tet's");
        let f = FastTf::new(&tf());
        assert!(!(0..100).any(|i| f.draws_nothing(i as f32 * 0.02, i as f32 * 0.02)));
    }
}
