//! Exact side of a triangle's plane the viewer is on: orient3d against the eye (perspective), or
//! the exact sign of the normal against a float view direction (orthographic, eye at infinity).

use num_bigint::BigInt;
use num_traits::Signed;

use crate::camera::Viewpoint;
use crate::geom::orient3d;

/// Sign (-1, 0, 1) of `orient3d(a, b, c, eye)`; for a view direction `v`, the sign it tends to
/// as the eye goes to infinity against `v`, which is the sign of `((b - a) x (c - a)) . v`.
/// Both are exact: zero means the plane contains the eye (or is parallel to the direction).
#[inline]
pub fn eye_side(view: &Viewpoint, a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> i8 {
    match view {
        Viewpoint::Eye(e) => sign(orient3d(a, b, c, e)),
        Viewpoint::Direction(v) => normal_dot_sign(a, b, c, v),
    }
}

#[inline]
fn sign(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// Exact sign of `det[b - a, c - a, v]`: a floating-point filter with a static error bound, and
/// exact big-integer arithmetic when the filter cannot decide.
pub fn normal_dot_sign(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], v: &[f64; 3]) -> i8 {
    let ba = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let ca = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let n = [
        ba[1] * ca[2] - ba[2] * ca[1],
        ba[2] * ca[0] - ba[0] * ca[2],
        ba[0] * ca[1] - ba[1] * ca[0],
    ];
    let det = n[0] * v[0] + n[1] * v[1] + n[2] * v[2];
    let perm = ((ba[1] * ca[2]).abs() + (ba[2] * ca[1]).abs()) * v[0].abs()
        + ((ba[2] * ca[0]).abs() + (ba[0] * ca[2]).abs()) * v[1].abs()
        + ((ba[0] * ca[1]).abs() + (ba[1] * ca[0]).abs()) * v[2].abs();
    // The rounded differences carry relative error eps each; products and sums a few more. 1e-14
    // (about 45 eps) is a generous bound; below it, and for anything non-finite, decide exactly.
    let bound = 1e-14 * perm;
    if det.is_finite() && perm.is_finite() && det.abs() > bound && perm > 1e-290 {
        return sign(det);
    }
    exact_sign(a, b, c, v)
}

/// `x = m * 2^e` with integer `m`.
pub(super) fn decompose(x: f64) -> (i64, i32) {
    if x == 0.0 {
        return (0, 0);
    }
    let bits = x.to_bits();
    let exp = ((bits >> 52) & 0x7ff) as i32;
    let frac = (bits & ((1u64 << 52) - 1)) as i64;
    let (m, e) = if exp == 0 {
        (frac, -1074)
    } else {
        (frac | (1i64 << 52), exp - 1075)
    };
    (if x < 0.0 { -m } else { m }, e)
}

fn exact_sign(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], v: &[f64; 3]) -> i8 {
    let all = [a, b, c];
    // Positions share one scale; the direction has its own (the determinant is linear in it).
    let emin = all
        .iter()
        .flat_map(|p| p.iter())
        .filter(|x| **x != 0.0)
        .map(|&x| decompose(x).1)
        .min()
        .unwrap_or(0);
    let vmin = v
        .iter()
        .filter(|x| **x != 0.0)
        .map(|&x| decompose(x).1)
        .min()
        .unwrap_or(0);
    let big = |x: f64, e0: i32| -> BigInt {
        let (m, e) = decompose(x);
        BigInt::from(m) << ((e - e0).max(0) as usize)
    };
    let p: Vec<[BigInt; 3]> = all.iter().map(|p| p.map(|x| big(x, emin))).collect();
    let w = v.map(|x| big(x, vmin));
    let ba: [BigInt; 3] = std::array::from_fn(|k| &p[1][k] - &p[0][k]);
    let ca: [BigInt; 3] = std::array::from_fn(|k| &p[2][k] - &p[0][k]);
    let n0 = &ba[1] * &ca[2] - &ba[2] * &ca[1];
    let n1 = &ba[2] * &ca[0] - &ba[0] * &ca[2];
    let n2 = &ba[0] * &ca[1] - &ba[1] * &ca[0];
    let det = n0 * &w[0] + n1 * &w[1] + n2 * &w[2];
    if det.is_positive() {
        1
    } else if det.is_negative() {
        -1
    } else {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn exact_zero_for_parallel_direction() {
        // The plane x = 0.1 (not representable exactly) against a direction within it.
        let a = [0.1, 0.0, 0.0];
        let b = [0.1, 1.0, 0.0];
        let c = [0.1, 0.3, 0.7];
        assert_eq!(normal_dot_sign(&a, &b, &c, &[0.0, 0.3, 0.1]), 0);
        assert_ne!(normal_dot_sign(&a, &b, &c, &[1e-300, 0.3, 0.1]), 0);
        assert_eq!(
            normal_dot_sign(&a, &b, &c, &[1e-300, 0.3, 0.1]),
            -normal_dot_sign(&a, &c, &b, &[1e-300, 0.3, 0.1])
        );
    }

    proptest! {
        #[test]
        fn filter_agrees_with_exact(
            a in prop::array::uniform3(-10.0f64..10.0),
            b in prop::array::uniform3(-10.0f64..10.0),
            c in prop::array::uniform3(-10.0f64..10.0),
            v in prop::array::uniform3(-1.0f64..1.0),
            t in 0.0f64..1.0,
        ) {
            prop_assert_eq!(normal_dot_sign(&a, &b, &c, &v), exact_sign(&a, &b, &c, &v));
            // Nearly degenerate: a direction almost inside the plane.
            let ba = [b[0]-a[0], b[1]-a[1], b[2]-a[2]];
            let ca = [c[0]-a[0], c[1]-a[1], c[2]-a[2]];
            let w = [0,1,2].map(|k| ba[k] * t + ca[k] * (1.0 - t));
            prop_assert_eq!(normal_dot_sign(&a, &b, &c, &w), exact_sign(&a, &b, &c, &w));
        }

        #[test]
        fn direction_is_the_limit_of_far_eyes(
            a in prop::array::uniform3(-1.0f64..1.0),
            b in prop::array::uniform3(-1.0f64..1.0),
            c in prop::array::uniform3(-1.0f64..1.0),
            v in prop::array::uniform3(-1.0f64..1.0),
        ) {
            let s = normal_dot_sign(&a, &b, &c, &v);
            prop_assume!(s != 0);
            let far = v.map(|x| -x * 1e12);
            let e = eye_side(&Viewpoint::Eye(far), &a, &b, &c);
            // Far against v the eye sees the same side, unless the plane is nearly parallel.
            let n = crate::geom::cross(&crate::geom::sub(&b, &a), &crate::geom::sub(&c, &a));
            let cosv = crate::geom::dot(&n, &v).abs() / (crate::geom::dot(&n, &n).sqrt() * crate::geom::dot(&v, &v).sqrt());
            prop_assume!(cosv > 1e-6);
            prop_assert_eq!(e, s);
        }
    }
}
