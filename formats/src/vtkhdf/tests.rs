//! Unit tests of the VTKHDF reader on the fixtures of scripts/make_vtkhdf_fixtures.py.

use super::*;
use std::path::PathBuf;

type TestResult = std::result::Result<(), Box<dyn std::error::Error>>;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures/vtkhdf")
        .join(name)
}

fn read(name: &str) -> Result<Grid> {
    let p = fixture(name);
    let bytes = std::fs::read(&p).map_err(|e| FormatError::io(&p, e))?;
    read_from(&bytes, &p)
}

/// The error reading `name`, with the file's name checked in it.
fn error(name: &str) -> String {
    match read(name) {
        Ok(_) => panic!("{name} should not read"),
        Err(e) => {
            let m = e.to_string();
            assert!(m.contains(name), "{m}");
            m
        }
    }
}

fn array<'a>(arrays: &'a [DataArray], name: &str) -> &'a DataArray {
    let Some(a) = arrays.iter().find(|a| a.name == name) else {
        panic!(
            "no array {name} in {:?}",
            arrays.iter().map(|a| &a.name).collect::<Vec<_>>()
        );
    };
    a
}

#[test]
fn tets_keep_every_array_with_its_type_and_components() -> TestResult {
    let g = read("tets.vtkhdf")?;
    g.validate()?;
    assert_eq!((g.num_points(), g.num_cells()), (36, 60));
    assert!(matches!(g.points.data, ArrayData::Float64(_)));
    assert!(g.cells.types.iter().all(|&t| t == cell_type::TETRA));
    let t = array(&g.point_data.arrays, "temperature");
    assert_eq!((t.data.type_name(), t.components), ("Float32", 1));
    let v = array(&g.point_data.arrays, "velocity");
    assert_eq!(
        (v.data.type_name(), v.components, v.tuples()),
        ("Float64", 3, 36)
    );
    let m = array(&g.cell_data.arrays, "material");
    assert_eq!((m.data.type_name(), m.components), ("Int32", 1));
    let s = array(&g.cell_data.arrays, "tensor");
    assert_eq!((s.data.type_name(), s.components), ("Float32", 9));
    let time = array(&g.field_data, "time");
    assert_eq!(time.data, ArrayData::Float64(vec![0.5, 1.25]));
    let ids = array(&g.field_data, "ids");
    assert_eq!(ids.components, 3);
    assert_eq!(ids.data, ArrayData::Int64(vec![1, 2, 3, 4, 5, 6]));
    Ok(())
}

#[test]
fn second_piece_ids_are_shifted_by_the_first_pieces_points() -> TestResult {
    let one = read("tets.vtkhdf")?;
    let two = read("two_pieces.vtkhdf")?;
    two.validate()?;
    assert_eq!((two.num_points(), two.num_cells()), (72, 120));
    let n = one.cells.connectivity.len();
    assert_eq!(&two.cells.connectivity[..n], &one.cells.connectivity[..]);
    let shifted: Vec<i64> = one.cells.connectivity.iter().map(|&i| i + 36).collect();
    assert_eq!(&two.cells.connectivity[n..], &shifted[..]);
    let offsets: Vec<i64> = one.cells.offsets[1..]
        .iter()
        .map(|&o| o + n as i64)
        .collect();
    assert_eq!(&two.cells.offsets[61..], &offsets[..]);
    assert_eq!(two.point(36), [2.0, 0.0, 0.0]);
    Ok(())
}

#[test]
fn compressed_chunked_file_reads_as_the_plain_one() -> TestResult {
    assert_eq!(read("gzip.vtkhdf")?, read("tets.vtkhdf")?);
    Ok(())
}

#[test]
fn float32_points_mixed_cells_and_small_types() -> TestResult {
    let g = read("float32.hdf")?;
    assert!(matches!(g.points.data, ArrayData::Float32(_)));
    assert_eq!(
        array(&g.point_data.arrays, "level").data.type_name(),
        "UInt16"
    );
    assert_eq!(array(&g.cell_data.arrays, "sign").data.type_name(), "Int8");
    let m = read("mixed.vtkhdf")?;
    m.validate()?;
    assert_eq!(m.cells.types, vec![12, 13, 13, 14, 10]);
    assert_eq!(
        array(&m.cell_data.arrays, "global_id").data.type_name(),
        "UInt64"
    );
    Ok(())
}

