//! read -> write in every encoding and compressor -> read gives the bit-identical grid, for the
//! VTK fixtures and for random grids (proptest); the .pvtu writer writes all files or none.

mod vtu_support;

use formats::{ArrayData, Attribute, Cells, Compression, DataArray, Encoding, Grid, WriteOptions};
use proptest::prelude::*;
use vtu_support::*;

const ENCODINGS: [Encoding; 3] = [Encoding::Appended, Encoding::Binary, Encoding::Ascii];
const COMPRESSIONS: [Compression; 4] = [
    Compression::None,
    Compression::Zlib,
    Compression::Lz4,
    Compression::Lzma,
];

fn round_trip(g: &Grid, opts: &WriteOptions) -> Result<Grid, String> {
    let mut bytes = Vec::new();
    formats::write_to(&mut bytes, formats::Format::Vtu, g, opts).map_err(|e| e.to_string())?;
    formats::read_bytes(&bytes, formats::Format::Vtu).map_err(|e| e.to_string())
}

#[test]
fn fixtures_survive_every_encoding_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    for name in [
        "tet_appended_none_h64_le.vtu",
        "tet_binary_zlib_h32_be.vtu",
        "polyhedra_ascii.vtu",
        "tet_parallel.pvtu",
    ] {
        let g = formats::read(&fixtures().join(name)).unwrap();
        for encoding in ENCODINGS {
            for compression in COMPRESSIONS {
                let opts = WriteOptions {
                    encoding,
                    compression,
                    ..WriteOptions::default()
                };
                // Through real files, the way `convert` does it.
                let out = dir.path().join(format!("{encoding:?}_{compression:?}.vtu"));
                formats::write(&out, &g, &opts).unwrap();
                let back = formats::read(&out).unwrap();
                grids_bit_eq(&g, &back)
                    .unwrap_or_else(|e| panic!("{name} as {encoding:?}/{compression:?}: {e}"));
            }
        }
    }
}

#[test]
fn ascii_output_keeps_nan_and_infinities() {
    let g = formats::read(&fixtures().join("tet_appended_none_h64_le.vtu")).unwrap();
    let mut bytes = Vec::new();
    let opts = WriteOptions {
        encoding: Encoding::Ascii,
        ..WriteOptions::default()
    };
    formats::write_to(&mut bytes, formats::Format::Vtu, &g, &opts).unwrap();
    let text = String::from_utf8(bytes).unwrap();
    // VTK 9.1 cannot read NaN/inf back from ascii: that one array goes inline binary instead.
    let line = text.lines().find(|l| l.contains("f_specials")).unwrap();
    assert!(line.contains("format=\"binary\""), "{line}");
    assert!(!text.contains("inf ") && !text.contains("NaN"));
    let line = text
        .lines()
        .find(|l| l.contains("Name=\"temperature\""))
        .unwrap();
    assert!(line.contains("format=\"ascii\""), "{line}");
}

#[test]
fn convert_writes_each_encoding() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("tet_appended64_lzma_h32_be.vtu");
    let g = formats::read(&input).unwrap();
    for (enc, comp) in [
        ("appended", "zlib"),
        ("binary", "lz4"),
        ("ascii", "none"),
        ("appended", "none"),
    ] {
        let out = dir.path().join(format!("{enc}_{comp}.vtu"));
        let st = std::process::Command::new(env!("CARGO_BIN_EXE_tetkit"))
            .args(["convert"])
            .arg(&input)
            .arg(&out)
            .args(["--encoding", enc, "--compress", comp])
            .output()
            .unwrap();
        assert!(
            st.status.success(),
            "{}",
            String::from_utf8_lossy(&st.stderr)
        );
        grids_bit_eq(&g, &formats::read(&out).unwrap()).unwrap();
    }
}

#[test]
fn pvtu_writes_all_pieces_or_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let g = formats::read(&fixtures().join("tet_appended_none_h64_le.vtu")).unwrap();
    let pieces = [g.clone(), g.clone(), g];
    let out = dir.path().join("many.pvtu");
    let opts = WriteOptions {
        compression: Compression::Lz4,
        ..WriteOptions::default()
    };
    formats::vtu::pvtu::write(&out, &pieces, &opts).unwrap();
    assert!(dir.path().join("many/many_2.vtu").is_file());
    let back = formats::read(&out).unwrap();
    assert_eq!(back.num_cells(), 3 * pieces[0].num_cells());
    assert_eq!(back.num_points(), 3 * pieces[0].num_points());
    let n = pieces[0].cells.connectivity.len();
    let np = pieces[0].num_points() as i64;
    assert_eq!(
        back.cells.connectivity[2 * n],
        pieces[0].cells.connectivity[0] + 2 * np
    );
    // An invalid last piece: nothing appears, not even the folder.
    let mut bad = pieces[0].clone();
    bad.cells.connectivity[0] = 1 << 40;
    let out = dir.path().join("broken.pvtu");
    let e = formats::vtu::pvtu::write(&out, &[pieces[0].clone(), bad], &opts).unwrap_err();
    assert!(e.to_string().contains("broken_1.vtu"), "{e}");
    assert!(!out.exists() && !dir.path().join("broken").exists());
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left.len(), 2, "{left:?}");
}

