//! Hostile legacy files: each is refused with an error that names the place (line in ASCII
//! files, byte offset in binary ones), quickly, without a panic and without allocating from a
//! declared size the file cannot back.

mod legacy_common;

use formats::{Format, FormatError, Place};
use legacy_common::*;

const ASCII51: &str = "# vtk DataFile Version 5.1\ntitle\nASCII\nDATASET UNSTRUCTURED_GRID\n";
const ASCII42: &str = "# vtk DataFile Version 4.2\ntitle\nASCII\nDATASET UNSTRUCTURED_GRID\n";
const TET_POINTS: &str = "POINTS 4 float\n0 0 0 1 0 0 0 1 0 0 0 1\n";

fn err(text: &[u8]) -> FormatError {
    match formats::read_bytes(text, Format::Legacy) {
        Ok(_) => panic!("accepted:\n{}", String::from_utf8_lossy(text)),
        Err(e) => e,
    }
}

/// Refused at `line`, with `words` in the message.
fn refused_at(text: &str, line: usize, words: &str) {
    let e = err(text.as_bytes());
    assert_eq!(e.place, Place::Line(line), "{e} (for:\n{text})");
    assert!(e.message.contains(words), "'{e}' lacks '{words}'");
}

fn be_i32(v: &[i32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_be_bytes()).collect()
}

#[test]
fn huge_and_negative_counts() {
    let t = format!("{ASCII51}POINTS 1099511627776 float\n0 0 0\n");
    refused_at(&t, 5, "declares 3298534883328 values");
    refused_at(&format!("{ASCII51}POINTS -5 float\n"), 5, "non-negative");
    refused_at(
        &format!("{ASCII51}POINTS 18446744073709551615 float\n"),
        5,
        "overflow",
    );
    let t = format!("{ASCII42}{TET_POINTS}CELLS 1099511627776 5\n4 0 1 2 3\n");
    refused_at(&t, 7, "1099511627776 cells");
    let t = format!("{ASCII51}{TET_POINTS}CELLS 2 1099511627776\nOFFSETS vtktypeint64\n0 4\nCONNECTIVITY vtktypeint64\n0 1 2 3\n");
    refused_at(&t, 10, "declares 1099511627776 values");
    let t = format!("{ASCII51}FIELD FieldData 1\nx 1099511627776 1099511627776 double\n1\n");
    refused_at(&t, 6, "overflows");
    let t = format!("{ASCII51}FIELD FieldData 1099511627776\nx 1 1 double\n1\n");
    assert!(matches!(err(t.as_bytes()).place, Place::Line(_)));
    let t = format!("{ASCII51}{TET_POINTS}POINT_DATA 4\nLOOKUP_TABLE t 1099511627776\n1 0 0 1\n");
    refused_at(&t, 8, "declares 4398046511104 values");
    let t = format!("{ASCII51}{TET_POINTS}CELL_TYPES 1099511627776\n10\n");
    refused_at(&t, 7, "declares 1099511627776 values");
}

#[test]
fn binary_sizes_are_checked_against_the_bytes() {
    let head = b"# vtk DataFile Version 5.1\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\n".to_vec();
    let mut t = head.clone();
    t.extend_from_slice(b"POINTS 1099511627776 double\n");
    t.extend_from_slice(&[0u8; 48]);
    let e = err(&t);
    assert!(matches!(e.place, Place::Byte(_)), "{e}");
    assert!(e.message.contains("remain"), "{e}");
    // A string whose length prefix says 2^61 bytes.
    let mut t = head.clone();
    t.extend_from_slice(b"FIELD FieldData 1\ns 1 1 string\n");
    t.extend_from_slice(&(1u64 << 61).to_be_bytes());
    t.extend_from_slice(b"abc\n");
    let e = err(&t);
    assert!(matches!(e.place, Place::Byte(_)), "{e}");
    // 4.2 cells whose count runs past the block.
    let mut t =
        b"# vtk DataFile Version 4.2\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 float\n"
            .to_vec();
    t.extend_from_slice(&[0u8; 48]);
    t.extend_from_slice(b"\nCELLS 1 5\n");
    let at = t.len();
    t.extend_from_slice(&be_i32(&[40, 0, 1, 2, 3]));
    t.extend_from_slice(b"\nCELL_TYPES 1\n");
    t.extend_from_slice(&be_i32(&[10]));
    let e = err(&t);
    assert!(e.message.contains("declares 40 points"), "{e}");
    assert!(
        matches!(e.place, Place::Byte(b) if (b as usize) < at),
        "{e}"
    );
}

