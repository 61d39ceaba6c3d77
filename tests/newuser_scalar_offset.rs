//! Fields far from zero compared with their range (temperatures in kelvin varying by a few
//! degrees, `--scalar coord:x` of a mesh at UTM coordinates): projected tetrahedra kept the
//! scalars in f32 and drew `1e8 + [0, 1]` as one value (a blank image) and `1e7 + [0, 3]` in
//! whole steps. Each render must look the same as the same field near zero, with or without a
//! scene whose transfer functions are given in the field's own units.

mod common;

use common::{tempdir, tetkit};
use std::path::Path;
use tetkit::formats::{ArrayData, DataArray};
use tetkit::mesh::generate::structured_grid;

const OFFSET: f64 = 1e8;

fn rgba(png: &Path) -> Vec<u8> {
    image::open(png).unwrap().to_rgba8().into_raw()
}

/// Largest channel difference and the number of lit pixels of the first image.
fn compare(a: &Path, b: &Path) -> (u8, usize) {
    let (x, y) = (rgba(a), rgba(b));
    assert_eq!(x.len(), y.len());
    let worst = x.iter().zip(&y).map(|(p, q)| p.abs_diff(*q)).max().unwrap();
    let lit = x.chunks(4).filter(|p| p[..3] != [0, 0, 0]).count();
    (worst, lit)
}

fn render(input: &Path, out: &Path, extra: &[&str]) {
    let mut args: Vec<&std::ffi::OsStr> = vec![
        "render".as_ref(),
        input.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--size".as_ref(),
        "48x48".as_ref(),
        "-q".as_ref(),
        "--elevation".as_ref(),
        "30".as_ref(),
        "--azimuth".as_ref(),
        "20".as_ref(),
    ];
    args.extend(extra.iter().map(|s| std::ffi::OsStr::new(*s)));
    tetkit(args).assert_success();
}

#[test]
fn a_field_far_from_zero_renders_like_the_same_field_near_zero() {
    let dir = tempdir();
    let mesh = structured_grid([4, 4, 4], [0.0; 3], [1.0; 3]);
    let mut grid = mesh.to_grid();
    let near = grid.point_data.get("scalar").unwrap().data.to_f64_vec();
    let far: Vec<f64> = near.iter().map(|v| v + OFFSET).collect();
    grid.point_data
        .insert(DataArray::new("near", 1, ArrayData::Float64(near)));
    grid.point_data
        .insert(DataArray::new("far", 1, ArrayData::Float64(far)));
    let input = dir.path().join("m.vtu");
    tetkit::formats::write(&input, &grid, &Default::default()).unwrap();

    // A scene whose body carries the paper's two-level opacity, in the field's own units.
    let scene = |off: f64| {
        format!(
            "[transfer]\nrange = [{a}, {b}]\nopacity = [[{a}, 0.05], [{b}, 0.3]]\n\
             [[body]]\nshape = \"sphere\"\ncenter = [0.5, 0.5, 0.5]\nradius = 0.35\n\
             action = \"transfer\"\n[body.transfer]\ncolormap = \"inferno\"\n\
             opacity = [[{a}, 0.07], [{t}, 0.07], [{t}, 0.93], [{b}, 0.93]]\n",
            a = off,
            b = off + 1.0,
            t = off + 0.5
        )
    };
    let (near_scene, far_scene) = (dir.path().join("near.toml"), dir.path().join("far.toml"));
    std::fs::write(&near_scene, scene(0.0)).unwrap();
    std::fs::write(&far_scene, scene(OFFSET)).unwrap();
    let near_scene = near_scene.to_str().unwrap();
    let far_scene = far_scene.to_str().unwrap();

    for (what, near_args, far_args) in [
        ("preintegrated", vec![], vec![]),
        (
            "linear",
            vec!["--integration", "linear"],
            vec!["--integration", "linear"],
        ),
        (
            "raycast",
            vec!["--method", "raycast"],
            vec!["--method", "raycast"],
        ),
        (
            "scene",
            vec!["--scene", near_scene],
            vec!["--scene", far_scene],
        ),
        (
            "scene raycast",
            vec!["--scene", near_scene, "--method", "raycast"],
            vec!["--scene", far_scene, "--method", "raycast"],
        ),
    ] {
        let (a, b) = (dir.path().join("near.png"), dir.path().join("far.png"));
        let near_args: Vec<&str> = ["--scalar", "near"].into_iter().chain(near_args).collect();
        let far_args: Vec<&str> = ["--scalar", "far"].into_iter().chain(far_args).collect();
        render(&input, &a, &near_args);
        render(&input, &b, &far_args);
        let (worst, lit) = compare(&a, &b);
        assert!(lit > 500, "{what}: only {lit} lit pixels near zero");
        assert!(worst <= 2, "{what}: images differ by {worst}/255");
    }
}

