//! The exact kd order and PT against the ray caster on non-convex meshes from real meshers, at
//! the hardest views of a new-user sweep (fixtures/newuser/make_nonconvex_views.sh): a Gmsh
//! (OpenCASCADE) U whose arms overlap on screen seen along x, with a spherical cavity and a
//! cylindrical through-hole, 1e6 from the origin; a TetGen box with two box cavities (hole
//! points). Views: the eye inside a cavity, inside the gap between the arms, inside the
//! material, along an axis (faces seen exactly edge-on), zoomed, parallel and perspective, and
//! the same meshes split into K-D leaves by `tetkit partition` (non-convex leaves). The sweep
//! (20 meshes and K-D splits, 4,124 views) found no ray-order violation and no cycle; these views keep it
//! so.

mod common;

use std::path::Path;

use common::{fixture, tempdir, tetkit};
use serde_json::Value;

const U: &str = "newuser/nonconvex_u.msh";
const CAVITY: &str = "newuser/nonconvex_cavity.1.ele";

/// The U's offset.
const E6: f64 = 1e6;

fn at(p: [f64; 3]) -> String {
    format!("{},{},{}", p[0], p[1], p[2])
}

/// Views of the U (camera options).
fn u_views() -> Vec<Vec<String>> {
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    let inside = |p: [f64; 3], d: [f64; 3], up: &str, angle: &str| {
        let f = [p[0] + d[0], p[1] + d[1], p[2] + d[2]];
        vec![
            "--position".to_string(),
            at([E6 + p[0], E6 + p[1], E6 + p[2]]),
            "--focal".to_string(),
            at([E6 + f[0], E6 + f[1], E6 + f[2]]),
            "--up".to_string(),
            up.to_string(),
            "--view-angle".to_string(),
            angle.to_string(),
        ]
    };
    vec![
        // The arms overlap on screen, their faces seen exactly edge-on.
        s(&["--azimuth", "90", "--elevation", "0", "--parallel"]),
        s(&["--azimuth", "90", "--elevation", "0", "--zoom", "3"]),
        s(&["--azimuth", "100", "--elevation", "-30"]),
        s(&["--azimuth", "275", "--elevation", "30", "--parallel"]),
        // The eye in the spherical cavity, looking at an arm through the base.
        inside([1.5, 0.4, 0.5], [0.0, 1.0, 0.0], "0,0,1", "100"),
        // The eye in the gap between the arms, looking along the gap and across both arms.
        inside([1.5, 1.8, 0.5], [1.0, 0.0, 0.0], "0,0,1", "100"),
        inside([1.5, 1.8, 0.5], [0.0, -1.0, 0.0], "0,0,1", "30"),
        // The eye inside an arm's material, looking across the gap at the other arm.
        inside([0.35, 2.0, 0.5], [1.0, 0.4, 0.3], "0,0,1", "100"),
        // The same eye looking along z: the most pairs settled by the exact fallback (280).
        inside([0.35, 2.0, 0.5], [0.0, 0.0, 1.0], "0,1,0", "100"),
    ]
}

/// Views of the box with two cavities.
fn cavity_views() -> Vec<Vec<String>> {
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    vec![
        // The eye in one cavity, looking through the other.
        s(&[
            "--position",
            "0.55,0.5,0.5",
            "--focal",
            "1.55,0.5,0.5",
            "--up",
            "0,0,1",
            "--view-angle",
            "100",
        ]),
        s(&[
            "--position",
            "2.1,0.5,0.5",
            "--focal",
            "1.6,0.0,1.2",
            "--up",
            "0,0,1",
            "--view-angle",
            "100",
        ]),
        // The eye in the material between the cavities.
        s(&[
            "--position",
            "1.2,0.5,0.5",
            "--focal",
            "2.2,0.9,0.8",
            "--up",
            "0,0,1",
            "--view-angle",
            "100",
        ]),
        // The same eye looking along z: the most exact fallbacks of the sweep on this mesh.
        s(&[
            "--position",
            "1.2,0.5,0.5",
            "--focal",
            "1.2,0.5,1.5",
            "--up",
            "0,1,0",
            "--view-angle",
            "100",
        ]),
        // Along the axis through both cavities, from outside.
        s(&["--azimuth", "90", "--elevation", "0", "--parallel"]),
        s(&["--azimuth", "270", "--elevation", "0"]),
        s(&["--azimuth", "25", "--elevation", "-60", "--zoom", "2.5"]),
    ]
}

/// `tetkit sort --json` stats of `mesh` for `view`: no cycle, no broken constraint.
fn assert_sort_exact(dir: &Path, mesh: &Path, view: &[String], label: &str) {
    let out = dir.join("ordered.vtu");
    let mut args = vec![
        "sort".to_string(),
        mesh.display().to_string(),
        "-o".to_string(),
        out.display().to_string(),
        "--method".to_string(),
        "kd".to_string(),
        "--json".to_string(),
    ];
    args.extend(view.iter().cloned());
    let r = tetkit(&args);
    r.assert_success();
    let j: Value = serde_json::from_str(&r.stdout_str()).expect("sort --json");
    let stats = &j["stats"];
    for key in ["cycles", "cycle_tets", "broken_constraints"] {
        assert_eq!(stats[key], 0, "{label} {view:?}: {key} in {stats}");
    }
    assert!(
        stats["nonconvex_leaves"].as_u64().unwrap_or(0) > 0,
        "{label} {view:?}: no non-convex leaf, the view tests nothing: {stats}"
    );
}