#[test]
fn every_truncation_of_a_binary_file_is_refused_or_whole() {
    for name in [
        "handmade_42_binary.vtk",
        "mixed_51_binary.vtk",
        "mixed_42_binary.vtk",
    ] {
        let full = std::fs::read(root().join("fixtures/legacy").join(name)).unwrap();
        let whole = formats::read_bytes(&full, Format::Legacy).unwrap();
        let step = (full.len() / 400).max(1);
        for cut in (0..full.len()).step_by(step) {
            let part = &full[..cut];
            match formats::read_bytes(part, Format::Legacy) {
                Err(e) => assert!(!e.message.is_empty()),
                // Cutting trailing newlines or whole optional sections may leave a valid file,
                // but never one that claims more than the original.
                Ok(g) => assert!(
                    g.num_cells() <= whole.num_cells() && g.num_points() <= whole.num_points()
                ),
            }
        }
    }
}

#[test]
fn nan_points_and_out_of_range_ids_name_their_place() {
    let t = format!("{ASCII51}POINTS 4 float\n0 0 0 1 0 0\n0 nan 0 0 0 1\n");
    refused_at(&t, 7, "not finite");
    let t = format!("{ASCII51}{TET_POINTS}CELLS 2 4\nOFFSETS vtktypeint64\n0 4\nCONNECTIVITY vtktypeint64\n0 1\n2 7\nCELL_TYPES 1\n10\n");
    refused_at(&t, 12, "point id 7");
    let t = format!("{ASCII42}{TET_POINTS}CELLS 1 5\n4 0 1 -2 3\nCELL_TYPES 1\n10\n");
    refused_at(&t, 8, "point id -2");
    // Binary: the byte offset of the bad coordinate.
    let mut t =
        b"# vtk DataFile Version 5.1\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 2 double\n"
            .to_vec();
    let start = t.len();
    for v in [0.0f64, 1.0, 2.0, 3.0, f64::INFINITY, 5.0] {
        t.extend_from_slice(&v.to_be_bytes());
    }
    let e = err(&t);
    assert_eq!(e.place, Place::Byte((start + 4 * 8) as u64), "{e}");
}

#[test]
fn broken_structure() {
    let cells = |offsets: &str, conn: &str| {
        format!("{ASCII51}{TET_POINTS}CELLS 2 4\nOFFSETS vtktypeint64\n{offsets}\nCONNECTIVITY vtktypeint64\n{conn}\nCELL_TYPES 1\n10\n")
    };
    refused_at(&cells("1 4", "0 1 2 3"), 7, "OFFSETS starts at 1");
    refused_at(&cells("0 3", "0 1 2 3"), 7, "OFFSETS end at 3");
    let t = format!("{ASCII51}{TET_POINTS}CELLS 3 4\nOFFSETS vtktypeint64\n0 4 2\nCONNECTIVITY vtktypeint64\n0 1 2 3\nCELL_TYPES 2\n10 10\n");
    refused_at(&t, 7, "decrease");
    let t = format!("{ASCII51}{TET_POINTS}CELLS 2 4\nOFFSETS double\n0 4\n");
    refused_at(&t, 8, "integer type");
    let t = format!("{ASCII42}{TET_POINTS}CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 2\n10 10\n");
    refused_at(&t, 9, "2 entries for 1 cells");
    let t = format!("{ASCII42}{TET_POINTS}CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n99\n");
    refused_at(&t, 10, "unknown type 99");
    let t = format!("{ASCII42}{TET_POINTS}CELLS 1 5\n4 0 1 2 3\n");
    assert!(err(t.as_bytes()).message.contains("no CELL_TYPES"));
    let t = format!("{ASCII42}{TET_POINTS}CELLS 1 5\n-4 0 1 2 3\nCELL_TYPES 1\n10\n");
    refused_at(&t, 7, "declares -4 points");
    let t = format!("{ASCII42}{TET_POINTS}CELLS 1 6\n5 9 3 0 1 2\nCELL_TYPES 1\n42\n");
    refused_at(&t, 7, "polyhedron cell 0");
    let t = format!("{ASCII42}{TET_POINTS}CELLS 1 6\n5 1 3 0 1 9\nCELL_TYPES 1\n42\n");
    refused_at(&t, 7, "point id 9");
}

