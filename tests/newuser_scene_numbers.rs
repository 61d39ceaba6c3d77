//! TOML lets a scene say `inf` and `nan`: a sphere of `radius = inf` was refused as "must be
//! positive", which it is; the message now says what is wrong (finite), with the line.

mod common;

use common::{fixture, tempdir, tetkit};

#[test]
fn an_infinite_radius_is_called_infinite() {
    let dir = tempdir();
    let scene = dir.path().join("s.toml");
    std::fs::write(
        &scene,
        "[[body]]\nshape = \"sphere\"\ncenter = [0.5, 0.5, 0.5]\nradius = inf\n",
    )
    .unwrap();
    let out = dir.path().join("c.vtu");
    let r = tetkit([
        "classify".as_ref(),
        fixture("gmsh/lshape.vtk").as_os_str(),
        "--scene".as_ref(),
        scene.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    r.assert_failure(&["s.toml", "line 4", "radius = inf", "finite"]);
    assert!(!out.exists());
}
