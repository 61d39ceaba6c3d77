//! Several files written as one (TetGen's `.node` + `.ele` + `.face`, partition's split mesh and
//! tree): a folder in the way of one of them (`x.ele/` left from unpacking an archive) made
//! the write fail only after the files before it were in place, so `x.node` stayed behind,
//! replacing the user's previous one, and the error named `x.ele` when `x.face` was the folder.
//! Now nothing is placed, what was there stays, and the error names the file in the way.

mod common;

use common::{dir_listing, fixture, tempdir, tetkit};

#[test]
fn a_folder_in_the_way_places_nothing_and_is_named() {
    let dir = tempdir();
    let d = dir.path();
    // `.ele` itself is a folder: no `.node` may appear.
    std::fs::create_dir(d.join("k.ele")).unwrap();
    let r = tetkit([
        "convert".as_ref(),
        fixture("tetgen/sphere.1.ele").as_os_str(),
        d.join("k.ele").as_os_str(),
    ]);
    r.assert_failure(&["k.ele", "folder"]);
    assert!(!d.join("k.node").exists());

    // `.face` is the folder: the `.node` already there is kept as it was.
    std::fs::create_dir(d.join("m.face")).unwrap();
    std::fs::write(d.join("m.node"), "previous").unwrap();
    let r = tetkit([
        "convert".as_ref(),
        fixture("tetgen/torus.1.ele").as_os_str(),
        d.join("m.ele").as_os_str(),
    ]);
    r.assert_failure(&["m.face", "folder"]);
    assert!(!r.stderr.contains("m.ele"), "{}", r.stderr);
    assert_eq!(
        std::fs::read_to_string(d.join("m.node")).unwrap(),
        "previous"
    );
    assert!(!d.join("m.ele").exists());

    // Partition: the tree's name is a folder; the split mesh does not appear.
    std::fs::create_dir(d.join("tree.vtu")).unwrap();
    let r = tetkit([
        "partition".as_ref(),
        fixture("gmsh/lshape.vtk").as_os_str(),
        "-o".as_ref(),
        d.join("split.vtu").as_os_str(),
        "--tree".as_ref(),
        d.join("tree.vtu").as_os_str(),
    ]);
    r.assert_failure(&["tree.vtu", "folder"]);
    assert!(!d.join("split.vtu").exists());

    // Replacing earlier outputs still works and leaves no temporary or set-aside files.
    for _ in 0..2 {
        tetkit([
            "convert".as_ref(),
            fixture("tetgen/torus.1.ele").as_os_str(),
            d.join("n.ele").as_os_str(),
        ])
        .assert_success();
    }
    let hidden: Vec<String> = dir_listing(d)
        .into_iter()
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(hidden.is_empty(), "{hidden:?}");
    for ext in ["node", "ele", "face"] {
        assert!(d.join(format!("n.{ext}")).is_file(), "{ext}");
    }
}

/// `partition -o x.vtu --tree x.vtu` (or `--tree ./x.vtu`): both outputs named one file, and
/// the split mesh silently replaced the tree (exit 0, one file, the tree gone). Now refused
/// before anything is written, naming both, and the file that was there stays as it was.
#[test]
fn two_outputs_named_as_one_file_are_refused() {
    let dir = tempdir();
    let d = dir.path();
    let before = b"the user's previous file".to_vec();
    std::fs::write(d.join("x.vtu"), &before).unwrap();
    for tree in [d.join("x.vtu"), d.join(".").join("x.vtu")] {
        let r = tetkit([
            "partition".as_ref(),
            fixture("tetgen/sphere.1.ele").as_os_str(),
            "-o".as_ref(),
            d.join("x.vtu").as_os_str(),
            "--tree".as_ref(),
            tree.as_os_str(),
        ]);
        r.assert_failure(&["x.vtu", "two outputs cannot share one file"]);
        assert_eq!(std::fs::read(d.join("x.vtu")).unwrap(), before);
        assert_eq!(dir_listing(d), vec!["x.vtu".to_string()]);
    }
}

/// `partition --pieces DIR` where DIR cannot be made (a file of that name): the split mesh and
/// tree had been placed first and were then deleted, so the user's previous `s.vtu` and `t.vtu`
/// were gone. The pieces are now written before the two are placed: their failure leaves the
/// previous files as they were.
#[test]
fn pieces_that_cannot_be_written_keep_the_previous_outputs() {
    let dir = tempdir();
    let d = dir.path();
    std::fs::write(d.join("s.vtu"), b"old split").unwrap();
    std::fs::write(d.join("t.vtu"), b"old tree").unwrap();
    std::fs::write(d.join("blocker"), b"a file").unwrap();
    let r = tetkit([
        "partition".as_ref(),
        fixture("tetgen/sphere.1.ele").as_os_str(),
        "-o".as_ref(),
        d.join("s.vtu").as_os_str(),
        "--tree".as_ref(),
        d.join("t.vtu").as_os_str(),
        "--pieces".as_ref(),
        d.join("blocker").as_os_str(),
        "--leaves".as_ref(),
        "2".as_ref(),
    ]);
    r.assert_failure(&["blocker"]);
    assert_eq!(std::fs::read(d.join("s.vtu")).unwrap(), b"old split");
    assert_eq!(std::fs::read(d.join("t.vtu")).unwrap(), b"old tree");
    assert_eq!(
        dir_listing(d),
        vec!["blocker".to_string(), "s.vtu".into(), "t.vtu".into()]
    );
    // And with a folder it can write into, all of them appear.
    let r = tetkit([
        "partition".as_ref(),
        fixture("tetgen/sphere.1.ele").as_os_str(),
        "-o".as_ref(),
        d.join("s.vtu").as_os_str(),
        "--tree".as_ref(),
        d.join("t.vtu").as_os_str(),
        "--pieces".as_ref(),
        d.join("p").as_os_str(),
        "--leaves".as_ref(),
        "2".as_ref(),
    ]);
    r.assert_success();
    assert!(d.join("p/s.pvtu").is_file() && d.join("p/s.vtm").is_file());
    assert_ne!(std::fs::read(d.join("s.vtu")).unwrap(), b"old split");
}
