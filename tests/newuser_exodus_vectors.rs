//! Exodus vector and tensor variables, and element attributes
//! (`fixtures/newuser/make_exodus_vectors.py`).
//!
//! Exodus stores each component as a variable of its own (`DISPLX DISPLY DISPLZ`, `vel_x vel_y
//! vel_z`, `sig_R sig_Z`, `T_XX T_YY T_ZZ T_XY T_XZ T_YZ`). VTK 9.1's vtkExodusIIReader joins
//! consecutive ones with a common prefix and a known suffix set into one array named by the
//! prefix (`DISPL`, `vel_`, `sig_`, `T_`); tetkit gave one scalar array per variable, so a
//! ParaView user's `DISPL` or `vel_` was not there. tetkit now joins them by VTK's rule, with
//! VTK's names and component order, keeping the stored type.
//!
//! Element attributes (`attrib{k}`, named by `attrib_name{k}`) were skipped with a warning; VTK
//! reads each as a cell array of its name. tetkit now reads them so, NaN in blocks without them.

mod common;

use common::{fixture, require_vtk, tempdir, tetkit, vtk_python};
use serde_json::Value;
use std::path::Path;
use tetkit::formats::{self, ArrayData, DataArray, Grid};

fn convert(input: &Path, dir: &Path, name: &str) -> (Grid, String) {
    let out = dir.join(name);
    let run = tetkit(["convert".as_ref(), input.as_os_str(), out.as_os_str()]);
    run.assert_success();
    let (_, _, stderr) = run.parts();
    (formats::read(&out).unwrap(), stderr)
}

fn array<'a>(arrays: &'a [DataArray], name: &str) -> &'a DataArray {
    arrays
        .iter()
        .find(|a| a.name == name)
        .unwrap_or_else(|| panic!("no array {name} in {:?}", names(arrays)))
}

fn names(arrays: &[DataArray]) -> Vec<&str> {
    arrays.iter().map(|a| a.name.as_str()).collect()
}

/// Tuple `i` of `a`.
fn tuple(a: &DataArray, i: usize) -> Vec<f64> {
    (0..a.components)
        .map(|k| a.data.get_f64(i * a.components + k))
        .collect()
}

#[test]
fn components_joined_as_vtk_names_them() {
    let dir = tempdir();
    let input = fixture("newuser/exodus_vectors.exo");
    let (g, stderr) = convert(&input, dir.path(), "out.vtu");
    assert!(!stderr.contains("attributes"), "{stderr}");
    let p = &g.point_data.arrays;
    // Variable v at node i holds 100 v + i: the components' variables in file order.
    for (name, first, comps) in [
        ("DISPL", 0, 3),
        ("vel_", 3, 3),
        ("a_", 6, 3),
        ("sig_", 9, 2),
        ("p_", 11, 2),
        ("T_", 28, 6),
        ("tenX", 34, 3),
        ("d__", 41, 3),
    ] {
        let a = array(p, name);
        assert_eq!(a.components, comps, "{name}");
        assert!(matches!(a.data, ArrayData::Float64(_)), "{name}");
        let want: Vec<f64> = (0..comps)
            .map(|k| 100.0 * (first + k) as f64 + 4.0)
            .collect();
        assert_eq!(tuple(a, 4), want, "{name}");
    }
    // The variables' own names name the components, so `--scalar DISPL:DISPLY` picks one.
    assert_eq!(
        array(p, "DISPL").component_names,
        ["DISPLX", "DISPLY", "DISPLZ"]
    );
    // What VTK leaves scalars: x z without y, an interrupted vector, R THETA Z, a tensor with ZX
    // for XZ, the rest of VTK's writer's tensor, prefixes differing in case, a scalar whose name
    // the joined d_x d_y d_z then takes `_` after, names that are all suffix.
    for name in [
        "q_x", "q_z", "w_x", "other", "w_y", "w_z", "u_r", "u_theta", "u_z", "S_XX", "S_YY",
        "S_ZZ", "S_XY", "S_YZ", "S_ZX", "tenYY", "tenYZ", "tenZZ", "d_", "n_X", "N_Y", "vx", "Vy",
        "x", "y",
    ] {
        assert_eq!(array(p, name).components, 1, "{name}");
    }
    for gone in ["DISPLX", "vel_x", "sig_R", "T_XX", "tenXX"] {
        assert!(
            g.point_data.get(gone).is_none(),
            "{gone} is a component now"
        );
    }

    let c = &g.cell_data.arrays;
    // f_x f_y f_z only in block 2 (the second cell): NaN in block 1.
    let f = array(c, "f_");
    assert_eq!(f.components, 3);
    assert!(tuple(f, 0).iter().all(|x| x.is_nan()));
    assert_eq!(tuple(f, 1), [1.0, 101.0, 201.0]);
    // Integration points s_hex_GP111 .. GP222 fill a 2 x 2 x 2 box: 8 components.
    let s = array(c, "s_hex");
    assert_eq!(s.components, 8);
    assert_eq!(tuple(s, 1)[7], 1001.0);
    // Attributes: block 2's, one array each, not joined; NaN in block 1.
    for (name, v) in [("area", 0.5), ("thick_x", 1.5), ("thick_y", 2.5)] {
        let a = array(c, name);
        assert_eq!(a.components, 1, "{name}");
        assert!(a.data.get_f64(0).is_nan(), "{name}");
        assert_eq!(a.data.get_f64(1), v, "{name}");
    }

    // Global variables: every step's value, joined as nodal ones are.
    let ke = array(&g.field_data, "KE_");
    assert_eq!((ke.components, ke.tuples()), (3, 2));
    assert_eq!(tuple(ke, 1), [0.25, 100.25, 200.25]);
    assert_eq!(array(&g.field_data, "E").components, 1);

    // Step 1 as `FILE.exo@1`.
    let mut at = input.into_os_string();
    at.push("@1");
    let (g1, _) = convert(Path::new(&at), dir.path(), "step1.vtu");
    assert_eq!(
        tuple(g1.point_data.get("vel_").unwrap(), 0),
        [300.25, 400.25, 500.25]
    );
}

