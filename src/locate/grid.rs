//! The hierarchical uniform grid of Li, Wang and Wu (2011): O(N) cells and references.
//!
//! Resolution of each (sub-)grid: Eq. 1 with the flat-box fallbacks of Algorithm 1, capped by
//! Algorithm 2 at `alpha` cells per mean primitive extent on each axis. A cell becomes a sub-grid
//! when its sub-grid, at `lambda * n / beta` cells, would have at least `gamma` cells, where
//! `beta = references in the sub-grid / references in the cell` (measured at the undamped
//! resolution), so each level holds about `lambda * N` cells; at most `max_depth` levels.

// Negated comparisons are deliberate: they also catch NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::geom::Aabb;

/// The paper's parameters (defaults: lambda = 1, alpha = 2, gamma = 16, 8 levels).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridParams {
    pub lambda: f64,
    pub alpha: f64,
    pub gamma: usize,
    pub max_depth: usize,
}

impl Default for GridParams {
    fn default() -> Self {
        GridParams {
            lambda: 1.0,
            alpha: 2.0,
            gamma: 16,
            max_depth: 8,
        }
    }
}

/// What a cell holds: nothing, a run of `refs`, or a sub-grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Cell {
    Empty,
    Leaf { start: u32, len: u32 },
    Child(u32),
}

#[derive(Clone, Debug)]
struct Node {
    bounds: Aabb,
    res: [usize; 3],
    /// Cell size per axis (0 on a flat axis).
    size: [f64; 3],
    first_cell: usize,
}

/// Counts in the style of the paper's Table 1.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GridStats {
    pub primitives: usize,
    pub cells: usize,
    pub references: usize,
    pub grids: usize,
    pub depth: usize,
}

impl GridStats {
    /// Cells per primitive (the paper's r_c).
    pub fn cells_per_primitive(&self) -> f64 {
        self.cells as f64 / self.primitives.max(1) as f64
    }
    /// References per primitive (the paper's r_p).
    pub fn refs_per_primitive(&self) -> f64 {
        self.references as f64 / self.primitives.max(1) as f64
    }
}

/// A hierarchical uniform grid over primitives given by their boxes.
#[derive(Clone, Debug)]
pub struct HGrid {
    nodes: Vec<Node>,
    cells: Vec<Cell>,
    refs: Vec<u32>,
    pub stats: GridStats,
}

/// Algorithm 1: resolution for `target` cells over a box with sides `l`.
pub fn resolution_alg1(l: [f64; 3], target: f64) -> [usize; 3] {
    let target = target.max(1.0);
    let mut ax = [0usize, 1, 2];
    ax.sort_by(|&a, &b| l[b].total_cmp(&l[a]));
    let (li, lj, lk) = (l[ax[0]], l[ax[1]], l[ax[2]]);
    let mut m = [1.0f64; 3]; // in sorted-axis order
    let case2 = |m: &mut [f64; 3]| *m = [target, 1.0, 1.0];
    let case3 = |m: &mut [f64; 3]| {
        let mi = (target * li / lj).sqrt();
        let mj = (target * lj / li).sqrt();
        if mj < 1.0 {
            *m = [target, 1.0, 1.0];
        } else {
            *m = [mi, mj, 1.0];
        }
    };
    if !(li > 0.0) {
        // all zero
    } else if !(lj > 0.0) {
        case2(&mut m);
    } else if !(lk > 0.0) {
        case3(&mut m);
    } else {
        let c = (target / (li * lj * lk)).cbrt();
        let mm = [li * c, lj * c, lk * c];
        if mm[2] < 1.0 {
            case3(&mut m);
        } else {
            m = mm;
        }
    }
    let mut out = [1usize; 3];
    for (k, &a) in ax.iter().enumerate() {
        out[a] = (m[k].round().max(1.0) as usize).min(1 << 20);
    }
    out
}

/// Algorithm 2: caps each axis at `alpha * L / mean primitive extent`.
pub fn resolution_alg2(l: [f64; 3], target: f64, mean_extent: [f64; 3], alpha: f64) -> [usize; 3] {
    let mut m = resolution_alg1(l, target);
    for a in 0..3 {
        if mean_extent[a] > 0.0 && l[a] > 0.0 {
            let cap = (alpha * l[a] / mean_extent[a]).floor().max(1.0);
            if (m[a] as f64) > cap {
                m[a] = cap as usize;
            }
        }
    }
    // Keep the product representable.
    while m.iter().product::<usize>() > 1 << 28 {
        let a = (0..3).max_by_key(|&a| m[a]).unwrap_or(0);
        m[a] = (m[a] / 2).max(1);
    }
    m
}

struct Builder<'a> {
    boxes: &'a [Aabb],
    params: GridParams,
    nodes: Vec<Node>,
    cells: Vec<Cell>,
    refs: Vec<u32>,
    depth: usize,
}

