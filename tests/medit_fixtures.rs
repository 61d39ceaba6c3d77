//! Medit `.mesh` through the real binary: the fixtures from TetGen and Gmsh
//! (scripts/make_medit_fixtures.sh) read, convert to VTU and back unchanged, agree with the same
//! tool's legacy VTK of the mesh, and give VTK positive cell volumes; what Medit cannot hold is
//! refused (cell types) or named on stderr (arrays).

mod common;

use common::{fixture, grids_bit_equal, require_vtk, tempdir, tetkit, vtk_check};
use std::path::PathBuf;
use tetkit::formats::{self, cell_type as ct, ArrayData, Grid};

const MESHES: [&str; 4] = [
    "medit/tetgen_regions.mesh",
    "medit/gmsh_tets.mesh",
    "medit/gmsh_hex.mesh",
    "medit/hand_mixed.mesh",
];

fn read(p: &std::path::Path) -> Grid {
    formats::read(p).unwrap_or_else(|e| panic!("{e}"))
}

fn ints(g: &Grid, cells: bool, name: &str) -> Vec<i64> {
    let attrs = if cells { &g.cell_data } else { &g.point_data };
    let a = attrs
        .get(name)
        .unwrap_or_else(|| panic!("no array '{name}'"));
    a.data.to_f64_vec().iter().map(|&x| x as i64).collect()
}

#[test]
fn info_reads_every_fixture() {
    for m in MESHES {
        let r = tetkit(["info".as_ref(), fixture(m).as_os_str(), "--json".as_ref()]);
        r.assert_success();
        let v: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
        let g = read(&fixture(m));
        assert_eq!(v["points"], g.num_points(), "{m}");
        assert_eq!(v["cells"], g.num_cells(), "{m}");
        assert!(g.num_cells() > 0, "{m}");
    }
}

#[test]
fn what_the_fixtures_hold() {
    let t = read(&fixture("medit/tetgen_regions.mesh"));
    let count = |g: &Grid, ty: u8| g.cells.types.iter().filter(|&&x| x == ty).count();
    assert_eq!(count(&t, ct::TETRA), 261);
    // TetGen writes Triangles, Tetrahedra, Corners, then Edges: cells follow the file.
    let first_edge = t.cells.types.iter().position(|&x| x == ct::LINE).unwrap();
    assert!(t.cells.types[first_edge..].iter().all(|&x| x == ct::LINE));
    assert_eq!(ints(&t, false, "medit:corner").iter().sum::<i64>(), 12);
    let g = read(&fixture("medit/gmsh_tets.mesh"));
    let refs = ints(&g, true, "medit:ref");
    for (i, &ty) in g.cells.types.iter().enumerate() {
        match ty {
            ct::TRIANGLE => assert_eq!(refs[i], 3),
            ct::TETRA => assert!(refs[i] == 10 || refs[i] == 20),
            _ => panic!("unexpected {}", ct::name(ty)),
        }
    }
    assert!(refs.contains(&10) && refs.contains(&20));
    let h = read(&fixture("medit/gmsh_hex.mesh"));
    assert_eq!(count(&h, ct::HEXAHEDRON), 27);
    let m = read(&fixture("medit/hand_mixed.mesh"));
    assert_eq!(
        m.cells.types,
        vec![ct::LINE, ct::LINE, ct::HEXAHEDRON, ct::WEDGE, ct::PYRAMID]
    );
    assert_eq!(ints(&m, true, "medit:ridge"), vec![0, 1, 0, 0, 0]);
    assert_eq!(
        ints(&m, false, "medit:required"),
        vec![1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0]
    );
}

