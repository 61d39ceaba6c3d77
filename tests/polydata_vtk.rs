//! PolyData written by VTK 9.1 (.vtp in every encoding, compressor and header type; legacy
//! POLYDATA 4.2 and 5.1, ASCII and binary) reads back through the formats crate with VTK's cell
//! order, cell types, point ids and arrays. These readers load the surfaces of cutting bodies.

mod common;

use common::*;
use serde_json::Value;
use std::path::Path;

/// Writes one surface with verts, lines, polys (triangles, quads, a pentagon) and strips, with
/// point and cell data, in many encodings; prints JSON describing it as VTK sees it.
const WRITE: &str = r#"
import sys, json, vtk
out = sys.argv[1]
pd = vtk.vtkPolyData()
pts = vtk.vtkPoints(); pts.SetDataTypeToDouble()
for i in range(12):
    pts.InsertNextPoint(0.5 * i, (i * 7) % 5 - 2.0, 1e6 + 0.25 * (i % 3))
pd.SetPoints(pts)
def cells(lists):
    a = vtk.vtkCellArray()
    for l in lists:
        a.InsertNextCell(len(l))
        for p in l: a.InsertCellPoint(p)
    return a
pd.SetVerts(cells([[0], [1, 2, 3]]))
pd.SetLines(cells([[3, 4], [4, 5, 6, 7]]))
pd.SetPolys(cells([[0, 1, 2], [2, 3, 4, 5], [5, 6, 7, 8, 9]]))
pd.SetStrips(cells([[6, 7, 8, 9, 10, 11]]))
pdat = vtk.vtkFloatArray(); pdat.SetName("temperature"); pdat.SetNumberOfComponents(2)
for i in range(12): pdat.InsertNextTuple2(i * 1.5, -i)
pd.GetPointData().AddArray(pdat)
cdat = vtk.vtkIntArray(); cdat.SetName("region")
for i in range(pd.GetNumberOfCells()): cdat.InsertNextValue(10 * i + 3)
pd.GetCellData().AddArray(cdat)
files = []
for mode in ["ascii", "binary", "appended"]:
    for comp in ["none", "zlib", "lz4", "lzma"]:
        for header in [32, 64]:
            if mode == "ascii" and (comp != "none" or header == 64): continue
            name = "%s/s_%s_%s_%d.vtp" % (out, mode, comp, header)
            w = vtk.vtkXMLPolyDataWriter(); w.SetFileName(name); w.SetInputData(pd)
            {"ascii": w.SetDataModeToAscii, "binary": w.SetDataModeToBinary,
             "appended": w.SetDataModeToAppended}[mode]()
            if mode == "appended" and comp == "none": w.EncodeAppendedDataOff()
            {"none": w.SetCompressorTypeToNone, "zlib": w.SetCompressorTypeToZLib,
             "lz4": w.SetCompressorTypeToLZ4, "lzma": w.SetCompressorTypeToLZMA}[comp]()
            w.SetHeaderTypeToUInt64() if header == 64 else w.SetHeaderTypeToUInt32()
            assert w.Write() == 1
            files.append(name)
for version in [42, 51]:
    for binary in [False, True]:
        name = "%s/s_legacy_%d_%s.vtk" % (out, version, "binary" if binary else "ascii")
        w = vtk.vtkPolyDataWriter(); w.SetFileName(name); w.SetInputData(pd)
        w.SetFileVersion(version)
        w.SetFileTypeToBinary() if binary else w.SetFileTypeToASCII()
        assert w.Write() == 1
        files.append(name)
cells = []
for i in range(pd.GetNumberOfCells()):
    c = pd.GetCell(i)
    cells.append([pd.GetCellType(i), [c.GetPointId(k) for k in range(c.GetNumberOfPoints())]])
print(json.dumps({"files": files, "points": pd.GetNumberOfPoints(), "cells": cells,
    "temperature": [pdat.GetValue(k) for k in range(24)],
    "region": [cdat.GetValue(k) for k in range(cdat.GetNumberOfTuples())]}))
"#;

fn read_any(p: &Path) -> formats::Grid {
    let r = if p.extension().is_some_and(|e| e == "vtp") {
        formats::vtu::read_path(p)
    } else {
        formats::legacy::read_path(p)
    };
    r.unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn vtk_written_polydata_reads_with_vtk_cell_order_types_and_arrays() {
    if !require_vtk("vtk_written_polydata_reads_with_vtk_cell_order_types_and_arrays") {
        return;
    }
    let dir = tempdir();
    let v: Value = serde_json::from_str(&vtk_python(WRITE, &[dir.path().to_str().unwrap()]))
        .expect("the script's JSON");
    let files = v["files"].as_array().unwrap();
    assert_eq!(files.len(), 17 + 4);
    let cells = v["cells"].as_array().unwrap();
    for f in files {
        let p = Path::new(f.as_str().unwrap());
        let g = read_any(p);
        let what = p.display();
        assert_eq!(
            g.num_points(),
            v["points"].as_u64().unwrap() as usize,
            "{what}"
        );
        assert_eq!(g.num_cells(), cells.len(), "{what}");
        for (i, c) in cells.iter().enumerate() {
            assert_eq!(
                g.cells.types[i] as u64,
                c[0].as_u64().unwrap(),
                "{what} cell {i}"
            );
            let ids: Vec<i64> = c[1]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_i64().unwrap())
                .collect();
            let (a, b) = (g.cells.offsets[i] as usize, g.cells.offsets[i + 1] as usize);
            assert_eq!(g.cells.connectivity[a..b], ids[..], "{what} cell {i}");
        }
        // The offset z survives in double precision.
        assert_eq!(g.points.data.get_f64(2), 1e6, "{what}");
        let t = g.point_data.get("temperature").expect("temperature");
        assert_eq!(t.components, 2, "{what}");
        let want: Vec<f64> = v["temperature"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        assert_eq!(t.data.to_f64_vec(), want, "{what}");
        let r = g.cell_data.get("region").expect("region");
        let want: Vec<f64> = v["region"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        assert_eq!(r.data.to_f64_vec(), want, "{what}");
    }
}

#[test]
fn polydata_errors_name_the_section() {
    let dir = tempdir();
    let p = dir.path().join("bad.vtk");
    std::fs::write(
        &p,
        "# vtk DataFile Version 4.2\nt\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 7\n",
    )
    .unwrap();
    let e = formats::legacy::read_path(&p).unwrap_err().to_string();
    assert!(e.contains("bad.vtk") && e.contains('7'), "{e}");
    std::fs::write(
        &p,
        "# vtk DataFile Version 4.2\nt\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\nCELLS 1 4\n3 0 1 2\n",
    )
    .unwrap();
    let e = formats::legacy::read_path(&p).unwrap_err().to_string();
    assert!(e.contains("CELLS") && e.contains("POLYDATA"), "{e}");
}
