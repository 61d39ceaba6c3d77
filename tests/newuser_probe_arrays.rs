//! `probe` on the arrays ParaView files carry: a point and a cell array of the same name (the
//! cell value silently replaced the point value in `--json`, and the CSV had two columns of one
//! name), 64-bit ids (blended and printed as rounded floats: `2.0999999999999996` for a vertex
//! id), string arrays (left out without a word) and names or strings holding commas and quotes
//! (they broke the CSV's columns). Also `render --scalar cell:NAME` picks the cell array of such
//! a pair, which could not be drawn before.

mod common;

use common::{tempdir, tetkit};
use serde_json::Value;
use tetkit::formats::{ArrayData, DataArray};
use tetkit::mesh::generate::structured_grid;

/// Splits one RFC 4180 line into its fields.
fn csv_fields(line: &str) -> Vec<String> {
    let mut out = vec![String::new()];
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                chars.next();
                out.last_mut().unwrap().push('"');
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(String::new()),
            (c, _) => out.last_mut().unwrap().push(c),
        }
    }
    out
}

const BIG: i64 = (1 << 60) + 7;

#[test]
fn probe_keeps_every_array_apart_exact_and_quoted() {
    let dir = tempdir();
    let mut grid = structured_grid([3, 3, 3], [0.0; 3], [1.0; 3]).to_grid();
    grid.point_data.arrays.clear();
    grid.cell_data.arrays.clear();
    let (np, nc) = (grid.num_points(), grid.num_cells());
    let xyz = grid.points.data.to_f64_vec();
    let pd = &mut grid.point_data;
    pd.insert(DataArray::new(
        "pressure",
        1,
        ArrayData::Float64(xyz.chunks(3).map(|p| p[0] + 2.0 * p[1]).collect()),
    ));
    pd.insert(DataArray::new(
        "id",
        1,
        ArrayData::Int64((0..np as i64).map(|i| BIG + i).collect()),
    ));
    pd.insert(DataArray::new(
        "label, \"quoted\"",
        1,
        ArrayData::String((0..np).map(|i| format!("v{i}, \"x\"")).collect()),
    ));
    grid.cell_data.insert(DataArray::new(
        "pressure",
        1,
        ArrayData::Float32((0..nc).map(|i| 100.0 + i as f32).collect()),
    ));
    let input = dir.path().join("pair.vtu");
    tetkit::formats::write(&input, &grid, &Default::default()).unwrap();

    // Close to vertex 0, the corner (0, 0, 0): its weight is the largest.
    let p = [0.01, 0.02, 0.03];
    let spec = format!("{},{},{}", p[0], p[1], p[2]);
    let json = tetkit([
        "probe",
        input.to_str().unwrap(),
        "--points",
        &spec,
        "--json",
    ]);
    json.assert_success();
    let v: Value = serde_json::from_str(json.stdout_str().trim()).unwrap();
    let vals = &v["values"];
    let tet = v["tet"].as_u64().unwrap() as usize;
    assert!((vals["point:pressure"].as_f64().unwrap() - (p[0] + 2.0 * p[1])).abs() < 1e-12);
    assert_eq!(vals["cell:pressure"].as_f64().unwrap(), 100.0 + tet as f64);
    assert_eq!(vals["id"].as_i64(), Some(BIG), "{vals}");
    assert_eq!(vals["label, \"quoted\""], "v0, \"x\"", "{vals}");

    let csv = tetkit(["probe", input.to_str().unwrap(), "--points", &spec]);
    csv.assert_success();
    let text = csv.stdout_str();
    let lines: Vec<&str> = text.lines().collect();
    let header = csv_fields(lines[0]);
    let row = csv_fields(lines[1]);
    assert_eq!(header.len(), row.len(), "{text}");
    let col = |n: &str| {
        let i = header.iter().position(|h| h == n).unwrap_or_else(|| {
            panic!("no column {n:?} in {header:?}");
        });
        row[i].clone()
    };
    assert_eq!(col("id"), BIG.to_string());
    assert_eq!(col("label, \"quoted\""), "v0, \"x\"");
    assert_eq!(col("cell:pressure"), format!("{}", 100 + tet));
    assert!(header.contains(&"point:pressure".to_string()));

    // The cell array of the pair can be drawn, and it is not the point one.
    let mut images = Vec::new();
    for scalar in ["pressure", "cell:pressure"] {
        let png = dir.path().join(format!("{}.png", scalar.replace(':', "_")));
        let run = tetkit([
            "render",
            input.to_str().unwrap(),
            "-o",
            png.to_str().unwrap(),
            "--size",
            "48x48",
            "--scalar",
            scalar,
            "-q",
        ]);
        run.assert_success();
        images.push(image::open(&png).unwrap().to_rgba8().into_raw());
    }
    assert_ne!(images[0], images[1]);
}