/// Fields (or ranges) beyond f32's reach: `--range -1e100,1e100` drew a blank image in PT (the
/// table started at -inf) while the f64 ray caster drew it right. Scaled by a power of two into
/// f32's range, each render looks the same as the field in ordinary units, a scene's transfer
/// functions scaled with it.
#[test]
fn fields_beyond_f32_render_like_ordinary_ones() -> Result<(), Box<dyn std::error::Error>> {
    let dir = tempdir();
    let mesh = structured_grid([4, 4, 4], [0.0; 3], [1.0; 3]);
    let mut grid = mesh.to_grid();
    let near = grid
        .point_data
        .get("scalar")
        .ok_or("no scalar")?
        .data
        .to_f64_vec();
    for (name, k) in [("huge", 1e200), ("tiny", 1e-200)] {
        let v: Vec<f64> = near.iter().map(|x| x * k).collect();
        grid.point_data
            .insert(DataArray::new(name, 1, ArrayData::Float64(v)));
    }
    grid.point_data
        .insert(DataArray::new("near", 1, ArrayData::Float64(near)));
    let input = dir.path().join("m.vtu");
    tetkit::formats::write(&input, &grid, &Default::default())?;
    let scene = |k: f64| {
        format!(
            "[[body]]\nshape = \"sphere\"\ncenter = [0.5, 0.5, 0.5]\nradius = 0.35\n\
             action = \"transfer\"\n[body.transfer]\ncolormap = \"inferno\"\n\
             opacity = [[0.0, 0.07], [{t:e}, 0.07], [{t:e}, 0.93], [{b:e}, 0.93]]\n",
            t = 0.5 * k,
            b = k
        )
    };
    for (name, k) in [("huge", 1e200), ("tiny", 1e-200)] {
        let (near_scene, far_scene) = (dir.path().join("n.toml"), dir.path().join("f.toml"));
        std::fs::write(&near_scene, scene(1.0))?;
        std::fs::write(&far_scene, scene(k))?;
        let (ns, fs) = (
            near_scene.to_str().ok_or("path")?,
            far_scene.to_str().ok_or("path")?,
        );
        for (what, near_args, far_args) in [
            ("pt", vec![], vec![]),
            (
                "raycast",
                vec!["--method", "raycast"],
                vec!["--method", "raycast"],
            ),
            ("scene", vec!["--scene", ns], vec!["--scene", fs]),
        ] {
            let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
            let near_args: Vec<&str> = ["--scalar", "near"].into_iter().chain(near_args).collect();
            let far_args: Vec<&str> = ["--scalar", name].into_iter().chain(far_args).collect();
            render(&input, &a, &near_args);
            render(&input, &b, &far_args);
            let (worst, lit) = compare(&a, &b);
            assert!(lit > 500, "{name} {what}: only {lit} lit pixels");
            assert!(worst <= 2, "{name} {what}: images differ by {worst}/255");
        }
    }
    // A given range past f32's: the same image as the equivalent ordinary one.
    let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
    render(&input, &a, &["--scalar", "near", "--range=-1,1"]);
    render(&input, &b, &["--scalar", "huge", "--range=-1e200,1e200"]);
    let (worst, lit) = compare(&a, &b);
    assert!(lit > 500 && worst <= 2, "range: {worst}/255, {lit} lit");
    Ok(())
}