fn cell_range(node_b: &Aabb, size: [f64; 3], res: [usize; 3], b: &Aabb) -> [(usize, usize); 3] {
    [0, 1, 2].map(|a| {
        if res[a] == 1 || !(size[a] > 0.0) {
            return (0, 0);
        }
        let idx = |x: f64| {
            let v = ((x - node_b.min[a]) / size[a]).floor();
            (v.max(0.0) as usize).min(res[a] - 1)
        };
        (idx(b.min[a]), idx(b.max[a]))
    })
}

fn count_refs(node_b: &Aabb, res: [usize; 3], boxes: &[Aabb], prims: &[u32]) -> usize {
    let size = [0, 1, 2].map(|a| (node_b.max[a] - node_b.min[a]) / res[a] as f64);
    prims
        .iter()
        .map(|&p| {
            let r = cell_range(node_b, size, res, &boxes[p as usize]);
            (0..3).map(|a| r[a].1 - r[a].0 + 1).product::<usize>()
        })
        .sum()
}

impl Builder<'_> {
    fn resolution(&self, b: &Aabb, prims: &[u32], target: f64) -> [usize; 3] {
        let l = b.extent();
        let mut mean = [0.0f64; 3];
        for &p in prims {
            let e = self.boxes[p as usize].extent();
            for a in 0..3 {
                mean[a] += e[a];
            }
        }
        let n = prims.len().max(1) as f64;
        resolution_alg2(l, target, mean.map(|x| x / n), self.params.alpha)
    }

    /// Builds a grid over `prims` inside `b`, returns its node index.
    fn build(&mut self, b: Aabb, prims: &[u32], res: [usize; 3], depth: usize) -> u32 {
        self.depth = self.depth.max(depth + 1);
        let size = [0, 1, 2].map(|a| (b.max[a] - b.min[a]) / res[a] as f64);
        let ncell = res[0] * res[1] * res[2];
        // Bucket references per cell (counting sort).
        let mut counts = vec![0u32; ncell + 1];
        let ranges: Vec<[(usize, usize); 3]> = prims
            .iter()
            .map(|&p| cell_range(&b, size, res, &self.boxes[p as usize]))
            .collect();
        let id = |x: usize, y: usize, z: usize| x + res[0] * (y + res[1] * z);
        for r in &ranges {
            for z in r[2].0..=r[2].1 {
                for y in r[1].0..=r[1].1 {
                    for x in r[0].0..=r[0].1 {
                        counts[id(x, y, z) + 1] += 1;
                    }
                }
            }
        }
        for i in 0..ncell {
            counts[i + 1] += counts[i];
        }
        let mut fill = counts.clone();
        let mut local = vec![0u32; counts[ncell] as usize];
        for (r, &p) in ranges.iter().zip(prims) {
            for z in r[2].0..=r[2].1 {
                for y in r[1].0..=r[1].1 {
                    for x in r[0].0..=r[0].1 {
                        let c = id(x, y, z);
                        local[fill[c] as usize] = p;
                        fill[c] += 1;
                    }
                }
            }
        }
        drop(ranges);
        let node = self.nodes.len() as u32;
        let first_cell = self.cells.len();
        self.nodes.push(Node {
            bounds: b,
            res,
            size,
            first_cell,
        });
        self.cells.resize(first_cell + ncell, Cell::Empty);
        for c in 0..ncell {
            let (s, e) = (counts[c] as usize, counts[c + 1] as usize);
            if s == e {
                continue;
            }
            let cp = &local[s..e];
            let (z, rem) = (c / (res[0] * res[1]), c % (res[0] * res[1]));
            let (y, x) = (rem / res[0], rem % res[0]);
            let cb = Aabb {
                min: [0, 1, 2].map(|a| b.min[a] + [x, y, z][a] as f64 * size[a]),
                max: [0, 1, 2].map(|a| {
                    if [x, y, z][a] + 1 == res[a] {
                        b.max[a]
                    } else {
                        b.min[a] + ([x, y, z][a] + 1) as f64 * size[a]
                    }
                }),
            };
            let mut child = None;
            if depth + 1 < self.params.max_depth {
                let n = cp.len() as f64;
                let full = self.resolution(&cb, cp, self.params.lambda * n);
                if full.iter().product::<usize>() >= self.params.gamma {
                    let r_sub = count_refs(&cb, full, self.boxes, cp) as f64;
                    let beta = (r_sub / n).max(1.0);
                    let damped = self.resolution(&cb, cp, self.params.lambda * n / beta);
                    if damped.iter().product::<usize>() >= self.params.gamma {
                        child = Some(damped);
                    }
                }
            }
            self.cells[first_cell + c] = match child {
                Some(r) => {
                    let cp = cp.to_vec();
                    Cell::Child(self.build(cb, &cp, r, depth + 1))
                }
                None => {
                    let start = self.refs.len() as u32;
                    self.refs.extend_from_slice(cp);
                    Cell::Leaf {
                        start,
                        len: cp.len() as u32,
                    }
                }
            };
        }
        node
    }
}

