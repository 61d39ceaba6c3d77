//! `tetkit info` and `tetkit convert` run as a user runs them: real binary, real files, pipes, and
//! the error cases (exit code, message naming file and place, no partial output).

mod common;

use common::*;

#[test]
fn crc32_matches_zlib() {
    // The standard check value of CRC-32/ISO-HDLC (zlib.crc32(b"123456789")).
    assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
    assert_eq!(crc32(b""), 0);
}

#[test]
fn info_missing_file_names_it() {
    let dir = tempdir();
    let missing = dir.path().join("nope.vtu");
    tetkit(["info".as_ref(), missing.as_os_str()]).assert_failure(&["nope.vtu"]);
}

#[test]
fn unknown_extension_is_refused() {
    let dir = tempdir();
    let p = dir.path().join("mesh.xyz");
    std::fs::write(&p, "hello").unwrap();
    tetkit(["info".as_ref(), p.as_os_str()]).assert_failure(&["mesh.xyz", ".xyz"]);
}

#[test]
fn convert_failure_leaves_no_output() {
    let dir = tempdir();
    let input = dir.path().join("in.vtu");
    std::fs::write(&input, "<VTKFile type=\"UnstructuredGrid\"><broken").unwrap();
    let out = dir.path().join("out.vtu");
    tetkit(["convert".as_ref(), input.as_os_str(), out.as_os_str()]).assert_failure(&["in.vtu"]);
    assert_eq!(dir_listing(dir.path()), vec!["in.vtu".to_string()]);
}

#[test]
fn stdin_that_is_no_mesh_is_refused() {
    tetkit_stdin(["info", "-"], b"just some text\n").assert_failure(&["<stdin>"]);
}

/// The check script itself: VTK writes a mesh with known content, vtk_check.py reports it, and
/// the Rust checksum of the same values agrees with the script's.
#[test]
fn vtk_check_script_reports_what_vtk_wrote() {
    if !require_vtk("vtk_check_script_reports_what_vtk_wrote") {
        return;
    }
    let dir = tempdir();
    let code = r#"
import sys, vtk
pts = vtk.vtkPoints(); pts.SetDataTypeToDouble()
for p in [(0,0,0),(1,0,0),(0,1,0),(0,0,1),(1,1,1)]: pts.InsertNextPoint(p)
g = vtk.vtkUnstructuredGrid(); g.SetPoints(pts)
g.InsertNextCell(vtk.VTK_TETRA, 4, [0,1,2,3])
g.InsertNextCell(vtk.VTK_TETRA, 4, [1,2,3,4])
g.InsertNextCell(vtk.VTK_TRIANGLE, 3, [0,1,2])
a = vtk.vtkIntArray(); a.SetName("label"); a.SetNumberOfComponents(2)
a.SetComponentName(0, "lo"); a.SetComponentName(1, "hi")
for t in [(1,-2),(3,4),(5,600000)]: a.InsertNextTuple2(*t)
g.GetCellData().AddArray(a)
s = vtk.vtkFloatArray(); s.SetName("s")
for v in [0.5, 1.5, 2.5, 3.5, 4.5]: s.InsertNextValue(v)
g.GetPointData().AddArray(s)
for name, w in [("m.vtu", vtk.vtkXMLUnstructuredGridWriter()), ("m.vtk", vtk.vtkUnstructuredGridWriter())]:
    w.SetFileName(sys.argv[1] + "/" + name); w.SetInputData(g); w.Write()
"#;
    vtk_python(code, &[dir.path().to_str().unwrap()]);
    for name in ["m.vtu", "m.vtk"] {
        let v = vtk_check(&dir.path().join(name), true);
        assert_eq!(v["points"], 5, "{name}");
        assert_eq!(v["cells"], 3, "{name}");
        assert_eq!(v["cell_types"]["10"], 2, "{name}");
        assert_eq!(v["cell_types"]["5"], 1, "{name}");
        assert_eq!(
            v["bounds"],
            serde_json::json!([0.0, 1.0, 0.0, 1.0, 0.0, 1.0])
        );
        // Unit tet (1/6) plus the tet (1,0,0),(0,1,0),(0,0,1),(1,1,1) (1/3); the triangle has none.
        let vol = v["volume"].as_f64().unwrap();
        assert!((vol - 0.5).abs() < 1e-12, "{name}: volume {vol}");
        assert_eq!(v["volume_cells"], 2);
        let label = &v["cell_data"][0];
        assert_eq!(label["name"], "label");
        assert_eq!(label["type"], "Int32");
        assert_eq!(label["components"], 2);
        assert_eq!(label["sum"], "600011");
        let ours = tetkit::formats::DataArray::new(
            "label",
            2,
            tetkit::formats::ArrayData::Int32(vec![1, -2, 3, 4, 5, 600000]),
        );
        assert_eq!(array_summary(&ours)["crc32"], label["crc32"], "{name}");
        let s = &v["point_data"][0];
        assert_eq!(s["type"], "Float32");
        assert_eq!(s["fsum"], 12.5);
        let ours = tetkit::formats::DataArray::new(
            "s",
            1,
            tetkit::formats::ArrayData::Float32(vec![0.5, 1.5, 2.5, 3.5, 4.5]),
        );
        assert_eq!(array_summary(&ours)["crc32"], s["crc32"], "{name}");
        assert_eq!(v["connectivity"]["sum"], "19", "{name}");
    }
    assert_eq!(
        vtk_check(&dir.path().join("m.vtu"), false)["cell_data"][0]["component_names"],
        serde_json::json!(["lo", "hi"])
    );
}