/// `tetkit tradeoff` of `mesh` for `view`: kd has no ray-order violation and its pre-integrated
/// image is within 2/255 of the ray caster's.
fn assert_kd_matches_rays(dir: &Path, mesh: &Path, view: &[String], label: &str) {
    let out = dir.join("tradeoff");
    let mut args = vec![
        "tradeoff".to_string(),
        mesh.display().to_string(),
        "-o".to_string(),
        out.display().to_string(),
        "--scalar".to_string(),
        "coord:z".to_string(),
        "--size".to_string(),
        "96x72".to_string(),
        "--opacity".to_string(),
        "0:0.2,1:0.8".to_string(),
        "-q".to_string(),
    ];
    args.extend(view.iter().cloned());
    tetkit(&args).assert_success();
    let text = std::fs::read_to_string(out.join("tradeoff.json")).expect("tradeoff.json");
    let j: Value = serde_json::from_str(&text).expect("tradeoff.json parses");
    let rows = j["rows"].as_array().expect("rows");
    let kd: Vec<&Value> = rows.iter().filter(|r| r["sort"] == "kd").collect();
    assert_eq!(kd.len(), 3, "{label}: kd rows in {text}");
    for row in kd {
        assert_eq!(
            row["order_violations"], 0,
            "{label} {view:?}: kd ray-order violations: {row}"
        );
    }
    let open = |name: &str| {
        image::open(out.join(name))
            .expect("a tradeoff image")
            .to_rgb8()
    };
    let worst = common::max_channel_diff(&open("pt_kd_preintegrated.png"), &open("reference.png"));
    assert!(
        worst <= 2,
        "{label} {view:?}: kd + preintegrated is {worst}/255 off the ray caster"
    );
}

fn check(mesh: &Path, views: &[Vec<String>], label: &str) {
    for view in views {
        let dir = tempdir();
        assert_sort_exact(dir.path(), mesh, view, label);
        assert_kd_matches_rays(dir.path(), mesh, view, label);
    }
}

/// `tetkit partition MESH --leaves N` into `dir`: non-convex K-D leaves.
fn split(dir: &Path, mesh: &Path, leaves: &str) -> std::path::PathBuf {
    let out = dir.join("split.vtu");
    tetkit([
        "partition",
        &mesh.display().to_string(),
        "-o",
        &out.display().to_string(),
        "--leaves",
        leaves,
    ])
    .assert_success();
    out
}

#[test]
fn gmsh_u_with_cavity_and_hole_kd_is_exact_from_hard_views() {
    check(&fixture(U), &u_views(), "U");
}

#[test]
fn tetgen_box_with_two_cavities_kd_is_exact_from_hard_views() {
    check(&fixture(CAVITY), &cavity_views(), "cavities");
}

#[test]
fn split_nonconvex_meshes_kd_is_exact_from_hard_views() {
    let dir = tempdir();
    let u = split(dir.path(), &fixture(U), "6");
    check(&u, &u_views(), "U in 6 leaves");
    let dir2 = tempdir();
    let cav = split(dir2.path(), &fixture(CAVITY), "5");
    check(&cav, &cavity_views(), "cavities in 5 leaves");
}

/// A face a few fixed-point units thin on screen, not thin enough for its orientation to flip
/// (`fixtures/newuser/make_thin_face_tet.py`): a pixel centre 0.4 units from its edge went, by
/// the snapped edge, outside the tet, and its 0.024 chord was lost (10/255 on the tet alone,
/// 4/255 in the whole Gmsh box). Such a face now sends its tet to the per-pixel path.
#[test]
fn a_face_a_few_grid_units_thin_keeps_its_chord() {
    let dir = tempdir();
    let input = fixture("newuser/thin_face_tet.vtu");
    let render = |method: &str| {
        let out = dir.path().join(format!("{method}.png"));
        let r = tetkit([
            "render",
            input.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--method",
            method,
            "--size",
            "96x72",
            "--scalar",
            "coord:z",
            "--range",
            "0,2",
            "--unit-distance",
            "0.6928203230275509",
            "--opacity",
            "0:0.2,1:0.8",
            "--position",
            "1.5832575981823545,1.0,-5.666664853207268",
            "--focal",
            "1,1,1",
            "--up",
            "0,1,0",
            "--view-angle",
            "30",
        ]);
        r.assert_success();
        image::open(&out).unwrap().to_rgb8()
    };
    let (pt, rc) = (render("pt"), render("raycast"));
    // The pixel the chord was lost at is drawn by both.
    assert!(rc.get_pixel(45, 33).0[0] >= 8, "{:?}", rc.get_pixel(45, 33));
    let worst = common::max_channel_diff(&pt, &rc);
    assert!(worst <= 1, "PT is {worst}/255 off the ray caster");
}
