//! Exact rational decision for one pair of boundary faces seen from the viewpoint: whether some
//! ray crosses both interiors and, if so, whether it can cross the first before the second.
//! Big-integer homogeneous arithmetic; used only where the float filters and orient3d-based
//! tests in `nonconvex` cannot decide, so its cost does not show in a sort.

use num_bigint::BigInt;
use num_traits::{Signed, Zero};

use super::side::decompose;
use crate::camera::Viewpoint;

type V3 = [BigInt; 3];

/// A point `x / w` with `w > 0`.
#[derive(Clone, Debug)]
struct Hp {
    x: V3,
    w: BigInt,
}

/// The plane `n . x + d w = 0`.
struct Plane {
    n: V3,
    d: BigInt,
}

impl Plane {
    fn through(a: &V3, b: &V3, c: &V3) -> Plane {
        let n = cross(&sub(b, a), &sub(c, a));
        let d = -dot(&n, a);
        Plane { n, d }
    }

    /// The plane through `a` and `b` parallel to `v`.
    fn along(a: &V3, b: &V3, v: &V3) -> Plane {
        let n = cross(&sub(b, a), v);
        let d = -dot(&n, a);
        Plane { n, d }
    }

    fn value(&self, p: &Hp) -> BigInt {
        dot(&self.n, &p.x) + &self.d * &p.w
    }

    fn flipped(self) -> Plane {
        Plane {
            n: self.n.map(|x| -x),
            d: -self.d,
        }
    }
}

fn sub(a: &V3, b: &V3) -> V3 {
    std::array::from_fn(|k| &a[k] - &b[k])
}

fn dot(a: &V3, b: &V3) -> BigInt {
    &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
}

fn cross(a: &V3, b: &V3) -> V3 {
    [
        &a[1] * &b[2] - &a[2] * &b[1],
        &a[2] * &b[0] - &a[0] * &b[2],
        &a[0] * &b[1] - &a[1] * &b[0],
    ]
}

/// Integers `x * 2^-e0` for floats sharing the exponent floor `e0` (exact: every finite float is
/// an integer multiple of `2^e` for its own `e >= e0`).
fn ints(values: &[[f64; 3]]) -> Vec<V3> {
    let e0 = values
        .iter()
        .flat_map(|p| p.iter())
        .filter(|x| **x != 0.0)
        .map(|&x| decompose(x).1)
        .min()
        .unwrap_or(0);
    values
        .iter()
        .map(|p| {
            p.map(|x| {
                let (m, e) = decompose(x);
                BigInt::from(m) << ((e - e0).max(0) as usize)
            })
        })
        .collect()
}

/// What the rays from the viewpoint see of exit face `f` and entry face `g` (triangles, any
/// orientation; neither may contain the eye in its plane, or be parallel to the view direction).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PairRelation {
    /// Some ray crosses the relative interiors of both.
    pub overlap: bool,
    /// On some such ray `f` is crossed strictly before `g`, or at the same point (the faces
    /// lie in one plane and touch there: the tet behind `f` ends where the tet behind `g`
    /// begins). Both can hold for opposite pairs only when the triangles cross each other.
    pub f_first: bool,
}

/// Exact [`PairRelation`] of `f` and `g` for `view`. All coordinates must be finite.
///
/// The rays through `g` form a closed cone from the eye (a prism along the direction for an
/// orthographic view), the intersection of the three half-spaces bounded by the planes through
/// the eye and each edge. Clipping `f` by them leaves the points of `f` whose ray meets `g`; the
/// rays cross both interiors exactly when that polygon has positive area. Its vertices' sides of
/// `g`'s plane then say where `f` comes first: the polygon is convex and the side is affine on
/// it, so some interior point is strictly on the eye's side exactly when some vertex is.
pub fn relation(view: &Viewpoint, f: &[[f64; 3]; 3], g: &[[f64; 3]; 3]) -> PairRelation {
    let none = PairRelation {
        overlap: false,
        f_first: false,
    };
    let mut all = vec![f[0], f[1], f[2], g[0], g[1], g[2]];
    if let Viewpoint::Eye(e) = view {
        all.push(*e);
    }
    let pts = ints(&all);
    let (eye, dir) = match view {
        Viewpoint::Eye(_) => (Some(pts[6].clone()), None),
        // The direction has its own scale: every test is homogeneous in it.
        Viewpoint::Direction(d) => (None, Some(ints(&[*d]).remove(0))),
    };
    let (fp, gp) = (&pts[0..3], &pts[3..6]);
    let mut poly: Vec<Hp> = fp
        .iter()
        .map(|x| Hp {
            x: x.clone(),
            w: BigInt::from(1),
        })
        .collect();
    for i in 0..3 {
        let (a, b, c) = (&gp[i], &gp[(i + 1) % 3], &gp[(i + 2) % 3]);
        let plane = match (&eye, &dir) {
            (Some(e), _) => Plane::through(e, a, b),
            (None, Some(v)) => Plane::along(a, b, v),
            (None, None) => unreachable!("a viewpoint is an eye or a direction"),
        };
        let inside = plane.value(&Hp {
            x: c.clone(),
            w: BigInt::from(1),
        });
        if inside.is_zero() {
            // g is seen edge-on: no ray crosses its interior.
            return none;
        }
        let plane = if inside.is_negative() {
            plane.flipped()
        } else {
            plane
        };
        poly = clip(&poly, &plane);
        if poly.len() < 3 {
            return none;
        }
    }
    if !has_area(&poly) {
        return none;
    }
    let gplane = Plane::through(&gp[0], &gp[1], &gp[2]);
    let eye_side = match (&eye, &dir) {
        (Some(e), _) => gplane
            .value(&Hp {
                x: e.clone(),
                w: BigInt::from(1),
            })
            .signum(),
        (None, Some(v)) => -dot(&gplane.n, v).signum(),
        (None, None) => unreachable!("a viewpoint is an eye or a direction"),
    };
    let sides: Vec<BigInt> = poly.iter().map(|p| gplane.value(p).signum()).collect();
    let f_first = sides.iter().all(|s| s.is_zero()) || sides.contains(&eye_side);
    PairRelation {
        overlap: true,
        f_first,
    }
}

