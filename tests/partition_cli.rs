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
