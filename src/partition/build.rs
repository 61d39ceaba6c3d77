//! Building the K-D partition: nodes are split level by level (plane searches of one level run in
//! parallel), each cut splits the node's crossing tets and, to keep the whole mesh conforming, the
//! tets of other nodes that share a cut edge on the node's box faces; then the split mesh is
//! assembled leaf by leaf with its data arrays and the tree.
//!
//! Why neighbours are split too: a face lying on an earlier split plane is shared by tets on both
//! sides of it. When a later plane on one side crosses such a face, the tet across it must receive
//! the same new vertices, or the mesh would get hanging vertices. Every such tet lies wholly in its
//! own node (the cut face is on the node's boundary), so cutting it along the marked edges (one
//! edge: bisection; two edges of a face: the same tet + pyramid pattern as case b) keeps it inside
//! its box and its node, and adds no vertex elsewhere.

use std::time::Instant;

use anyhow::{bail, Result};
use formats::{ArrayData, DataArray};
use rayon::prelude::*;
use serde::Serialize;

use super::search::{choose_plane, Candidate, SearchParams, Strategy};
use super::split::{crosses, edge_point, side, split_tet, Pieces};
use super::tree::{KdNode, KdTree, Split};
use crate::geom::{orient3d, Aabb};
use crate::mesh::TetMesh;

/// When to stop splitting.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// Split the largest nodes level by level until there are this many leaves (or no node has a
    /// qualifying plane).
    Leaves(usize),
    /// Split every node down to this depth (while planes qualify).
    Depth(u32),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PartitionOptions {
    pub stop: Stop,
    pub search: SearchParams,
}

impl Default for PartitionOptions {
    fn default() -> Self {
        PartitionOptions {
            stop: Stop::Leaves(8),
            search: SearchParams {
                strategy: Strategy::Paper,
                candidates: 16,
                phi: 1.0,
                eps: 0.2,
                balance_weight: 0.5,
            },
        }
    }
}

/// What one level of splitting did.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LevelReport {
    pub depth: u32,
    /// Nodes split at this depth, and nodes tried that had no qualifying plane.
    pub split: usize,
    pub no_plane: usize,
    /// Tets in the whole mesh after this level.
    pub tets_after: usize,
    pub seconds: f64,
}

/// What the partition did, for the user (stderr table or JSON).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PartitionReport {
    pub strategy: Strategy,
    pub leaves: usize,
    pub depth: u32,
    pub tets_before: usize,
    pub tets_after: usize,
    /// tets_after / tets_before.
    pub growth: f64,
    /// Largest leaf over the mean leaf (1 is perfect balance).
    pub balance: f64,
    pub largest_leaf: usize,
    pub smallest_leaf: usize,
    pub points_before: usize,
    pub points_after: usize,
    /// Input tets with negative volume, reoriented (two vertices swapped).
    pub reoriented: usize,
    /// Input tets with zero volume (kept as they are).
    pub degenerate: usize,
    /// Tets of neighbouring nodes split to keep the mesh conforming across box faces.
    pub neighbour_splits: usize,
    /// Neighbour tets with a marked-edge pattern that no plane makes (a non-conforming input);
    /// left unsplit, so the output is as conforming as the input.
    pub neighbour_skipped: usize,
    pub levels: Vec<LevelReport>,
    pub seconds: f64,
}

/// The split mesh (tets grouped by leaf, cell data `original_cell_id` and `leaf_id` added, the
/// tree in field data), the tree, and the report.
#[derive(Clone, Debug)]
pub struct Partitioned {
    pub mesh: TetMesh,
    pub tree: KdTree,
    /// For each output tet, the input tet it came from.
    pub original: Vec<u32>,
    pub report: PartitionReport,
}

pub const ORIGINAL_CELL_ID: &str = "original_cell_id";
pub const LEAF_ID: &str = "leaf_id";

struct BuildNode {
    bounds: Aabb,
    depth: u32,
    parent: Option<u32>,
    split: Option<Split>,
    tets: Vec<u32>,
}

struct Build {
    points: Vec<[f64; 3]>,
    /// One `(first endpoint, second endpoint, t)` per new point, in order.
    lerp: Vec<(usize, usize, f64)>,
    tets: Vec<[u32; 4]>,
    original: Vec<u32>,
    node_of: Vec<u32>,
    nodes: Vec<BuildNode>,
    root: Aabb,
    neighbour_splits: usize,
    neighbour_skipped: usize,
}

