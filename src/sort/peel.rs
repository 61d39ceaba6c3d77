//! Layer peeling of one leaf's precedence graph (face constraints plus extra edges), parallel
//! within a layer, with strongly-connected-component detection and deterministic cycle breaking.

use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

use super::adjacency::NONE;

/// Layer value of a tet not yet placed.
pub const UNSET: u32 = u32::MAX;
/// A released tet's in-degree: far above any count of decrements it can still receive.
const RELEASED: u32 = 1 << 30;
/// Frontiers at least this large are relaxed in parallel (smaller ones cost more in atomics and
/// shared cache lines than a second core gains).
const PAR_FRONTIER: usize = 1024;

/// How many frontier tets ahead the serial loop prefetches (twice this for a tet's neighbours).
const AHEAD: usize = 16;

/// A hint to bring `x`'s cache line in; no effect on results.
#[inline(always)]
fn prefetch<T>(x: &T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch reads nothing architecturally and cannot fault, whatever the address;
    // SSE is part of the x86_64 baseline.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(
            x as *const T as *const i8,
        )
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = x;
}

/// Bit of `post[t]` saying `t` has extra successors (the CSR is read only for those tets).
pub const HAS_EXTRA: u8 = 16;

/// The precedence graph of one view, over global tet ids. `t` must come before `n` when bit `i`
/// (0..4) of `post[t]` is set and `n = neighbors[t][i]`, and before every
/// `extra_to[extra_off[t]..extra_off[t + 1]]` when `post[t]` has [`HAS_EXTRA`].
pub struct Graph<'a> {
    pub neighbors: &'a [[u32; 4]],
    pub post: &'a [u8],
    /// CSR over all tets; empty when there are no extra edges.
    pub extra_off: &'a [u32],
    pub extra_to: &'a [u32],
}

impl Graph<'_> {
    #[inline]
    fn for_each_successor(&self, t: u32, mut f: impl FnMut(u32)) {
        let tu = t as usize;
        let mut bits = self.post[tu] & 15;
        while bits != 0 {
            let i = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let n = self.neighbors[tu][i];
            if n != NONE {
                f(n);
            }
        }
        if self.post[tu] & HAS_EXTRA != 0 {
            for &n in &self.extra_to[self.extra_off[tu] as usize..self.extra_off[tu + 1] as usize] {
                f(n);
            }
        }
    }
}

/// What peeling one leaf found.
#[derive(Clone, Debug, Default)]
pub struct PeelResult {
    pub layers: u32,
    /// Strongly connected components (visibility cycles) broken.
    pub cycles: usize,
    /// Tets that were part of a broken cycle.
    pub cycle_tets: usize,
    /// Constraints ignored to break the cycles.
    pub broken_constraints: usize,
}

/// Peels the leaf's tets (`tets`, any order) into layers: writes each tet's layer into `layer`.
/// `indeg[t]` must hold the number of predecessors of `t` within the leaf; it is consumed.
pub fn peel(g: &Graph, tets: &[u32], indeg: &[AtomicU32], layer: &[AtomicU32]) -> PeelResult {
    peel_with(g, tets, indeg, layer, PAR_FRONTIER)
}

