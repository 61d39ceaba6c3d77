//! Helpers shared by the integration tests: running the real binary, temp dirs, fixtures, and the
//! VTK cross-check (scripts/vtk_check.py run by /usr/bin/python3).
//!
//! VTK policy: a test that needs VTK calls `if !common::require_vtk("test name") { return; }`.
//! Without VTK it skips with a message on stderr, unless `TETKIT_REQUIRE_VTK=1` (CI, land.sh), in
//! which case it fails.
#![allow(dead_code)]

pub mod look;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;

use serde_json::{json, Value};
use tetkit::formats::{self, ArrayData, DataArray, Grid};

/// The tetkit binary cargo built for these tests.
pub fn bin() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_tetkit"))
}

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `fixtures/<rel>`.
pub fn fixture(rel: &str) -> PathBuf {
    root().join("fixtures").join(rel)
}

/// A fresh temporary directory, removed when dropped.
pub fn tempdir() -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix("tetkit-test-")
        .tempdir()
        .expect("creating a temporary directory")
}

/// What one run of the binary gave.
#[derive(Debug)]
pub struct Run {
    /// Exit code (`None` when killed by a signal).
    pub code: Option<i32>,
    pub stdout: Vec<u8>,
    pub stderr: String,
    pub args: Vec<String>,
}

impl Run {
    pub fn success(&self) -> bool {
        self.code == Some(0)
    }

    pub fn stdout_str(&self) -> String {
        String::from_utf8_lossy(&self.stdout).into_owned()
    }

    /// (success, stdout, stderr), for tests that look at all three.
    pub fn parts(&self) -> (bool, String, String) {
        (self.success(), self.stdout_str(), self.stderr.clone())
    }

    /// Panics with the command, exit code and stderr unless the run succeeded.
    #[track_caller]
    pub fn assert_success(&self) -> &Run {
        assert!(
            self.success(),
            "tetkit {:?} failed with {:?}\nstderr:\n{}",
            self.args,
            self.code,
            self.stderr
        );
        self
    }

    /// Panics unless the run exited with a non-zero code (not a signal, not a panic) and stderr
    /// contains every one of `needles`.
    #[track_caller]
    pub fn assert_failure(&self, needles: &[&str]) -> &Run {
        assert!(
            matches!(self.code, Some(c) if c != 0),
            "tetkit {:?} should have failed but exited with {:?}\nstderr:\n{}",
            self.args,
            self.code,
            self.stderr
        );
        assert!(
            !self.stderr.contains("panicked"),
            "tetkit {:?} panicked:\n{}",
            self.args,
            self.stderr
        );
        for n in needles {
            assert!(
                self.stderr.contains(n),
                "tetkit {:?}: stderr lacks {n:?}:\n{}",
                self.args,
                self.stderr
            );
        }
        self
    }
}

fn to_strings<I, S>(args: I) -> Vec<String>
where
    I: IntoIterator<Item = S>,
    S: AsRef<std::ffi::OsStr>,
{
    args.into_iter()
        .map(|a| a.as_ref().to_string_lossy().into_owned())
        .collect()
}

/// Runs `tetkit ARGS` with an empty stdin.
pub fn tetkit<I, S>(args: I) -> Run
where
    I: IntoIterator<Item = S>,
    S: AsRef<std::ffi::OsStr>,
{
    tetkit_stdin(args, &[])
}

