//! Visibility ordering of tets for a viewpoint: centroid (approximate), MPVO and K-D exact.
//!
//! [`Sorter::new`] builds the view-independent parts once (face adjacency, leaves, boundary
//! faces of non-convex leaves); [`Sorter::order`] is the per-frame call the renderer makes.

pub mod adjacency;
pub mod centroid;
pub mod check;
pub mod exact;
pub mod nonconvex;
pub mod peel;
pub mod side;

use anyhow::{bail, Result};
use rayon::prelude::*;
use serde::Serialize;
use std::borrow::Cow;
use std::sync::atomic::{AtomicU32, Ordering::Relaxed};
use std::time::Instant;

use crate::camera::{Camera, Viewpoint};
use crate::mesh::TetMesh;
use crate::partition::KdTree;
use adjacency::{face_vertices, Adjacency, NONE};

/// How to order the tets.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// VTK's vtkCellCenterDepthSort: tet centroids sorted by depth (approximate).
    Centroid,
    /// Face adjacency only, the whole mesh as one leaf (exact for convex acyclic meshes).
    Mpvo,
    /// The paper: per-leaf layer peeling plus the dependencies of non-convex leaves, leaves in
    /// the K-D tree's order for the eye.
    Kd,
}

/// Drawing order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum Direction {
    BackToFront,
    FrontToBack,
}

/// Counts that describe one sort.
#[derive(Clone, Debug, Default, Serialize)]
pub struct SortStats {
    pub method: Option<Method>,
    pub tets: usize,
    pub leaves: usize,
    /// Most layers of any leaf (leaves peel in parallel, so this is the critical path).
    pub layers: u32,
    /// Layers summed over leaves.
    pub layers_total: u64,
    /// Face constraints used (shared faces not seen edge-on).
    pub face_constraints: usize,
    /// Extra constraints between boundary faces of non-convex leaves.
    pub extra_constraints: usize,
    /// Pairs of boundary faces that needed the big-integer test (reaching behind the eye, or
    /// neither face's plane separating them).
    pub exact_fallbacks: usize,
    /// Seconds spent finding the extra constraints (included in `seconds`).
    pub extra_seconds: f64,
    pub nonconvex_leaves: usize,
    /// Visibility cycles (strongly connected components) broken.
    pub cycles: usize,
    pub cycle_tets: usize,
    pub broken_constraints: usize,
    /// Tets with a vertex outside their leaf's box (`kd` only): a tree that does not cut tets
    /// (leaves by tet centroid) lets them cross a split plane, where the leaf order may misplace
    /// them; 0 for a mesh split by `tetkit partition`.
    pub tets_outside_leaf: usize,
    pub seconds: f64,
}

/// A visibility order: `order[k]` is the tet drawn `k`-th; `layer[t]` and `leaf[t]` per tet
/// (layers count in the drawing direction within each leaf; 0 for `centroid`).
#[derive(Clone, Debug, Default)]
pub struct Order {
    pub order: Vec<u32>,
    pub layer: Vec<u32>,
    pub leaf: Vec<u32>,
    pub stats: SortStats,
}

impl Order {
    /// `rank[t]`: position of tet `t` in the drawing order (the `visibility_order` cell array).
    pub fn ranks(&self) -> Vec<u32> {
        let mut r = vec![0u32; self.order.len()];
        for (k, &t) in self.order.iter().enumerate() {
            r[t as usize] = k as u32;
        }
        r
    }
}