#[test]
fn string_field_data_vlen_type_and_active_scalars_are_read() -> TestResult {
    let g = read("string_field.vtkhdf")?;
    let s = array(&g.field_data, "names");
    assert_eq!(
        s.data,
        ArrayData::String(vec!["alpha".into(), "beta".into()])
    );
    Ok(())
}

/// Step `k` of `name` (`None`: the last).
fn read_step(name: &str, k: Option<usize>) -> Result<Grid> {
    let p = fixture(name);
    let bytes = std::fs::read(&p).map_err(|e| FormatError::io(&p, e))?;
    let sel = k.map_or(Selector::Last, Selector::Index);
    read_from_at(&bytes, &p, sel)
}

#[test]
fn each_temporal_step_reads_as_its_static_file_with_its_time() -> TestResult {
    // The static files were built from the same arrays without the Steps layout: parts
    // changing at step 2, arrays replayed from an earlier step's rows, field data sized 0 at
    // step 2, CellOffsets N x 1 beside ConnectivityIdOffsets 1-D.
    let times = [0.0, 0.5, 1.25, 2.0];
    for (k, t) in times.into_iter().enumerate() {
        let got = read_step("temporal.vtkhdf", Some(k))?;
        let mut want = read(&format!("temporal_step{k}.vtkhdf"))?;
        want.field_data
            .push(DataArray::new("Time", 1, ArrayData::Float64(vec![t])));
        got.validate()?;
        assert_eq!(got, want, "step {k}");
    }
    assert_eq!(
        read("temporal.vtkhdf")?,
        read_step("temporal.vtkhdf", Some(0))?
    );
    assert_eq!(
        read_step("temporal.vtkhdf", None)?,
        read_step("temporal.vtkhdf", Some(3))?
    );
    // Step 3 replays step 2's temperature rows but has its own velocity.
    let (two, three) = (
        read_step("temporal.vtkhdf", Some(2))?,
        read_step("temporal.vtkhdf", Some(3))?,
    );
    let pd = |g: &Grid, n: &str| array(&g.point_data.arrays, n).data.clone();
    assert_eq!(pd(&two, "temperature"), pd(&three, "temperature"));
    assert_ne!(pd(&two, "velocity"), pd(&three, "velocity"));
    assert!(two.field_data.iter().all(|a| a.name != "history"));
    assert_eq!(array(&three.field_data, "history").tuples(), 4);
    // Deflated in chunks of 4 rows: each step's rows are decoded from the chunks they cross.
    for k in 0..times.len() {
        assert_eq!(
            read_step("temporal_gzip.vtkhdf", Some(k))?,
            read_step("temporal.vtkhdf", Some(k))?,
            "step {k}"
        );
    }
    // The same bytes owned or borrowed.
    let p = fixture("temporal.vtkhdf");
    let bytes = std::fs::read(&p)?;
    assert_eq!(read_vec_at(bytes, &p, Selector::Index(2))?, two);
    Ok(())
}

#[test]
fn steps_that_are_not_there_are_named() -> TestResult {
    let m = read_step("temporal.vtkhdf", Some(4))
        .err()
        .map(|e| e.to_string());
    let m = m.unwrap_or_default();
    assert!(
        m.contains("temporal.vtkhdf") && m.contains("no time step 4: the file has 4 (0 to 3)"),
        "{m}"
    );
    let m = read_step("tets.vtkhdf", Some(1))
        .err()
        .map(|e| e.to_string());
    let m = m.unwrap_or_default();
    assert!(
        m.contains("no time step 1: the file is not temporal"),
        "{m}"
    );
    // A static file has its one step, 0 or last.
    assert_eq!(read_step("tets.vtkhdf", None)?, read("tets.vtkhdf")?);
    assert_eq!(times(&fixture("temporal.vtkhdf"))?, [0.0, 0.5, 1.25, 2.0]);
    assert!(times(&fixture("tets.vtkhdf"))?.is_empty());
    assert_eq!(
        split_selector(Path::new("a/b.vtkhdf@last")),
        Some((PathBuf::from("a/b.vtkhdf"), Selector::Last))
    );
    assert_eq!(split_selector(Path::new("b.vtu@2")), None);
    Ok(())
}

