//! Hostile TetGen files: each is refused with an error naming the file and the line, without a
//! panic and without allocating from a count the file cannot back.

mod legacy_common;

use formats::{FormatError, Place};
use legacy_common::*;
use std::path::{Path, PathBuf};

const NODE: &str = "# four points\n4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
const ELE: &str = "1 4 0\n1 1 2 3 4\n";

/// Writes `name.1.*` files into `dir` and reads the mesh through its `.ele`.
fn read(dir: &Path, files: &[(&str, &str)]) -> Result<formats::Grid, FormatError> {
    for (ext, text) in files {
        std::fs::write(dir.join(format!("m.1.{ext}")), text).unwrap();
    }
    formats::read(&dir.join("m.1.ele"))
}

/// Refused in `m.1.{ext}` at `line`, with `words` in the message.
fn refused(files: &[(&str, &str)], ext: &str, line: usize, words: &str) {
    let dir = tempfile::tempdir().unwrap();
    let e = match read(dir.path(), files) {
        Ok(_) => panic!("accepted {files:?}"),
        Err(e) => e,
    };
    let want: PathBuf = dir.path().join(format!("m.1.{ext}"));
    assert_eq!(e.file.as_deref(), Some(want.as_path()), "{e}");
    assert_eq!(e.place, Place::Line(line), "{e}");
    assert!(e.message.contains(words), "'{e}' lacks '{words}'");
}

#[test]
fn the_good_case_reads() {
    let dir = tempfile::tempdir().unwrap();
    let g = read(dir.path(), &[("node", NODE), ("ele", ELE)]).unwrap();
    assert_eq!((g.num_points(), g.num_cells()), (4, 1));
    assert_eq!(g.cells.cell(0), [0, 1, 2, 3]);
}

#[test]
fn counts_and_headers() {
    refused(
        &[("node", "1099511627776 3 0 0\n1 0 0 0\n"), ("ele", ELE)],
        "node",
        2,
        "end of file",
    );
    refused(
        &[("node", "-4 3 0 0\n"), ("ele", ELE)],
        "node",
        1,
        "must not be negative",
    );
    refused(
        &[("node", "4 2 0 0\n"), ("ele", ELE)],
        "node",
        1,
        "dimension 2",
    );
    refused(
        &[("node", "4 3 1099511627776 0\n1 0 0 0\n"), ("ele", ELE)],
        "node",
        1,
        "cannot fit",
    );
    refused(
        &[("node", "4 3 0 2\n"), ("ele", ELE)],
        "node",
        1,
        "must be 0 or 1",
    );
    refused(
        &[("node", NODE), ("ele", "1 7 0\n")],
        "ele",
        1,
        "must be 4 or 10",
    );
    refused(
        &[("node", NODE), ("ele", "1099511627776 4 0\n1 1 2 3 4\n")],
        "ele",
        2,
        "end of file",
    );
    refused(
        &[("node", NODE), ("ele", "1 4 99999999999999\n")],
        "ele",
        1,
        "cannot fit",
    );
    refused(
        &[("node", NODE), ("ele", "x 4 0\n")],
        "ele",
        1,
        "not an integer",
    );
}

