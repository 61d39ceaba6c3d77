//! Files as meshio (the Python mesh converter many FEM users go through) writes them, made here
//! by hand in its exact layout: legacy VTK FIELD arrays typed `vtktypeuint8`, `vtktypeint32`...
//! (refused as "unknown data type"), TetGen markers written `0.0` (refused as "not an
//! integer"), and meshio's 3x3 cell tensors: in legacy files declared with 3 components but
//! holding 9 (the error named only a stray number, not the array at fault), in VTU written with
//! no `NumberOfComponents` at all (refused, so the whole mesh could not be read; VTK keeps a
//! ninth of the values): the 9 components are now kept.

mod common;

use common::{tempdir, tetkit};
use tetkit::formats::{self, ArrayData, ScalarType};

const HEAD: &str = "# vtk DataFile Version 5.1\nwritten by meshio v5.0.0\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n0 0 0 1 0 0 0 1 0 0 0 1\nCELLS 2 4\nOFFSETS vtktypeint64\n0 4\nCONNECTIVITY vtktypeint64\n0 1 2 3\nCELL_TYPES 1\n10\n";

#[test]
fn fixed_size_vtktype_names_are_read_and_kept() {
    let dir = tempdir();
    let types = [
        ("vtktypeint8", ScalarType::Int8),
        ("vtktypeuint8", ScalarType::UInt8),
        ("vtktypeint16", ScalarType::Int16),
        ("vtktypeuint16", ScalarType::UInt16),
        ("vtktypeint32", ScalarType::Int32),
        ("vtktypeuint32", ScalarType::UInt32),
        ("vtktypeint64", ScalarType::Int64),
        ("vtktypeuint64", ScalarType::UInt64),
        ("vtktypefloat32", ScalarType::Float32),
        ("vtktypefloat64", ScalarType::Float64),
    ];
    let mut text = format!("{HEAD}POINT_DATA 4\nFIELD FieldData {}\n", types.len());
    for (name, _) in &types {
        text += &format!("{name}_a 1 4 {name}\n1 2 3 4\n");
    }
    let input = dir.path().join("meshio.vtk");
    std::fs::write(&input, text).unwrap();
    let out = dir.path().join("out.vtu");
    tetkit(["convert".as_ref(), input.as_os_str(), out.as_os_str()]).assert_success();
    let g = formats::read(&out).unwrap();
    for (name, ty) in types {
        let a = g.point_data.get(&format!("{name}_a")).unwrap();
        assert_eq!(a.data.scalar_type(), Some(ty), "{name}");
        assert_eq!(a.data.to_f64_vec(), [1.0, 2.0, 3.0, 4.0], "{name}");
    }
}

#[test]
fn integral_float_markers_are_read_and_fractional_ones_named() {
    let dir = tempdir();
    let node = |marks: [&str; 4]| {
        let mut s = "# This file was created by meshio v5.0.0\n4 3 0 1\n".to_string();
        for (i, (p, m)) in ["0 0 0", "1 0 0", "0 1 0", "0 0 1"]
            .iter()
            .zip(marks)
            .enumerate()
        {
            s += &format!("{i} {p} {m}\n");
        }
        s
    };
    std::fs::write(dir.path().join("m.ele"), "1 4 0\n0 0 1 2 3\n").unwrap();
    std::fs::write(
        dir.path().join("m.node"),
        node(["0.0", "1.0", "-2.", "3e0"]),
    )
    .unwrap();
    let g = formats::read(&dir.path().join("m.ele")).unwrap();
    let m = g.point_data.get("boundary_marker").unwrap();
    assert_eq!(m.data, ArrayData::Int32(vec![0, 1, -2, 3]));

    std::fs::write(dir.path().join("m.node"), node(["0.0", "1.0", "0.5", "3"])).unwrap();
    let ele = dir.path().join("m.ele");
    let r = tetkit(["info".as_ref(), ele.as_os_str()]);
    r.assert_failure(&["m.node", "line 5", "boundary marker", "0.5"]);
}

