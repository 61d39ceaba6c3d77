//! Tests of tetrahedralization: volume, orientation and conformity on random mixed grids.

use super::*;
use crate::geom::tet_volume;
use proptest::prelude::*;
use std::collections::HashMap;

/// An `n` grid of hexahedra over the unit box, interior points jittered (boundary points stay in
/// their planes), point ids permuted by `perm`. `kind[c]` picks how cell `c` is written:
/// 0 hexahedron, 1 voxel ordering, 2 two wedges, 3 six pyramids around a new centre point
/// (`kind` is indexed by the cell's column, see below).
fn mixed_grid(n: [usize; 3], jitter: &[f64], perm: &[usize], kind: &[u8]) -> Grid {
    let [nx, ny, nz] = n;
    let lattice = |i: usize, j: usize, k: usize| i + (nx + 1) * (j + (ny + 1) * k);
    let np = (nx + 1) * (ny + 1) * (nz + 1);
    let mut pts = vec![[0.0; 3]; np];
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                let l = lattice(i, j, k);
                let ijk = [i, j, k];
                let p = [0, 1, 2].map(|a| {
                    let inner = ijk[a] > 0 && ijk[a] < n[a];
                    let d = if inner {
                        jitter[(3 * l + a) % jitter.len()]
                    } else {
                        0.0
                    };
                    (ijk[a] as f64 + d) / n[a] as f64
                });
                pts[perm[l]] = p;
            }
        }
    }
    let mut cells = Cells::new();
    let mut cube = Vec::new();
    let mut extra = Vec::new();
    let mut c = 0i32;
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let h: [i64; 8] = [
                    lattice(i, j, k),
                    lattice(i + 1, j, k),
                    lattice(i + 1, j + 1, k),
                    lattice(i, j + 1, k),
                    lattice(i, j, k + 1),
                    lattice(i + 1, j, k + 1),
                    lattice(i + 1, j + 1, k + 1),
                    lattice(i, j + 1, k + 1),
                ]
                .map(|l| perm[l] as i64);
                // Chosen per column: a wedge pair puts a diagonal on its top and bottom faces,
                // which only the same split above and below matches.
                match kind[(i + nx * j) % kind.len()] {
                    0 => {
                        cells.push(ct::HEXAHEDRON, &h);
                        cube.push(c);
                    }
                    1 => {
                        cells.push(ct::VOXEL, &cells::VOXEL_TO_HEX.map(|l| h[l]));
                        cube.push(c);
                    }
                    2 => {
                        cells.push(ct::WEDGE, &[h[0], h[1], h[2], h[4], h[5], h[6]]);
                        cells.push(ct::WEDGE, &[h[0], h[2], h[3], h[4], h[6], h[7]]);
                        cube.extend([c; 2]);
                    }
                    _ => {
                        let centre = (np + extra.len()) as i64;
                        let mut m = [0.0; 3];
                        for &v in &h {
                            for a in 0..3 {
                                m[a] += pts[v as usize][a] / 8.0;
                            }
                        }
                        extra.push(m);
                        // Each face, seen from the centre, as a pyramid base.
                        for f in cells::HEX_FACES {
                            let b: Vec<i64> = f.iter().map(|&l| h[l]).collect();
                            cells.push(ct::PYRAMID, &[b[0], b[1], b[2], b[3], centre]);
                            cube.push(c);
                        }
                    }
                }
                c += 1;
            }
        }
    }
    pts.extend(extra);
    let mut g = Grid {
        points: DataArray::new(
            "Points",
            3,
            ArrayData::Float64(pts.iter().flatten().copied().collect()),
        ),
        cells,
        ..Grid::default()
    };
    let s: Vec<f32> = pts.iter().map(|p| (p[0] + 2.0 * p[1]) as f32).collect();
    g.point_data
        .insert(DataArray::new("s", 1, ArrayData::Float32(s)));
    g.cell_data
        .insert(DataArray::new("cube", 1, ArrayData::Int32(cube)));
    g
}

