//! `convert` to TetGen files from what users have: a TetGen mesh read with its `.face` (it was
//! refused: "TetGen files hold only linear tetrahedra"), quadratic TetGen output (`-o2`), a Gmsh
//! mesh with `--tetrahedralize` (its boundary triangles used to be dropped though the writer
//! makes `.face`), and ParaView-like arrays TetGen cannot hold (dropped silently before; now
//! named on stderr).

mod common;

use common::{fixture, tempdir, tetkit};
use tetkit::formats::{self, cell_type};

#[test]
fn tetgen_meshes_with_boundary_faces_convert_back_to_tetgen() {
    let dir = tempdir();
    for name in ["tetgen/torus.1.ele", "tetgen/quadratic.1.ele"] {
        let input = fixture(name);
        let out = dir.path().join("out.ele");
        tetkit(["convert".as_ref(), input.as_os_str(), out.as_os_str()]).assert_success();
        assert!(dir.path().join("out.face").is_file(), "{name}: no .face");
        let a = formats::read(&input).unwrap();
        let b = formats::read(&out).unwrap();
        assert_eq!(a.cells, b.cells, "{name}");
        assert_eq!(
            a.points.data.to_f64_vec(),
            b.points.data.to_f64_vec(),
            "{name}"
        );
        assert_eq!(
            a.cell_data.get("boundary_marker"),
            b.cell_data.get("boundary_marker"),
            "{name}"
        );
    }
}

#[test]
fn tetrahedralize_to_tetgen_keeps_the_boundary_triangles() {
    let dir = tempdir();
    let input = fixture("gmsh/cavity.vtk");
    let grid = formats::read(&input).unwrap();
    let count = |g: &formats::Grid, t: u8| g.cells.types.iter().filter(|&&x| x == t).count();
    let out = dir.path().join("cavity.ele");
    let run = tetkit([
        "convert".as_ref(),
        input.as_os_str(),
        out.as_os_str(),
        "--tetrahedralize".as_ref(),
    ]);
    run.assert_success();
    // Gmsh's vertices and lines cannot be TetGen records: dropped, and said.
    let lower = count(&grid, cell_type::VERTEX) + count(&grid, cell_type::LINE);
    assert!(
        run.stderr.contains(&format!(
            "dropped {lower} cells that TetGen files cannot hold"
        )),
        "{}",
        run.stderr
    );
    let back = formats::read(&out).unwrap();
    assert_eq!(
        count(&back, cell_type::TRIANGLE),
        count(&grid, cell_type::TRIANGLE)
    );
    assert_eq!(
        count(&back, cell_type::TETRA),
        count(&grid, cell_type::TETRA)
    );
    assert_eq!(back.num_cells(), grid.num_cells() - lower);
}

#[test]
fn what_tetgen_cannot_hold_is_named_not_silently_dropped() {
    let dir = tempdir();
    let input = dir.path().join("in.vtu");
    // Point and cell strings and field data, as ParaView files carry.
    let mut grid = formats::read(&fixture("scenes/cube_mesh.vtk")).unwrap();
    let n = grid.num_points();
    grid.point_data.insert(formats::DataArray::new(
        "label",
        1,
        formats::ArrayData::String((0..n).map(|i| format!("p{i}")).collect()),
    ));
    grid.field_data.push(formats::DataArray::new(
        "units",
        1,
        formats::ArrayData::String(vec!["m".into()]),
    ));
    formats::write(&input, &grid, &Default::default()).unwrap();
    let out = dir.path().join("out.ele");
    let run = tetkit(["convert".as_ref(), input.as_os_str(), out.as_os_str()]);
    run.assert_success();
    for needle in [
        "out.ele",
        "point array 'label' (strings)",
        "field data 'units'",
    ] {
        assert!(run.stderr.contains(needle), "{needle}: {}", run.stderr);
    }
    // A cell TetGen cannot hold still fails before writing anything, naming the fix.
    let bad = dir.path().join("bad.ele");
    tetkit([
        "convert".as_ref(),
        fixture("mixed/mixed.vtk").as_os_str(),
        bad.as_os_str(),
    ])
    .assert_failure(&["bad.ele", "cell 0 is a hexahedron", "--tetrahedralize"]);
    assert!(!bad.exists() && !dir.path().join("bad.node").exists());
}

/// What a `.face` line and TetGen's reals cannot hold is named too: a Gmsh mesh's boundary
/// triangles lost their `gmsh:physical` (only `boundary_marker` goes to `.face`) and Int64
/// values past 2^53 came back rounded, both without a word. Without a `boundary_marker`, the
/// triangles' `gmsh:physical` is now written as their `.face` markers (their physical surfaces
/// are what TetGen's boundary markers hold); other cell arrays on them are still named.
#[test]
fn face_arrays_and_huge_integers_are_named_when_tetgen_cannot_hold_them() {
    let dir = tempdir();
    let out = dir.path().join("b.node");
    let src = formats::read(&fixture("msh/twobodies_41.msh")).unwrap();
    let r = tetkit([
        "convert".as_ref(),
        fixture("msh/twobodies_41.msh").as_os_str(),
        out.as_os_str(),
    ]);
    r.assert_success();
    assert!(
        r.stderr
            .contains("gmsh:physical written as their .face markers"),
        "{}",
        r.stderr
    );
    assert!(
        !r.stderr.contains("cell array 'gmsh:physical' on"),
        "{}",
        r.stderr
    );
    assert!(
        r.stderr
            .contains("cell array 'gmsh:geometrical' on the 26 boundary triangles"),
        "{}",
        r.stderr
    );
    // The triangles read back with their physical surfaces as boundary markers.
    let back = formats::read(&dir.path().join("b.ele")).unwrap();
    let tri = |g: &formats::Grid| -> Vec<usize> {
        (0..g.num_cells())
            .filter(|&i| g.cells.types[i] == formats::cell_type::TRIANGLE)
            .collect()
    };
    let (ts, tb) = (tri(&src), tri(&back));
    assert_eq!(ts.len(), 26);
    assert_eq!(tb.len(), 26);
    let phys = src.cell_data.get("gmsh:physical").unwrap();
    let marker = back.cell_data.get("boundary_marker").unwrap();
    let want: Vec<f64> = ts.iter().map(|&i| phys.data.get_f64(i)).collect();
    let got: Vec<f64> = tb.iter().map(|&i| marker.data.get_f64(i)).collect();
    assert_eq!(got, want);
    // Gmsh's physical tags start at 1: a marker of 0 would be TetGen's "none".
    assert!(want.iter().all(|&v| v >= 1.0), "{want:?}");
    let mut g = formats::read(&fixture("tetgen/torus.1.ele")).unwrap();
    let n = g.num_points();
    g.point_data.insert(formats::DataArray::new(
        "id",
        1,
        formats::ArrayData::Int64((0..n as i64).map(|i| (1 << 53) + i).collect()),
    ));
    let vtu = dir.path().join("big.vtu");
    formats::write(&vtu, &g, &Default::default()).unwrap();
    let r = tetkit([
        "convert".as_ref(),
        vtu.as_os_str(),
        dir.path().join("big.node").as_os_str(),
    ]);
    r.assert_success();
    assert!(
        r.stderr
            .contains("point array 'id' exactly (integers past 2^53"),
        "{}",
        r.stderr
    );
}