#[test]
fn vtk_check_script_refuses_garbage() {
    if !require_vtk("vtk_check_script_refuses_garbage") {
        return;
    }
    let dir = tempdir();
    let p = dir.path().join("bad.vtu");
    std::fs::write(&p, "<VTKFile type=\"UnstructuredGrid\"><oops").unwrap();
    assert!(vtk_check_result(&p, false).is_err());
}

// ---------------------------------------------------------------------------------------------
// info and convert on real fixtures

#[test]
fn info_text_lists_counts_types_bounds_and_arrays() {
    let run = tetkit(["info".as_ref(), fixture("mixed/mixed.vtu").as_os_str()]);
    run.assert_success();
    let out = run.stdout_str();
    for needle in [
        "points:  91 (Float64)",
        "cells:   140",
        "hexahedron",
        "polyhedron",
        "bounds:",
        "temperature",
        "velocity",
        "Float32",
        "3 comp",
        "components (vx, vy, vz)",
        "material",
        "source",
        "String",
    ] {
        assert!(out.contains(needle), "info output lacks {needle:?}:\n{out}");
    }
}

#[test]
fn info_json_is_complete() {
    let run = tetkit([
        "info".as_ref(),
        fixture("gmsh/block_hole.vtk").as_os_str(),
        "--json".as_ref(),
    ]);
    run.assert_success();
    let v: serde_json::Value = serde_json::from_slice(&run.stdout).expect("info --json is JSON");
    let g = tetkit::formats::read(&fixture("gmsh/block_hole.vtk")).unwrap();
    assert_eq!(v["points"], g.num_points());
    assert_eq!(v["cells"], g.num_cells());
    let types = v["cell_types"].as_array().unwrap();
    let tets = types.iter().find(|t| t["name"] == "tetra").unwrap();
    assert_eq!(tets["type"], 10);
    let n_tets = g.cells.types.iter().filter(|&&t| t == 10).count();
    assert_eq!(tets["count"], n_tets);
    let b = v["bounds"].as_array().unwrap();
    assert_eq!(b.len(), 6);
    assert_eq!(b[0], 0.0);
    assert_eq!(b[1], 2.0);

    let run = tetkit([
        "info".as_ref(),
        fixture("mixed/mixed.vtu").as_os_str(),
        "--json".as_ref(),
    ]);
    let v: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    let vel = v["point_data"]
        .as_array()
        .unwrap()
        .iter()
        .find(|a| a["name"] == "velocity")
        .unwrap();
    assert_eq!(vel["type"], "Float32");
    assert_eq!(vel["components"], 3);
    assert_eq!(
        vel["component_names"],
        serde_json::json!(["vx", "vy", "vz"])
    );
    let mat = v["cell_data"]
        .as_array()
        .unwrap()
        .iter()
        .find(|a| a["name"] == "material")
        .unwrap();
    assert_eq!(mat["range"], serde_json::json!([0.0, 6.0]));
    assert_eq!(v["field_data"].as_array().unwrap().len(), 2);
}

