//! Exodus II element blocks as other tools write them (`fixtures/newuser/make_exodus_names.py`).
//!
//! `elem_type` spelled out (`TETRAHEDRON`, `HEXAHEDRON`, `QUADRILATERAL`) or as libMesh and
//! Cubit name some shapes (`EDGE2`, a 3-node `SHELL3`) was refused ("unknown element type
//! 'TETRAHEDRON'"), while VTK 9.1's vtkExodusIIReader matches the first three letters and reads
//! all seven blocks (tetra, hexahedron, wedge, pyramid, quad, triangle, line). tetkit now matches
//! them as VTK does.
//!
//! A block with elements (`num_el_in_blk2` = 1) but no `connect2` was silently read as empty:
//! its cells were lost and the file converted without a word. VTK refuses the file ("Could not
//! read block params"); tetkit now refuses it naming the block, and writes nothing.
//!
//! Element attributes (`attrib{k}`: a beam's area, a sphere's radius) were dropped without a
//! word; they are now read as cell arrays, as VTK reads them (tests/newuser_exodus_vectors.rs).

mod common;

use common::{fixture, tempdir, tetkit};
use tetkit::formats;
use tetkit::formats::cell_type as ct;

#[test]
fn element_types_named_as_vtk_reads_them() {
    let dir = tempdir();
    let input = fixture("newuser/exodus_vtk_names.exo");
    let out = dir.path().join("out.vtu");
    tetkit(["convert".as_ref(), input.as_os_str(), out.as_os_str()]).assert_success();
    let g = formats::read(&out).unwrap();
    assert_eq!(g.num_points(), 14);
    // Block order, as VTK's reader gives them: cell types 10, 12, 13, 14, 9, 5, 3.
    assert_eq!(
        g.cells.types,
        [
            ct::TETRA,
            ct::HEXAHEDRON,
            ct::WEDGE,
            ct::PYRAMID,
            ct::QUAD,
            ct::TRIANGLE,
            ct::LINE
        ]
    );
    // Exodus numbers nodes from 1: the SHELL3 triangle is nodes 10, 11, 13.
    assert_eq!(g.cells.cell(5), [9, 10, 12]);
    let ids = g.cell_data.get("ObjectId").expect("block ids");
    assert_eq!(
        ids.data.to_f64_vec(),
        [10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0]
    );
    let stress = g.cell_data.get("stress").expect("element variable");
    assert_eq!(
        stress.data.to_f64_vec(),
        [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
    );
    // The beam block's cross-section area, an element attribute, as VTK reads it: a cell array
    // named from attrib_name7, NaN in the blocks without it.
    let area = g
        .cell_data
        .get("area")
        .expect("element attribute")
        .data
        .to_f64_vec();
    assert!(area[..6].iter().all(|x| x.is_nan()), "{area:?}");
    assert_eq!(area[6], 0.25);
    let temp = g.point_data.get("temp").expect("nodal variable");
    assert_eq!(temp.data.get_f64(13), 13.0);

    // Step 1 of 2, as `FILE.exo@1`.
    let mut at = input.into_os_string();
    at.push("@1");
    let out1 = dir.path().join("step1.vtu");
    tetkit(["convert".as_ref(), at.as_os_str(), out1.as_os_str()]).assert_success();
    let g1 = formats::read(&out1).unwrap();
    assert_eq!(g1.cell_data.get("stress").unwrap().data.get_f64(6), 1006.0);
    assert_eq!(g1.point_data.get("temp").unwrap().data.get_f64(13), 113.0);
}

#[test]
fn a_block_without_connectivity_is_refused() {
    let dir = tempdir();
    let input = fixture("newuser/bad/exodus_no_connect.exo");
    let out = dir.path().join("out.vtu");
    tetkit(["convert".as_ref(), input.as_os_str(), out.as_os_str()]).assert_failure(&[
        "exodus_no_connect.exo",
        "element block 2 (id 20)",
        "num_el_in_blk2",
        "connect2",
    ]);
    assert!(!out.exists(), "no output on error");
}
