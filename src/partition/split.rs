//! Cutting one tet by a plane into conforming sub-tets (the paper's cases a-d), and creating the
//! one new vertex of each cut edge.
//!
//! The cut is combinatorial once each vertex has a side (-1 below, 0 on, +1 above the plane, from
//! exact comparisons): each side's piece is a convex polytope (tet, pyramid or prism) whose faces
//! are the clipped faces of the tet plus the cut polygon. Every face polygon is triangulated as a
//! fan from its smallest vertex id, and each polytope is coned from its smallest vertex id over the
//! faces that do not contain it. A face's triangulation therefore depends only on the face's own
//! vertex ids, so two tets sharing a face (or a quad of a cut face) always agree: the result is
//! conforming. Piece counts: one edge on the plane and the opposite edge crossed, 2; one vertex on
//! the plane and two edges crossed, 3 (tet + pyramid); three edges crossed, 4 (tet + prism); four
//! edges crossed, 6 (two prisms). A plane that only touches a vertex, an edge or a face cuts
//! nothing. Orientation is derived combinatorially from the parent's (positive) orientation, never
//! from rounded coordinates.

/// Faces of a positively oriented tet `(0, 1, 2, 3)`, each ordered so that its right-hand normal
/// points into the tet (towards the opposite vertex).
const INWARD_FACES: [[usize; 3]; 4] = [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]];

/// At most 6 sub-tets come out of one cut.
pub type Pieces = Vec<([u32; 4], i8)>;

/// Side of a coordinate against a plane position, by exact comparison.
#[inline]
pub fn side(x: f64, position: f64) -> i8 {
    if x < position {
        -1
    } else if x > position {
        1
    } else {
        0
    }
}

/// Whether a tet with these vertex sides is cut (has vertices strictly on both sides).
#[inline]
pub fn crosses(sides: &[i8; 4]) -> bool {
    sides.contains(&-1) && sides.contains(&1)
}

/// Sub-tets per side for a tet with `below`, `on`, `above` vertices against a plane:
/// `(left, right)` tet counts after the cut (left = below). Non-crossing tets count 1 on their side
/// (all four on the plane, a degenerate tet, counts left).
#[inline]
pub fn case_counts(below: u8, on: u8, above: u8) -> (u8, u8) {
    if above == 0 {
        return (1, 0);
    }
    if below == 0 {
        return (0, 1);
    }
    match (below, on, above) {
        (1, 0, 3) => (1, 3),
        (2, 0, 2) => (3, 3),
        (3, 0, 1) => (3, 1),
        (1, 1, 2) => (1, 2),
        (2, 1, 1) => (2, 1),
        _ => (1, 1), // (1, 2, 1): an edge on the plane, the opposite edge crossed
    }
}

/// Cuts `tet` (positively oriented) whose vertices have `sides`, appending `(sub-tet, side)` pairs
/// to `out`; every sub-tet is positively oriented and lies on one side (-1 or +1). `mid(a, b)` gives
/// the id of the new vertex on the crossed edge `(a, b)` (called with `a < b`). A tet that does not
/// cross is appended whole, with the side of its off-plane vertices (-1 when all are on the plane).
pub fn split_tet(tet: [u32; 4], sides: [i8; 4], mid: &impl Fn(u32, u32) -> u32, out: &mut Pieces) {
    if !crosses(&sides) {
        let s = if sides.contains(&1) { 1 } else { -1 };
        out.push((tet, s));
        return;
    }
    for s in [-1i8, 1] {
        cone_side(tet, sides, s, mid, out);
    }
}

/// A polygon of up to 4 vertices: `(id, on the plane)`.
#[derive(Clone, Copy)]
struct Poly {
    v: [(u32, bool); 4],
    n: usize,
}

impl Poly {
    const EMPTY: Poly = Poly {
        v: [(0, false); 4],
        n: 0,
    };
    fn push(&mut self, id: u32, on: bool) {
        self.v[self.n] = (id, on);
        self.n += 1;
    }
    fn ids(&self) -> impl Iterator<Item = u32> + '_ {
        self.v[..self.n].iter().map(|x| x.0)
    }
}

