//! PT where a pixel's ray passes through a mesh node along a face seen nearly edge-on
//! (`fixtures/newuser/make_vertex_ray.py`: VTK's tetrahedralized 4x4x4 grid, whose centre node
//! the default camera looks at, so an odd image size puts a pixel centre on it; at azimuth 30,
//! elevation 20 a face through it, normal (1, 1, -1), is 0.1 degrees off edge-on). The
//! silhouettes were built from snapped corners and the depth planes from unsnapped ones: the
//! pixel went to the silhouette of one tet beside the face and the chord to the other, so the
//! ray lost the whole stretch it runs along the face (up to 129/255 off the ray caster at 3x3).

mod common;

use common::{fixture, max_channel_diff, tempdir, tetkit};

#[test]
fn a_ray_along_a_face_through_a_node_keeps_its_chord() {
    let dir = tempdir();
    let mesh = fixture("newuser/vertex_ray.vtu");
    for size in ["1x1", "3x3", "5x3", "7x3", "5x5", "4x3", "33x33"] {
        let render = |method: &str| {
            let out = dir.path().join(format!("{method}_{size}.png"));
            tetkit([
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
            ])
            .assert_success();
            image::open(&out).unwrap().to_rgb8()
        };
        let (pt, rc) = (render("pt"), render("raycast"));
        let d = max_channel_diff(&pt, &rc);
        assert!(d <= 2, "{size}: PT is {d}/255 off the ray caster");
    }
}