/// Runs `tetkit ARGS` feeding `input` on stdin.
pub fn tetkit_stdin<I, S>(args: I, input: &[u8]) -> Run
where
    I: IntoIterator<Item = S>,
    S: AsRef<std::ffi::OsStr>,
{
    let args = to_strings(args);
    let mut child = Command::new(bin())
        .args(&args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starting the tetkit binary");
    let mut stdin = child.stdin.take().expect("child stdin");
    let input = input.to_vec();
    // A writer thread, so a child that writes a lot before reading cannot deadlock us.
    let feeder = std::thread::spawn(move || {
        // The child may exit without reading everything (an error): a broken pipe is fine.
        let _ = stdin.write_all(&input);
    });
    let out = child.wait_with_output().expect("waiting for tetkit");
    let _ = feeder.join();
    Run {
        code: out.status.code(),
        stdout: out.stdout,
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        args,
    }
}

/// Every file name in `dir` (not recursive), sorted, for "no partial output" checks.
pub fn dir_listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// Every mesh under fixtures/ that a reader must accept: `.vtu`, `.pvtu`, `.vtk`, structured
/// `.vti`/`.vtr`/`.vts`, TetGen `.ele`, Medit `.mesh`, Gmsh `.msh` and Exodus `.exo` files,
/// recursively, sorted.
/// Folders named `hostile` or `bad` (inputs that must be refused), `surfaces` (polydata bodies for
/// scenes, not meshes) and `gmsh_vtk` (Gmsh's own VTK export of the .msh fixtures, kept for
/// comparison: it writes 2nd-order pyramids as linear ones with 13 or 14 points, which no reader
/// should accept) are left out.
pub fn fixture_meshes() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(rd) = std::fs::read_dir(dir) else {
            return;
        };
        for e in rd.filter_map(|e| e.ok()) {
            let p = e.path();
            if p.is_dir() {
                let name = e.file_name().to_string_lossy().to_ascii_lowercase();
                if !matches!(name.as_str(), "hostile" | "bad" | "surfaces" | "gmsh_vtk") {
                    walk(&p, out);
                }
            } else if let Some(ext) = p.extension().and_then(|x| x.to_str()) {
                if matches!(
                    ext.to_ascii_lowercase().as_str(),
                    "vtu" | "pvtu" | "vtk" | "ele" | "mesh" | "msh" | "exo" | "vti" | "vtr" | "vts"
                ) {
                    out.push(p);
                }
            }
        }
    }
    let mut out = Vec::new();
    walk(&root().join("fixtures"), &mut out);
    out.sort();
    out
}

// ---------------------------------------------------------------------------------------------
// VTK

/// The Python that has VTK (Debian's python3-vtk9); the `python3` on PATH may not.
pub const VTK_PYTHON: &str = "/usr/bin/python3";

