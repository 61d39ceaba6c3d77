//! Choosing a node's split plane: the paper's search (evenly spaced candidates, beta threshold PHI,
//! balance alpha < EPS, best beta over x/y/z) and tetkit's cost strategy, both evaluated exactly.
//!
//! Slivers are avoided by where candidates go: a candidate never lies near a vertex coordinate.
//! The paper's evenly spaced position x_i is moved to the midpoint of the gap between the two
//! vertex coordinates of the node that surround it; this does not change which tets are cut or how
//! (every vertex keeps its side), so the paper's beta and alpha are exactly those of x_i, but each
//! new vertex is at least half a gap away from both endpoints of its edge along the axis. The cost
//! strategy goes further: it takes the widest gap within a window around each evenly spaced
//! position, and it also tries a plane exactly through a vertex coordinate when that coordinate is
//! isolated (no other vertex within 1/(8(N+1)) of the node's extent): such a plane meets vertices
//! only exactly, which cuts fewer tets (cases a/b, or none at all across the layers of a structured
//! mesh) and still keeps every other vertex far from the plane.

use rayon::prelude::*;

use super::split::case_counts;

/// Which plane search to use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Strategy {
    /// Li et al. 2012, section 2.3, as published.
    Paper,
    /// Fewest tets after the cut plus W times the imbalance, over wide-gap and vertex-layer
    /// candidates.
    Cost,
}

/// Parameters of the plane search (see the README's Partition section for defaults).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SearchParams {
    pub strategy: Strategy,
    /// N: evenly spaced candidate planes per axis.
    pub candidates: usize,
    /// PHI: largest accepted beta = (tets made by cutting) / (tets in the node).
    pub phi: f64,
    /// EPS: largest accepted (exclusive) alpha = |l - r| / ((l + r) / 2) (paper strategy).
    pub eps: f64,
    /// W of the cost strategy, which minimizes `l + r + W |l - r|`: tets after the cut plus W
    /// times the imbalance (W = 1 is the smallest larger child; smaller W saves more tets).
    pub balance_weight: f64,
}

/// One candidate plane and what cutting there would give.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Candidate {
    pub axis: u8,
    pub position: f64,
    /// Tets on each side after cutting (pieces counted on their side).
    pub left: u64,
    pub right: u64,
    /// Tets the plane cuts, and the sub-tets they become.
    pub cut: u64,
    pub pieces: u64,
    /// Distance along the axis from the plane to the nearest vertex coordinate not on it, when
    /// the plane was chosen (a node's cut re-checks it: a neighbour's cut may have added vertices).
    pub clearance: f64,
}

impl Candidate {
    /// The paper's beta: new tets created by the cut over the tets in the node.
    pub fn beta(&self, n: usize) -> f64 {
        self.pieces as f64 / n.max(1) as f64
    }

    /// The paper's alpha: |l - r| / ((l + r) / 2).
    pub fn alpha(&self) -> f64 {
        let (l, r) = (self.left as f64, self.right as f64);
        (l - r).abs() / ((l + r) / 2.0).max(f64::MIN_POSITIVE)
    }
}

/// Sorted distinct coordinates on `axis` of the vertices used by `node_tets`.
pub fn vertex_coordinates(
    node_tets: &[u32],
    tets: &[[u32; 4]],
    points: &[[f64; 3]],
) -> [Vec<f64>; 3] {
    let mut used = vec![false; points.len()];
    let mut ids = Vec::new();
    for &t in node_tets {
        for v in tets[t as usize] {
            if !used[v as usize] {
                used[v as usize] = true;
                ids.push(v);
            }
        }
    }
    let axis_coords = |a: usize| {
        let mut c: Vec<f64> = ids.iter().map(|&v| points[v as usize][a]).collect();
        c.par_sort_unstable_by(f64::total_cmp);
        c.dedup();
        c
    };
    [axis_coords(0), axis_coords(1), axis_coords(2)]
}

/// Gaps between vertex coordinates narrower than this fraction of the node's extent are never
/// used for a plane: a plane that close to a vertex would make slivers whose new vertices round
/// onto each other.
pub const MIN_GAP: f64 = 1e-9;

/// The midpoint of the open gap `(a, b)`, if the gap is at least `min` wide and a float lies
/// strictly inside it.
fn gap_mid(a: f64, b: f64, min: f64) -> Option<f64> {
    let m = 0.5 * a + 0.5 * b;
    (b - a >= min && a < m && m < b).then_some(m)
}

