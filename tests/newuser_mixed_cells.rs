//! `probe` and `classify` on the files TetGen and Gmsh write by default: TetGen's `.face`
//! triangles after the tets, Gmsh's vertices, lines and triangles before them, hexahedra. Both
//! used to refuse every such file ("only linear tetrahedra are accepted here"); they now work
//! through the tets as the view commands do, and answer per input cell.

mod common;

use common::{fixture, tempdir, tetkit};
use std::path::Path;
use tetkit::formats::{self, cell_type, ArrayData, Cells, Grid};

/// The tets of `g` alone, with their cell data, as a new grid.
fn tets_only(g: &Grid) -> (Grid, Vec<usize>) {
    let keep: Vec<usize> = (0..g.num_cells())
        .filter(|&i| g.cells.types[i] == cell_type::TETRA)
        .collect();
    let mut out = g.clone();
    let mut cells = Cells::new();
    for &i in &keep {
        cells.push(cell_type::TETRA, g.cells.cell(i));
    }
    out.cells = cells;
    out.cell_data = g.cell_data.gather(&keep);
    (out, keep)
}

fn probe_csv(input: &Path, points: &str) -> Vec<Vec<String>> {
    let run = tetkit([
        "probe".as_ref(),
        input.as_os_str(),
        "--points".as_ref(),
        points.as_ref(),
    ]);
    run.assert_success();
    run.stdout_str()
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

const POINTS: &str = "0.5,0.5,0.5;0.1,0.2,0.3;0.9,0.9,0.1;0.25,0.75,0.6;5,5,5";

#[test]
fn probe_answers_on_gmsh_and_tetgen_files_with_their_boundary_cells() {
    let dir = tempdir();
    for (name, points) in [
        ("gmsh/cavity.vtk", POINTS),
        (
            "tetgen/regions.1.ele",
            "0.5,0.5,0.5;0.5,0.5,1.5;0.2,0.7,1.1;3,3,3",
        ),
    ] {
        let input = fixture(name);
        let grid = formats::read(&input).unwrap();
        let (tets, keep) = tets_only(&grid);
        assert!(
            keep.len() < grid.num_cells(),
            "{name} has no boundary cells"
        );
        let plain = dir.path().join("tets.vtu");
        formats::write(&plain, &tets, &formats::WriteOptions::default()).unwrap();
        let got = probe_csv(&input, points);
        let want = probe_csv(&plain, points);
        assert_eq!(got.len(), want.len());
        let mut found = 0;
        for (g, w) in got.iter().zip(&want) {
            // The same values; `tet` is the input cell, i.e. the tet's index in the file.
            assert_eq!(g[..3], w[..3]);
            assert_eq!(g[4..], w[4..], "{name}");
            if w[3].is_empty() {
                assert!(g[3].is_empty(), "{name}: {g:?}");
            } else {
                found += 1;
                let t: usize = w[3].parse().unwrap();
                assert_eq!(g[3], keep[t].to_string(), "{name}");
                assert_eq!(grid.cells.types[keep[t]], cell_type::TETRA);
            }
        }
        assert!(found >= 3, "{name}: {got:?}");
    }
}

fn classify(input: &Path, scene: &Path, out: &Path) -> Grid {
    tetkit([
        "classify".as_ref(),
        input.as_os_str(),
        "--scene".as_ref(),
        scene.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ])
    .assert_success();
    formats::read(out).unwrap()
}

fn codes(g: &Grid) -> Vec<u8> {
    match &g.cell_data.get("region_code").expect("region_code").data {
        ArrayData::UInt8(v) => v.clone(),
        other => panic!("region_code is {}", other.type_name()),
    }
}

#[test]
fn classify_keeps_every_input_cell_and_codes_them_by_their_tets() {
    let dir = tempdir();
    let scene = dir.path().join("scene.toml");
    std::fs::write(
        &scene,
        "[[body]]\nshape = \"sphere\"\ncenter = [0.5, 0.5, 0.15]\nradius = 0.3\naction = \"cut\"\n\
         [[body]]\nshape = \"box\"\nmin = [1.2, -1.0, -1.0]\nmax = [3.0, 0.5, 0.2]\naction = \"cut\"\n",
    )
    .unwrap();
    // Tets beside Gmsh's boundary cells: each tet keeps the code the tets alone get.
    for name in ["gmsh/cavity.vtk", "tetgen/torus.1.ele"] {
        let input = fixture(name);
        let grid = formats::read(&input).unwrap();
        let (tets, keep) = tets_only(&grid);
        let plain = dir.path().join("tets.vtu");
        formats::write(&plain, &tets, &formats::WriteOptions::default()).unwrap();
        let out = classify(&input, &scene, &dir.path().join("mixed.vtu"));
        assert_eq!(out.num_cells(), grid.num_cells(), "{name}");
        assert_eq!(out.cells.types, grid.cells.types);
        for a in &grid.cell_data.arrays {
            assert_eq!(out.cell_data.get(&a.name), Some(a), "{name}: {}", a.name);
        }
        let got = codes(&out);
        let want = codes(&classify(&plain, &scene, &dir.path().join("plain.vtu")));
        let mut is_tet = vec![false; grid.num_cells()];
        for (t, &i) in keep.iter().enumerate() {
            assert_eq!(got[i], want[t], "{name}: cell {i}");
            is_tet[i] = true;
        }
        for (i, &c) in got.iter().enumerate() {
            if !is_tet[i] {
                assert_eq!(c, 0, "{name}: boundary cell {i}");
            }
        }
        assert!(
            want.iter().any(|&c| c != 0),
            "{name}: the scene touches nothing"
        );
    }
    // Hexahedra (Gmsh's extruded block): a cell's code is the union of its tets' codes.
    let input = fixture("gmsh/extruded.vtk");
    let grid = formats::read(&input).unwrap();
    let split = dir.path().join("split.vtu");
    tetkit([
        "convert".as_ref(),
        input.as_os_str(),
        split.as_os_str(),
        "--tetrahedralize".as_ref(),
    ])
    .assert_success();
    let (tets, _) = tets_only(&formats::read(&split).unwrap());
    let plain = dir.path().join("tets.vtu");
    formats::write(&plain, &tets, &formats::WriteOptions::default()).unwrap();
    let per_tet = codes(&classify(&plain, &scene, &dir.path().join("plain.vtu")));
    let parent = tets
        .cell_data
        .get("original_cell_id")
        .unwrap()
        .data
        .to_f64_vec();
    let mut want = vec![0u8; grid.num_cells()];
    for (c, p) in per_tet.iter().zip(parent) {
        want[p as usize] |= c;
    }
    let got = codes(&classify(&input, &scene, &dir.path().join("hex.vtu")));
    assert_eq!(got, want);
    assert!(got.iter().filter(|&&c| c != 0).count() > 10, "{got:?}");
    assert!(got.contains(&0));
}
