//! Options whose size the user types, mistyped by a few zeros, made tetkit allocate until it
//! aborted ("memory allocation of ... bytes failed", a core dump): `--tf-nodes 1000000000`
//! (24 GB), `--table 4096x4096` (each side allowed, together 1 TiB), `partition --candidates
//! 1000000000` (8 GB). Each is now refused up front with the range it takes, and nothing is
//! written. `check-order --rays` above 8192^2 was cut down to that without a word; it is refused
//! too.

mod common;

use common::{fixture, tempdir, tetkit};

#[test]
fn a_huge_tf_node_count_is_refused_up_front() {
    let dir = tempdir();
    let input = fixture("gmsh/lshape.vtk");
    let png = dir.path().join("x.png");
    for k in ["1000000000", "0", "1", "4097"] {
        let r = tetkit([
            "render",
            input.to_str().unwrap(),
            "-o",
            png.to_str().unwrap(),
            "--tf-nodes",
            k,
        ]);
        r.assert_failure(&["--tf-nodes", k, "between 2 and 4096"]);
        assert!(!png.exists(), "{k}");
    }
    let out = dir.path().join("t");
    let r = tetkit([
        "tradeoff",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--tf-nodes",
        "99999999999",
    ]);
    r.assert_failure(&["--tf-nodes", "between 2 and 4096"]);
    assert!(!out.exists());
    for k in ["2", "4096"] {
        tetkit([
            "render",
            input.to_str().unwrap(),
            "-o",
            png.to_str().unwrap(),
            "--tf-nodes",
            k,
            "--size",
            "32x32",
            "-q",
        ])
        .assert_success();
    }
}

#[test]
fn a_huge_table_or_candidate_count_is_refused_up_front() {
    let dir = tempdir();
    let input = fixture("gmsh/lshape.vtk");
    let png = dir.path().join("x.png");
    let r = tetkit([
        "render",
        input.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--table",
        "4096x4096",
    ]);
    r.assert_failure(&["--table", "4096x4096", "table entries, at most"]);
    assert!(!png.exists());
    tetkit([
        "render",
        input.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--table",
        "512x128",
        "--size",
        "16x16",
        "-q",
    ])
    .assert_success();

    let (split, tree) = (dir.path().join("s.vtu"), dir.path().join("t.vtu"));
    for n in ["1000000000", "0"] {
        let r = tetkit([
            "partition",
            input.to_str().unwrap(),
            "-o",
            split.to_str().unwrap(),
            "--tree",
            tree.to_str().unwrap(),
            "--candidates",
            n,
        ]);
        r.assert_failure(&["--candidates", n, "between 1 and 4096"]);
        assert!(!split.exists() && !tree.exists());
    }
}

#[test]
fn too_many_rays_are_refused_not_silently_cut() {
    let input = fixture("gmsh/lshape.vtk");
    for n in ["1000000000000", "0"] {
        tetkit([
            "check-order",
            input.to_str().unwrap(),
            "--method",
            "kd",
            "--rays",
            n,
        ])
        .assert_failure(&["--rays", n, "between 1 and 67108864"]);
    }
    tetkit([
        "check-order",
        input.to_str().unwrap(),
        "--method",
        "kd",
        "--rays",
        "100",
    ])
    .assert_success();
}

/// Options a new user tried that were quietly ignored or answered oddly: `--orbit-step`
/// without `--orbit` (ignored), `probe --points ""` (an empty CSV, exit 0), a focal point near
/// f64's range (reported as a NaN view-up "parallel to the view direction"), and a missing
/// output folder for `partition --tree` (the I/O error printed twice).
#[test]
fn odd_options_are_answered_plainly() {
    let dir = tempdir();
    let input = fixture("tetgen/torus.1.ele");
    let png = dir.path().join("x.png");
    let run = |extra: &[&str]| {
        let mut args: Vec<std::ffi::OsString> = vec![
            "render".into(),
            input.clone().into(),
            "-o".into(),
            png.clone().into(),
        ];
        args.extend(extra.iter().map(std::ffi::OsString::from));
        tetkit(args)
    };
    run(&["--orbit-step", "10"]).assert_failure(&["--orbit <N>"]);
    run(&["--focal", "1e308,1e308,1e308"]).assert_failure(&["no finite view direction", "--focal"]);
    assert!(!png.exists());
    tetkit([
        "probe".as_ref(),
        input.as_os_str(),
        "--points".as_ref(),
        "".as_ref(),
    ])
    .assert_failure(&["--points", "no points given"]);
    let out = dir.path().join("p.vtu");
    let tree = dir.path().join("nodir").join("t.vtu");
    let r = tetkit([
        "partition".as_ref(),
        input.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--tree".as_ref(),
        tree.as_os_str(),
    ]);
    r.assert_failure(&["nodir", "No such file or directory"]);
    assert_eq!(
        r.stderr.matches("No such file or directory").count(),
        1,
        "{}",
        r.stderr
    );
    assert!(!out.exists());
}