/// Checks every tet is positive, the total volume, and that every triangle is shared by two tets
/// or lies on the unit box's boundary.
fn check_tets(g: &Grid, volume: f64) -> Result<(), TestCaseError> {
    let pts = g.points_f64();
    let mut faces: HashMap<[i64; 3], usize> = HashMap::new();
    let mut total = 0.0;
    for c in 0..g.num_cells() {
        prop_assert_eq!(g.cells.types[c], ct::TETRA);
        let t = g.cells.cell(c);
        let p = [0, 1, 2, 3].map(|k| pts[t[k] as usize]);
        let v = tet_volume(&p[0], &p[1], &p[2], &p[3]);
        prop_assert!(v > 0.0, "tet {} {:?} has volume {}", c, t, v);
        total += v;
        for skip in 0..4 {
            let mut f: Vec<i64> = (0..4).filter(|&k| k != skip).map(|k| t[k]).collect();
            f.sort_unstable();
            *faces.entry([f[0], f[1], f[2]]).or_default() += 1;
        }
    }
    prop_assert!(
        (total - volume).abs() < 1e-9,
        "volume {} != {}",
        total,
        volume
    );
    for (f, n) in faces {
        prop_assert!(n <= 2, "face {:?} in {} tets", f, n);
        if n == 1 {
            let on_boundary = (0..3).any(|a| {
                [0.0, 1.0]
                    .iter()
                    .any(|&b| f.iter().all(|&v| pts[v as usize][a] == b))
            });
            prop_assert!(on_boundary, "face {:?} has one tet but is inside", f);
        }
    }
    Ok(())
}

/// Jitter of the inner points: up to 0.15 of a cell per axis. At 0.2 a rare wedge (one seed in
/// proptest-regressions) is cut by its neighbours' forced diagonals into a surface that no point
/// inside sees whole (sampled: the best point is 0.0034 outside one face's plane), which the
/// split refuses by design, since it adds at most one point per cell.
fn grid_strategy() -> impl Strategy<Value = Grid> {
    ([1usize..4, 1usize..4, 1usize..4], any::<u64>())
        .prop_flat_map(|(n, _)| {
            let np = (n[0] + 1) * (n[1] + 1) * (n[2] + 1);
            (
                Just(n),
                prop::collection::vec(-0.15f64..0.15, 1..64),
                Just((0..np).collect::<Vec<usize>>()).prop_shuffle(),
                prop::collection::vec(0u8..4, 1..16),
            )
        })
        .prop_map(|(n, j, perm, kind)| mixed_grid(n, &j, &perm, &kind))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Random jittered grids of hexes, voxels, wedge pairs and pyramid stars, with randomly
    /// numbered points: the tets fill the box exactly and every inner face is shared by 2 tets.
    #[test]
    fn random_mixed_grids_are_conforming(g in grid_strategy()) {
        let (t, report) = tetrahedralize(&g, false).unwrap();
        check_tets(&t, 1.0)?;
        prop_assert_eq!(report.tets_out, t.num_cells());
        // Cell data copied to each child, original ids point back.
        let orig = t.cell_data.get("original_cell_id").unwrap();
        let cube = t.cell_data.get("cube").unwrap();
        let src = g.cell_data.get("cube").unwrap();
        for c in 0..t.num_cells() {
            let p = orig.data.get_f64(c) as usize;
            prop_assert_eq!(cube.data.get_f64(c), src.data.get_f64(p));
        }
        // Point data: one tuple per point, the old ones untouched.
        let s = t.point_data.get("s").unwrap();
        prop_assert_eq!(s.tuples(), t.num_points());
        let s0 = g.point_data.get("s").unwrap().data.to_f64_vec();
        prop_assert_eq!(&s.data.to_f64_vec()[..s0.len()], &s0[..]);
    }
}

fn grid_of(points: Vec<[f64; 3]>, cells: &[(u8, &[i64])]) -> Grid {
    let mut c = Cells::new();
    for (t, ids) in cells {
        c.push(*t, ids);
    }
    Grid {
        points: DataArray::new(
            "Points",
            3,
            ArrayData::Float64(points.iter().flatten().copied().collect()),
        ),
        cells: c,
        ..Grid::default()
    }
}

