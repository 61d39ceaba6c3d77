//! Exact side of a triangle's plane the viewer is on: orient3d against the eye (perspective), or
//! the exact sign of the normal against a float view direction (orthographic, eye at infinity).

use num_bigint::BigInt;
use num_traits::Signed;

use crate::camera::Viewpoint;
use crate::geom::{orient3d, Aabb};

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

/// Faces of a tet in [`super::adjacency::face_vertices`] order: face `i` skips vertex `i`.
const FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]];

/// A bound on the rounding error of every face determinant [`tet_eye_sides`] computes for the
/// eye `e` and a mesh inside `bounds`. Each determinant equals Shewchuk's stage-A `orient3d`
/// expression bit for bit, so its error is at most (7 + 56 eps) eps times its permanent, and every
/// permanent is at most 6 |dx| |dy| |dz| with each the largest distance from the eye to the box
/// along that axis (rounding is monotone, so no rounded difference exceeds the box corners').
/// 1e-15 instead of 7.8e-16 covers the rounding of the bound itself. Infinite (decide nothing)
/// where underflow or overflow could break the error analysis.
pub fn eye_error_bound(bounds: &Aabb, e: &[f64; 3]) -> f64 {
    let m = [0, 1, 2].map(|k| {
        (bounds.min[k] - e[k])
            .abs()
            .max((bounds.max[k] - e[k]).abs())
    });
    let b = 6e-15 * m[0] * m[1] * m[2];
    if b > 1e-280 && b < 1e280 {
        b
    } else {
        f64::INFINITY
    }
}

/// Exact signs of `orient3d(face i, eye)` for the four faces of one tet, each face's vertices in
/// tet order ([`super::adjacency::face_vertices`]). The four determinants share their six 2x2
/// minors; a determinant larger than `bound` (from [`eye_error_bound`] for a box holding the
/// tet) has the sign of the exact one, and the rest go to the exact `orient3d`.
#[inline]
pub fn tet_eye_sides(p: &[[f64; 3]; 4], e: &[f64; 3], bound: f64) -> [i8; 4] {
    // Written out: `array::map` here leaves copies through the stack in the hot loop.
    let dif = |q: &[f64; 3]| [q[0] - e[0], q[1] - e[1], q[2] - e[2]];
    let d = [dif(&p[0]), dif(&p[1]), dif(&p[2]), dif(&p[3])];
    // minor(a, b) = dx_a dy_b - dx_b dy_a.
    let m = |a: usize, b: usize| d[a][0] * d[b][1] - d[b][0] * d[a][1];
    let (m01, m02, m03, m12, m13, m23) = (m(0, 1), m(0, 2), m(0, 3), m(1, 2), m(1, 3), m(2, 3));
    let z = [d[0][2], d[1][2], d[2][2], d[3][2]];
    // det[d_j; d_k; d_l] = z_j m(k, l) - z_k m(j, l) + z_l m(j, k), summed as Shewchuk does.
    let det = [
        z[1] * m23 - z[2] * m13 + z[3] * m12,
        z[0] * m23 - z[2] * m03 + z[3] * m02,
        z[0] * m13 - z[1] * m03 + z[3] * m01,
        z[0] * m12 - z[1] * m02 + z[2] * m01,
    ];
    let mut out = [0i8; 4];
    for i in 0..4 {
        out[i] = if det[i].abs() > bound {
            sign(det[i])
        } else {
            let [a, b, c] = FACES[i];
            sign(orient3d(&p[a], &p[b], &p[c], e))
        };
    }
    out
}

/// Exact [`eye_side`] of each face of a tet whose bit is set in `mask` (0 for the others), each
/// face's vertices in tet order; `bound` from [`eye_error_bound`] (unused for a direction).
#[inline]
pub fn tet_sides(view: &Viewpoint, p: &[[f64; 3]; 4], mask: u8, bound: f64) -> [i8; 4] {
    match view {
        Viewpoint::Eye(e) => tet_eye_sides(p, e, bound),
        Viewpoint::Direction(v) => std::array::from_fn(|i| {
            let [a, b, c] = FACES[i];
            if mask >> i & 1 == 1 {
                normal_dot_sign(&p[a], &p[b], &p[c], v)
            } else {
                0
            }
        }),
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

    fn bound(p: &[[f64; 3]; 4], e: &[f64; 3]) -> f64 {
        eye_error_bound(&Aabb::of_points(p.iter()), e)
    }

    fn faces_exact(p: &[[f64; 3]; 4], e: &[f64; 3]) -> [i8; 4] {
        FACES.map(|[a, b, c]| sign(orient3d(&p[a], &p[b], &p[c], e)))
    }

    #[test]
    fn tet_sides_exact_on_coplanar_and_tiny() {
        let p = [
            [0.1, 0.0, 0.0],
            [0.1, 1.0, 0.0],
            [0.1, 0.3, 0.7],
            [0.9, 0.2, 0.1],
        ];
        // The eye in the plane of face 3 (x = 0.1, not representable): exact zero there.
        for e in [
            [0.1, 5.0, -3.0],
            [0.1, 0.2, 0.3],
            [0.5, 0.5, 0.5],
            [1e-300, 0.0, 0.0],
        ] {
            assert_eq!(tet_eye_sides(&p, &e, bound(&p, &e)), faces_exact(&p, &e));
        }
        for scale in [1e-300, 1e-100, 1e100, 1e300] {
            let q = p.map(|q| q.map(|x| x * scale));
            let e = [0.3 * scale, -0.2 * scale, 0.0];
            assert_eq!(tet_eye_sides(&q, &e, bound(&q, &e)), faces_exact(&q, &e));
        }
    }

    proptest! {
        #[test]
        fn tet_sides_agree_with_orient3d(
            p in prop::array::uniform4(prop::array::uniform3(-10.0f64..10.0)),
            e in prop::array::uniform3(-20.0f64..20.0),
            t in 0.0f64..1.0,
            u in 0.0f64..1.0,
            k in 0usize..4,
        ) {
            prop_assert_eq!(tet_eye_sides(&p, &e, bound(&p, &e)), faces_exact(&p, &e));
            // A bound from a larger box (the whole mesh's) is as exact.
            let big = Aabb { min: [-1e3; 3], max: [1e3; 3] };
            prop_assert_eq!(tet_eye_sides(&p, &e, eye_error_bound(&big, &e)), faces_exact(&p, &e));
            // Nearly (or exactly) in the plane of face k: an affine combination of its vertices.
            let [a, b, c] = FACES[k];
            let w = [0, 1, 2].map(|j| p[a][j] + t * (p[b][j] - p[a][j]) + u * (p[c][j] - p[a][j]) * 3.0);
            prop_assert_eq!(tet_eye_sides(&p, &w, bound(&p, &w)), faces_exact(&p, &w));
            prop_assert_eq!(tet_eye_sides(&p, &p[a], bound(&p, &p[a])), faces_exact(&p, &p[a]));
        }

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
