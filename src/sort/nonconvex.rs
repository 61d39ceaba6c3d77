//! What adjacency misses in a non-convex leaf: a ray that leaves the leaf's tets through an exit
//! face and re-enters through an entry face further on. Convex leaves are detected once and
//! skipped; for the others each view adds "exit face's tet before entry face's tet" for every
//! pair of boundary faces that overlap on screen with the exit face in front (as XMPVO does),
//! decided with exact plane-side predicates.

use rayon::prelude::*;

use super::adjacency::{sorted_face, Adjacency};
use super::side::eye_side;
use crate::camera::{Camera, Viewpoint};
use crate::geom::{cross, dot, orient3d, sub};
use crate::mesh::TetMesh;

/// The boundary faces of one leaf that is not convex, outward-oriented.
pub struct LeafBoundary {
    /// Tet owning each face.
    pub tet: Vec<u32>,
    /// Point ids, ordered so the normal `(b - a) x (c - a)` points out of the tet.
    pub tri: Vec<[u32; 3]>,
}

impl LeafBoundary {
    /// The leaf's boundary faces, or `None` when the leaf's tets form a convex region: one
    /// connected, closed, edge-manifold boundary with no reflex edge (a closed, connected, locally
    /// convex surface bounds a convex body), decided with exact orientation tests.
    pub fn build(
        mesh: &TetMesh,
        adj: &Adjacency,
        same_leaf: &[u8],
        tets: &[u32],
    ) -> Option<LeafBoundary> {
        let mut tet = Vec::new();
        let mut tri = Vec::new();
        for &t in tets {
            let tu = t as usize;
            for i in 0..4 {
                if same_leaf[tu] >> i & 1 == 0 {
                    let mut f = sorted_face(&mesh.tets[tu], i);
                    if adj.positive_side[tu] >> i & 1 == 0 {
                        f.swap(1, 2);
                    }
                    tet.push(t);
                    tri.push(f);
                }
            }
        }
        if tri.is_empty() || is_convex(&mesh.points, &tri) {
            return None;
        }
        Some(LeafBoundary { tet, tri })
    }

    pub fn len(&self) -> usize {
        self.tri.len()
    }

    pub fn is_empty(&self) -> bool {
        self.tri.is_empty()
    }