/// The exact sign of a tet's volume (positive in [`crate::geom::tet_volume`]'s convention).
pub fn volume_sign(p: &[[f64; 3]; 4]) -> f64 {
    -orient3d(&p[0], &p[1], &p[2], &p[3])
}

/// Partitions `input` (linear tets) with a K-D tree.
pub fn partition(input: &TetMesh, opts: &PartitionOptions) -> Result<Partitioned> {
    let start = Instant::now();
    if input.tets.len() > u32::MAX as usize / 8 {
        bail!(
            "{} tets is more than the partition handles (u32 ids with room for growth)",
            input.tets.len()
        );
    }
    if let Some(t) = input
        .tets
        .iter()
        .position(|t| t.iter().any(|&v| v as usize >= input.points.len()))
    {
        bail!(
            "tet {t} refers to a point beyond the {} points",
            input.points.len()
        );
    }
    let mut tets = input.tets.clone();
    let signs: Vec<f64> = tets
        .par_iter()
        .map(|t| volume_sign(&t.map(|v| input.points[v as usize])))
        .collect();
    let (mut reoriented, mut degenerate) = (0, 0);
    for (t, s) in tets.iter_mut().zip(&signs) {
        if *s < 0.0 {
            t.swap(2, 3);
            reoriented += 1;
        } else if *s == 0.0 {
            degenerate += 1;
        }
    }
    let n = tets.len();
    let root = input.bounds();
    let mut b = Build {
        points: input.points.clone(),
        lerp: Vec::new(),
        tets,
        original: (0..n as u32).collect(),
        node_of: vec![0; n],
        nodes: vec![BuildNode {
            bounds: root,
            depth: 0,
            parent: None,
            split: None,
            tets: (0..n as u32).collect(),
        }],
        root,
        neighbour_splits: 0,
        neighbour_skipped: 0,
    };
    let mut levels = Vec::new();
    let mut frontier = vec![0usize];
    let mut depth = 0u32;
    while !frontier.is_empty() {
        let leaves_now = b.nodes.iter().filter(|x| x.split.is_none()).count();
        let mut chosen = frontier.clone();
        chosen.sort_by_key(|&i| std::cmp::Reverse(b.nodes[i].tets.len()));
        match opts.stop {
            Stop::Depth(d) if depth >= d => break,
            Stop::Leaves(l) if leaves_now >= l => break,
            Stop::Leaves(l) => chosen.truncate(l - leaves_now),
            Stop::Depth(_) => {}
        }
        let t0 = Instant::now();
        let planes: Vec<Option<Candidate>> = chosen
            .par_iter()
            .map(|&i| choose_plane(&b.nodes[i].tets, &b.tets, &b.points, &opts.search))
            .collect();
        let mut next = Vec::new();
        let mut no_plane = 0;
        for (&i, plane) in chosen.iter().zip(&planes) {
            // A neighbour cut in this level may have put vertices near the plane chosen before
            // it: search again on the current tets then.
            let plane = match plane {
                Some(c) if b.clearance(i, c) < c.clearance => {
                    choose_plane(&b.nodes[i].tets, &b.tets, &b.points, &opts.search)
                }
                other => *other,
            };
            match plane {
                Some(c) => {
                    let (l, r) = b.cut_node(i, &c);
                    next.push(l);
                    next.push(r);
                }
                None => no_plane += 1,
            }
        }
        levels.push(LevelReport {
            depth,
            split: next.len() / 2,
            no_plane,
            tets_after: b.tets.len(),
            seconds: t0.elapsed().as_secs_f64(),
        });
        frontier = next;
        depth += 1;
    }
    Ok(b.finish(input, opts, reoriented, degenerate, levels, start))
}

impl Build {
    /// The distance along the plane's axis from the plane to the nearest vertex of node `n` not
    /// on it.
    fn clearance(&self, n: usize, c: &Candidate) -> f64 {
        let (k, p) = (c.axis as usize, c.position);
        self.nodes[n]
            .tets
            .par_iter()
            .flat_map_iter(|&t| self.tets[t as usize].into_iter())
            .map(|v| (self.points[v as usize][k] - p).abs())
            .filter(|&d| d > 0.0)
            .reduce(|| f64::INFINITY, f64::min)
    }

