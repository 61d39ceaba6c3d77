//! Ray-order check of a visibility order, sharing no code with the sorts it checks: rays through
//! pixel centres, each tet a ray crosses found by its own ray/tet clipping, and every pair of
//! crossed tets whose order in the sort disagrees with their order along the ray counted.

use rayon::prelude::*;
use serde::Serialize;

use crate::camera::Camera;
use crate::mesh::TetMesh;

#[derive(Clone, Debug, Default, Serialize)]
pub struct CheckReport {
    pub width: u32,
    pub height: u32,
    pub rays: usize,
    /// Rays that cross at least one tet.
    pub rays_hit: usize,
    /// Tets a ray passes through inside, summed over rays (the ones whose order is checked).
    pub crossings: usize,
    /// Tets a ray meets only along a face or edge it runs inside (not checked).
    pub boundary_only_crossings: usize,
    /// Pairs of tets crossed by one ray, drawn in the wrong order (summed over rays).
    pub violations: usize,
    /// Of those, pairs that follow each other directly on the ray.
    pub adjacent_violations: usize,
    pub rays_with_violations: usize,
    /// Neighbours on a ray that share only an edge or a vertex, where the ray passes from one to
    /// the other (within rounding of that shared edge or vertex): not counted as violations. The
    /// ray then runs through the shared element itself or through tets between them too thin for
    /// floating point to see, so its order of the two is not decided by the ray (on a grid seen
    /// from one of its symmetry planes, pixel rays graze edges this way).
    pub edge_meetings: usize,
}

/// Casts `width x height` rays through pixel centres and counts order violations. `rank[t]` is
/// tet `t`'s position in the drawing order; `front_to_back` says which way the order runs.
pub fn check_order(
    mesh: &TetMesh,
    cam: &Camera,
    rank: &[u32],
    front_to_back: bool,
    width: u32,
    height: u32,
) -> CheckReport {
    let (w, h) = (width.max(1), height.max(1));
    let bounds = mesh.bounds();
    let e = bounds.extent();
    let diag = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt().max(1e-300);
    // Bin tets by the pixels their projection covers; tets reaching behind the eye go to every ray.
    let mut everywhere = Vec::new();
    let mut spans: Vec<(u32, [u32; 4])> = Vec::with_capacity(mesh.tets.len());
    for t in 0..mesh.tets.len() {
        // A tet of zero volume (four coplanar points, or a repeated one) holds no segment of
        // any ray; clipping against its degenerate face planes gave it made-up intervals, and
        // 200 such tets in a grid showed 1644 violations of an order that has none.
        let p = mesh.tets[t].map(|v| mesh.points[v as usize]);
        if crate::geom::orient3d(&p[0], &p[1], &p[2], &p[3]) == 0.0 {
            continue;
        }
        let q = p.map(|x| cam.project(&x, w, h));
        if !cam.parallel {
            let near = 1e-9 * diag;
            if q.iter().all(|p| p[2] <= 0.0) {
                continue;
            }
            if q.iter().any(|p| p[2] <= near) {
                everywhere.push(t as u32);
                continue;
            }
        }
        let xmin = q.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min);
        let xmax = q.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max);
        let ymin = q.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
        let ymax = q.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max);
        // Pixel centres at i + 0.5; one pixel of margin for rounding.
        let lo = |x: f64| (x - 1.5).ceil().max(0.0);
        let hi = |x: f64, n: u32| (x + 0.5).floor().min(n as f64 - 1.0);
        let (x0, x1, y0, y1) = (lo(xmin), hi(xmax, w), lo(ymin), hi(ymax, h));
        if !(x0 <= x1 && y0 <= y1) {
            continue;
        }
        spans.push((t as u32, [x0 as u32, x1 as u32, y0 as u32, y1 as u32]));
    }
    let npix = (w * h) as usize;
    let mut start = vec![0u32; npix + 1];
    for (_, s) in &spans {
        for y in s[2]..=s[3] {
            for x in s[0]..=s[1] {
                start[(y * w + x) as usize + 1] += 1;
            }
        }
    }
    for i in 0..npix {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut bins = vec![0u32; start[npix] as usize];
    for (t, s) in &spans {
        for y in s[2]..=s[3] {
            for x in s[0]..=s[1] {
                let f = &mut fill[(y * w + x) as usize];
                bins[*f as usize] = *t;
                *f += 1;
            }
        }
    }
    drop(fill);
    let min_len = 1e-10 * diag;
    let per_ray: Vec<(usize, usize, usize, usize, usize)> = (0..npix)
        .into_par_iter()
        .map(|pix| {
            let (px, py) = ((pix as u32 % w) as f64 + 0.5, (pix as u32 / w) as f64 + 0.5);
            let (o, d) = cam.pixel_ray(px, py, w, h);
            let mut hits: Vec<(f64, f64, u32)> = Vec::new();
            let cand = bins[start[pix] as usize..start[pix + 1] as usize]
                .iter()
                .chain(everywhere.iter());
            for &t in cand {
                let p = mesh.tets[t as usize].map(|v| mesh.points[v as usize]);
                if let Some((t0, t1)) = clip(&p, &o, &d, cam.parallel) {
                    if t1 - t0 > min_len {
                        hits.push((t0, t1, t));
                    }
                }
            }
            if hits.is_empty() {
                return (0, 0, 0, 0, 0);
            }
            hits.sort_by(|a, b| (a.0 + a.1).total_cmp(&(b.0 + b.1)));
            // Tets whose intervals overlap share the ray only along a common face or edge (a ray
            // running inside a face plane): the ray meets none of them inside, so no generic ray
            // nearby orders them this way. Compare only tets the ray passes through inside.
            let mut group = vec![0u32; hits.len()];
            let mut reach = hits[0].1;
            let tol = 1e-9 * diag;
            for k in 1..hits.len() {
                group[k] = if hits[k].0 < reach - tol {
                    group[k - 1]
                } else {
                    group[k - 1] + 1
                };
                reach = reach.max(hits[k].1);
            }
            let mut members = vec![0u32; hits.len()];
            for &g in &group {
                members[g as usize] += 1;
            }
            // (hit index, tet) of the tets the ray passes through inside, in ray order.
            let inside: Vec<(usize, u32)> = (0..hits.len())
                .filter(|&k| members[group[k] as usize] == 1)
                .map(|k| (k, hits[k].2))
                .collect();
            let boundary_only = hits.len() - inside.len();
            let wrong = |a: u32, b: u32| {
                let (ra, rb) = (rank[a as usize], rank[b as usize]);
                if front_to_back {
                    ra > rb
                } else {
                    ra < rb
                }
            };
            // Neighbours on the ray whose intervals touch where they share only an edge or a
            // vertex (see `CheckReport::edge_meetings`).
            let edge_meeting = |i: usize, j: usize| {
                let (a, b) = (&hits[inside[i].0], &hits[inside[j].0]);
                let (ta, tb) = (mesh.tets[a.2 as usize], mesh.tets[b.2 as usize]);
                let shared = ta.iter().filter(|v| tb.contains(v)).count();
                (1..=2).contains(&shared) && (b.0 - a.1).abs() <= tol
            };
            let mut v = 0usize;
            let mut adj = 0usize;
            let mut edges = 0usize;
            for i in 0..inside.len() {
                for j in i + 1..inside.len() {
                    if wrong(inside[i].1, inside[j].1) {
                        if j == i + 1 && edge_meeting(i, j) {
                            edges += 1;
                            continue;
                        }
                        v += 1;
                        if j == i + 1 {
                            adj += 1;
                        }
                    }
                }
            }
            (inside.len(), boundary_only, v, adj, edges)
        })
        .collect();
    let mut r = CheckReport {
        width: w,
        height: h,
        rays: npix,
        ..Default::default()
    };
    for (n, b, v, a, e) in per_ray {
        r.edge_meetings += e;
        r.rays_hit += (n + b > 0) as usize;
        r.crossings += n;
        r.boundary_only_crossings += b;
        r.violations += v;
        r.adjacent_violations += a;
        r.rays_with_violations += (v > 0) as usize;
    }
    r
}

