//! Tests of Lagrange, Bezier and convex point set cells on the fixtures of scripts/make_highorder_fixtures.py.

use crate::{cell_type as ct, Encoding, Format, Grid, LegacyVersion, Result, WriteOptions};
use std::path::{Path, PathBuf};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures/highorder")
        .join(name)
}

/// What VTK 9.1 read back from each fixture (the script prints it): (type, count).
const COUNTS: [(u8, usize); 13] = [
    (ct::CONVEX_POINT_SET, 1),
    (ct::LAGRANGE_CURVE, 1),
    (ct::LAGRANGE_TRIANGLE, 2),
    (ct::LAGRANGE_QUADRILATERAL, 1),
    (ct::LAGRANGE_TETRAHEDRON, 12),
    (ct::LAGRANGE_HEXAHEDRON, 1),
    (ct::LAGRANGE_WEDGE, 2),
    (ct::BEZIER_CURVE, 1),
    (ct::BEZIER_TRIANGLE, 2),
    (ct::BEZIER_QUADRILATERAL, 1),
    (ct::BEZIER_TETRAHEDRON, 12),
    (ct::BEZIER_HEXAHEDRON, 1),
    (ct::BEZIER_WEDGE, 2),
];

const FIXTURES: [&str; 3] = ["highorder.vtu", "highorder_51.vtk", "highorder_42.vtk"];

fn tiny(t: u8, n: usize) -> Grid {
    let mut g = Grid::default();
    g.points.data = crate::ArrayData::Float64((0..3 * n).map(|k| k as f64).collect());
    let ids: Vec<i64> = (0..n as i64).collect();
    g.cells.push(t, &ids);
    g
}

#[test]
fn the_new_types_have_names_shapes_and_minimum_sizes() {
    let all: Vec<u8> = (68..=81).chain([ct::CONVEX_POINT_SET]).collect();
    for &t in &all {
        assert!(ct::is_known(t), "type {t}");
        assert_ne!(ct::name(t), "unknown", "type {t}");
        assert_eq!(ct::fixed_size(t), None, "type {t}");
    }
    assert_eq!(ct::name(ct::LAGRANGE_TETRAHEDRON), "lagrange_tetrahedron");
    assert_eq!(ct::name(ct::BEZIER_PYRAMID), "bezier_pyramid");
    assert_eq!(ct::name(ct::CONVEX_POINT_SET), "convex_point_set");
    for (lagrange, bezier, linear, dim) in [
        (ct::LAGRANGE_CURVE, ct::BEZIER_CURVE, ct::LINE, 1),
        (ct::LAGRANGE_TRIANGLE, ct::BEZIER_TRIANGLE, ct::TRIANGLE, 2),
        (
            ct::LAGRANGE_QUADRILATERAL,
            ct::BEZIER_QUADRILATERAL,
            ct::QUAD,
            2,
        ),
        (
            ct::LAGRANGE_TETRAHEDRON,
            ct::BEZIER_TETRAHEDRON,
            ct::TETRA,
            3,
        ),
        (
            ct::LAGRANGE_HEXAHEDRON,
            ct::BEZIER_HEXAHEDRON,
            ct::HEXAHEDRON,
            3,
        ),
        (ct::LAGRANGE_WEDGE, ct::BEZIER_WEDGE, ct::WEDGE, 3),
        (ct::LAGRANGE_PYRAMID, ct::BEZIER_PYRAMID, ct::PYRAMID, 3),
    ] {
        for t in [lagrange, bezier] {
            assert!(ct::is_higher_order(t));
            assert_eq!(ct::linear_counterpart(t), Some(linear));
            assert_eq!(ct::min_size(t), ct::fixed_size(linear));
            assert_eq!(ct::dimension(t), dim);
        }
        assert!(ct::is_lagrange(lagrange) && !ct::is_bezier(lagrange));
        assert!(ct::is_bezier(bezier) && !ct::is_lagrange(bezier));
    }
    assert_eq!(ct::min_size(ct::CONVEX_POINT_SET), Some(4));
    assert_eq!(ct::dimension(ct::CONVEX_POINT_SET), 3);
    assert_eq!(ct::linear_counterpart(ct::QUADRATIC_TETRA), None);
    assert_eq!(ct::min_size(ct::POLYGON), None);
    assert!(!ct::is_known(67) && !ct::is_known(82));
}

