//! Files behind a UTF-8 byte order mark. A VTU with appended data
//! (`fixtures/newuser/make_bom_vtu.py`, which VTK 9.1 reads) was refused: "byte 1436: expected
//! the '_' that starts the appended data", since the XML parser's positions left out the mark's 3
//! bytes. TetGen files saved by a Windows editor: a UTF-8 byte order mark, CRLF line endings, comments
//! and blank lines (`fixtures/newuser/make_bom_tetgen.sh`). The byte order mark was read as part
//! of the first number ("the number of points is '\u{feff}', not an integer"), while the legacy,
//! Medit and VTU readers skip it; now TetGen files read as the same mesh without it.

mod common;

use common::{fixture, tempdir, tetkit};
use tetkit::formats;

#[test]
fn tetgen_files_with_a_byte_order_mark_read_as_without_it() {
    let dir = tempdir();
    let input = fixture("newuser/bom_box.1.ele");
    let out = dir.path().join("out.vtu");
    tetkit(["convert".as_ref(), input.as_os_str(), out.as_os_str()]).assert_success();
    let g = formats::read(&out).unwrap();
    assert_eq!(g.num_points(), 8);
    assert_eq!(g.num_cells(), 6);

    // The same files without the mark read the same.
    for ext in ["node", "ele"] {
        let bytes = std::fs::read(fixture(&format!("newuser/bom_box.1.{ext}"))).unwrap();
        std::fs::write(dir.path().join(format!("plain.1.{ext}")), &bytes[3..]).unwrap();
    }
    let plain = formats::read(&dir.path().join("plain.1.ele")).unwrap();
    let ours = formats::read(&input).unwrap();
    assert_eq!(plain.num_points(), ours.num_points());
    assert_eq!(plain.num_cells(), ours.num_cells());
}

#[test]
fn a_vtu_with_a_byte_order_mark_keeps_its_appended_data() {
    let dir = tempdir();
    let input = fixture("newuser/bom_appended.vtu");
    let out = dir.path().join("out.vtu");
    tetkit(["convert".as_ref(), input.as_os_str(), out.as_os_str()]).assert_success();
    let g = formats::read(&out).unwrap();
    assert_eq!(g.num_points(), 5);
    assert_eq!(g.num_cells(), 2);
    let t = g.point_data.get("temperature").expect("temperature kept");
    assert_eq!(t.components, 1);
    assert_eq!(t.data.get_f64(4), 40.0);
    assert!(g.cell_data.get("material").is_some());
    if common::require_vtk("a_vtu_with_a_byte_order_mark_keeps_its_appended_data") {
        common::vtk_check(&out, true);
    }
}

/// Gmsh files behind a byte order mark were refused ("line 1: expected $MeshFormat, found
/// '\u{feff}$MeshFormat'"); they now read as without it, ASCII and binary, 2.2 and 4.1.
#[test]
fn gmsh_files_with_a_byte_order_mark_read_as_without_it() {
    let dir = tempdir();
    for name in [
        "block_hole_22.msh",
        "block_hole_41_bin.msh",
        "block_hole_22_bin.msh",
    ] {
        let plain = fixture(&format!("msh/{name}"));
        let mut bytes = b"\xef\xbb\xbf".to_vec();
        bytes.extend(std::fs::read(&plain).unwrap());
        let marked = dir.path().join(name);
        std::fs::write(&marked, &bytes).unwrap();
        let out = dir.path().join(format!("{name}.vtu"));
        tetkit(["convert".as_ref(), marked.as_os_str(), out.as_os_str()]).assert_success();
        let a = formats::read(&marked).unwrap();
        let b = formats::read(&plain).unwrap();
        assert_eq!(a.num_points(), b.num_points(), "{name}");
        assert_eq!(a.num_cells(), b.num_cells(), "{name}");
        assert_eq!(a.points, b.points, "{name}");
    }
}
