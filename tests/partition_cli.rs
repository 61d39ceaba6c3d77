//! `tetkit partition` run as a binary: argument and input errors.

mod common;

#[test]
fn missing_input_is_named() {
    let dir = common::tempdir();
    let out = dir.path().join("s.vtu");
    let tree = dir.path().join("t.vtu");
    let r = common::tetkit([
        "partition".as_ref(),
        dir.path().join("nope.vtu").as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--tree".as_ref(),
        tree.as_os_str(),
    ]);
    r.assert_failure(&["nope.vtu"]);
    assert!(!out.exists() && !tree.exists());
}

#[test]
fn bad_options_are_refused() {
    let dir = common::tempdir();
    let out = dir.path().join("s.vtu");
    let tree = dir.path().join("t.vtu");
    let base = |extra: &[&str]| {
        let mut v: Vec<String> = vec![
            "partition".into(),
            "in.vtu".into(),
            "-o".into(),
            out.display().to_string(),
            "--tree".into(),
            tree.display().to_string(),
        ];
        v.extend(extra.iter().map(|s| s.to_string()));
        common::tetkit(v)
    };
    base(&["--candidates", "0"]).assert_failure(&["--candidates"]);
    base(&["--phi=-1"]).assert_failure(&["--phi"]);
    base(&["--eps=nan"]).assert_failure(&["--eps"]);
    base(&["--leaves", "0"]).assert_failure(&["--leaves"]);
    base(&["--leaves", "4", "--depth", "2"]).assert_failure(&["--depth"]);
    let r = common::tetkit(["partition", "in.vtu", "-o", "s.vtk", "--tree", "t.vtu"]);
    r.assert_failure(&["s.vtk"]);
}

use std::path::{Path, PathBuf};

use serde_json::Value;
use tetkit::mesh::TetMesh;
use tetkit::partition::KdTree;

/// Runs `tetkit partition IN -o DIR/split.vtu --tree DIR/tree.vtu --pieces DIR/pieces --json EXTRA`.
fn run_partition(input: &Path, dir: &Path, extra: &[&str]) -> (Value, String) {
    let mut args: Vec<String> = vec![
        "partition".into(),
        input.display().to_string(),
        "-o".into(),
        dir.join("split.vtu").display().to_string(),
        "--tree".into(),
        dir.join("tree.vtu").display().to_string(),
        "--pieces".into(),
        dir.join("pieces").display().to_string(),
        "--json".into(),
    ];
    args.extend(extra.iter().map(|s| s.to_string()));
    let r = common::tetkit(&args);
    r.assert_success();
    let report: Value = serde_json::from_slice(&r.stdout).expect("--json prints JSON");
    (report, r.stderr.clone())
}

/// What tetkit reads back of the split mesh and the tree, checked against the report.
fn check_outputs(dir: &Path, report: &Value) {
    let tets = report["tets_after"].as_u64().unwrap() as usize;
    let leaves = report["leaves"].as_u64().unwrap() as usize;
    let split = tetkit::formats::read(&dir.join("split.vtu")).unwrap();
    assert_eq!(split.num_cells(), tets);
    let leaf = split.cell_data.get("leaf_id").expect("leaf_id");
    assert_eq!(leaf.data.type_name(), "Int32");
    let orig = split
        .cell_data
        .get("original_cell_id")
        .expect("original_cell_id");
    assert_eq!(orig.data.type_name(), "Int64");
    let tree = KdTree::from_field_data(&split.field_data)
        .unwrap()
        .expect("tree in field data");
    assert_eq!(tree.num_leaves(), leaves);
    assert_eq!(tree.nodes[0].tet_count as usize, tets);
    let mesh = TetMesh::from_grid(&split).unwrap();
    for (t, q) in mesh.tets.iter().enumerate() {
        let l = leaf.data.get_f64(t) as usize;
        let b = tree.nodes[tree.leaf_nodes()[l] as usize].bounds;
        assert!(q.iter().all(|&v| b.contains(&mesh.points[v as usize])));
    }
    let tg = tetkit::formats::read(&dir.join("tree.vtu")).unwrap();
    assert_eq!(tg.num_cells(), tree.nodes.len());
    for name in [
        "node_id",
        "parent_id",
        "depth",
        "is_leaf",
        "leaf_id",
        "split_axis",
        "split_position",
        "tet_count",
    ] {
        assert!(tg.cell_data.get(name).is_some(), "tree.vtu lacks {name}");
    }
}

/// VTK reads split.vtu, tree.vtu and the pieces: counts, leaf_id and volume agree with tetkit.
fn vtk_agrees(dir: &Path, report: &Value, input_volume: f64) {
    let tets = report["tets_after"].as_u64().unwrap();
    let leaves = report["leaves"].as_u64().unwrap();
    let files: Vec<PathBuf> = vec![dir.join("split.vtu"), dir.join("tree.vtu")];
    let res = common::vtk_check_many(&files, true);
    let split = res[0].as_ref().expect("VTK reads split.vtu");
    assert_eq!(split["cells"].as_u64(), Some(tets), "{split}");
    let names: Vec<&str> = split["cell_data"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a["name"].as_str().unwrap())
        .collect();
    assert!(names.contains(&"leaf_id") && names.contains(&"original_cell_id"));
    let v = split["abs_volume"].as_f64().unwrap();
    assert!(
        (v - input_volume).abs() <= 1e-9 * input_volume,
        "VTK volume {v} vs {input_volume}"
    );
    let tree = res[1].as_ref().expect("VTK reads tree.vtu");
    assert_eq!(
        tree["cell_types"]["12"].as_u64().unwrap() as usize,
        2 * leaves as usize - 1
    );
    // The multiblock of pieces: one block per leaf, cells adding up to the split mesh.
    let code = r#"
import sys, vtk
r = vtk.vtkXMLMultiBlockDataReader()
r.SetFileName(sys.argv[1])
r.Update()
mb = r.GetOutput()
n = mb.GetNumberOfBlocks()
cells = sum(mb.GetBlock(i).GetNumberOfCells() for i in range(n))
leaf = all(mb.GetBlock(i).GetCellData().GetArray("leaf_id") is not None for i in range(n))
p = vtk.vtkXMLPUnstructuredGridReader()
p.SetFileName(sys.argv[2])
p.Update()
g = p.GetOutput()
print(n, cells, leaf, p.GetNumberOfPieces(), g.GetNumberOfCells(), g.GetCellData().GetArray("leaf_id") is not None)
"#;
    let out = common::vtk_python(
        code,
        &[
            &dir.join("pieces/split.vtm").display().to_string(),
            &dir.join("pieces/split.pvtu").display().to_string(),
        ],
    );
    assert_eq!(
        out.trim(),
        format!("{leaves} {tets} True {leaves} {tets} True")
    );
}