#[test]
fn lower_cells_kept_or_dropped() {
    let pts = vec![
        [0., 0., 0.],
        [1., 0., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
        [1., 1., 0.],
    ];
    let g = grid_of(
        pts,
        &[
            (ct::TRIANGLE, &[0, 1, 2]),
            (ct::TETRA, &[0, 1, 2, 3]),
            (ct::QUAD, &[0, 1, 4, 2]),
            (ct::LINE, &[0, 3]),
            (ct::VERTEX, &[4]),
        ],
    );
    let (kept, r) = tetrahedralize(&g, true).unwrap();
    assert_eq!(kept.num_cells(), 5);
    assert_eq!(kept.cells.types, g.cells.types);
    assert_eq!(r.dropped, 0);
    assert_eq!(r.kept_lower.len(), 4);
    let (only, r) = tetrahedralize(&g, false).unwrap();
    assert_eq!(only.num_cells(), 1);
    assert_eq!(r.dropped, 4);
    assert_eq!(
        r.dropped_by_type,
        vec![
            (ct::VERTEX, 1),
            (ct::LINE, 1),
            (ct::TRIANGLE, 1),
            (ct::QUAD, 1)
        ]
    );
    assert_eq!(
        only.cell_data.get("original_cell_id").unwrap().data,
        ArrayData::Int64(vec![1])
    );
    assert!(r.lines().iter().any(|l| l.contains("dropped 1 triangle")));
}

#[test]
fn inverted_tet_is_flipped_and_flat_tet_reported() {
    let pts = vec![
        [0., 0., 0.],
        [1., 0., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
        [1., 1., 0.],
    ];
    let g = grid_of(
        pts,
        &[(ct::TETRA, &[0, 2, 1, 3]), (ct::TETRA, &[0, 1, 2, 4])],
    );
    let (t, r) = tetrahedralize(&g, false).unwrap();
    assert_eq!(r.inverted, 1);
    assert_eq!(r.flat_tets, 1);
    assert_eq!(t.cells.cell(0), &[0, 2, 3, 1]);
}

#[test]
fn quadratic_tets_split_conformingly() {
    // Two quadratic tets sharing the face 1-2-3 (with its three mid-edge nodes).
    let c = [
        [0., 0., 0.],
        [1., 0., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
        [1., 1., 1.],
    ];
    let mut pts = c.to_vec();
    let mut mid: HashMap<(usize, usize), i64> = HashMap::new();
    let mut q = |v: [usize; 4]| -> Vec<i64> {
        let mut ids: Vec<i64> = v.iter().map(|&x| x as i64).collect();
        for (a, b) in [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)] {
            let (a, b) = (v[a], v[b]);
            let id = *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                pts.push([0, 1, 2].map(|k| 0.5 * (c[a][k] + c[b][k])));
                pts.len() as i64 - 1
            });
            ids.push(id);
        }
        ids
    };
    let a = q([0, 1, 2, 3]);
    let b = q([1, 2, 3, 4]);
    // Orient b positively: (1,2,3,4) has the apex 4 on the far side of 1-2-3 from 0.
    let g = grid_of(pts, &[(ct::QUADRATIC_TETRA, &a), (ct::QUADRATIC_TETRA, &b)]);
    let (t, r) = tetrahedralize(&g, false).unwrap();
    assert_eq!(t.num_cells(), 16);
    assert_eq!(r.split, vec![(ct::QUADRATIC_TETRA, 2)]);
    let pts = t.points_f64();
    let mut faces: HashMap<Vec<i64>, usize> = HashMap::new();
    let mut vol = 0.0;
    for i in 0..t.num_cells() {
        let ids = t.cells.cell(i);
        let p: Vec<[f64; 3]> = ids.iter().map(|&v| pts[v as usize]).collect();
        let v = tet_volume(&p[0], &p[1], &p[2], &p[3]);
        assert!(v > 0.0);
        vol += v;
        for skip in 0..4 {
            let mut f: Vec<i64> = (0..4).filter(|&k| k != skip).map(|k| ids[k]).collect();
            f.sort_unstable();
            *faces.entry(f).or_default() += 1;
        }
    }
    assert!((vol - (1.0 / 6.0 + 1.0 / 3.0)).abs() < 1e-12, "{vol}");
    // The shared face's 4 triangles are each in two tets.
    // Inside each: 4 corner tets against the octahedron, 4 faces between octahedron tets.
    assert_eq!(faces.values().filter(|&&n| n == 2).count(), 4 + 2 * 8);
}

