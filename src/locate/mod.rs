//! The hierarchical uniform grid of seed 002: O(N) cell location and ray entry faces.
//!
//! [`grid::HGrid`] is the structure itself; [`TetLocator`] indexes tets to find the one holding a
//! point (probes, eyes inside the mesh), [`BoundaryIndex`] indexes boundary faces to find where a
//! ray enters the mesh, and [`Topology`] gives the face neighbours the ray caster walks through.

// Negated comparisons are deliberate: they also catch NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod grid;

use crate::geom::{orient3d, Aabb};
use crate::render::pt::FACES;
pub use grid::{GridParams, GridStats, HGrid};
use rayon::prelude::*;

/// No neighbour across a face (the face is on the mesh boundary).
pub const NONE: u32 = u32::MAX;

/// Face adjacency: `neighbor[t][i]` is the tet across face `i` (opposite vertex `i`) of tet `t`.
#[derive(Clone, Debug)]
pub struct Topology {
    pub neighbor: Vec<[u32; 4]>,
    /// Boundary faces as (tet, face index).
    pub boundary: Vec<(u32, u8)>,
    /// Faces shared by more than two tets (left as boundary for all of them).
    pub nonmanifold: usize,
}

impl Topology {
    /// Matches faces by their sorted vertex triples (parallel sort).
    pub fn build(tets: &[[u32; 4]]) -> Topology {
        let mut keys: Vec<([u32; 3], u32)> = tets
            .par_iter()
            .enumerate()
            .flat_map_iter(|(t, tet)| {
                (0..4).map(move |i| {
                    let mut k = FACES[i].map(|j| tet[j]);
                    k.sort_unstable();
                    (k, (t as u32) * 4 + i as u32)
                })
            })
            .collect();
        keys.par_sort_unstable();
        let mut neighbor = vec![[NONE; 4]; tets.len()];
        let mut boundary = Vec::new();
        let mut nonmanifold = 0;
        let mut i = 0;
        while i < keys.len() {
            let mut j = i + 1;
            while j < keys.len() && keys[j].0 == keys[i].0 {
                j += 1;
            }
            if j - i == 2 {
                let (a, b) = (keys[i].1, keys[i + 1].1);
                neighbor[(a / 4) as usize][(a % 4) as usize] = b / 4;
                neighbor[(b / 4) as usize][(b % 4) as usize] = a / 4;
            } else {
                if j - i > 2 {
                    nonmanifold += 1;
                }
                for k in &keys[i..j] {
                    boundary.push((k.1 / 4, (k.1 % 4) as u8));
                }
            }
            i = j;
        }
        Topology {
            neighbor,
            boundary,
            nonmanifold,
        }
    }
}

fn tet_box(points: &[[f64; 3]], t: &[u32; 4]) -> Aabb {
    Aabb::of_points(t.iter().map(|&v| &points[v as usize]))
}

/// Finds the tet holding a point.
#[derive(Clone, Debug)]
pub struct TetLocator {
    pub grid: HGrid,
}

impl TetLocator {
    pub fn build(points: &[[f64; 3]], tets: &[[u32; 4]], params: GridParams) -> TetLocator {
        let boxes: Vec<Aabb> = tets.par_iter().map(|t| tet_box(points, t)).collect();
        TetLocator {
            grid: HGrid::build(&boxes, params),
        }
    }

    /// A tet containing `p` (closed, exact orientation tests), with `p`'s barycentric
    /// coordinates in it; the lowest tet id when `p` lies on shared faces.
    pub fn locate(
        &self,
        points: &[[f64; 3]],
        tets: &[[u32; 4]],
        p: &[f64; 3],
    ) -> Option<(u32, [f64; 4])> {
        let mut best: Option<(u32, [f64; 4])> = None;
        for &t in self.grid.candidates(p) {
            if best.is_some_and(|b| b.0 < t) {
                continue;
            }
            let v = tets[t as usize].map(|i| points[i as usize]);
            let vol = orient3d(&v[0], &v[1], &v[2], &v[3]);
            if vol == 0.0 {
                continue;
            }
            let sgn = vol.signum();
            let mut inside = true;
            for f in 0..4 {
                let mut q = v;
                q[f] = *p;
                if orient3d(&q[0], &q[1], &q[2], &q[3]) * sgn < 0.0 {
                    inside = false;
                    break;
                }
            }
            if inside {
                best = Some((t, barycentric(&v, p)));
            }
        }
        best
    }
}

/// Barycentric coordinates of `p` in the tet `v` (floating point, summing to 1).
pub fn barycentric(v: &[[f64; 3]; 4], p: &[f64; 3]) -> [f64; 4] {
    let vol = crate::geom::tet_volume(&v[0], &v[1], &v[2], &v[3]);
    if vol == 0.0 {
        return [0.25; 4];
    }
    let mut b = [0.0; 4];
    for (f, slot) in b.iter_mut().enumerate() {
        let mut q = *v;
        q[f] = *p;
        *slot = crate::geom::tet_volume(&q[0], &q[1], &q[2], &q[3]) / vol;
    }
    let s: f64 = b.iter().sum();
    if s != 0.0 {
        for x in b.iter_mut() {
            *x /= s;
        }
    }
    b
}

