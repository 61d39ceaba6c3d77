//! What adjacency misses in a non-convex leaf: a ray that leaves the leaf's tets through an exit
//! face and re-enters through an entry face further on. Convex leaves are detected once and
//! skipped; for the others each view adds "exit face's tet before entry face's tet" for every
//! pair of boundary faces that some ray from the eye crosses in that order (as XMPVO does).
//!
//! Exactness: candidate pairs come from conservative screen boxes (float, enlarged by their
//! rounding bound; faces reaching behind the eye get boxes open towards infinity); each pair is
//! decided exactly: float 2-D tests count only beyond their error bound, then orient3d plane
//! sides, separating planes and witness rays, and the rare rest by big-integer arithmetic
//! (`exact::relation`). What an exact zero means: faces that only touch on screen (a shared edge
//! or vertex, an edge-on face) constrain nothing; coplanar faces that overlap (tets touching
//! without sharing a face) order the exit face's tet first, as the ray meets it first.

use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

use super::adjacency::{sorted_face, Adjacency};
use super::exact;
use super::side::eye_side;
use crate::camera::{Camera, Viewpoint};
use crate::geom::{dot, orient3d, sub};
use crate::mesh::TetMesh;

const EPS: f64 = f64::EPSILON;

/// The boundary faces of one leaf that is not convex, outward-oriented (those that can order
/// anything: see [`LeafBoundary::build`]).
pub struct LeafBoundary {
    /// Tet owning each face.
    pub tet: Vec<u32>,
    /// Point ids, ordered so the normal `(b - a) x (c - a)` points out of the tet.
    pub tri: Vec<[u32; 3]>,
}

