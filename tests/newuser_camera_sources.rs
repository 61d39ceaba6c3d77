//! A camera that came from a scene's `[camera]` or a ParaView camera file and has no view: a
//! scene's `up = [0, 0, 0]` (or an up along the view) was reported as "point.vtu: view-up ...:
//! give another --up", naming neither the scene nor an option the user gave; a .pvcc with a
//! zero CameraViewUp or CameraPosition equal to CameraFocalPoint likewise. Each now names the
//! file (and the line where it has one), and no image is written.

mod common;

use common::{fixture, tempdir, tetkit};

const PVCC: &str = r#"<?xml version="1.0"?>
<PVCameraConfiguration description="ParaView camera configuration" version="1.0">
  <Proxy group="views" type="RenderView" id="4867" servers="21">
    <Property name="CameraPosition" id="4867.CameraPosition" number_of_elements="3">
      <Element index="0" value="POS"/>
      <Element index="1" value="0.5"/>
      <Element index="2" value="3"/>
    </Property>
    <Property name="CameraFocalPoint" id="4867.CameraFocalPoint" number_of_elements="3">
      <Element index="0" value="0.5"/>
      <Element index="1" value="0.5"/>
      <Element index="2" value="3"/>
    </Property>
    <Property name="CameraViewUp" id="4867.CameraViewUp" number_of_elements="3">
      <Element index="0" value="0"/>
      <Element index="1" value="UP"/>
      <Element index="2" value="0"/>
    </Property>
  </Proxy>
</PVCameraConfiguration>
"#;

#[test]
fn a_viewless_camera_from_a_file_names_that_file() -> Result<(), Box<dyn std::error::Error>> {
    let dir = tempdir();
    let input = fixture("gmsh/lshape.vtk");
    let png = dir.path().join("x.png");
    let render = |extra: &[&str]| {
        let mut a = vec![
            "render",
            input.to_str().unwrap_or(""),
            "-o",
            png.to_str().unwrap_or(""),
            "--size",
            "16x16",
        ];
        a.extend_from_slice(extra);
        tetkit(a)
    };
    let scene = dir.path().join("s.toml");
    let s = scene.to_str().unwrap_or("");
    std::fs::write(&scene, "[camera]\nup = [0.0, 0.0, 0.0]\n")?;
    render(&["--scene", s]).assert_failure(&["s.toml", "line 1", "up", "zero"]);
    assert!(!png.exists());
    // Up along the reset's view direction (-z): the scene is named beside the mesh.
    std::fs::write(&scene, "[camera]\nup = [0.0, 0.0, 1.0]\n")?;
    render(&["--scene", s]).assert_failure(&["lshape.vtk", "[camera] of", "s.toml", "view-up"]);
    assert!(!png.exists());
    // A scene without [camera] keeps the plain message (the --up was the user's).
    std::fs::write(&scene, "")?;
    let r = render(&["--scene", s, "--up", "0,0,1"]);
    r.assert_failure(&["lshape.vtk", "view-up"]);
    assert!(!r.stderr.contains("[camera]"), "{}", r.stderr);
    let cam = dir.path().join("v.pvcc");
    let c = cam.to_str().unwrap_or("");
    std::fs::write(&cam, PVCC.replace("POS", "2").replace("UP", "0"))?;
    render(&["--camera-file", c]).assert_failure(&["v.pvcc", "line 14", "CameraViewUp", "zero"]);
    std::fs::write(&cam, PVCC.replace("POS", "0.5").replace("UP", "1"))?;
    render(&["--camera-file", c]).assert_failure(&["v.pvcc", "CameraPosition", "CameraFocalPoint"]);
    assert!(!png.exists());
    std::fs::write(&cam, PVCC.replace("POS", "2").replace("UP", "1"))?;
    render(&["--camera-file", c, "-q"]).assert_success();
    assert!(png.exists());
    Ok(())
}
