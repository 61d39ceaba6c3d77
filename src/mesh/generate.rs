//! Generated test and benchmark meshes: tetrahedralized structured grids, optionally jittered.

use formats::{ArrayData, Attributes, DataArray};

use super::TetMesh;
use crate::geom::tet_volume;

/// A structured grid of `n[0] x n[1] x n[2]` cubes over `[min, max]`, each cube cut into six tets
/// around its main diagonal (Kuhn / Freudenthal), so neighbouring cubes share faces exactly:
/// `6 * n0 * n1 * n2` tets, conforming, every tet positively oriented. Point data: `scalar`
/// (Float64, the linear field x + 2y + 3z scaled to [0, 1] over the box) and `vec` (Float32, 3
/// components, the point itself relative to `min`). Cell data: `cube_id` (Int32).
pub fn structured_grid(n: [usize; 3], min: [f64; 3], max: [f64; 3]) -> TetMesh {
    let [nx, ny, nz] = n.map(|v| v.max(1));
    let (px, py) = (nx + 1, ny + 1);
    let pid = |i: usize, j: usize, k: usize| (i + px * (j + py * k)) as u32;
    let mut points = Vec::with_capacity(px * py * (nz + 1));
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                let t = [
                    i as f64 / nx as f64,
                    j as f64 / ny as f64,
                    k as f64 / nz as f64,
                ];
                points.push([0, 1, 2].map(|a| min[a] + t[a] * (max[a] - min[a])));
            }
        }
    }
    // The six monotone lattice paths from corner 000 to 111, one tet each.
    const PATHS: [[usize; 3]; 6] = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    let mut tets = Vec::with_capacity(6 * nx * ny * nz);
    let mut cube = Vec::with_capacity(6 * nx * ny * nz);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                for path in PATHS {
                    let mut c = [i, j, k];
                    let mut t = [pid(i, j, k); 4];
                    for (s, &axis) in path.iter().enumerate() {
                        c[axis] += 1;
                        t[s + 1] = pid(c[0], c[1], c[2]);
                    }
                    let p = t.map(|v| points[v as usize]);
                    if tet_volume(&p[0], &p[1], &p[2], &p[3]) < 0.0 {
                        t.swap(2, 3);
                    }
                    tets.push(t);
                    cube.push((i + nx * (j + ny * k)) as i32);
                }
            }
        }
    }
    let ext = [0, 1, 2].map(|a| max[a] - min[a]);
    let norm = ext[0] + 2.0 * ext[1] + 3.0 * ext[2];
    let scalar: Vec<f64> = points
        .iter()
        .map(|p| {
            let d = [0, 1, 2].map(|a| p[a] - min[a]);
            if norm > 0.0 {
                (d[0] + 2.0 * d[1] + 3.0 * d[2]) / norm
            } else {
                0.0
            }
        })
        .collect();
    let vec: Vec<f32> = points
        .iter()
        .flat_map(|p| [0, 1, 2].map(|a| (p[a] - min[a]) as f32))
        .collect();
    let mut point_data = Attributes::default();
    point_data.insert(DataArray::new("scalar", 1, ArrayData::Float64(scalar)));
    point_data.insert(DataArray::new("vec", 3, ArrayData::Float32(vec)));
    let mut cell_data = Attributes::default();
    cell_data.insert(DataArray::new("cube_id", 1, ArrayData::Int32(cube)));
    TetMesh {
        points,
        tets,
        point_data,
        cell_data,
        field_data: Vec::new(),
    }
}

/// Moves every interior point by up to `amount` of a cell width along each axis, with a fixed
/// pseudo-random sequence from `seed` (deterministic, no dependency). Boundary points move only
/// within their boundary plane. `amount` below 0.25 keeps every tet positively oriented.
pub fn jitter(mesh: &mut TetMesh, n: [usize; 3], amount: f64, seed: u64) {
    let b = mesh.bounds();
    let cell = [0, 1, 2].map(|a| (b.max[a] - b.min[a]) / n[a].max(1) as f64);
    let mut state = seed ^ 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        // splitmix64
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for p in mesh.points.iter_mut() {
        for a in 0..3 {
            let r = next();
            if p[a] > b.min[a] && p[a] < b.max[a] {
                p[a] += r * amount * cell[a];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_volume_and_orientation() {
        let mut m = structured_grid([3, 4, 5], [0.0, -1.0, 2.0], [3.0, 1.0, 7.0]);
        assert_eq!(m.tets.len(), 6 * 60);
        assert_eq!(m.points.len(), 4 * 5 * 6);
        jitter(&mut m, [3, 4, 5], 0.2, 7);
        let mut total = 0.0;
        for t in 0..m.tets.len() {
            let p = m.tet_points(t);
            let v = tet_volume(&p[0], &p[1], &p[2], &p[3]);
            assert!(v > 0.0, "tet {t} has volume {v}");
            total += v;
        }
        assert!(
            (total - 3.0 * 2.0 * 5.0).abs() < 1e-9,
            "total volume {total}"
        );
    }

    #[test]
    fn shared_faces_match() {
        use std::collections::HashMap;
        let m = structured_grid([2, 2, 2], [0.0; 3], [1.0; 3]);
        let mut faces: HashMap<[u32; 3], usize> = HashMap::new();
        for t in &m.tets {
            for skip in 0..4 {
                let mut f = [0u32; 3];
                let mut k = 0;
                for (i, &v) in t.iter().enumerate() {
                    if i != skip {
                        f[k] = v;
                        k += 1;
                    }
                }
                f.sort_unstable();
                *faces.entry(f).or_default() += 1;
            }
        }
        // Boundary: 6 sides x 4 squares x 2 triangles; every other face shared by exactly two.
        let boundary = faces.values().filter(|&&c| c == 1).count();
        assert_eq!(boundary, 48);
        assert!(faces.values().all(|&c| c == 1 || c == 2));
    }
}