// ---- random grids ----

fn any_array(n: usize) -> impl Strategy<Value = ArrayData> {
    prop_oneof![
        prop::collection::vec(any::<i8>(), n).prop_map(ArrayData::Int8),
        prop::collection::vec(any::<u8>(), n).prop_map(ArrayData::UInt8),
        prop::collection::vec(any::<i16>(), n).prop_map(ArrayData::Int16),
        prop::collection::vec(any::<u16>(), n).prop_map(ArrayData::UInt16),
        prop::collection::vec(any::<i32>(), n).prop_map(ArrayData::Int32),
        prop::collection::vec(any::<u32>(), n).prop_map(ArrayData::UInt32),
        prop::collection::vec(any::<i64>(), n).prop_map(ArrayData::Int64),
        prop::collection::vec(any::<u64>(), n).prop_map(ArrayData::UInt64),
        // Any bit pattern: NaN payloads, infinities, -0.0 and subnormals included.
        prop::collection::vec(any::<u32>().prop_map(f32::from_bits), n)
            .prop_map(ArrayData::Float32),
        prop::collection::vec(any::<u64>().prop_map(f64::from_bits), n)
            .prop_map(ArrayData::Float64),
        prop::collection::vec("[^\u{0}]{0,6}", n).prop_map(ArrayData::String),
    ]
}

fn named_array(tuples: usize, tag: &'static str) -> impl Strategy<Value = DataArray> {
    (1usize..4, "[a-zA-Z_<&\" ]{1,8}", any::<bool>()).prop_flat_map(move |(c, name, names)| {
        any_array(tuples * c).prop_map(move |data| DataArray {
            name: format!("{tag}{name}"),
            components: c,
            component_names: if names {
                (0..c).map(|k| format!("c{k}&<")).collect()
            } else {
                Vec::new()
            },
            // An id array (IdType="1") round-trips as such when its values are Int64 or Int32.
            id_type: names && matches!(data, ArrayData::Int64(_) | ArrayData::Int32(_)),
            data,
        })
    })
}

fn random_grid() -> impl Strategy<Value = Grid> {
    (1usize..40, 0usize..30, any::<bool>()).prop_flat_map(|(np, nc, f32pts)| {
        let coord = -1e6f64..1e6;
        let points = prop::collection::vec(coord, np * 3);
        let cells = prop::collection::vec(prop::collection::vec(0..np as i64, 4), nc);
        let pd = prop::collection::vec(named_array(np, "p"), 0..3);
        let cd = prop::collection::vec(named_array(nc, "c"), 0..3);
        let fd = prop::collection::vec((0usize..5).prop_flat_map(|t| named_array(t, "f")), 0..3);
        (points, cells, pd, cd, fd).prop_map(move |(p, c, pd, cd, fd)| {
            let mut cells = Cells::new();
            for ids in &c {
                cells.push(formats::cell_type::TETRA, ids);
            }
            let points = if f32pts {
                ArrayData::Float32(p.iter().map(|&x| x as f32).collect())
            } else {
                ArrayData::Float64(p)
            };
            let mut g = Grid {
                points: DataArray::new("Points", 3, points),
                cells,
                ..Grid::default()
            };
            for a in pd {
                g.point_data.insert(a);
            }
            for a in cd {
                g.cell_data.insert(a);
            }
            if let Some(a) = g.point_data.arrays.first() {
                g.point_data
                    .active
                    .push((Attribute::Scalars, a.name.clone()));
            }
            g.field_data = fd;
            g
        })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn random_grids_round_trip_bit_for_bit(g in random_grid(), e in 0usize..3, c in 0usize..4) {
        let opts = WriteOptions { encoding: ENCODINGS[e], compression: COMPRESSIONS[c], ..WriteOptions::default() };
        let back = round_trip(&g, &opts);
        prop_assert!(back.is_ok(), "{:?}", back.err());
        let back = back.unwrap();
        let eq = grids_bit_eq(&g, &back);
        prop_assert!(eq.is_ok(), "{:?}/{:?}: {:?}", opts.encoding, opts.compression, eq.err());
    }
}

#[test]
fn bench_io_runs_on_a_small_file() {
    // Only that the command works end to end; speed is measured by scripts/bench_io.py.
    let dir = tempfile::tempdir().unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_tetkit"))
        .args(["bench", "io", "--repeat", "1", "--json", "--dir"])
        .arg(dir.path())
        .arg(fixtures().join("tet_appended_none_h64_le.vtu"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["cells"], 135);
    assert_eq!(v["steps"].as_array().unwrap().len(), 5);
    let raw = formats::read(&dir.path().join("tetkit_bench_raw.vtu")).unwrap();
    let zlib = formats::read(&dir.path().join("tetkit_bench_zlib.vtu")).unwrap();
    grids_bit_eq(&raw, &zlib).unwrap();
}