#[test]
fn convert_pipes_through_stdin_and_stdout() {
    let input = fixture("mixed/mixed.vtu");
    let bytes = std::fs::read(&input).unwrap();
    let original = tetkit::formats::read(&input).unwrap();
    for to in ["vtk", "vtu"] {
        let run = tetkit_stdin(["convert", "-", "-", "--to", to], &bytes);
        run.assert_success();
        let format = tetkit::formats::Format::from_name(to).unwrap();
        let back = tetkit::formats::read_bytes(&run.stdout, format).unwrap();
        grids_bit_equal(&original, &back).unwrap();
        // And back in again: info reads the stream.
        let info = tetkit_stdin(["info", "-", "--json"], &run.stdout);
        info.assert_success();
        let v: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
        assert_eq!(v["cells"], 140);
    }
    // A pipeline with tetrahedralization in the middle.
    let run = tetkit_stdin(["convert", "-", "-", "--tetrahedralize"], &bytes);
    run.assert_success();
    assert!(
        run.stderr.contains("split 6 hexahedron cells into tets"),
        "{}",
        run.stderr
    );
    let t = tetkit::formats::read_bytes(&run.stdout, tetkit::formats::Format::Vtu).unwrap();
    assert!(t.cells.types.iter().all(|&c| c != 12 && c != 13 && c != 14));
}

#[test]
fn convert_file_to_file_and_back() {
    let dir = tempdir();
    let input = fixture("gmsh/lshape.vtk");
    let a = dir.path().join("l.vtu");
    let b = dir.path().join("l.vtk");
    tetkit(["convert".as_ref(), input.as_os_str(), a.as_os_str()]).assert_success();
    tetkit([
        "convert".as_ref(),
        a.as_os_str(),
        b.as_os_str(),
        "--encoding".as_ref(),
        "ascii".as_ref(),
        "--legacy-version".as_ref(),
        "4.2".as_ref(),
    ])
    .assert_success();
    let g0 = tetkit::formats::read(&input).unwrap();
    let g2 = tetkit::formats::read(&b).unwrap();
    grids_bit_equal(&g0, &g2).unwrap();
    assert!(std::fs::read_to_string(&b)
        .unwrap()
        .starts_with("# vtk DataFile Version 4.2"));
    assert_eq!(dir_listing(dir.path()), vec!["l.vtk", "l.vtu"]);
}

#[test]
fn convert_takes_the_output_as_o_like_the_other_subcommands() {
    let dir = tempdir();
    let input = fixture("gmsh/lshape.vtk");
    let a = dir.path().join("pos.vtu");
    let b = dir.path().join("flag.vtu");
    tetkit(["convert".as_ref(), input.as_os_str(), a.as_os_str()]).assert_success();
    tetkit([
        "convert".as_ref(),
        input.as_os_str(),
        "-o".as_ref(),
        b.as_os_str(),
    ])
    .assert_success();
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    // Both at once is ambiguous; neither names nothing to write.
    let c = dir.path().join("c.vtu");
    tetkit([
        "convert".as_ref(),
        input.as_os_str(),
        a.as_os_str(),
        "-o".as_ref(),
        c.as_os_str(),
    ])
    .assert_failure(&["cannot be used with"]);
    tetkit(["convert".as_ref(), input.as_os_str()]).assert_failure(&["OUTPUT"]);
    assert_eq!(dir_listing(dir.path()), vec!["flag.vtu", "pos.vtu"]);
}

// ---------------------------------------------------------------------------------------------
// errors: exit code, file and place named, no output left behind