/// Boundary faces indexed by the grid, for finding where rays enter the mesh.
#[derive(Clone, Debug)]
pub struct BoundaryIndex {
    pub grid: HGrid,
    /// (tet, face) of each indexed boundary face.
    pub faces: Vec<(u32, u8)>,
}

/// A boundary face a ray meets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f64,
    pub tet: u32,
    pub face: u8,
}

impl BoundaryIndex {
    pub fn build(
        points: &[[f64; 3]],
        tets: &[[u32; 4]],
        topo: &Topology,
        params: GridParams,
    ) -> BoundaryIndex {
        let boxes: Vec<Aabb> = topo
            .boundary
            .par_iter()
            .map(|&(t, f)| {
                let tet = &tets[t as usize];
                Aabb::of_points(FACES[f as usize].iter().map(|&k| &points[tet[k] as usize]))
            })
            .collect();
        BoundaryIndex {
            grid: HGrid::build(&boxes, params),
            faces: topo.boundary.clone(),
        }
    }

    /// The first boundary face at `t >= after` through which the ray enters its tet, skipping
    /// the faces in `skip` (those already crossed at `after`). Edge and vertex hits count for every
    /// face that shares them (a small barycentric tolerance), so a ray through a boundary edge
    /// still finds an entry.
    pub fn first_entry(
        &self,
        points: &[[f64; 3]],
        tets: &[[u32; 4]],
        o: &[f64; 3],
        d: &[f64; 3],
        after: f64,
        skip: &[(u32, u8)],
    ) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        self.grid
            .walk_ray(o, d, after, f64::INFINITY, &mut |refs, _t0, t1| {
                for &r in refs {
                    let (tet, face) = self.faces[r as usize];
                    if skip.contains(&(tet, face)) {
                        continue;
                    }
                    if let Some(t) = entry_hit(points, &tets[tet as usize], face, o, d) {
                        if t >= after && best.is_none_or(|b| t < b.t) {
                            best = Some(Hit { t, tet, face });
                        }
                    }
                }
                // Stop once the best hit lies before the end of this cell.
                !best.is_some_and(|b| b.t <= t1)
            });
        best
    }
}

/// Where the ray crosses face `face` of `tet` going into the tet, if it does.
#[inline]
pub fn entry_hit(
    points: &[[f64; 3]],
    tet: &[u32; 4],
    face: u8,
    o: &[f64; 3],
    d: &[f64; 3],
) -> Option<f64> {
    // Written out: the array `map` here is left as a call in some builds.
    let fv = &FACES[face as usize];
    let f = [
        points[tet[fv[0]] as usize],
        points[tet[fv[1]] as usize],
        points[tet[fv[2]] as usize],
    ];
    let opp = points[tet[face as usize] as usize];
    let sub = |a: &[f64; 3], b: &[f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cross = |a: &[f64; 3], b: &[f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let e1 = sub(&f[1], &f[0]);
    let e2 = sub(&f[2], &f[0]);
    let mut n = cross(&e1, &e2);
    // Orient the normal outward (away from the opposite vertex), by the exact sign: next to a
    // sliver the float dot product is rounding noise, and a flipped normal took the face the
    // ray leaves by for one it enters by (a new user's clipped grid drew a chord through a tet
    // the ray does not cross: up to 0.69 off in a dozen pixels). A flat tet has no inside to
    // enter.
    let side = crate::geom::orient3d(&f[0], &f[1], &f[2], &opp);
    if side == 0.0 {
        return None;
    }
    // orient3d is positive when `opp` lies below the plane of (f0, f1, f2), the side
    // opposite to `n = (f1 - f0) x (f2 - f0)`: then `n` already points away from it.
    if side < 0.0 {
        n = [-n[0], -n[1], -n[2]];
    }
    let dn = dot(&n, d);
    if !(dn < 0.0) {
        return None;
    }
    // Moller-Trumbore.
    let pvec = cross(d, &e2);
    let det = dot(&e1, &pvec);
    if det == 0.0 {
        return None;
    }
    let inv = 1.0 / det;
    let tvec = sub(o, &f[0]);
    let u = dot(&tvec, &pvec) * inv;
    let qvec = cross(&tvec, &e1);
    let v = dot(d, &qvec) * inv;
    let tol = 1e-10;
    if u < -tol || v < -tol || u + v > 1.0 + tol {
        return None;
    }
    let t = dot(&e2, &qvec) * inv;
    t.is_finite().then_some(t)
}