    /// Cuts node `n` by the candidate's plane; returns the two children's node ids.
    fn cut_node(&mut self, n: usize, c: &Candidate) -> (usize, usize) {
        let (k, p) = (c.axis as usize, c.position);
        let list = std::mem::take(&mut self.nodes[n].tets);
        let points = &self.points;
        let tets = &self.tets;
        let sides_of = |t: u32| tets[t as usize].map(|v| side(points[v as usize][k], p));
        let class: Vec<i8> = list
            .par_iter()
            .map(|&t| {
                let s = sides_of(t);
                if crosses(&s) {
                    0
                } else if s.contains(&1) {
                    1
                } else {
                    -1
                }
            })
            .collect();
        let crossing: Vec<u32> = list
            .iter()
            .zip(&class)
            .filter(|x| *x.1 == 0)
            .map(|x| *x.0)
            .collect();
        let mut edges: Vec<(u32, u32)> = crossing
            .par_iter()
            .flat_map_iter(|&t| {
                let s = sides_of(t);
                let q = tets[t as usize];
                (0..4)
                    .flat_map(move |i| (i + 1..4).map(move |j| (i, j)))
                    .filter(move |&(i, j)| s[i] * s[j] == -1)
                    .map(move |(i, j)| (q[i].min(q[j]), q[i].max(q[j])))
            })
            .collect();
        edges.par_sort_unstable();
        edges.dedup();
        let base = self.points.len() as u32;
        let made: Vec<([f64; 3], (usize, usize, f64))> = edges
            .par_iter()
            .map(|&(a, bb)| {
                let (pt, a_first, t) = edge_point(&points[a as usize], &points[bb as usize], k, p);
                let (lo, hi) = if a_first { (a, bb) } else { (bb, a) };
                (pt, (lo as usize, hi as usize, t))
            })
            .collect();
        // Edges on a face of this node's box that is not the mesh's outer box: other nodes' tets
        // may share them.
        let bounds = self.nodes[n].bounds;
        let faces: Vec<(usize, f64)> = (0..3)
            .filter(|&j| j != k)
            .flat_map(|j| [(j, bounds.min[j]), (j, bounds.max[j])])
            .filter(|&(j, q)| q != self.root.min[j] && q != self.root.max[j])
            .collect();
        let shared: Vec<(u32, u32)> = if faces.is_empty() {
            Vec::new()
        } else {
            edges
                .iter()
                .copied()
                .filter(|&(a, bb)| {
                    let (pa, pb) = (&points[a as usize], &points[bb as usize]);
                    faces.iter().any(|&(j, q)| pa[j] == q && pb[j] == q)
                })
                .collect()
        };
        let mid = |a: u32, bb: u32| -> u32 {
            match edges.binary_search(&(a, bb)) {
                Ok(i) => base + i as u32,
                Err(_) => unreachable!("edge ({a}, {bb}) was not collected as crossing"),
            }
        };
        let cut_pieces: Vec<Pieces> = crossing
            .par_iter()
            .map(|&t| {
                let mut out = Vec::with_capacity(6);
                split_tet(tets[t as usize], sides_of(t), &mid, &mut out);
                out
            })
            .collect();
        let (neighbours, skipped) = self.neighbour_cuts(n, &shared, &mid);
        for (pt, l) in made {
            self.points.push(pt);
            self.lerp.push(l);
        }
        let (mut left, mut right) = (Vec::new(), Vec::new());
        for (&t, &cl) in list.iter().zip(&class) {
            match cl {
                -1 => left.push(t),
                1 => right.push(t),
                _ => {}
            }
        }
        for (&t, pieces) in crossing.iter().zip(cut_pieces) {
            for (q, s) in pieces
                .into_iter()
                .enumerate()
                .map(|(i, x)| (self.place(t, i, x.0), x.1))
            {
                if s < 0 {
                    left.push(q);
                } else {
                    right.push(q);
                }
            }
        }
        self.neighbour_splits += neighbours.len();
        self.neighbour_skipped += skipped;
        for (t, pieces) in neighbours {
            let node = self.node_of[t as usize] as usize;
            for (i, (q, _)) in pieces.into_iter().enumerate() {
                let id = self.place(t, i, q);
                if i > 0 {
                    self.nodes[node].tets.push(id);
                }
            }
        }
        let depth = self.nodes[n].depth + 1;
        let (mut lb, mut rb) = (bounds, bounds);
        lb.max[k] = p;
        rb.min[k] = p;
        let (li, ri) = (self.nodes.len(), self.nodes.len() + 1);
        for &t in &left {
            self.node_of[t as usize] = li as u32;
        }
        for &t in &right {
            self.node_of[t as usize] = ri as u32;
        }
        self.nodes[n].split = Some(Split {
            axis: k as u8,
            position: p,
            left: li as u32,
            right: ri as u32,
        });
        for (bx, ts) in [(lb, left), (rb, right)] {
            self.nodes.push(BuildNode {
                bounds: bx,
                depth,
                parent: Some(n as u32),
                split: None,
                tets: ts,
            });
        }
        (li, ri)
    }