/// `convert X.mesh a.vtu`, `convert a.vtu b.mesh`: every step gives back the same grid, refs and
/// flags included; the written .mesh is stable (writing it again gives the same bytes).
#[test]
fn mesh_to_vtu_and_back() {
    let dir = tempdir();
    for m in MESHES {
        let src = fixture(m);
        let stem = src.file_stem().unwrap().to_string_lossy().into_owned();
        let vtu = dir.path().join(format!("{stem}.vtu"));
        let back = dir.path().join(format!("{stem}.mesh"));
        let again = dir.path().join(format!("{stem}.again.mesh"));
        tetkit(["convert".as_ref(), src.as_os_str(), vtu.as_os_str()]).assert_success();
        let r = tetkit([
            "convert".as_ref(),
            vtu.as_os_str(),
            "-o".as_ref(),
            back.as_os_str(),
        ]);
        r.assert_success();
        assert!(
            !r.stderr.contains("dropped"),
            "{m}: nothing should be dropped:\n{}",
            r.stderr
        );
        tetkit(["convert".as_ref(), back.as_os_str(), again.as_os_str()]).assert_success();
        let g = read(&src);
        for p in [&vtu, &back, &again] {
            if let Err(e) = grids_bit_equal(&g, &read(p)) {
                panic!("{m} -> {}: {e}", p.display());
            }
        }
        assert_eq!(
            std::fs::read(&back).unwrap(),
            std::fs::read(&again).unwrap(),
            "{m}"
        );
    }
}

/// The .mesh and the other file (Gmsh's .vtk, TetGen's .node/.ele) the same tool wrote of one
/// mesh hold the same points and 3-D cells, and their refs are the tool's region/entity numbers.
#[test]
fn agrees_with_the_same_tools_vtk() {
    for (mesh, vtk, array) in [
        (
            "medit/tetgen_regions.mesh",
            "medit/tetgen_regions.ele",
            "region",
        ),
        (
            "medit/gmsh_tets.mesh",
            "medit/gmsh_tets.vtk",
            "CellEntityIds",
        ),
        ("medit/gmsh_hex.mesh", "medit/gmsh_hex.vtk", "CellEntityIds"),
    ] {
        let a = read(&fixture(mesh));
        let b = read(&fixture(vtk));
        assert_eq!(a.num_points(), b.num_points(), "{mesh}");
        for i in 0..a.num_points() {
            let (p, q) = (a.point(i), b.point(i));
            for k in 0..3 {
                assert!(
                    (p[k] - q[k]).abs() <= 1e-9,
                    "{mesh}: point {i}: {p:?} vs {q:?}"
                );
            }
        }
        // The 3-D cells, in order, with their refs.
        let solid = |g: &Grid| -> Vec<usize> {
            (0..g.num_cells())
                .filter(|&i| ct::dimension(g.cells.types[i]) == 3)
                .collect()
        };
        let (sa, sb) = (solid(&a), solid(&b));
        assert_eq!(sa.len(), sb.len(), "{mesh}");
        let ra = ints(&a, true, "medit:ref");
        let rb = ints(&b, true, array);
        for (&i, &j) in sa.iter().zip(&sb) {
            assert_eq!(a.cells.types[i], b.cells.types[j], "{mesh}");
            assert_eq!(a.cells.cell(i), b.cells.cell(j), "{mesh}: cell {i}");
            assert_eq!(ra[i], rb[j], "{mesh}: ref of cell {i}");
        }
    }
}

/// VTK reads the converted .vtu with the same counts and finds every 3-D cell's volume positive
/// (the node orders tetkit keeps or maps are VTK's).
#[test]
fn vtk_finds_positive_volumes() {
    if !require_vtk("vtk_finds_positive_volumes") {
        return;
    }
    let dir = tempdir();
    for m in MESHES {
        let src = fixture(m);
        let vtu: PathBuf = dir.path().join(format!(
            "{}.vtu",
            src.file_stem().unwrap().to_string_lossy()
        ));
        tetkit(["convert".as_ref(), src.as_os_str(), vtu.as_os_str()]).assert_success();
        let g = read(&src);
        let v = vtk_check(&vtu, true);
        if let Err(e) = common::compare_with_vtk(&g, &v) {
            panic!("{m}: tetkit and VTK disagree:\n{e}");
        }
        let min = v["min_cell_volume"].as_f64().unwrap();
        assert!(min > 0.0, "{m}: smallest cell volume {min}");
        let (vol, tri) = (
            v["volume"].as_f64().unwrap(),
            v["tri_volume"].as_f64().unwrap(),
        );
        assert!(
            (vol - tri).abs() <= 1e-9 * tri.abs().max(1.0),
            "{m}: {vol} vs {tri}"
        );
    }
}

