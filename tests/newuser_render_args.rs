//! A mistyped `--tf-nodes` (an extra few zeros) made `render` and `tradeoff` try to allocate
//! tens of gigabytes and abort ("memory allocation of 24000000000 bytes failed", a core dump).
//! It is now refused on the command line with the range it takes, and nothing is written.

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