#[test]
fn too_few_points_for_the_shape_are_refused_by_name() {
    assert_eq!(tiny(ct::LAGRANGE_TETRAHEDRON, 4).validate(), Ok(()));
    assert_eq!(
        tiny(ct::LAGRANGE_TETRAHEDRON, 3).validate(),
        Err("cell 0 is a lagrange_tetrahedron with 3 points, expected at least 4".into())
    );
    assert_eq!(
        tiny(ct::BEZIER_HEXAHEDRON, 7).validate(),
        Err("cell 0 is a bezier_hexahedron with 7 points, expected at least 8".into())
    );
    assert!(tiny(ct::CONVEX_POINT_SET, 3).validate().is_err());
    assert_eq!(tiny(ct::CONVEX_POINT_SET, 5).validate(), Ok(()));
}

#[test]
fn vtk_written_fixtures_read_with_every_cell_and_array() -> Result<()> {
    let first = crate::read(&fixture(FIXTURES[0]))?;
    for name in FIXTURES {
        let g = crate::read(&fixture(name))?;
        assert_eq!(g.cell_type_counts(), COUNTS.to_vec(), "{name}");
        assert_eq!(g.num_points(), 302, "{name}");
        let hod = g.cell_data.get("HigherOrderDegrees");
        assert!(
            hod.is_some_and(|a| a.components == 3 && a.data.type_name() == "Int32"),
            "{name}: {hod:?}"
        );
        // The 64-node order 3 hexahedra, cells 16 and 35 in the script's order.
        assert_eq!(g.cells.cell(16).len(), 64, "{name}");
        assert_eq!(g.cells.cell(35).len(), 64, "{name}");
        // VTK 9.1 writes 4.2 files in its new hexahedron order but reads any file before 5.1
        // in the old one (edges 10 and 11 traded); tetkit reads as VTK does.
        let mut want = first.clone();
        if name.ends_with("_42.vtk") {
            want.swap_hex_edges_10_11();
        }
        assert_eq!(g.cells, want.cells, "{name}");
        for a in &first.cell_data.arrays {
            let b = g.cell_data.get(&a.name);
            assert!(b.is_some_and(|b| b.data == a.data), "{name}: {}", a.name);
        }
    }
    Ok(())
}