/// [`peel`] relaxing frontiers of at least `par_frontier` tets in parallel.
fn peel_with(
    g: &Graph,
    tets: &[u32],
    indeg: &[AtomicU32],
    layer: &[AtomicU32],
    par_frontier: usize,
) -> PeelResult {
    let mut res = PeelResult::default();
    let mut frontier: Vec<u32> = if tets.len() >= par_frontier {
        tets.par_iter()
            .copied()
            .filter(|&t| indeg[t as usize].load(Relaxed) == 0)
            .collect()
    } else {
        tets.iter()
            .copied()
            .filter(|&t| indeg[t as usize].load(Relaxed) == 0)
            .collect()
    };
    let mut next: Vec<u32> = Vec::new();
    let mut placed = 0usize;
    let mut current = 0u32;
    let mut in_cycle: HashMap<u32, ()> = HashMap::new();
    loop {
        if frontier.is_empty() {
            if placed == tets.len() {
                break;
            }
            frontier = break_cycles(g, tets, indeg, layer, &mut res, &mut in_cycle);
            if frontier.is_empty() {
                // Cannot happen (a stalled graph always has a source component); never loop.
                frontier = tets
                    .iter()
                    .copied()
                    .filter(|&t| layer[t as usize].load(Relaxed) == UNSET)
                    .collect();
                for &t in &frontier {
                    indeg[t as usize].store(RELEASED, Relaxed);
                }
            }
        }
        placed += frontier.len();
        let threads = rayon::current_num_threads();
        if frontier.len() >= par_frontier && threads > 1 {
            // Counters shared between threads: locked decrements. A few long chunks per thread,
            // so the prefetching inside each chunk runs ahead of it.
            let chunk = frontier.len().div_ceil(2 * threads).max(256);
            let parts: Vec<Vec<u32>> = frontier
                .par_chunks(chunk)
                .map(|ch| {
                    let mut out = Vec::with_capacity(ch.len());
                    relax(g, ch, indeg, layer, current, &mut out, |c| {
                        c.fetch_sub(1, Relaxed).wrapping_sub(1)
                    });
                    out
                })
                .collect();
            next.clear();
            for p in parts {
                next.extend_from_slice(&p);
            }
        } else {
            // One thread owns these counters (leaves never share a tet or an edge), so plain
            // loads and stores do: no locked read-modify-write, no cache-line traffic.
            next.clear();
            relax(g, &frontier, indeg, layer, current, &mut next, |c| {
                let v = c.load(Relaxed).wrapping_sub(1);
                c.store(v, Relaxed);
                v
            });
        }
        std::mem::swap(&mut frontier, &mut next);
        current += 1;
    }
    res.layers = current;
    res
}

/// Places `frontier` in layer `current` and takes one from each successor's counter with
/// `decrement` (which returns the new count), collecting in `out` the tets that reach zero.
/// The loop is a chain of cache misses (a tet's neighbours, then their counters): it asks for
/// them a few tets ahead so they overlap.
#[inline]
fn relax(
    g: &Graph,
    frontier: &[u32],
    indeg: &[AtomicU32],
    layer: &[AtomicU32],
    current: u32,
    out: &mut Vec<u32>,
    decrement: impl Fn(&AtomicU32) -> u32,
) {
    for (k, &t) in frontier.iter().enumerate() {
        if let Some(&u) = frontier.get(k + 2 * AHEAD) {
            prefetch(&g.neighbors[u as usize]);
            prefetch(&g.post[u as usize]);
            prefetch(&layer[u as usize]);
        }
        if let Some(&u) = frontier.get(k + AHEAD) {
            g.for_each_successor(u, |n| prefetch(&indeg[n as usize]));
        }
        layer[t as usize].store(current, Relaxed);
        g.for_each_successor(t, |n| {
            if decrement(&indeg[n as usize]) == 0 {
                out.push(n);
            }
        });
    }
}

