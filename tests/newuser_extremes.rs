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
            // The ray caster is exact at any scale; PT still loses its f32 depths at 1e30 (known,
            // reported), so only the ray caster's image is required to show the mesh.
            if method == "raycast" {
                assert!(lit(&png) > 100, "{name}: {} lit pixels", lit(&png));
            }
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