    /// Puts piece `i` of tet `t`: the first piece takes the tet's own slot, the others are appended
    /// (same original cell and node). Returns the piece's tet id.
    fn place(&mut self, t: u32, i: usize, q: [u32; 4]) -> u32 {
        if i == 0 {
            self.tets[t as usize] = q;
            return t;
        }
        let id = self.tets.len() as u32;
        self.tets.push(q);
        self.original.push(self.original[t as usize]);
        self.node_of.push(self.node_of[t as usize]);
        id
    }

    /// The tets outside node `n` that contain a `shared` edge, with their pieces; and how many had
    /// a pattern no plane makes (left whole).
    fn neighbour_cuts(
        &self,
        n: usize,
        shared: &[(u32, u32)],
        mid: &(impl Fn(u32, u32) -> u32 + Sync),
    ) -> (Vec<(u32, Pieces)>, usize) {
        if shared.is_empty() {
            return (Vec::new(), 0);
        }
        let mut marked = vec![false; self.points.len()];
        for &(a, b) in shared {
            marked[a as usize] = true;
            marked[b as usize] = true;
        }
        // Only nodes whose boxes touch this one can hold tets sharing its edges.
        let b = self.nodes[n].bounds;
        let touching: Vec<&[u32]> = self
            .nodes
            .iter()
            .enumerate()
            .filter(|(i, x)| {
                *i != n
                    && x.split.is_none()
                    && (0..3).all(|k| x.bounds.min[k] <= b.max[k] && b.min[k] <= x.bounds.max[k])
            })
            .map(|(_, x)| x.tets.as_slice())
            .collect();
        let found: Vec<(u32, Option<Pieces>)> = touching
            .par_iter()
            .flat_map(|list| list.par_iter().copied())
            .filter_map(|t| {
                let q = self.tets[t as usize];
                if q.iter().filter(|&&v| marked[v as usize]).count() < 2 {
                    return None;
                }
                let mut cut = [(0usize, 0usize); 6];
                let mut nc = 0;
                for i in 0..4 {
                    for j in i + 1..4 {
                        let e = (q[i].min(q[j]), q[i].max(q[j]));
                        if shared.binary_search(&e).is_ok() {
                            cut[nc] = (i, j);
                            nc += 1;
                        }
                    }
                }
                let mut sides = [0i8; 4];
                match nc {
                    0 => return None,
                    1 => {
                        sides[cut[0].0] = -1;
                        sides[cut[0].1] = 1;
                    }
                    2 => {
                        let (e, f) = (cut[0], cut[1]);
                        let common = [e.0, e.1].into_iter().find(|&v| v == f.0 || v == f.1);
                        let Some(a) = common else {
                            return Some((t, None));
                        };
                        for v in [e.0, e.1, f.0, f.1] {
                            sides[v] = -1;
                        }
                        sides[a] = 1;
                    }
                    _ => return Some((t, None)),
                }
                let mut out = Vec::with_capacity(3);
                split_tet(q, sides, mid, &mut out);
                Some((t, Some(out)))
            })
            .collect();
        let skipped = found.iter().filter(|x| x.1.is_none()).count();
        (
            found
                .into_iter()
                .filter_map(|(t, p)| p.map(|p| (t, p)))
                .collect(),
            skipped,
        )
    }

