//! Helpers shared by the legacy VTK and TetGen integration tests: fixture paths, VTK's summary
//! of a file (scripts/vtk_legacy_summary.py) and comparing a Grid with it.
#![allow(dead_code)]

use formats::{cell_type, ArrayData, Attribute, DataArray, Grid, ScalarType};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub fn legacy_fixtures() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join("fixtures/legacy"))
        .expect("fixtures/legacy exists")
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "vtk"))
        .collect();
    v.sort();
    assert!(v.len() >= 6, "expected the legacy fixtures, found {v:?}");
    v
}

/// VTK's own reading of each fixture, recorded by scripts/make_legacy_fixtures.py.
pub fn checksums() -> Value {
    let text = std::fs::read_to_string(root().join("fixtures/legacy/checksums.json"))
        .expect("fixtures/legacy/checksums.json");
    serde_json::from_str(&text).expect("valid JSON")
}

/// Whether VTK's python is there; panics when it is missing and TETKIT_REQUIRE_VTK=1.
pub fn have_vtk() -> bool {
    let ok = Command::new("/usr/bin/python3")
        .args(["-c", "import vtk"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        assert!(
            std::env::var("TETKIT_REQUIRE_VTK").ok().as_deref() != Some("1"),
            "TETKIT_REQUIRE_VTK=1 but /usr/bin/python3 cannot import vtk"
        );
        eprintln!("skipping: /usr/bin/python3 has no vtk module");
    }
    ok
}

/// Runs scripts/vtk_legacy_summary.py on `files` and returns {path: summary}.
pub fn vtk_summaries(files: &[PathBuf]) -> Value {
    let out = Command::new("/usr/bin/python3")
        .arg(root().join("scripts/vtk_legacy_summary.py"))
        .args(files)
        .output()
        .expect("run /usr/bin/python3");
    assert!(
        out.status.success(),
        "vtk_legacy_summary.py failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("summary JSON")
}

/// Our element type for a vtkDataArray::GetDataTypeAsString() name.
pub fn vtk_type(name: &str) -> Option<ScalarType> {
    Some(match name {
        "float" => ScalarType::Float32,
        "double" => ScalarType::Float64,
        "char" | "signed char" => ScalarType::Int8,
        "unsigned char" | "bit" => ScalarType::UInt8,
        "short" => ScalarType::Int16,
        "unsigned short" => ScalarType::UInt16,
        "int" => ScalarType::Int32,
        "unsigned int" => ScalarType::UInt32,
        "long" | "long long" | "idtype" | "vtkIdType" => ScalarType::Int64,
        "unsigned long" | "unsigned long long" => ScalarType::UInt64,
        _ => return None,
    })
}

fn close(a: f64, b: f64, scale: f64) -> bool {
    a == b || (a - b).abs() <= 1e-12 * scale.max(1.0)
}

/// Compares one array with VTK's summary of it.
pub fn compare_array(what: &str, a: &DataArray, s: &Value) -> Result<(), String> {
    let err = |m: String| Err(format!("{what} '{}': {m}", a.name));
    if s["components"].as_u64() != Some(a.components as u64) {
        return err(format!(
            "components {} vs VTK {}",
            a.components, s["components"]
        ));
    }
    if s["tuples"].as_u64() != Some(a.tuples() as u64) {
        return err(format!("tuples {} vs VTK {}", a.tuples(), s["tuples"]));
    }
    if let ArrayData::String(v) = &a.data {
        let vs: Vec<String> = s["strings"]
            .as_array()
            .map(|x| {
                x.iter()
                    .filter_map(|y| y.as_str().map(String::from))
                    .collect()
            })
            .unwrap_or_default();
        return if *v == vs {
            Ok(())
        } else {
            err(format!("strings {v:?} vs VTK {vs:?}"))
        };
    }
    let ty = s["type"].as_str().unwrap_or("");
    if vtk_type(ty) != a.data.scalar_type() {
        return err(format!("type {:?} vs VTK {ty}", a.data.scalar_type()));
    }
    let vals = a.data.to_f64_vec();
    let fin: Vec<f64> = vals.iter().copied().filter(|x| x.is_finite()).collect();
    let sum: f64 = fin.iter().sum();
    let abs: f64 = fin.iter().map(|x| x.abs()).sum();
    let (vsum, vabs) = (
        s["sum"].as_f64().unwrap_or(f64::NAN),
        s["abs_sum"].as_f64().unwrap_or(f64::NAN),
    );
    if !close(sum, vsum, abs) || !close(abs, vabs, abs) {
        return err(format!("sum {sum} / abs sum {abs} vs VTK {vsum} / {vabs}"));
    }
    if s["nonfinite"].as_u64() != Some((vals.len() - fin.len()) as u64) {
        return err(format!(
            "{} non-finite values vs VTK {}",
            vals.len() - fin.len(),
            s["nonfinite"]
        ));
    }
    let names: Vec<String> = s["component_names"]
        .as_array()
        .map(|x| {
            x.iter()
                .filter_map(|y| y.as_str().map(String::from))
                .collect()
        })
        .unwrap_or_default();
    if names != a.component_names {
        return err(format!(
            "component names {:?} vs VTK {names:?}",
            a.component_names
        ));
    }
    Ok(())
}

/// Compares a grid with VTK's summary of a file: counts, cell types, connectivity and point
/// sums, every array (lookup tables, which VTK attaches to the scalars, are not field data for
/// VTK and are skipped), and the active attributes.
pub fn compare_grid(grid: &Grid, s: &Value) -> Result<(), String> {
    if s["points"].as_u64() != Some(grid.num_points() as u64) {
        return Err(format!(
            "{} points vs VTK {}",
            grid.num_points(),
            s["points"]
        ));
    }
    if s["cells"].as_u64() != Some(grid.num_cells() as u64) {
        return Err(format!("{} cells vs VTK {}", grid.num_cells(), s["cells"]));
    }
    for (t, n) in grid.cell_type_counts() {
        if s["cell_types"][t.to_string()].as_u64() != Some(n as u64) {
            return Err(format!(
                "{n} cells of type {} vs VTK {}",
                cell_type::name(t),
                s["cell_types"]
            ));
        }
    }
    let conn: i64 = grid.cells.connectivity.iter().sum();
    if s["connectivity_sum"].as_i64() != Some(conn) {
        return Err(format!(
            "connectivity sum {conn} vs VTK {}",
            s["connectivity_sum"]
        ));
    }
    if grid.num_points() > 0 {
        let ps: f64 = grid.points.data.to_f64_vec().iter().sum();
        let scale: f64 = grid.points.data.to_f64_vec().iter().map(|x| x.abs()).sum();
        if !close(ps, s["points_sum"].as_f64().unwrap_or(f64::NAN), scale) {
            return Err(format!("points sum {ps} vs VTK {}", s["points_sum"]));
        }
    }
    let field: Vec<&DataArray> = grid
        .field_data
        .iter()
        .filter(|a| !a.name.starts_with(formats::legacy::LOOKUP_TABLE_PREFIX))
        .collect();
    for (key, arrays) in [
        (
            "point_data",
            grid.point_data.arrays.iter().collect::<Vec<_>>(),
        ),
        ("cell_data", grid.cell_data.arrays.iter().collect()),
        ("field_data", field),
    ] {
        let vtk = s[key].as_object().cloned().unwrap_or_default();
        if vtk.len() != arrays.len() {
            let ours: Vec<&str> = arrays.iter().map(|a| a.name.as_str()).collect();
            let theirs: Vec<&String> = vtk.keys().collect();
            return Err(format!("{key}: ours {ours:?} vs VTK {theirs:?}"));
        }
        for a in arrays {
            let v = vtk
                .get(&a.name)
                .ok_or_else(|| format!("{key}: VTK has no '{}'", a.name))?;
            compare_array(key, a, v)?;
        }
    }
    for (key, attrs) in [
        ("point_active", &grid.point_data),
        ("cell_active", &grid.cell_data),
    ] {
        for role in Attribute::ALL {
            let ours = attrs.active(role).map(|a| a.name.clone());
            let theirs = s[key][role.xml_name()].as_str().map(String::from);
            if ours != theirs {
                return Err(format!(
                    "{key} {}: ours {ours:?} vs VTK {theirs:?}",
                    role.xml_name()
                ));
            }
        }
    }
    Ok(())
}

/// Bit-exact equality of two grids, naming the first difference.
pub fn same_grid(a: &Grid, b: &Grid) -> Result<(), String> {
    if !a.points.data.bit_eq(&b.points.data) || a.points.component_names != b.points.component_names
    {
        return Err("points differ".into());
    }
    if a.cells != b.cells {
        return Err("cells differ".into());
    }
    for (what, x, y) in [
        ("point", &a.point_data, &b.point_data),
        ("cell", &a.cell_data, &b.cell_data),
    ] {
        same_arrays(what, &x.arrays, &y.arrays)?;
        let mut xa = x.active.clone();
        let mut ya = y.active.clone();
        xa.sort();
        ya.sort();
        if xa != ya {
            return Err(format!("{what} active attributes {xa:?} vs {ya:?}"));
        }
        if x.lookup_tables != y.lookup_tables {
            return Err(format!(
                "{what} lookup tables {:?} vs {:?}",
                x.lookup_tables, y.lookup_tables
            ));
        }
    }
    same_arrays("field", &a.field_data, &b.field_data)
}

pub fn same_arrays(what: &str, x: &[DataArray], y: &[DataArray]) -> Result<(), String> {
    let mut xs: Vec<&DataArray> = x.iter().collect();
    let mut ys: Vec<&DataArray> = y.iter().collect();
    xs.sort_by(|p, q| p.name.cmp(&q.name));
    ys.sort_by(|p, q| p.name.cmp(&q.name));
    if xs.len() != ys.len() {
        return Err(format!(
            "{what} data: {:?} vs {:?}",
            xs.iter().map(|a| &a.name).collect::<Vec<_>>(),
            ys.iter().map(|a| &a.name).collect::<Vec<_>>()
        ));
    }
    for (p, q) in xs.iter().zip(ys) {
        if !p.bit_eq(q) {
            return Err(format!(
                "{what} data '{}' differs ({} {:?} x{} vs '{}' {} {:?} x{})",
                p.name,
                p.data.type_name(),
                p.component_names,
                p.components,
                q.name,
                q.data.type_name(),
                q.component_names,
                q.components
            ));
        }
    }
    Ok(())
}

pub fn tetkit(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_tetkit"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("run tetkit")
}

pub fn path_str(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}