    /// Extra precedence edges `(before, after)` for this view and drawing direction.
    pub fn constraints(&self, mesh: &TetMesh, cam: &Camera, ftb: bool) -> Vec<(u32, u32)> {
        let view = cam.viewpoint();
        let pts = &mesh.points;
        let nf = self.tri.len();
        let p = |v: u32| &pts[v as usize];
        // +1: exit face (the eye is on the tet's side), -1: entry face, 0: edge-on.
        let kind: Vec<i8> = self
            .tri
            .par_iter()
            .map(|f| eye_side(&view, p(f[0]), p(f[1]), p(f[2])))
            .collect();
        let (r, u, fw) = cam.frame();
        let b = mesh.bounds().extent();
        let near = 1e-9 * (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt().max(1e-300);
        // Projected faces. Perspective faces reaching behind the eye are clipped at a plane just
        // in front of it (only forward rays make the image); faces entirely behind are dropped.
        // `exact`: all three corners in front, so the exact projective overlap test applies.
        let mut exact = vec![true; nf];
        let shapes: Vec<Option<Vec<[f64; 2]>>> = self
            .tri
            .iter()
            .enumerate()
            .map(|(k, f)| {
                let q = [p(f[0]), p(f[1]), p(f[2])];
                match view {
                    Viewpoint::Direction(_) => {
                        Some(q.iter().map(|x| [dot(x, &r), dot(x, &u)]).collect())
                    }
                    Viewpoint::Eye(e) => {
                        let rel: Vec<[f64; 3]> = q.iter().map(|x| sub(x, &e)).collect();
                        let z: Vec<f64> = rel.iter().map(|x| dot(x, &fw)).collect();
                        let proj = |x: &[f64; 3], zz: f64| [dot(x, &r) / zz, dot(x, &u) / zz];
                        if z.iter().all(|&zz| zz > near) {
                            return Some((0..3).map(|i| proj(&rel[i], z[i])).collect());
                        }
                        exact[k] = false;
                        let mut poly = Vec::with_capacity(4);
                        for i in 0..3 {
                            let j = (i + 1) % 3;
                            if z[i] > near {
                                poly.push(proj(&rel[i], z[i]));
                            }
                            if (z[i] > near) != (z[j] > near) {
                                let t = (near - z[i]) / (z[j] - z[i]);
                                let x = [0, 1, 2].map(|c| rel[i][c] + t * (rel[j][c] - rel[i][c]));
                                poly.push(proj(&x, near));
                            }
                        }
                        (poly.len() >= 3).then_some(poly)
                    }
                }
            })
            .collect();
        let behind: Vec<bool> = shapes.iter().map(|s| s.is_none()).collect();
        let exits: Vec<u32> = (0..nf as u32)
            .filter(|&k| kind[k as usize] > 0 && !behind[k as usize])
            .collect();
        let entries: Vec<u32> = (0..nf as u32)
            .filter(|&k| kind[k as usize] < 0 && !behind[k as usize])
            .collect();
        if exits.is_empty() || entries.is_empty() {
            return Vec::new();
        }
        let bbox = |s: &Vec<[f64; 2]>| -> [f64; 4] {
            s.iter().fold(
                [
                    f64::INFINITY,
                    f64::INFINITY,
                    f64::NEG_INFINITY,
                    f64::NEG_INFINITY,
                ],
                |b, q| {
                    [
                        b[0].min(q[0]),
                        b[1].min(q[1]),
                        b[2].max(q[0]),
                        b[3].max(q[1]),
                    ]
                },
            )
        };
        let boxes: Vec<Option<[f64; 4]>> = shapes.iter().map(|s| s.as_ref().map(bbox)).collect();
        // A grid over the bounded exit faces' boxes; perspective windows are clamped (far off-axis
        // faces share the border cells, which keeps the candidate search conservative).
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for &k in exits.iter().chain(entries.iter()) {
            if let Some(b) = boxes[k as usize] {
                lo = [lo[0].min(b[0]), lo[1].min(b[1])];
                hi = [hi[0].max(b[2]), hi[1].max(b[3])];
            }
        }
        if matches!(view, Viewpoint::Eye(_)) {
            lo = lo.map(|x| x.max(-8.0));
            hi = hi.map(|x| x.min(8.0));
        }
        let g = ((exits.len() as f64).sqrt() as usize).clamp(1, 512);
        let valid = lo[0] <= hi[0] && lo[1] <= hi[1];
        let span = [0, 1].map(|a| (hi[a] - lo[a]).max(1e-300));
        let cell = |x: f64, a: usize| -> usize {
            if !valid {
                return 0;
            }
            let c = ((x - lo[a]) / span[a] * g as f64).floor();
            if c.is_nan() || c < 0.0 {
                0
            } else {
                (c as usize).min(g - 1)
            }
        };
        let range = |b: &[f64; 4]| (cell(b[0], 0), cell(b[2], 0), cell(b[1], 1), cell(b[3], 1));
        let mut count = vec![0u32; g * g + 1];
        let mut unbounded_exits = Vec::new();
        for &k in &exits {
            match &boxes[k as usize] {
                Some(b) => {
                    let (x0, x1, y0, y1) = range(b);
                    for y in y0..=y1 {
                        for x in x0..=x1 {
                            count[y * g + x + 1] += 1;
                        }
                    }
                }
                None => unbounded_exits.push(k),
            }
        }
        for i in 0..g * g {
            count[i + 1] += count[i];
        }
        let mut fill = count.clone();
        let mut bins = vec![0u32; count[g * g] as usize];
        for &k in &exits {
            if let Some(b) = &boxes[k as usize] {
                let (x0, x1, y0, y1) = range(b);
                for y in y0..=y1 {
                    for x in x0..=x1 {
                        let s = &mut fill[y * g + x];
                        bins[*s as usize] = k;
                        *s += 1;
                    }
                }
            }
        }
        let tol = 1e-9 * span[0].max(span[1]).max(1e-300);
        let ctx = PairCtx {
            pts,
            tri: &self.tri,
            view,
            cam,
            shapes: &shapes,
            exact: &exact,
            tol,
        };
        let mut out: Vec<(u32, u32)> = entries
            .par_iter()
            .with_min_len(64)
            .flat_map_iter(|&gk| {
                let mut found = Vec::new();
                let gb = self.tet[gk as usize];
                let mut consider = |fk: u32| {
                    let fa = self.tet[fk as usize];
                    if fa != gb && ctx.exit_in_front(fk as usize, gk as usize) {
                        found.push(if ftb { (fa, gb) } else { (gb, fa) });
                    }
                };
                match &boxes[gk as usize] {
                    Some(b) => {
                        let (x0, x1, y0, y1) = range(b);
                        for y in y0..=y1 {
                            for x in x0..=x1 {
                                let bin = y * g + x;
                                for &fk in &bins[count[bin] as usize..count[bin + 1] as usize] {
                                    let Some(fb) = &boxes[fk as usize] else {
                                        continue;
                                    };
                                    if fb[0] > b[2] + tol
                                        || b[0] > fb[2] + tol
                                        || fb[1] > b[3] + tol
                                        || b[1] > fb[3] + tol
                                    {
                                        continue;
                                    }
                                    // Test each pair once: in the cell holding the low corner of
                                    // the boxes' overlap.
                                    let cx = cell(fb[0].max(b[0]), 0);
                                    let cy = cell(fb[1].max(b[1]), 1);
                                    if (cx, cy) != (x, y) {
                                        continue;
                                    }
                                    consider(fk);
                                }
                            }
                        }
                        for &fk in &unbounded_exits {
                            consider(fk);
                        }
                    }
                    None => {
                        for &fk in &exits {
                            consider(fk);
                        }
                    }
                }
                found
            })
            .collect();
        out.par_sort_unstable();
        out.dedup();
        out
    }
}

struct PairCtx<'a> {
    pts: &'a [[f64; 3]],
    tri: &'a [[u32; 3]],
    view: Viewpoint,
    cam: &'a Camera,
    shapes: &'a [Option<Vec<[f64; 2]>>],
    exact: &'a [bool],
    tol: f64,
}

