//! `--elevation 90` far from the origin: the camera's offset from the focal point keeps
//! cos(90 degrees) = 6e-17 of its length along the old view-up, which keeps the view-up
//! defined. At the origin that survived; moved by 1e9 (UTM-like coordinates) the position's
//! rounding dropped it, and render stopped with "view-up [0.0, 0.0, 0.0] is parallel to the view
//! direction" for a view that renders at the origin. The up is now orthogonalized against the
//! rotated offset itself (`fixtures/newuser/make_offset_cube.py`).

mod common;

use common::{fixture, tempdir, tetkit};

fn render(dir: &std::path::Path, mesh: &str, method: &str, extra: &[&str]) -> image::RgbImage {
    let out = dir.join(format!("{mesh}_{method}_{}.png", extra.join("_")));
    let path = fixture(&format!("newuser/{mesh}.vtk"));
    let mut args = vec![
        "render",
        path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
        "--method",
        method,
    ];
    args.extend_from_slice(extra);
    tetkit(args).assert_success();
    image::open(&out).unwrap().to_rgb8()
}

#[test]
fn elevation_90_far_from_the_origin_renders_as_at_the_origin() {
    let dir = tempdir();
    for extra in [
        &["--elevation", "90", "--size", "33x21"][..],
        &["--elevation", "-90", "--azimuth", "30", "--size", "33x21"][..],
        &["--elevation", "90", "--parallel", "--size", "33x21"][..],
    ] {
        // Before, the 1e9 copy was refused outright.
        let near = render(dir.path(), "offset_cube_0", "raycast", extra);
        let far = render(dir.path(), "offset_cube_1e9", "raycast", extra);
        let far_pt = render(dir.path(), "offset_cube_1e9", "pt", extra);
        let near_pt = render(dir.path(), "offset_cube_0", "pt", extra);
        let worst = common::max_channel_diff(&near, &far);
        assert!(
            worst <= 1,
            "{extra:?}: the 1e9 copy is {worst}/255 off the one at the origin"
        );
        for (pt, rc, at) in [(&far_pt, &far, "1e9"), (&near_pt, &near, "the origin")] {
            let worst = common::max_channel_diff(pt, rc);
            assert!(
                worst <= 2,
                "{extra:?} at {at}: PT is {worst}/255 off the ray caster"
            );
        }
    }
}

/// The ray caster down a tetrahedralized grid's edges and in its faces' planes (the centre row
/// and column of the block seen from above or at 45 degrees): each face's rate along such a ray
/// is rounding noise, and its root pushed the start of the chord to the next node, so the
/// reference lost chords the ray has: the centre pixel 187/255 darker than PT at elevation 45,
/// the centre row up to 189/255 at elevation 90. Rates that small are now taken as zero.
#[test]
fn rays_down_grid_edges_keep_their_chords_in_the_ray_caster() {
    let dir = tempdir();
    for extra in [
        &["--elevation", "45"][..],
        &["--elevation", "90"][..],
        &["--elevation", "-90"][..],
        &["--elevation", "90", "--parallel"][..],
    ] {
        for size in ["1x1", "3x3", "33x21"] {
            let mut args = extra.to_vec();
            args.extend_from_slice(&["--size", size]);
            let pt = render(dir.path(), "offset_cube_0", "pt", &args);
            let rc = render(dir.path(), "offset_cube_0", "raycast", &args);
            let worst = common::max_channel_diff(&pt, &rc);
            assert!(worst <= 2, "{args:?}: the ray caster is {worst}/255 off PT");
        }
    }
}

/// PT with a pixel's ray exactly down a tet edge seen end-on, through the block's interior
/// nodes (from below, and down the main diagonal): the 1/256-pixel grid handed the pixel to a
/// tet whose planes do not hold the ray, or the per-pixel path let two of the tets around the
/// edge take the whole edge (60/255 and 52/255 off the ray caster at 33x21). The tets around
/// such an edge take the per-pixel path, where a ray in a face's plane goes to one side only.
#[test]
fn a_ray_down_an_edge_seen_end_on_keeps_one_chord_in_pt() {
    let dir = tempdir();
    let diagonal = "-35.264389682754654";
    for extra in [
        &["--elevation", "-90", "--azimuth", "30"][..],
        &["--azimuth", "-45", "--elevation", diagonal][..],
        &["--azimuth", "-45", "--elevation", diagonal, "--parallel"][..],
    ] {
        for size in ["1x1", "3x3", "33x21"] {
            let mut args = extra.to_vec();
            args.extend_from_slice(&["--size", size]);
            let pt = render(dir.path(), "offset_cube_0", "pt", &args);
            let rc = render(dir.path(), "offset_cube_0", "raycast", &args);
            let worst = common::max_channel_diff(&pt, &rc);
            assert!(worst <= 2, "{args:?}: PT is {worst}/255 off the ray caster");
        }
    }
}
