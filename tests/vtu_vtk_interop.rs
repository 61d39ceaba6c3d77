//! VTK 9.1 (python3-vtk9) reads every tetkit .vtu/.pvtu output, in every encoding and
//! compressor, with the same counts and array checksums. Skipped only when VTK is missing and
//! TETKIT_REQUIRE_VTK is not 1 (CI sets it).

mod vtu_support;

use formats::{Compression, Encoding, WriteOptions};
use std::path::PathBuf;
use vtu_support::*;

fn vtk_describe(files: &[PathBuf]) -> serde_json::Value {
    let script = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scripts/vtu_describe.py");
    let out = std::process::Command::new("/usr/bin/python3")
        .arg(script)
        .args(files)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn vtk_reads_every_tetkit_output_identically() {
    if !vtk_available() {
        eprintln!("skipping: /usr/bin/python3 has no vtk");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut jobs = Vec::new();
    for name in [
        "tet_appended_none_h64_le.vtu",
        "polyhedra_binary_zlib.vtu",
        "tet_3pieces.vtu",
    ] {
        let g = formats::read(&fixtures().join(name)).unwrap();
        for encoding in [Encoding::Appended, Encoding::Binary, Encoding::Ascii] {
            for compression in [
                Compression::None,
                Compression::Zlib,
                Compression::Lz4,
                Compression::Lzma,
            ] {
                if encoding == Encoding::Ascii && compression != Compression::None {
                    continue;
                }
                let opts = WriteOptions {
                    encoding,
                    compression,
                    ..WriteOptions::default()
                };
                let out = dir.path().join(format!(
                    "{}_{encoding:?}_{compression:?}.vtu",
                    name.trim_end_matches(".vtu")
                ));
                formats::write(&out, &g, &opts).unwrap();
                jobs.push((out, g.clone()));
            }
        }
        let out = dir
            .path()
            .join(format!("{}.pvtu", name.trim_end_matches(".vtu")));
        formats::vtu::pvtu::write(&out, &[g.clone(), g.clone()], &WriteOptions::default()).unwrap();
        let merged = formats::read(&out).unwrap();
        jobs.push((out, merged));
    }
    let files: Vec<PathBuf> = jobs.iter().map(|(p, _)| p.clone()).collect();
    let vtk = vtk_describe(&files);
    for (path, g) in &jobs {
        let key = path.to_str().unwrap();
        let m = &vtk[key];
        assert!(m.get("error").is_none(), "{key}: {}", m["error"]);
        check_grid(g, m, key);
    }
    assert_eq!(jobs.len(), 3 * 10);
}
