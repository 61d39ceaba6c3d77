//! Tet classification: each tet's region code has bit `i` set when the tet's interior and body
//! `i`'s interior overlap. Touching (sharing only boundary points: a face, an edge, a vertex, or
//! a tangent point) does not count, so a body whose surface passes exactly through mesh faces and
//! vertices marks only the tets on its inside.
//!
//! Every shape is decided exactly with that one meaning of exact zero: boxes and triangle
//! surfaces by separating planes with exact signs; a sphere by its distance to the tet, filtered
//! in floats with exact dyadic arithmetic near tangency (distance exactly `r` only touches);
//! cylinders and cone frusta by [`super::frustum`] (outward-rounded intervals, exact dyadic
//! arithmetic where an interval straddles zero; a tet at exactly the radius from the axis, or
//! exactly on a cap plane, only touches). The only culling before them is the bodies' boxes,
//! which are rounded outwards.

use rayon::prelude::*;

use super::exact::{ball_meets_tet, det3_sign, orient, orient2, parallel};
use super::frustum::tet_meets_frustum;
use super::{Primitive, Scene, Shape, TriSurface};
use crate::geom::{dot, sub, Aabb};
use crate::mesh::TetMesh;

const TET_FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];
const TET_EDGES: [[usize; 2]; 6] = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]];

/// Region codes of every tet of `mesh` (parallel).
pub fn classify(scene: &Scene, mesh: &TetMesh) -> Vec<u8> {
    let bounds: Vec<Aabb> = scene.bodies.iter().map(|b| b.bounds()).collect();
    (0..mesh.tets.len())
        .into_par_iter()
        .map(|t| tet_code(scene, &bounds, &mesh.tet_points(t)))
        .collect()
}

/// The region code of one tet; `bounds` are the bodies' boxes.
pub fn tet_code(scene: &Scene, bounds: &[Aabb], p: &[[f64; 3]; 4]) -> u8 {
    let tb = Aabb::of_points(p.iter());
    let mut code = 0u8;
    for (i, b) in scene.bodies.iter().enumerate() {
        // Open boxes must overlap for the interiors to.
        let bb = &bounds[i];
        if (0..3).any(|k| tb.max[k] <= bb.min[k] || tb.min[k] >= bb.max[k]) {
            continue;
        }
        let hit = match &b.shape {
            Shape::Primitive(Primitive::Box { min, max }) => tet_box(p, min, max),
            Shape::Primitive(Primitive::Sphere { center, radius }) => {
                tet_sphere(p, center, *radius)
            }
            Shape::Primitive(Primitive::Frustum { start, end, r0, r1 }) => {
                tet_frustum(p, start, end, *r0, *r1)
            }
            Shape::Surface(s) => tet_surface(p, &tb, s),
        };
        if hit {
            code |= 1 << i;
        }
    }
    code
}

/// Whether a plane weakly separates the tet from the other point set: the tet's signs `ta`
/// and the others' `sb` on opposite closed sides.
fn separates(ta: &[i32], sb: impl Iterator<Item = i32> + Clone) -> bool {
    (ta.iter().all(|&s| s >= 0) && sb.clone().all(|s| s <= 0))
        || (ta.iter().all(|&s| s <= 0) && sb.clone().all(|s| s >= 0))
}

/// Separating planes through a tet face: the face's own vertices are on it (sign 0), so only the
/// opposite vertex and the other set are evaluated.
fn tet_face_separates(p: &[[f64; 3]; 4], others: &[[f64; 3]]) -> bool {
    TET_FACES.iter().enumerate().any(|(i, f)| {
        let (a, b, c) = (p[f[0]], p[f[1]], p[f[2]]);
        let own = orient(&a, &b, &c, &p[i]);
        others.iter().all(|x| orient(&a, &b, &c, x) * own <= 0)
    })
}

