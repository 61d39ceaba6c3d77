//! Shared by the VTU tests: fixture paths, the checksum the fixture and interop scripts compute,
//! and bit-exact grid comparison.
#![allow(dead_code)]

use formats::{ArrayData, DataArray, Grid};
use std::path::PathBuf;

pub fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/vtk")
}

pub fn manifest() -> serde_json::Value {
    let text = std::fs::read_to_string(fixtures().join("manifest.json")).expect("manifest.json");
    serde_json::from_str(&text).expect("manifest parses")
}

/// Zero-pad to 8 bytes, read little-endian u64 words w_i, sum w_i * (2i + 1) mod 2^64
/// (scripts/make_vtk_fixtures.py and scripts/vtu_describe.py compute the same).
pub fn csum_bytes(b: &[u8]) -> u64 {
    let mut s = 0u64;
    for (i, c) in b.chunks(8).enumerate() {
        let mut w = [0u8; 8];
        w[..c.len()].copy_from_slice(c);
        s = s.wrapping_add(u64::from_le_bytes(w).wrapping_mul(2 * i as u64 + 1));
    }
    s
}

/// Little-endian bytes of a numeric array (none for strings: the manifest sums numbers only).
pub fn le_bytes(d: &ArrayData) -> Vec<u8> {
    match d {
        ArrayData::String(_) => Vec::new(),
        _ => d.le_bytes(),
    }
}

pub fn csum(d: &ArrayData) -> u64 {
    csum_bytes(&le_bytes(d))
}

pub fn csum_i64(v: &[i64]) -> u64 {
    csum(&ArrayData::Int64(v.to_vec()))
}

/// Checks one array against its manifest entry.
pub fn check_array(a: &DataArray, m: &serde_json::Value, what: &str) {
    assert_eq!(a.data.type_name(), m["type"], "{what}: type");
    assert_eq!(a.components as u64, m["components"], "{what}: components");
    assert_eq!(a.tuples() as u64, m["tuples"], "{what}: tuples");
    let names: Vec<String> = m["component_names"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap().to_string())
        .collect();
    assert_eq!(a.component_names, names, "{what}: component names");
    match &a.data {
        ArrayData::String(s) => {
            let want: Vec<&str> = m["strings"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_str().unwrap())
                .collect();
            assert_eq!(s, &want, "{what}: strings");
        }
        d => assert_eq!(
            csum(d).to_string(),
            m["csum"].as_str().unwrap(),
            "{what}: checksum"
        ),
    }
}

fn arrays_bit_eq(a: &[DataArray], b: &[DataArray], what: &str) -> Result<(), String> {
    if a.len() != b.len() {
        return Err(format!("{what}: {} arrays vs {}", a.len(), b.len()));
    }
    for (x, y) in a.iter().zip(b) {
        if !x.bit_eq(y) {
            return Err(format!(
                "{what}: array '{}' differs from '{}'",
                x.name, y.name
            ));
        }
    }
    Ok(())
}

/// Everything equal bit for bit (NaN payloads included).
pub fn grids_bit_eq(a: &Grid, b: &Grid) -> Result<(), String> {
    if !a.points.bit_eq(&b.points) {
        return Err("points differ".into());
    }
    if a.cells != b.cells {
        return Err("cells differ".into());
    }
    arrays_bit_eq(&a.point_data.arrays, &b.point_data.arrays, "point data")?;
    arrays_bit_eq(&a.cell_data.arrays, &b.cell_data.arrays, "cell data")?;
    arrays_bit_eq(&a.field_data, &b.field_data, "field data")?;
    if a.point_data.active != b.point_data.active || a.cell_data.active != b.cell_data.active {
        return Err("active attributes differ".into());
    }
    Ok(())
}

/// Is VTK (python3-vtk9) usable? Panics when it is not but TETKIT_REQUIRE_VTK=1.
pub fn vtk_available() -> bool {
    let ok = std::process::Command::new("/usr/bin/python3")
        .args(["-c", "import vtk"])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    if !ok && std::env::var("TETKIT_REQUIRE_VTK").as_deref() == Ok("1") {
        panic!("TETKIT_REQUIRE_VTK=1 but /usr/bin/python3 cannot import vtk");
    }
    ok
}

/// Checks counts, cells and every array of `g` against a description in the manifest's shape
/// (what scripts/make_vtk_fixtures.py and scripts/vtu_describe.py print).
pub fn check_grid(g: &Grid, m: &serde_json::Value, file: &str) {
    assert_eq!(g.num_points() as u64, m["points"], "{file}: points");
    assert_eq!(g.num_cells() as u64, m["cells"], "{file}: cells");
    check_array(&g.points, &m["points_array"], &format!("{file}: Points"));
    assert_eq!(
        csum_i64(&g.cells.connectivity).to_string(),
        m["connectivity_csum"].as_str().unwrap(),
        "{file}: connectivity"
    );
    assert_eq!(
        csum_i64(&g.cells.offsets).to_string(),
        m["offsets_csum"].as_str().unwrap(),
        "{file}: offsets"
    );
    assert_eq!(
        csum(&ArrayData::UInt8(g.cells.types.clone())).to_string(),
        m["types_csum"].as_str().unwrap(),
        "{file}: types"
    );
    for (key, arrays) in [
        ("point_data", &g.point_data.arrays),
        ("cell_data", &g.cell_data.arrays),
        ("field_data", &g.field_data),
    ] {
        let want = m[key].as_object().unwrap();
        assert_eq!(arrays.len(), want.len(), "{file}: number of {key} arrays");
        for a in arrays {
            let mm = want
                .get(&a.name)
                .unwrap_or_else(|| panic!("{file}: unexpected {key} array {}", a.name));
            check_array(a, mm, &format!("{file}: {key} '{}'", a.name));
        }
    }
}