impl LeafBoundary {
    /// The leaf's boundary faces that can order anything, or `None` when the leaf's tets form a
    /// convex region: one connected, closed, edge-manifold boundary with no reflex edge (a
    /// closed, connected, locally convex surface bounds a convex body), decided with exact
    /// orientation tests. Faces lying in a plane of the leaf's bounding box are left out: the
    /// whole leaf is on one side of that plane, so a ray leaving through such a face never comes
    /// back, and one entering through it was never inside before (exact float comparisons).
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
        let pts = &mesh.points;
        let bounds = crate::geom::Aabb::of_points(
            tets.iter()
                .flat_map(|&t| mesh.tets[t as usize].iter().map(|&v| &pts[v as usize])),
        );
        let on_box = |f: &[u32; 3]| {
            (0..3).any(|k| {
                let c = f.map(|v| pts[v as usize][k]);
                (c[0] == c[1] && c[1] == c[2]) && (c[0] == bounds.min[k] || c[0] == bounds.max[k])
            })
        };
        let mut keep: Vec<usize> = (0..tri.len()).filter(|&k| !on_box(&tri[k])).collect();
        // Faces near each other in space near each other in memory: every view tests each face
        // against the faces overlapping it on screen, and those reads then hit the cache. (The
        // constraints are a sorted set, so the order changes no answer.)
        let code = |f: &[u32; 3]| {
            let c = (0..3).map(|k| {
                let x = f.iter().map(|&v| pts[v as usize][k]).sum::<f64>() / 3.0;
                let span = bounds.max[k] - bounds.min[k];
                let u = if span > 0.0 {
                    (x - bounds.min[k]) / span
                } else {
                    0.0
                };
                // In [0, 1023]; NaN becomes 0.
                (u.clamp(0.0, 1.0) * 1023.0) as u32
            });
            c.enumerate()
                .fold(0u32, |acc, (k, q)| acc | spread_bits(q) << k)
        };
        keep.sort_by_cached_key(|&k| (code(&tri[k]), k));
        Some(LeafBoundary {
            tet: keep.iter().map(|&k| tet[k]).collect(),
            tri: keep.iter().map(|&k| tri[k]).collect(),
        })
    }

    pub fn len(&self) -> usize {
        self.tri.len()
    }

    pub fn is_empty(&self) -> bool {
        self.tri.is_empty()
    }

    /// Extra precedence edges `(before, after)` for this view and drawing direction, and how
    /// many pairs needed the big-integer fallback.
    pub fn constraints(&self, mesh: &TetMesh, cam: &Camera, ftb: bool) -> (Vec<(u32, u32)>, usize) {
        let view = cam.viewpoint();
        let pts = &mesh.points;
        let p = |v: u32| &pts[v as usize];
        // +1: exit face (the eye is on the tet's side), -1: entry face, 0: edge-on (no ray
        // crosses its interior, so it constrains nothing).
        let kind: Vec<i8> = self
            .tri
            .par_iter()
            .map(|f| eye_side(&view, p(f[0]), p(f[1]), p(f[2])))
            .collect();
        let frame = cam.frame();
        let proj: Vec<Option<Proj>> = self
            .tri
            .par_iter()
            .zip(kind.par_iter())
            .map(|(f, &k)| {
                if k == 0 {
                    return None;
                }
                project(&view, &frame, [p(f[0]), p(f[1]), p(f[2])])
            })
            .collect();
        let exits: Vec<u32> = (0..self.tri.len() as u32)
            .filter(|&k| kind[k as usize] > 0 && proj[k as usize].is_some())
            .collect();
        let entries: Vec<u32> = (0..self.tri.len() as u32)
            .filter(|&k| kind[k as usize] < 0 && proj[k as usize].is_some())
            .collect();
        if exits.is_empty() || entries.is_empty() {
            return (Vec::new(), 0);
        }
        let bx = |k: u32| -> &[f64; 4] {
            match &proj[k as usize] {
                Some(q) => &q.bbox,
                None => &EMPTY_BOX,
            }
        };
        // A grid over the finite part of the boxes; perspective windows are clamped (far
        // off-axis and unbounded boxes share the border cells, which keeps the search
        // conservative).
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for &k in exits.iter().chain(entries.iter()) {
            let b = bx(k);
            for (a, (x0, x1)) in [(b[0], b[2]), (b[1], b[3])].into_iter().enumerate() {
                for x in [x0, x1] {
                    if x.is_finite() {
                        lo[a] = lo[a].min(x);
                        hi[a] = hi[a].max(x);
                    }
                }
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
        // Boxes covering many cells (faces reaching behind the eye, or huge on screen) are kept
        // out of the grid and tried against every face of the other kind instead.
        let wide =
            |(x0, x1, y0, y1): (usize, usize, usize, usize)| (x1 - x0 + 1) * (y1 - y0 + 1) > 4 * g;
        let mut count = vec![0u32; g * g + 1];
        // Each exit's cell range, found once: the scan below compares cells as integers.
        let (wide_exits, binned): (Vec<_>, Vec<_>) = exits
            .iter()
            .map(|&k| (k, range(bx(k))))
            .partition(|&(_, r)| wide(r));
        let wide_exits: Vec<u32> = wide_exits.into_iter().map(|(k, _)| k).collect();
        for &(_, (x0, x1, y0, y1)) in &binned {
            for y in y0..=y1 {
                for x in x0..=x1 {
                    count[y * g + x + 1] += 1;
                }
            }
        }
        for i in 0..g * g {
            count[i + 1] += count[i];
        }
        let mut fill = count.clone();
        // The bins hold what the scan tests (the box and its low cell) next to the face, so a
        // candidate costs no look-up in `proj` and no division: one entry face meets dozens of
        // exits that the tests below reject.
        let mut bins = vec![Binned::default(); count[g * g] as usize];
        for &(k, (x0, x1, y0, y1)) in &binned {
            let e = Binned {
                k,
                lo: [x0 as u32, y0 as u32],
                bbox: *bx(k),
            };
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let s = &mut fill[y * g + x];
                    bins[*s as usize] = e;
                    *s += 1;
                }
            }
        }
        let ctx = PairCtx {
            pts,
            tri: &self.tri,
            view,
            proj: &proj,
            exact_calls: AtomicUsize::new(0),
        };
        let disjoint =
            |a: &[f64; 4], b: &[f64; 4]| a[0] > b[2] || b[0] > a[2] || a[1] > b[3] || b[1] > a[3];
        let mut out: Vec<(u32, u32)> = entries
            .par_iter()
            .with_min_len(64)
            .flat_map_iter(|&gk| {
                let mut found = Vec::new();
                let gb = self.tet[gk as usize];
                let b = bx(gk);
                let mut consider = |fk: u32, fb: &[f64; 4]| {
                    let fa = self.tet[fk as usize];
                    if fa != gb && !disjoint(fb, b) && ctx.exit_in_front(fk as usize, gk as usize) {
                        found.push(if ftb { (fa, gb) } else { (gb, fa) });
                    }
                };
                let r = range(b);
                if wide(r) {
                    for &fk in &exits {
                        consider(fk, bx(fk));
                    }
                    return found;
                }
                let (x0, x1, y0, y1) = r;
                for y in y0..=y1 {
                    for x in x0..=x1 {
                        let bin = y * g + x;
                        for e in &bins[count[bin] as usize..count[bin + 1] as usize] {
                            // Test each pair once: in the cell holding the low corner of the
                            // boxes' overlap. `cell` does not decrease, so the cell of the
                            // larger coordinate is the larger of the two cells.
                            if (e.lo[0] as usize).max(x0) != x || (e.lo[1] as usize).max(y0) != y {
                                continue;
                            }
                            consider(e.k, &e.bbox);
                        }
                    }
                }
                for &fk in &wide_exits {
                    consider(fk, bx(fk));
                }
                found
            })
            .collect();
        out.par_sort_unstable();
        out.dedup();
        (out, ctx.exact_calls.into_inner())
    }
}