impl PairCtx<'_> {
    fn p(&self, v: u32) -> &[f64; 3] {
        &self.pts[v as usize]
    }

    /// Whether some ray from the eye crosses exit face `f` and then entry face `g`.
    fn exit_in_front(&self, f: usize, g: usize) -> bool {
        let (ft, gt) = (self.tri[f], self.tri[g]);
        if let (Some(a), Some(b)) = (&self.shapes[f], &self.shapes[g]) {
            if separated(a, b, self.tol) {
                return false;
            }
            // Exactly: the projections' interiors must meet, or no ray crosses both faces.
            if self.exact[f]
                && self.exact[g]
                && (self.exactly_separated(&ft, &gt) || self.exactly_separated(&gt, &ft))
            {
                return false;
            }
        }
        // g against f's plane: for an exit face the eye is on the inner (positive) side.
        let side_f = ft_side(self.pts, &ft, &gt);
        match side_f {
            Side::Outer => return true,
            Side::Inner | Side::Coplanar => return false,
            Side::Mixed => {}
        }
        // f against g's plane: for an entry face the eye is on the outer (negative) side.
        match ft_side(self.pts, &gt, &ft) {
            Side::Outer => return true,
            Side::Inner => return false,
            Side::Coplanar => return false,
            Side::Mixed => {}
        }
        self.sample_in_front(f, g)
    }

    /// Whether an edge line of `t` (seen from the eye) leaves all of `o` on the side away from
    /// `t`, touching allowed: the projective orientation `orient3d(p, q, x, eye)` has the same
    /// sign as the projected 2D orientation for points in front of the eye, so this is exact.
    fn exactly_separated(&self, t: &[u32; 3], o: &[u32; 3]) -> bool {
        let s = eye_side(&self.view, self.p(t[0]), self.p(t[1]), self.p(t[2]));
        if s == 0 {
            return true;
        }
        (0..3).any(|i| {
            let (p, q) = (self.p(t[i]), self.p(t[(i + 1) % 3]));
            o.iter()
                .all(|&x| eye_side(&self.view, p, q, self.p(x)) * s <= 0)
        })
    }

    /// Neither plane separates the two (rare): compare depths along a ray through a point of
    /// the overlap of their projections.
    fn sample_in_front(&self, f: usize, g: usize) -> bool {
        let (Some(a), Some(b)) = (&self.shapes[f], &self.shapes[g]) else {
            return false;
        };
        let Some(q) = overlap_point(a, b) else {
            return false;
        };
        let (r, u, fw) = self.cam.frame();
        let (o, dir) = match self.view {
            Viewpoint::Direction(v) => ([0, 1, 2].map(|k| q[0] * r[k] + q[1] * u[k]), v),
            Viewpoint::Eye(e) => (e, [0, 1, 2].map(|k| fw[k] + q[0] * r[k] + q[1] * u[k])),
        };
        let depth = |t: &[u32; 3]| {
            let (a, b, c) = (self.p(t[0]), self.p(t[1]), self.p(t[2]));
            let n = cross(&sub(b, a), &sub(c, a));
            dot(&n, &sub(a, &o)) / dot(&n, &dir)
        };
        depth(&self.tri[f]) < depth(&self.tri[g])
    }
}

