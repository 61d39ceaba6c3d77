//! Interop: every fixture is read by tetkit as VTK reads it, written in every encoding, read back
//! bit-identical, and every output is read by VTK 9.1 with the same counts and checksums.
//! Runs in CI with TETKIT_REQUIRE_VTK=1.

mod common;

use common::*;
use std::path::{Path, PathBuf};
use tetkit::formats::{self, Compression, Encoding, Grid, LegacyVersion, WriteOptions};

/// Every output encoding: `(file suffix, options)`.
fn encodings() -> Vec<(String, WriteOptions)> {
    let mut out = Vec::new();
    for (en, e) in [
        ("appended", Encoding::Appended),
        ("binary", Encoding::Binary),
        ("ascii", Encoding::Ascii),
    ] {
        for (cn, c) in [
            ("none", Compression::None),
            ("zlib", Compression::Zlib),
            ("lz4", Compression::Lz4),
        ] {
            out.push((
                format!("{en}-{cn}.vtu"),
                WriteOptions {
                    encoding: e,
                    compression: c,
                    ..WriteOptions::default()
                },
            ));
        }
    }
    for (vn, v) in [("42", LegacyVersion::V42), ("51", LegacyVersion::V51)] {
        for (en, e) in [("ascii", Encoding::Ascii), ("binary", Encoding::Binary)] {
            out.push((
                format!("legacy{vn}-{en}.vtk"),
                WriteOptions {
                    encoding: e,
                    legacy_version: v,
                    ..WriteOptions::default()
                },
            ));
        }
    }
    out
}

/// Whether scripts/vtk_check.py (VTK's unstructured readers) reads the file as it is. Structured
/// data is compared with VTK's own conversion in tests/structured.rs instead.
fn vtk_reads(path: &Path) -> bool {
    matches!(
        path.extension().and_then(|e| e.to_str()),
        Some("vtu" | "pvtu" | "vtk")
    ) && !path.components().any(|c| c.as_os_str() == "structured")
}

fn short(path: &Path) -> String {
    path.strip_prefix(root().join("fixtures"))
        .unwrap_or(path)
        .display()
        .to_string()
}

/// Whether any float array of `g` holds NaN or an infinity.
fn has_non_finite(g: &Grid) -> bool {
    g.point_data
        .arrays
        .iter()
        .chain(&g.cell_data.arrays)
        .chain(&g.field_data)
        .any(|a| a.data.is_float_with_non_finite())
}

trait NonFinite {
    fn is_float_with_non_finite(&self) -> bool;
}

impl NonFinite for formats::ArrayData {
    fn is_float_with_non_finite(&self) -> bool {
        match self {
            formats::ArrayData::Float32(v) => v.iter().any(|x| !x.is_finite()),
            formats::ArrayData::Float64(v) => v.iter().any(|x| !x.is_finite()),
            _ => false,
        }
    }
}

/// What VTK 9.1 itself cannot do, said once each on stderr instead of failing:
/// - a fixture VTK crashes on or reads as empty (VTK segfaults on some valid .pvtu files, and
///   reads nothing from ASCII files with NaN it wrote itself): only tetkit's outputs are compared;
/// - ASCII legacy output of arrays holding NaN/inf: VTK's legacy reader cannot parse `nan`/`inf`,
///   which its own writer writes the same way.
fn vtk_limitation(
    job: &Job,
    grid: &Grid,
    vtk: &Result<serde_json::Value, String>,
) -> Option<String> {
    let (path, _, is_fixture) = job;
    match vtk {
        Err(e) if *is_fixture => Some(format!(
            "VTK cannot read fixture {}: {}",
            short(path),
            e.lines().next().unwrap_or("")
        )),
        Ok(v) if *is_fixture && v["points"] == 0 && v["cells"] == 0 && grid.num_points() > 0 => {
            Some(format!("VTK reads fixture {} as empty", short(path)))
        }
        Err(e)
            if path.extension().is_some_and(|x| x == "vtk")
                && path.to_string_lossy().contains("-ascii")
                && has_non_finite(grid)
                // VTK names the token it stopped at, or, when a FIELD array's `nan` ends its
                // read early, only that its ASCII data did not parse.
                && (e.contains("nan")
                    || e.contains("inf")
                    || e.contains("Error reading ascii data")) =>
        {
            Some(format!(
                "VTK 9.1 cannot parse nan/inf in ASCII legacy {}",
                short(path)
            ))
        }
        _ => None,
    }
}

