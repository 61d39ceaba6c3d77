//! Hostile .vtu input: every case is an error naming the place (never a panic, never an
//! allocation sized by an unchecked header).

mod vtu_support;

use formats::{read_bytes, Format};
use vtu_support::fixtures;

fn fixture(name: &str) -> Vec<u8> {
    std::fs::read(fixtures().join(name)).unwrap()
}

fn err(bytes: &[u8]) -> String {
    match read_bytes(bytes, Format::Vtu) {
        Ok(_) => panic!("accepted hostile input"),
        Err(e) => e.to_string(),
    }
}

/// A one-tet file with appended raw data built by hand: `arrays` are (xml attributes, bytes
/// including the size header) in order; offsets are filled in.
fn handmade(header: &str, piece: &str, arrays: &[(&str, &str, Vec<u8>)]) -> Vec<u8> {
    let mut xml = format!(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\" {header}>\n<UnstructuredGrid>\n<Piece {piece}>\n"
    );
    let mut data = Vec::new();
    for (section, attrs, bytes) in arrays {
        xml.push_str(&format!(
            "<{section}><DataArray {attrs} format=\"appended\" offset=\"{}\"/></{section}>\n",
            data.len()
        ));
        data.extend_from_slice(bytes);
    }
    xml.push_str("</Piece>\n</UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_");
    let mut out = xml.into_bytes();
    out.extend_from_slice(&data);
    out.extend_from_slice(b"\n</AppendedData>\n</VTKFile>\n");
    out
}

fn raw<T: bytemuck::Pod>(v: &[T]) -> Vec<u8> {
    let b: &[u8] = bytemuck::cast_slice(v);
    let mut out = (b.len() as u64).to_le_bytes().to_vec();
    out.extend_from_slice(b);
    out
}

fn one_tet(points: Vec<u8>, conn: Vec<u8>, np: &str) -> Vec<u8> {
    handmade(
        "header_type=\"UInt64\"",
        &format!("NumberOfPoints=\"{np}\" NumberOfCells=\"1\""),
        &[
            (
                "Points",
                "type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"",
                points,
            ),
            ("Cells", "type=\"Int64\" Name=\"connectivity\"", conn),
            ("Cells", "type=\"Int64\" Name=\"offsets\"", raw(&[4i64])),
            ("Cells", "type=\"UInt8\" Name=\"types\"", raw(&[10u8])),
        ],
    )
}

const TET: [f64; 12] = [0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1.];

#[test]
fn the_handmade_file_itself_is_fine() {
    let g = read_bytes(&one_tet(raw(&TET), raw(&[0i64, 1, 2, 3]), "4"), Format::Vtu).unwrap();
    assert_eq!((g.num_points(), g.num_cells()), (4, 1));
}

#[test]
fn truncated_files_are_errors() {
    for name in [
        "tet_appended_none_h64_le.vtu",
        "tet_appended_zlib_h32_be.vtu",
        "tet_appended64_lzma_h64_le.vtu",
        "tet_binary_lz4_h32_le.vtu",
        "tet_ascii.vtu",
    ] {
        let b = fixture(name);
        let mut cut = 0;
        while cut < b.len() - 12 {
            let e = err(&b[..cut]);
            assert!(e.contains("byte"), "{name} cut at {cut}: {e}");
            cut += 37;
        }
    }
}

#[test]
fn wrong_offsets_are_errors() {
    let b = String::from_utf8_lossy(&fixture("tet_appended_none_h64_le.vtu")).into_owned();
    // Past the end of the appended block.
    let e = err(b
        .replacen("offset=\"0\"", "offset=\"99999999\"", 1)
        .as_bytes());
    assert!(e.contains("past the end"), "{e}");
    // Off by a few bytes: the size header is garbage, and says so.
    let i = b.find("offset=\"").unwrap();
    let j = b[i + 8..].find('"').unwrap() + i + 8;
    let off: u64 = b[i + 8..j].trim().parse().unwrap();
    for delta in [1u64, 3, 8] {
        let bad = format!("{}offset=\"{}\"{}", &b[..i], off + delta, &b[j + 1..]);
        let e = err(bad.as_bytes());
        assert!(e.contains("array '"), "{e}");
    }
}