/// Triangulates the part of the tet on side `s` and appends its sub-tets.
fn cone_side(
    tet: [u32; 4],
    sides: [i8; 4],
    s: i8,
    mid: &impl Fn(u32, u32) -> u32,
    out: &mut Pieces,
) {
    let edge_mid = |i: usize, j: usize| {
        let (a, b) = (tet[i].min(tet[j]), tet[i].max(tet[j]));
        mid(a, b)
    };
    let mut faces = [Poly::EMPTY; 5];
    let mut nf = 0;
    // Directed edges of the cut polygon, reversed from the faces' traversal so the cut face gets
    // the same (inward) orientation as the clipped faces.
    let mut next: [(u32, u32); 4] = [(0, 0); 4];
    let mut nseg = 0;
    for f in INWARD_FACES {
        let mut p = Poly::EMPTY;
        for k in 0..3 {
            let (i, j) = (f[k], f[(k + 1) % 3]);
            if sides[i] == s || sides[i] == 0 {
                p.push(tet[i], sides[i] == 0);
            }
            if sides[i] * sides[j] == -1 {
                p.push(edge_mid(i, j), true);
            }
        }
        if p.n < 3 {
            continue;
        }
        for k in 0..p.n {
            let (u, w) = (p.v[k], p.v[(k + 1) % p.n]);
            if u.1 && w.1 {
                next[nseg] = (w.0, u.0);
                nseg += 1;
            }
        }
        faces[nf] = p;
        nf += 1;
    }
    // Chain the cut polygon (3 or 4 vertices) from its directed edges.
    let mut cut = Poly::EMPTY;
    let start = next[0].0;
    let mut cur = start;
    for _ in 0..nseg {
        cut.push(cur, true);
        match next[..nseg].iter().find(|e| e.0 == cur) {
            Some(e) => cur = e.1,
            None => break,
        }
        if cur == start {
            break;
        }
    }
    faces[nf] = cut;
    nf += 1;
    let apex = faces[..nf].iter().flat_map(|f| f.ids()).min().unwrap_or(0);
    for f in &faces[..nf] {
        if f.ids().any(|v| v == apex) {
            continue;
        }
        let ids: Vec<u32> = f.ids().collect();
        let r = (0..ids.len()).min_by_key(|&k| ids[k]).unwrap_or(0);
        let at = |k: usize| ids[(r + k) % ids.len()];
        for k in 1..ids.len() - 1 {
            out.push(([at(0), at(k), at(k + 1), apex], s));
        }
    }
}