/// The remaining tets form a graph where every tet has a predecessor: find its strongly connected
/// components (iterative Tarjan), and release one tet of every source component: the one with the
/// fewest predecessors left (so the fewest constraints are ignored), the smallest id on ties.
fn break_cycles(
    g: &Graph,
    tets: &[u32],
    indeg: &[AtomicU32],
    layer: &[AtomicU32],
    res: &mut PeelResult,
    in_cycle: &mut HashMap<u32, ()>,
) -> Vec<u32> {
    let mut rest: Vec<u32> = tets
        .iter()
        .copied()
        .filter(|&t| layer[t as usize].load(Relaxed) == UNSET)
        .collect();
    rest.sort_unstable();
    let local: HashMap<u32, u32> = rest
        .iter()
        .enumerate()
        .map(|(i, &t)| (t, i as u32))
        .collect();
    let m = rest.len();
    let mut succ_off = vec![0u32; m + 1];
    let mut succ = Vec::new();
    for (i, &t) in rest.iter().enumerate() {
        g.for_each_successor(t, |n| {
            if let Some(&j) = local.get(&n) {
                succ.push(j);
            }
        });
        succ_off[i + 1] = succ.len() as u32;
    }
    let comp = tarjan(m, &succ_off, &succ);
    let ncomp = comp.iter().map(|&c| c as usize + 1).max().unwrap_or(0);
    let mut size = vec![0usize; ncomp];
    let mut has_pred = vec![false; ncomp];
    let mut pick = vec![(u32::MAX, u32::MAX); ncomp];
    for i in 0..m {
        let c = comp[i] as usize;
        size[c] += 1;
        pick[c] = pick[c].min((indeg[rest[i] as usize].load(Relaxed), rest[i]));
        for &j in &succ[succ_off[i] as usize..succ_off[i + 1] as usize] {
            if comp[j as usize] != comp[i] {
                has_pred[comp[j as usize] as usize] = true;
            }
        }
    }
    for i in 0..m {
        let c = comp[i] as usize;
        if size[c] > 1 && in_cycle.insert(rest[i], ()).is_none() {
            res.cycle_tets += 1;
        }
    }
    let mut released = Vec::new();
    for c in 0..ncomp {
        if !has_pred[c] {
            let t = pick[c].1;
            res.cycles += 1;
            res.broken_constraints += indeg[t as usize].load(Relaxed) as usize;
            indeg[t as usize].store(RELEASED, Relaxed);
            released.push(t);
        }
    }
    released.sort_unstable();
    released
}

