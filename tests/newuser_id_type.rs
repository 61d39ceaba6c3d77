//! Id arrays as VTK writes them after ParaView's Threshold or Extract Cells
//! (`vtkOriginalCellIds`, `vtkOriginalPointIds`: vtkIdTypeArray, XML `IdType="1"`, legacy
//! `vtkIdType`): tetkit kept their values but wrote them as plain Int64 (`vtktypeint64`), so VTK
//! read them back as vtkTypeInt64Array, and code that asks for a vtkIdTypeArray by name
//! (`vtkIdTypeArray::SafeDownCast`, ParaView's selection by original ids) found none. Every
//! writer (VTU, PVTU, legacy 4.2 and 5.1, ascii and binary) and every command that carries the
//! arrays through (partition, sort) keeps them id arrays; plain Int64 arrays stay plain.
//! Fixtures: fixtures/newuser/make_id_type.py.

mod common;

use common::*;
use std::path::{Path, PathBuf};
use tetkit::formats::{ArrayData, DataArray, Grid};

const IDS: [&str; 2] = ["vtkOriginalPointIds", "vtkOriginalCellIds"];

fn arrays(g: &Grid) -> Vec<&DataArray> {
    g.point_data
        .arrays
        .iter()
        .chain(g.cell_data.arrays.iter())
        .collect()
}

/// Every id array is flagged, its Int64 twin is not, and both hold `1000 + i`.
fn check_grid(g: &Grid, what: &str, values: bool) -> Result<(), String> {
    for name in IDS {
        for (n, id) in [(name.to_string(), true), (format!("{name}_int64"), false)] {
            let a = arrays(g)
                .into_iter()
                .find(|a| a.name == n)
                .ok_or_else(|| format!("{what}: no array {n}"))?;
            if a.id_type != id {
                return Err(format!("{what}: {n}: id_type {} (want {id})", a.id_type));
            }
            let ArrayData::Int64(v) = &a.data else {
                return Err(format!("{what}: {n}: not Int64"));
            };
            if values && !v.iter().enumerate().all(|(i, &x)| x == 1000 + i as i64) {
                return Err(format!("{what}: {n}: values changed"));
            }
        }
    }
    Ok(())
}

/// VTK's own reading of `path`: each id array's class and values (as `class:first:last:count`).
fn vtk_classes(path: &Path) -> String {
    vtk_python(
        r#"
import sys, vtk
f = sys.argv[1]
if f.endswith('.pvtu'): r = vtk.vtkXMLPUnstructuredGridReader()
elif f.endswith('.vtu'): r = vtk.vtkXMLUnstructuredGridReader()
else:
    r = vtk.vtkUnstructuredGridReader(); r.ReadAllFieldsOn(); r.ReadAllScalarsOn()
r.SetFileName(f); r.Update(); g = r.GetOutput()
out = []
for d in (g.GetPointData(), g.GetCellData()):
    for i in range(d.GetNumberOfArrays()):
        a = d.GetAbstractArray(i)
        n = a.GetNumberOfTuples()
        # Legacy files give vtkTypeInt64Array, XML vtkLongLongArray: the same 64-bit ints.
        c = a.GetClassName().replace('vtkTypeInt64Array', 'vtkLongLongArray')
        out.append('%s=%s:%d:%d:%d' % (a.GetName(), c, a.GetTuple1(0), a.GetTuple1(n - 1), n))
print(' '.join(sorted(out)))
"#,
        &[path.to_str().unwrap_or("")],
    )
}