/// The low 10 bits of `x` spread to every third bit (a Morton code's one axis).
fn spread_bits(x: u32) -> u32 {
    let mut x = x & 0x3ff;
    x = (x | x << 16) & 0x030000ff;
    x = (x | x << 8) & 0x0300f00f;
    x = (x | x << 4) & 0x030c30c3;
    (x | x << 2) & 0x09249249
}

/// An exit face in a grid cell, with what the scan tests before looking further.
#[derive(Clone, Copy, Default)]
struct Binned {
    k: u32,
    /// The cell of the box's low corner.
    lo: [u32; 2],
    bbox: [f64; 4],
}

const UNKNOWN_DEPTH: [f64; 2] = [f64::NEG_INFINITY, f64::INFINITY];

const EMPTY_BOX: [f64; 4] = [
    f64::INFINITY,
    f64::INFINITY,
    f64::NEG_INFINITY,
    f64::NEG_INFINITY,
];

/// A face seen from the viewpoint, in the camera's screen coordinates (`x . r`, `x . u`, over
/// the depth `x . f` for perspective).
struct Proj {
    /// A box holding the screen image of every forward ray through the face: the corners'
    /// images grown by their rounding bound, open towards infinity on the sides where the face
    /// reaches the eye's plane.
    bbox: [f64; 4],
    /// The corners' images and a bound on their absolute error, when every corner is surely in
    /// front of the eye (always, for orthographic views): then the image is this triangle.
    tri: Option<([[f64; 2]; 3], f64)>,
    /// Bounds on the depth along the view direction of every point of the face, where `tri` is
    /// known (else infinite). On one ray from the eye (or along the view direction) depth grows
    /// with the distance travelled, so a face wholly shallower than another is met first on
    /// every ray through both.
    depth: [f64; 2],
}

/// Depth bounds of corners at depths `z` with absolute error at most `err` each.
fn depth_range(z: [f64; 3], err: [f64; 3]) -> [f64; 2] {
    let lo = (0..3).map(|i| z[i] - err[i]).fold(f64::INFINITY, f64::min);
    let hi = (0..3)
        .map(|i| z[i] + err[i])
        .fold(f64::NEG_INFINITY, f64::max);
    // Computing the bounds rounds too: widen by one unit of it each way.
    [lo - EPS * lo.abs(), hi + EPS * hi.abs()]
}