#[test]
fn quadratic_cells_are_refused_and_nothing_is_left() {
    let dir = tempdir();
    let out = dir.path().join("x.mesh");
    tetkit([
        "convert".as_ref(),
        fixture("tetgen/quadratic.1.ele").as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ])
    .assert_failure(&["x.mesh", "Medit files hold", "12 quadratic_tetra cells"]);
    assert!(common::dir_listing(dir.path()).is_empty());
}

#[test]
fn dropped_arrays_are_named() {
    let dir = tempdir();
    let out = dir.path().join("sphere.mesh");
    let r = tetkit([
        "convert".as_ref(),
        fixture("tetgen/sphere.1.ele").as_os_str(),
        out.as_os_str(),
    ]);
    r.assert_success();
    for n in [
        "sphere.mesh",
        "cell array 'boundary_marker'",
        "cell array 'neighbors'",
        "dropped",
    ] {
        assert!(r.stderr.contains(n), "stderr lacks {n:?}:\n{}", r.stderr);
    }
    let g = read(&out);
    let src = read(&fixture("tetgen/sphere.1.ele"));
    assert_eq!(g.cells, src.cells);
    assert!(matches!(
        &g.cell_data.get("medit:ref").unwrap().data,
        ArrayData::Int32(v) if v.iter().all(|&x| x == 0)
    ));
}

#[test]
fn stdin_and_stdout() {
    let text = std::fs::read(fixture("medit/gmsh_hex.mesh")).unwrap();
    let r = common::tetkit_stdin(["convert", "-", "-", "--to", "mesh"], &text);
    r.assert_success();
    let a = formats::read_bytes(&r.stdout, formats::Format::Medit).unwrap();
    grids_bit_equal(&a, &read(&fixture("medit/gmsh_hex.mesh"))).unwrap();
}

#[test]
fn binary_meshb_is_refused_clearly() {
    let dir = tempdir();
    let p = dir.path().join("x.meshb");
    std::fs::write(&p, [1u8, 0, 0, 0]).unwrap();
    tetkit(["info".as_ref(), p.as_os_str()]).assert_failure(&["x.meshb", "binary Medit"]);
}