/// `(file, index of its grid, whether it is a fixture rather than tetkit's output)`.
type Job = (PathBuf, usize, bool);

/// Runs vtk_check.py over `jobs`, in batches of 12 files per VTK start-up on two threads (CI has
/// two cores), and compares each answer with its grid.
fn vtk_compare(jobs: &[Job], grids: &[Grid], problems: &mut Vec<String>) {
    let batches: Vec<&[Job]> = jobs.chunks(12).collect();
    let next = std::sync::atomic::AtomicUsize::new(0);
    let results = std::sync::Mutex::new(vec![Vec::new(); batches.len()]);
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| loop {
                let b = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(batch) = batches.get(b) else { break };
                let paths: Vec<PathBuf> = batch.iter().map(|j| j.0.clone()).collect();
                let r = vtk_check_many(&paths, false);
                results.lock().unwrap()[b] = r;
            });
        }
    });
    let results = results.into_inner().unwrap();
    let mut notes = Vec::new();
    for (job, res) in jobs.iter().zip(results.into_iter().flatten()) {
        let grid = &grids[job.1];
        if let Some(note) = vtk_limitation(job, grid, &res) {
            notes.push(note);
            continue;
        }
        match res {
            Ok(v) => {
                if let Err(e) = compare_with_vtk(grid, &v) {
                    problems.push(format!(
                        "{}: tetkit and VTK disagree:\n  {}",
                        short(&job.0),
                        e.replace('\n', "\n  ")
                    ));
                }
            }
            Err(e) => problems.push(format!("{}: {e}", short(&job.0))),
        }
    }
    for n in notes {
        eprintln!("note: {n}");
    }
}

/// Legacy binary files store LOOKUP_TABLE entries as unsigned char (VTK's format), so tetkit's
/// `lookup_table:*` field arrays come back quantized to 1/255 from them; everything else must be
/// bit-identical.
fn legacy_binary_equal(a: &Grid, b: &Grid) -> Result<(), String> {
    let prefix = formats::legacy::LOOKUP_TABLE_PREFIX;
    let strip = |g: &Grid| {
        let mut g = g.clone();
        g.field_data.retain(|x| !x.name.starts_with(prefix));
        g
    };
    grids_bit_equal(&strip(a), &strip(b))?;
    for x in a.field_data.iter().filter(|x| x.name.starts_with(prefix)) {
        let y = b
            .field_data
            .iter()
            .find(|y| y.name == x.name)
            .ok_or_else(|| format!("{} lost", x.name))?;
        let (xv, yv) = (x.data.to_f64_vec(), y.data.to_f64_vec());
        if xv.len() != yv.len()
            || xv
                .iter()
                .zip(&yv)
                .any(|(p, q)| (p.clamp(0.0, 1.0) - q).abs() > 0.5 / 255.0 + 1e-6)
        {
            return Err(format!("{} differs beyond 1/255 quantization", x.name));
        }
    }
    Ok(())
}

