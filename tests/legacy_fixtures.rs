//! Every fixture in fixtures/legacy/ (written by VTK 9.1, or by hand and checked with VTK) reads
//! with the same counts, types, components, names, sums and active attributes VTK reads.

mod legacy_common;

use formats::{ArrayData, Attribute};
use legacy_common::*;

#[test]
fn every_fixture_reads_as_vtk_reads_it() {
    let sums = checksums();
    for path in legacy_fixtures() {
        let name = path.file_name().unwrap().to_str().unwrap();
        let grid = formats::read(&path).unwrap_or_else(|e| panic!("{e}"));
        compare_grid(&grid, &sums[name]).unwrap_or_else(|e| panic!("{name}: {e}"));
    }
}

#[test]
fn the_four_vtk_encodings_hold_the_same_mesh() {
    let dir = root().join("fixtures/legacy");
    let bin42 = formats::read(&dir.join("mixed_42_binary.vtk")).unwrap();
    let bin51 = formats::read(&dir.join("mixed_51_binary.vtk")).unwrap();
    same_grid(&bin42, &bin51).unwrap();
    let asc42 = formats::read(&dir.join("mixed_42_ascii.vtk")).unwrap();
    let asc51 = formats::read(&dir.join("mixed_51_ascii.vtk")).unwrap();
    same_grid(&asc42, &asc51).unwrap();
    assert_eq!(bin51.cells, asc51.cells);
    // VTK writes doubles with 11 digits and floats with 6 in ASCII, so only the structure and
    // integer arrays agree exactly between the two encodings.
    assert_eq!(bin51.cell_data.get("region"), asc51.cell_data.get("region"));
    let poly = bin51
        .cells
        .polyhedron_faces
        .as_ref()
        .expect("polyhedron faces");
    assert_eq!(poly.0.len(), 17);
    assert_eq!(poly.1.iter().filter(|&&o| o >= 0).count(), 1);
}

#[test]
fn handmade_ascii_keeps_field_metadata_tables_and_bits() {
    let g = formats::read(&root().join("fixtures/legacy/handmade_51_ascii.vtk")).unwrap();
    let ids = g.field_data.iter().find(|a| a.name == "ids").unwrap();
    assert_eq!(ids.data, ArrayData::Int64(vec![5, 6, 7]));
    let labels = g.field_data.iter().find(|a| a.name == "labels").unwrap();
    assert_eq!(
        labels.data,
        ArrayData::String(vec!["first label".into(), "second".into()])
    );
    assert_eq!(g.points.component_names, ["X", "Y", "Z"]);
    assert_eq!(
        g.points.data,
        ArrayData::Float64(vec![
            0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1., 1., 1., 1.
        ])
    );
    let disp = g.point_data.get("disp").unwrap();
    assert_eq!(disp.component_names, ["dx", "dy", "dz"]);
    assert_eq!(
        g.point_data.active(Attribute::Vectors).unwrap().name,
        "disp"
    );
    let colors = g.point_data.get("colors").unwrap();
    assert_eq!(colors.components, 3);
    assert_eq!(
        colors.data,
        ArrayData::UInt8(vec![
            255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255, 51, 102, 153
        ])
    );
    assert_eq!(
        g.point_data.get("flags").unwrap().data,
        ArrayData::UInt8(vec![1, 0, 1, 1, 0])
    );
    assert_eq!(g.point_data.get("count").unwrap().components, 2);
    assert_eq!(
        g.cell_data.lookup_tables,
        [("mat".to_string(), "materials".to_string())]
    );
    let lut = g
        .field_data
        .iter()
        .find(|a| a.name == "lookup_table:materials")
        .unwrap();
    assert_eq!(lut.components, 4);
    assert_eq!(
        lut.data,
        ArrayData::Float32(vec![1., 0., 0., 1., 0., 0., 1., 0.5])
    );
    let sym = g.cell_data.active(Attribute::Tensors).unwrap();
    assert_eq!((sym.name.as_str(), sym.components), ("sym", 6));
}

#[test]
fn handmade_binary_keeps_ids_strings_bits_and_polyhedra() {
    let g = formats::read(&root().join("fixtures/legacy/handmade_42_binary.vtk")).unwrap();
    assert_eq!(g.cells.types, [10, 42]);
    assert_eq!(g.cells.cell(1), [1, 2, 3, 4]);
    let (faces, offsets) = g.cells.polyhedron_faces.clone().unwrap();
    assert_eq!(faces, [4, 3, 1, 2, 3, 3, 1, 2, 4, 3, 1, 3, 4, 3, 2, 3, 4]);
    assert_eq!(offsets, [-1, 17]);
    assert_eq!(
        g.cell_data.get("big").unwrap().data,
        ArrayData::UInt64(vec![u64::MAX, 12345])
    );
    assert_eq!(
        g.point_data.get("bits").unwrap().data,
        ArrayData::UInt8(vec![1, 0, 1, 1, 0])
    );
    assert_eq!(
        g.point_data.get("gid").unwrap().data,
        ArrayData::Int64(vec![10, 11, 12, 13, 14])
    );
    let names = g.field_data.iter().find(|a| a.name == "names").unwrap();
    assert_eq!(
        names.data,
        ArrayData::String(vec!["a b c".into(), "x".repeat(70)])
    );
}

#[test]
fn info_runs_on_a_binary_fixture() {
    let out = tetkit(&["info", "--json", "fixtures/legacy/mixed_51_binary.vtk"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["points"], 56);
    assert_eq!(v["cells"], 162);
}
