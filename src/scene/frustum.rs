//! Exact test of a closed tet against the open interior of a cylinder or cone frustum: one
//! polynomial procedure run first in floats with a proven error bound ([`Fb`]), then in
//! outward-rounded intervals (inputs the bound does not cover), then, only where neither can
//! settle a sign, in exact dyadic arithmetic.
//!
//! The body with axis `a = end - start` (`L^2 = a.a`), radii `r0` at `start` and `r1` at `end`,
//! is, for `w = x - start`, `u = w.a` and `c = a x w` (so `|c| = L * distance to the axis`),
//!
//! ```text
//!   0 < u < L^2   and   L |c| < rho,   rho = r0 L^2 + (r1 - r0) u   (rho = L^2 * radius at x)
//! ```
//!
//! The closed tet T meets that open set iff T meets the open slab `0 < u < L^2` and the polytope
//! K = T ∩ {0 <= u <= L^2} meets the open cone `L|c| < rho` (from a point of K in the cone, a
//! small step towards a point of T inside the slab stays in the cone). `(c, rho)` is affine in x,
//! so K maps to the cone spanned by the vectors `y = (c, rho)` of K's vertices: the tet's vertices
//! in the slab, and the points where tet edges cross a cap plane, which `(u_j - l) y_i + (l - u_i)
//! y_j` represents up to a positive factor without a division. With `Q(y) = L^2 |c|^2 - rho^2`,
//! the cone spanned by those vectors meets the open cone iff
//! - some `Q(y_k) < 0` (a vertex of K inside), or
//! - for a pair, `Q(y_k, y_l) < 0` and `Q(y_k, y_l)^2 > Q(y_k) Q(y_l)` (the quadratic form is
//!   negative between them: in the plane across the axis, the segment or ray between two points
//!   of K comes within the radius), or
//! - `(0, 1)` (the axis itself) is a non-negative combination of three of them (the axis passes
//!   through K).
//!
//! A point of K at distance exactly the radius (tangency, a vertex on the side surface, a face
//! on a tangent plane, K touching a rim) makes no strict inequality hold: touching is not
//! overlapping, as for spheres, boxes and surfaces. Every test is a sign of a polynomial in the
//! input coordinates (no square root, no division), so the procedure is exact over [`Dyadic`].

use std::sync::atomic::{AtomicU64, Ordering};

use super::exact::{Arith, Dyadic};
use super::fb::Fb;
use super::interval::Interval;

static FALLBACKS: AtomicU64 = AtomicU64::new(0);

/// How many frustum tests so far needed exact arithmetic (the interval filter could not decide).
pub fn exact_fallbacks() -> u64 {
    FALLBACKS.load(Ordering::Relaxed)
}

/// Whether the closed tet `p` meets the open frustum (see the module doc). Radii must be
/// non-negative and not both zero, `start != end`, all finite; otherwise the body has no
/// interior and nothing meets it. A flat tet is the caller's business (it has no interior
/// either).
pub fn tet_meets_frustum(
    p: &[[f64; 3]; 4],
    start: &[f64; 3],
    end: &[f64; 3],
    r0: f64,
    r1: f64,
) -> bool {
    if !valid(p, start, end, r0, r1) {
        return false;
    }
    if let Some(hit) = fast(p, start, end, r0, r1) {
        return hit;
    }
    if let Some(hit) = decide(Interval::diff, p, start, end, r0, r1) {
        return hit;
    }
    FALLBACKS.fetch_add(1, Ordering::Relaxed);
    decide(Dyadic::diff, p, start, end, r0, r1) == Some(true)
}

/// The same decision in dyadic arithmetic only (the reference the filters must agree with).
pub fn decide_exact(p: &[[f64; 3]; 4], start: &[f64; 3], end: &[f64; 3], r0: f64, r1: f64) -> bool {
    valid(p, start, end, r0, r1) && decide(Dyadic::diff, p, start, end, r0, r1) == Some(true)
}

fn valid(p: &[[f64; 3]; 4], start: &[f64; 3], end: &[f64; 3], r0: f64, r1: f64) -> bool {
    let finite = p
        .iter()
        .chain([start, end])
        .all(|x| x.iter().all(|v| v.is_finite()));
    finite
        && r0 >= 0.0
        && r1 >= 0.0
        && r0.is_finite()
        && r1.is_finite()
        && (r0 > 0.0 || r1 > 0.0)
        && start != end
}