/// Distance from `p` to the nearest coordinate in `coords` (sorted) other than `p` itself.
pub fn clearance(coords: &[f64], p: f64) -> f64 {
    let j = coords.partition_point(|&c| c < p);
    let below = coords[..j].last().map_or(f64::INFINITY, |&c| p - c);
    let k = coords.partition_point(|&c| c <= p);
    let above = coords.get(k).map_or(f64::INFINITY, |&c| c - p);
    below.min(above)
}

/// The paper's candidates on one axis: `lo + i (hi - lo) / (N + 1)`, i = 1..N, each moved to the
/// middle of the gap between the node's vertex coordinates around it (a position exactly on a
/// coordinate takes the gap above it). A gap narrower than [`MIN_GAP`] of the extent is replaced
/// by the nearest wide enough one.
pub fn paper_positions(coords: &[f64], n: usize) -> Vec<f64> {
    let (Some(&lo), Some(&hi)) = (coords.first(), coords.last()) else {
        return Vec::new();
    };
    let min = MIN_GAP * (hi - lo);
    let gap = |j: usize| gap_mid(coords[j - 1], coords[j], min);
    let mut out = Vec::with_capacity(n);
    for i in 1..=n {
        let x = lo + (hi - lo) * (i as f64 / (n + 1) as f64);
        let j = coords.partition_point(|&c| c <= x);
        if j == 0 || j >= coords.len() {
            continue;
        }
        // Gap j holds x; look outward, nearer side first, for one wide enough.
        let found = (0..coords.len()).find_map(|d| {
            let down = (j > d).then(|| gap(j - d)).flatten();
            let up = (j + d < coords.len()).then(|| gap(j + d)).flatten();
            match (down, up) {
                (Some(a), Some(b)) => Some(if x - a <= b - x { a } else { b }),
                (a, b) => a.or(b),
            }
        });
        if let Some(m) = found {
            out.push(m);
        }
    }
    out.sort_unstable_by(f64::total_cmp);
    out.dedup();
    out
}

/// The cost strategy's candidates on one axis: for each of N evenly spaced positions, the middle of
/// the widest gap whose middle lies within half a spacing of it; plus every isolated vertex
/// coordinate (see the module doc).
pub fn cost_positions(coords: &[f64], n: usize) -> Vec<f64> {
    let (Some(&lo), Some(&hi)) = (coords.first(), coords.last()) else {
        return Vec::new();
    };
    let spacing = (hi - lo) / (n + 1) as f64;
    let mut out = Vec::new();
    for i in 1..=n {
        let x = lo + (hi - lo) * (i as f64 / (n + 1) as f64);
        let (wlo, whi) = (x - 0.5 * spacing, x + 0.5 * spacing);
        let mut j = coords.partition_point(|&c| c < wlo).saturating_sub(1);
        let mut best: Option<(f64, f64, f64)> = None; // (width, -distance, mid)
        while j + 1 < coords.len() && coords[j] <= whi {
            let (a, b) = (coords[j], coords[j + 1]);
            if let Some(m) = gap_mid(a, b, MIN_GAP * (hi - lo)) {
                if (wlo..=whi).contains(&m) {
                    let key = (b - a, -(m - x).abs(), m);
                    if best.is_none_or(|bk| (key.0, key.1) > (bk.0, bk.1)) {
                        best = Some(key);
                    }
                }
            }
            j += 1;
        }
        if let Some((_, _, m)) = best {
            out.push(m);
        }
    }
    let delta = spacing / 8.0;
    for j in 1..coords.len().saturating_sub(1) {
        if coords[j] - coords[j - 1] >= delta && coords[j + 1] - coords[j] >= delta {
            out.push(coords[j]);
        }
    }
    out.sort_unstable_by(f64::total_cmp);
    out.dedup();
    out
}

