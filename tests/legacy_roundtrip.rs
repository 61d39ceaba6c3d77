//! read -> write (4.2 and 5.1, ASCII and binary) -> read gives the same grid, bit for bit: every
//! fixture, TetGen meshes, and random grids with every element type (proptest).

mod legacy_common;

use formats::legacy::LOOKUP_TABLE_PREFIX;
use formats::{
    cell_type, ArrayData, Attribute, DataArray, Encoding, Format, Grid, LegacyVersion, ScalarType,
    WriteOptions,
};
use legacy_common::*;
use proptest::prelude::*;

fn options() -> Vec<(&'static str, WriteOptions)> {
    let mut v = Vec::new();
    for (vn, version) in [("4.2", LegacyVersion::V42), ("5.1", LegacyVersion::V51)] {
        for (en, encoding) in [("binary", Encoding::Binary), ("ascii", Encoding::Ascii)] {
            v.push((
                if vn == "4.2" {
                    if en == "binary" {
                        "4.2 binary"
                    } else {
                        "4.2 ascii"
                    }
                } else if en == "binary" {
                    "5.1 binary"
                } else {
                    "5.1 ascii"
                },
                WriteOptions {
                    encoding,
                    legacy_version: version,
                    ..Default::default()
                },
            ));
        }
    }
    v
}

fn write_read(g: &Grid, opts: &WriteOptions) -> Grid {
    let mut bytes = Vec::new();
    formats::write_to(&mut bytes, Format::Legacy, g, opts).unwrap_or_else(|e| panic!("{e}"));
    formats::read_bytes(&bytes, Format::Legacy).unwrap_or_else(|e| panic!("{e}"))
}

/// Binary files store lookup tables as bytes: what a table reads back as after that.
fn quantize_luts(g: &Grid) -> Grid {
    let mut g = g.clone();
    for a in &mut g.field_data {
        if a.name.starts_with(LOOKUP_TABLE_PREFIX) {
            if let ArrayData::Float32(v) = &mut a.data {
                for x in v.iter_mut() {
                    *x = ((*x as f64 * 255.0).round().clamp(0.0, 255.0) as u8) as f32 / 255.0;
                }
            }
        }
    }
    g
}

#[test]
fn fixtures_round_trip_bit_for_bit() {
    let mut inputs = legacy_fixtures();
    for name in ["sphere", "quadratic", "regions", "torus"] {
        inputs.push(root().join(format!("fixtures/tetgen/{name}.1.ele")));
    }
    for path in inputs {
        let g = formats::read(&path).unwrap();
        for (what, opts) in options() {
            let back = write_read(&g, &opts);
            let want = if opts.encoding == Encoding::Binary {
                quantize_luts(&g)
            } else {
                g.clone()
            };
            same_grid(&back, &want).unwrap_or_else(|e| panic!("{} as {what}: {e}", path.display()));
            // And again: a second trip changes nothing at all.
            same_grid(&write_read(&back, &opts), &back).unwrap();
        }
    }
}