/// Everything about a mesh that does not depend on the view, built once.
pub struct Sorter<'m> {
    /// The mesh as sorted: the caller's, or a copy whose tets use welded point ids
    /// ([`TetMesh::welded_tets`]) when points coincide.
    mesh: Cow<'m, TetMesh>,
    adj: Adjacency,
    tree: KdTree,
    leaf_of: Vec<u32>,
    leaf_tets: Vec<Vec<u32>>,
    /// Bit `i`: the neighbour across face `i` exists and lies in the same leaf.
    same_leaf: Vec<u8>,
    /// Bit `i`: the neighbour across face `i` exists.
    any_neighbor: Vec<u8>,
    /// Bit `i`: a tet is in front across face `i` when the sign of `orient3d(face i in tet order,
    /// eye)` is positive (set) or negative (clear): the parity of sorting the face's vertex ids
    /// XOR [`Adjacency::positive_side`], so both tets of a face read one consistent decision.
    flip: Vec<u8>,
    /// `0..n`, the single leaf of `mpvo`.
    all_tets: Vec<u32>,
    /// Boundary faces of each non-convex leaf (`None` for convex leaves).
    leaf_boundary: Vec<Option<nonconvex::LeafBoundary>>,
    centroids: Vec<[f64; 3]>,
    bounds: crate::geom::Aabb,
    outside_leaf: usize,
}

