//! `partition --leaves 4` on a small structured hex mesh (as Gmsh writes with `Recombine`) came
//! back with one leaf and exit 0: the paper's search finds no plane within its default
//! `--phi`/`--eps` there, and only the table's leaf count said so. It now warns, naming the
//! options that find more, and `--strategy cost` gives the leaves asked for.

mod common;

use common::{fixture, tempdir, tetkit};

#[test]
fn fewer_leaves_than_asked_for_is_said_with_a_way_out() {
    let dir = tempdir();
    let input = fixture("gmsh/extruded.vtk");
    let (split, tree) = (dir.path().join("split.vtu"), dir.path().join("tree.vtu"));
    let run = |strategy: &str, leaves: &str| {
        let r = tetkit([
            "partition",
            input.to_str().unwrap(),
            "-o",
            split.to_str().unwrap(),
            "--tree",
            tree.to_str().unwrap(),
            "--leaves",
            leaves,
            "--strategy",
            strategy,
            "--json",
        ]);
        r.assert_success();
        let report: serde_json::Value = serde_json::from_str(&r.stdout_str()).unwrap();
        (report["leaves"].as_u64().unwrap(), r.stderr.clone())
    };
    let (got, err) = run("paper", "64");
    assert!(got < 64, "{got}");
    assert!(
        err.contains("warning")
            && err.contains(&format!("{got} of the 64 leaves"))
            && err.contains("--strategy cost"),
        "{err}"
    );
    let (got, err) = run("cost", "2");
    assert_eq!(got, 2);
    assert!(!err.contains("warning"), "{err}");
}