/// The parameter interval of the ray `o + t d` inside the tet (clipped to `t >= 0` for a
/// perspective eye), by clipping against the four face planes.
fn clip(p: &[[f64; 3]; 4], o: &[f64; 3], d: &[f64; 3], parallel: bool) -> Option<(f64, f64)> {
    let sub = |a: &[f64; 3], b: &[f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let crs = |a: &[f64; 3], b: &[f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let (mut t0, mut t1) = if parallel {
        (f64::NEG_INFINITY, f64::INFINITY)
    } else {
        (0.0, f64::INFINITY)
    };
    for i in 0..4 {
        let f: Vec<&[f64; 3]> = (0..4).filter(|&k| k != i).map(|k| &p[k]).collect();
        let mut n = crs(&sub(f[1], f[0]), &sub(f[2], f[0]));
        // Point the normal away from the opposite vertex.
        if dot(&n, &sub(&p[i], f[0])) > 0.0 {
            n = n.map(|x| -x);
        }
        let dist = dot(&n, &sub(o, f[0]));
        let den = dot(&n, d);
        if den == 0.0 {
            if dist > 0.0 {
                return None;
            }
            continue;
        }
        let t = -dist / den;
        if den < 0.0 {
            t0 = t0.max(t);
        } else {
            t1 = t1.min(t);
        }
        if t0 >= t1 {
            return None;
        }
    }
    (t1.is_finite() && t0.is_finite()).then_some((t0, t1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clip_unit_tet() {
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let (t0, t1) = clip(&p, &[0.1, 0.1, -1.0], &[0.0, 0.0, 1.0], false).unwrap();
        assert!((t0 - 1.0).abs() < 1e-12 && (t1 - 1.8).abs() < 1e-12);
        assert!(clip(&p, &[0.9, 0.9, -1.0], &[0.0, 0.0, 1.0], false).is_none());
    }
}