/// Runs `convert IN OUT` expecting failure; asserts the message names `needles` and that the
/// directory holds only the input afterwards.
fn convert_fails(
    input_name: &str,
    content: &[u8],
    out_name: &str,
    extra: &[&str],
    needles: &[&str],
) {
    let dir = tempdir();
    let input = dir.path().join(input_name);
    std::fs::write(&input, content).unwrap();
    let out = dir.path().join(out_name);
    let mut args = vec![
        "convert".to_string(),
        input.display().to_string(),
        out.display().to_string(),
    ];
    args.extend(extra.iter().map(|s| s.to_string()));
    tetkit(&args).assert_failure(needles);
    assert_eq!(
        dir_listing(dir.path()),
        vec![input_name.to_string()],
        "a failed convert left files behind"
    );
}

#[test]
fn truncated_legacy_file_is_refused_with_its_line() {
    let text = std::fs::read_to_string(fixture("gmsh/cavity.vtk")).unwrap();
    let cut = &text[..text.len() / 2];
    convert_fails("cut.vtk", cut.as_bytes(), "out.vtu", &[], &["cut.vtk"]);
    let run = {
        let dir = tempdir();
        let p = dir.path().join("cut.vtk");
        std::fs::write(&p, cut).unwrap();
        tetkit(["info".as_ref(), p.as_os_str()])
    };
    run.assert_failure(&["cut.vtk"]);
    assert!(
        run.stderr.contains("line") || run.stderr.contains("byte"),
        "the error should say where: {}",
        run.stderr
    );
}

#[test]
fn truncated_vtu_is_refused() {
    let bytes = std::fs::read(fixture("mixed/quadratic_tets.vtu")).unwrap();
    convert_fails(
        "cut.vtu",
        &bytes[..bytes.len() * 2 / 3],
        "out.vtk",
        &[],
        &["cut.vtu"],
    );
}

const ONE_TET: &str = "# vtk DataFile Version 4.2\nbad\nASCII\nDATASET UNSTRUCTURED_GRID\n\
POINTS 4 double\n0 0 0\n1 0 0\n0 1 0\n0 0 1\nCELLS 1 5\n4 0 1 2 7\nCELL_TYPES 1\n10\n";

#[test]
fn connectivity_out_of_range_is_refused() {
    convert_fails("bad.vtk", ONE_TET.as_bytes(), "out.vtu", &[], &["bad.vtk"]);
}

#[test]
fn flat_hexahedron_cannot_be_tetrahedralized() {
    let flat = "# vtk DataFile Version 4.2\nflat\nASCII\nDATASET UNSTRUCTURED_GRID\n\
POINTS 8 double\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n\
CELLS 1 9\n8 0 1 2 3 4 5 6 7\nCELL_TYPES 1\n12\n";
    convert_fails(
        "flat.vtk",
        flat.as_bytes(),
        "out.vtu",
        &["--tetrahedralize"],
        &["flat.vtk", "cell 0 (hexahedron"],
    );
    // Without --tetrahedralize the same file converts as it is.
    let dir = tempdir();
    let input = dir.path().join("flat.vtk");
    std::fs::write(&input, flat).unwrap();
    let out = dir.path().join("flat.vtu");
    tetkit(["convert".as_ref(), input.as_os_str(), out.as_os_str()]).assert_success();
}

#[test]
fn bad_output_names_are_refused_before_writing() {
    let good = std::fs::read(fixture("mixed/mixed.vtk")).unwrap();
    convert_fails("m.vtk", &good, "out.xyz", &[], &["out.xyz"]);
    convert_fails(
        "m.vtk",
        &good,
        "out.vtu",
        &["--encoding", "nonsense"],
        &["nonsense"],
    );
    // A non-tet mesh cannot be TetGen without --tetrahedralize.
    convert_fails("m.vtk", &good, "out.ele", &[], &["--tetrahedralize"]);
    // stdout only takes single-file formats.
    tetkit([
        "convert".as_ref(),
        fixture("mixed/mixed.vtk").as_os_str(),
        "-".as_ref(),
        "--to".as_ref(),
        "tetgen".as_ref(),
    ])
    .assert_failure(&["--to tetgen"]);
}

#[test]
fn output_into_a_missing_directory_names_it() {
    let dir = tempdir();
    let out = dir.path().join("no/such/dir/out.vtu");
    tetkit([
        "convert".as_ref(),
        fixture("mixed/mixed.vtk").as_os_str(),
        out.as_os_str(),
    ])
    .assert_failure(&["out.vtu"]);
}