#[test]
fn a_component_picked_by_its_variable_name() {
    let dir = tempdir();
    let input = fixture("newuser/exodus_vectors.exo");
    let png = dir.path().join("out.png");
    for scalar in ["DISPL:DISPLY", "DISPL:Y", "DISPL:1", "DISPL", "T_:T_XZ"] {
        tetkit([
            "render".as_ref(),
            input.as_os_str(),
            "-o".as_ref(),
            png.as_os_str(),
            "--size".as_ref(),
            "16x16".as_ref(),
            "--scalar".as_ref(),
            scalar.as_ref(),
        ])
        .assert_success();
    }
}

#[test]
fn two_d_vectors_get_a_zero_third_component_and_keep_float32() {
    let dir = tempdir();
    let (g, _) = convert(
        &fixture("newuser/exodus_vectors_2d.exo"),
        dir.path(),
        "out.vtu",
    );
    for (arrays, name, want) in [
        (&g.point_data.arrays, "u_", [1.0, 101.0, 0.0]),
        (&g.point_data.arrays, "v_", [201.0, 301.0, 401.0]),
        (&g.point_data.arrays, "r_", [501.0, 601.0, 0.0]),
        (&g.cell_data.arrays, "c_", [1.0, 101.0, 0.0]),
    ] {
        let a = array(arrays, name);
        assert!(matches!(a.data, ArrayData::Float32(_)), "{name}");
        assert_eq!(tuple(a, 1), want, "{name}");
    }
    // Global variables are not padded.
    assert_eq!(array(&g.field_data, "g_").components, 2);
}

#[test]
fn a_component_a_block_lacks_is_nan() {
    let dir = tempdir();
    let (g, _) = convert(
        &fixture("newuser/exodus_vectors_truth.exo"),
        dir.path(),
        "out.vtu",
    );
    let b = g.cell_data.get("b_").expect("joined b_");
    assert_eq!(tuple(b, 0), [0.0, 100.0, 200.0]);
    let t = tuple(b, 1);
    assert_eq!((t[0], t[2]), (1.0, 201.0));
    assert!(t[1].is_nan(), "{t:?}");
    // Attributes without attrib_name1 are attrib1, attrib2 (VTK 9.1 names them "").
    for (name, v) in [("attrib1", 0.5), ("attrib2", 1.5)] {
        let a = g.cell_data.get(name).expect(name).data.to_f64_vec();
        assert_eq!(a[0], v, "{name}");
        assert!(a[1].is_nan(), "{name}");
    }
}

/// VTK's reading: per array, its components and, per block's cell (cell arrays) or per cell
/// corner (point arrays), its tuple, `null` where the block has no such array; field arrays
/// whole.
const VTK_READ: &str = r#"
import json, sys, vtk
r = vtk.vtkExodusIIReader()
r.SetFileName(sys.argv[1])
r.UpdateInformation()
for t in (r.NODAL, r.ELEM_BLOCK, r.GLOBAL):
    r.SetAllArrayStatus(t, 1)
for b in range(r.GetNumberOfObjects(r.ELEM_BLOCK)):
    for i in range(r.GetNumberOfObjectAttributes(r.ELEM_BLOCK, b)):
        r.SetObjectAttributeStatus(r.ELEM_BLOCK, b, i, 1)
