//! Structured data (image data, rectilinear and curvilinear grids; XML and legacy) read as the
//! voxels and hexahedra VTK itself makes of them, compared with VTK's own conversion
//! (vtkAppendFilter), then converted, rendered and read back by VTK. Fixtures come from
//! scripts/make_structured_fixtures.py (VTK 9.1's writers).

mod common;

use common::{fixture, require_vtk, tempdir, tetkit, vtk_check};
use tetkit::formats::{self, cell_type, ArrayData, Grid};

fn read(rel: &str) -> Grid {
    formats::read(&fixture(&format!("structured/{rel}")))
        .unwrap_or_else(|e| panic!("tetkit cannot read {rel}: {e}"))
}

/// Whether `ours` is what VTK's conversion `theirs` holds: the same cells exactly, the same
/// points to the precision VTK kept (vtkAppendFilter stores image points as Float32), and every
/// array VTK has, with the same type, components and values (bit for bit, or to relative `tol`
/// where VTK wrote ASCII with fewer digits).
fn same_as_vtk(ours: &Grid, theirs: &Grid, check_points: bool, tol: f64) -> Result<(), String> {
    let mut errors = Vec::new();
    if ours.cells.types != theirs.cells.types {
        errors.push(format!(
            "cell types: ours {:?}..., VTK {:?}...",
            &ours.cells.types[..ours.cells.types.len().min(4)],
            &theirs.cells.types[..theirs.cells.types.len().min(4)]
        ));
    }
    if ours.cells.connectivity != theirs.cells.connectivity
        || ours.cells.offsets != theirs.cells.offsets
    {
        errors.push("connectivity differs".into());
    }
    if ours.num_points() != theirs.num_points() {
        errors.push(format!(
            "points: ours {}, VTK {}",
            ours.num_points(),
            theirs.num_points()
        ));
    } else if check_points {
        let (a, b) = (
            ours.points.data.to_f64_vec(),
            theirs.points.data.to_f64_vec(),
        );
        let f32_ref = matches!(theirs.points.data, ArrayData::Float32(_));
        for (k, (x, y)) in a.iter().zip(&b).enumerate() {
            let tol = if f32_ref {
                2.0 * f32::EPSILON as f64 * x.abs().max(1.0)
            } else {
                1e-12 * x.abs().max(1.0)
            };
            if (x - y).abs() > tol {
                errors.push(format!(
                    "point {} coordinate {}: ours {x}, VTK {y}",
                    k / 3,
                    k % 3
                ));
                break;
            }
        }
    }
    for (what, mine, vtk) in [
        ("point", &ours.point_data, &theirs.point_data),
        ("cell", &ours.cell_data, &theirs.cell_data),
    ] {
        for v in &vtk.arrays {
            match mine.get(&v.name) {
                None => errors.push(format!("{what} array '{}' missing", v.name)),
                Some(m) if !close(m, v, tol) => errors.push(format!(
                    "{what} array '{}' differs ({} x{} vs VTK {} x{})",
                    v.name,
                    m.data.type_name(),
                    m.components,
                    v.data.type_name(),
                    v.components
                )),
                Some(_) => {}
            }
        }
    }
    if errors.is_empty() {
        Ok(())
    } else {
        Err(errors.join("\n"))
    }
}

fn close(a: &formats::DataArray, b: &formats::DataArray, tol: f64) -> bool {
    if tol == 0.0 || a.data.scalar_type() != b.data.scalar_type() {
        return a.bit_eq(b);
    }
    let (x, y) = (a.data.to_f64_vec(), b.data.to_f64_vec());
    a.components == b.components
        && x.len() == y.len()
        && x.iter()
            .zip(&y)
            .all(|(p, q)| (p - q).abs() <= tol * p.abs().max(1.0))
}