impl<'m> Sorter<'m> {
    /// Builds adjacency (in parallel), assigns tets to the tree's leaves (the `leaf_id` cell array
    /// when it is valid, else by descending the tree with each tet's centroid), and finds the
    /// boundary faces of the leaves that are not convex. Without a tree there is one leaf.
    pub fn new(mesh: &'m TetMesh, tree: Option<&KdTree>) -> Result<Sorter<'m>> {
        Sorter::with_welded(mesh, tree, mesh.welded_tets().as_deref())
    }

    /// [`Sorter::new`] given the mesh's [`TetMesh::welded_tets`] (computed by the caller, who
    /// also needs them elsewhere).
    pub fn with_welded(
        mesh: &'m TetMesh,
        tree: Option<&KdTree>,
        welded: Option<&[[u32; 4]]>,
    ) -> Result<Sorter<'m>> {
        let n = mesh.tets.len();
        if n >= u32::MAX as usize / 4 {
            bail!("{n} tets: too many for 32-bit tet ids");
        }
        let np = mesh.points.len();
        if let Some((t, _)) = mesh
            .tets
            .iter()
            .enumerate()
            .find(|(_, tet)| tet.iter().any(|&v| v as usize >= np))
        {
            bail!("tet {t} refers to a point id beyond the {np} points");
        }
        // Coincident points are one point to the sort: the two copies of a face between
        // pieces stored apart become a shared face (an unwelded mesh of 8,640 tets took 5.8 s
        // and 682,775 extra constraints, its welded twin 0.003 s; mpvo could not order it).
        let mesh: Cow<'m, TetMesh> = match welded {
            Some(tets) => Cow::Owned(TetMesh {
                points: mesh.points.clone(),
                tets: tets.to_vec(),
                point_data: Default::default(),
                cell_data: mesh.cell_data.clone(),
                field_data: Vec::new(),
            }),
            None => Cow::Borrowed(mesh),
        };
        let adj = Adjacency::build(&mesh.points, &mesh.tets);
        let centroids: Vec<[f64; 3]> = mesh
            .tets
            .par_iter()
            .map(|t| {
                let p = t.map(|v| mesh.points[v as usize]);
                [0, 1, 2].map(|k| 0.25 * (p[0][k] + p[1][k] + p[2][k] + p[3][k]))
            })
            .collect();
        let tree = match tree {
            Some(t) => t.clone(),
            None => KdTree::single_leaf(mesh.bounds(), n as u64),
        };
        let nleaves = tree.num_leaves().max(1);
        let leaf_of = assign_leaves(&mesh, &tree, &centroids);
        let mut leaf_tets = vec![Vec::new(); nleaves];
        for (t, &l) in leaf_of.iter().enumerate() {
            leaf_tets[l as usize].push(t as u32);
        }
        let same_leaf: Vec<u8> = (0..n)
            .into_par_iter()
            .map(|t| {
                let mut bits = 0u8;
                for i in 0..4 {
                    let m = adj.neighbors[t][i];
                    if m != NONE && leaf_of[m as usize] == leaf_of[t] {
                        bits |= 1 << i;
                    }
                }
                bits
            })
            .collect();
        let leaf_boundary = leaf_tets
            .par_iter()
            .map(|tets| nonconvex::LeafBoundary::build(&mesh, &adj, &same_leaf, tets))
            .collect();
        let any_neighbor: Vec<u8> = adj
            .neighbors
            .par_iter()
            .map(|nb| (0..4).fold(0u8, |m, i| m | (((nb[i] != NONE) as u8) << i)))
            .collect();
        let outside_leaf = if nleaves > 1 {
            let node_of = tree.leaf_nodes();
            (0..n)
                .into_par_iter()
                .filter(|&t| {
                    let Some(node) = node_of
                        .get(leaf_of[t] as usize)
                        .and_then(|&i| tree.nodes.get(i as usize))
                    else {
                        return false;
                    };
                    let b = &node.bounds;
                    mesh.tets[t].iter().any(|&v| {
                        let p = &mesh.points[v as usize];
                        (0..3).any(|k| p[k] < b.min[k] || p[k] > b.max[k])
                    })
                })
                .count()
        } else {
            0
        };
        // Every frame reads these out of their order (points and neighbours by tet): in huge
        // pages those reads stop missing the TLB.
        crate::mem::collapse_huge(&mesh.points);
        crate::mem::collapse_huge(&mesh.tets);
        crate::mem::collapse_huge(&adj.neighbors);
        let flip: Vec<u8> = (0..n)
            .into_par_iter()
            .map(|t| {
                (0..4).fold(0u8, |bits, i| {
                    let f = face_vertices(&mesh.tets[t], i);
                    let odd = ((f[0] > f[1]) as u8 ^ (f[0] > f[2]) as u8 ^ (f[1] > f[2]) as u8) & 1;
                    bits | ((odd ^ (adj.positive_side[t] >> i & 1)) << i)
                })
            })
            .collect();
        let bounds = mesh.bounds();
        Ok(Sorter {
            mesh,
            flip,
            any_neighbor,
            all_tets: (0..n as u32).collect(),
            adj,
            tree,
            leaf_of,
            leaf_tets,
            same_leaf,
            leaf_boundary,
            centroids,
            bounds,
            outside_leaf,
        })
    }

    pub fn num_leaves(&self) -> usize {
        self.leaf_tets.len()
    }

    pub fn adjacency(&self) -> &Adjacency {
        &self.adj
    }

    pub fn tree(&self) -> &KdTree {
        &self.tree
    }

    /// Leaf of each tet.
    pub fn leaf_of(&self) -> &[u32] {
        &self.leaf_of
    }

    /// Tets with a vertex outside their leaf's box (see [`SortStats::tets_outside_leaf`]).
    pub fn tets_outside_leaf(&self) -> usize {
        self.outside_leaf
    }

    /// Faces shared by more than two tets (duplicated or overlapping tets): paired by side in
    /// the adjacency, but no order is exact between overlapping tets.
    pub fn nonmanifold_faces(&self) -> usize {
        self.adj.nonmanifold_faces
    }

    /// Number of leaves whose tets do not form a convex region.
    pub fn nonconvex_leaves(&self) -> usize {
        self.leaf_boundary.iter().filter(|b| b.is_some()).count()
    }

    /// The visibility order for one view.
    pub fn order(&self, cam: &Camera, method: Method, dir: Direction) -> Order {
        let start = Instant::now();
        let mut out = match method {
            Method::Centroid => centroid::order(&self.centroids, cam, dir),
            Method::Mpvo => self.peel_order(cam, dir, false),
            Method::Kd => self.peel_order(cam, dir, true),
        };
        out.stats.method = Some(method);
        out.stats.tets = self.mesh.tets.len();
        out.stats.seconds = start.elapsed().as_secs_f64();
        out
    }

    fn peel_order(&self, cam: &Camera, dir: Direction, kd: bool) -> Order {
        let viewpoint = cam.viewpoint();
        let view = &viewpoint;
        let mesh: &TetMesh = &self.mesh;
        let n = mesh.tets.len();
        let ftb = dir == Direction::FrontToBack;
        let nbr = &self.adj.neighbors;
        let mask_of = |t: usize| -> u8 {
            if kd {
                self.same_leaf[t]
            } else {
                self.any_neighbor[t]
            }
        };
        // One pass over tets: each tet judges all its faces itself (the four share their minors),
        // so no per-face array has to be read back across neighbours. Both tets of a face get the
        // same exact sign, so they always agree on who is in front. Bit i of `post`: the tet
        // across face i comes after this one; `indeg`: how many come before it.
        let flip = &self.flip;
        let bound = match view {
            Viewpoint::Eye(e) => side::eye_error_bound(&self.bounds, e),
            Viewpoint::Direction(_) => 0.0,
        };
        // The peel decrements `indeg` and writes `layer` all over: huge pages (see `mem`).
        let mut post: Vec<u8> = Vec::with_capacity(n);
        let mut indeg: Vec<AtomicU32> = Vec::with_capacity(n);
        crate::mem::huge_pages(&mut indeg);
        (0..n)
            .into_par_iter()
            .with_min_len(4096)
            .map(|t| {
                let (mut post, mut pre) = (0u8, 0u32);
                let mask = mask_of(t);
                if mask != 0 {
                    let (tet, pts) = (&mesh.tets[t], &mesh.points);
                    let p = [
                        pts[tet[0] as usize],
                        pts[tet[1] as usize],
                        pts[tet[2] as usize],
                        pts[tet[3] as usize],
                    ];
                    let s = side::tet_sides(view, &p, mask, bound);
                    let mut bits = mask;
                    while bits != 0 {
                        let i = bits.trailing_zeros() as usize;
                        bits &= bits - 1;
                        if s[i] == 0 {
                            continue; // seen edge-on: no constraint
                        }
                        let in_front = (s[i] > 0) == (flip[t] >> i & 1 == 1);
                        if in_front == ftb {
                            post |= 1 << i;
                        } else {
                            pre += 1;
                        }
                    }
                }
                (post, AtomicU32::new(pre))
            })
            .unzip_into_vecs(&mut post, &mut indeg);
        let face_constraints = post.par_iter().map(|b| b.count_ones() as usize).sum();
        let leaves: &[Vec<u32>] = if kd {
            &self.leaf_tets
        } else {
            std::slice::from_ref(&self.all_tets)
        };
        let leaf_of: Vec<u32> = if kd { self.leaf_of.clone() } else { vec![0; n] };
        // Dependencies adjacency misses: boundary faces of non-convex leaves overlapping on screen.
        let t_extra = Instant::now();
        let (mut extra, exact_fallbacks): (Vec<(u32, u32)>, usize) = if kd {
            let per_leaf: Vec<(Vec<(u32, u32)>, usize)> = self
                .leaf_boundary
                .par_iter()
                .filter_map(|b| b.as_ref())
                .map(|b| b.constraints(mesh, cam, ftb))
                .collect();
            let fallbacks = per_leaf.iter().map(|x| x.1).sum();
            (per_leaf.into_iter().flat_map(|x| x.0).collect(), fallbacks)
        } else {
            (Vec::new(), 0)
        };
        extra.par_sort_unstable();
        extra.dedup();
        let extra_seconds = t_extra.elapsed().as_secs_f64();
        let (extra_off, extra_to) = if extra.is_empty() {
            (Vec::new(), Vec::new())
        } else {
            let mut off = vec![0u32; n + 1];
            for &(a, b) in &extra {
                off[a as usize + 1] += 1;
                indeg[b as usize].fetch_add(1, Relaxed);
                post[a as usize] |= peel::HAS_EXTRA;
            }
            for i in 0..n {
                off[i + 1] += off[i];
            }
            (off, extra.iter().map(|e| e.1).collect::<Vec<u32>>())
        };
        let mut layer: Vec<AtomicU32> = Vec::with_capacity(n);
        crate::mem::huge_pages(&mut layer);
        (0..n)
            .into_par_iter()
            .map(|_| AtomicU32::new(peel::UNSET))
            .collect_into_vec(&mut layer);
        let g = peel::Graph {
            neighbors: nbr,
            post: &post,
            extra_off: &extra_off,
            extra_to: &extra_to,
        };
        let results: Vec<peel::PeelResult> = leaves
            .par_iter()
            .map(|tets| peel::peel(&g, tets, &indeg, &layer))
            .collect();
        let layer: Vec<u32> = layer.into_iter().map(|a| a.into_inner()).collect();
        let mut leaf_order: Vec<u32> = if kd {
            self.tree.leaf_order_front_to_back(view)
        } else {
            vec![0]
        };
        // A tree that does not list every leaf would drop tets: append any missing leaf.
        let mut listed = vec![false; leaves.len()];
        leaf_order.retain(|&l| {
            (l as usize) < leaves.len() && !std::mem::replace(&mut listed[l as usize], true)
        });
        for (l, seen) in listed.iter().enumerate() {
            if !seen {
                leaf_order.push(l as u32);
            }
        }
        if !ftb {
            leaf_order.reverse();
        }
        // Within a leaf: by layer, then by tet id (deterministic), by counting sort, every leaf
        // into its own range of the order.
        let mut order: Vec<AtomicU32> = Vec::with_capacity(n);
        crate::mem::huge_pages(&mut order);
        (0..n)
            .into_par_iter()
            .map(|_| AtomicU32::new(0))
            .collect_into_vec(&mut order);
        let mut at = Vec::with_capacity(leaf_order.len());
        let mut acc = 0usize;
        for &l in &leaf_order {
            at.push(acc);
            acc += leaves[l as usize].len();
        }
        leaf_order.par_iter().zip(&at).for_each(|(&l, &start)| {
            let tets = &leaves[l as usize];
            let nl = results[l as usize].layers as usize;
            by_layer(tets, &layer, nl, &order[start..start + tets.len()]);
        });
        let order: Vec<u32> = order.into_iter().map(|a| a.into_inner()).collect();
        let mut stats = SortStats {
            leaves: leaves.len(),
            face_constraints,
            extra_constraints: extra.len(),
            exact_fallbacks,
            extra_seconds,
            nonconvex_leaves: if kd { self.nonconvex_leaves() } else { 0 },
            tets_outside_leaf: if kd { self.outside_leaf } else { 0 },
            ..Default::default()
        };
        for r in &results {
            stats.layers = stats.layers.max(r.layers);
            stats.layers_total += r.layers as u64;
            stats.cycles += r.cycles;
            stats.cycle_tets += r.cycle_tets;
            stats.broken_constraints += r.broken_constraints;
        }
        Order {
            order,
            layer,
            leaf: leaf_of,
            stats,
        }
    }
}