fn tet_box(p: &[[f64; 3]; 4], min: &[f64; 3], max: &[f64; 3]) -> bool {
    if orient(&p[0], &p[1], &p[2], &p[3]) == 0 {
        return false; // a flat tet has no interior
    }
    // Quick accept: a tet vertex strictly inside the open box.
    if p.iter()
        .any(|v| (0..3).all(|k| min[k] < v[k] && v[k] < max[k]))
    {
        return true;
    }
    // The box's own face planes are the axis-aligned box test the caller already made.
    let corners: Vec<[f64; 3]> = (0..8)
        .map(|i| {
            [
                if i & 1 == 0 { min[0] } else { max[0] },
                if i & 2 == 0 { min[1] } else { max[1] },
                if i & 4 == 0 { min[2] } else { max[2] },
            ]
        })
        .collect();
    if tet_face_separates(p, &corners) {
        return false;
    }
    // Planes through a tet edge parallel to axis k: exact 2-D orientation in the other two axes.
    for k in 0..3 {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let side = |a: &[f64; 3], b: &[f64; 3], x: &[f64; 3]| {
            orient2([a[i], a[j]], [b[i], b[j]], [x[i], x[j]])
        };
        // An edge along the axis spans no plane with it: all its signs are 0, which `separates`
        // would take for a separation, so such edges are skipped.
        let skip = |q0: &[f64; 3], q1: &[f64; 3]| q0[i] == q1[i] && q0[j] == q1[j];
        if TET_EDGES.iter().any(|e| {
            let (q0, q1) = (p[e[0]], p[e[1]]);
            if skip(&q0, &q1) {
                return false;
            }
            let rest: Vec<i32> = (0..4)
                .filter(|&m| m != e[0] && m != e[1])
                .map(|m| side(&q0, &q1, &p[m]))
                .collect();
            separates(&rest, corners.iter().map(|x| side(&q0, &q1, x)))
        }) {
            return false;
        }
    }
    true
}

/// Whether the open tet meets the closed triangle `v`: no separating plane among the tet's
/// faces, the triangle's plane and the planes through a tet edge parallel to a triangle edge.
fn tet_triangle(p: &[[f64; 3]; 4], v: &[[f64; 3]; 3]) -> bool {
    if tet_face_separates(p, v) {
        return false;
    }
    let tri_side: Vec<i32> = p.iter().map(|x| orient(&v[0], &v[1], &v[2], x)).collect();
    if tri_side.iter().all(|&s| s >= 0) || tri_side.iter().all(|&s| s <= 0) {
        return false;
    }
    for (a, b) in [(0, 1), (1, 2), (2, 0)] {
        let (u0, u1) = (v[a], v[b]);
        let sep = TET_EDGES.iter().any(|e| {
            let (q0, q1) = (p[e[0]], p[e[1]]);
            if parallel((q1, q0), (u1, u0)) {
                return false;
            }
            let side = |x: &[f64; 3]| det3_sign((q1, q0), (u1, u0), (*x, q0));
            let rest: Vec<i32> = (0..4)
                .filter(|&m| m != e[0] && m != e[1])
                .map(|m| side(&p[m]))
                .collect();
            // u0 and u1 give the same sign (the plane is parallel to u1 - u0).
            separates(&rest, [side(&u0), side(&v[3 - a - b])].into_iter())
        });
        if sep {
            return false;
        }
    }
    true
}