/// Adds one tet's contribution to the difference arrays of one axis. `s`: the tet's vertex
/// coordinates on the axis, sorted; `exact`: some positions may equal a vertex coordinate.
#[inline]
fn add_tet(d: &mut [[i64; 4]], positions: &[f64], s: &[f64; 4], exact: bool) {
    let m = positions.len();
    let lt = |x: f64| positions.partition_point(|&c| c < x);
    let mut add = |from: usize, to: usize, v: [i64; 4]| {
        if from < to {
            for k in 0..4 {
                d[from][k] += v[k];
                d[to][k] -= v[k];
            }
        }
    };
    let l = [lt(s[0]), lt(s[1]), lt(s[2]), lt(s[3])];
    // Positions never equal to a coordinate: "< x" and "<= x" find the same index.
    let e = if exact {
        s.map(|x| positions.partition_point(|&c| c <= x))
    } else {
        l
    };
    add(0, l[0], [0, 1, 0, 0]);
    add(e[0], l[1], [1, 3, 1, 4]);
    add(e[1], l[2], [3, 3, 1, 6]);
    add(e[2], l[3], [3, 1, 1, 4]);
    add(e[3], m, [1, 0, 0, 0]);
    if !exact {
        return;
    }
    for i in 0..4 {
        if (i > 0 && s[i] == s[i - 1]) || l[i] == e[i] {
            continue;
        }
        let x = s[i];
        let below = s.iter().filter(|&&y| y < x).count() as u8;
        let on = s.iter().filter(|&&y| y == x).count() as u8;
        let (lc, rc) = case_counts(below, on, 4 - below - on);
        let cut = (lc > 0 && rc > 0) as i64;
        add(
            l[i],
            e[i],
            [lc as i64, rc as i64, cut, cut * (lc + rc) as i64],
        );
    }
}

/// Exact counts for every candidate position (sorted, distinct) of each axis, in one pass over
/// the tets with difference arrays: O(tets log candidates), each tet's points read once.
pub fn evaluate(
    node_tets: &[u32],
    tets: &[[u32; 4]],
    points: &[[f64; 3]],
    positions: &[Vec<f64>; 3],
    coords: &[Vec<f64>; 3],
) -> [Vec<Candidate>; 3] {
    let exact: [bool; 3] = [0, 1, 2].map(|a| {
        positions[a]
            .iter()
            .any(|p| coords[a].binary_search_by(|c| c.total_cmp(p)).is_ok())
    });
    let zero = || [0, 1, 2].map(|a| vec![[0i64; 4]; positions[a].len() + 1]);
    let diff = node_tets
        .par_iter()
        .fold(zero, |mut d, &t| {
            let q = tets[t as usize].map(|v| points[v as usize]);
            for a in 0..3 {
                if positions[a].is_empty() {
                    continue;
                }
                let mut s = q.map(|p| p[a]);
                s.sort_unstable_by(f64::total_cmp);
                add_tet(&mut d[a], &positions[a], &s, exact[a]);
            }
            d
        })
        .reduce(zero, |mut x, y| {
            for a in 0..3 {
                for (u, v) in x[a].iter_mut().zip(&y[a]) {
                    for k in 0..4 {
                        u[k] += v[k];
                    }
                }
            }
            x
        });
    [0, 1, 2].map(|a| {
        let mut acc = [0i64; 4];
        positions[a]
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                for k in 0..4 {
                    acc[k] += diff[a][i][k];
                }
                Candidate {
                    axis: a as u8,
                    position: p,
                    left: acc[0] as u64,
                    right: acc[1] as u64,
                    cut: acc[2] as u64,
                    pieces: acc[3] as u64,
                    clearance: clearance(&coords[a], p),
                }
            })
            .collect()
    })
}