#[test]
fn convert_on_the_command_line_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    let src = root().join("fixtures/legacy/mixed_51_binary.vtk");
    let a = dir.path().join("a.vtk");
    let b = dir.path().join("b.vtk");
    let out = tetkit(&[
        "convert",
        path_str(&src),
        path_str(&a),
        "--encoding",
        "ascii",
        "--legacy-version",
        "4.2",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = tetkit(&[
        "convert",
        path_str(&a),
        path_str(&b),
        "--encoding",
        "binary",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read(&a).unwrap();
    assert!(
        text.starts_with(b"# vtk DataFile Version 4.2\n")
            && text.windows(6).any(|w| w == b"\nASCII")
    );
    assert!(std::fs::read(&b)
        .unwrap()
        .starts_with(b"# vtk DataFile Version 5.1\n"));
    let orig = formats::read(&src).unwrap();
    same_grid(&formats::read(&b).unwrap(), &quantize_luts(&orig)).unwrap();
}

#[test]
fn non_finite_values_survive_both_encodings() {
    let mut g = Grid {
        points: DataArray::new(
            "Points",
            3,
            ArrayData::Float64(vec![0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1.]),
        ),
        ..Default::default()
    };
    g.cells.push(cell_type::TETRA, &[0, 1, 2, 3]);
    let special = vec![f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -0.0];
    g.point_data
        .insert(DataArray::new("special", 1, ArrayData::Float32(special)));
    g.cell_data.insert(DataArray::new(
        "tiny",
        2,
        ArrayData::Float64(vec![f64::MIN_POSITIVE, 5e-324]),
    ));
    for (what, opts) in options() {
        same_grid(&write_read(&g, &opts), &g).unwrap_or_else(|e| panic!("{what}: {e}"));
    }
}

#[test]
fn too_large_ids_for_4_2_are_refused_not_truncated() {
    let mut g = Grid {
        points: DataArray::new("Points", 3, ArrayData::Float32(vec![0.0; 15])),
        ..Default::default()
    };
    g.cells.push(cell_type::TETRA, &[0, 1, 2, 3]);
    g.cells.connectivity[3] = 1 << 33;
    let opts = WriteOptions {
        legacy_version: LegacyVersion::V42,
        ..Default::default()
    };
    let mut out = Vec::new();
    let e = formats::legacy::write(&mut out, &g, &opts).unwrap_err();
    assert!(e.message.contains("write 5.1"), "{e}");
}

fn array_strategy(tuples: usize) -> impl Strategy<Value = DataArray> {
    let types = prop::sample::select(ScalarType::ALL.to_vec());
    (
        types,
        1usize..5,
        "[a-z %\"é]{1,8}",
        any::<u64>(),
        any::<bool>(),
    )
        .prop_map(move |(ty, comps, name, seed, named)| {
            let n = tuples * comps;
            let mut s = seed | 1;
            let mut next = move || {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                s
            };
            let data = match ty {
                ScalarType::Int8 => ArrayData::Int8((0..n).map(|_| next() as i8).collect()),
                ScalarType::UInt8 => ArrayData::UInt8((0..n).map(|_| next() as u8).collect()),
                ScalarType::Int16 => ArrayData::Int16((0..n).map(|_| next() as i16).collect()),
                ScalarType::UInt16 => ArrayData::UInt16((0..n).map(|_| next() as u16).collect()),
                ScalarType::Int32 => ArrayData::Int32((0..n).map(|_| next() as i32).collect()),
                ScalarType::UInt32 => ArrayData::UInt32((0..n).map(|_| next() as u32).collect()),
                ScalarType::Int64 => ArrayData::Int64((0..n).map(|_| next() as i64).collect()),
                ScalarType::UInt64 => ArrayData::UInt64((0..n).map(|_| next()).collect()),
                // Any finite bit pattern (NaN payloads are not text-representable).
                ScalarType::Float32 => ArrayData::Float32(
                    (0..n)
                        .map(|_| f32::from_bits(next() as u32))
                        .map(|x| if x.is_finite() { x } else { 1.5 })
                        .collect(),
                ),
                ScalarType::Float64 => ArrayData::Float64(
                    (0..n)
                        .map(|_| f64::from_bits(next()))
                        .map(|x| if x.is_finite() { x } else { -2.5 })
                        .collect(),
                ),
            };
            let mut a = DataArray::new(name, comps, data);
            if named {
                a.component_names = (0..comps)
                    .map(|k| {
                        if k == 1 {
                            String::new()
                        } else {
                            format!("c {k}%")
                        }
                    })
                    .collect();
            }
            a
        })
}

fn grid_strategy() -> impl Strategy<Value = Grid> {
    (4usize..12, 1usize..6, any::<bool>(), any::<u64>())
        .prop_flat_map(|(np, nc, f32pts, seed)| {
            (
                Just((np, nc, f32pts, seed)),
                prop::collection::vec(array_strategy(np), 0..4),
                prop::collection::vec(array_strategy(nc), 0..4),
                prop::collection::vec(array_strategy(3), 0..3),
                prop::collection::vec("[ -~]{0,12}", 0..4),
            )
        })
        .prop_map(|((np, nc, f32pts, seed), pd, cd, fd, strings)| {
            let mut g = Grid::default();
            let mut s = seed | 1;
            let mut next = move || {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                s
            };
            let coords: Vec<f64> = (0..3 * np)
                .map(|_| (next() % 2001) as f64 / 7.0 - 140.0)
                .collect();
            g.points.data = if f32pts {
                ArrayData::Float32(coords.iter().map(|&x| x as f32).collect())
            } else {
                ArrayData::Float64(coords)
            };
            for _ in 0..nc {
                let ids: Vec<i64> = (0..4).map(|_| (next() % np as u64) as i64).collect();
                g.cells.push(cell_type::TETRA, &ids);
            }
            for a in pd {
                g.point_data.insert(a);
            }
            for a in cd {
                g.cell_data.insert(a);
            }
            for a in fd {
                if !g.field_data.iter().any(|b| b.name == a.name) {
                    g.field_data.push(a);
                }
            }
            if !g.field_data.iter().any(|b| b.name == "strings") {
                let n = strings.len();
                g.field_data
                    .push(DataArray::new("strings", 1, ArrayData::String(strings)));
                let _ = n;
            }
            // Make the first fitting arrays active, as a reader would.
            for attrs in [&mut g.point_data, &mut g.cell_data] {
                let names: Vec<(String, usize)> = attrs
                    .arrays
                    .iter()
                    .map(|a| (a.name.clone(), a.components))
                    .collect();
                for (name, c) in names {
                    let role = match c {
                        1 if !attrs.active.iter().any(|r| r.0 == Attribute::Scalars) => {
                            Attribute::Scalars
                        }
                        3 if !attrs.active.iter().any(|r| r.0 == Attribute::Vectors) => {
                            Attribute::Vectors
                        }
                        2 if !attrs.active.iter().any(|r| r.0 == Attribute::TCoords) => {
                            Attribute::TCoords
                        }
                        _ => continue,
                    };
                    attrs.active.push((role, name));
                }
            }
            g
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn random_grids_round_trip(g in grid_strategy()) {
        g.validate().unwrap();
        for (what, opts) in options() {
            let back = write_read(&g, &opts);
            if let Err(e) = same_grid(&back, &g) {
                return Err(TestCaseError::fail(format!("{what}: {e}")));
            }
        }
    }
}

/// Files bigger than the reader's parallel-read threshold go through positional reads in
/// pieces; the result must be the same as a read from memory.
#[test]
fn big_binary_files_stream_the_same_as_memory() {
    let np = 400_000usize;
    let mut g = Grid {
        points: DataArray::new(
            "Points",
            3,
            ArrayData::Float64((0..3 * np).map(|i| i as f64 * 0.25 - 7.0).collect()),
        ),
        ..Default::default()
    };
    for t in 0..(np - 3) / 2 {
        g.cells.push(
            cell_type::TETRA,
            &[t as i64, t as i64 + 1, t as i64 + 2, t as i64 + 3],
        );
    }
    let nc = g.num_cells();
    g.cell_data.insert(DataArray::new(
        "id",
        1,
        ArrayData::Int64((0..nc as i64).collect()),
    ));
    g.point_data.insert(DataArray::new(
        "s",
        1,
        ArrayData::Float32((0..np).map(|i| i as f32).collect()),
    ));
    let dir = tempfile::tempdir().unwrap();
    for (what, opts) in options() {
        if opts.encoding == Encoding::Ascii {
            continue;
        }
        let path = dir.path().join("big.vtk");
        formats::write(&path, &g, &opts).unwrap();
        assert!(std::fs::metadata(&path).unwrap().len() > 9 << 20);
        let back = formats::read(&path).unwrap_or_else(|e| panic!("{what}: {e}"));
        same_grid(&back, &g).unwrap_or_else(|e| panic!("{what}: {e}"));
        // Cut inside the big points block: refused with a byte offset, from the file too.
        let bytes = std::fs::read(&path).unwrap();
        std::fs::write(&path, &bytes[..bytes.len() / 3]).unwrap();
        let e = formats::read(&path).unwrap_err();
        assert!(matches!(e.place, formats::Place::Byte(_)), "{e}");
        assert_eq!(e.file.as_deref(), Some(path.as_path()));
    }
}