/// `probe` on a mesh of other cells (voxels, hexahedra, quadratic tets: split into tets to be
/// located) printed a column `original_cell_id` that the file does not have: the split's own
/// bookkeeping. Only the input's arrays are printed now (`tet` names the input cell); a file
/// that has its own `original_cell_id` (partition's output) keeps it.
#[test]
fn probe_prints_only_the_files_arrays() {
    let r = tetkit([
        "probe".as_ref(),
        common::fixture("structured/image.vti").as_os_str(),
        "--points".as_ref(),
        "0.5,0.5,0.5".as_ref(),
    ]);
    r.assert_success();
    let header = r.stdout_str().lines().next().unwrap_or("").to_string();
    assert!(header.contains("material"), "{header}");
    assert!(!header.contains("original_cell_id"), "{header}");
    let dir = tempdir();
    let split = dir.path().join("split.vtu");
    tetkit([
        "partition".as_ref(),
        common::fixture("structured/image.vti").as_os_str(),
        "-o".as_ref(),
        split.as_os_str(),
        "--leaves".as_ref(),
        "2".as_ref(),
        "--strategy".as_ref(),
        "cost".as_ref(),
    ])
    .assert_success();
    let r = tetkit([
        "probe".as_ref(),
        split.as_os_str(),
        "--points".as_ref(),
        "0.5,0.5,0.5".as_ref(),
    ]);
    r.assert_success();
    assert!(r
        .stdout_str()
        .lines()
        .next()
        .unwrap_or("")
        .contains("original_cell_id"));
}

/// `probe --points FILE` on ParaView's CSV export of points (File > Save Data: a quoted header,
/// the point arrays' columns, then `Points:0`, `Points:1`, `Points:2`) was refused at line 1
/// ("'"Points:0"' is not a finite number"). A header naming the coordinate columns is read now,
/// other columns ignored; a header without them is an error naming the line and the names.
#[test]
fn probe_reads_paraviews_csv_of_points() {
    let dir = tempdir();
    let image = common::fixture("structured/image.vti");
    let csv = dir.path().join("points.csv");
    std::fs::write(
        &csv,
        "\"material\",\"Points:0\",\"Points:1\",\"Points:2\",\"Points_Magnitude\"\n\
         3,0.5,0.5,0.5,0.866\n\
         1,0.25,0.75,0.5,0.935\n",
    )
    .unwrap();
    let from_csv = tetkit([
        "probe".as_ref(),
        image.as_os_str(),
        "--points".as_ref(),
        csv.as_os_str(),
    ]);
    from_csv.assert_success();
    let inline = tetkit([
        "probe".as_ref(),
        image.as_os_str(),
        "--points".as_ref(),
        "0.5,0.5,0.5;0.25,0.75,0.5".as_ref(),
    ]);
    inline.assert_success();
    assert_eq!(from_csv.stdout_str(), inline.stdout_str());
    assert_eq!(from_csv.stdout_str().lines().count(), 3);

    // Plain x, y, z headers, in another order, with spaces.
    let xyz = dir.path().join("xyz.csv");
    std::fs::write(&xyz, "z, x, y\n0.5, 0.5, 0.5\n0.5, 0.25, 0.75\n").unwrap();
    let r = tetkit([
        "probe".as_ref(),
        image.as_os_str(),
        "--points".as_ref(),
        xyz.as_os_str(),
    ]);
    r.assert_success();
    assert_eq!(r.stdout_str(), inline.stdout_str());

    // A header without coordinates: refused, naming the file's line and what it looked for.
    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "\"a\",\"b\",\"c\"\n1,2,3\n").unwrap();
    tetkit([
        "probe".as_ref(),
        image.as_os_str(),
        "--points".as_ref(),
        bad.as_os_str(),
    ])
    .assert_failure(&["bad.csv: line 1", "Points:0"]);

    // A data line short of the header's columns names its line.
    let short = dir.path().join("short.csv");
    std::fs::write(&short, "x,y,z\n0.5,0.5,0.5\n0.5,0.5\n").unwrap();
    tetkit([
        "probe".as_ref(),
        image.as_os_str(),
        "--points".as_ref(),
        short.as_os_str(),
    ])
    .assert_failure(&["short.csv: line 3"]);
}