/// The decision in [`Fb`] floats, every leaf (a difference from `start`, a radius) scaled by
/// the power of two that brings the largest to `[1, 2)`: exact, and every test is homogeneous
/// in the leaves, so the signs are those of the unscaled problem. `None` where a sign is not
/// certain or a leaf is out of [`Fb`]'s range.
fn fast(p: &[[f64; 3]; 4], start: &[f64; 3], end: &[f64; 3], r0: f64, r1: f64) -> Option<bool> {
    let mut mx = r0.max(r1);
    for k in 0..3 {
        mx = mx.max((end[k] - start[k]).abs());
        for x in p {
            mx = mx.max((x[k] - start[k]).abs());
        }
    }
    let s = Fb::scale_for(mx)?;
    decide(|x, y| Fb::scaled_diff(x, y, s), p, start, end, r0, r1)
}

type V<N> = [N; 3];

fn dot<N: Arith>(a: &V<N>, b: &V<N>) -> N {
    a[0].mul(&b[0]).add(&a[1].mul(&b[1])).add(&a[2].mul(&b[2]))
}

fn cross<N: Arith>(a: &V<N>, b: &V<N>) -> V<N> {
    [
        a[1].mul(&b[2]).sub(&a[2].mul(&b[1])),
        a[2].mul(&b[0]).sub(&a[0].mul(&b[2])),
        a[0].mul(&b[1]).sub(&a[1].mul(&b[0])),
    ]
}

/// `(c, rho)` of a point of K, up to a positive factor.
#[derive(Clone)]
struct Gen<N> {
    c: V<N>,
    rho: N,
}

/// `s * x + t * y` for positive `s`, `t`.
fn combine<N: Arith>(s: &N, x: &Gen<N>, t: &N, y: &Gen<N>) -> Gen<N> {
    Gen {
        c: [
            s.mul(&x.c[0]).add(&t.mul(&y.c[0])),
            s.mul(&x.c[1]).add(&t.mul(&y.c[1])),
            s.mul(&x.c[2]).add(&t.mul(&y.c[2])),
        ],
        rho: s.mul(&x.rho).add(&t.mul(&y.rho)),
    }
}

/// Kleene disjunction: `Some(true)` as soon as one term is true, `Some(false)` when all are
/// known false, `None` (ask exact arithmetic) otherwise.
#[derive(Default)]
struct Any {
    unknown: bool,
}

impl Any {
    /// Records a term; true when it settles the disjunction.
    fn term(&mut self, t: Option<bool>) -> bool {
        match t {
            Some(true) => true,
            Some(false) => false,
            None => {
                self.unknown = true;
                false
            }
        }
    }
}

const EDGES: [[usize; 2]; 6] = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]];