#[test]
fn structured_files_read_as_vtk_converts_them() {
    let cases = [
        ("image.vti", "image_vtk.vtu", cell_type::VOXEL),
        ("image_ascii.vti", "image_vtk.vtu", cell_type::VOXEL),
        ("image_slice.vti", "image_slice_vtk.vtu", cell_type::PIXEL),
        ("wavelet.vti", "wavelet_vtk.vtu", cell_type::VOXEL),
        ("rect.vtr", "rect_vtk.vtu", cell_type::VOXEL),
        ("rect.vtk", "rect_vtk.vtu", cell_type::VOXEL),
        ("curvi.vts", "curvi_vtk.vtu", cell_type::HEXAHEDRON),
        ("curvi.vtk", "curvi_vtk.vtu", cell_type::HEXAHEDRON),
        (
            "parallel/wavelet.pvti",
            "parallel/wavelet_vtk.vtu",
            cell_type::VOXEL,
        ),
        (
            "parallel/wavelet_sg.pvts",
            "parallel/wavelet_sg_vtk.vtu",
            cell_type::HEXAHEDRON,
        ),
        (
            "parallel/rect.pvtr",
            "parallel/rect_vtk.vtu",
            cell_type::VOXEL,
        ),
    ];
    let mut problems = Vec::new();
    for (file, reference, ty) in cases {
        let (ours, theirs) = (read(file), read(reference));
        assert!(ours.num_cells() > 0, "{file}: no cells");
        assert!(
            ours.cells.types.iter().all(|&t| t == ty),
            "{file}: cell types"
        );
        if let Err(e) = same_as_vtk(&ours, &theirs, true, 0.0) {
            problems.push(format!("{file} vs {reference}:\n{e}"));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n\n"));
}

#[test]
fn image_points_keep_double_precision_far_from_the_origin() {
    let g = read("image.vti");
    let ArrayData::Float64(p) = &g.points.data else {
        panic!("image points are {}", g.points.data.type_name());
    };
    // Point (i, j, k) = (1, 0, 0): origin + a quarter turn of (0.5, 0, 0).
    assert_eq!(&p[3..6], &[100000.5, -2.5, 7.0]);
    // The last point (4, 3, 2): index (2, 0.75, 2) turned to (-0.75, 2, 2).
    assert_eq!(&p[p.len() - 3..], &[100000.5 - 0.75, -1.0, 9.0]);
}

#[test]
fn legacy_structured_points_follow_what_vtk_wrote() {
    // VTK's legacy writer keeps 6 digits of the origin and no direction; cells and data are the
    // same as the XML file's.
    let g = read("image.vtk");
    same_as_vtk(&g, &read("image_vtk.vtu"), false, 1e-9).unwrap();
    let p = g.points.data.to_f64_vec();
    assert_eq!(&p[..3], &[100000.0, -3.0, 7.0]);
    assert_eq!(&p[p.len() - 3..], &[100002.0, -2.25, 9.0]);
}

#[test]
fn pieces_sharing_boundaries_make_one_lattice() {
    // Three pieces of different extents (-4..-2, -2..4 x -3..0, -2..4 x 0..3): one 9 x 7 x 3
    // lattice, as VTK reads it, not 3 meshes side by side.
    let g = read("wavelet.vti");
    assert_eq!((g.num_points(), g.num_cells()), (9 * 7 * 3, 8 * 6 * 2));
    // Two pieces that each hold the whole extent read as one.
    let g = read("image.vti");
    assert_eq!((g.num_points(), g.num_cells()), (60, 24));
    // The same from parallel files naming one piece file each.
    let g = read("parallel/wavelet.pvti");
    assert_eq!((g.num_points(), g.num_cells()), (9 * 7 * 3, 8 * 6 * 2));
    assert!(formats::read(&fixture("structured/wavelet.vti"))
        .unwrap()
        .point_data
        .get("RTData")
        .unwrap()
        .bit_eq(g.point_data.get("RTData").unwrap()));
}

#[test]
fn broken_parallel_structured_files_name_the_piece() {
    let dir = tempdir();
    let src = fixture("structured/parallel");
    for f in [
        "wavelet_0.vti",
        "wavelet_1.vti",
        "wavelet_2.vti",
        "rect_0.vtr",
    ] {
        std::fs::copy(src.join(f), dir.path().join(f)).unwrap();
    }
    let text = std::fs::read_to_string(src.join("wavelet.pvti")).unwrap();
    let cases = [
        // A piece of another type.
        (
            "other.pvti",
            text.replace("wavelet_2.vti", "rect_0.vtr"),
            vec!["other.pvti", "piece 2", "RectilinearGrid", "ImageData"],
        ),
        // An extent the piece file does not hold.
        (
            "extent.pvti",
            text.replace("Extent=\"-4 -2 -3 3 0 2\"", "Extent=\"-4 -1 -3 3 0 2\""),
            vec!["extent.pvti", "piece 0", "does not match"],
        ),
        // Pieces that leave a hole in the whole extent.
        (
            "hole.pvti",
            text.replace(
                "<Piece Extent=\"-2 4 0 3 0 2\" Source=\"wavelet_2.vti\"/>",
                "",
            ),
            vec!["hole.pvti", "uncovered"],
        ),
    ];
    for (name, body, needles) in cases {
        assert_ne!(body, text, "{name}: the fixture text changed");
        let p = dir.path().join(name);
        std::fs::write(&p, body).unwrap();
        tetkit(["info", p.to_str().unwrap()]).assert_failure(&needles);
    }
}

#[test]
fn cli_reads_converts_and_renders_structured_data() {
    let dir = tempdir();
    let info = tetkit(["info", fixture("structured/curvi.vts").to_str().unwrap()]);
    info.assert_success();
    let out = info.stdout_str();
    assert!(
        out.contains("hexahedron") && out.contains("temperature"),
        "{out}"
    );
    let vtu = dir.path().join("curvi.vtu");
    tetkit([
        "convert",
        fixture("structured/curvi.vts").to_str().unwrap(),
        "-o",
        vtu.to_str().unwrap(),
    ])
    .assert_success();
    let back = formats::read(&vtu).unwrap();
    common::grids_bit_equal(&back, &read("curvi.vts")).unwrap();
    let png = dir.path().join("image.png");
    let r = tetkit([
        "render",
        fixture("structured/image.vti").to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--size",
        "64x64",
        "--scalar",
        "temperature",
    ]);
    r.assert_success();
    assert!(png.is_file());
    // Structured formats are read, not written.
    let r = tetkit([
        "convert",
        vtu.to_str().unwrap(),
        "-o",
        dir.path().join("x.vti").to_str().unwrap(),
    ]);
    assert!(
        !r.success() && r.stderr.contains("does not write"),
        "{}",
        r.stderr
    );
    assert!(!dir.path().join("x.vti").exists());
    if !require_vtk("cli_reads_converts_and_renders_structured_data (VTK part)") {
        return;
    }
    let v = vtk_check(&vtu, true);
    assert_eq!(v["cells"], 3 * 5 * 2);
    assert!(v["min_cell_volume"].as_f64().unwrap() > 0.0, "{v}");
}

#[test]
fn broken_structured_files_are_refused_with_the_place() {
    let dir = tempdir();
    let cases: [(&str, &str, &str); 8] = [
        (
            "huge.vti",
            "<VTKFile type=\"ImageData\"><ImageData><Piece Extent=\"0 2000000 0 2000000 0 2000000\"/></ImageData></VTKFile>",
            "this machine has",
        ),
        (
            "gap.vti",
            "<VTKFile type=\"ImageData\"><ImageData><Piece Extent=\"0 1 0 1 0 1\"/><Piece Extent=\"3 4 0 1 0 1\"/></ImageData></VTKFile>",
            "uncovered",
        ),
        (
            "no_extent.vti",
            "<VTKFile type=\"ImageData\"><ImageData WholeExtent=\"0 1 0 1 0 1\"><Piece><PointData/></Piece></ImageData></VTKFile>",
            "without an Extent",
        ),
        (
            "bad_spacing.vti",
            "<VTKFile type=\"ImageData\"><ImageData Spacing=\"1 nan 1\"><Piece Extent=\"0 1 0 1 0 1\"/></ImageData></VTKFile>",
            "Spacing",
        ),
        (
            "two_coords.vtr",
            "<VTKFile type=\"RectilinearGrid\"><RectilinearGrid><Piece Extent=\"0 1 0 1 0 0\"><Coordinates><DataArray type=\"Float32\" format=\"ascii\">0 1</DataArray><DataArray type=\"Float32\" format=\"ascii\">0 1</DataArray></Coordinates></Piece></RectilinearGrid></VTKFile>",
            "expected 3",
        ),
        (
            "short_coords.vtk",
            "# vtk DataFile Version 3.0\nt\nASCII\nDATASET RECTILINEAR_GRID\nDIMENSIONS 2 2 2\nX_COORDINATES 2 float\n0 1\nY_COORDINATES 1 float\n0\nZ_COORDINATES 2 float\n0 1\n",
            "Y_COORDINATES has 1 values",
        ),
        (
            "big_dims.vtk",
            "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 1500 1500 1500\n",
            "this machine has",
        ),
        (
            "no_dims.vtk",
            "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nORIGIN 0 0 0\nPOINT_DATA 8\n",
            "DIMENSIONS",
        ),
    ];
    for (name, text, needle) in cases {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        let r = tetkit(["info", path.to_str().unwrap()]);
        assert!(!r.success(), "{name} was accepted");
        assert!(
            r.stderr.contains(name) && r.stderr.contains(needle),
            "{name}: {}",
            r.stderr
        );
    }
}