/// The screen image of one face, or `None` when it is surely behind the eye.
fn project(
    view: &Viewpoint,
    frame: &([f64; 3], [f64; 3], [f64; 3]),
    q: [&[f64; 3]; 3],
) -> Option<Proj> {
    let (r, u, fw) = frame;
    let mut bbox = EMPTY_BOX;
    let mut grow = |x: f64, y: f64, d: f64| {
        bbox = [
            bbox[0].min(x - d),
            bbox[1].min(y - d),
            bbox[2].max(x + d),
            bbox[3].max(y + d),
        ];
    };
    match view {
        Viewpoint::Direction(_) => {
            let c = q.map(|x| [dot(x, r), dot(x, u)]);
            // Each dot product: a few roundings of terms no larger than |x|_1 (|r|, |u| ~ 1).
            let errs = q.map(|x| 8.0 * EPS * (x[0].abs() + x[1].abs() + x[2].abs()));
            let d = errs.iter().copied().fold(0.0, f64::max);
            for s in &c {
                grow(s[0], s[1], d);
            }
            Some(Proj {
                bbox,
                tri: Some((c, d)),
                // `fw` is the view direction normalized, so depth grows along every ray.
                depth: depth_range(q.map(|x| dot(x, fw)), errs),
            })
        }
        Viewpoint::Eye(e) => {
            let rel = q.map(|x| sub(x, e));
            // Lateral coordinates and depth, each with the same absolute error bound.
            let lat = rel.map(|x| [dot(&x, r), dot(&x, u), dot(&x, fw)]);
            let err = rel.map(|x| 8.0 * EPS * (x[0].abs() + x[1].abs() + x[2].abs()));
            let front: [bool; 3] = std::array::from_fn(|i| lat[i][2] > 2.0 * err[i]);
            let behind: [bool; 3] = std::array::from_fn(|i| lat[i][2] < -2.0 * err[i]);
            if behind.iter().all(|&b| b) {
                return None;
            }
            let mut img = [[0.0; 2]; 3];
            let mut dmax: f64 = 0.0;
            for i in 0..3 {
                if !front[i] {
                    continue;
                }
                let [x, y, z] = lat[i];
                let (px, py) = (x / z, y / z);
                // |X'/Z' - X/Z| <= 2 err (|X| + Z) / Z^2 for |Z' - Z|, |X' - X| <= err <= Z / 2,
                // plus the division's own rounding.
                let d = 2.0 * err[i] * (x.abs() + y.abs() + z) / (z * z)
                    + 2.0 * EPS * (px.abs() + py.abs());
                img[i] = [px, py];
                dmax = dmax.max(d);
                grow(px, py, d);
            }
            if front.iter().all(|&f| f) {
                return Some(Proj {
                    bbox,
                    tri: Some((img, dmax)),
                    // Every corner surely in front: depth grows along each ray through the face.
                    depth: depth_range(lat.map(|x| x[2]), err),
                });
            }
            if !front.iter().any(|&f| f) {
                // Only corners near the eye's plane reach the front: no useful box.
                return Some(Proj {
                    bbox: [
                        f64::NEG_INFINITY,
                        f64::NEG_INFINITY,
                        f64::INFINITY,
                        f64::INFINITY,
                    ],
                    tri: None,
                    depth: UNKNOWN_DEPTH,
                });
            }
            // Along an edge that reaches the eye's plane the image runs off to infinity on the
            // side of the lateral coordinate where it gets there (the image of a segment is
            // monotone); elsewhere the corners in front bound it.
            for i in 0..3 {
                let j = (i + 1) % 3;
                if (front[i] && front[j]) || (behind[i] && behind[j]) {
                    continue;
                }
                let d = err[i].max(err[j]);
                for a in 0..2 {
                    if lat[i][a].max(lat[j][a]) + d > 0.0 {
                        bbox[2 + a] = f64::INFINITY;
                    }
                    if lat[i][a].min(lat[j][a]) - d < 0.0 {
                        bbox[a] = f64::NEG_INFINITY;
                    }
                }
            }
            Some(Proj {
                bbox,
                tri: None,
                depth: UNKNOWN_DEPTH,
            })
        }
    }
}

struct PairCtx<'a> {
    pts: &'a [[f64; 3]],
    tri: &'a [[u32; 3]],
    view: Viewpoint,
    proj: &'a [Option<Proj>],
    exact_calls: AtomicUsize,
}

