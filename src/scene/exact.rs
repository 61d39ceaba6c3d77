//! Exact signs of 3x3 determinants of point differences: a floating-point filter, then exact
//! dyadic (big integer times a power of two) arithmetic when the filter cannot decide.

use num_bigint::BigInt;
use num_traits::{Signed, Zero};

/// A dyadic rational `m * 2^e`: every finite f64 is one, and sums and products stay exact.
#[derive(Clone, Debug)]
pub struct Dyadic {
    m: BigInt,
    e: i32,
}

impl Dyadic {
    fn from_f64(x: f64) -> Dyadic {
        if x == 0.0 {
            return Dyadic {
                m: BigInt::zero(),
                e: 0,
            };
        }
        let bits = x.to_bits();
        let sign = if bits >> 63 == 1 { -1i64 } else { 1 };
        let exp = ((bits >> 52) & 0x7ff) as i32;
        let frac = (bits & ((1u64 << 52) - 1)) as i64;
        let (mant, e) = if exp == 0 {
            (frac, -1074)
        } else {
            (frac | (1i64 << 52), exp - 1075)
        };
        Dyadic {
            m: BigInt::from(sign * mant),
            e,
        }
    }

    fn align(a: &Dyadic, b: &Dyadic) -> (BigInt, BigInt, i32) {
        let e = a.e.min(b.e);
        (&a.m << (a.e - e) as usize, &b.m << (b.e - e) as usize, e)
    }

    fn sub(&self, o: &Dyadic) -> Dyadic {
        let (a, b, e) = Dyadic::align(self, o);
        Dyadic { m: a - b, e }
    }

    fn add(&self, o: &Dyadic) -> Dyadic {
        let (a, b, e) = Dyadic::align(self, o);
        Dyadic { m: a + b, e }
    }

    fn mul(&self, o: &Dyadic) -> Dyadic {
        Dyadic {
            m: &self.m * &o.m,
            e: self.e + o.e,
        }
    }

    fn sign(&self) -> i32 {
        if self.m.is_zero() {
            0
        } else if self.m.is_positive() {
            1
        } else {
            -1
        }
    }
}

/// The ring operations the generic predicates need, with a sign that may be unknown: exact
/// ([`Dyadic`], always known) or a filter ([`super::interval::Interval`], unknown when its
/// rounding bound straddles zero).
pub trait Arith: Clone {
    /// `x - y`.
    fn diff(x: f64, y: f64) -> Self;
    fn add(&self, o: &Self) -> Self;
    fn sub(&self, o: &Self) -> Self;
    fn mul(&self, o: &Self) -> Self;
    fn neg(&self) -> Self;
    fn sign(&self) -> Option<i32>;
}

impl Arith for Dyadic {
    fn diff(x: f64, y: f64) -> Dyadic {
        Dyadic::from_f64(x).sub(&Dyadic::from_f64(y))
    }
    fn add(&self, o: &Dyadic) -> Dyadic {
        Dyadic::add(self, o)
    }
    fn sub(&self, o: &Dyadic) -> Dyadic {
        Dyadic::sub(self, o)
    }
    fn mul(&self, o: &Dyadic) -> Dyadic {
        Dyadic::mul(self, o)
    }
    fn neg(&self) -> Dyadic {
        Dyadic {
            m: -&self.m,
            e: self.e,
        }
    }
    fn sign(&self) -> Option<i32> {
        Some(Dyadic::sign(self))
    }
}

/// A vector given as the difference `p - q` of two exactly represented points.
pub type Diff = ([f64; 3], [f64; 3]);

/// Exact sign (-1, 0, 1) of `det[u, v, w]` where each row is a difference of two f64 points.
pub fn det3_sign(u: Diff, v: Diff, w: Diff) -> i32 {
    let d = |x: &Diff| [0, 1, 2].map(|k| x.0[k] - x.1[k]);
    let (a, b, c) = (d(&u), d(&v), d(&w));
    let det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0]);
    let aa = a.map(f64::abs);
    let ab = b.map(f64::abs);
    let ac = c.map(f64::abs);
    let perm = aa[0] * (ab[1] * ac[2] + ab[2] * ac[1])
        + aa[1] * (ab[0] * ac[2] + ab[2] * ac[0])
        + aa[2] * (ab[0] * ac[1] + ab[1] * ac[0]);
    // Each difference is off by at most one rounding, each product by two more and the sums by
    // three: 16 units of roundoff bound the total with room to spare. Tiny or huge magnitudes
    // (underflow, overflow) skip the filter.
    let bound = 16.0 * f64::EPSILON * perm;
    if perm.is_finite() && perm > 1e-280 && det.is_finite() && det.abs() > bound {
        return if det > 0.0 { 1 } else { -1 };
    }
    det3_exact(u, v, w)
}