/// Cell type counts as VTK 9.1 reads `path`, or `None` where /usr/bin/python3 has no vtk.
fn vtk_counts(path: &Path) -> Option<Vec<(u8, usize)>> {
    const CODE: &str = "import sys, vtk
p = sys.argv[1]
r = vtk.vtkXMLUnstructuredGridReader() if p.endswith('.vtu') else vtk.vtkUnstructuredGridReader()
r.SetFileName(p)
r.Update()
g = r.GetOutput()
c = {}
for i in range(g.GetNumberOfCells()):
    c[g.GetCellType(i)] = c.get(g.GetCellType(i), 0) + 1
print(' '.join('%d:%d' % kv for kv in sorted(c.items())))
";
    let out = std::process::Command::new("/usr/bin/python3")
        .arg("-c")
        .arg(CODE)
        .arg(path)
        .output()
        .ok()?;
    if !out.status.success() {
        eprintln!(
            "VTK check skipped: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        return None;
    }
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    Some(
        text.split_whitespace()
            .filter_map(|kv| {
                let (t, n) = kv.split_once(':')?;
                Some((t.parse().ok()?, n.parse().ok()?))
            })
            .collect(),
    )
}

#[test]
fn they_round_trip_through_vtu_and_legacy_and_vtk_reads_them_back() -> Result<()> {
    let dir = tempfile::tempdir().map_err(|e| crate::FormatError::whole(e.to_string()))?;
    let g = crate::read(&fixture("highorder.vtu"))?;
    let mut checked = 0;
    for (k, (ext, encoding, legacy_version)) in [
        ("vtu", Encoding::Appended, LegacyVersion::V51),
        ("vtu", Encoding::Ascii, LegacyVersion::V51),
        ("vtk", Encoding::Binary, LegacyVersion::V51),
        ("vtk", Encoding::Ascii, LegacyVersion::V51),
        ("vtk", Encoding::Binary, LegacyVersion::V42),
        ("vtk", Encoding::Ascii, LegacyVersion::V42),
    ]
    .into_iter()
    .enumerate()
    {
        let path = dir.path().join(format!("out{k}.{ext}"));
        let opts = WriteOptions {
            encoding,
            legacy_version,
            ..WriteOptions::default()
        };
        crate::write(&path, &g, &opts)?;
        let back = crate::read(&path)?;
        assert_eq!(back.cells, g.cells, "{}", path.display());
        assert!(back.points.bit_eq(&g.points), "{}", path.display());
        for a in g.point_data.arrays.iter().chain(&g.cell_data.arrays) {
            let b = back
                .point_data
                .get(&a.name)
                .or_else(|| back.cell_data.get(&a.name));
            assert!(
                b.is_some_and(|b| b.bit_eq(a)),
                "{}: {}",
                path.display(),
                a.name
            );
        }
        if let Some(counts) = vtk_counts(&path) {
            assert_eq!(counts, COUNTS.to_vec(), "VTK reading {}", path.display());
            checked += 1;
        }
    }
    eprintln!("VTK read back {checked} of 6 written files");
    Ok(())
}

#[test]
fn tetgen_and_medit_refuse_them_by_name() -> Result<()> {
    let g = crate::read(&fixture("highorder.vtu"))?;
    let dir = tempfile::tempdir().map_err(|e| crate::FormatError::whole(e.to_string()))?;
    let e = crate::write(&dir.path().join("a.ele"), &g, &WriteOptions::default()).err();
    assert!(
        e.as_ref()
            .is_some_and(|e| e.to_string().contains("lagrange_curve")),
        "{e:?}"
    );
    let mut out = Vec::new();
    let e = crate::write_to(&mut out, Format::Medit, &g, &WriteOptions::default()).err();
    let msg = e.map(|e| e.to_string()).unwrap_or_default();
    for part in [
        "12 lagrange_tetrahedron cells",
        "1 convex_point_set cells",
        "2 bezier_wedge cells",
    ] {
        assert!(msg.contains(part), "{msg}");
    }
    Ok(())
}

#[test]
fn old_files_higher_order_hexahedra_trade_edges_10_and_11() {
    // An order-3 hexahedron (64 nodes, two per edge): edge 10's nodes are ids 28-29, edge 11's
    // 30-31, as VTK 9.1 converts them; the swap undoes itself.
    let mut g = tiny(ct::LAGRANGE_HEXAHEDRON, 64);
    let before = g.cells.clone();
    g.swap_hex_edges_10_11();
    let ids = g.cells.cell(0);
    assert_eq!(&ids[26..34], &[26, 27, 30, 31, 28, 29, 32, 33]);
    g.swap_hex_edges_10_11();
    assert_eq!(g.cells, before);
    // Orders from HigherOrderDegrees: (1, 1, 3) has no x or y edge nodes, two on each z edge.
    let mut g = tiny(ct::BEZIER_HEXAHEDRON, 16);
    g.cell_data.insert(crate::DataArray::new(
        "HigherOrderDegrees",
        3,
        crate::ArrayData::Int32(vec![1, 1, 3]),
    ));
    g.swap_hex_edges_10_11();
    assert_eq!(&g.cells.cell(0)[8..16], &[8, 9, 10, 11, 14, 15, 12, 13]);
}
