//! Output piped into a reader that stops early (`tetkit info mesh.vtu | head`,
//! `tetkit convert mesh.vtu - | head -c 100`): `info` used to panic ("failed printing to stdout:
//! Broken pipe", exit 101 with a backtrace) and `convert -` to fail with an error. Both now end
//! quietly, as `cat` does.

mod common;

use common::{bin, tempdir};
use std::io::Read;
use std::process::{Command, Stdio};
use tetkit::formats::{ArrayData, DataArray};
use tetkit::mesh::generate::structured_grid;

/// Runs tetkit with `args`, reads the first line of its stdout, closes the pipe and waits.
fn read_one_line_and_close(args: &[&std::ffi::OsStr]) -> (std::process::ExitStatus, String) {
    let mut child = Command::new(bin())
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut out = child.stdout.take().unwrap();
    let mut first = [0u8; 16];
    out.read_exact(&mut first).unwrap();
    drop(out);
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    (child.wait().unwrap(), err)
}

#[test]
fn a_reader_that_stops_early_ends_tetkit_quietly() {
    let dir = tempdir();
    // Enough arrays that `info` prints far more than a pipe buffer holds (64 KiB), so it is
    // still printing when the reader has gone.
    let mesh = structured_grid([12, 12, 12], [0.0; 3], [1.0; 3]);
    let mut grid = mesh.to_grid();
    let n = grid.num_points();
    for i in 0..1500 {
        grid.point_data.insert(DataArray::new(
            format!("array_{i}"),
            1,
            ArrayData::Float32((0..n).map(|k| (k + i) as f32).collect()),
        ));
    }
    let input = dir.path().join("many.vtu");
    tetkit::formats::write(&input, &grid, &Default::default()).unwrap();
    for args in [
        vec!["info".as_ref(), input.as_os_str()],
        vec![
            "convert".as_ref(),
            input.as_os_str(),
            "-".as_ref(),
            "--encoding".as_ref(),
            "ascii".as_ref(),
        ],
    ] {
        let (status, err) = read_one_line_and_close(&args);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(!err.contains("error"), "{args:?}: {err}");
        assert_ne!(status.code(), Some(101), "{args:?}: {err}");
        // Killed by SIGPIPE (as `cat` is), or done before the pipe closed.
        assert!(
            status.success() || status.code().is_none(),
            "{args:?}: {status:?} {err}"
        );
    }
}

/// A stream the writer refuses blames the output, not "<input>".
#[test]
fn a_refused_stream_names_stdout() -> Result<(), Box<dyn std::error::Error>> {
    let vtk = std::fs::read(common::fixture("gmsh/extruded.vtk"))?;
    let r = common::tetkit_stdin(["convert", "-", "-", "--to", "mesh"], &vtk);
    r.assert_failure(&["<stdout>", "Medit files hold"]);
    assert!(!r.stderr.contains("<input>"), "{}", r.stderr);
    assert!(
        r.stdout.is_empty(),
        "nothing written to a stream that failed"
    );
    Ok(())
}