impl HGrid {
    /// Builds the hierarchy over primitives with the given boxes.
    pub fn build(boxes: &[Aabb], params: GridParams) -> HGrid {
        let mut bounds = Aabb::EMPTY;
        for b in boxes {
            if !b.is_empty() {
                bounds.grow(&b.min);
                bounds.grow(&b.max);
            }
        }
        if bounds.is_empty() {
            bounds = Aabb {
                min: [0.0; 3],
                max: [0.0; 3],
            };
        }
        let prims: Vec<u32> = (0..boxes.len() as u32)
            .filter(|&p| !boxes[p as usize].is_empty())
            .collect();
        let mut b = Builder {
            boxes,
            params,
            nodes: Vec::new(),
            cells: Vec::new(),
            refs: Vec::new(),
            depth: 0,
        };
        let res = b.resolution(&bounds, &prims, params.lambda * prims.len() as f64);
        b.build(bounds, &prims, res, 0);
        let stats = GridStats {
            primitives: boxes.len(),
            cells: b.cells.len(),
            references: b.refs.len(),
            grids: b.nodes.len(),
            depth: b.depth,
        };
        HGrid {
            nodes: b.nodes,
            cells: b.cells,
            refs: b.refs,
            stats,
        }
    }

    pub fn bounds(&self) -> Aabb {
        self.nodes[0].bounds
    }

    fn cell_index(&self, node: &Node, p: &[f64; 3]) -> Option<[usize; 3]> {
        let mut c = [0usize; 3];
        for a in 0..3 {
            if p[a] < node.bounds.min[a] || p[a] > node.bounds.max[a] || p[a].is_nan() {
                return None;
            }
            if node.res[a] > 1 && node.size[a] > 0.0 {
                let v = ((p[a] - node.bounds.min[a]) / node.size[a]).floor();
                c[a] = (v.max(0.0) as usize).min(node.res[a] - 1);
            }
        }
        Some(c)
    }

    /// Primitives whose boxes may contain `p` (the leaf cell's list; empty outside).
    pub fn candidates(&self, p: &[f64; 3]) -> &[u32] {
        let mut node = &self.nodes[0];
        loop {
            let Some(c) = self.cell_index(node, p) else {
                return &[];
            };
            let idx = node.first_cell + c[0] + node.res[0] * (c[1] + node.res[1] * c[2]);
            match self.cells[idx] {
                Cell::Empty => return &[],
                Cell::Leaf { start, len } => {
                    return &self.refs[start as usize..(start + len) as usize]
                }
                Cell::Child(n) => node = &self.nodes[n as usize],
            }
        }
    }

    /// Visits the leaf cells a ray passes, in order along the ray, with each cell's parameter
    /// interval. `visit` returns false to stop. Returns false when stopped.
    pub fn walk_ray(
        &self,
        o: &[f64; 3],
        d: &[f64; 3],
        tmin: f64,
        tmax: f64,
        visit: &mut dyn FnMut(&[u32], f64, f64) -> bool,
    ) -> bool {
        self.walk_node(0, o, d, tmin, tmax, visit)
    }