#[test]
fn sizes_of_two_to_the_forty_are_refused_before_allocating() {
    let huge = 1u64 << 40;
    // A size header claiming 2^40 bytes.
    let mut p = huge.to_le_bytes().to_vec();
    p.extend_from_slice(bytemuck::cast_slice(&TET));
    let e = err(&one_tet(p, raw(&[0i64, 1, 2, 3]), "4"));
    assert!(e.contains("1099511627776") && e.contains("Points"), "{e}");
    // NumberOfPoints 2^40 with a matching size header.
    let mut p = (huge * 24).to_le_bytes().to_vec();
    p.extend_from_slice(bytemuck::cast_slice(&TET));
    let e = err(&one_tet(p, raw(&[0i64, 1, 2, 3]), &huge.to_string()));
    assert!(e.contains("byte"), "{e}");
    // A huge component count with a component name: no list of 2^40 names.
    let f = handmade(
        "header_type=\"UInt64\"",
        "NumberOfPoints=\"4\" NumberOfCells=\"0\"",
        &[
            ("Points", "type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"", raw(&TET)),
            ("PointData", "type=\"Float64\" Name=\"v\" NumberOfComponents=\"1099511627776\" ComponentName0=\"x\"", raw(&TET)),
        ],
    );
    assert!(err(&f).contains("1099511627776 components"));
    // NumberOfPoints that overflows tuples x components.
    let e = err(&one_tet(
        raw(&TET),
        raw(&[0i64, 1, 2, 3]),
        "18446744073709551615",
    ));
    assert!(e.contains("too large") || e.contains("overflow"), "{e}");
    // A last offset of 2^40 sizes connectivity: refused against the bytes present.
    let f = handmade(
        "header_type=\"UInt64\"",
        "NumberOfPoints=\"4\" NumberOfCells=\"1\"",
        &[
            (
                "Points",
                "type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"",
                raw(&TET),
            ),
            (
                "Cells",
                "type=\"Int64\" Name=\"connectivity\"",
                raw(&[0i64, 1, 2, 3]),
            ),
            (
                "Cells",
                "type=\"Int64\" Name=\"offsets\"",
                raw(&[huge as i64]),
            ),
            ("Cells", "type=\"UInt8\" Name=\"types\"", raw(&[10u8])),
        ],
    );
    let e = err(&f);
    assert!(e.contains("connectivity"), "{e}");
    // A compression header claiming 2^40 blocks.
    let mut c = Vec::new();
    for v in [huge, 32768, 0] {
        c.extend_from_slice(&v.to_le_bytes());
    }
    let f = handmade(
        "header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\"",
        "NumberOfPoints=\"4\" NumberOfCells=\"0\"",
        &[(
            "Points",
            "type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"",
            c,
        )],
    );
    let e = err(&f);
    assert!(e.contains("header of 1099511627776 values"), "{e}");
}

fn zlib(data: &[u8]) -> Vec<u8> {
    use std::io::Write;
    let mut e = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::best());
    e.write_all(data).unwrap();
    e.finish().unwrap()
}

fn compressed_points(block: Vec<u8>, declared: u64) -> Vec<u8> {
    let mut c = Vec::new();
    for v in [1, declared, declared, block.len() as u64] {
        c.extend_from_slice(&v.to_le_bytes());
    }
    c.extend_from_slice(&block);
    c
}

#[test]
fn a_zlib_bomb_is_refused() {
    // 64 MiB of zeros in a ~64 KiB stream, declared as the 96 bytes 4 points need: inflating
    // stops at the declared size.
    let bomb = zlib(&vec![0u8; 64 << 20]);
    let f = handmade(
        "header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\"",
        "NumberOfPoints=\"4\" NumberOfCells=\"0\"",
        &[(
            "Points",
            "type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"",
            compressed_points(bomb.clone(), 96),
        )],
    );
    let e = err(&f);
    assert!(e.contains("more than the 96 bytes"), "{e}");
    // The same stream declared at its true size, with NumberOfPoints to match: the ratio is
    // refused before anything is allocated.
    let np = (64u64 << 20) / 24;
    let f = handmade(
        "header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\"",
        &format!("NumberOfPoints=\"{np}\" NumberOfCells=\"0\""),
        &[(
            "Points",
            "type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"",
            compressed_points(zlib(&vec![0u8; 1 << 20]), 64 << 20),
        )],
    );
    let e = err(&f);
    assert!(e.contains("decompression bomb"), "{e}");
    // A block that inflates to less than declared.
    let f = handmade(
        "header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\"",
        "NumberOfPoints=\"4\" NumberOfCells=\"0\"",
        &[(
            "Points",
            "type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"",
            compressed_points(zlib(&[0u8; 50]), 96),
        )],
    );
    let e = err(&f);
    assert!(
        e.contains("inflates to 50 bytes, the header declares 96"),
        "{e}"
    );
}