/// Sutherland-Hodgman: the part of the convex polygon where `plane.value >= 0`.
fn clip(poly: &[Hp], plane: &Plane) -> Vec<Hp> {
    let vals: Vec<BigInt> = poly.iter().map(|p| plane.value(p)).collect();
    let n = poly.len();
    let mut out = Vec::with_capacity(n + 1);
    for a in 0..n {
        let b = (a + 1) % n;
        if !vals[a].is_negative() {
            out.push(poly[a].clone());
        }
        if (vals[a].is_positive() && vals[b].is_negative())
            || (vals[a].is_negative() && vals[b].is_positive())
        {
            // |va| b + |vb| a: on the plane, and w stays positive.
            let (ua, ub) = (vals[a].abs(), vals[b].abs());
            out.push(Hp {
                x: std::array::from_fn(|k| &ua * &poly[b].x[k] + &ub * &poly[a].x[k]),
                w: &ua * &poly[b].w + &ub * &poly[a].w,
            });
        }
    }
    out
}

/// Whether the (convex, planar) polygon has positive area: some three vertices not on a line.
fn has_area(poly: &[Hp]) -> bool {
    let p0 = &poly[0];
    let d: Vec<V3> = poly[1..]
        .iter()
        .map(|p| std::array::from_fn(|k| &p.x[k] * &p0.w - &p0.x[k] * &p.w))
        .collect();
    (0..d.len()).any(|j| (j + 1..d.len()).any(|k| cross(&d[j], &d[k]).iter().any(|c| !c.is_zero())))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stacked_triangles_seen_from_above() {
        let low = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let high = [[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]];
        let eye = Viewpoint::Eye([0.2, 0.2, 5.0]);
        let r = relation(&eye, &high, &low);
        assert_eq!(
            r,
            PairRelation {
                overlap: true,
                f_first: true
            }
        );
        assert!(!relation(&eye, &low, &high).f_first);
        let down = Viewpoint::Direction([0.0, 0.0, -1.0]);
        assert!(relation(&down, &high, &low).f_first);
        assert!(!relation(&down, &low, &high).f_first);
        // Coplanar and overlapping: touching, counted as first.
        let low2 = [[0.1, 0.1, 0.0], [2.0, 0.1, 0.0], [0.1, 2.0, 0.0]];
        let r = relation(&eye, &low, &low2);
        assert!(r.overlap && r.f_first);
        // Sharing only an edge in projection: no interior ray crosses both.
        let side = [[1.0, 0.0, 1.0], [0.0, 1.0, 1.0], [1.0, 1.0, 1.0]];
        assert!(!relation(&down, &side, &low).overlap);
    }

    #[test]
    fn behind_the_eye_and_straddling() {
        // f crosses the plane of the eye; g is behind the eye only.
        let eye = Viewpoint::Eye([0.0, 0.0, 0.0]);
        let f = [[-1.0, -1.0, 1.0], [1.0, -1.0, 1.0], [0.0, 1.0, -0.5]];
        let g_behind = [[-50.0, -50.0, -3.0], [50.0, -50.0, -3.0], [0.0, 50.0, -3.0]];
        let g_front = [[-1.0, -1.0, 3.0], [1.0, -1.0, 3.0], [0.0, 1.0, 3.0]];
        // The antipodal cone of g_front is not a ray through it.
        let r = relation(
            &eye,
            &g_front,
            &[[0.0, 0.0, -1.0], [1.0, 0.0, -1.0], [0.0, 1.0, -1.0]],
        );
        assert!(!r.overlap);
        let r = relation(&eye, &f, &g_behind);
        assert!(r.overlap && r.f_first, "{r:?}");
        let r = relation(&eye, &f, &g_front);
        assert!(r.overlap && r.f_first, "{r:?}");
        let r = relation(&eye, &g_front, &f);
        assert!(r.overlap && !r.f_first, "{r:?}");
    }
}
