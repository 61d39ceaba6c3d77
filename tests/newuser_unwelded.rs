//! Per-element meshes (every cell its own points, as DG codes and some exporters write them, or
//! pieces appended without merging points): the sort and the ray caster weld coincident points
//! for adjacency. Unwelded, every face was a boundary face: the kd sort took 5.8 s and 682,775
//! extra constraints on 8,640 tets (its welded twin 0.003 s), mpvo could not order it at all,
//! and the ray caster re-entered through its grid at every face (5x slower).

mod common;

use common::{tempdir, tetkit};
use std::path::Path;
use tetkit::mesh::generate::structured_grid;
use tetkit::mesh::TetMesh;

/// The same grid with every tet given its own four points.
fn unwelded(m: &TetMesh) -> TetMesh {
    let mut points = Vec::with_capacity(4 * m.tets.len());
    let mut tets = Vec::with_capacity(m.tets.len());
    for t in &m.tets {
        let base = points.len() as u32;
        points.extend(t.iter().map(|&v| m.points[v as usize]));
        tets.push([base, base + 1, base + 2, base + 3]);
    }
    TetMesh {
        points,
        tets,
        ..Default::default()
    }
}

fn json(args: &[&str]) -> serde_json::Value {
    let run = tetkit(args);
    run.assert_success();
    serde_json::from_slice(&run.stdout).unwrap()
}

fn rgb(png: &Path) -> Vec<u8> {
    image::open(png).unwrap().to_rgb8().into_raw()
}

#[test]
fn unwelded_meshes_sort_and_render_as_their_welded_twins() {
    let dir = tempdir();
    let welded = structured_grid([5, 4, 3], [0.0; 3], [1.0, 0.8, 0.6]);
    let apart = unwelded(&welded);
    let path = |name: &str| dir.path().join(name).display().to_string();
    tetkit::formats::write(
        Path::new(&path("welded.vtu")),
        &welded.to_grid(),
        &Default::default(),
    )
    .unwrap();
    tetkit::formats::write(
        Path::new(&path("apart.vtu")),
        &apart.to_grid(),
        &Default::default(),
    )
    .unwrap();
    let view = ["--azimuth", "35", "--elevation", "25"];
    for method in ["kd", "mpvo"] {
        let mut args = vec!["sort", "", "-o", "", "--method", method, "--json"];
        args.extend(view);
        let (input, out) = (path("apart.vtu"), path(&format!("apart_{method}.vtu")));
        args[1] = &input;
        args[3] = &out;
        let report = json(&args);
        // Every interior face is a face between neighbours again: no extra constraints.
        assert_eq!(
            report["stats"]["extra_constraints"], 0,
            "{method}: {report}"
        );
        let mut check = vec![
            "check-order",
            &out,
            "--rays",
            "2500",
            "--json",
            "--fail-on-violation",
        ];
        check.extend(view);
        let r = json(&check);
        assert_eq!(r["report"]["violations"], 0, "{method}: {r}");
        assert!(r["report"]["crossings"].as_u64().unwrap() > 1000, "{r}");
    }
    for method in ["raycast", "pt"] {
        let mut images = Vec::new();
        for name in ["welded", "apart"] {
            let (input, png) = (path(&format!("{name}.vtu")), path(&format!("{name}.png")));
            let mut args = vec![
                "render", &input, "-o", &png, "--size", "64x64", "-q", "--scalar", "coord:z",
                "--method", method,
            ];
            args.extend(view);
            tetkit(&args).assert_success();
            images.push(rgb(Path::new(&png)));
        }
        let off = images[0]
            .iter()
            .zip(&images[1])
            .filter(|(a, b)| a.abs_diff(**b) > 1)
            .count();
        assert_eq!(off, 0, "{method}: {off} channels differ");
    }
}