/// Writes `tets` (ascending ids, layers below `nl`) into `out` by layer, then by id: a counting
/// sort, in parallel chunks for a big leaf. Each chunk's share of a layer goes after the earlier
/// chunks' share, so the result does not depend on the number of chunks.
fn by_layer(tets: &[u32], layer: &[u32], nl: usize, out: &[AtomicU32]) {
    let parts = if tets.len() >= 1 << 16 {
        rayon::current_num_threads()
    } else {
        1
    };
    let chunks: Vec<&[u32]> = tets.chunks(tets.len().div_ceil(parts).max(1)).collect();
    let hist: Vec<Vec<usize>> = chunks
        .par_iter()
        .map(|c| {
            let mut h = vec![0usize; nl];
            for &t in *c {
                h[layer[t as usize] as usize] += 1;
            }
            h
        })
        .collect();
    let mut starts = vec![vec![0usize; nl]; chunks.len()];
    let mut acc = 0usize;
    for l in 0..nl {
        for (s, h) in starts.iter_mut().zip(&hist) {
            s[l] = acc;
            acc += h[l];
        }
    }
    chunks.par_iter().zip(starts).for_each(|(c, mut start)| {
        for &t in *c {
            let s = &mut start[layer[t as usize] as usize];
            out[*s].store(t, Relaxed);
            *s += 1;
        }
    });
}