/// Whether /usr/bin/python3 can `import vtk` (checked once per test binary).
pub fn vtk_available() -> bool {
    static AVAILABLE: OnceLock<bool> = OnceLock::new();
    *AVAILABLE.get_or_init(|| {
        Command::new(VTK_PYTHON)
            .args(["-c", "import vtk"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .map(|s| s.success())
            .unwrap_or(false)
    })
}

/// Whether `TETKIT_REQUIRE_VTK=1` is set.
pub fn vtk_required() -> bool {
    std::env::var("TETKIT_REQUIRE_VTK").is_ok_and(|v| v == "1")
}

/// True when VTK can be used. Otherwise: panics if `TETKIT_REQUIRE_VTK=1`, else prints why
/// `test` is skipped and returns false.
#[track_caller]
pub fn require_vtk(test: &str) -> bool {
    if vtk_available() {
        return true;
    }
    if vtk_required() {
        panic!(
            "{test}: TETKIT_REQUIRE_VTK=1 but {VTK_PYTHON} cannot import vtk (install python3-vtk9)"
        );
    }
    eprintln!(
        "SKIPPED {test}: {VTK_PYTHON} cannot import vtk (set TETKIT_REQUIRE_VTK=1 to fail instead)"
    );
    false
}

/// Runs a Python snippet with VTK's Python; panics with its stderr if it fails. Returns stdout.
#[track_caller]
pub fn vtk_python(code: &str, args: &[&str]) -> String {
    let out = Command::new(VTK_PYTHON)
        .arg("-c")
        .arg(code)
        .args(args)
        .output()
        .expect("running /usr/bin/python3");
    assert!(
        out.status.success(),
        "python failed ({:?}):\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// scripts/vtk_check.py's JSON for `path`, or VTK's complaint.
pub fn vtk_check_result(path: &Path, volume: bool) -> Result<Value, String> {
    let mut cmd = Command::new(VTK_PYTHON);
    cmd.arg(root().join("scripts/vtk_check.py")).arg(path);
    if volume {
        cmd.arg("--volume");
    }
    let out = cmd
        .output()
        .map_err(|e| format!("running vtk_check.py: {e}"))?;
    if out.status.code().is_none() {
        return Err(format!(
            "VTK crashed reading {} ({:?})",
            path.display(),
            out.status
        ));
    }
    if !out.status.success() {
        return Err(format!(
            "vtk_check.py {} failed ({:?}): {}",
            path.display(),
            out.status,
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    serde_json::from_slice(&out.stdout).map_err(|e| format!("vtk_check.py output is not JSON: {e}"))
}

/// scripts/vtk_check.py's JSON for each of `paths`, from one VTK start-up: `Err` with VTK's
/// complaint for a file it cannot read. If VTK crashes (it segfaults on some valid files), each
/// file is retried alone so the crash is pinned on the file that causes it.
pub fn vtk_check_many(paths: &[PathBuf], volume: bool) -> Vec<Result<Value, String>> {
    if paths.len() == 1 {
        return vec![vtk_check_result(&paths[0], volume)];
    }
    if paths.is_empty() {
        return Vec::new();
    }
    let mut cmd = Command::new(VTK_PYTHON);
    cmd.arg(root().join("scripts/vtk_check.py")).args(paths);
    if volume {
        cmd.arg("--volume");
    }
    let out = cmd.output().expect("running vtk_check.py");
    if !out.status.success() {
        return paths.iter().map(|p| vtk_check_result(p, volume)).collect();
    }
    let list: Vec<Value> =
        serde_json::from_slice(&out.stdout).expect("vtk_check.py output is a JSON list");
    assert_eq!(list.len(), paths.len());
    list.into_iter()
        .map(|v| match v.get("error") {
            Some(e) => Err(format!("VTK cannot read {}: {}", v["file"], e)),
            None => Ok(v),
        })
        .collect()
}

/// scripts/vtk_check.py's JSON for `path`; panics if VTK cannot read it.
#[track_caller]
pub fn vtk_check(path: &Path, volume: bool) -> Value {
    match vtk_check_result(path, volume) {
        Ok(v) => v,
        Err(e) => panic!("{e}"),
    }
}

// ---------------------------------------------------------------------------------------------
// Checksums, computed exactly as scripts/vtk_check.py computes them.

/// CRC-32 (IEEE, zlib's), so Python's `zlib.crc32` gives the same number.
pub fn crc32(bytes: &[u8]) -> u32 {
    static TABLE: OnceLock<[u32; 256]> = OnceLock::new();
    let table = TABLE.get_or_init(|| {
        let mut t = [0u32; 256];
        for (i, slot) in t.iter_mut().enumerate() {
            let mut c = i as u32;
            for _ in 0..8 {
                c = if c & 1 != 0 {
                    0xEDB8_8320 ^ (c >> 1)
                } else {
                    c >> 1
                };
            }
            *slot = c;
        }
        t
    });
    let mut c = !0u32;
    for &b in bytes {
        c = table[((c ^ b as u32) & 0xFF) as usize] ^ (c >> 8);
    }
    !c
}

/// Exact integer sum of an integer array, as a decimal string; `None` for floats and strings.
fn int_sum(data: &ArrayData) -> Option<String> {
    fn s<T: Copy + Into<i128>>(v: &[T]) -> String {
        v.iter().map(|&x| x.into()).sum::<i128>().to_string()
    }
    Some(match data {
        ArrayData::Int8(v) => s(v),
        ArrayData::UInt8(v) => s(v),
        ArrayData::Int16(v) => s(v),
        ArrayData::UInt16(v) => s(v),
        ArrayData::Int32(v) => s(v),
        ArrayData::UInt32(v) => s(v),
        ArrayData::Int64(v) => s(v),
        ArrayData::UInt64(v) => s(v),
        _ => return None,
    })
}

/// vtk_check.py's summary of one array (name, type, components, component names, tuples, values,
/// crc32, and `sum` for integers). Float sums are left out: the CRC already says bit-identical.
pub fn array_summary(a: &DataArray) -> Value {
    let mut v = json!({
        "name": a.name,
        "type": a.data.type_name(),
        "components": a.components,
        "component_names": a.component_names,
        "tuples": a.tuples(),
        "values": a.data.len(),
        "crc32": crc32(&a.data.le_bytes()),
    });
    if let Some(s) = int_sum(&a.data) {
        v["sum"] = json!(s);
    }
    v
}

/// Summary of a structural array (cell types, offsets, connectivity, faces): what vtk_check.py
/// reports for those (no name, type or components).
fn structural_summary(data: ArrayData) -> Value {
    let a = array_summary(&DataArray::new("", 1, data));
    json!({"values": a["values"], "crc32": a["crc32"], "sum": a["sum"]})
}

fn i64_summary(v: &[i64]) -> Value {
    structural_summary(ArrayData::Int64(v.to_vec()))
}

/// Compares the keys of `ours` with the same keys in `theirs`; component names count only when
/// either side has some (VTK reports none when a file names none).
fn compare_summary(what: &str, ours: &Value, theirs: &Value, errors: &mut Vec<String>) {
    let Some(obj) = ours.as_object() else { return };
    for (k, v) in obj {
        if k == "name" && what.starts_with("Points") {
            continue;
        }
        let t = &theirs[k];
        if t != v {
            errors.push(format!("{what}: {k}: tetkit {v}, VTK {t}"));
        }
    }
}

fn compare_arrays(what: &str, ours: &[DataArray], theirs: &Value, errors: &mut Vec<String>) {
    let empty = Vec::new();
    let theirs = theirs.as_array().unwrap_or(&empty);
    let their_names: Vec<&str> = theirs.iter().filter_map(|a| a["name"].as_str()).collect();
    // tetkit keeps a legacy LOOKUP_TABLE block as field data `lookup_table:NAME`; VTK reading a
    // legacy file attaches it to the scalars instead, so it is not among VTK's arrays there.
    let ours: Vec<&DataArray> = ours
        .iter()
        .filter(|a| {
            !a.name.starts_with(formats::legacy::LOOKUP_TABLE_PREFIX)
                || their_names.contains(&a.name.as_str())
        })
        .collect();
    let our_names: Vec<&str> = ours.iter().map(|a| a.name.as_str()).collect();
    let (mut o, mut t) = (our_names.clone(), their_names.clone());
    o.sort_unstable();
    t.sort_unstable();
    if o != t {
        errors.push(format!(
            "{what}: arrays differ: tetkit {our_names:?}, VTK {their_names:?}"
        ));
        return;
    }
    for a in ours {
        if let Some(ta) = theirs.iter().find(|x| x["name"] == a.name.as_str()) {
            compare_summary(
                &format!("{what} '{}'", a.name),
                &array_summary(a),
                ta,
                errors,
            );
        }
    }
}

/// Checks that VTK's reading (`vtk`, from [`vtk_check`]) has the same counts, cell types, and
/// bit-identical points, cells and arrays (by CRC-32 and exact integer sums) as `grid`.
pub fn compare_with_vtk(grid: &Grid, vtk: &Value) -> Result<(), String> {
    let mut errors = Vec::new();
    if vtk["points"] != json!(grid.num_points()) {
        errors.push(format!(
            "points: tetkit {}, VTK {}",
            grid.num_points(),
            vtk["points"]
        ));
    }
    if vtk["cells"] != json!(grid.num_cells()) {
        errors.push(format!(
            "cells: tetkit {}, VTK {}",
            grid.num_cells(),
            vtk["cells"]
        ));
    }
    let types: serde_json::Map<String, Value> = grid
        .cell_type_counts()
        .into_iter()
        .map(|(t, n)| (t.to_string(), json!(n)))
        .collect();
    if vtk["cell_types"] != Value::Object(types.clone()) {
        errors.push(format!(
            "cell types: tetkit {types:?}, VTK {}",
            vtk["cell_types"]
        ));
    }
    if grid.num_points() > 0 {
        compare_summary(
            "Points",
            &array_summary(&grid.points),
            &vtk["points_array"],
            &mut errors,
        );
    }
    if grid.num_cells() > 0 {
        compare_summary(
            "cell types array",
            &structural_summary(ArrayData::UInt8(grid.cells.types.clone())),
            &vtk["types"],
            &mut errors,
        );
        compare_summary(
            "offsets",
            &i64_summary(&grid.cells.offsets),
            &vtk["offsets"],
            &mut errors,
        );
        compare_summary(
            "connectivity",
            &i64_summary(&grid.cells.connectivity),
            &vtk["connectivity"],
            &mut errors,
        );
    }
    match (
        &grid.cells.polyhedron_faces,
        vtk["polyhedron_faces"].is_null(),
    ) {
        (Some((faces, _)), false) => compare_summary(
            "polyhedron faces",
            &i64_summary(faces),
            &vtk["polyhedron_faces"],
            &mut errors,
        ),
        (Some((faces, _)), true) if !faces.is_empty() => {
            errors.push("polyhedron faces: tetkit has them, VTK none".into())
        }
        (None, false) => errors.push("polyhedron faces: VTK has them, tetkit none".into()),
        _ => {}
    }
    compare_arrays(
        "point data",
        &grid.point_data.arrays,
        &vtk["point_data"],
        &mut errors,
    );
    compare_arrays(
        "cell data",
        &grid.cell_data.arrays,
        &vtk["cell_data"],
        &mut errors,
    );
    compare_arrays(
        "field data",
        &grid.field_data,
        &vtk["field_data"],
        &mut errors,
    );
    if errors.is_empty() {
        Ok(())
    } else {
        Err(errors.join("\n"))
    }
}

/// Reads `path` with tetkit and with VTK and asserts they agree (see [`compare_with_vtk`]).
#[track_caller]
pub fn assert_vtk_agrees(path: &Path) {
    let grid = formats::read(path).unwrap_or_else(|e| panic!("tetkit cannot read it: {e}"));
    let vtk = vtk_check(path, false);
    if let Err(e) = compare_with_vtk(&grid, &vtk) {
        panic!("{}: tetkit and VTK disagree:\n{e}", path.display());
    }
}

/// Bit-exact equality of two grids (points, cells, every array with name, type, components and
/// component names); the error lists what differs.
pub fn grids_bit_equal(a: &Grid, b: &Grid) -> Result<(), String> {
    let mut errors = Vec::new();
    if !a.points.data.bit_eq(&b.points.data) || a.points.components != b.points.components {
        errors.push("points differ".to_string());
    }
    if a.cells.types != b.cells.types {
        errors.push("cell types differ".into());
    }
    if a.cells.offsets != b.cells.offsets {
        errors.push("offsets differ".into());
    }
    if a.cells.connectivity != b.cells.connectivity {
        errors.push("connectivity differs".into());
    }
    if a.cells.polyhedron_faces != b.cells.polyhedron_faces {
        errors.push("polyhedron faces differ".into());
    }
    for (what, x, y) in [
        ("point data", &a.point_data.arrays, &b.point_data.arrays),
        ("cell data", &a.cell_data.arrays, &b.cell_data.arrays),
        ("field data", &a.field_data, &b.field_data),
    ] {
        if x.len() != y.len() {
            errors.push(format!("{what}: {} arrays vs {}", x.len(), y.len()));
        }
        for ax in x {
            match y.iter().find(|ay| ay.name == ax.name) {
                None => errors.push(format!("{what} '{}' missing", ax.name)),
                Some(ay) if !ax.bit_eq(ay) => errors.push(format!(
                    "{what} '{}' differs ({} x{} vs {} x{})",
                    ax.name,
                    ax.data.type_name(),
                    ax.components,
                    ay.data.type_name(),
                    ay.components
                )),
                _ => {}
            }
        }
    }
    if errors.is_empty() {
        Ok(())
    } else {
        Err(errors.join("; "))
    }
}

/// The largest difference of any channel of any pixel between two 8-bit RGB images of one size.
pub fn max_channel_diff(a: &image::RgbImage, b: &image::RgbImage) -> u8 {
    a.pixels()
        .zip(b.pixels())
        .flat_map(|(p, q)| (0..3).map(move |k| p.0[k].abs_diff(q.0[k])))
        .max()
        .unwrap_or(0)
}