#[test]
fn warped_hex_gets_a_centre_point_with_interpolated_data() {
    let mut pts = vec![
        [0., 0., 0.],
        [1., 0., 0.],
        [1., 1., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
        [1., 0., 1.],
        [1., 1., 1.],
        [0., 1., 1.],
    ];
    let a = 50f64.to_radians();
    for p in pts.iter_mut().skip(4) {
        let (x, y) = (p[0] - 0.5, p[1] - 0.5);
        *p = [
            0.5 + x * a.cos() - y * a.sin(),
            0.5 + x * a.sin() + y * a.cos(),
            1.0,
        ];
    }
    let ids: Vec<i64> = (0..8).collect();
    let mut g = grid_of(pts, &[(ct::HEXAHEDRON, &ids)]);
    g.point_data.insert(DataArray::new(
        "t",
        1,
        ArrayData::Float64((0..8).map(|i| i as f64).collect()),
    ));
    g.point_data.insert(DataArray::new(
        "label",
        1,
        ArrayData::Int32((0..8).map(|i| 10 + i).collect()),
    ));
    let (t, r) = tetrahedralize(&g, false).unwrap();
    assert_eq!(r.centre_points, 1);
    assert_eq!(t.num_points(), 9);
    assert_eq!(t.point_data.get("t").unwrap().data.get_f64(8), 3.5);
    assert_eq!(t.point_data.get("label").unwrap().data.get_f64(8), 10.0);
    assert_eq!(t.num_cells(), 12);
    let p = t.points_f64();
    for i in 0..t.num_cells() {
        let c = t.cells.cell(i);
        let q: Vec<_> = c.iter().map(|&v| p[v as usize]).collect();
        assert!(tet_volume(&q[0], &q[1], &q[2], &q[3]) > 0.0);
    }
}

#[test]
fn flat_hex_and_unsupported_cells_are_errors() {
    let pts: Vec<[f64; 3]> = (0..24).map(|i| [i as f64, (i % 3) as f64, 0.0]).collect();
    let ids: Vec<i64> = (0..8).collect();
    let g = grid_of(pts.clone(), &[(ct::HEXAHEDRON, &ids)]);
    let e = tetrahedralize(&g, false).unwrap_err().to_string();
    assert!(e.contains("cell 0 (hexahedron"), "{e}");
    // A flat quadratic wedge and pyramid: named as the input has them (their completion adds
    // nodes, not a type).
    let ids: Vec<i64> = (0..15).collect();
    let g = grid_of(
        pts.clone(),
        &[(ct::HEXAHEDRON, &ids[..8]), (ct::QUADRATIC_WEDGE, &ids)],
    );
    let e = tetrahedralize(&g, false).unwrap_err().to_string();
    assert!(e.contains("cell 0 (hexahedron, type 12)"), "{e}");
    let g = grid_of(pts.clone(), &[(ct::QUADRATIC_WEDGE, &ids)]);
    let e = tetrahedralize(&g, false).unwrap_err().to_string();
    assert!(e.contains("cell 0 (quadratic_wedge, type 26)"), "{e}");
    let g = grid_of(pts.clone(), &[(ct::QUADRATIC_PYRAMID, &ids[..13])]);
    let e = tetrahedralize(&g, false).unwrap_err().to_string();
    assert!(e.contains("cell 0 (quadratic_pyramid, type 27)"), "{e}");
    let ids: Vec<i64> = (0..24).collect();
    let g = grid_of(pts, &[(ct::BIQUADRATIC_QUADRATIC_HEXAHEDRON, &ids)]);
    let e = tetrahedralize(&g, false).unwrap_err().to_string();
    assert!(
        e.contains("cell 0 (biquadratic_quadratic_hexahedron") && e.contains("not supported"),
        "{e}"
    );
}

#[test]
fn polyhedron_and_triquadratic_hex() {
    // A unit cube as a polyhedron (faces in a mixed orientation).
    let cube = vec![
        [0., 0., 0.],
        [1., 0., 0.],
        [1., 1., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
        [1., 0., 1.],
        [1., 1., 1.],
        [0., 1., 1.],
    ];
    let ids: Vec<i64> = (0..8).collect();
    let mut g = grid_of(cube, &[(ct::POLYHEDRON, &ids)]);
    let mut stream = vec![6i64];
    for (k, f) in cells::HEX_FACES.iter().enumerate() {
        stream.push(4);
        let mut f: Vec<i64> = f.iter().map(|&l| l as i64).collect();
        if k % 2 == 1 {
            f.reverse();
        }
        stream.extend(f);
    }
    g.cells.polyhedron_faces = Some((stream.clone(), vec![stream.len() as i64]));
    let (t, r) = tetrahedralize(&g, false).unwrap();
    assert_eq!(r.split, vec![(ct::POLYHEDRON, 1)]);
    assert_eq!(t.num_cells(), 6);
    assert!(t.cells.polyhedron_faces.is_none());

    // Triquadratic hex on the lattice {0, 0.5, 1}^3.
    let pts: Vec<[f64; 3]> = cells::TQHEX_LATTICE
        .iter()
        .map(|l| l.map(|x| x as f64 * 0.5))
        .collect();
    let ids: Vec<i64> = (0..27).collect();
    let g = grid_of(pts, &[(ct::TRIQUADRATIC_HEXAHEDRON, &ids)]);
    let (t, _) = tetrahedralize(&g, false).unwrap();
    assert_eq!(t.num_cells(), 48);
    let p = t.points_f64();
    let vol: f64 = (0..48)
        .map(|i| {
            let c = t.cells.cell(i);
            let q: Vec<_> = c.iter().map(|&v| p[v as usize]).collect();
            tet_volume(&q[0], &q[1], &q[2], &q[3])
        })
        .sum();
    assert!((vol - 1.0).abs() < 1e-14);
}

#[test]
fn collapsed_hexahedra_are_split_like_the_cell_they_stand_for() {
    let cube = vec![
        [0., 0., 0.],
        [1., 0., 0.],
        [1., 1., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
        [1., 0., 1.],
        [1., 1., 1.],
        [0., 1., 1.],
    ];
    // Nodes 3 = 2 and 7 = 6: the wedge 0-1-2 / 4-5-6, volume 1/2. Nodes 4..7 = 4: a pyramid, 1/3.
    for (ids, volume, tets) in [
        (vec![0i64, 1, 2, 2, 4, 5, 6, 6], 0.5, 3),
        (vec![0i64, 1, 2, 3, 4, 4, 4, 4], 1.0 / 3.0, 2),
    ] {
        let g = grid_of(cube.clone(), &[(ct::HEXAHEDRON, &ids)]);
        let (t, r) = tetrahedralize(&g, false).unwrap();
        assert_eq!(t.num_cells(), tets, "{ids:?}");
        assert_eq!(r.centre_points, 0);
        let p = t.points_f64();
        let v: f64 = (0..t.num_cells())
            .map(|i| {
                let c = t.cells.cell(i);
                let q: Vec<_> = c.iter().map(|&v| p[v as usize]).collect();
                let v = tet_volume(&q[0], &q[1], &q[2], &q[3]);
                assert!(v > 0.0);
                v
            })
            .sum();
        assert!((v - volume).abs() < 1e-15, "{ids:?}: {v}");
    }
}

#[test]
fn second_order_wedges_split_inverted_once_tangled_refused() -> anyhow::Result<()> {
    // VTK's positive wedge with its mid-edge nodes and quad-face centres (18 nodes); `lift` moves
    // the middle layer (vertical edges' mid nodes, face centres) to that height.
    let wedge = |flip: bool, lift: f64| -> Vec<[f64; 3]> {
        let c = [
            [0., 0., 0.],
            [0., 1., 0.],
            [1., 0., 0.],
            [0., 0., 1.],
            [0., 1., 1.],
            [1., 0., 1.],
        ];
        let of: [&[usize]; 18] = [
            &[0],
            &[1],
            &[2],
            &[3],
            &[4],
            &[5],
            &[0, 1],
            &[1, 2],
            &[2, 0],
            &[3, 4],
            &[4, 5],
            &[5, 3],
            &[0, 3],
            &[1, 4],
            &[2, 5],
            &[0, 1, 4, 3],
            &[1, 2, 5, 4],
            &[2, 0, 3, 5],
        ];
        of.iter()
            .enumerate()
            .map(|(n, of)| {
                let mut p = [0, 1, 2].map(|k| of.iter().map(|&l| c[l][k]).sum::<f64>());
                p = p.map(|x| x / of.len() as f64);
                if (12..18).contains(&n) {
                    p[2] = lift;
                }
                if flip {
                    p[2] = -p[2];
                }
                p
            })
            .collect()
    };
    let ids: Vec<i64> = (0..18).collect();
    for (t, n) in [
        (ct::BIQUADRATIC_QUADRATIC_WEDGE, 18),
        (ct::QUADRATIC_WEDGE, 15),
    ] {
        for flip in [false, true] {
            let g = grid_of(wedge(flip, 0.5), &[(t, &ids[..n])]);
            let (out, r) = tetrahedralize(&g, false)?;
            assert_eq!(r.inverted, flip as usize, "type {t}");
            assert_eq!(r.split, vec![(t, 1)]);
            let p = out.points_f64();
            let v: f64 = (0..out.num_cells())
                .map(|i| {
                    let q = out
                        .cells
                        .cell(i)
                        .iter()
                        .map(|&v| p[v as usize])
                        .collect::<Vec<_>>();
                    let v = tet_volume(&q[0], &q[1], &q[2], &q[3]);
                    assert!(v > 0.0);
                    v
                })
                .sum();
            assert!((v - 0.5).abs() < 1e-15, "type {t}: {v}");
        }
        // The middle layer above the top: the upper pieces turn over, the lower ones do not.
        let g = grid_of(wedge(false, 1.5), &[(t, &ids[..n])]);
        let e = tetrahedralize(&g, false).unwrap_err().to_string();
        assert!(
            e.contains(&format!("cell 0 ({}, type {t}): is tangled", ct::name(t))),
            "{e}"
        );
    }
    // The 12-node wedge (no middle layer): 4 wedges, 12 tets, no new point.
    let nodes = wedge(false, 0.5);
    let g = grid_of(
        nodes[..12].to_vec(),
        &[(ct::QUADRATIC_LINEAR_WEDGE, &ids[..12])],
    );
    let (out, r) = tetrahedralize(&g, false)?;
    assert_eq!(r.split, vec![(ct::QUADRATIC_LINEAR_WEDGE, 1)]);
    assert_eq!((out.num_cells(), out.num_points()), (12, 12));
    let p = out.points_f64();
    let v: f64 = (0..12)
        .map(|i| {
            let q = out
                .cells
                .cell(i)
                .iter()
                .map(|&v| p[v as usize])
                .collect::<Vec<_>>();
            tet_volume(&q[0], &q[1], &q[2], &q[3])
        })
        .sum();
    assert!((v - 0.5).abs() < 1e-15, "{v}");
    Ok(())
}

#[test]
fn higher_order_cells_split_by_their_corners() -> anyhow::Result<()> {
    // A unit cube as a 27-node Lagrange hexahedron (corners first, then edge, face and body
    // nodes, here only placed at the centre: they must not matter), and a Bezier tet of 10
    // nodes on top of it, written inverted.
    let mut pts = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
        [0.5, 0.5, 2.0],
    ];
    let centre = pts.len() as i64;
    pts.push([0.5, 0.5, 0.5]);
    let hex: Vec<i64> = (0..8).chain(std::iter::repeat_n(centre, 19)).collect();
    let tet: Vec<i64> = [4, 6, 5, 8]
        .into_iter()
        .chain(std::iter::repeat_n(centre, 6))
        .collect();
    let g = grid_of(
        pts,
        &[
            (ct::LAGRANGE_HEXAHEDRON, &hex),
            (ct::BEZIER_TETRAHEDRON, &tet),
        ],
    );
    let (out, report) = tetrahedralize(&g, false)?;
    let pts = out.points_f64();
    let mut volume = 0.0;
    for c in 0..out.num_cells() {
        anyhow::ensure!(out.cells.types[c] == ct::TETRA, "cell {c} is not a tet");
        let t = out.cells.cell(c);
        anyhow::ensure!(
            t.iter().all(|&v| v != centre),
            "a higher-order node was used"
        );
        let v = tet_volume(
            &pts[t[0] as usize],
            &pts[t[1] as usize],
            &pts[t[2] as usize],
            &pts[t[3] as usize],
        );
        anyhow::ensure!(v > 0.0, "tet {c} has volume {v}");
        volume += v;
    }
    // The cube and the tet above it (base area 1/2, height 1): 1 + 1/6.
    anyhow::ensure!(
        (volume - (1.0 + 1.0 / 6.0)).abs() < 1e-12,
        "volume {volume}"
    );
    assert_eq!(report.inverted, 1);
    assert!(report
        .lines()
        .iter()
        .any(|l| l.contains("lagrange_hexahedron") && l.contains("by their corners")));
    // Fewer nodes than corners is an error naming the cell.
    let short = grid_of(vec![[0.0; 3]; 4], &[(ct::LAGRANGE_TETRAHEDRON, &[0, 1, 2])]);
    anyhow::ensure!(
        tetrahedralize(&short, false).is_err(),
        "a 3-node tet accepted"
    );
    Ok(())
}

#[test]
fn second_order_lagrange_tets_split_over_their_nodes_as_quadratic_tetra() -> anyhow::Result<()> {
    // A tet with its mid-edge nodes pushed off the straight edges (a curved cell), and a
    // third-order Lagrange tet (20 nodes) beside it, which still goes by its corners.
    let mut pts = vec![
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 2.0, 0.0],
        [0.0, 0.0, 2.0],
    ];
    for (a, b) in [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)] {
        let (p, q): ([f64; 3], [f64; 3]) = (pts[a], pts[b]);
        pts.push([0, 1, 2].map(|k| 0.5 * (p[k] + q[k]) + 0.05 * (k as f64 + 1.0)));
    }
    let nodes: Vec<i64> = (0..10).collect();
    let lag = grid_of(pts.clone(), &[(ct::LAGRANGE_TETRAHEDRON, &nodes)]);
    let quad = grid_of(pts.clone(), &[(ct::QUADRATIC_TETRA, &nodes)]);
    let (a, report) = tetrahedralize(&lag, false)?;
    let (b, _) = tetrahedralize(&quad, false)?;
    assert_eq!(a.num_cells(), 8);
    assert_eq!(a.cells.types, b.cells.types);
    for c in 0..8 {
        assert_eq!(a.cells.cell(c), b.cells.cell(c), "tet {c}");
    }
    // Every node is used, so the curved edges shape the pieces.
    let mut used: Vec<i64> = (0..8).flat_map(|c| a.cells.cell(c).to_vec()).collect();
    used.sort();
    used.dedup();
    assert_eq!(used, nodes);
    assert!(report
        .lines()
        .iter()
        .any(|l| l.contains("lagrange_tetrahedron") && l.contains("10 nodes")));
    // Order 3: 20 nodes, corners only.
    let centre = pts.len() as i64;
    pts.push([0.4, 0.4, 0.4]);
    let third: Vec<i64> = (0..4).chain(std::iter::repeat_n(centre, 16)).collect();
    let g = grid_of(pts, &[(ct::LAGRANGE_TETRAHEDRON, &third)]);
    let (c, _) = tetrahedralize(&g, false)?;
    assert_eq!(c.num_cells(), 1);
    assert_eq!(c.cells.cell(0).len(), 4);
    Ok(())
}
