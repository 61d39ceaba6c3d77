//! Meshes far from the origin or of huge size, as a user's files can be: every view command
//! finds a camera for them (the default camera used to collapse onto its focal point once the
//! coordinates passed 2^53, and refused with "view-up is parallel to the view direction").

mod common;

use common::{tempdir, tetkit};
use std::path::Path;
use tetkit::mesh::generate::structured_grid;

/// Lit pixels of a PNG.
fn lit(png: &Path) -> usize {
    let img = image::open(png).unwrap().to_rgb8();
    img.pixels().filter(|p| p.0 != [0, 0, 0]).count()
}

#[test]
fn far_off_and_huge_meshes_get_the_default_camera() {
    let dir = tempdir();
    for (name, min, max) in [
        // Side 1024 at 1e17: every coordinate is exact (spacing 16 there).
        (
            "far",
            [1e17, -1e17, 3e17],
            [1e17 + 1024.0, -1e17 + 1024.0, 3e17 + 1024.0],
        ),
        ("huge", [0.0; 3], [1e30; 3]),
        ("huge_far", [-3e30, 1e30, 0.0], [-2e30, 2e30, 1e30]),
    ] {
        let mesh = structured_grid([3, 3, 3], min, max);
        let input = dir.path().join(format!("{name}.vtu"));
        tetkit::formats::write(&input, &mesh.to_grid(), &Default::default()).unwrap();
        let png = dir.path().join(format!("{name}.png"));
        for method in ["raycast", "pt"] {
            tetkit([
                "render".as_ref(),
                input.as_os_str(),
                "-o".as_ref(),
                png.as_os_str(),
                "--size".as_ref(),
                "32x32".as_ref(),
                "-q".as_ref(),
                "--method".as_ref(),
                method.as_ref(),
            ])
            .assert_success();
            // Both at any scale: PT's perspective depths used to overflow f32 at 1e30.
            assert!(lit(&png) > 100, "{name} {method}: {} lit pixels", lit(&png));
        }
        let sorted = dir.path().join(format!("{name}_sorted.vtu"));
        tetkit([
            "sort".as_ref(),
            input.as_os_str(),
            "-o".as_ref(),
            sorted.as_os_str(),
        ])
        .assert_success();
        let run = tetkit([
            "check-order".as_ref(),
            sorted.as_os_str(),
            "--rays".as_ref(),
            "1024".as_ref(),
            "--json".as_ref(),
            "--fail-on-violation".as_ref(),
        ]);
        run.assert_success();
        let report: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
        // Rays hit the mesh and cross tets (the camera sees it), in a valid order.
        assert!(
            report["report"]["rays_hit"].as_u64().unwrap() > 100,
            "{name}: {report}"
        );
        assert!(
            report["report"]["crossings"].as_u64().unwrap() > 100,
            "{name}: {report}"
        );
        assert_eq!(report["report"]["violations"], 0, "{name}: {report}");
    }
}

#[test]
fn tiny_meshes_are_drawn_by_projected_tetrahedra() {
    // A mesh 1e-10 across (nanometres in metres) put every point within the fixed 1e-9 near
    // depth of PT's eye: all "behind the camera", a blank image. The near depth now scales
    // with the camera's distance below 1.
    let dir = tempdir();
    for size in [1e-10, 1e-14] {
        let mesh = structured_grid([3, 3, 3], [0.0; 3], [size; 3]);
        let input = dir.path().join("tiny.vtu");
        tetkit::formats::write(&input, &mesh.to_grid(), &Default::default()).unwrap();
        let mut lit_by = Vec::new();
        for method in ["pt", "raycast"] {
            let png = dir.path().join(format!("{method}.png"));
            tetkit([
                "render".as_ref(),
                input.as_os_str(),
                "-o".as_ref(),
                png.as_os_str(),
                "--size".as_ref(),
                "32x32".as_ref(),
                "-q".as_ref(),
                "--method".as_ref(),
                method.as_ref(),
                "--elevation".as_ref(),
                "25".as_ref(),
            ])
            .assert_success();
            lit_by.push(lit(&png));
        }
        assert!(lit_by[1] > 200, "{size}: {lit_by:?}");
        assert!(
            lit_by[0].abs_diff(lit_by[1]) <= 10,
            "{size}: PT vs ray caster {lit_by:?}"
        );
    }
}

/// RGB bytes of a PNG.
fn pixels(png: &Path) -> Vec<u8> {
    image::open(png).unwrap().to_rgb8().into_raw()
}

/// Channels of two images more than 2/255 apart.
fn channels_off(a: &[u8], b: &[u8]) -> usize {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).filter(|(x, y)| x.abs_diff(**y) > 2).count()
}