#[test]
fn records() {
    let node = |body: &str| format!("4 3 0 0\n{body}");
    refused(
        &[
            ("node", &node("1 0 0 0\n2 1 0 0\n3 0 nan 0\n4 0 0 1\n")),
            ("ele", ELE),
        ],
        "node",
        4,
        "not finite",
    );
    refused(
        &[
            ("node", &node("1 0 0 0\n2 1 0 0\n3 0 1e999 0\n4 0 0 1\n")),
            ("ele", ELE),
        ],
        "node",
        4,
        "not finite",
    );
    refused(
        &[("node", &node("1 0 0 0\n2 1 zero 0\n")), ("ele", ELE)],
        "node",
        3,
        "not a number",
    );
    refused(
        &[("node", &node("1 0 0 0\n3 1 0 0\n")), ("ele", ELE)],
        "node",
        3,
        "consecutive",
    );
    refused(
        &[("node", &node("5 0 0 0\n")), ("ele", ELE)],
        "node",
        2,
        "from 0 or 1",
    );
    refused(
        &[("node", &node("1 0 0 0 7\n")), ("ele", ELE)],
        "node",
        2,
        "5 fields, expected 4",
    );
    refused(
        &[("node", &format!("{NODE}5 1 1 1\n")), ("ele", ELE)],
        "node",
        7,
        "more lines",
    );
    refused(
        &[("node", NODE), ("ele", "1 4 0\n1 1 2 3 5\n")],
        "ele",
        2,
        "node number 5 is out of range (there are 4 nodes, numbered 1 to 4)",
    );
    refused(
        &[("node", NODE), ("ele", "1 4 0\n1 0 2 3 4\n")],
        "ele",
        2,
        "node number 0 is out of range (there are 4 nodes, numbered 1 to 4)",
    );
    refused(
        &[
            ("node", NODE),
            ("ele", "1 4 0\n1 1 2 3 -9223372036854775808\n"),
        ],
        "ele",
        2,
        "out of range",
    );
    refused(
        &[("node", NODE), ("ele", "1 4 1\n1 1 2 3 4 abc\n")],
        "ele",
        2,
        "not a number",
    );
    refused(
        &[("node", NODE), ("ele", ELE), ("face", "1 1\n1 1 2 3\n")],
        "face",
        2,
        "expected 5",
    );
    refused(
        &[("node", NODE), ("ele", ELE), ("face", "1 0\n1 1 2 9\n")],
        "face",
        2,
        "out of range",
    );
    refused(
        &[("node", NODE), ("ele", ELE), ("neigh", "2 4\n")],
        "neigh",
        1,
        "the .ele file has 1",
    );
    refused(
        &[
            ("node", NODE),
            ("ele", ELE),
            ("neigh", "1 4\n1 -1 -1 5 -1\n"),
        ],
        "neigh",
        2,
        "neither -1",
    );
}

#[test]
fn tabs_comments_and_zero_based_numbering_are_fine() {
    let node = "# c\n\t4\t3\t1\t1 # header\n\n0\t0 0 0\t0.5\t1\n1 1 0 0 1.5 0 # x\n2 0 1 0 2.5 0\n3 0 0 1 3.5 2\n";
    let ele = "1 4 1\n# body\n0 0 1 2 3 7\n";
    let dir = tempfile::tempdir().unwrap();
    let g = read(dir.path(), &[("node", node), ("ele", ele)]).unwrap();
    assert_eq!(g.cells.cell(0), [0, 1, 2, 3]);
    assert_eq!(
        g.point_data
            .get("node_attribute_0")
            .unwrap()
            .data
            .to_f64_vec(),
        [0.5, 1.5, 2.5, 3.5]
    );
    assert_eq!(
        g.point_data
            .get("boundary_marker")
            .unwrap()
            .data
            .to_f64_vec(),
        [1.0, 0.0, 0.0, 2.0]
    );
    assert_eq!(g.cell_data.get("region").unwrap().data.to_f64_vec(), [7.0]);
}

#[test]
fn missing_files() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("m.1.ele"), ELE).unwrap();
    let e = formats::read(&dir.path().join("m.1.ele")).unwrap_err();
    assert_eq!(
        e.file.as_deref(),
        Some(dir.path().join("m.1.node").as_path())
    );
    let out = tetkit(&["info", path_str(&dir.path().join("m.1.ele"))]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("m.1.node"));
}

/// Deterministic mutations of the sphere fixture: nothing may panic (cargo-fuzz runs the same
/// parser longer: fuzz/fuzz_targets/tetgen.rs).
#[test]
fn mutated_fixture_never_panics() {
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut rnd = move |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n.max(1) as u64) as usize
    };
    let src = root().join("fixtures/tetgen");
    let node = std::fs::read(src.join("sphere.1.node")).unwrap();
    let ele = std::fs::read(src.join("sphere.1.ele")).unwrap();
    let face = std::fs::read(src.join("sphere.1.face")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for round in 0..120 {
        let mut files = [node.clone(), ele.clone(), face.clone()];
        let which = round % 3;
        let b = &mut files[which];
        for _ in 0..1 + rnd(3) {
            let i = rnd(b.len());
            match rnd(4) {
                0 => b[i] = rnd(256) as u8,
                1 => b[i] = b"0123456789-#\t\n"[rnd(14)],
                2 => b.truncate(i),
                _ => {
                    let j = (i + rnd(40)).min(b.len());
                    b.drain(i..j);
                }
            }
            if b.is_empty() {
                break;
            }
        }
        for (ext, bytes) in ["node", "ele", "face"].iter().zip(&files) {
            std::fs::write(dir.path().join(format!("s.{ext}")), bytes).unwrap();
        }
        let _ = formats::read(&dir.path().join("s.ele"));
    }
}