    fn walk_node(
        &self,
        n: u32,
        o: &[f64; 3],
        d: &[f64; 3],
        tmin: f64,
        tmax: f64,
        visit: &mut dyn FnMut(&[u32], f64, f64) -> bool,
    ) -> bool {
        let node = &self.nodes[n as usize];
        let b = &node.bounds;
        // Clip to the node box (slabs, closed).
        let (mut t0, mut t1) = (tmin, tmax);
        for a in 0..3 {
            if d[a] == 0.0 {
                if o[a] < b.min[a] || o[a] > b.max[a] {
                    return true;
                }
            } else {
                let inv = 1.0 / d[a];
                let (mut ta, mut tb) = ((b.min[a] - o[a]) * inv, (b.max[a] - o[a]) * inv);
                if ta > tb {
                    std::mem::swap(&mut ta, &mut tb);
                }
                t0 = t0.max(ta);
                t1 = t1.min(tb);
            }
        }
        if t0 > t1 {
            return true;
        }
        // 3-D DDA from the entry point.
        let p = [0, 1, 2].map(|a| o[a] + d[a] * t0);
        let mut c = [0i64; 3];
        let mut step = [0i64; 3];
        let mut tnext = [f64::INFINITY; 3];
        let mut tdelta = [f64::INFINITY; 3];
        for a in 0..3 {
            let res = node.res[a] as i64;
            if res == 1 || !(node.size[a] > 0.0) {
                c[a] = 0;
                continue;
            }
            let v = ((p[a] - b.min[a]) / node.size[a]).floor();
            c[a] = (v.max(0.0) as i64).min(res - 1);
            if d[a] > 0.0 {
                step[a] = 1;
                let edge = b.min[a] + (c[a] + 1) as f64 * node.size[a];
                tnext[a] = (edge - o[a]) / d[a];
                tdelta[a] = node.size[a] / d[a];
            } else if d[a] < 0.0 {
                step[a] = -1;
                let edge = b.min[a] + c[a] as f64 * node.size[a];
                tnext[a] = (edge - o[a]) / d[a];
                tdelta[a] = -node.size[a] / d[a];
            }
        }
        let mut t = t0;
        loop {
            let a = if tnext[0] <= tnext[1] && tnext[0] <= tnext[2] {
                0
            } else if tnext[1] <= tnext[2] {
                1
            } else {
                2
            };
            let tend = tnext[a].min(t1).max(t);
            let idx = node.first_cell
                + c[0] as usize
                + node.res[0] * (c[1] as usize + node.res[1] * c[2] as usize);
            let go_on = match self.cells[idx] {
                Cell::Empty => true,
                Cell::Leaf { start, len } => {
                    visit(&self.refs[start as usize..(start + len) as usize], t, tend)
                }
                Cell::Child(ch) => self.walk_node(ch, o, d, t, tend, visit),
            };
            if !go_on {
                return false;
            }
            if tnext[a] >= t1 {
                return true;
            }
            t = tnext[a];
            c[a] += step[a];
            if c[a] < 0 || c[a] >= node.res[a] as i64 {
                return true;
            }
            tnext[a] += tdelta[a];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn algorithm1_flat_boxes() {
        // The paper's example: N = 1000, box 1000 x 1000 x 1 -> 2-D split, about N cells.
        let m = resolution_alg1([1000.0, 1000.0, 1.0], 1000.0);
        assert_eq!(m[2], 1);
        assert!(
            (m[0] * m[1]) as f64 <= 1100.0 && m[0] * m[1] >= 900,
            "{m:?}"
        );
        assert_eq!(resolution_alg1([0.0, 0.0, 0.0], 50.0), [1, 1, 1]);
        assert_eq!(resolution_alg1([0.0, 3.0, 0.0], 50.0), [1, 50, 1]);
        // Very thin in one direction but positive: Eq. 1 gives M_k < 1, fall back.
        let m = resolution_alg1([10.0, 10.0, 1e-6], 100.0);
        assert_eq!(m, [10, 10, 1]);
        let m = resolution_alg1([8.0, 8.0, 8.0], 512.0);
        assert_eq!(m, [8, 8, 8]);
    }

    #[test]
    fn algorithm2_caps_large_primitives() {
        // Primitives spanning half the box: at most alpha * 2 = 4 cells per axis.
        let m = resolution_alg2([1.0; 3], 1e6, [0.5; 3], 2.0);
        assert_eq!(m, [4, 4, 4]);
    }

    #[test]
    fn hierarchy_refines_clusters_and_walks_in_order() {
        // Many tiny boxes in one corner and a few spread out: the corner cell gets a sub-grid.
        let mut boxes = Vec::new();
        for i in 0..2000 {
            let x = (i % 13) as f64 * 0.001 + 0.001;
            let y = (i / 13 % 13) as f64 * 0.001 + 0.001;
            let z = (i / 169) as f64 * 0.001 + 0.001;
            boxes.push(Aabb {
                min: [x, y, z],
                max: [x + 0.0005, y + 0.0005, z + 0.0005],
            });
        }
        for i in 0..50 {
            let x = 0.02 * i as f64;
            boxes.push(Aabb {
                min: [x, x, x],
                max: [x + 0.01, x + 0.01, x + 0.01],
            });
        }
        let g = HGrid::build(&boxes, GridParams::default());
        assert!(g.stats.depth >= 2, "{:?}", g.stats);
        assert!(g.stats.cells_per_primitive() < 10.0, "{:?}", g.stats);
        // Every box is found from its centre.
        for (i, b) in boxes.iter().enumerate() {
            assert!(g.candidates(&b.center()).contains(&(i as u32)));
        }
        // A diagonal ray meets cells in increasing t and sees the spread boxes.
        let mut last = f64::NEG_INFINITY;
        let mut seen = std::collections::BTreeSet::new();
        g.walk_ray(
            &[-1.0; 3],
            &[1.0; 3],
            0.0,
            f64::INFINITY,
            &mut |r, t0, t1| {
                assert!(t0 >= last - 1e-12 && t1 >= t0);
                last = t1;
                seen.extend(r.iter().copied());
                true
            },
        );
        for i in 0..50 {
            assert!(seen.contains(&(2000 + i)), "box {i} missed");
        }
    }
}
