//! VTKHDF fixtures (scripts/make_vtkhdf_fixtures.py, written with h5py) through the real binary:
//! each good file reads to the points, cells and arrays VTK 9.1's vtkHDFReader gave (saved
//! beside it as X_vtk.vtu), `convert` keeps every array, bad files fail naming the file and the
//! problem and write nothing, and damaged copies never panic.

mod common;

use common::*;
use std::path::{Path, PathBuf};
use tetkit::formats;

type TestResult = Result<(), Box<dyn std::error::Error>>;

const GOOD: [&str; 7] = [
    "tets.vtkhdf",
    "two_pieces.vtkhdf",
    "float32.hdf",
    "mixed.vtkhdf",
    "gzip.vtkhdf",
    "version2.vtkhdf",
    "userblock.vtkhdf",
];

fn vtkhdf(name: &str) -> PathBuf {
    fixture("vtkhdf").join(name)
}

fn stem(p: &Path) -> String {
    p.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

#[test]
fn every_good_fixture_reads_as_vtk_9_1_read_it() -> TestResult {
    for name in GOOD {
        let f = vtkhdf(name);
        let ours = formats::read(&f)?;
        let vtk = formats::read(&f.with_file_name(format!("{}_vtk.vtu", stem(&f))))?;
        grids_bit_equal(&ours, &vtk).map_err(|e| format!("{name}: {e}"))?;
        assert!(ours.num_cells() > 0, "{name}");
    }
    Ok(())
}

#[test]
fn info_and_convert_keep_every_array() -> TestResult {
    let dir = tempdir();
    for name in GOOD.iter().chain(&["string_field.vtkhdf"]) {
        let f = vtkhdf(name);
        let info = tetkit(["info".as_ref(), f.as_os_str()]);
        info.assert_success();
        let ours = formats::read(&f)?;
        let out = info.stdout_str();
        for a in ours.point_data.arrays.iter().chain(&ours.cell_data.arrays) {
            assert!(
                out.contains(&a.name),
                "{name}: info lacks {}:\n{out}",
                a.name
            );
        }
        let vtu = dir.path().join(format!("{}.vtu", stem(&f)));
        tetkit(["convert".as_ref(), f.as_os_str(), vtu.as_os_str()]).assert_success();
        grids_bit_equal(&ours, &formats::read(&vtu)?).map_err(|e| format!("{name}: {e}"))?;
    }
    Ok(())
}

#[test]
fn bad_files_fail_naming_the_file_and_the_problem_and_write_nothing() {
    let dir = tempdir();
    for (name, needle) in [
        ("bad_type.vtkhdf", "VTKHDF ImageData is not read"),
        (
            "bad_connectivity.vtkhdf",
            "array 'Connectivity': entry 7 is point id 11",
        ),
        (
            "bad_offsets.vtkhdf",
            "array 'Offsets': offsets decrease at cell 2",
        ),
        ("bad_cellsize.vtkhdf", "cell 1 is a tetra with 5 points"),
        ("bad_points.vtkhdf", "array 'Points': has shape [8, 2]"),
        (
            "bad_pointdata.vtkhdf",
            "array 'PointData/temperature': has 7 tuples",
        ),
        ("polyhedron.vtkhdf", "polyhedron (type 42)"),
        ("bad_steps.vtkhdf", "array 'Steps/PartOffsets'"),
        (
            "bad_step_offsets.vtkhdf",
            "array 'Points': has 28 rows, but time step 0 reads rows 1000 to 1008",
        ),
        ("temporal.vtkhdf@7", "there is no time step 7"),
        ("truncated.vtkhdf", "HDF5:"),
    ] {
        let f = vtkhdf(name);
        let out = dir.path().join(format!("{}.vtu", stem(&f)));
        let shown = name.split('@').next().unwrap_or(name);
        tetkit(["convert".as_ref(), f.as_os_str(), out.as_os_str()])
            .assert_failure(&[shown, needle]);
        assert!(!out.exists(), "{name}: wrote {}", out.display());
    }
}

#[test]
fn temporal_steps_list_convert_and_render() -> TestResult {
    let dir = tempdir();
    let f = vtkhdf("temporal.vtkhdf");
    let info = tetkit(["info".as_ref(), f.as_os_str()]);
    info.assert_success();
    let out = info.stdout_str();
    assert!(out.contains("time steps: 4"), "{out}");
    assert!(out.contains("t = 1.25"), "{out}");
    let times = [0.0, 0.5, 1.25, 2.0];
    for (k, t) in times.into_iter().enumerate() {
        // `FILE@K` through the binary: the step's grid, its time as the field array Time.
        let step = PathBuf::from(format!("{}@{k}", f.display()));
        let vtu = dir.path().join(format!("step{k}.vtu"));
        tetkit(["convert".as_ref(), step.as_os_str(), vtu.as_os_str()]).assert_success();
        let got = formats::read(&vtu)?;
        let mut want = formats::read(&vtkhdf(&format!("temporal_step{k}.vtkhdf")))?;
        want.field_data.push(formats::DataArray::new(
            "Time",
            1,
            formats::ArrayData::Float64(vec![t]),
        ));
        grids_bit_equal(&got, &want).map_err(|e| format!("step {k}: {e}"))?;
    }
    let last = PathBuf::from(format!("{}@last", f.display()));
    let info = tetkit(["info".as_ref(), last.as_os_str()]);
    info.assert_success();
    assert!(
        info.stdout_str().contains("this is step 3"),
        "{}",
        info.stdout_str()
    );
    let png = dir.path().join("last.png");
    tetkit([
        "render".as_ref(),
        last.as_os_str(),
        "-o".as_ref(),
        png.as_os_str(),
        "--size".as_ref(),
        "64x64".as_ref(),
        "--quiet".as_ref(),
    ])
    .assert_success();
    assert!(png.exists());
    Ok(())
}

#[test]
fn other_content_behind_a_vtkhdf_extension_is_named() -> TestResult {
    let dir = tempdir();
    let vtu = dir.path().join("a.vtkhdf");
    std::fs::copy(vtkhdf("tets_vtk.vtu"), &vtu)?;
    tetkit(["info".as_ref(), vtu.as_os_str()]).assert_failure(&["a.vtkhdf", "the content is VTU"]);
    let exo = dir.path().join("b.hdf");
    std::fs::copy(fixture("exodus/nc4/tets.exo"), &exo)?;
    tetkit(["info".as_ref(), exo.as_os_str()])
        .assert_failure(&["b.hdf", "without a /VTKHDF group"]);
    let empty = dir.path().join("c.vtkhdf");
    std::fs::write(&empty, b"")?;
    tetkit(["info".as_ref(), empty.as_os_str()]).assert_failure(&["c.vtkhdf", "not an HDF5 file"]);
    Ok(())
}

#[test]
fn truncated_and_flipped_copies_never_panic() -> TestResult {
    let dir = tempdir();
    let bytes = std::fs::read(vtkhdf("tets.vtkhdf"))?;
    let f = dir.path().join("damaged.vtkhdf");
    let stride = bytes.len() / 24 + 1;
    for at in (0..bytes.len()).step_by(stride) {
        for cut in [true, false] {
            let mut b = bytes.clone();
            if cut {
                b.truncate(at);
            } else {
                b[at] ^= 0xff;
            }
            std::fs::write(&f, &b)?;
            let run = tetkit(["info".as_ref(), f.as_os_str()]);
            if !run.success() {
                run.assert_failure(&["damaged.vtkhdf"]);
            }
            assert!(!run.stderr.contains("panicked"), "{}", run.stderr);
        }
    }
    Ok(())
}
