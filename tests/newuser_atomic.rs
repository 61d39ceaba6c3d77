//! `partition` writes the split mesh, the tree and optionally the leaf pieces: all of them or
//! none (a split mesh that could not be written used to leave the tree file behind); `tradeoff`
//! leaves no results folder when it fails; `render` refuses image names it would not honour.

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

#[test]
fn tradeoff_and_render_leave_nothing_on_bad_input() {
    let dir = tempdir();
    let input = fixture("gmsh/cavity.vtk");
    // A tradeoff whose input or array is wrong used to leave an empty results folder.
    let folder = dir.path().join("results");
    for (mesh, extra) in [
        (dir.path().join("missing.vtu"), vec![]),
        (input.clone(), vec!["--scalar", "nope"]),
    ] {
        let mut args = vec![
            "tradeoff".to_string(),
            mesh.display().to_string(),
            "-o".into(),
            folder.display().to_string(),
        ];
        args.extend(extra.iter().map(|s| s.to_string()));
        tetkit(&args).assert_failure(&[]);
        assert!(dir_listing(dir.path()).is_empty(), "{args:?}");
    }
    // render writes PNG only: another image extension is refused before anything is written.
    let jpg = dir.path().join("view.jpg");
    tetkit([
        "render".as_ref(),
        input.as_os_str(),
        "-o".as_ref(),
        jpg.as_os_str(),
    ])
    .assert_failure(&["view.jpg", "PNG"]);
    assert!(dir_listing(dir.path()).is_empty());
}

/// A folder in the way of a file tradeoff writes last (tradeoff.csv) failed the run after every
/// image had been written into an existing results folder: found before any work now.
#[test]
fn tradeoff_finds_a_folder_in_its_way_before_writing() -> Result<(), std::io::Error> {
    let dir = tempdir();
    let folder = dir.path().join("results");
    std::fs::create_dir_all(folder.join("tradeoff.csv"))?;
    tetkit([
        "tradeoff".as_ref(),
        fixture("gmsh/cavity.vtk").as_os_str(),
        "-o".as_ref(),
        folder.as_os_str(),
        "--size".as_ref(),
        "16x16".as_ref(),
    ])
    .assert_failure(&["tradeoff.csv", "a folder is in the way"]);
    assert_eq!(dir_listing(&folder), vec!["tradeoff.csv".to_string()]);
    Ok(())
}

/// `tradeoff -o` naming an existing file said only "creating folder: File exists"; it now says
/// that -o names a folder, and the file is left as it was.
#[test]
fn tradeoff_says_its_output_is_a_folder() -> Result<(), std::io::Error> {
    let dir = tempdir();
    let file = dir.path().join("results.png");
    std::fs::write(&file, b"mine")?;
    tetkit([
        "tradeoff".as_ref(),
        fixture("gmsh/cavity.vtk").as_os_str(),
        "-o".as_ref(),
        file.as_os_str(),
        "--size".as_ref(),
        "16x16".as_ref(),
    ])
    .assert_failure(&["results.png", "is a file", "-o names the folder"]);
    assert_eq!(std::fs::read(&file)?, b"mine");
    Ok(())
}