    fn finish(
        self,
        input: &TetMesh,
        opts: &PartitionOptions,
        reoriented: usize,
        degenerate: usize,
        levels: Vec<LevelReport>,
        start: Instant,
    ) -> Partitioned {
        // Leaf ids depth first, left to right; tet counts bottom up (children follow parents).
        let mut leaf_of_node = vec![None; self.nodes.len()];
        let mut stack = vec![0usize];
        let mut leaf_nodes = Vec::new();
        while let Some(i) = stack.pop() {
            match self.nodes[i].split {
                Some(s) => {
                    stack.push(s.right as usize);
                    stack.push(s.left as usize);
                }
                None => {
                    leaf_of_node[i] = Some(leaf_nodes.len() as u32);
                    leaf_nodes.push(i);
                }
            }
        }
        let mut counts: Vec<u64> = self.nodes.iter().map(|x| x.tets.len() as u64).collect();
        for i in (0..self.nodes.len()).rev() {
            if let Some(s) = self.nodes[i].split {
                counts[i] = counts[s.left as usize] + counts[s.right as usize];
            }
        }
        let tree = KdTree {
            nodes: self
                .nodes
                .iter()
                .enumerate()
                .map(|(i, x)| KdNode {
                    bounds: x.bounds,
                    depth: x.depth,
                    parent: x.parent,
                    split: x.split,
                    leaf_id: leaf_of_node[i],
                    tet_count: counts[i],
                })
                .collect(),
        };
        let order: Vec<u32> = leaf_nodes
            .iter()
            .flat_map(|&i| self.nodes[i].tets.iter().copied())
            .collect();
        let leaf_ids: Vec<i32> = leaf_nodes
            .iter()
            .enumerate()
            .flat_map(|(l, &i)| std::iter::repeat_n(l as i32, self.nodes[i].tets.len()))
            .collect();
        let out_tets: Vec<[u32; 4]> = order.iter().map(|&t| self.tets[t as usize]).collect();
        let original: Vec<u32> = order.iter().map(|&t| self.original[t as usize]).collect();
        let idx: Vec<usize> = original.iter().map(|&o| o as usize).collect();
        let mut cell_data = input.cell_data.gather(&idx);
        cell_data.insert(DataArray::new(
            ORIGINAL_CELL_ID,
            1,
            ArrayData::Int64(original.iter().map(|&o| o as i64).collect()),
        ));
        cell_data.insert(DataArray::new(LEAF_ID, 1, ArrayData::Int32(leaf_ids)));
        let mut point_data = input.point_data.clone();
        point_data.append_lerp(&self.lerp);
        let mut field_data: Vec<DataArray> = input
            .field_data
            .iter()
            .filter(|a| !a.name.starts_with("kd_node_"))
            .cloned()
            .collect();
        field_data.extend(tree.to_field_data());
        let sizes: Vec<usize> = leaf_nodes
            .iter()
            .map(|&i| self.nodes[i].tets.len())
            .collect();
        let largest = sizes.iter().copied().max().unwrap_or(0);
        let smallest = sizes.iter().copied().min().unwrap_or(0);
        let mean = out_tets.len() as f64 / sizes.len().max(1) as f64;
        let report = PartitionReport {
            strategy: opts.search.strategy,
            leaves: leaf_nodes.len(),
            depth: tree.depth(),
            tets_before: input.tets.len(),
            tets_after: out_tets.len(),
            growth: out_tets.len() as f64 / input.tets.len().max(1) as f64,
            balance: if mean > 0.0 {
                largest as f64 / mean
            } else {
                1.0
            },
            largest_leaf: largest,
            smallest_leaf: smallest,
            points_before: input.points.len(),
            points_after: self.points.len(),
            reoriented,
            degenerate,
            neighbour_splits: self.neighbour_splits,
            neighbour_skipped: self.neighbour_skipped,
            levels,
            seconds: start.elapsed().as_secs_f64(),
        };
        Partitioned {
            mesh: TetMesh {
                points: self.points,
                tets: out_tets,
                point_data,
                cell_data,
                field_data,
            },
            tree,
            original,
            report,
        }
    }
}