r.Update()
skip = {"ObjectId", "GlobalElementId", "GlobalNodeId", "PedigreeElementId", "PedigreeNodeId",
        "ElementBlockIds", "Title", "Info Records", "QA Records"}
leaves, out = [], {"point": {}, "cell": {}, "field": {}}
it = r.GetOutput().NewIterator()
it.InitTraversal()
while not it.IsDoneWithTraversal():
    leaves.append(it.GetCurrentDataObject())
    it.GoToNextItem()
def names(d):
    return [d.GetArrayName(i) for i in range(d.GetNumberOfArrays())
            if d.GetArrayName(i) not in skip]
for ds in leaves:
    for kind, d in (("point", ds.GetPointData()), ("cell", ds.GetCellData())):
        for n in names(d):
            out[kind][n] = [d.GetArray(n).GetNumberOfComponents(), []]
    fd = ds.GetFieldData()
    for n in names(fd):
        a = fd.GetArray(n)
        out["field"][n] = [a.GetNumberOfComponents(),
                           [list(a.GetTuple(i)) for i in range(a.GetNumberOfTuples())]]
for ds in leaves:
    for c in range(ds.GetNumberOfCells()):
        ids = ds.GetCell(c).GetPointIds()
        for n, v in out["cell"].items():
            a = ds.GetCellData().GetArray(n)
            v[1].append(list(a.GetTuple(c)) if a else None)
        for n, v in out["point"].items():
            a = ds.GetPointData().GetArray(n)
            for k in range(ids.GetNumberOfIds()):
                v[1].append(list(a.GetTuple(ids.GetId(k))) if a else None)
print(json.dumps(out))
"#;

fn same(what: &str, ours: &[f64], theirs: &Value) {
    let theirs: Vec<f64> = theirs
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert_eq!(ours.len(), theirs.len(), "{what}");
    for (a, b) in ours.iter().zip(&theirs) {
        assert!(
            (a - b).abs() <= 1e-6 * b.abs().max(1.0),
            "{what}: {ours:?} vs VTK {theirs:?}"
        );
    }
}

#[test]
fn the_same_arrays_as_vtk_reads() {
    if !require_vtk("the_same_arrays_as_vtk_reads") {
        return;
    }
    let dir = tempdir();
    for name in ["exodus_vectors.exo", "exodus_vectors_2d.exo"] {
        let input = fixture(&format!("newuser/{name}"));
        let (g, _) = convert(&input, dir.path(), "out.vtu");
        let vtk: Value =
            serde_json::from_str(&vtk_python(VTK_READ, &[input.to_str().unwrap()])).unwrap();
        for (kind, arrays) in [("point", &g.point_data), ("cell", &g.cell_data)] {
            let theirs = vtk[kind].as_object().unwrap();
            let ours: Vec<&str> = arrays
                .arrays
                .iter()
                .map(|a| a.name.as_str())
                .filter(|n| !["ObjectId", "GlobalElementId", "GlobalNodeId"].contains(n))
                .collect();
            let mut want: Vec<&str> = theirs.keys().map(String::as_str).collect();
            let mut have = ours.clone();
            want.sort();
            have.sort();
            assert_eq!(have, want, "{name}: {kind} arrays");
            for (n, v) in theirs {
                let a = arrays.get(n).unwrap();
                let what = format!("{name} {kind} {n}");
                assert_eq!(Some(a.components as u64), v[0].as_u64(), "{what}");
                let mut at = 0;
                for c in 0..g.num_cells() {
                    let items: Vec<usize> = if kind == "cell" {
                        vec![c]
                    } else {
                        g.cells.cell(c).iter().map(|&p| p as usize).collect()
                    };
                    for i in items {
                        let t = &v[1][at];
                        at += 1;
                        if t.is_null() {
                            assert!(tuple(a, i).iter().all(|x| x.is_nan()), "{what} {i}");
                        } else {
                            same(&format!("{what} {i}"), &tuple(a, i), t);
                        }
                    }
                }
            }
        }
        for (n, v) in vtk["field"].as_object().unwrap() {
            let a = array(&g.field_data, n);
            assert_eq!(Some(a.components as u64), v[0].as_u64(), "{name} field {n}");
            let flat: Vec<Value> = v[1]
                .as_array()
                .unwrap()
                .iter()
                .flat_map(|t| t.as_array().unwrap().clone())
                .collect();
            same(
                &format!("{name} field {n}"),
                &a.data.to_f64_vec(),
                &Value::Array(flat),
            );
        }
    }
}
