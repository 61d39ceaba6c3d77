//! Every VTK-written fixture (each encoding, compressor, header type and byte order, multi-piece
//! and .pvtu) reads with VTK's counts and bit-identical arrays.

mod vtu_support;

use formats::{cell_type, Attribute, Grid};
use serde_json::Value;
use vtu_support::*;

fn read(name: &str) -> Grid {
    let p = fixtures().join(name);
    let mut g = formats::read(&p).unwrap_or_else(|e| panic!("{e}"));
    if name == "tet_ascii.vtu" {
        // VTK's ascii writer prints -0.0 as "0": the one value its ascii output does not keep.
        let a = g
            .field_data
            .iter_mut()
            .find(|a| a.name == "f_float32")
            .unwrap();
        let formats::ArrayData::Float32(v) = &mut a.data else {
            panic!()
        };
        assert_eq!(v[1].to_bits(), 0);
        v[1] = -0.0;
    }
    g
}

fn tet_files(m: &Value) -> Vec<String> {
    m["tet_files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap().to_string())
        .filter(|f| f.starts_with("tet_") && !f.contains("pieces") && !f.ends_with(".pvtu"))
        .collect()
}

#[test]
fn every_encoding_reads_with_vtk_counts_and_checksums() {
    let m = manifest();
    let files = tet_files(&m);
    // ascii + 3 binary encodings x 4 compressors x 2 header types x 2 byte orders.
    assert_eq!(files.len(), 49);
    for f in &files {
        let g = read(f);
        check_grid(&g, &m["tet"], f);
        assert_eq!(
            g.point_data.active,
            vec![
                (Attribute::Scalars, "temperature".to_string()),
                (Attribute::Vectors, "velocity".to_string())
            ],
            "{f}"
        );
    }
}

#[test]
fn every_encoding_gives_the_bit_identical_grid() {
    let m = manifest();
    let reference = read("tet_appended_none_h64_le.vtu");
    for f in tet_files(&m) {
        let g = read(&f);
        if let Err(e) = grids_bit_eq(&reference, &g) {
            panic!("{f}: {e}");
        }
    }
    // The NaN and infinities survive, bit for bit.
    let s = reference
        .field_data
        .iter()
        .find(|a| a.name == "f_specials")
        .unwrap();
    let formats::ArrayData::Float64(v) = &s.data else {
        panic!()
    };
    assert!(v[0].is_nan() && v[1] == f64::INFINITY && v[2] == f64::NEG_INFINITY);
}

#[test]
fn in_memory_reading_matches_file_reading() {
    for f in [
        "tet_appended_zlib_h32_be.vtu",
        "tet_appended64_lz4_h64_le.vtu",
        "tet_binary_lzma_h64_be.vtu",
        "tet_ascii.vtu",
    ] {
        let bytes = std::fs::read(fixtures().join(f)).unwrap();
        let a = formats::read_bytes(&bytes, formats::Format::Vtu).unwrap();
        let b = formats::read(&fixtures().join(f)).unwrap();
        grids_bit_eq(&a, &b).unwrap_or_else(|e| panic!("{f}: {e}"));
    }
}

/// Pieces are consecutive cell ranges of the original mesh (points duplicated per piece): the
/// merged grid has the original cells, cell data and field data, and every cell the same
/// corner coordinates.
fn check_pieces(g: &Grid, reference: &Grid, file: &str) {
    assert_eq!(g.num_cells(), reference.num_cells(), "{file}");
    assert!(
        g.num_points() > reference.num_points(),
        "{file}: pieces duplicate shared points"
    );
    assert_eq!(g.cells.types, reference.cells.types, "{file}");
    assert_eq!(g.cells.offsets, reference.cells.offsets, "{file}");
    for i in 0..g.num_cells() {
        let a: Vec<[f64; 3]> = g
            .cells
            .cell(i)
            .iter()
            .map(|&p| g.point(p as usize))
            .collect();
        let b: Vec<[f64; 3]> = reference
            .cells
            .cell(i)
            .iter()
            .map(|&p| reference.point(p as usize))
            .collect();
        assert_eq!(a, b, "{file}: cell {i}");
    }
    for y in &reference.cell_data.arrays {
        let x = g.cell_data.get(&y.name).unwrap();
        assert!(x.bit_eq(y), "{file}: cell data {}", x.name);
    }
    // vtkExtractCells (which cut the pieces) adds the original cell ids: 0..n in piece order.
    let ids = g
        .cell_data
        .get("vtkOriginalCellIds")
        .expect("vtkOriginalCellIds");
    let want: Vec<f64> = (0..g.num_cells()).map(|i| i as f64).collect();
    assert_eq!(ids.data.to_f64_vec(), want, "{file}");
    assert_eq!(
        g.cell_data.arrays.len(),
        reference.cell_data.arrays.len() + 1
    );
    for y in &reference.point_data.arrays {
        assert_eq!(
            g.point_data.get(&y.name).unwrap().data.type_name(),
            y.data.type_name()
        );
    }
    for (x, y) in g.field_data.iter().zip(&reference.field_data) {
        assert!(x.bit_eq(y), "{file}: field data {}", x.name);
    }
}

#[test]
fn multi_piece_vtu_and_pvtu_merge_in_order() {
    let reference = read("tet_appended_none_h64_le.vtu");
    check_pieces(&read("tet_3pieces.vtu"), &reference, "tet_3pieces.vtu");
    check_pieces(&read("tet_parallel.pvtu"), &reference, "tet_parallel.pvtu");
}

#[test]
fn polyhedra_keep_their_face_streams() {
    let m = manifest();
    let a = read("polyhedra_ascii.vtu");
    let b = read("polyhedra_binary_zlib.vtu");
    check_grid(&a, &m["polyhedra"], "polyhedra_ascii.vtu");
    grids_bit_eq(&a, &b).unwrap();
    assert_eq!(
        a.cells.types,
        vec![
            cell_type::POLYHEDRON,
            cell_type::TETRA,
            cell_type::POLYHEDRON
        ]
    );
    let (faces, offsets) = a.cells.polyhedron_faces.as_ref().expect("faces kept");
    assert_eq!(offsets[1], -1);
    assert_eq!(faces[0], 6, "the cube has 6 faces");
    assert_eq!(offsets[2] as usize, faces.len());
}

#[test]
fn info_prints_the_fixture_counts() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_tetkit"))
        .args(["info", "--json"])
        .arg(fixtures().join("tet_binary_zlib_h32_be.vtu"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["points"], 64);
    assert_eq!(v["cells"], 135);
    assert_eq!(v["field_data"].as_array().unwrap().len(), 12);
}