fn det3_exact(u: Diff, v: Diff, w: Diff) -> i32 {
    let d = |x: &Diff| [0, 1, 2].map(|k| Dyadic::from_f64(x.0[k]).sub(&Dyadic::from_f64(x.1[k])));
    let (a, b, c) = (d(&u), d(&v), d(&w));
    let m = |i: usize, j: usize| b[i].mul(&c[j]).sub(&b[j].mul(&c[i]));
    let det = a[0]
        .mul(&m(1, 2))
        .sub(&a[1].mul(&m(0, 2)))
        .add(&a[2].mul(&m(0, 1)));
    det.sign()
}

type D3 = [Dyadic; 3];

fn d3_dot(a: &D3, b: &D3) -> Dyadic {
    a[0].mul(&b[0]).add(&a[1].mul(&b[1])).add(&a[2].mul(&b[2]))
}

fn d3_sub(a: &D3, b: &D3) -> D3 {
    [0, 1, 2].map(|k| a[k].sub(&b[k]))
}

fn d3_cross(a: &D3, b: &D3) -> D3 {
    [
        a[1].mul(&b[2]).sub(&a[2].mul(&b[1])),
        a[2].mul(&b[0]).sub(&a[0].mul(&b[2])),
        a[0].mul(&b[1]).sub(&a[1].mul(&b[0])),
    ]
}

/// Exact: whether the closed tet `p` comes strictly closer to `c` than `r`, i.e. whether the
/// tet meets the open ball. The distance to a convex polytope is attained on the relative
/// interior of one of its faces (a vertex, an edge or a triangle) where the foot of the
/// perpendicular onto that face's hull lies in the face, so the minimum over those feet is the
/// distance; every comparison is of polynomials in the input coordinates (no division), in
/// exact dyadic arithmetic. A ball that only touches the tet (distance exactly `r`) does not
/// meet it. `c` inside the tet is the caller's exact test; a flat tet is not handled here.
pub fn ball_meets_tet(p: &[[f64; 3]; 4], c: &[f64; 3], r: f64) -> bool {
    let v: Vec<D3> = p
        .iter()
        .map(|x| [0, 1, 2].map(|k| Dyadic::from_f64(x[k]).sub(&Dyadic::from_f64(c[k]))))
        .collect();
    let rr = Dyadic::from_f64(r).mul(&Dyadic::from_f64(r));
    // Vertices.
    if v.iter().any(|a| d3_dot(a, a).sub(&rr).sign() < 0) {
        return true;
    }
    // Edges: with c at the origin the foot on a + t e is at t = -a.e / e.e.
    const EDGES: [[usize; 2]; 6] = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]];
    for [i, j] in EDGES {
        let (a, b) = (&v[i], &v[j]);
        let e = d3_sub(b, a);
        let ae = d3_dot(a, &e);
        let ee = d3_dot(&e, &e);
        // 0 <= -a.e <= e.e
        if ae.sign() > 0 || ae.add(&ee).sign() < 0 {
            continue;
        }
        // |a|^2 - (a.e)^2 / e.e < r^2  <=>  |a|^2 e.e - (a.e)^2 < r^2 e.e
        let lhs = d3_dot(a, a).mul(&ee).sub(&ae.mul(&ae));
        if lhs.sub(&rr.mul(&ee)).sign() < 0 {
            return true;
        }
    }
    // Triangles: the foot of the origin lies in abc when it is on the inner side of each edge.
    const FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];
    for [i, j, k] in FACES {
        let (a, b, cc) = (&v[i], &v[j], &v[k]);
        let n = d3_cross(&d3_sub(b, a), &d3_sub(cc, a));
        let zero = [a, b, cc];
        let inside = (0..3).all(|e| {
            let (s, t) = (zero[e], zero[(e + 1) % 3]);
            // n . ((t - s) x (0 - s)) >= 0
            let neg_s = [0, 1, 2].map(|q| Dyadic::from_f64(0.0).sub(&s[q]));
            d3_dot(&n, &d3_cross(&d3_sub(t, s), &neg_s)).sign() >= 0
        });
        if !inside {
            continue;
        }
        let an = d3_dot(a, &n);
        if an.mul(&an).sub(&rr.mul(&d3_dot(&n, &n))).sign() < 0 {
            return true;
        }
    }
    false
}

