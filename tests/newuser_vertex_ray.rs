//! A ray along a face seen nearly edge-on: VTK's tetrahedralized 4x4x4 grid
//! (`fixtures/newuser/make_vertex_ray.py`) seen at azimuth 30, elevation 20 from the default
//! camera, whose centre pixel (odd image sizes) has its ray through the grid's centre node, where
//! a face is 0.1 degrees off edge-on. The ray runs a third of its length along that face. PT's
//! silhouettes come from corners on a 1/256-pixel grid and its depth planes from the true
//! corners; the grid flipped the face, so the pixel went to the tet on the face's wrong side,
//! whose planes give it no chord: the centre pixel was up to 129/255 off the ray caster. Such
//! tets now take the per-pixel path.

mod common;

use common::{fixture, tempdir, tetkit};

fn render(dir: &std::path::Path, size: &str, method: &str, extra: &[&str]) -> image::RgbImage {
    render_saying(dir, size, method, extra).0
}

/// The render's image and what it said on stderr.
fn render_saying(
    dir: &std::path::Path,
    size: &str,
    method: &str,
    extra: &[&str],
) -> (image::RgbImage, String) {
    let out = dir.join(format!("{size}_{method}.png"));
    let mesh = fixture("newuser/vertex_ray.vtu");
    let mut args = vec![
        "render",
        mesh.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--size",
        size,
        "--azimuth",
        "30",
        "--elevation",
        "20",
        "--method",
        method,
    ];
    args.extend_from_slice(extra);
    let r = tetkit(args);
    r.assert_success();
    (image::open(&out).unwrap().to_rgb8(), r.stderr)
}

#[test]
fn a_ray_along_a_face_seen_edge_on_keeps_its_chord() {
    let dir = tempdir();
    for extra in [&[][..], &["--parallel"][..]] {
        for size in ["1x1", "3x3", "5x3", "7x3", "5x5", "9x9", "33x33"] {
            let pt = render(dir.path(), size, "pt", extra);
            let rc = render(dir.path(), size, "raycast", extra);
            let worst = common::max_channel_diff(&pt, &rc);
            assert!(
                worst <= 2,
                "{size} {extra:?}: PT is {worst}/255 off the ray caster"
            );
        }
    }
}

/// The default opacity ramp ends in a node clamped just below 1, whose extinction jumps: the
/// "table is coarse" note counted that jump and fired on every default render of a coarse mesh
/// like this one, though a fragment there is opaque already at the interval's lower end.
#[test]
fn a_default_render_of_a_coarse_mesh_has_no_table_note() {
    let dir = tempdir();
    let (_, said) = render_saying(dir.path(), "33x33", "pt", &[]);
    assert!(!said.contains("coarse"), "{said}");
}