#[test]
fn id_arrays_stay_id_arrays_through_every_writer() -> Result<(), String> {
    let dir = tempdir();
    let with_vtk = require_vtk("id_arrays_stay_id_arrays_through_every_writer");
    for input in ["newuser/id_type.vtu", "newuser/id_type.vtk"] {
        let src = fixture(input);
        let g = tetkit::formats::read(&src).map_err(|e| e.to_string())?;
        check_grid(&g, input, true)?;
        let outs: Vec<(PathBuf, Vec<&str>)> = vec![
            (dir.path().join("a.vtu"), vec![]),
            (dir.path().join("b.vtu"), vec!["--encoding", "ascii"]),
            (dir.path().join("c.vtk"), vec!["--legacy-version", "4.2"]),
            (
                dir.path().join("d.vtk"),
                vec!["--legacy-version", "5.1", "--encoding", "ascii"],
            ),
            (dir.path().join("e.pvtu"), vec![]),
        ];
        for (out, extra) in outs {
            let mut args = vec![
                "convert",
                src.to_str().unwrap_or(""),
                out.to_str().unwrap_or(""),
            ];
            args.extend(extra);
            tetkit(&args).assert_success();
            let back = tetkit::formats::read(&out).map_err(|e| e.to_string())?;
            // A .pvtu's pieces each repeat their shared points, so only flags are compared there.
            let pieces = out.extension().is_some_and(|e| e == "pvtu");
            check_grid(&back, &format!("{input} -> {}", out.display()), !pieces)?;
            if with_vtk && !pieces {
                let seen = vtk_classes(&out);
                let want = vtk_classes(&src);
                if seen != want {
                    return Err(format!(
                        "{input} -> {}: VTK reads\n{seen}\nbut the input as\n{want}",
                        out.display()
                    ));
                }
            }
        }
    }
    // partition and sort carry the flag to the split and ordered meshes.
    let split = dir.path().join("split.vtu");
    let tree = dir.path().join("tree.vtu");
    let sorted = dir.path().join("sorted.vtu");
    let src = fixture("newuser/id_type.vtu");
    let s = |p: &Path| p.to_str().unwrap_or("").to_string();
    tetkit([
        "partition".to_string(),
        s(&src),
        "-o".into(),
        s(&split),
        "--tree".into(),
        s(&tree),
        "--leaves".into(),
        "2".into(),
        "--strategy".into(),
        "cost".into(),
    ])
    .assert_success();
    tetkit(["sort".to_string(), s(&split), "-o".into(), s(&sorted)]).assert_success();
    for p in [&split, &sorted] {
        let g = tetkit::formats::read(p).map_err(|e| e.to_string())?;
        check_grid(&g, &p.display().to_string(), false)?;
        if with_vtk {
            let seen = vtk_classes(p);
            for name in IDS {
                if !seen.contains(&format!("{name}=vtkIdTypeArray")) {
                    return Err(format!("{}: VTK reads {seen}", p.display()));
                }
            }
        }
    }
    Ok(())
}

/// Ids past 2^31 do not fit legacy `vtkIdType` (32-bit in VTK's files): such an array is written
/// `vtktypeint64` with its values whole rather than cut down.
#[test]
fn legacy_ids_past_32_bits_keep_their_values() -> Result<(), String> {
    let dir = tempdir();
    let mut g =
        tetkit::formats::read(&fixture("newuser/id_type.vtu")).map_err(|e| e.to_string())?;
    let big: Vec<i64> = (0..g.num_cells() as i64).map(|i| (1 << 40) + i).collect();
    let mut a = DataArray::new("vtkOriginalCellIds", 1, ArrayData::Int64(big.clone()));
    a.id_type = true;
    g.cell_data.arrays.retain(|x| x.name != a.name);
    g.cell_data.arrays.push(a);
    let out = dir.path().join("big.vtk");
    tetkit::formats::write(&out, &g, &Default::default()).map_err(|e| e.to_string())?;
    let back = tetkit::formats::read(&out).map_err(|e| e.to_string())?;
    let b = back
        .cell_data
        .get("vtkOriginalCellIds")
        .ok_or("array lost")?;
    if b.data != ArrayData::Int64(big) {
        return Err("values changed".into());
    }
    Ok(())
}