/// Closest point of triangle `abc` to `x` (Ericson, Real-Time Collision Detection 5.1.5).
fn closest_on_triangle(x: &[f64; 3], a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> [f64; 3] {
    let ab = sub(b, a);
    let ac = sub(c, a);
    let ap = sub(x, a);
    let d1 = dot(&ab, &ap);
    let d2 = dot(&ac, &ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return *a;
    }
    let bp = sub(x, b);
    let d3 = dot(&ab, &bp);
    let d4 = dot(&ac, &bp);
    if d3 >= 0.0 && d4 <= d3 {
        return *b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return [0, 1, 2].map(|k| a[k] + v * ab[k]);
    }
    let cp = sub(x, c);
    let d5 = dot(&ab, &cp);
    let d6 = dot(&ac, &cp);
    if d6 >= 0.0 && d5 <= d6 {
        return *c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return [0, 1, 2].map(|k| a[k] + w * ac[k]);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return [0, 1, 2].map(|k| b[k] + w * (c[k] - b[k]));
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    [0, 1, 2].map(|k| a[k] + ab[k] * v + ac[k] * w)
}

fn inside_tet(p: &[[f64; 3]; 4], x: &[f64; 3]) -> bool {
    let s = orient(&p[0], &p[1], &p[2], &p[3]);
    (0..4).all(|i| {
        let mut q = *p;
        q[i] = *x;
        let o = orient(&q[0], &q[1], &q[2], &q[3]);
        o == s || o == 0
    })
}

fn tet_sphere(p: &[[f64; 3]; 4], c: &[f64; 3], r: f64) -> bool {
    if orient(&p[0], &p[1], &p[2], &p[3]) == 0 {
        return false;
    }
    if inside_tet(p, c) {
        return true;
    }
    // Filter: the closest distance in floats, with the tet moved so `c` is the origin (rounding
    // then scales with the tet's distance from `c`, not with the coordinates' offset). The
    // closest-point arithmetic is off by a small multiple of eps times that scale; a margin of
    // 1e-9 of it leaves the exact test only the near-tangent cases.
    let q = p.map(|x| sub(&x, c));
    let o = [0.0; 3];
    let mut best = f64::INFINITY;
    for f in TET_FACES {
        let x = closest_on_triangle(&o, &q[f[0]], &q[f[1]], &q[f[2]]);
        best = best.min(dot(&x, &x));
    }
    let scale = q.iter().map(|x| dot(x, x)).fold(r * r, f64::max);
    let margin = 1e-9 * scale;
    if best.is_finite() && scale.is_finite() && scale > 1e-280 {
        if best < r * r - margin {
            return true;
        }
        if best > r * r + margin {
            return false;
        }
    }
    ball_meets_tet(p, c, r)
}

fn tet_frustum(p: &[[f64; 3]; 4], start: &[f64; 3], end: &[f64; 3], r0: f64, r1: f64) -> bool {
    if orient(&p[0], &p[1], &p[2], &p[3]) == 0 {
        return false;
    }
    tet_meets_frustum(p, start, end, r0, r1)
}

/// Distance from the origin to the convex hull of 2D points, compared with `r`: true when the
/// hull reaches inside the open disc of radius `r`.
fn tet_surface(p: &[[f64; 3]; 4], tb: &Aabb, s: &TriSurface) -> bool {
    if orient(&p[0], &p[1], &p[2], &p[3]) == 0 {
        return false;
    }
    let mut ids = Vec::new();
    s.candidates(tb, &mut ids);
    // Boxes first (cheap), then each surviving triangle once.
    ids.retain(|&ti| {
        let v = s.tris[ti as usize].map(|i| s.points[i as usize]);
        !(0..3).any(|k| v.iter().all(|x| x[k] < tb.min[k]) || v.iter().all(|x| x[k] > tb.max[k]))
    });
    ids.sort_unstable();
    ids.dedup();
    for &ti in &ids {
        let v = s.tris[ti as usize].map(|i| s.points[i as usize]);
        if tet_triangle(p, &v) {
            return true;
        }
    }
    // The surface misses the open tet, so the tet is wholly inside or wholly outside: test one
    // interior point.
    let mut w = [0.25; 4];
    for attempt in 0..4 {
        let x = [0, 1, 2].map(|k| (0..4).map(|i| w[i] * p[i][k]).sum::<f64>());
        if strictly_inside(p, &x) {
            return s.contains(&x);
        }
        w = [0.1; 4];
        w[attempt] = 0.7;
    }
    false
}

fn strictly_inside(p: &[[f64; 3]; 4], x: &[f64; 3]) -> bool {
    let s = orient(&p[0], &p[1], &p[2], &p[3]);
    (0..4).all(|i| {
        let mut q = *p;
        q[i] = *x;
        orient(&q[0], &q[1], &q[2], &q[3]) == s
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::surface::{tests::cube_raw, TriSurface};
    use std::path::Path;

    const UNIT: [[f64; 3]; 4] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];

    #[test]
    fn box_touching_is_not_overlapping() {
        // Box sharing the tet's face z = 0 from below: touching only.
        assert!(!tet_box(&UNIT, &[-1.0, -1.0, -1.0], &[2.0, 2.0, 0.0]));
        // Box above the slanted face x + y + z = 1, touching it at a vertex (1,0,0)... and along
        // nothing else.
        assert!(!tet_box(&UNIT, &[1.0, 0.0, 0.0], &[2.0, 1.0, 1.0]));
        // A box corner poking into the slanted face.
        assert!(tet_box(&UNIT, &[0.3, 0.3, 0.3], &[2.0, 2.0, 2.0]));
        // Just beyond the slanted face: (1/3,1/3,1/3) is on it.
        assert!(!tet_box(
            &UNIT,
            &[1.0 / 3.0 + 1e-12, 1.0 / 3.0 + 1e-12, 1.0 / 3.0 + 1e-12],
            &[2.0; 3]
        ));
        // Box holding the tet, and a thin box through the middle with no tet vertex inside.
        assert!(tet_box(&UNIT, &[-1.0; 3], &[2.0; 3]));
        assert!(tet_box(&UNIT, &[0.1, -1.0, -1.0], &[0.2, 2.0, 2.0]));
    }

    #[test]
    fn sphere_tangency_is_exact_at_large_offsets() {
        // The unit tet moved to 2^23 + a fraction: tangent spheres at exactly representable
        // distances (3-4-5 and 2-3-6 triangles) touch only; a hair more radius overlaps.
        let o = 8_388_608.25;
        let t = UNIT.map(|v| v.map(|x| x + o));
        let face = [o - 1.0, o + 0.2, o + 0.2];
        assert!(!tet_sphere(&t, &face, 1.0));
        assert!(tet_sphere(&t, &face, 1.0 + f64::EPSILON));
        let edge = [o + 0.5, o - 3.0, o - 4.0];
        assert!(!tet_sphere(&t, &edge, 5.0));
        assert!(tet_sphere(&t, &edge, 5.0 + 4.0 * f64::EPSILON));
        let vertex = [o - 2.0, o - 3.0, o - 6.0];
        assert!(!tet_sphere(&t, &vertex, 7.0));
        assert!(tet_sphere(&t, &vertex, 7.0 + 4.0 * f64::EPSILON));
        // The slanted face x + y + z = 1 (relative): centre on its normal through (1/4, 1/4,
        // 1/2) at distance sqrt(3) (the point plus (1, 1, 1)).
        let slant = [o + 1.25, o + 1.25, o + 1.5];
        assert!(!tet_sphere(&t, &slant, 3f64.sqrt() * (1.0 - 1e-15)));
        for (c, r) in [(face, 1.0), (edge, 5.0), (vertex, 7.0)] {
            assert!(!ball_meets_tet(&t, &c, r));
        }
        // A slanted face on the plane 3x + 4y = 12 (unit normal (3, 4, 0) / 5): the centre 5
        // along the normal from the face point (3, 0.75, 0.25) is exactly 5 away.
        let s = [
            [4.0, 0.0, 0.0],
            [0.0, 3.0, 0.0],
            [4.0, 0.0, 1.0],
            [0.0, 0.0, 0.0],
        ]
        .map(|v: [f64; 3]| v.map(|x| x + o));
        let c = [6.0 + o, 4.75 + o, 0.25 + o];
        assert!(!tet_sphere(&s, &c, 5.0));
        assert!(!ball_meets_tet(&s, &c, 5.0));
        assert!(tet_sphere(&s, &c, 5.0 + 8.0 * f64::EPSILON));
        // The exact test alone agrees with the filtered one away from tangency.
        let mut seed = 5u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 4.0 - 2.0
        };
        for _ in 0..300 {
            let c = [rnd(), rnd(), rnd()];
            let r = rnd().abs() + 0.05;
            if inside_tet(&UNIT, &c) {
                continue;
            }
            assert_eq!(
                tet_sphere(&UNIT, &c, r),
                ball_meets_tet(&UNIT, &c, r),
                "c {c:?} r {r}"
            );
        }
    }

    #[test]
    fn sphere_and_frustum() {
        assert!(tet_sphere(&UNIT, &[0.2, 0.2, 0.2], 0.01));
        assert!(!tet_sphere(&UNIT, &[-1.0, 0.2, 0.2], 1.0)); // tangent to the face x = 0
        assert!(tet_sphere(&UNIT, &[-1.0, 0.2, 0.2], 1.0 + 1e-9));
        let cyl = |r: f64| tet_frustum(&UNIT, &[-0.5, 0.2, -1.0], &[-0.5, 0.2, 3.0], r, r);
        assert!(!cyl(0.5)); // tangent to x = 0
        assert!(cyl(0.51));
        // Cylinder along z through the tet's interior.
        assert!(tet_frustum(
            &UNIT,
            &[0.1, 0.1, -5.0],
            &[0.1, 0.1, 5.0],
            0.01,
            0.01
        ));
        // Cylinder ending just below the tet (the slab excludes it).
        assert!(!tet_frustum(
            &UNIT,
            &[0.1, 0.1, -5.0],
            &[0.1, 0.1, 0.0],
            0.01,
            0.01
        ));
        // A cone whose apex pokes into the tet, and one whose wide end stays outside.
        assert!(tet_frustum(
            &UNIT,
            &[0.1, 0.1, -2.0],
            &[0.1, 0.1, 0.5],
            1.0,
            0.0
        ));
        assert!(!tet_frustum(
            &UNIT,
            &[3.0, 3.0, 0.0],
            &[3.0, 3.0, 1.0],
            1.0,
            0.1
        ));
    }

    #[test]
    fn surface_cube_exact() {
        let s = TriSurface::from_raw(Path::new("cube"), cube_raw()).unwrap();
        // The tet's face z = 0 lies on the cube's face... shift: tet below the cube touching it.
        let below = UNIT.map(|v| [v[0], v[1], v[2] - 1.0]);
        assert!(!tet_surface(&below, &Aabb::of_points(below.iter()), &s));
        assert!(tet_surface(&UNIT, &Aabb::of_points(UNIT.iter()), &s));
        let small = UNIT.map(|v| [0.2 + 0.1 * v[0], 0.2 + 0.1 * v[1], 0.2 + 0.1 * v[2]]);
        assert!(tet_surface(&small, &Aabb::of_points(small.iter()), &s));
        let far = UNIT.map(|v| [v[0] + 5.0, v[1], v[2]]);
        assert!(!tet_surface(&far, &Aabb::of_points(far.iter()), &s));
        // Touching along an edge only.
        let edge = [
            [1.0, 1.0, 0.0],
            [2.0, 1.0, 0.0],
            [1.0, 2.0, 0.0],
            [1.0, 1.0, 1.0],
        ];
        assert!(!tet_surface(&edge, &Aabb::of_points(edge.iter()), &s));
        assert!(!tet_box(&edge, &[0.0; 3], &[1.0; 3]));
    }
}

#[cfg(test)]
mod proptests {
    use super::*;
    use crate::scene::shapes::Primitive;
    use proptest::prelude::*;

    fn pt() -> impl Strategy<Value = [f64; 3]> {
        prop::array::uniform3(-1.0f64..1.0)
    }

    /// Points strictly inside the tet (positive barycentric weights from a fixed sequence).
    fn interior(p: &[[f64; 3]; 4], n: usize) -> Vec<[f64; 3]> {
        let mut s = 0x2545_F491_4F6C_DD1Du64;
        let mut r = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            0.01 + 0.98 * ((s >> 11) as f64 / (1u64 << 53) as f64)
        };
        (0..n)
            .map(|_| {
                let w = [r(), r(), r(), r()];
                let t: f64 = w.iter().sum();
                [0, 1, 2].map(|k| (0..4).map(|i| w[i] / t * p[i][k]).sum())
            })
            .collect()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]

        /// A tet point strictly inside a body means the interiors overlap: the exact and the
        /// float tests must never miss such a tet.
        #[test]
        fn no_overlap_is_missed(
            a in pt(), b in pt(), c in pt(), d in pt(),
            lo in pt(), ext in prop::array::uniform3(0.05f64..1.2),
            r in 0.05f64..0.9, r1 in 0.0f64..0.9,
        ) {
            let p = [a, b, c, d];
            prop_assume!(orient(&a, &b, &c, &d) != 0);
            let hi = [0, 1, 2].map(|k| lo[k] + ext[k]);
            let samples = interior(&p, 400);
            let bodies = [
                Primitive::Box { min: lo, max: hi },
                Primitive::Sphere { center: lo, radius: r },
                Primitive::Frustum { start: lo, end: hi, r0: r, r1 },
            ];
            for body in &bodies {
                let strictly = |x: &[f64; 3]| match body {
                    Primitive::Box { min, max } => (0..3).all(|k| min[k] < x[k] && x[k] < max[k]),
                    Primitive::Sphere { center, radius } => {
                        let v = sub(x, center);
                        dot(&v, &v) < radius * radius * (1.0 - 1e-9)
                    }
                    Primitive::Frustum { start, end, r0, r1 } => {
                        let ax = sub(end, start);
                        let s = dot(&sub(x, start), &ax) / dot(&ax, &ax);
                        let foot = [0, 1, 2].map(|k| start[k] + s * ax[k]);
                        let v = sub(x, &foot);
                        let rr = r0 + (r1 - r0) * s;
                        s > 1e-6 && s < 1.0 - 1e-6 && dot(&v, &v) < rr * rr * (1.0 - 1e-6)
                    }
                };
                let hit = match body {
                    Primitive::Box { min, max } => tet_box(&p, min, max),
                    Primitive::Sphere { center, radius } => tet_sphere(&p, center, *radius),
                    Primitive::Frustum { start, end, r0, r1 } => tet_frustum(&p, start, end, *r0, *r1),
                };
                if samples.iter().any(strictly) {
                    prop_assert!(hit, "{:?} missed tet {:?}", body, p);
                }
            }
            // A point of a triangle strictly inside the tet: the triangle meets the open tet.
            let tri = [lo, hi, [lo[0], hi[1], 0.5 * (lo[2] + hi[2])]];
            let on_tri = (0..60).map(|i| {
                let (u, v) = ((i % 7) as f64 / 7.0 + 0.05, (i / 7) as f64 / 9.0 + 0.03);
                let (u, v) = if u + v < 0.98 { (u, v) } else { ((0.98 - v).max(0.01), v) };
                [0, 1, 2].map(|k| tri[0][k] + u * (tri[1][k] - tri[0][k]) + v * (tri[2][k] - tri[0][k]))
            });
            let mut inside_tet = false;
            for x in on_tri {
                let s = orient(&a, &b, &c, &d);
                if (0..4).all(|i| {
                    let mut q = p;
                    q[i] = x;
                    orient(&q[0], &q[1], &q[2], &q[3]) == s
                }) {
                    inside_tet = true;
                }
            }
            if inside_tet {
                prop_assert!(tet_triangle(&p, &tri));
            }
        }
    }
}