#[derive(Debug, PartialEq)]
enum Side {
    /// Every vertex on the outer (normal) side or on the plane, not all on it.
    Outer,
    Inner,
    Coplanar,
    Mixed,
}

/// Where triangle `other` lies against the plane of outward triangle `t`.
fn ft_side(pts: &[[f64; 3]], t: &[u32; 3], other: &[u32; 3]) -> Side {
    let (a, b, c) = (
        &pts[t[0] as usize],
        &pts[t[1] as usize],
        &pts[t[2] as usize],
    );
    let (mut pos, mut neg) = (false, false);
    for &v in other {
        // orient3d > 0: below the normal, i.e. on the inner side.
        let s = orient3d(a, b, c, &pts[v as usize]);
        pos |= s > 0.0;
        neg |= s < 0.0;
    }
    match (pos, neg) {
        (false, false) => Side::Coplanar,
        (true, false) => Side::Inner,
        (false, true) => Side::Outer,
        (true, true) => Side::Mixed,
    }
}

/// Twice the signed area of a polygon (shoelace).
fn signed_area(s: &[[f64; 2]]) -> f64 {
    (0..s.len())
        .map(|i| {
            let (p, q) = (&s[i], &s[(i + 1) % s.len()]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum()
}

fn orient2(a: &[f64; 2], b: &[f64; 2], c: &[f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Whether an edge line of either triangle separates them by more than `tol` (so a conservative
/// "maybe overlapping" for touching or nearly touching triangles).
fn separated(a: &[[f64; 2]], b: &[[f64; 2]], tol: f64) -> bool {
    let sep = |s: &[[f64; 2]], o: &[[f64; 2]]| -> bool {
        let area = signed_area(s);
        if area == 0.0 {
            return false;
        }
        let sg = area.signum();
        (0..s.len()).any(|i| {
            let (p, q) = (&s[i], &s[(i + 1) % s.len()]);
            let len = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt();
            o.iter().all(|x| sg * orient2(p, q, x) < -tol * len)
        })
    };
    sep(a, b) || sep(b, a)
}

/// A point inside both triangles' projections (the centroid of their clipped intersection).
fn overlap_point(a: &[[f64; 2]], b: &[[f64; 2]]) -> Option<[f64; 2]> {
    let mut poly: Vec<[f64; 2]> = b.to_vec();
    let sg = signed_area(a).signum();
    if sg == 0.0 {
        return None;
    }
    for i in 0..a.len() {
        let (p, q) = (&a[i], &a[(i + 1) % a.len()]);
        let inside = |x: &[f64; 2]| sg * orient2(p, q, x) >= 0.0;
        let mut next = Vec::with_capacity(poly.len() + 1);
        for k in 0..poly.len() {
            let (c, d) = (&poly[k], &poly[(k + 1) % poly.len()]);
            let (ic, id) = (inside(c), inside(d));
            if ic {
                next.push(*c);
            }
            if ic != id {
                let oc = orient2(p, q, c);
                let od = orient2(p, q, d);
                let t = oc / (oc - od);
                next.push([c[0] + t * (d[0] - c[0]), c[1] + t * (d[1] - c[1])]);
            }
        }
        poly = next;
        if poly.is_empty() {
            return None;
        }
    }
    let n = poly.len() as f64;
    Some([
        poly.iter().map(|x| x[0]).sum::<f64>() / n,
        poly.iter().map(|x| x[1]).sum::<f64>() / n,
    ])
}

/// Whether outward triangles form one closed, connected, edge-manifold surface with no reflex
/// edge.
fn is_convex(pts: &[[f64; 3]], tri: &[[u32; 3]]) -> bool {
    let mut edges: Vec<(u32, u32, u32)> = Vec::with_capacity(3 * tri.len());
    for (k, f) in tri.iter().enumerate() {
        for i in 0..3 {
            let (a, b) = (f[i], f[(i + 1) % 3]);
            edges.push((a.min(b), a.max(b), k as u32));
        }
    }
    edges.par_sort_unstable();
    let mut parent: Vec<u32> = (0..tri.len() as u32).collect();
    fn find(p: &mut [u32], mut x: u32) -> u32 {
        while p[x as usize] != x {
            p[x as usize] = p[p[x as usize] as usize];
            x = p[x as usize];
        }
        x
    }
    let mut i = 0;
    while i < edges.len() {
        let mut j = i + 1;
        while j < edges.len() && edges[j].0 == edges[i].0 && edges[j].1 == edges[i].1 {
            j += 1;
        }
        if j - i != 2 {
            return false;
        }
        let (f1, f2) = (edges[i].2 as usize, edges[i + 1].2 as usize);
        let t1 = &tri[f1];
        let Some(&w) = tri[f2]
            .iter()
            .find(|&&v| v != edges[i].0 && v != edges[i].1)
        else {
            return false;
        };
        // The other face's far vertex must not be outside this face's plane.
        if orient3d(
            &pts[t1[0] as usize],
            &pts[t1[1] as usize],
            &pts[t1[2] as usize],
            &pts[w as usize],
        ) < 0.0
        {
            return false;
        }
        let (a, b) = (find(&mut parent, f1 as u32), find(&mut parent, f2 as u32));
        parent[a as usize] = b;
        i = j;
    }
    let root = find(&mut parent, 0);
    (0..tri.len() as u32).all(|k| find(&mut parent, k) == root)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::structured_grid;

    fn boundary(mesh: &TetMesh) -> Option<LeafBoundary> {
        let adj = Adjacency::build(&mesh.points, &mesh.tets);
        let same: Vec<u8> = adj
            .neighbors
            .iter()
            .map(|n| {
                (0..4).fold(0u8, |m, i| {
                    m | (((n[i] != super::super::adjacency::NONE) as u8) << i)
                })
            })
            .collect();
        let tets: Vec<u32> = (0..mesh.tets.len() as u32).collect();
        LeafBoundary::build(mesh, &adj, &same, &tets)
    }

    #[test]
    fn box_is_convex_and_l_shape_is_not() {
        let m = structured_grid([3, 3, 2], [0.0; 3], [1.0; 3]);
        assert!(boundary(&m).is_none());
        let mut l = m.clone();
        // Drop cube (2, 2, *): an L-shaped prism.
        let keep: Vec<usize> = (0..l.tets.len())
            .filter(|&t| {
                let c = m.cell_data.get("cube_id").unwrap().data.get_f64(t) as usize;
                c % 9 != 8
            })
            .collect();
        l.tets = keep.iter().map(|&t| m.tets[t]).collect();
        let b = boundary(&l).expect("an L shape is not convex");
        assert!(!b.is_empty());
    }

    #[test]
    fn overlap_and_separation() {
        let a = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        let b = [[0.2, 0.2], [2.0, 0.2], [0.2, 2.0]];
        let c = [[2.0, 2.0], [3.0, 2.0], [2.0, 3.0]];
        assert!(!separated(&a, &b, 0.0));
        assert!(separated(&a, &c, 0.0));
        let q = overlap_point(&a, &b).unwrap();
        assert!(q[0] > 0.2 && q[1] > 0.2 && q[0] + q[1] < 1.0);
        assert!(overlap_point(&a, &c).is_none());
    }
}