/// The position of the new vertex where the segment `pa`-`pb` crosses the plane `axis = position`
/// (which it must cross strictly), and the interpolation parameter from the canonical first
/// endpoint. The endpoints are put in canonical order (lexicographic by coordinates) first, so the
/// same segment gives the same bits whichever way round it is passed; the coordinate on `axis` is
/// exactly `position`, and every other coordinate is clamped to the segment's range so the vertex
/// stays in any box that holds both endpoints. Returns `(point, first endpoint is a, t)`.
pub fn edge_point(
    pa: &[f64; 3],
    pb: &[f64; 3],
    axis: usize,
    position: f64,
) -> ([f64; 3], bool, f64) {
    let a_first = pa.partial_cmp(pb) != Some(std::cmp::Ordering::Greater);
    let (lo, hi) = if a_first { (pa, pb) } else { (pb, pa) };
    let t = (position - lo[axis]) / (hi[axis] - lo[axis]);
    let mut p = [0.0; 3];
    for k in 0..3 {
        let v = lo[k] + t * (hi[k] - lo[k]);
        p[k] = v.clamp(lo[k].min(hi[k]), lo[k].max(hi[k]));
    }
    p[axis] = position;
    (p, a_first, t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::tet_volume;
    use std::collections::HashMap;

    /// Cuts one tet of `pts` by `x = position`, creating new vertices; returns points and pieces.
    fn cut(pts: &[[f64; 3]; 4], axis: usize, position: f64) -> (Vec<[f64; 3]>, Pieces) {
        let mut points: Vec<[f64; 3]> = pts.to_vec();
        let tet = [0u32, 1, 2, 3];
        let sides = pts.map(|p| side(p[axis], position));
        let mut mids = HashMap::new();
        for i in 0..4 {
            for j in i + 1..4 {
                if sides[i] * sides[j] == -1 {
                    let (p, _, _) = edge_point(&pts[i], &pts[j], axis, position);
                    mids.insert((i as u32, j as u32), points.len() as u32);
                    points.push(p);
                }
            }
        }
        let mut out = Vec::new();
        split_tet(tet, sides, &|a, b| mids[&(a, b)], &mut out);
        (points, out)
    }

    fn check(pts: [[f64; 3]; 4], position: f64, pieces: usize) {
        let (points, out) = cut(&pts, 0, position);
        assert_eq!(out.len(), pieces, "{pts:?} at {position}");
        let whole = tet_volume(&pts[0], &pts[1], &pts[2], &pts[3]);
        let mut sum = 0.0;
        for (t, s) in &out {
            let p = t.map(|v| points[v as usize]);
            let v = tet_volume(&p[0], &p[1], &p[2], &p[3]);
            assert!(v > 0.0, "piece {t:?} volume {v}");
            for q in p {
                assert!(side(q[0], position) * s >= 0, "piece {t:?} on side {s}");
            }
            sum += v;
        }
        assert!((sum - whole).abs() <= 1e-14 * whole, "{sum} vs {whole}");
        let (l, r) = out.iter().fold(
            (0, 0),
            |(l, r), x| {
                if x.1 < 0 {
                    (l + 1, r)
                } else {
                    (l, r + 1)
                }
            },
        );
        let sides = pts.map(|p| side(p[0], position));
        let c = |s: i8| sides.iter().filter(|&&x| x == s).count() as u8;
        assert_eq!(case_counts(c(-1), c(0), c(1)), (l, r));
    }

    const T: [[f64; 3]; 4] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];

    #[test]
    fn four_cases_and_touching() {
        // (c) one vertex against three: 4 tets.
        check(T, 0.5, 4);
        // (d) two against two.
        let d = [
            [0.0, 0.0, 0.0],
            [0.1, 1.0, 0.0],
            [1.0, 0.0, 1.0],
            [1.2, 1.0, 1.0],
        ];
        let d = if tet_volume(&d[0], &d[1], &d[2], &d[3]) > 0.0 {
            d
        } else {
            [d[0], d[1], d[3], d[2]]
        };
        check(d, 0.6, 6);
        // (b) one vertex on the plane, two edges crossed: 3 tets.
        let b = [
            [0.5, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, 0.0, 1.0],
        ];
        let b = if tet_volume(&b[0], &b[1], &b[2], &b[3]) > 0.0 {
            b
        } else {
            [b[0], b[1], b[3], b[2]]
        };
        check(b, 0.5, 3);
        // (a) an edge on the plane, the opposite edge crossed: 2 tets.
        let a = [
            [0.5, 0.0, 0.0],
            [0.5, 1.0, 0.0],
            [0.0, 0.5, 1.0],
            [1.0, 0.5, 1.0],
        ];
        let a = if tet_volume(&a[0], &a[1], &a[2], &a[3]) > 0.0 {
            a
        } else {
            [a[0], a[1], a[3], a[2]]
        };
        check(a, 0.5, 2);
        // Touching: vertex, edge, face on the plane cut nothing.
        check(T, 0.0, 1);
        check(T, 1.0, 1);
        check(a, 0.0, 1);
    }

    #[test]
    fn edge_point_is_canonical() {
        let a = [0.1, 0.7, -3.0];
        let b = [0.9, 0.2, 5.0];
        let (p, fa, t) = edge_point(&a, &b, 0, 0.3);
        let (q, fb, u) = edge_point(&b, &a, 0, 0.3);
        assert_eq!(p.map(f64::to_bits), q.map(f64::to_bits));
        assert!(fa && !fb);
        assert_eq!(t, u);
        assert_eq!(p[0], 0.3);
    }
}