#[test]
fn a_truncated_fixture_is_refused_with_its_line() {
    let dir = tempdir();
    let text = std::fs::read_to_string(fixture("medit/gmsh_tets.mesh")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    // Cut inside the Tetrahedra section, mid-record.
    let at = lines.iter().position(|l| l.trim() == "Tetrahedra").unwrap() + 5;
    let cut = format!("{}\n{}", lines[..at].join("\n"), &lines[at][..6]);
    let p = dir.path().join("cut.mesh");
    std::fs::write(&p, cut).unwrap();
    let want = format!("line {}", at + 1);
    tetkit(["info".as_ref(), p.as_os_str()]).assert_failure(&[
        "cut.mesh",
        &want,
        "truncated",
        "Tetrahedra element 4",
    ]);
}

/// Gmsh (when installed) reads the .mesh tetkit writes: saved again by Gmsh as .mesh, it holds
/// the same cells in order (corners at the same places) with the same refs. (Gmsh renumbers
/// vertices and their refs by entity, and 4.8 reads no prisms or pyramids, so the tet and hex
/// fixtures are used.)
#[test]
fn gmsh_reads_what_tetkit_writes() {
    let ok = std::process::Command::new("gmsh")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        eprintln!("SKIPPED gmsh_reads_what_tetkit_writes: no gmsh on PATH");
        return;
    }
    let dir = tempdir();
    for m in ["medit/gmsh_tets.mesh", "medit/gmsh_hex.mesh"] {
        // Through VTU, so the .mesh is tetkit's own writing, not a copy.
        let vtu = dir.path().join("a.vtu");
        let out = dir.path().join("a.mesh");
        let back = dir.path().join("b.mesh");
        tetkit(["convert".as_ref(), fixture(m).as_os_str(), vtu.as_os_str()]).assert_success();
        tetkit(["convert".as_ref(), vtu.as_os_str(), out.as_os_str()]).assert_success();
        let st = std::process::Command::new("gmsh")
            .arg("-0")
            .arg(&out)
            .args(["-format", "mesh", "-o"])
            .arg(&back)
            .output()
            .unwrap();
        assert!(st.status.success(), "{m}: gmsh failed: {st:?}");
        let (a, b) = (read(&out), read(&back));
        // Gmsh renumbers vertices (grouped by entity) and prints 14 significant digits: compare
        // each cell's corners by position.
        assert_eq!(a.num_points(), b.num_points(), "{m}");
        assert_eq!(a.cells.types, b.cells.types, "{m}");
        for i in 0..a.num_cells() {
            for (&x, &y) in a.cells.cell(i).iter().zip(b.cells.cell(i)) {
                let (p, q) = (a.point(x as usize), b.point(y as usize));
                assert!(
                    (0..3).all(|k| (p[k] - q[k]).abs() <= 1e-12),
                    "{m}: cell {i}: {p:?} vs {q:?}"
                );
            }
        }
        assert_eq!(
            ints(&a, true, "medit:ref"),
            ints(&b, true, "medit:ref"),
            "{m}"
        );
    }
}

/// A Gmsh mesh converted to Medit lost its regions: `gmsh:physical` was dropped and every ref
/// written 0. With no `medit:ref`, the cell refs come from `gmsh:physical` now (or VTK's
/// `CellEntityIds`), said on stderr; a `medit:ref` stored as whole reals is taken too (it was
/// dropped as an array Medit cannot hold).
#[test]
fn regions_become_refs() {
    let dir = tempdir();
    let src_path = fixture("msh/twobodies_41.msh");
    let src = read(&src_path);
    let physical = ints(&src, true, "gmsh:physical");
    assert!(physical.iter().any(|&p| p != physical[0]), "{physical:?}");
    let out = dir.path().join("two.mesh");
    let r = tetkit(["convert".as_ref(), src_path.as_os_str(), out.as_os_str()]);
    r.assert_success();
    assert!(
        r.stderr.contains("cell refs written from 'gmsh:physical'"),
        "{}",
        r.stderr
    );
    assert!(
        !r.stderr.contains("cell array 'gmsh:physical'"),
        "{}",
        r.stderr
    );
    let g = read(&out);
    assert_eq!(g.cells.types, src.cells.types);
    assert_eq!(ints(&g, true, "medit:ref"), physical);

    // Refs kept as Float64 (whole numbers) by another tool.
    let mut grid = src.clone();
    grid.cell_data.arrays.clear();
    grid.cell_data.insert(tetkit::formats::DataArray::new(
        "medit:ref",
        1,
        ArrayData::Float64(physical.iter().map(|&p| p as f64 + 10.0).collect()),
    ));
    let vtu = dir.path().join("float_refs.vtu");
    formats::write(&vtu, &grid, &Default::default()).unwrap();
    let out = dir.path().join("float_refs.mesh");
    let r = tetkit(["convert".as_ref(), vtu.as_os_str(), out.as_os_str()]);
    r.assert_success();
    assert!(!r.stderr.contains("'medit:ref'"), "{}", r.stderr);
    let want: Vec<i64> = physical.iter().map(|&p| p + 10).collect();
    assert_eq!(ints(&read(&out), true, "medit:ref"), want);
}
