//! The ray-cast reference next to slivers: a ParaView-style clip of a tetrahedralized grid,
//! tetrahedralized again (`fixtures/newuser/make_clip_notch.py`), has valid tets down to volume
//! 1e-18. The ray caster drew chords the rays do not have there (12 pixels up to 0.69 off PT,
//! which was right): a walk went round four slivers meeting where the ray passes until its step
//! budget ran out, and a re-entry through the grid took a face of the tet the ray had just left,
//! walking back into the tet before it. Both now keep to the ray.

mod common;

use common::{fixture, tempdir, tetkit};

#[test]
fn the_ray_caster_keeps_to_the_ray_next_to_slivers() {
    let dir = tempdir();
    let mesh = fixture("newuser/clip_notch.vtu");
    let render = |method: &str| {
        let out = dir.path().join(format!("{method}.png"));
        let r = tetkit([
            "render",
            mesh.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--size",
            "128x128",
            "--position",
            "1.5,0.4,0.5",
            "--focal",
            "0.5,0.5,0.5",
            "--range",
            "0,6",
            "--unit-distance",
            "0.3",
            "--scalar",
            "s",
            "--method",
            method,
        ]);
        r.assert_success();
        (image::open(&out).unwrap().to_rgb8(), r.stderr)
    };
    let (pt, _) = render("pt");
    let (rc, said) = render("raycast");
    assert!(said.contains("lost walks 0"), "{said}");
    let worst = common::max_channel_diff(&pt, &rc);
    assert!(worst <= 2, "the ray caster is {worst}/255 off PT");
}