/// The plane to split a node with, or `None` when no candidate qualifies.
pub fn choose_plane(
    node_tets: &[u32],
    tets: &[[u32; 4]],
    points: &[[f64; 3]],
    params: &SearchParams,
) -> Option<Candidate> {
    let n = node_tets.len();
    if n < 2 {
        return None;
    }
    let coords = vertex_coordinates(node_tets, tets, points);
    let positions = [0, 1, 2].map(|a| match params.strategy {
        Strategy::Paper => paper_positions(&coords[a], params.candidates),
        Strategy::Cost => cost_positions(&coords[a], params.candidates),
    });
    let per_axis = evaluate(node_tets, tets, points, &positions, &coords);
    let two_sided = |c: &Candidate| c.left > 0 && c.right > 0;
    match params.strategy {
        Strategy::Paper => {
            let mut best: Option<Candidate> = None;
            for cands in per_axis {
                // Steps 2-4: smallest beta first; give up the axis once beta exceeds PHI.
                let mut order = cands;
                order.sort_by_key(|a| a.pieces);
                let found = order
                    .into_iter()
                    .take_while(|c| c.beta(n) <= params.phi)
                    .find(|c| c.alpha() < params.eps && two_sided(c));
                if let Some(c) = found {
                    // Step 5: of the qualifying planes of x, y and z take the smallest beta.
                    if best.is_none_or(|b| (c.pieces, c.alpha()) < (b.pieces, b.alpha())) {
                        best = Some(c);
                    }
                }
            }
            best
        }
        Strategy::Cost => per_axis
            .into_iter()
            .flatten()
            .filter(|c| two_sided(c) && c.beta(n) <= params.phi)
            .min_by(|a, b| {
                let w = params.balance_weight;
                let key = |c: &Candidate| {
                    (c.left + c.right) as f64 + w * (c.left as f64 - c.right as f64).abs()
                };
                key(a).total_cmp(&key(b))
            }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::{jitter, structured_grid};

    /// Counts by cutting every tet for real, to check the difference arrays.
    fn brute(
        node: &[u32],
        tets: &[[u32; 4]],
        pts: &[[f64; 3]],
        axis: usize,
        p: f64,
    ) -> (u64, u64, u64, u64) {
        let (mut l, mut r, mut cut, mut pieces) = (0, 0, 0, 0);
        for &t in node {
            let s = tets[t as usize].map(|v| super::super::split::side(pts[v as usize][axis], p));
            let c = |x: i8| s.iter().filter(|&&y| y == x).count() as u8;
            let (a, b) = case_counts(c(-1), c(0), c(1));
            l += a as u64;
            r += b as u64;
            if a > 0 && b > 0 {
                cut += 1;
                pieces += (a + b) as u64;
            }
        }
        (l, r, cut, pieces)
    }

    #[test]
    fn difference_arrays_match_brute_force() {
        let mut m = structured_grid([5, 4, 3], [0.0; 3], [1.0; 3]);
        jitter(&mut m, [5, 4, 3], 0.2, 3);
        let node: Vec<u32> = (0..m.tets.len() as u32).collect();
        let coords = vertex_coordinates(&node, &m.tets, &m.points);
        // Gap midpoints, exact vertex coordinates and positions outside the mesh.
        let positions = [0, 1, 2].map(|a| {
            let mut pos = paper_positions(&coords[a], 9);
            pos.extend(coords[a].iter().step_by(3));
            pos.extend([-1.0, 2.0]);
            pos.sort_unstable_by(f64::total_cmp);
            pos.dedup();
            pos
        });
        let paper = [0, 1, 2].map(|a| paper_positions(&coords[a], 9));
        for set in [positions, paper] {
            let all = evaluate(&node, &m.tets, &m.points, &set, &coords);
            for (axis, cands) in all.iter().enumerate() {
                for c in cands {
                    assert_eq!(
                        (c.left, c.right, c.cut, c.pieces),
                        brute(&node, &m.tets, &m.points, axis, c.position),
                        "axis {axis} at {}",
                        c.position
                    );
                }
            }
        }
    }

    #[test]
    fn paper_candidates_sit_between_coordinates() {
        let coords = [0.0, 0.1, 0.5, 0.5000001, 1.0];
        let p = paper_positions(&coords, 3);
        // 0.25 -> (0.1, 0.5); 0.5 -> on a coordinate, gap above; 0.75 -> (0.5000001, 1).
        assert_eq!(p.len(), 3);
        assert!(0.1 < p[0] && p[0] < 0.5);
        assert!(0.5 < p[1] && p[1] < 0.5000001);
        assert!(0.5000001 < p[2] && p[2] < 1.0);
        for x in p {
            assert!(!coords.contains(&x));
        }
    }

    #[test]
    fn both_strategies_split_a_grid_in_balance() {
        let mut m = structured_grid([8, 4, 4], [0.0; 3], [2.0, 1.0, 1.0]);
        jitter(&mut m, [8, 4, 4], 0.2, 1);
        let node: Vec<u32> = (0..m.tets.len() as u32).collect();
        for strategy in [Strategy::Paper, Strategy::Cost] {
            let params = SearchParams {
                strategy,
                candidates: 16,
                phi: 1.0,
                eps: 0.2,
                balance_weight: 0.5,
            };
            let c = choose_plane(&node, &m.tets, &m.points, &params).unwrap();
            // The long axis has the smallest cross-section.
            assert_eq!(c.axis, 0, "{strategy:?}: {c:?}");
            assert!(c.alpha() < 0.2, "{strategy:?}: {c:?}");
        }
    }
}
