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