/// Strongly connected components of a CSR graph (iterative Tarjan); returns the component of
/// each node.
pub fn tarjan(n: usize, off: &[u32], succ: &[u32]) -> Vec<u32> {
    const UNV: u32 = u32::MAX;
    let mut index = vec![UNV; n];
    let mut low = vec![0u32; n];
    let mut on_stack = vec![false; n];
    let mut comp = vec![UNV; n];
    let mut stack: Vec<u32> = Vec::new();
    let mut call: Vec<(u32, u32)> = Vec::new();
    let mut next_index = 0u32;
    let mut next_comp = 0u32;
    for root in 0..n as u32 {
        if index[root as usize] != UNV {
            continue;
        }
        call.push((root, off[root as usize]));
        index[root as usize] = next_index;
        low[root as usize] = next_index;
        next_index += 1;
        stack.push(root);
        on_stack[root as usize] = true;
        while let Some(&mut (v, ref mut e)) = call.last_mut() {
            let vu = v as usize;
            if *e < off[vu + 1] {
                let w = succ[*e as usize];
                *e += 1;
                let wu = w as usize;
                if index[wu] == UNV {
                    index[wu] = next_index;
                    low[wu] = next_index;
                    next_index += 1;
                    stack.push(w);
                    on_stack[wu] = true;
                    call.push((w, off[wu]));
                } else if on_stack[wu] {
                    low[vu] = low[vu].min(index[wu]);
                }
            } else {
                call.pop();
                if let Some(&(p, _)) = call.last() {
                    low[p as usize] = low[p as usize].min(low[vu]);
                }
                if low[vu] == index[vu] {
                    while let Some(w) = stack.pop() {
                        on_stack[w as usize] = false;
                        comp[w as usize] = next_comp;
                        if w == v {
                            break;
                        }
                    }
                    next_comp += 1;
                }
            }
        }
    }
    comp
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(n: usize, edges: &[(u32, u32)]) -> (Vec<u32>, PeelResult) {
        run_with(n, edges, PAR_FRONTIER)
    }

    fn run_with(n: usize, edges: &[(u32, u32)], par_frontier: usize) -> (Vec<u32>, PeelResult) {
        let neighbors = vec![[NONE; 4]; n];
        let mut post = vec![0u8; n];
        for &(a, _) in edges {
            post[a as usize] |= HAS_EXTRA;
        }
        let mut off = vec![0u32; n + 1];
        let mut sorted = edges.to_vec();
        sorted.sort_unstable();
        for &(a, _) in &sorted {
            off[a as usize + 1] += 1;
        }
        for i in 0..n {
            off[i + 1] += off[i];
        }
        let to: Vec<u32> = sorted.iter().map(|e| e.1).collect();
        let indeg: Vec<AtomicU32> = (0..n).map(|_| AtomicU32::new(0)).collect();
        for &(_, b) in edges {
            indeg[b as usize].fetch_add(1, Relaxed);
        }
        let layer: Vec<AtomicU32> = (0..n).map(|_| AtomicU32::new(UNSET)).collect();
        let g = Graph {
            neighbors: &neighbors,
            post: &post,
            extra_off: &off,
            extra_to: &to,
        };
        let tets: Vec<u32> = (0..n as u32).collect();
        let r = peel_with(&g, &tets, &indeg, &layer, par_frontier);
        (layer.into_iter().map(|a| a.into_inner()).collect(), r)
    }

    #[test]
    fn chain_and_diamond() {
        let (l, r) = run(4, &[(0, 1), (0, 2), (1, 3), (2, 3)]);
        assert_eq!(l, vec![0, 1, 1, 2]);
        assert_eq!((r.layers, r.cycles), (3, 0));
    }

    #[test]
    fn cycle_is_broken_and_everything_placed() {
        // 0 -> 1 -> 2 -> 0, and 2 -> 3, 3 -> 4 -> 3 (second cycle behind the first)
        let (l, r) = run(5, &[(0, 1), (1, 2), (2, 0), (2, 3), (3, 4), (4, 3)]);
        assert!(l.iter().all(|&x| x != UNSET));
        assert_eq!(r.cycles, 2);
        assert_eq!(r.cycle_tets, 5);
        assert_eq!(r.broken_constraints, 2);
        // Deterministic: the smallest id of each source component goes first.
        assert_eq!(l[0], 0);
        assert!(l[1] < l[2] && l[2] < l[3] && l[3] < l[4]);
    }

    /// A layered random DAG with a few cycles: the parallel frontier (any thread count) gives
    /// the layers and counts the serial one does.
    #[test]
    fn parallel_frontier_matches_serial() {
        // 40 rows of 500: each node points at 3 random nodes of the next row; a few
        // successors point back at their predecessor (2-cycles).
        let (rows, w) = (40u32, 500u32);
        let n = rows * w;
        let mut edges = Vec::new();
        let mut x = 12345u64;
        let mut rnd = |m: u32| {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((x >> 33) % m as u64) as u32
        };
        for a in 0..n - w {
            for _ in 0..3 {
                edges.push((a, (a / w + 1) * w + rnd(w)));
            }
        }
        for k in 0..6 {
            let (a, b) = edges[(k * 4001) % edges.len()];
            edges.push((b, a));
        }
        edges.sort_unstable();
        edges.dedup();
        let serial = run_with(n as usize, &edges, usize::MAX);
        assert!(
            serial.1.cycles > 0 && serial.1.layers >= rows,
            "{:?}",
            serial.1
        );
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let par = pool.install(|| run_with(n as usize, &edges, 1));
            assert_eq!(par.0, serial.0, "{threads} threads");
            assert_eq!(
                (
                    par.1.layers,
                    par.1.cycles,
                    par.1.cycle_tets,
                    par.1.broken_constraints
                ),
                (
                    serial.1.layers,
                    serial.1.cycles,
                    serial.1.cycle_tets,
                    serial.1.broken_constraints
                )
            );
        }
    }

    #[test]
    fn tarjan_components() {
        let off = [0, 1, 2, 3, 3];
        let succ = [1, 2, 0];
        let c = tarjan(4, &off, &succ);
        assert_eq!(c[0], c[1]);
        assert_eq!(c[1], c[2]);
        assert_ne!(c[0], c[3]);
    }
}
