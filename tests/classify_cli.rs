//! `tetkit classify` on real files: region codes as cell data that VTK reads back, every input
//! array kept, the JSON report, and scene errors that leave no output behind.

mod common;

use common::{fixture, tetkit};
use tetkit::formats::{self, ArrayData};

#[test]
fn classify_writes_region_codes_that_vtk_reads() {
    let dir = common::tempdir();
    let out = dir.path().join("classified.vtk");
    let run = tetkit([
        "classify".as_ref(),
        fixture("scenes/cube_mesh.vtk").as_os_str(),
        "--scene".as_ref(),
        fixture("scenes/example.toml").as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--json".as_ref(),
        "--size".as_ref(),
        "64".as_ref(),
    ]);
    run.assert_success();
    let report: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(report["tets"], 384);
    assert_eq!(report["bodies"].as_array().unwrap().len(), 4);
    let before = report["pixel_codes_before_merging"].as_array().unwrap();
    assert!(before.len() >= 3, "{report}");
    let classes: usize = report["classes_after_merging"]
        .as_array()
        .unwrap()
        .iter()
        .map(|g| g["classes"].as_array().unwrap().len())
        .sum();
    assert!(classes <= before.len());

    let input = formats::read(&fixture("scenes/cube_mesh.vtk")).unwrap();
    let back = formats::read(&out).unwrap();
    assert_eq!(back.num_cells(), 384);
    // Every input array is kept, bit for bit.
    for a in input
        .point_data
        .arrays
        .iter()
        .chain(input.cell_data.arrays.iter())
    {
        let b = back
            .point_data
            .get(&a.name)
            .or_else(|| back.cell_data.get(&a.name))
            .unwrap_or_else(|| panic!("array {} lost", a.name));
        assert!(a.bit_eq(b), "array {} changed", a.name);
    }
    let codes = match &back.cell_data.get("region_code").unwrap().data {
        ArrayData::UInt8(v) => v.clone(),
        other => panic!("region_code is {}", other.type_name()),
    };
    // The library's classification of the same mesh and scene.
    let mesh = tetkit::mesh::TetMesh::from_grid(&input).unwrap();
    let scene = tetkit::scene::load(&fixture("scenes/example.toml")).unwrap();
    assert_eq!(codes, tetkit::scene::classify::classify(&scene, &mesh));
    // The corner box [0.5, 1.1]^3 has its faces on lattice planes: exactly the tets of the
    // corner octant (an eighth of the volume) carry bit 0.
    let vol: f64 = (0..mesh.tets.len())
        .filter(|&t| codes[t] & 1 == 1)
        .map(|t| {
            let p = mesh.tet_points(t);
            tetkit::geom::tet_volume(&p[0], &p[1], &p[2], &p[3]).abs()
        })
        .sum();
    assert!((vol - 0.125).abs() < 1e-6, "{vol}");

    if !common::require_vtk("classify_writes_region_codes_that_vtk_reads") {
        return;
    }
    let py = r#"
import sys, json, vtk
r = vtk.vtkUnstructuredGridReader(); r.SetFileName(sys.argv[1]); r.Update()
g = r.GetOutput(); a = g.GetCellData().GetArray("region_code")
print(json.dumps({"cells": g.GetNumberOfCells(), "type": a.GetDataTypeAsString(),
  "codes": [int(a.GetValue(i)) for i in range(a.GetNumberOfTuples())],
  "arrays": sorted([g.GetCellData().GetArrayName(i) for i in range(g.GetCellData().GetNumberOfArrays())]
   + [g.GetPointData().GetArrayName(i) for i in range(g.GetPointData().GetNumberOfArrays())])}))
"#;
    let v: serde_json::Value =
        serde_json::from_str(&common::vtk_python(py, &[out.to_str().unwrap()])).unwrap();
    assert_eq!(v["cells"], 384);
    assert_eq!(v["type"], "unsigned char");
    let vtk_codes: Vec<u8> = v["codes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap() as u8)
        .collect();
    assert_eq!(vtk_codes, codes);
    assert_eq!(
        v["arrays"],
        serde_json::json!(["cell_id", "region_code", "scalar"])
    );
}

#[test]
fn bad_scenes_fail_with_the_line_and_write_nothing() {
    let dir = common::tempdir();
    let out = dir.path().join("o.vtk");
    let cases: [(&str, &[&str]); 3] = [
        (
            "[[body]]\nshape = \"box\"\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 1.0]\nmaximum = 2\n",
            &["s.toml", "line 5", "maximum"],
        ),
        (
            "\n\n[[body]]\nshape = \"surface\"\nfile = \"nowhere.stl\"\n",
            &["s.toml", "line 5", "nowhere.stl"],
        ),
        ("[[body]]\nshape = \"sphere\"\ncenter = [0.0, 0.0]\nradius = 1.0\n", &["s.toml", "line 3"]),
    ];
    for (text, needles) in cases {
        let scene = dir.path().join("s.toml");
        std::fs::write(&scene, text).unwrap();
        let run = tetkit([
            "classify".as_ref(),
            fixture("scenes/cube_mesh.vtk").as_os_str(),
            "--scene".as_ref(),
            scene.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ]);
        run.assert_failure(needles);
        assert!(!out.exists());
    }
    // An empty scene is valid: every code is 0.
    let scene = dir.path().join("empty.toml");
    std::fs::write(&scene, "").unwrap();
    tetkit([
        "classify".as_ref(),
        fixture("scenes/cube_mesh.vtk").as_os_str(),
        "--scene".as_ref(),
        scene.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ])
    .assert_success();
    let back = formats::read(&out).unwrap();
    match &back.cell_data.get("region_code").unwrap().data {
        ArrayData::UInt8(v) => assert!(v.iter().all(|&c| c == 0)),
        _ => panic!(),
    }
}