#[test]
fn bad_base64_names_the_byte() {
    let b = String::from_utf8_lossy(&fixture("tet_binary_none_h64_le.vtu")).into_owned();
    let i = b.find("format=\"binary\"").unwrap();
    let j = b[i..].find('>').unwrap() + i + 1;
    let k = b[j..].find(|c: char| c.is_ascii_alphanumeric()).unwrap() + j + 2;
    let bad = format!("{}!{}", &b[..k], &b[k + 1..]);
    let e = err(bad.as_bytes());
    assert!(
        e.contains(&format!("byte {k}")) && e.contains("not base64"),
        "{e}"
    );
}

#[test]
fn nan_coordinates_are_refused() {
    let mut p = TET;
    p[4] = f64::NAN;
    let e = err(&one_tet(raw(&p), raw(&[0i64, 1, 2, 3]), "4"));
    assert!(e.contains("non-finite"), "{e}");
    let b = String::from_utf8_lossy(&fixture("polyhedra_ascii.vtu")).into_owned();
    let i = b.find("<Points>").unwrap();
    let j = b[i..].find('>').unwrap() + i;
    let k = b[j + 1..].find('>').unwrap() + j + 2;
    let bad = format!(
        "{} -Infinity {}",
        &b[..k],
        b[k..].trim_start().split_once(' ').unwrap().1
    );
    let e = err(bad.as_bytes());
    assert!(e.contains("non-finite"), "{e}");
}

#[test]
fn connectivity_out_of_range_is_refused() {
    let e = err(&one_tet(raw(&TET), raw(&[0i64, 1, 2, 4]), "4"));
    assert!(e.contains("point id 4"), "{e}");
    let e = err(&one_tet(raw(&TET), raw(&[0i64, -1, 2, 3]), "4"));
    assert!(e.contains("point id -1"), "{e}");
    // UInt64 ids that do not fit i64.
    let f = handmade(
        "header_type=\"UInt64\"",
        "NumberOfPoints=\"4\" NumberOfCells=\"1\"",
        &[
            (
                "Points",
                "type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"",
                raw(&TET),
            ),
            (
                "Cells",
                "type=\"UInt64\" Name=\"connectivity\"",
                raw(&[0u64, 1, 2, u64::MAX]),
            ),
            ("Cells", "type=\"Int64\" Name=\"offsets\"", raw(&[4i64])),
            ("Cells", "type=\"UInt8\" Name=\"types\"", raw(&[10u8])),
        ],
    );
    assert!(err(&f).contains("connectivity"));
}

#[test]
fn a_doctype_is_refused() {
    let b = String::from_utf8_lossy(&fixture("polyhedra_ascii.vtu")).into_owned();
    let evil = b.replacen(
        "<VTKFile",
        "<!DOCTYPE VTKFile [<!ENTITY a \"aaaaaaaaaa\"><!ENTITY b \"&a;&a;&a;&a;&a;&a;\">]>\n<VTKFile",
        1,
    );
    assert!(err(evil.as_bytes()).contains("DOCTYPE"));
}

#[test]
fn pvtu_with_a_missing_piece_names_it() {
    let dir = tempfile::tempdir().unwrap();
    let src = fixtures();
    std::fs::copy(src.join("tet_parallel.pvtu"), dir.path().join("p.pvtu")).unwrap();
    let e = formats::read(&dir.path().join("p.pvtu"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("p.pvtu") && e.contains("tet_parallel_0.vtu") && e.contains("does not exist"),
        "{e}"
    );
}

/// Cheap deterministic mutation fuzzing: flipped bytes anywhere must give a result or an error,
/// never a panic.
#[test]
fn mutated_fixtures_never_panic() {
    let mut state = 0x2545F4914F6CDD1Du64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for name in [
        "tet_appended_zlib_h64_le.vtu",
        "tet_appended64_none_h32_be.vtu",
        "tet_binary_lz4_h64_be.vtu",
        "tet_appended_lzma_h32_le.vtu",
        "tet_ascii.vtu",
        "polyhedra_binary_zlib.vtu",
    ] {
        let b = fixture(name);
        for _ in 0..150 {
            let mut m = b.clone();
            for _ in 0..1 + next() % 4 {
                let i = (next() % m.len() as u64) as usize;
                m[i] = next() as u8;
            }
            let _ = read_bytes(&m, Format::Vtu);
        }
    }
}