#[test]
fn an_array_holding_more_values_than_declared_is_named() {
    let dir = tempdir();
    // meshio writes an (n, 3, 3) tensor as `sig 3 n double` followed by 9 n values.
    let nine: Vec<String> = (0..9).map(|k| format!("0.{k}5")).collect();
    let ascii = format!(
        "{HEAD}CELL_DATA 1\nFIELD FieldData 2\nrho 1 1 double\n0.5\nsig 3 1 double\n{}\n",
        nine.join(" ")
    );
    let input = dir.path().join("tensor.vtk");
    std::fs::write(&input, &ascii).unwrap();
    let r = tetkit(["info".as_ref(), input.as_os_str()]);
    r.assert_failure(&["tensor.vtk", "line 19", "'sig'", "more values than"]);

    // The same in binary: big-endian doubles after the header line.
    let mut bin =
        b"# vtk DataFile Version 4.2\nmeshio\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n"
            .to_vec();
    for v in [0.0f64, 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1.] {
        bin.extend_from_slice(&v.to_be_bytes());
    }
    bin.extend_from_slice(b"\nCELLS 1 5\n");
    for v in [4i32, 0, 1, 2, 3] {
        bin.extend_from_slice(&v.to_be_bytes());
    }
    bin.extend_from_slice(b"\nCELL_TYPES 1\n");
    bin.extend_from_slice(&10i32.to_be_bytes());
    bin.extend_from_slice(b"\nCELL_DATA 1\nFIELD FieldData 1\nsig 3 1 double\n");
    for k in 0..9 {
        bin.extend_from_slice(&(0.25 + k as f64).to_be_bytes());
    }
    bin.push(b'\n');
    let input = dir.path().join("tensor_bin.vtk");
    std::fs::write(&input, &bin).unwrap();
    let r = tetkit(["info".as_ref(), input.as_os_str()]);
    r.assert_failure(&["tensor_bin.vtk", "byte", "'sig'", "more values than"]);
}

fn vtu_with_cell_array(array: &str) -> String {
    format!(
        r#"<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">
<UnstructuredGrid><Piece NumberOfPoints="5" NumberOfCells="2">
<Points><DataArray type="Float64" Name="Points" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0 0 0 1 1 1 1</DataArray></Points>
<Cells><DataArray type="Int32" Name="connectivity" format="ascii">0 1 2 3 1 2 3 4</DataArray>
<DataArray type="Int32" Name="offsets" format="ascii">4 8</DataArray>
<DataArray type="Int64" Name="types" format="ascii">10 10</DataArray></Cells>
<CellData>{array}</CellData>
</Piece></UnstructuredGrid></VTKFile>
"#
    )
}

#[test]
fn a_vtu_tensor_without_a_component_count_keeps_its_nine_components() {
    let dir = tempdir();
    let values: Vec<f64> = (0..18).map(|k| k as f64 * 0.5).collect();
    let text: Vec<String> = values.iter().map(|v| v.to_string()).collect();
    let ascii = format!(
        r#"<DataArray type="Float64" Name="sig" format="ascii">{}</DataArray>"#,
        text.join(" ")
    );
    // meshio's binary form: a UInt32 byte count, then the values, base64 together.
    let mut raw = ((values.len() * 8) as u32).to_le_bytes().to_vec();
    for v in &values {
        raw.extend_from_slice(&v.to_le_bytes());
    }
    use base64::Engine;
    let binary = format!(
        r#"<DataArray type="Float64" Name="sig" format="binary">{}</DataArray>"#,
        base64::engine::general_purpose::STANDARD.encode(&raw)
    );
    for (name, array) in [("ascii", ascii), ("binary", binary)] {
        let input = dir.path().join(format!("{name}.vtu"));
        std::fs::write(&input, vtu_with_cell_array(&array)).unwrap();
        let out = dir.path().join(format!("{name}_out.vtu"));
        tetkit(["convert".as_ref(), input.as_os_str(), out.as_os_str()]).assert_success();
        let g = formats::read(&out).unwrap();
        let a = g.cell_data.get("sig").unwrap();
        assert_eq!(a.components, 9, "{name}");
        assert_eq!(a.data, ArrayData::Float64(values.clone()), "{name}");
    }
    // 17 values for 2 cells fit no component count: refused, naming the array.
    let input = dir.path().join("odd.vtu");
    std::fs::write(
        &input,
        vtu_with_cell_array(&format!(
            r#"<DataArray type="Float64" Name="sig" format="ascii">{}</DataArray>"#,
            text[..17].join(" ")
        )),
    )
    .unwrap();
    let r = tetkit(["info".as_ref(), input.as_os_str()]);
    r.assert_failure(&["odd.vtu", "byte", "'sig'", "17 values"]);
}