/// Leaf of each tet: the mesh's `leaf_id` cell array when it names valid leaves, otherwise the
/// leaf whose box holds the tet's centroid (descending the tree; ties go left, as the tree's
/// convention puts tets with every vertex at the plane's coordinate on the left).
fn assign_leaves(mesh: &TetMesh, tree: &KdTree, centroids: &[[f64; 3]]) -> Vec<u32> {
    let n = mesh.tets.len();
    let nleaves = tree.num_leaves();
    if nleaves <= 1 {
        return vec![0; n];
    }
    if let Some(a) = mesh.cell_data.get("leaf_id") {
        if a.components == 1 && a.data.len() == n {
            let ids: Vec<f64> = a.data.to_f64_vec();
            if ids
                .iter()
                .all(|&x| x >= 0.0 && x < nleaves as f64 && x.fract() == 0.0)
            {
                return ids.iter().map(|&x| x as u32).collect();
            }
        }
    }
    centroids
        .par_iter()
        .map(|c| {
            let mut i = 0usize;
            for _ in 0..=tree.nodes.len() {
                let Some(node) = tree.nodes.get(i) else {
                    break;
                };
                match (node.split, node.leaf_id) {
                    (Some(s), _) => {
                        i = if c[s.axis as usize] <= s.position {
                            s.left as usize
                        } else {
                            s.right as usize
                        };
                    }
                    (None, Some(l)) => return l.min(nleaves as u32 - 1),
                    (None, None) => break,
                }
            }
            0
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::{jitter, structured_grid};
    use adjacency::sorted_face;

    /// Each tet's own decision (four shared minors, `flip`) is the per-face one: the exact side
    /// of the sorted face against the side the tet lies on, and zero exactly when that is zero.
    #[test]
    fn per_tet_decisions_match_per_face_ones() {
        let n = 5;
        let plain = structured_grid([n, n, n], [0.0; 3], [1.0; 3]);
        let mut jittered = plain.clone();
        jitter(&mut jittered, [n, n, n], 0.2, 11);
        for mesh in [&plain, &jittered] {
            let views = [
                Viewpoint::Eye([2.3, 1.7, 1.9]),
                // A mesh vertex: the faces around it contain the eye.
                Viewpoint::Eye(mesh.points[43]),
                // On grid planes of the plain grid (face planes of many of its tets).
                Viewpoint::Eye([mesh.points[43][0], mesh.points[43][1], 7.5]),
                Viewpoint::Eye([0.43, 0.51, 0.37]),
                Viewpoint::Eye([1e7 + 0.1, -3e6, 0.2]),
                Viewpoint::Direction([1.0, 0.0, 0.0]),
                Viewpoint::Direction([0.3, -0.7, 0.2]),
            ];
            let s = Sorter::new(mesh, None).unwrap();
            let bound = |v: &Viewpoint| match v {
                Viewpoint::Eye(e) => side::eye_error_bound(&s.bounds, e),
                Viewpoint::Direction(_) => 0.0,
            };
            let mut zeros = 0;
            for v in &views {
                for (t, tet) in mesh.tets.iter().enumerate() {
                    let p = tet.map(|i| mesh.points[i as usize]);
                    let sides = side::tet_sides(v, &p, 15, bound(v));
                    for (i, &si) in sides.iter().enumerate() {
                        if s.adj.neighbors[t][i] == NONE {
                            continue;
                        }
                        let f = sorted_face(tet, i);
                        let want = side::eye_side(
                            v,
                            &mesh.points[f[0] as usize],
                            &mesh.points[f[1] as usize],
                            &mesh.points[f[2] as usize],
                        );
                        assert_eq!(si == 0, want == 0, "tet {t} face {i} {v:?}");
                        if want == 0 {
                            zeros += 1;
                            continue;
                        }
                        let old = (want > 0) == (s.adj.positive_side[t] >> i & 1 == 1);
                        let new = (si > 0) == (s.flip[t] >> i & 1 == 1);
                        assert_eq!(old, new, "tet {t} face {i} {v:?}");
                    }
                }
            }
            assert!(zeros > 0, "an eye at a vertex sees faces edge-on");
        }
    }
}