fn volume_of(m: &TetMesh) -> f64 {
    (0..m.tets.len())
        .map(|t| {
            let p = m.tet_points(t);
            tetkit::geom::tet_volume(&p[0], &p[1], &p[2], &p[3]).abs()
        })
        .sum()
}

#[test]
fn tetgen_and_gmsh_fixtures_both_strategies() {
    for (fixture, name) in [
        (common::fixture("tetgen/torus.1.ele"), "torus"),
        (common::fixture("gmsh/block_hole.vtk"), "block_hole"),
    ] {
        let grid = tetkit::formats::read(&fixture).unwrap();
        let (mesh, _, _) = tetkit::partition::input::tets_of(&grid, name).unwrap();
        let vol = volume_of(&mesh);
        for strategy in ["paper", "cost"] {
            let dir = common::tempdir();
            let (report, _) = run_partition(&fixture, dir.path(), &["--strategy", strategy]);
            assert_eq!(
                report["tets_before"].as_u64().unwrap() as usize,
                mesh.tets.len()
            );
            assert_eq!(
                report["leaves"].as_u64(),
                Some(8),
                "{name} {strategy}: {report}"
            );
            check_outputs(dir.path(), &report);
            if common::require_vtk("partition fixtures") {
                vtk_agrees(dir.path(), &report, vol);
            }
        }
    }
}

#[test]
fn inverted_input_is_reoriented_and_said() {
    let dir = common::tempdir();
    let mut m = tetkit::mesh::generate::structured_grid([3, 3, 3], [0.0; 3], [1.0; 3]);
    for t in m.tets.iter_mut().step_by(2) {
        t.swap(1, 2);
    }
    let input = dir.path().join("inverted.vtu");
    tetkit::formats::write(&input, &m.to_grid(), &Default::default()).unwrap();
    let r = common::tetkit([
        "partition".as_ref(),
        input.as_os_str(),
        "-o".as_ref(),
        dir.path().join("split.vtu").as_os_str(),
        "--tree".as_ref(),
        dir.path().join("tree.vtu").as_os_str(),
        "--depth".as_ref(),
        "2".as_ref(),
        "--phi".as_ref(),
        "5".as_ref(),
    ]);
    r.assert_success();
    assert!(
        r.stderr
            .contains("81 tets had negative volume and were reoriented"),
        "{}",
        r.stderr
    );
    assert!(
        r.stderr.contains("growth"),
        "the table goes to stderr: {}",
        r.stderr
    );
    let split = tetkit::formats::read(&dir.path().join("split.vtu")).unwrap();
    let s = TetMesh::from_grid(&split).unwrap();
    for t in 0..s.tets.len() {
        assert!(tetkit::partition::build::volume_sign(&s.tet_points(t)) > 0.0);
    }
    // Cell data was copied to every piece of a cell.
    let cube = split.cell_data.get("cube_id").unwrap();
    let orig = split.cell_data.get("original_cell_id").unwrap();
    for t in 0..s.tets.len() {
        let o = orig.data.get_f64(t) as usize;
        assert_eq!(cube.data.get_f64(t) as usize, o / 6);
    }
}

#[test]
fn mixed_cells_are_tetrahedralized_first() {
    let dir = common::tempdir();
    let input = common::fixture("mixed/mixed.vtu");
    let grid = tetkit::formats::read(&input).unwrap();
    let (report, _) = run_partition(
        &input,
        dir.path(),
        &["--leaves", "2", "--phi", "10", "--eps", "1.5"],
    );
    check_outputs(dir.path(), &report);
    let split = tetkit::formats::read(&dir.path().join("split.vtu")).unwrap();
    let orig = split.cell_data.get("original_cell_id").unwrap();
    let n = grid.num_cells() as f64;
    for t in 0..split.num_cells() {
        let o = orig.data.get_f64(t);
        assert!(o >= 0.0 && o < n);
        let ty = grid.cells.types[o as usize];
        assert_eq!(
            tetkit::formats::cell_type::dimension(ty),
            3,
            "a tet from a 3-D cell"
        );
    }
}

#[test]
fn the_tree_file_is_optional_since_the_split_mesh_holds_the_tree() {
    let dir = common::tempdir();
    let out = dir.path().join("s.vtu");
    let input = common::fixture("gmsh/hexgrid.vtk");
    common::tetkit([
        "partition".as_ref(),
        input.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--leaves".as_ref(),
        "4".as_ref(),
    ])
    .assert_success();
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, vec!["s.vtu".to_string()]);
    let g = tetkit::formats::read(&out).unwrap();
    let tree = KdTree::from_field_data(&g.field_data).unwrap().unwrap();
    assert_eq!(tree.num_leaves(), 4);
}