#[test]
fn bad_keywords_types_and_headers() {
    refused_at(
        "# vtk DataFile Version 6.0\nt\nASCII\n",
        1,
        "newer than 5.1",
    );
    refused_at("# vtk DataFile Version x\nt\nASCII\n", 1, "MAJOR.MINOR");
    refused_at("hello\n", 1, "not a legacy VTK file");
    refused_at(
        "# vtk DataFile Version 4.2\nt\nTEXT\n",
        3,
        "ASCII or BINARY",
    );
    // Structured data sets are read, but need their DIMENSIONS.
    refused_at(
        "# vtk DataFile Version 4.2\nt\nASCII\nDATASET STRUCTURED_POINTS\n",
        4,
        "STRUCTURED_POINTS data set without DIMENSIONS",
    );
    refused_at(
        "# vtk DataFile Version 4.2\nt\nASCII\nDATASET UNIFORM_GRID\n",
        4,
        "'UNIFORM_GRID' is not supported",
    );
    // POLYDATA is read (surfaces of cutting bodies), but not with an unstructured grid's CELLS.
    refused_at(
        "# vtk DataFile Version 4.2\nt\nASCII\nDATASET POLYDATA\nPOINTS 1 float\n0 0 0\nCELLS 1 2\n1 0\n",
        7,
        "unknown keyword 'CELLS' in a POLYDATA",
    );
    refused_at(
        &format!("{ASCII51}POINTS 1 quaternion\n"),
        5,
        "unknown data type 'quaternion'",
    );
    refused_at(
        &format!("{ASCII51}POINTS 2 float\n0 0 0 1 x 0\n"),
        6,
        "value 4 of 6 is 'x'",
    );
    refused_at(
        &format!("{ASCII51}{TET_POINTS}WHATEVER 3\n"),
        7,
        "unknown keyword 'WHATEVER'",
    );
    refused_at(
        &format!("{ASCII51}{TET_POINTS}POINT_DATA 5\n"),
        7,
        "does not match the 4 points",
    );
    refused_at(
        &format!("{ASCII51}{TET_POINTS}POINT_DATA 4\nSCALARS s float 5\n"),
        8,
        "1..4",
    );
    refused_at(
        &format!("{ASCII51}{TET_POINTS}POINT_DATA 4\nSCALARS s float\n1 2 3 4\n"),
        9,
        "LOOKUP_TABLE",
    );
    refused_at(
        &format!("{ASCII51}{TET_POINTS}POINT_DATA 4\nVECTORS v float\n1 2 3 4\n"),
        8,
        "declares 12 values",
    );
    refused_at(
        &format!("{ASCII51}{TET_POINTS}POINT_DATA 4\nTEXTURE_COORDINATES t 7 float\n"),
        8,
        "1..3",
    );
    refused_at(&format!("{ASCII51}{TET_POINTS}POINT_DATA 4\nSCALARS s int\nLOOKUP_TABLE default\n1 2 3 99999999999\n"), 10, "declared type");
    let t = format!("{ASCII51}{TET_POINTS}POINT_DATA 4\nSCALARS s int\nLOOKUP_TABLE default\n1 2 3 4\nMETADATA\nGARBAGE\n");
    refused_at(&t, 12, "METADATA");
    refused_at(
        &format!("{ASCII51}FIELD FieldData 1\nx 0 1 double\n"),
        6,
        "0 components",
    );
}

#[test]
fn errors_name_the_file_and_the_command_fails() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.vtk");
    std::fs::write(&path, format!("{ASCII51}POINTS 2 float\n0 0 0 1 x 0\n")).unwrap();
    let e = formats::read(&path).unwrap_err();
    assert_eq!(e.file.as_deref(), Some(path.as_path()));
    assert_eq!(e.place, Place::Line(6));
    let out = tetkit(&["info", path_str(&path)]);
    assert!(!out.status.success());
    let msg = String::from_utf8_lossy(&out.stderr);
    assert!(msg.contains("bad.vtk") && msg.contains("line 6"), "{msg}");
    assert!(!msg.contains("panicked"), "{msg}");
}

/// A small deterministic mutation fuzzer over the fixtures: flipped bytes, digits typed over
/// counts, cut and duplicated spans. Nothing may panic (cargo-fuzz runs the same reader longer:
/// fuzz/fuzz_targets/legacy.rs).
#[test]
fn mutated_fixtures_never_panic() {
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut rnd = move |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n.max(1) as u64) as usize
    };
    for path in legacy_fixtures() {
        let orig = std::fs::read(&path).unwrap();
        for _ in 0..150 {
            let mut b = orig.clone();
            for _ in 0..1 + rnd(4) {
                let i = rnd(b.len());
                match rnd(5) {
                    0 => b[i] = rnd(256) as u8,
                    1 => b[i] = b"0123456789-"[rnd(11)],
                    2 => b.truncate(i),
                    3 => {
                        let j = (i + rnd(64)).min(b.len());
                        let span = b[i..j].to_vec();
                        b.splice(i..i, span);
                    }
                    _ => {
                        let j = (i + rnd(16)).min(b.len());
                        b.drain(i..j);
                    }
                }
                if b.is_empty() {
                    break;
                }
            }
            let _ = formats::read_bytes(&b, Format::Legacy);
        }
    }
}