#[test]
fn errors_name_the_file_and_the_place() {
    for (name, needles) in [
        (
            "bad_type.vtkhdf",
            &["'Type'", "ImageData", "UnstructuredGrid only"][..],
        ),
        (
            "bad_connectivity.vtkhdf",
            &["'Connectivity'", "entry 7", "outside piece 0's points"],
        ),
        (
            "bad_offsets.vtkhdf",
            &["'Offsets'", "decrease at cell 2", "12 then 8"],
        ),
        (
            "bad_cellsize.vtkhdf",
            &["'Offsets'", "cell 1 is a tetra with 5 points"],
        ),
        ("bad_points.vtkhdf", &["'Points'", "expected [8, 3]"]),
        (
            "bad_pointdata.vtkhdf",
            &["'PointData/temperature'", "7 tuples", "8 points"],
        ),
        ("polyhedron.vtkhdf", &["'Types'", "cell 0 is a polyhedron"]),
        ("bad_steps.vtkhdf", &["'Steps/PartOffsets'", "PartOffsets"]),
        (
            "bad_step_offsets.vtkhdf",
            &[
                "'Points'",
                "has 28 rows",
                "time step 0 reads rows 1000 to 1008",
            ],
        ),
        ("truncated.vtkhdf", &["HDF5"]),
    ] {
        let m = error(name);
        for n in needles {
            assert!(m.contains(n), "{name}: {m:?} lacks {n:?}");
        }
    }
}

#[test]
fn other_files_are_refused_by_what_they_are() -> TestResult {
    let p = Path::new("x.vtkhdf");
    let e = read_from(b"# vtk DataFile Version 4.2\n", p).err();
    assert!(e.is_some_and(|e| e.to_string().contains("not an HDF5 file")));
    let nc4 = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/exodus/nc4/hand.exo");
    let bytes = std::fs::read(&nc4)?;
    let e = read_from(&bytes, p).err();
    assert!(
        e.as_ref()
            .is_some_and(|e| e.to_string().contains("without a /VTKHDF group")),
        "{e:?}"
    );
    Ok(())
}

#[test]
fn truncations_and_flipped_bytes_give_errors_not_panics() -> TestResult {
    // A static file, and the last step of a temporal one (deflated, read by hyperslabs).
    for (name, sel) in [
        ("mixed.vtkhdf", Selector::Index(0)),
        ("temporal_gzip.vtkhdf", Selector::Last),
    ] {
        let p = fixture(name);
        let bytes = std::fs::read(&p)?;
        let whole = read_from_at(&bytes, &p, sel)?;
        // A cut that leaves every byte the file uses (HDF5 files can end in unused space)
        // reads the same grid; any other is an error naming the file.
        for cut in (0..bytes.len()).step_by(97) {
            match read_from_at(&bytes[..cut], &p, sel) {
                Ok(g) => assert_eq!(g, whole, "{name}: cut at {cut}"),
                Err(e) => assert!(e.to_string().contains(name), "{e}"),
            }
        }
        for at in (0..bytes.len()).step_by(13) {
            let mut b = bytes.clone();
            b[at] ^= 0x5a;
            if let Err(e) = read_from_at(&b, &p, sel) {
                assert!(e.to_string().contains(name), "{e}");
            }
        }
    }
    Ok(())
}

#[test]
fn owned_bytes_read_as_borrowed_ones() -> TestResult {
    // `read_vec` (files) and `read_from` (stdin) give the same grid, or the same error, for
    // every fixture, good and bad.
    let mut n = 0;
    for entry in std::fs::read_dir(fixture(""))? {
        let p = entry?.path();
        if !matches!(
            p.extension().and_then(|e| e.to_str()),
            Some("vtkhdf" | "hdf")
        ) {
            continue;
        }
        let bytes = std::fs::read(&p)?;
        let borrowed = read_from(&bytes, &p).map_err(|e| e.to_string());
        let owned = read_vec(bytes, &p).map_err(|e| e.to_string());
        assert!(borrowed == owned, "{}", p.display());
        n += 1;
    }
    assert!(n >= 10, "only {n} fixtures");
    Ok(())
}
