//! `partition` writes the split mesh, the tree and optionally the leaf pieces: all of them or
//! none. A split mesh that could not be written used to leave the tree file behind.

mod common;

use common::{dir_listing, fixture, tempdir, tetkit};

#[test]
fn a_failed_partition_leaves_no_file_behind() {
    let dir = tempdir();
    let input = fixture("gmsh/cavity.vtk");
    let tree = dir.path().join("tree.vtu");
    let in_a_file = dir.path().join("file.txt");
    std::fs::write(&in_a_file, "not a folder").unwrap();
    // The split mesh cannot be written (its folder is missing), then the pieces cannot be
    // (their folder would be inside a file).
    let cases: [(std::path::PathBuf, Vec<String>); 2] = [
        (dir.path().join("missing/split.vtu"), vec![]),
        (
            dir.path().join("split.vtu"),
            vec![
                "--pieces".into(),
                in_a_file.join("pieces").display().to_string(),
            ],
        ),
    ];
    for (split, extra) in cases {
        let mut args = vec![
            "partition".to_string(),
            input.display().to_string(),
            "-o".into(),
            split.display().to_string(),
            "--tree".into(),
            tree.display().to_string(),
        ];
        args.extend(extra);
        tetkit(&args).assert_failure(&[]);
        assert_eq!(
            dir_listing(dir.path()),
            vec!["file.txt".to_string()],
            "{args:?}"
        );
    }
}