/// The procedure of the module doc over `N`, whose leaves `leaf(x, y)` stand for `x - y` (a
/// radius is `leaf(r, 0)`); `None` only where a sign is unknown in `N`.
fn decide<N: Arith>(
    leaf: impl Fn(f64, f64) -> N,
    p: &[[f64; 3]; 4],
    start: &[f64; 3],
    end: &[f64; 3],
    r0: f64,
    r1: f64,
) -> Option<bool> {
    // Arrays are spelled out: `map` and `from_fn` are not inlined here, and this is hot.
    let diff = |x: &[f64; 3]| {
        [
            leaf(x[0], start[0]),
            leaf(x[1], start[1]),
            leaf(x[2], start[2]),
        ]
    };
    let a: V<N> = diff(end);
    let l2 = dot(&a, &a);
    let rho0 = leaf(r0, 0.0).mul(&l2);
    let dr = leaf(r1, r0);
    let w: [V<N>; 4] = [diff(&p[0]), diff(&p[1]), diff(&p[2]), diff(&p[3])];
    // Axial positions against the cap planes u = 0 and u = L^2.
    let axial = |w: &V<N>| {
        let ui = dot(w, &a);
        let far = ui.sub(&l2);
        [ui, far]
    };
    let u: [[N; 2]; 4] = [axial(&w[0]), axial(&w[1]), axial(&w[2]), axial(&w[3])];
    let gen = |i: usize| Gen {
        c: cross(&a, &w[i]),
        rho: rho0.add(&dr.mul(&u[i][0])),
    };
    // Q(x, y) = L^2 x.c y.c - x.rho y.rho.
    let q = |x: &Gen<N>, y: &Gen<N>| l2.mul(&dot(&x.c, &y.c)).sub(&x.rho.mul(&y.rho));
    // A vertex strictly inside settles most tets at once (it is in the open slab too).
    let mut all: [Option<(Gen<N>, N)>; 4] = Default::default();
    for i in 0..4 {
        if u[i][0].sign() == Some(1) && u[i][1].sign() == Some(-1) {
            let g = gen(i);
            let qi = q(&g, &g);
            if qi.sign() == Some(-1) {
                return Some(true);
            }
            all[i] = Some((g, qi));
        }
    }
    let mut side = [[0i32; 2]; 4];
    for i in 0..4 {
        side[i] = [u[i][0].sign()?, u[i][1].sign()?];
    }
    if side.iter().all(|s| s[0] <= 0) || side.iter().all(|s| s[1] >= 0) {
        return Some(false);
    }
    let known = |i: usize| match &all[i] {
        Some((g, _)) => g.clone(),
        None => gen(i),
    };
    let full: [Gen<N>; 4] = [known(0), known(1), known(2), known(3)];
    let mut any = Any::default();
    let mut gens: Vec<Gen<N>> = Vec::with_capacity(12);
    let mut qd: Vec<N> = Vec::with_capacity(12);
    // The other vertices in the closed slab.
    for i in 0..4 {
        if side[i][0] >= 0 && side[i][1] <= 0 {
            let qi = match all[i].take() {
                Some((_, qi)) => qi,
                None => q(&full[i], &full[i]),
            };
            if any.term(qi.sign().map(|s| s < 0)) {
                return Some(true);
            }
            gens.push(full[i].clone());
            qd.push(qi);
        }
    }
    // Edges crossing a cap plane strictly.
    for [i, j] in EDGES {
        for level in 0..2 {
            let (si, sj) = (side[i][level], side[j][level]);
            if si * sj >= 0 {
                continue;
            }
            // |u_j - l| y_i + |u_i - l| y_j.
            let abs = |x: &N, s: i32| if s > 0 { x.clone() } else { x.neg() };
            let g = combine(
                &abs(&u[j][level], sj),
                &full[i],
                &abs(&u[i][level], si),
                &full[j],
            );
            let qg = q(&g, &g);
            if any.term(qg.sign().map(|s| s < 0)) {
                return Some(true);
            }
            gens.push(g);
            qd.push(qg);
        }
    }
    let m = gens.len();
    // `facing[j]`: Q(y_j, y_l) >= 0 for every l, known.
    let mut facing: Vec<bool> = qd.iter().map(|x| x.sign() == Some(1)).collect();
    for k in 0..m {
        for l in k + 1..m {
            let qkl = q(&gens[k], &gens[l]);
            let sk = qkl.sign();
            if sk.is_none_or(|s| s < 0) {
                facing[k] = false;
                facing[l] = false;
            }
            let t = match sk {
                Some(s) if s >= 0 => Some(false),
                s => {
                    let disc = qkl.mul(&qkl).sub(&qd[k].mul(&qd[l])).sign();
                    match (s, disc) {
                        (_, Some(d)) if d <= 0 => Some(false),
                        (Some(_), Some(_)) => Some(true),
                        _ => None,
                    }
                }
            };
            if any.term(t) {
                return Some(true);
            }
        }
    }
    // No vertex and no pair meets the cone. If some c_j != 0 (Q(y_j) > 0) has c_j . c_l >= 0
    // for every l (which Q(y_j, y_l) >= 0 implies, rho being >= 0), the axis could only lie in
    // K on the line through it across c_j, i.e. in the cone of two vectors, which the pairs
    // ruled out: no triple is needed (this also spares exact arithmetic the exact zeros of
    // triples collinear across the axis, common in meshes aligned with a body).
    if !any.unknown && facing.iter().any(|&f| f) {
        return Some(false);
    }
    // The axis inside K: (0, 1) = x_i y_i + x_j y_j + x_k y_k with x >= 0, by Cramer's rule.
    // `cr` is `a . (c_k x c_l)`: L times the 2-D cross product across the axis.
    if m >= 3 {
        let mut cr = vec![None; m * m];
        let mut crs = |k: usize, l: usize| -> N {
            cr[k * m + l]
                .get_or_insert_with(|| dot(&a, &cross(&gens[k].c, &gens[l].c)))
                .clone()
        };
        for i in 0..m {
            for j in i + 1..m {
                for k in j + 1..m {
                    let (cjk, cik, cij) = (crs(j, k), crs(i, k), crs(i, j));
                    let det = gens[i]
                        .rho
                        .mul(&cjk)
                        .sub(&gens[j].rho.mul(&cik))
                        .add(&gens[k].rho.mul(&cij));
                    let nums = [cjk.sign(), cik.neg().sign(), cij.sign()];
                    let t = match det.sign() {
                        Some(0) => Some(false),
                        Some(d) => {
                            if nums.iter().any(|n| n.is_some_and(|n| n * d < 0)) {
                                Some(false)
                            } else if nums.iter().all(Option::is_some) {
                                Some(true)
                            } else {
                                None
                            }
                        }
                        // Two coefficients of strictly opposite signs fail for either sign.
                        None => {
                            let pos = nums.contains(&Some(1));
                            let neg = nums.contains(&Some(-1));
                            if pos && neg {
                                Some(false)
                            } else {
                                None
                            }
                        }
                    };
                    if any.term(t) {
                        return Some(true);
                    }
                }
            }
        }
    }
    if any.unknown {
        None
    } else {
        Some(false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{cross as fcross, dot as fdot};

    /// An orthogonal frame with integer entries, every vector of length 7: the axis direction
    /// and two directions across it, so points on the side surface are exact.
    const AX: [f64; 3] = [2.0, 3.0, 6.0];
    const N: [f64; 3] = [3.0, -6.0, 2.0];
    const T: [f64; 3] = [6.0, 2.0, -3.0];

    /// `o + sum s_i v_i`.
    fn at(o: &[f64; 3], terms: &[(f64, [f64; 3])]) -> [f64; 3] {
        let mut x = *o;
        for (s, v) in terms {
            for k in 0..3 {
                x[k] += s * v[k];
            }
        }
        x
    }

    /// Each stage that decides must agree with exact arithmetic.
    pub(super) fn stages_agree(p: &[[f64; 3]; 4], s: &[f64; 3], e: &[f64; 3], r0: f64, r1: f64) {
        let exact = decide_exact(p, s, e, r0, r1);
        let f = fast(p, s, e, r0, r1);
        let i = decide(Interval::diff, p, s, e, r0, r1);
        for (name, got) in [("floats", f), ("intervals", i)] {
            assert!(
                got.is_none_or(|g| g == exact),
                "{name} decided {got:?}, exact {exact}: {p:?} {s:?} {e:?} {r0} {r1}"
            );
        }
    }

    /// The filtered test, checked against exact arithmetic alone.
    fn both(p: &[[f64; 3]; 4], s: &[f64; 3], e: &[f64; 3], r0: f64, r1: f64) -> bool {
        stages_agree(p, s, e, r0, r1);
        let f = tet_meets_frustum(p, s, e, r0, r1);
        assert_eq!(
            f,
            decide_exact(p, s, e, r0, r1),
            "filter and exact differ on {p:?} {s:?} {e:?} {r0} {r1}"
        );
        f
    }

    /// A body along `a = 2 AX` (length 14) from `o + (1, 2, 3)` with radii `7 q0`, `7 q1`: on
    /// it, `side(s)` is the point at axial fraction `s` on the side surface in direction `N`.
    struct Body {
        start: [f64; 3],
        end: [f64; 3],
        a: [f64; 3],
        q0: f64,
        q1: f64,
    }

    impl Body {
        fn new(o: f64, q0: f64, q1: f64) -> Body {
            let start = [o + 1.0, o + 2.0, o + 3.0];
            let a = AX.map(|x| 2.0 * x);
            Body {
                start,
                end: at(&start, &[(1.0, a)]),
                a,
                q0,
                q1,
            }
        }
        fn meets(&self, p: &[[f64; 3]; 4]) -> bool {
            assert_ne!(crate::geom::orient3d(&p[0], &p[1], &p[2], &p[3]), 0.0);
            both(p, &self.start, &self.end, 7.0 * self.q0, 7.0 * self.q1)
        }
        fn side(&self, s: f64) -> [f64; 3] {
            at(
                &self.start,
                &[(s, self.a), (self.q0 + (self.q1 - self.q0) * s, N)],
            )
        }
        /// A generator of the side surface (from rim to rim along `N`).
        fn g(&self) -> [f64; 3] {
            at(&self.a, &[(self.q1 - self.q0, N)])
        }
        /// Outward normal of the tangent plane along the generator in direction `N`.
        fn out(&self) -> [f64; 3] {
            let n = fcross(&self.g(), &T);
            if fdot(&n, &N) > 0.0 {
                n
            } else {
                n.map(|x| -x)
            }
        }
    }

    const TINY: f64 = 1.0 / 1048576.0; // 2^-20: exact next to 1e7

    fn bodies(o: f64) -> Vec<Body> {
        vec![
            Body::new(o, 0.5, 0.5),  // cylinder of radius 3.5
            Body::new(o, 1.0, 0.25), // narrowing cone frustum
            Body::new(o, 0.25, 1.0), // widening
            Body::new(o, 1.0, 0.0),  // cone, apex at the end
            Body::new(o, 0.0, 0.75), // cone, apex at the start
        ]
    }

    #[test]
    fn vertex_on_the_side_surface_only_touches() {
        for o in [0.0, 1e7, 8_388_608.25] {
            for b in bodies(o) {
                for s in [0.5, 0.25, 0.75] {
                    let x = b.side(s);
                    let (n, g) = (b.out(), b.g());
                    let rest = [
                        at(&x, &[(1.0, n), (1.0, T)]),
                        at(&x, &[(1.0, n), (-1.0, T), (0.25, g)]),
                        at(&x, &[(2.0, n), (-0.25, g)]),
                    ];
                    let tet = [x, rest[0], rest[1], rest[2]];
                    assert!(!b.meets(&tet), "o {o} q {} {} s {s}", b.q0, b.q1);
                    // The vertex a hair inside.
                    let inside = [at(&x, &[(-TINY, N)]), rest[0], rest[1], rest[2]];
                    assert!(b.meets(&inside), "o {o} q {} {} s {s}", b.q0, b.q1);
                    // A hair outside (along the outward normal).
                    let outside = [at(&x, &[(TINY, n)]), rest[0], rest[1], rest[2]];
                    assert!(!b.meets(&outside));
                }
            }
        }
    }

    #[test]
    fn face_on_a_tangent_plane_only_touches() {
        for o in [0.0, 1e7, 8_388_608.25] {
            for b in bodies(o) {
                let x = b.side(0.25);
                let (n, g) = (b.out(), b.g());
                let face = [x, at(&x, &[(0.5, g)]), at(&x, &[(0.5, T)])];
                let tet = |v: [f64; 3]| [face[0], face[1], face[2], v];
                // Touching along the generator segment from s = 0.25 to 0.75.
                assert!(!b.meets(&tet(at(&x, &[(0.5, n)]))));
                assert!(!b.meets(&tet(at(&x, &[(0.5, n), (-3.0, T), (0.1, g)]))));
                // The fourth vertex on the inner side: the tet enters the body.
                assert!(b.meets(&tet(at(&x, &[(-0.5, n)]))));
                // The whole face a hair outside.
                let lift = face.map(|v| at(&v, &[(TINY, n)]));
                assert!(!b.meets(&[lift[0], lift[1], lift[2], at(&x, &[(0.5, n)])]));
            }
        }
    }

    #[test]
    fn vertex_on_a_cap_plane_only_touches() {
        for o in [0.0, 1e7, 8_388_608.25] {
            for b in bodies(o) {
                let a = b.a;
                // Inside the start disc (radius 7 q0), the rest below it (u < 0).
                if b.q0 > 0.0 {
                    let x = at(&b.start, &[(0.5 * b.q0, N), (0.25 * b.q0, T)]);
                    let rest = [
                        at(&x, &[(-0.25, a)]),
                        at(&x, &[(-0.25, a), (1.0, T)]),
                        at(&x, &[(-0.5, a), (1.0, N)]),
                    ];
                    assert!(!b.meets(&[x, rest[0], rest[1], rest[2]]));
                    assert!(b.meets(&[x, at(&x, &[(TINY, a), (1.0, N)]), rest[1], rest[2]]));
                    // A whole face on the cap plane, the tet outside the slab.
                    let f = [x, at(&x, &[(0.0625, N)]), at(&x, &[(0.0625, T)])];
                    assert!(!b.meets(&[f[0], f[1], f[2], rest[0]]));
                    assert!(b.meets(&[f[0], f[1], f[2], at(&x, &[(0.25, a)])]));
                }
                if b.q1 > 0.0 {
                    let x = at(&b.end, &[(-0.5 * b.q1, T)]);
                    let rest = [
                        at(&x, &[(0.25, a)]),
                        at(&x, &[(0.25, a), (1.0, T)]),
                        at(&x, &[(0.5, a), (1.0, N)]),
                    ];
                    assert!(!b.meets(&[x, rest[0], rest[1], rest[2]]));
                    assert!(b.meets(&[x, at(&x, &[(-TINY, a), (1.0, N)]), rest[1], rest[2]]));
                }
            }
        }
    }

    #[test]
    fn tets_straddling_a_rim() {
        for o in [0.0, 1e7, 8_388_608.25] {
            for b in bodies(o) {
                let a = b.a;
                let n = b.out();
                for (s, q) in [(0.0, b.q0), (1.0, b.q1)] {
                    if q == 0.0 {
                        continue;
                    }
                    let r = b.side(s);
                    // Outside the side's tangent plane on both sides of the cap plane: only the
                    // rim point touches.
                    let rest = [
                        at(&r, &[(-0.25, a), (0.5, n)]),
                        at(&r, &[(0.25, a), (1.0, n)]),
                        at(&r, &[(1.0, T), (0.5, n)]),
                    ];
                    assert!(!b.meets(&[r, rest[0], rest[1], rest[2]]), "s {s}");
                    // The rim point pulled a hair inward along the axis and towards it.
                    let d = if s == 0.0 { TINY } else { -TINY };
                    let pulled = at(&r, &[(d, a), (-2.0 * TINY, N)]);
                    assert!(b.meets(&[pulled, rest[0], rest[1], rest[2]]), "s {s}");
                    // Beyond the cap and outside the radius: within the cap plane only the rim
                    // point is shared.
                    let out = if s == 0.0 { -0.25 } else { 0.25 };
                    let tet = [
                        r,
                        at(&r, &[(out, a)]),
                        at(&r, &[(0.5, N)]),
                        at(&r, &[(0.5, T), (out, a)]),
                    ];
                    assert!(!b.meets(&tet), "s {s}");
                }
            }
        }
    }

    #[test]
    fn axis_through_a_tet_with_every_vertex_outside() {
        for o in [0.0, 1e7, 8_388_608.25] {
            for b in bodies(o) {
                let m = at(&b.start, &[(0.5, b.a)]);
                let tri = [
                    at(&m, &[(3.0, N)]),
                    at(&m, &[(-3.0, N), (3.0, T)]),
                    at(&m, &[(-3.0, N), (-3.0, T)]),
                ];
                let top = at(&m, &[(0.125, b.a), (3.0, N), (3.0, T)]);
                assert!(b.meets(&[tri[0], tri[1], tri[2], top]));
                // Moved sideways so the axis runs well outside the tet.
                let far = [tri[0], tri[1], tri[2], top].map(|v| at(&v, &[(6.0, N)]));
                assert!(!b.meets(&far));
            }
        }
    }

    #[test]
    fn cone_apex() {
        for o in [0.0, 1e7, 8_388_608.25] {
            let b = Body::new(o, 1.0, 0.0);
            let e = b.end;
            let (n, g) = (b.out(), b.g());
            // A vertex at the apex, the rest strictly outside a tangent plane through it.
            let tet = [
                e,
                at(&e, &[(1.0, n)]),
                at(&e, &[(1.0, n), (1.0, T)]),
                at(&e, &[(0.5, n), (-0.5, g)]),
            ];
            assert!(!b.meets(&tet));
            // A face through the apex on that tangent plane.
            let face = [
                e,
                at(&e, &[(-0.5, g)]),
                at(&e, &[(1.0, T)]),
                at(&e, &[(1.0, n)]),
            ];
            assert!(!b.meets(&face));
            // The apex vertex and one vertex on the axis inside the cone.
            let inner = [e, at(&e, &[(-0.25, b.a)]), tet[1], tet[2]];
            assert!(b.meets(&inner));
            // Beyond the apex (outside the slab): nothing.
            let beyond = [
                e,
                at(&e, &[(0.25, b.a)]),
                at(&e, &[(0.25, b.a), (1.0, T)]),
                tet[1],
            ];
            assert!(!b.meets(&beyond));
        }
    }

    /// The float code this replaced pulled a cone's apex end in by 1e-9 of the axis length (so a
    /// tet within that of the apex was never marked) and compared rounded distances (a tangent
    /// tet away from the origin came out either way).
    #[test]
    fn old_float_failures() {
        let (s, e) = ([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
        let h = 1.0 / (1u64 << 40) as f64;
        let near_apex = [
            [0.0, 0.0, 1.0 - h],
            [h, 0.0, 1.0 + h],
            [0.0, h, 1.0 + h],
            [0.0, 0.0, 1.0 + 2.0 * h],
        ];
        assert!(both(&near_apex, &s, &e, 1.0, 0.0));
        // Cases of the tests above that it got wrong (all touching only, where it answered
        // true): a face on a tangent plane of a cylinder, a vertex on a cone's side.
        let (s, e) = ([1.0, 2.0, 3.0], [5.0, 8.0, 15.0]);
        let face = [
            [3.5, 0.5, 7.0],
            [5.5, 3.5, 13.0],
            [6.5, 1.5, 5.5],
            [24.5, -41.5, 21.0],
        ];
        assert!(!both(&face, &s, &e, 3.5, 3.5));
        let vertex = [
            [4.875, 1.25, 10.25],
            [63.375, -65.0, 66.75],
            [51.8125, -66.375, 75.375],
            [109.4375, -137.875, 126.625],
        ];
        assert!(!both(&vertex, &s, &e, 7.0, 1.75));
        let o = 1e7;
        let moved = vertex.map(|v| v.map(|x| x + o));
        assert!(!both(
            &moved,
            &s.map(|x| x + o),
            &e.map(|x| x + o),
            7.0,
            1.75
        ));
    }
}

#[cfg(test)]
mod proptests {
    use super::*;
    use crate::geom::{dot, sub};
    use proptest::prelude::*;

    /// How far inside the open frustum `x` is (positive inside, zero on the surface), and a
    /// Lipschitz constant of that function: `min(s L, (1 - s) L, r(s) - distance to the axis)`.
    fn depth(x: &[f64; 3], start: &[f64; 3], end: &[f64; 3], r0: f64, r1: f64) -> f64 {
        let a = sub(end, start);
        let l2 = dot(&a, &a);
        let s = dot(&sub(x, start), &a) / l2;
        let foot = [0, 1, 2].map(|k| start[k] + s * a[k]);
        let v = sub(x, &foot);
        let l = l2.sqrt();
        (s * l)
            .min((1.0 - s) * l)
            .min(r0 + (r1 - r0) * s - dot(&v, &v).sqrt())
    }

    /// The independent reference: branch and bound over a subdivision of the tet into eighths.
    /// A sampled point deeper than `eps` proves an overlap; a cell whose vertices are all deeper
    /// outside than the Lipschitz bound over its diameter is pruned. `None` when the budget ran
    /// out (a tie or a near-tie, which the constructed tests cover).
    fn reference(
        p: &[[f64; 3]; 4],
        start: &[f64; 3],
        end: &[f64; 3],
        r0: f64,
        r1: f64,
    ) -> Option<bool> {
        let a = sub(end, start);
        let lip = 1.0 + (r1 - r0).abs() / dot(&a, &a).sqrt();
        let eps = 1e-10;
        let mid = |x: &[f64; 3], y: &[f64; 3]| [0, 1, 2].map(|k| 0.5 * (x[k] + y[k]));
        let mut stack = vec![*p];
        let mut budget = 40_000;
        while let Some(c) = stack.pop() {
            budget -= 1;
            if budget == 0 {
                return None;
            }
            let d = c.map(|x| depth(&x, start, end, r0, r1));
            let centre = [0, 1, 2].map(|k| 0.25 * (c[0][k] + c[1][k] + c[2][k] + c[3][k]));
            if d.iter().any(|&v| v > eps) || depth(&centre, start, end, r0, r1) > eps {
                return Some(true);
            }
            let diam = (0..4)
                .flat_map(|i| (0..4).map(move |j| (i, j)))
                .map(|(i, j)| dot(&sub(&c[i], &c[j]), &sub(&c[i], &c[j])).sqrt())
                .fold(0.0, f64::max);
            let lowest = d.iter().copied().fold(f64::INFINITY, f64::min);
            if lowest + lip * diam < -eps {
                continue;
            }
            let m = |i: usize, j: usize| mid(&c[i], &c[j]);
            let (m01, m02, m03, m12, m13, m23) =
                (m(0, 1), m(0, 2), m(0, 3), m(1, 2), m(1, 3), m(2, 3));
            stack.extend([
                [c[0], m01, m02, m03],
                [m01, c[1], m12, m13],
                [m02, m12, c[2], m23],
                [m03, m13, m23, c[3]],
                [m02, m13, m01, m12],
                [m02, m13, m12, m23],
                [m02, m13, m23, m03],
                [m02, m13, m03, m01],
            ]);
        }
        Some(false)
    }

    /// Coordinates on a 2^-28 grid, so adding 2^23 is exact and the geometry moves unchanged.
    fn snap(x: f64) -> f64 {
        (x * 268_435_456.0).round() / 268_435_456.0
    }

    fn pt(range: f64) -> impl Strategy<Value = [f64; 3]> {
        prop::array::uniform3((-range..range).prop_map(snap))
    }

    fn radius() -> impl Strategy<Value = f64> {
        prop_oneof![1 => Just(0.0), 4 => (0.0f64..0.9).prop_map(snap)]
    }

    const OFFSET: f64 = 8_388_608.0;

    fn flat(p: &[[f64; 3]; 4]) -> bool {
        super::super::exact::orient(&p[0], &p[1], &p[2], &p[3]) == 0
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 300, max_global_rejects: 4000, ..ProptestConfig::default() })]

        /// Random tets against random cylinders and cones with arbitrary axes: the filtered
        /// test, exact arithmetic alone, the same case moved by 2^23, and the sampling reference
        /// (where it decides) all agree.
        #[test]
        fn agrees_with_sampling(
            a in pt(1.0), b in pt(1.0), c in pt(1.0), d in pt(1.0),
            s in pt(1.0), e in pt(1.0), r0 in radius(), r1 in radius(), cyl in any::<bool>(),
        ) {
            let p = [a, b, c, d];
            let r1 = if cyl { r0 } else { r1 };
            prop_assume!(!flat(&p) && (r0 > 0.0 || r1 > 0.0));
            let ax = sub(&e, &s);
            prop_assume!(dot(&ax, &ax) > 0.01);
            let got = tet_meets_frustum(&p, &s, &e, r0, r1);
            prop_assert_eq!(got, decide_exact(&p, &s, &e, r0, r1));
            super::tests::stages_agree(&p, &s, &e, r0, r1);
            let mv = |x: &[f64; 3]| x.map(|v| v + OFFSET);
            prop_assert_eq!(got, tet_meets_frustum(&p.map(|x| mv(&x)), &mv(&s), &mv(&e), r0, r1));
            let want = reference(&p, &s, &e, r0, r1);
            prop_assume!(want.is_some());
            prop_assert_eq!(Some(got), want, "tet {:?} body {:?} {:?} {} {}", p, s, e, r0, r1);
        }

        /// Inputs on a coarse grid hit exact ties (vertices on cap planes and side surfaces, edges
        /// through rims) often: the interval filter either decides them as exact arithmetic does
        /// or hands them over.
        #[test]
        fn ties_on_a_grid(
            p in prop::array::uniform4(prop::array::uniform3((-8i32..8).prop_map(|v| v as f64 / 4.0))),
            s in prop::array::uniform3((-8i32..8).prop_map(|v| v as f64 / 4.0)),
            e in prop::array::uniform3((-8i32..8).prop_map(|v| v as f64 / 4.0)),
            r0 in (0i32..8).prop_map(|v| v as f64 / 4.0),
            r1 in (0i32..8).prop_map(|v| v as f64 / 4.0),
        ) {
            prop_assume!(!flat(&p) && s != e && (r0 > 0.0 || r1 > 0.0));
            let got = tet_meets_frustum(&p, &s, &e, r0, r1);
            prop_assert_eq!(got, decide_exact(&p, &s, &e, r0, r1));
            super::tests::stages_agree(&p, &s, &e, r0, r1);
            if let Some(want) = reference(&p, &s, &e, r0, r1) {
                prop_assert_eq!(got, want, "tet {:?} body {:?} {:?} {} {}", p, s, e, r0, r1);
            }
        }
    }
}
