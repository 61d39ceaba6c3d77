//! Truncated legacy files: a word or number cut by the end of the file is an unexpected end of file.

use super::read;
use crate::{FormatError, Place};

const BINARY: &[u8] = include_bytes!("../../../fixtures/legacy/mixed_42_binary.vtk");
const ASCII: &[u8] = include_bytes!("../../../fixtures/legacy/mixed_51_ascii.vtk");

/// `bytes` up to `keep` bytes into the first `needle` after `from`.
fn cut(bytes: &[u8], from: &[u8], needle: &[u8], keep: usize) -> Option<Vec<u8>> {
    let start = if from.is_empty() {
        0
    } else {
        bytes.windows(from.len()).position(|w| w == from)?
    };
    let at = start
        + bytes[start..]
            .windows(needle.len())
            .position(|w| w == needle)?;
    Some(bytes[..at + keep].to_vec())
}

/// The error reading `bytes`, or `None` when they read.
fn error(bytes: Option<Vec<u8>>) -> Option<FormatError> {
    read(&bytes?).err()
}

fn says(e: &Option<FormatError>, needle: &str, place: fn(&Place) -> bool) -> bool {
    e.as_ref()
        .is_some_and(|e| e.message.contains(needle) && place(&e.place))
}

fn byte(p: &Place) -> bool {
    matches!(p, Place::Byte(_))
}

fn line(p: &Place) -> bool {
    matches!(p, Place::Line(_))
}

#[test]
fn a_data_type_cut_by_the_end_is_an_end_of_file_not_an_unknown_type() {
    // The user's file: a FIELD array's `signed_char` cut to `signe`; here `unsigned_char`.
    let e = error(cut(BINARY, b"\nu8 1 56 ", b"unsigned_char", 5));
    assert!(
        says(
            &e,
            "unexpected end of file in 'unsig' while reading the data type of FIELD array 'u8'",
            byte
        ),
        "{e:?}"
    );
    let e = error(cut(ASCII, b"POINTS", b"float", 3));
    assert!(
        says(
            &e,
            "unexpected end of file in 'flo' while reading the data type",
            line
        ),
        "{e:?}"
    );
}

#[test]
fn a_keyword_cut_by_the_end_is_an_end_of_file() {
    let e = error(cut(BINARY, b"", b"\nCELL_TYPES", 8));
    assert!(
        says(
            &e,
            "unexpected end of file in 'CELL_TY' while reading a keyword",
            byte
        ),
        "{e:?}"
    );
    let e = error(cut(ASCII, b"", b"\nPOINT_DATA", 6));
    assert!(
        says(&e, "unexpected end of file in 'POINT' while reading", line),
        "{e:?}"
    );
    // Inside the attributes (their own keyword loop) and the METADATA look-ahead.
    let e = error(cut(BINARY, b"POINT_DATA", b"\nVECTORS", 4));
    assert!(
        says(&e, "unexpected end of file in 'VEC' while reading", byte),
        "{e:?}"
    );
    let e = error(cut(ASCII, b"", b"\nMETADATA", 5));
    assert!(says(&e, "in 'META' while reading METADATA", line), "{e:?}");
    // A count: `POINTS 56` cut to `POINTS 5`.
    let e = error(cut(BINARY, b"", b"POINTS 56", 8));
    assert!(says(&e, "in '5' while reading", byte), "{e:?}");
}

#[test]
fn ascii_values_cut_by_the_end_are_an_end_of_file_but_the_last_needs_no_newline() {
    let whole = b"# vtk DataFile Version 4.2\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n\
POINTS 4 float\n0 0 0\n10 0 0\n0 10 0\n0 0 10\nCELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10";
    assert!(read(whole).is_ok());
    let e = error(cut(whole, b"", b"10 0\n0 0 10", 1));
    let want = "unexpected end of file in '1' while reading POINTS, value 7 of 12";
    assert!(says(&e, want, line), "{e:?}");
}

#[test]
fn every_truncation_of_a_binary_file_is_named_a_truncation() {
    let small = include_bytes!("../../../fixtures/legacy/handmade_42_binary.vtk");
    for n in 0..small.len() {
        match read(&small[..n]) {
            // Cut between two sections (before or after the newline that ends one), the file
            // is a whole smaller one.
            Ok(_) => assert!(
                small[n - 1] == b'\n' || small[n] == b'\n',
                "cut at {n} reads"
            ),
            Err(e) => assert!(
                [
                    "end of file",
                    "end of the file",
                    "truncated",
                    "remain",
                    "empty"
                ]
                .iter()
                .any(|w| e.message.contains(w)),
                "cut at {n}: {e:?}"
            ),
        }
    }
}

/// Files cut anywhere inside a METADATA INFORMATION block (VTK writes one after most arrays)
/// are cut files: they used to read as whole ones, with the points, cells or arrays after the
/// cut silently missing (VTK's own 4.2 file cut inside `NAME L2_NORM_RANGE` read as 0 points
/// and 0 cells). Every cut from the `INFORMATION` line to the block's closing empty line is an
/// error naming the block; a cut after that empty line is not this error.
#[test]
fn a_file_cut_inside_an_information_block_is_an_error() {
    for whole in [ASCII, BINARY] {
        let Some(begin) = whole.windows(12).position(|w| w == b"INFORMATION ") else {
            panic!("no INFORMATION block in the fixture");
        };
        let Some(len) = whole[begin..].windows(2).position(|w| w == b"\n\n") else {
            panic!("no end to the INFORMATION block");
        };
        // From inside the `INFORMATION` word to just before the closing empty line.
        for keep in begin + 3..begin + len + 1 {
            let e = read(&whole[..keep]).err();
            assert!(
                e.as_ref()
                    .is_some_and(|e| e.message.contains("unexpected end of file")),
                "cut at {keep}: {e:?}"
            );
        }
    }
}

/// An INFORMATION block that declares more keys than it holds and has no closing empty line
/// (hand-written files): the array after it is read, with a warning, where VTK drops it.
#[test]
fn a_miscounted_information_block_does_not_swallow_the_next_array() {
    let text = b"# vtk DataFile Version 5.1\nm\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 float\n0 0 0 1 0 0 0 1 0 0 0 1\nCELLS 2 4\nOFFSETS vtktypeint64\n0 4\nCONNECTIVITY vtktypeint64\n0 1 2 3\nCELL_TYPES 1\n10\nPOINT_DATA 4\nSCALARS s float 1\nLOOKUP_TABLE default\n1 2 3 4\nMETADATA\nINFORMATION 3\nNAME L2_NORM_RANGE LOCATION vtkDataArray\nDATA 2 1 4\nSCALARS t float 1\nLOOKUP_TABLE default\n5 6 7 8\n";
    let g = read(text);
    assert!(g.is_ok(), "{:?}", g.err());
    let Ok(g) = g else { return };
    let names: Vec<&str> = g
        .point_data
        .arrays
        .iter()
        .map(|a| a.name.as_str())
        .collect();
    assert_eq!(names, ["s", "t"]);
}