pub const ZERO: [f64; 3] = [0.0; 3];

/// Exact orientation of `x` against the plane through `a`, `b`, `c`: the sign of
/// `det[b - a, c - a, x - a]` (positive when `x` is on the side `(b - a) x (c - a)` points to).
pub fn orient(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], x: &[f64; 3]) -> i32 {
    // Shewchuk's adaptive predicate decides exact zeros (coplanar grid points) without the big
    // integers, but only where no product underflows or overflows; `robust` is positive on the
    // other side.
    let ok = |v: f64| v == 0.0 || (1e-60..=1e60).contains(&v.abs());
    if ![a, b, c, x].iter().all(|p| p.iter().all(|&v| ok(v)))
        || ![b, c, x].iter().all(|p| (0..3).all(|k| ok(p[k] - a[k])))
    {
        return det3_sign((*b, *a), (*c, *a), (*x, *a));
    }
    let r = crate::geom::orient3d(a, b, c, x);
    if r > 0.0 {
        -1
    } else if r < 0.0 {
        1
    } else {
        0
    }
}

/// Exact sign of the 2-D cross product `(b - a) x (c - a)` of points given by two coordinates.
pub fn orient2(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> i32 {
    let r = crate::geom::orient2d(a, b, c);
    if r > 0.0 {
        1
    } else if r < 0.0 {
        -1
    } else {
        0
    }
}

/// Whether `u x v` is exactly zero (parallel or zero vectors), `u = u.0 - u.1`, `v = v.0 - v.1`.
pub fn parallel(u: Diff, v: Diff) -> bool {
    let a = [0, 1, 2].map(|k| u.0[k] - u.1[k]);
    let b = [0, 1, 2].map(|k| v.0[k] - v.1[k]);
    let c = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    let mag = a.iter().chain(b.iter()).fold(0.0f64, |m, x| m.max(x.abs()));
    // A component clearly away from zero settles it without exact arithmetic.
    if c.iter()
        .any(|x| x.abs() > 8.0 * f64::EPSILON * mag * mag && mag * mag > 1e-280)
    {
        return false;
    }
    let axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    axes.iter().all(|ax| det3_sign(u, v, (*ax, ZERO)) == 0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_where_floats_fail() {
        // Nearly coplanar points with large offsets: the naive determinant rounds to garbage.
        let o = 1e15;
        let a = [o, o, o];
        let b = [o + 1.0, o, o];
        let c = [o, o + 1.0, o];
        let x = [o + 0.5, o + 0.5, o];
        assert_eq!(orient(&a, &b, &c, &x), 0);
        let y = [o + 0.5, o + 0.5, o + 0.125];
        assert_eq!(orient(&a, &b, &c, &y), 1);
        let z = [o + 0.5, o + 0.5, o - 0.125];
        assert_eq!(orient(&a, &b, &c, &z), -1);
        // Tiny coordinates (subnormal products) go to the exact path.
        let s = 1e-300;
        assert_eq!(
            orient(&[0.0; 3], &[s, 0.0, 0.0], &[0.0, s, 0.0], &[0.0, 0.0, s]),
            1
        );
    }

    #[test]
    fn agrees_with_robust_orient3d() {
        let pts = [
            [0.1, 0.2, 0.3],
            [1.7, -0.2, 0.9],
            [0.3, 2.2, -1.3],
            [0.5, 0.5, 0.5],
            [1.0 / 3.0, 2.0 / 3.0, 0.0],
        ];
        for a in &pts {
            for b in &pts {
                for c in &pts {
                    for x in &pts {
                        let r = crate::geom::orient3d(a, b, c, x);
                        // robust: positive when x is below the plane of counter-clockwise a, b, c.
                        let expect = if r > 0.0 {
                            -1
                        } else if r < 0.0 {
                            1
                        } else {
                            0
                        };
                        assert_eq!(orient(a, b, c, x), expect);
                        assert_eq!(det3_exact((*b, *a), (*c, *a), (*x, *a)), expect);
                    }
                }
            }
        }
    }
}
