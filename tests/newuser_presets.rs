//! ParaView preset files as ParaView exports them. The opacity editor's midpoint handle (the
//! third number of each `Points` quadruple) was ignored, so a preset whose opacity reaches half
//! way at 0.8 of an interval drew as a plain ramp; `UseLogScale`, sharpness and a file of several
//! presets were ignored without a word, and a categorical preset (IndexedColors) was refused as
//! "no preset with RGBPoints". Fixtures: fixtures/newuser/make_presets.py.

mod common;

use common::{fixture, tempdir, tetkit};

fn render(preset: &str, extra: &[&str], png: &std::path::Path) -> common::Run {
    let input = fixture("gmsh/lshape.vtk");
    let preset = fixture(&format!("newuser/{preset}"));
    let mut args = vec![
        "render".to_string(),
        input.to_string_lossy().into_owned(),
        "-o".into(),
        png.to_string_lossy().into_owned(),
        "--size".into(),
        "48x48".into(),
        "--colormap".into(),
        preset.to_string_lossy().into_owned(),
    ];
    args.extend(extra.iter().map(|s| s.to_string()));
    tetkit(args)
}

#[test]
fn a_preset_opacity_midpoint_is_drawn_as_vtk_draws_it() -> Result<(), Box<dyn std::error::Error>> {
    let dir = tempdir();
    let (mid, by_points, linear) = (
        dir.path().join("mid.png"),
        dir.path().join("points.png"),
        dir.path().join("lin.png"),
    );
    let r = render("preset_midpoint.json", &[], &mid);
    r.assert_success();
    assert!(!r.stderr.contains("warning"), "{}", r.stderr);
    // vtkPiecewiseFunction with midpoint 0.8, sharpness 0: 0.5 at 0.8, linear either side.
    render(
        "preset_linear.json",
        &["--opacity", "0:0,0.8:0.5,1:1"],
        &by_points,
    )
    .assert_success();
    render("preset_linear.json", &[], &linear).assert_success();
    let (a, b, c) = (
        std::fs::read(&mid)?,
        std::fs::read(&by_points)?,
        std::fs::read(&linear)?,
    );
    assert_eq!(
        a, b,
        "the midpoint preset differs from its opacity given as points"
    );
    assert_ne!(a, c, "the midpoint changed nothing");
    Ok(())
}

#[test]
fn preset_keys_tetkit_does_not_draw_are_named() {
    let dir = tempdir();
    let png = dir.path().join("x.png");
    for (preset, needles) in [
        (
            "preset_log.json",
            vec!["preset_log.json", "logmap", "UseLogScale"],
        ),
        (
            "preset_sharp.json",
            vec!["preset_sharp.json", "sharp.Points", "sharpness 0.7"],
        ),
        (
            "preset_two.json",
            vec!["preset_two.json", "2 presets", "using 'first'", "second"],
        ),
    ] {
        let r = render(preset, &[], &png);
        r.assert_success();
        for n in needles {
            assert!(r.stderr.contains(n), "{preset}: no '{n}' in {}", r.stderr);
        }
    }
    std::fs::remove_file(&png).ok();
    render("preset_categorical.json", &[], &png).assert_failure(&[
        "preset_categorical.json",
        "'cats'",
        "categorical",
        "IndexedColors",
    ]);
    assert!(!png.exists());
}

/// ParaView's names of the maps tetkit has ("Cool to Warm" was an unknown colormap).
#[test]
fn paraview_colormap_names_are_taken() -> Result<(), Box<dyn std::error::Error>> {
    let dir = tempdir();
    let input = fixture("gmsh/lshape.vtk");
    let draw = |map: Option<&str>, png: &std::path::Path| {
        let mut a = vec![
            "render".to_string(),
            input.to_string_lossy().into_owned(),
            "-o".into(),
            png.to_string_lossy().into_owned(),
            "--size".into(),
            "32x32".into(),
            "-q".into(),
        ];
        if let Some(m) = map {
            a.extend(["--colormap".to_string(), m.to_string()]);
        }
        tetkit(a)
    };
    let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
    draw(None, &a).assert_success();
    draw(Some("Cool to Warm"), &b).assert_success();
    assert_eq!(std::fs::read(&a)?, std::fs::read(&b)?);
    draw(Some("viridis"), &a).assert_success();
    draw(Some("Viridis (matplotlib)"), &b).assert_success();
    assert_eq!(std::fs::read(&a)?, std::fs::read(&b)?);
    let c = dir.path().join("c.png");
    draw(Some("Jet"), &c).assert_failure(&["unknown colormap 'Jet'", "Choose Preset"]);
    assert!(!c.exists());
    Ok(())
}
