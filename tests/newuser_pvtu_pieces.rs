//! A .pvtu whose `<Piece Source>` names a .pvtu (itself, or a collection of collections, as a
//! hand-edited file can) was read as a .vtu and refused with "this is a parallel file: name it
//! .pvtu", blaming a file that is named .pvtu. The piece is now named as what is wrong.

mod common;

use common::{tempdir, tetkit};

#[test]
fn a_piece_that_is_a_pvtu_is_named() {
    let dir = tempdir();
    for (file, source) in [("self.pvtu", "self.pvtu"), ("outer.pvtu", "inner.pvtu")] {
        let path = dir.path().join(file);
        std::fs::write(
            &path,
            format!(
                r#"<?xml version="1.0"?>
<VTKFile type="PUnstructuredGrid" version="1.0"><PUnstructuredGrid GhostLevel="0">
<PPoints><PDataArray type="Float32" NumberOfComponents="3"/></PPoints>
<Piece Source="{source}"/></PUnstructuredGrid></VTKFile>
"#
            ),
        )
        .unwrap();
    }
    std::fs::copy(dir.path().join("self.pvtu"), dir.path().join("inner.pvtu")).unwrap();
    for (file, source) in [("self.pvtu", "self.pvtu"), ("outer.pvtu", "inner.pvtu")] {
        let r = tetkit(["info".as_ref(), dir.path().join(file).as_os_str()]);
        r.assert_failure(&[file, "piece 0", source, "pieces must be .vtu files"]);
        assert!(!r.stderr.contains("name it .pvtu"), "{}", r.stderr);
    }
}
