//! A solver's result with NaN (or inf) where it is undefined: `render` used to refuse the whole
//! mesh ("value NaN is not finite"); the tets that read such a value are now left out (said on
//! stderr) and the rest is drawn, by PT and the ray caster alike.

mod common;

use common::{tempdir, tetkit};
use std::path::Path;
use tetkit::formats::{ArrayData, DataArray};
use tetkit::mesh::generate::structured_grid;

fn lit(png: &Path) -> usize {
    let img = image::open(png).unwrap().to_rgb8();
    img.pixels().filter(|p| p.0 != [0, 0, 0]).count()
}

#[test]
fn tets_reading_nan_are_left_out_and_the_rest_is_drawn() {
    let dir = tempdir();
    let mesh = structured_grid([6, 6, 6], [0.0; 3], [1.0; 3]);
    let mut grid = mesh.to_grid();
    // x, undefined (NaN) where x < 0.3 and infinite at one point.
    let mut s: Vec<f64> = mesh.points.iter().map(|p| p[0]).collect();
    for (i, p) in mesh.points.iter().enumerate() {
        if p[0] < 0.3 {
            s[i] = f64::NAN;
        }
    }
    let last = s.len() - 1;
    s[last] = f64::INFINITY;
    grid.point_data
        .insert(DataArray::new("s", 1, ArrayData::Float64(s)));
    grid.point_data.insert(DataArray::new(
        "undefined",
        1,
        ArrayData::Float64(vec![f64::NAN; mesh.points.len()]),
    ));
    let input = dir.path().join("nan.vtu");
    tetkit::formats::write(&input, &grid.clone(), &Default::default()).unwrap();
    let mut lit_by = Vec::new();
    for method in ["pt", "raycast"] {
        let png = dir.path().join(format!("{method}.png"));
        let run = tetkit([
            "render".as_ref(),
            input.as_os_str(),
            "-o".as_ref(),
            png.as_os_str(),
            "--scalar".as_ref(),
            "s".as_ref(),
            "--size".as_ref(),
            "48x48".as_ref(),
            "--method".as_ref(),
            method.as_ref(),
        ]);
        run.assert_success();
        let (_, _, err) = run.parts();
        assert!(
            err.contains("left out") && err.contains("'s'"),
            "{method}: {err}"
        );
        lit_by.push(lit(&png));
    }
    assert!(lit_by[0] > 300, "{lit_by:?}");
    assert!(
        lit_by[0].abs_diff(lit_by[1]) <= 10,
        "PT vs ray caster {lit_by:?}"
    );
    // Nothing left to draw: an error naming the array, and no image.
    let png = dir.path().join("none.png");
    tetkit([
        "render".as_ref(),
        input.as_os_str(),
        "-o".as_ref(),
        png.as_os_str(),
        "--scalar".as_ref(),
        "undefined".as_ref(),
    ])
    .assert_failure(&["nan.vtu", "'undefined'", "nothing to draw"]);
    assert!(!png.exists());
}