impl PairCtx<'_> {
    fn p(&self, v: u32) -> &[f64; 3] {
        &self.pts[v as usize]
    }

    /// Whether some ray from the eye crosses exit face `f` and then entry face `g` (exact).
    fn exit_in_front(&self, f: usize, g: usize) -> bool {
        let (ft, gt) = (self.tri[f], self.tri[g]);
        let (ta, tb) = match (&self.proj[f], &self.proj[g]) {
            // The entry face wholly shallower: every ray meets it first.
            (Some(a), Some(b)) if b.depth[1] < a.depth[0] => return false,
            (Some(a), Some(b)) => (&a.tri, &b.tri),
            _ => return false,
        };
        // Depth first (three orient3d each): a face wholly on the eye's side of the other's
        // plane comes first on every ray through both, so nothing else needs deciding.
        // g against f's plane: for an exit face the eye is on the inner (positive) side. Most
        // pairs whose boxes overlap are the two sides of one solid part, the entry face in
        // front: this test, before the 2-D one, settles them (both are exact filters, so
        // their order changes no answer).
        let side_f = ft_side(self.pts, &ft, &gt);
        if side_f == Side::Inner {
            return false;
        }
        if let (Some(a), Some(b)) = (ta, tb) {
            if float_separated(a, b) {
                return false;
            }
        }
        // f against g's plane: for an entry face the eye is on the outer (negative) side.
        let side_g = if side_f == Side::Mixed {
            ft_side(self.pts, &gt, &ft)
        } else {
            Side::Mixed
        };
        if side_g == Side::Inner {
            return false;
        }
        // A plane through the eye and an edge with the two faces on either side (touching
        // allowed) leaves no ray through both interiors. Skipped when a corner's image is surely
        // inside the other image (then the interiors overlap).
        let sure = match (ta, tb) {
            (Some(a), Some(b)) => float_overlapping(a, b),
            _ => false,
        };
        if !sure && (self.edge_plane_separated(&ft, &gt) || self.edge_plane_separated(&gt, &ft)) {
            return false;
        }
        if ta.is_none() || tb.is_none() {
            // Not both surely in front: the rays through them need not fit in one half-space, so
            // edge planes are not the only candidates; planes through a corner of each are the
            // others. Whatever they leave is decided exactly.
            if self.corner_plane_separated(&ft, &gt) {
                return false;
            }
            return self.exact(&ft, &gt);
        }
        // Both in front and not separated: the images' interiors overlap.
        match (side_f, side_g) {
            (Side::Outer | Side::Coplanar, _) | (_, Side::Outer | Side::Coplanar) => true,
            _ => self
                .witness(&ft, &gt)
                .unwrap_or_else(|| self.exact(&ft, &gt)),
        }
    }

    /// Both faces in front, their images overlapping, and each plane cutting the other face:
    /// the depth order along one ray through the overlap, found with orient3d alone, or `None`
    /// when every candidate ray is degenerate. Faces that do not cross each other (boundary faces
    /// of a valid mesh meet only at shared edges and corners) have one order on every such ray.
    /// Candidates: a corner of one strictly inside the other's image, compared with the other's
    /// plane; an edge of each crossing properly on screen (both in front, so the crossing is on
    /// one ray), compared by the side of one edge's line against the plane through the other
    /// edge and one of its ends.
    fn witness(&self, ft: &[u32; 3], gt: &[u32; 3]) -> Option<bool> {
        let v = &self.view;
        let (f, g) = (ft.map(|x| self.p(x)), gt.map(|x| self.p(x)));
        // The eye's side of each plane, in orient3d's sign.
        let sf = eye_side(v, f[0], f[1], f[2]);
        let sg = eye_side(v, g[0], g[1], g[2]);
        let sign = |x: f64| (x > 0.0) as i8 - (x < 0.0) as i8;
        for x in &f {
            if (0..3).all(|i| eye_side(v, g[i], g[(i + 1) % 3], x) == sg) {
                let s = sign(orient3d(g[0], g[1], g[2], x));
                if s != 0 {
                    return Some(s == sg);
                }
            }
        }
        for x in &g {
            if (0..3).all(|i| eye_side(v, f[i], f[(i + 1) % 3], x) == sf) {
                let s = sign(orient3d(f[0], f[1], f[2], x));
                if s != 0 {
                    return Some(s == -sf);
                }
            }
        }
        for i in 0..3 {
            let (p, q) = (f[i], f[(i + 1) % 3]);
            for j in 0..3 {
                let (r, s) = (g[j], g[(j + 1) % 3]);
                let a1 = eye_side(v, p, q, r);
                if a1 * eye_side(v, p, q, s) != -1
                    || eye_side(v, r, s, p) * eye_side(v, r, s, q) != -1
                {
                    continue;
                }
                // rs lies behind pq where they cross when s is on the other side of the plane
                // (p, q, r) from the eye (r is on it, so the crossing point is on s's side).
                let o = sign(orient3d(p, q, r, s));
                if o != 0 {
                    return Some(o == -a1);
                }
            }
        }
        None
    }

    fn exact(&self, ft: &[u32; 3], gt: &[u32; 3]) -> bool {
        self.exact_calls.fetch_add(1, Relaxed);
        let f = ft.map(|v| *self.p(v));
        let g = gt.map(|v| *self.p(v));
        exact::relation(&self.view, &f, &g).f_first
    }

    /// Whether an edge plane of `t` (through the eye, or along the view direction) leaves all of
    /// `o` on the side away from `t`, touching allowed. Exact (orient3d or exact normal signs).
    fn edge_plane_separated(&self, t: &[u32; 3], o: &[u32; 3]) -> bool {
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

    /// Whether a plane through the eye, a corner of `a` and a corner of `b` has `a` on one side
    /// and `b` on the other (touching allowed; a degenerate plane separates nothing).
    fn corner_plane_separated(&self, a: &[u32; 3], b: &[u32; 3]) -> bool {
        (0..3).any(|i| {
            (0..3).any(|j| {
                let (u, w) = (self.p(a[i]), self.p(b[j]));
                let sa = [1, 2].map(|k| eye_side(&self.view, u, w, self.p(a[(i + k) % 3])));
                let sb = [1, 2].map(|k| eye_side(&self.view, u, w, self.p(b[(j + k) % 3])));
                let one = |x: &[i8; 2], y: &[i8; 2]| {
                    x.iter().all(|&s| s >= 0)
                        && x.iter().any(|&s| s > 0)
                        && y.iter().all(|&s| s <= 0)
                        && y.iter().any(|&s| s < 0)
                };
                one(&sa, &sb) || one(&sb, &sa)
            })
        })
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
        // A shared corner lies on the plane: exactly 0, without the exact arithmetic orient3d
        // falls back to for a zero (adjacent faces share one or two).
        if t.contains(&v) {
            continue;
        }
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

/// `orient2(p, q, x)` and a bound on its error when every coordinate is off by at most `d`.
fn orient2_bound(p: &[f64; 2], q: &[f64; 2], x: &[f64; 2], d: f64) -> (f64, f64) {
    let (ux, uy) = (q[0] - p[0], q[1] - p[1]);
    let (vx, vy) = (x[0] - p[0], x[1] - p[1]);
    let (a, b) = (ux * vy, uy * vx);
    let bound = 2.0 * d * (ux.abs() + uy.abs() + vx.abs() + vy.abs())
        + 4.0 * d * d
        + 4.0 * EPS * (a.abs() + b.abs());
    (a - b, bound)
}

/// Whether a corner of either projected triangle is surely strictly inside the other, beyond the
/// error bound of the projected corners (then their interiors overlap; "no" decides nothing).
fn float_overlapping(a: &([[f64; 2]; 3], f64), b: &([[f64; 2]; 3], f64)) -> bool {
    let d = a.1.max(b.1);
    let inside = |s: &[[f64; 2]; 3], x: &[f64; 2]| -> bool {
        let (area, ab) = orient2_bound(&s[0], &s[1], &s[2], d);
        if area.abs().partial_cmp(&ab) != Some(std::cmp::Ordering::Greater) {
            return false;
        }
        let sg = area.signum();
        (0..3).all(|i| {
            let (v, bound) = orient2_bound(&s[i], &s[(i + 1) % 3], x, d);
            sg * v > bound
        })
    };
    a.0.iter().any(|x| inside(&b.0, x)) || b.0.iter().any(|x| inside(&a.0, x))
}

/// Whether an edge line of either projected triangle surely separates them: by more than the
/// error bound of the projected corners (so only a filter: "no" decides nothing).
fn float_separated(a: &([[f64; 2]; 3], f64), b: &([[f64; 2]; 3], f64)) -> bool {
    let d = a.1.max(b.1);
    let sep = |s: &[[f64; 2]; 3], o: &[[f64; 2]; 3]| -> bool {
        let (area, ab) = orient2_bound(&s[0], &s[1], &s[2], d);
        // NaN or within the bound: the orientation itself is unsure.
        if area.abs().partial_cmp(&ab) != Some(std::cmp::Ordering::Greater) {
            return false;
        }
        let sg = area.signum();
        (0..3).any(|i| {
            let (p, q) = (&s[i], &s[(i + 1) % 3]);
            o.iter().all(|x| {
                let (v, bound) = orient2_bound(p, q, x, d);
                sg * v < -bound
            })
        })
    };
    sep(&a.0, &b.0) || sep(&b.0, &a.0)
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
    use proptest::prelude::*;

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
    fn spread_bits_interleaves_three_axes() {
        assert_eq!(spread_bits(0), 0);
        assert_eq!(spread_bits(0b1), 0b1);
        assert_eq!(spread_bits(0b11), 0b1001);
        assert_eq!(spread_bits(0b1010), 0b10_0000_1000);
        assert_eq!(spread_bits(0x3ff), 0x0924_9249);
        // Only the low 10 bits count, and the three axes never share a bit.
        assert_eq!(spread_bits(0x7ff), spread_bits(0x3ff));
        let all = spread_bits(0x3ff) | spread_bits(0x3ff) << 1 | spread_bits(0x3ff) << 2;
        assert_eq!(all, (1 << 30) - 1);
        assert_eq!(spread_bits(0x3ff) & (spread_bits(0x3ff) << 1), 0);
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
    fn float_separation_is_a_filter() {
        let a = ([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], 1e-12);
        let b = ([[0.2, 0.2], [2.0, 0.2], [0.2, 2.0]], 1e-12);
        let c = ([[2.0, 2.0], [3.0, 2.0], [2.0, 3.0]], 1e-12);
        // Touching along an edge: not surely separated (the exact tests decide).
        let d = ([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]], 1e-12);
        assert!(!float_separated(&a, &b));
        assert!(float_separated(&a, &c));
        assert!(!float_separated(&a, &d));
    }

    fn tri_strategy() -> impl Strategy<Value = [[f64; 3]; 3]> {
        prop::array::uniform3(prop::array::uniform3(-2.0f64..2.0))
    }

    /// Two triangles on either side of the plane `z = h` (so they cannot cross): whatever ray
    /// crosses both meets first the one on the eye's side.
    fn split_pair() -> impl Strategy<Value = ([[f64; 3]; 3], [[f64; 3]; 3], f64)> {
        (tri_strategy(), tri_strategy(), -0.5f64..0.5).prop_map(|(mut a, mut b, h)| {
            for p in a.iter_mut() {
                p[2] = h + 0.05 + p[2].abs();
            }
            for p in b.iter_mut() {
                p[2] = h - 0.05 - p[2].abs();
            }
            (a, b, h)
        })
    }

    fn ray_hits(o: &[f64; 3], d: &[f64; 3], t: &[[f64; 3]; 3]) -> Option<f64> {
        // Moller-Trumbore with a margin: only clear interior hits count.
        let e1 = sub(&t[1], &t[0]);
        let e2 = sub(&t[2], &t[0]);
        let pv = crate::geom::cross(d, &e2);
        let det = dot(&e1, &pv);
        if det.abs() < 1e-9 {
            return None;
        }
        let s = sub(o, &t[0]);
        let u = dot(&s, &pv) / det;
        let qv = crate::geom::cross(&s, &e1);
        let v = dot(d, &qv) / det;
        let w = dot(&e2, &qv) / det;
        (u > 1e-6 && v > 1e-6 && u + v < 1.0 - 1e-6 && w > 1e-6).then_some(w)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(400))]

        /// The exact relation against rays cast through a grid of directions, for eyes anywhere
        /// (faces in front, behind, or reaching behind the eye) and orthographic directions.
        #[test]
        fn exact_relation_agrees_with_sampled_rays(
            (a, b, h) in split_pair(),
            eye in prop::array::uniform3(-3.0f64..3.0),
            ortho in any::<bool>(),
        ) {
            let view = if ortho {
                Viewpoint::Direction([eye[0] * 0.1, eye[1] * 0.1, -1.0])
            } else {
                Viewpoint::Eye(eye)
            };
            let sa = eye_side(&view, &a[0], &a[1], &a[2]);
            let sb = eye_side(&view, &b[0], &b[1], &b[2]);
            prop_assume!(sa != 0 && sb != 0);
            let r = exact::relation(&view, &a, &b);
            let r2 = exact::relation(&view, &b, &a);
            prop_assert_eq!(r.overlap, r2.overlap);
            // The eye's side of z = h says which comes first on every ray through both.
            let a_first = match view {
                Viewpoint::Eye(e) => e[2] > h,
                Viewpoint::Direction(_) => true,
            };
            if r.overlap {
                prop_assert_eq!(r.f_first, a_first);
                prop_assert_eq!(r2.f_first, !a_first);
            }
            // Any sampled ray through both interiors must be seen by the exact test.
            let mut hit = false;
            for i in 0..24 {
                for j in 0..24 {
                    let (x, y) = (-3.0 + 6.0 * (i as f64 + 0.5) / 24.0, -3.0 + 6.0 * (j as f64 + 0.5) / 24.0);
                    let (o, d) = match view {
                        Viewpoint::Eye(e) => {
                            // Rays in all directions: through points on a sphere-ish grid.
                            (e, [x, y, if (i + j) % 2 == 0 { 1.0 } else { -1.0 }])
                        }
                        Viewpoint::Direction(v) => ([x, y, 10.0], v),
                    };
                    if let (Some(ta), Some(tb)) = (ray_hits(&o, &d, &a), ray_hits(&o, &d, &b)) {
                        hit = true;
                        prop_assert_eq!(ta < tb, a_first);
                    }
                }
            }
            if hit {
                prop_assert!(r.overlap, "a sampled ray crosses both: {:?}", r);
            }
        }

        /// The orient3d witness agrees with the exact relation on faces that do not cross, seen
        /// from eyes above them all or along a direction.
        #[test]
        fn witness_agrees_with_exact(
            (a, b, _h) in split_pair(),
            eye in prop::array::uniform3(-3.0f64..3.0),
            ortho in any::<bool>(),
        ) {
            let view = if ortho {
                Viewpoint::Direction([eye[0] * 0.3, eye[1] * 0.3, -1.0])
            } else {
                Viewpoint::Eye([eye[0], eye[1], 6.0 + eye[2].abs()])
            };
            prop_assume!(eye_side(&view, &a[0], &a[1], &a[2]) != 0);
            prop_assume!(eye_side(&view, &b[0], &b[1], &b[2]) != 0);
            let pts: Vec<[f64; 3]> = a.iter().chain(b.iter()).copied().collect();
            let ctx = PairCtx {
                pts: &pts,
                tri: &[[0, 1, 2], [3, 4, 5]],
                view,
                proj: &[],
                exact_calls: AtomicUsize::new(0),
            };
            for (f, g, x, y) in [([0, 1, 2], [3, 4, 5], &a, &b), ([3, 4, 5], [0, 1, 2], &b, &a)] {
                let r = exact::relation(&view, x, y);
                if r.overlap {
                    if let Some(w) = ctx.witness(&f, &g) {
                        prop_assert_eq!(w, r.f_first);
                    }
                }
            }
        }

        /// In front of the eye the orient3d edge planes decide overlap exactly: both must agree,
        /// and the float filter must never claim a separation that is not there.
        #[test]
        fn edge_planes_and_float_filter_agree_with_exact(
            a in tri_strategy(),
            b in tri_strategy(),
            ortho in any::<bool>(),
            snap in any::<bool>(),
        ) {
            let (mut a, mut b) = (a, b);
            for p in a.iter_mut().chain(b.iter_mut()) {
                p[2] = 1.0 + p[2].abs();
            }
            if snap {
                // Shared corners and collinear images: the touching cases.
                b[0] = a[0];
                b[1] = [2.0 * a[1][0], 2.0 * a[1][1], 2.0 * a[1][2]];
            }
            let view = if ortho {
                Viewpoint::Direction([0.1, -0.2, 1.0])
            } else {
                Viewpoint::Eye([0.1, -0.2, 0.0])
            };
            prop_assume!(eye_side(&view, &a[0], &a[1], &a[2]) != 0);
            prop_assume!(eye_side(&view, &b[0], &b[1], &b[2]) != 0);
            let pts: Vec<[f64; 3]> = a.iter().chain(b.iter()).copied().collect();
            let ctx = PairCtx {
                pts: &pts,
                tri: &[[0, 1, 2], [3, 4, 5]],
                view,
                proj: &[],
                exact_calls: AtomicUsize::new(0),
            };
            let sat = ctx.edge_plane_separated(&[0, 1, 2], &[3, 4, 5])
                || ctx.edge_plane_separated(&[3, 4, 5], &[0, 1, 2]);
            let r = exact::relation(&view, &a, &b);
            prop_assert_eq!(!sat, r.overlap);
            prop_assert!(!(ctx.corner_plane_separated(&[0, 1, 2], &[3, 4, 5]) && r.overlap));
            let mut cam = Camera {
                position: [0.1, -0.2, 0.0],
                focal: [0.1, -0.2, 1.0],
                up: [0.0, 1.0, 0.0],
                view_angle: 60.0,
                parallel: ortho,
                parallel_scale: 1.0,
            };
            if ortho {
                cam.position = [0.0, 0.0, -10.0];
                cam.focal = [0.1, -0.2, -9.0];
            }
            let frame = cam.frame();
            let pa = project(&view, &frame, [&a[0], &a[1], &a[2]]).unwrap();
            let pb = project(&view, &frame, [&b[0], &b[1], &b[2]]).unwrap();
            let (ta, tb) = (pa.tri.unwrap(), pb.tri.unwrap());
            if float_separated(&ta, &tb) {
                prop_assert!(!r.overlap);
            }
            if float_overlapping(&ta, &tb) {
                prop_assert!(r.overlap);
            }
            if r.overlap {
                let (x, y) = (pa.bbox, pb.bbox);
                prop_assert!(!(x[0] > y[2] || y[0] > x[2] || x[1] > y[3] || y[1] > x[3]));
            }
            // A face wholly shallower is crossed first on every ray through both.
            if pb.depth[1] < pa.depth[0] {
                prop_assert!(!r.f_first);
            }
            if pa.depth[1] < pb.depth[0] {
                prop_assert!(!exact::relation(&view, &b, &a).f_first);
            }
            // The bounds hold the corners' depths (so every point's).
            for (p, t) in [(&pa, &a), (&pb, &b)] {
                for x in t.iter() {
                    let z = match view {
                        Viewpoint::Eye(e) => dot(&sub(x, &e), &frame.2),
                        Viewpoint::Direction(_) => dot(x, &frame.2),
                    };
                    prop_assert!(p.depth[0] <= z && z <= p.depth[1]);
                }
            }
        }
    }
}