#[test]
fn projected_tetrahedra_draw_meshes_of_any_size_alike() {
    // PT carried perspective depth to f32 as 1/z: the products of the per-pixel depth formula
    // overflowed for a mesh 1e-20 across and underflowed at 1e25, so both came out blank. Each
    // size must now give the unit mesh's image, perspective and parallel, every integration.
    let dir = tempdir();
    let render = |input: &Path, png: &Path, extra: &[&str]| {
        let mut args: Vec<&std::ffi::OsStr> = vec![
            "render".as_ref(),
            input.as_os_str(),
            "-o".as_ref(),
            png.as_os_str(),
        ];
        for a in [
            "--size",
            "48x48",
            "-q",
            "--scalar",
            "coord:z",
            "--elevation",
            "25",
        ]
        .iter()
        .chain(extra)
        {
            args.push(a.as_ref());
        }
        tetkit(args).assert_success();
    };
    let grid = |name: &str, size: f64| {
        let mesh = structured_grid([4, 3, 2], [0.0; 3], [size; 3]);
        let input = dir.path().join(format!("{name}.vtu"));
        tetkit::formats::write(&input, &mesh.to_grid(), &Default::default()).unwrap();
        input
    };
    let unit = grid("unit", 1.0);
    for extra in [
        &["--integration", "preintegrated"][..],
        &["--integration", "linear"],
        &["--integration", "average", "--parallel"],
    ] {
        let want_png = dir.path().join("unit.png");
        render(&unit, &want_png, extra);
        let want = pixels(&want_png);
        assert!(lit(&want_png) > 500, "{extra:?}: {} lit", lit(&want_png));
        for size in [1e-30, 1e-20, 1e-12, 1e12, 1e25, 1e30] {
            let input = grid("sized", size);
            let png = dir.path().join("sized.png");
            render(&input, &png, extra);
            let got = pixels(&png);
            // Coordinates scaled by a non-power of two round differently: a step of 2/255
            // at most, on few pixels.
            let off = channels_off(&want, &got);
            assert_eq!(
                off, 0,
                "size {size} {extra:?}: {off} channels differ from the unit mesh"
            );
        }
    }
}

#[test]
fn scenes_draw_alike_at_any_scale() {
    // Body crossings are compared with PT's fragment depths, which are in the rasterizer's
    // depth unit: a scene scaled by 1e-20 (or 1e20) must give the unit scene's image.
    let dir = tempdir();
    let mut want: Option<Vec<u8>> = None;
    for size in [1.0, 1e-20, 1e20] {
        let mesh = structured_grid([5, 5, 5], [0.0; 3], [size; 3]);
        let input = dir.path().join("mesh.vtu");
        tetkit::formats::write(&input, &mesh.to_grid(), &Default::default()).unwrap();
        let v = |x: f64| format!("{:e}", x * size);
        let toml = format!(
            "[camera]\nposition = [{}, {}, {}]\nfocal = [{}, {}, {}]\n\
             [transfer]\nopacity = [[0.0, 0.1], [{}, 0.5]]\nunit_distance = {}\n\
             [[body]]\nshape = \"box\"\nmin = [{}, {}, {}]\nmax = [{}, {}, {}]\naction = \"cut\"\n\
             [[body]]\nshape = \"sphere\"\ncenter = [{}, {}, {}]\nradius = {}\naction = \"transfer\"\n\
             [body.transfer]\nopacity = [[0.0, 0.9], [{}, 0.9]]\ncolormap = \"reds\"\n",
            v(2.2),
            v(1.7),
            v(2.9),
            v(0.5),
            v(0.5),
            v(0.5),
            // The scalar is x, so its opacity points scale too.
            v(1.0),
            v(0.3),
            v(0.5),
            v(0.5),
            v(0.5),
            v(1.1),
            v(1.1),
            v(1.1),
            v(0.3),
            v(0.4),
            v(0.4),
            v(0.2),
            v(1.0),
        );
        let scene = dir.path().join("scene.toml");
        std::fs::write(&scene, toml).unwrap();
        let png = dir.path().join("scene.png");
        tetkit([
            "render".as_ref(),
            input.as_os_str(),
            "--scene".as_ref(),
            scene.as_os_str(),
            "-o".as_ref(),
            png.as_os_str(),
            "--size".as_ref(),
            "48x48".as_ref(),
            "--scalar".as_ref(),
            "coord:x".as_ref(),
            "-q".as_ref(),
        ])
        .assert_success();
        let got = pixels(&png);
        match &want {
            None => {
                assert!(lit(&png) > 500, "{} lit", lit(&png));
                want = Some(got);
            }
            Some(w) => {
                let off = channels_off(w, &got);
                assert_eq!(
                    off, 0,
                    "size {size}: {off} channels differ from the unit scene"
                );
            }
        }
    }
}

#[test]
fn a_mesh_of_zero_extent_is_named_as_such() {
    // Every point at one place (coordinates that collapsed when written as f32 far from the
    // origin): the error said only that the camera position equals the focal point.
    let dir = tempdir();
    let mut mesh = structured_grid([1, 1, 1], [0.0; 3], [1.0; 3]);
    for p in mesh.points.iter_mut() {
        *p = [1e17, -1e17, 3e17];
    }
    let input = dir.path().join("collapsed.vtu");
    tetkit::formats::write(&input, &mesh.to_grid(), &Default::default()).unwrap();
    let png = dir.path().join("x.png");
    let sorted = dir.path().join("s.vtu");
    for args in [
        vec!["render", "", "-o", png.to_str().unwrap()],
        vec!["sort", "", "-o", sorted.to_str().unwrap()],
        vec!["check-order", ""],
    ] {
        let mut args = args;
        args[1] = input.to_str().unwrap();
        tetkit(&args).assert_failure(&["collapsed.vtu", "zero extent", "--position"]);
    }
    assert!(!png.exists() && !sorted.exists());
}