#[test]
fn every_fixture_in_every_encoding() {
    let fixtures = fixture_meshes();
    assert!(fixtures.len() >= 4, "expected fixtures, found {fixtures:?}");
    let use_vtk = require_vtk("every_fixture_in_every_encoding (VTK part)");
    let dir = tempdir();
    let mut problems = Vec::new();
    // Many fixtures hold one mesh in many encodings: round-trip each distinct grid once.
    let mut grids: Vec<Grid> = Vec::new();
    let mut names: Vec<String> = Vec::new();
    let mut vtk_jobs: Vec<Job> = Vec::new();
    for f in &fixtures {
        let g = match formats::read(f) {
            Ok(g) => g,
            Err(e) => {
                problems.push(format!("{}: tetkit cannot read it: {e}", short(f)));
                continue;
            }
        };
        let idx = match grids.iter().position(|x| grids_bit_equal(x, &g).is_ok()) {
            Some(i) => i,
            None => {
                grids.push(g);
                names.push(short(f));
                grids.len() - 1
            }
        };
        if vtk_reads(f) {
            vtk_jobs.push((f.clone(), idx, true));
        }
    }
    for (gi, grid) in grids.iter().enumerate() {
        let stem = names[gi].replace(['/', '.'], "_");
        for (suffix, opts) in encodings() {
            let out = dir.path().join(format!("{stem}.{suffix}"));
            let what = format!("{} -> {suffix}", names[gi]);
            if let Err(e) = formats::write(&out, grid, &opts) {
                problems.push(format!("{what}: write failed: {e}"));
                continue;
            }
            match formats::read(&out) {
                Ok(back) => {
                    let same = if suffix.ends_with("-binary.vtk") {
                        legacy_binary_equal(grid, &back)
                    } else {
                        grids_bit_equal(grid, &back)
                    };
                    if let Err(e) = same {
                        problems.push(format!("{what} -> read: not bit-identical: {e}"));
                    }
                }
                Err(e) => problems.push(format!("{what}: tetkit cannot read it back: {e}")),
            }
            vtk_jobs.push((out, gi, false));
        }
    }
    if use_vtk {
        vtk_compare(&vtk_jobs, &grids, &mut problems);
    }
    assert!(
        problems.is_empty(),
        "{} problems ({} fixtures, {} distinct meshes, {} encodings):\n{}",
        problems.len(),
        fixtures.len(),
        grids.len(),
        encodings().len(),
        problems.join("\n")
    );
    eprintln!(
        "{} fixtures, {} distinct meshes, each written in {} encodings and read back{}",
        fixtures.len(),
        grids.len(),
        encodings().len(),
        if use_vtk {
            " by tetkit and VTK"
        } else {
            " by tetkit"
        }
    );
}

/// The same through the command line: `convert` in each encoding, VTK reads the result.
#[test]
fn convert_cli_outputs_open_in_vtk() {
    let input = fixture("mixed/mixed.vtu");
    let dir = tempdir();
    let grid = formats::read(&input).unwrap();
    let mut outs = Vec::new();
    for (args, name) in [
        (
            vec!["--encoding", "appended", "--compress", "zlib"],
            "a.vtu",
        ),
        (vec!["--encoding", "binary", "--compress", "lz4"], "b.vtu"),
        (vec!["--encoding", "ascii"], "c.vtu"),
        (
            vec!["--encoding", "binary", "--legacy-version", "4.2"],
            "d.vtk",
        ),
        (
            vec!["--encoding", "ascii", "--legacy-version", "5.1"],
            "e.vtk",
        ),
    ] {
        let out = dir.path().join(name);
        let mut a = vec![
            "convert".to_string(),
            input.display().to_string(),
            out.display().to_string(),
        ];
        a.extend(args.iter().map(|s| s.to_string()));
        tetkit(&a).assert_success();
        let back = formats::read(&out).unwrap();
        grids_bit_equal(&grid, &back).unwrap_or_else(|e| panic!("{name}: {e}"));
        outs.push(out);
    }
    if !require_vtk("convert_cli_outputs_open_in_vtk") {
        return;
    }
    for (p, v) in outs.iter().zip(vtk_check_many(&outs, false)) {
        let v = v.unwrap_or_else(|e| panic!("{e}"));
        compare_with_vtk(&grid, &v).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    }
}
