//! Rendering with scenes: cuts and region transfer functions in PT and the ray caster, against
//! independent references (a grid-aligned cut equals deleting those tets; PT against the ray
//! caster with the same scene), touching bodies, an eye inside a body (and inside the mesh, where
//! PT clips tets per pixel), a body outside the mesh, a tessellated sphere converging to the
//! analytic one, and the CLI.

mod common;

use std::path::Path;

use tetkit::camera::Camera;
use tetkit::locate::{GridParams, Topology};
use tetkit::mesh::generate::{jitter, structured_grid};
use tetkit::mesh::TetMesh;
use tetkit::render::cut::{self, BaseLook, RegionReport, SceneLook, ShaderCache};
use tetkit::render::field::Field;
use tetkit::render::image::Image;
use tetkit::render::integrate::Integration;
use tetkit::render::prepare::{self, TableSize};
use tetkit::render::pt::{self, View};
use tetkit::render::raycast::RayCaster;
use tetkit::render::transfer::{named_colormap, TransferFunction};
use tetkit::scene::{self, Scene};
use tetkit::sort::{Direction, Method, Sorter};

const BG: [f32; 3] = [0.0, 0.0, 0.0];
/// The CLI's default table size, which the render tolerances were stated for.
const TABLE: TableSize = TableSize {
    scalar: 128,
    length: 32,
};

fn base(m: &TetMesh) -> BaseLook {
    BaseLook {
        colors: named_colormap("viridis").unwrap(),
        range: [0.0, 1.0],
        unit_distance: prepare::default_unit_distance(m),
        nodes: 33,
    }
}

fn tf(m: &TetMesh) -> TransferFunction {
    common::look::viridis_tf(
        "0:0.1,0.4:0.5,0.6:0.2,1:0.8",
        [0.0, 1.0],
        prepare::default_unit_distance(m),
        33,
    )
}

fn scene_of(text: &str, dir: &Path) -> Scene {
    scene::parse(text, &dir.join("scene.toml")).unwrap()
}

fn cam_of(m: &TetMesh, az: f64, el: f64, parallel: bool) -> Camera {
    common::look::orbit_camera(m, az, el, parallel, 1.2)
}

struct Ctx<'a> {
    m: &'a TetMesh,
    f: Field,
    tf: TransferFunction,
    topo: Topology,
}

impl<'a> Ctx<'a> {
    fn new(m: &'a TetMesh) -> Ctx<'a> {
        Ctx {
            m,
            f: common::look::point_field(m),
            tf: tf(m),
            topo: Topology::build(&m.tets),
        }
    }

    fn caster(&self) -> RayCaster<'_> {
        RayCaster::new(
            &self.m.points,
            &self.m.tets,
            &self.f,
            &self.topo,
            GridParams::default(),
        )
    }

    fn raycast(&self, s: Option<&Scene>, cam: &Camera, n: u32) -> (Image, Option<RegionReport>) {
        let rc = self.caster();
        match s {
            None => (rc.render(&self.tf, cam, n, n).0, None),
            Some(s) => {
                let look = SceneLook::new(s, &self.tf, &base(self.m)).unwrap();
                let (img, _, rep) = cut::raycast(&rc, &look, cam, n, n);
                (img, Some(rep))
            }
        }
    }

    fn order(&self, cam: &Camera) -> Vec<u32> {
        Sorter::new(self.m, None)
            .unwrap()
            .order(cam, Method::Kd, Direction::FrontToBack)
            .order
    }

    fn pt(&self, s: Option<&Scene>, cam: &Camera, n: u32) -> (Image, Option<RegionReport>) {
        let order = self.order(cam);
        let lmax = prepare::longest_edge(self.m);
        let view = View::new(cam, n, n);
        match s {
            None => {
                let sh = prepare::shader(&self.tf, Integration::Preintegrated, TABLE, lmax);
                let img = pt::render(&view, &self.m.points, &self.m.tets, &self.f, &order, &sh).0;
                (img, None)
            }
            Some(s) => {
                let look = SceneLook::new(s, &self.tf, &base(self.m)).unwrap();
                let mut cache = ShaderCache::new(Integration::Preintegrated, TABLE, lmax);
                let (img, _, rep) = cut::pt_render(
                    &view,
                    cam,
                    &self.m.points,
                    &self.m.tets,
                    &self.f,
                    &order,
                    &look,
                    &mut cache,
                );
                (img, Some(rep))
            }
        }
    }
}

/// No NaN, and every pixel the reference draws is drawn (no holes).
fn no_holes(img: &Image, reference: &Image, what: &str) {
    assert!(!img.has_nan() && !reference.has_nan(), "{what}: NaN");
    for (i, (a, b)) in img.pixels.iter().zip(&reference.pixels).enumerate() {
        if b[3] > 2e-3 {
            assert!(
                a[3] > 0.0,
                "{what}: hole at pixel {i}: reference {b:?}, got {a:?}"
            );
        }
    }
}

/// PT against the ray caster with the same scene: RMSE and max within the render tolerance
/// (tests/render.rs: RMSE 0.004, max 0.06 for kd + preintegrated).
fn pt_matches_reference(c: &Ctx, s: &Scene, cam: &Camera, n: u32, what: &str) -> (Image, Image) {
    let (reference, _) = c.raycast(Some(s), cam, n);
    let (img, _) = c.pt(Some(s), cam, n);
    no_holes(&img, &reference, what);
    let e = img.error_against(&reference, BG);
    eprintln!("{what}: PT vs ray cast RMSE {:.5} max {:.5}", e.rmse, e.max);
    assert!(e.rmse < 0.004 && e.max < 0.06, "{what}: {e:?}");
    (img, reference)
}

fn max_diff(a: &Image, b: &Image) -> f64 {
    let e = a.error_against(b, BG);
    let alpha = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| (p[3] - q[3]).abs() as f64)
        .fold(0.0, f64::max);
    e.max.max(alpha)
}

#[test]
fn a_grid_aligned_box_cut_equals_deleting_its_tets() {
    // The box's faces lie on grid planes (through mesh vertices, edges and faces), so cutting it
    // must give exactly the image of the mesh without the tets inside it: an independent
    // reference with no body code at all.
    let m = structured_grid([6, 6, 6], [0.0; 3], [1.0; 3]);
    let mut notched = m.clone();
    notched.tets.retain(|t| {
        let c = [0, 1, 2].map(|k| t.iter().map(|&v| m.points[v as usize][k]).sum::<f64>() / 4.0);
        !(c[0] > 0.5 && c[1] > 0.5 && c[2] > 0.5)
    });
    notched.cell_data = Default::default();
    let dir = tempfile::tempdir().unwrap();
    let s = scene_of(
        "[[body]]\nshape = \"box\"\nmin = [0.5, 0.5, 0.5]\nmax = [1.5, 1.5, 1.5]\n",
        dir.path(),
    );
    let full = Ctx::new(&m);
    let cut = Ctx::new(&notched);
    for (az, el, par) in [(35.0, 25.0, false), (-20.0, 40.0, true), (0.0, 0.0, false)] {
        let cam = cam_of(&m, az, el, par);
        let n = 48;
        let (rc_scene, rep) = full.raycast(Some(&s), &cam, n);
        let (rc_notch, _) = cut.raycast(None, &cam, n);
        let d = max_diff(&rc_scene, &rc_notch);
        assert!(d < 1e-5, "az {az} el {el} parallel {par}: ray cast {d}");
        let rep = rep.unwrap();
        assert_eq!(rep.codes, vec!["0", "1"]);
        let (pt_scene, _) = full.pt(Some(&s), &cam, n);
        let (pt_notch, _) = cut.pt(None, &cam, n);
        no_holes(&pt_scene, &rc_notch, "pt box cut");
        let d = max_diff(&pt_scene, &pt_notch);
        assert!(d < 0.02, "az {az} el {el} parallel {par}: PT {d}");
        pt_matches_reference(&full, &s, &cam, n, "grid-aligned box");
    }
}

#[test]
fn box_cut_and_sphere_transfer_through_a_jittered_mesh() {
    let n3 = [6, 5, 6];
    let mut m = structured_grid(n3, [0.0; 3], [1.2, 1.0, 1.1]);
    jitter(&mut m, n3, 0.25, 7);
    let c = Ctx::new(&m);
    let dir = tempfile::tempdir().unwrap();
    // The paper's two-level opacity inside the sphere, a box cut through the middle.
    let s = scene_of(&common::look::box_cut_and_two_level_sphere(0.3), dir.path());
    for (az, el, par) in [(30.0, 20.0, false), (-60.0, 35.0, true)] {
        let cam = cam_of(&m, az, el, par);
        let (_, reference) = pt_matches_reference(&c, &s, &cam, 56, "box + sphere");
        // The scene changed the picture.
        let (plain, _) = c.raycast(None, &cam, 56);
        assert!(max_diff(&plain, &reference) > 0.1);
    }
    let (_, rep) = c.raycast(Some(&s), &cam_of(&m, 30.0, 20.0, false), 56);
    let rep = rep.unwrap();
    // Codes 00, 01 (cut), 10 (sphere), 11 (cut: the box comes first): cut, default, transfer.
    assert_eq!(rep.codes, vec!["00", "01", "10", "11"]);
    assert_eq!(rep.drawn_classes, 2);
    assert_eq!(rep.tables, 2);
    assert!(rep
        .classes
        .iter()
        .any(|k| k.pattern == "X1" && k.effect == "cut"));
}

#[test]
fn a_body_outside_the_mesh_changes_nothing_and_an_eye_inside_a_body_works() {
    let n3 = [5, 5, 5];
    let mut m = structured_grid(n3, [0.0; 3], [1.0; 3]);
    jitter(&mut m, n3, 0.2, 3);
    let c = Ctx::new(&m);
    let dir = tempfile::tempdir().unwrap();
    let cam = cam_of(&m, 25.0, 15.0, false);
    let n = 48;
    // Beside the mesh on screen and in depth: crossings are computed (it is in view) but no tet
    // meets them, so the images are bit for bit the plain ones.
    let outside = scene_of(
        "[[body]]\nshape = \"sphere\"\ncenter = [1.5, 0.5, 0.5]\nradius = 0.3\n",
        dir.path(),
    );
    let (p0, _) = c.pt(None, &cam, n);
    let (p1, rep) = c.pt(Some(&outside), &cam, n);
    assert!(rep.unwrap().pixels_with_crossings > 0);
    assert_eq!(p0.pixels, p1.pixels);
    let (r0, _) = c.raycast(None, &cam, n);
    let (r1, _) = c.raycast(Some(&outside), &cam, n);
    assert_eq!(r0.pixels, r1.pixels);

    // A sphere around the eye reaching into the mesh, with its own transfer function: every
    // ray starts inside it.
    let e = cam.position;
    let dist = {
        let c = m.bounds().center();
        ((e[0] - c[0]).powi(2) + (e[1] - c[1]).powi(2) + (e[2] - c[2]).powi(2)).sqrt()
    };
    let eye = scene_of(
        &format!(
            "[[body]]\nshape = \"sphere\"\ncenter = [{}, {}, {}]\nradius = {}\naction = \"transfer\"\n[body.transfer]\nopacity = [[0.0, 0.6], [1.0, 0.0]]\ncolormap = \"reds\"\n",
            e[0],
            e[1],
            e[2],
            dist
        ),
        dir.path(),
    );
    let (_, rep) = c.raycast(Some(&eye), &cam, n);
    assert_eq!(rep.unwrap().codes, vec!["0", "1"]);
    pt_matches_reference(&c, &eye, &cam, n, "eye inside a body");
    // The same body as a cut: what remains is the mesh beyond the sphere.
    let eye_cut = scene_of(
        &format!(
            "[[body]]\nshape = \"sphere\"\ncenter = [{}, {}, {}]\nradius = {}\n",
            e[0], e[1], e[2], dist
        ),
        dir.path(),
    );
    pt_matches_reference(&c, &eye_cut, &cam, n, "eye inside a cut");
    // An eye inside the mesh and inside a body, looking outwards.
    let inside_cam = Camera {
        position: [0.5, 0.5, 0.5],
        focal: [0.5, 0.5, -1.0],
        ..Camera::default()
    };
    let small = scene_of(
        "[[body]]\nshape = \"box\"\nmin = [0.3, 0.3, 0.3]\nmax = [0.7, 0.7, 0.7]\n",
        dir.path(),
    );
    let (img, _) = c.raycast(Some(&small), &inside_cam, 32);
    assert!(!img.has_nan());
    // The cut box around the eye removes the first 0.2 of every central ray.
    let (plain, _) = c.raycast(None, &inside_cam, 32);
    let mid = 16 * 32 + 16;
    assert!(img.pixels[mid][3] < plain.pixels[mid][3]);
}

#[test]
fn pt_splits_tets_around_an_eye_inside_the_mesh_at_body_crossings() {
    // Tets with a vertex behind the eye take PT's per-pixel clipping path; a body whose surface
    // passes close to the eye crosses exactly those tets, so their segments must be split there
    // (dropping them instead was off by RMSE 0.16 here).
    let n3 = [5, 5, 5];
    let mut m = structured_grid(n3, [0.0; 3], [1.0; 3]);
    jitter(&mut m, n3, 0.2, 11);
    let c = Ctx::new(&m);
    let dir = tempfile::tempdir().unwrap();
    let n = 40;
    for (name, focal) in [("-z", [0.5, 0.5, -1.0]), ("oblique", [0.1, 0.2, 0.0])] {
        let cam = Camera {
            position: [0.5, 0.5, 0.5],
            focal,
            ..Camera::default()
        };
        let transfer = scene_of(
            "[[body]]\nshape = \"box\"\nmin = [0.43, 0.44, 0.45]\nmax = [0.56, 0.57, 0.58]\naction = \"transfer\"\n[body.transfer]\nopacity = [[0.0, 0.9], [1.0, 0.9]]\ncolormap = \"reds\"\n",
            dir.path(),
        );
        let (_, rep) = c.pt(Some(&transfer), &cam, n);
        assert!(rep.unwrap().split_fragments > 0, "{name}: nothing split");
        pt_matches_reference(
            &c,
            &transfer,
            &cam,
            n,
            &format!("{name}: transfer box at the eye"),
        );
        let cut = scene_of(
            "[[body]]\nshape = \"sphere\"\ncenter = [0.5, 0.5, 0.5]\nradius = 0.07\n",
            dir.path(),
        );
        pt_matches_reference(&c, &cut, &cam, n, &format!("{name}: cut sphere at the eye"));
    }
}

#[test]
fn touching_bodies_neither_leave_gaps_nor_count_twice() {
    // Not jittered: an exact grid makes the two-boxes-vs-one comparison independent of PT's own
    // error (plain PT vs the ray caster on jittered grids: see the test at the end).
    let m = structured_grid([6, 6, 6], [0.0; 3], [1.0; 3]);
    let c = Ctx::new(&m);
    let dir = tempfile::tempdir().unwrap();
    let cam = cam_of(&m, 40.0, 30.0, false);
    let n = 48;
    // Two boxes sharing the face x = 0.5, both carrying the same transfer function, equal one
    // box spanning both: no seam (gap) and no doubled piece at the shared face.
    let tfs = "action = \"transfer\"\n[body.transfer]\ncolormap = \"reds\"\nopacity = [[0.0, 0.9], [1.0, 0.3]]\n";
    let two = scene_of(
        &format!(
            "rule = \"union\"\n[[body]]\nshape = \"box\"\nmin = [0.2, 0.2, 0.2]\nmax = [0.5, 0.8, 0.8]\n{tfs}[[body]]\nshape = \"box\"\nmin = [0.5, 0.2, 0.2]\nmax = [0.8, 0.8, 0.8]\n{tfs}"
        ),
        dir.path(),
    );
    let one = scene_of(
        &format!("[[body]]\nshape = \"box\"\nmin = [0.2, 0.2, 0.2]\nmax = [0.8, 0.8, 0.8]\n{tfs}"),
        dir.path(),
    );
    let (r2, rep) = c.raycast(Some(&two), &cam, n);
    let (r1, _) = c.raycast(Some(&one), &cam, n);
    let d = max_diff(&r1, &r2);
    assert!(d < 1e-6, "ray cast: two touching boxes vs one: {d}");
    // The shared face is crossed twice at one depth: no code 11 has any length there.
    assert!(!rep.unwrap().codes.contains(&"11".to_string()));
    let (p2, _) = c.pt(Some(&two), &cam, n);
    let (p1, _) = c.pt(Some(&one), &cam, n);
    let d = max_diff(&p1, &p2);
    assert!(d < 1e-5, "PT: two touching boxes vs one: {d}");
    pt_matches_reference(&c, &two, &cam, n, "touching boxes");
    // Touching cuts: same story.
    let two_cuts = scene_of(
        "[[body]]\nshape = \"box\"\nmin = [0.2, 0.2, 0.2]\nmax = [0.5, 0.8, 0.8]\n[[body]]\nshape = \"box\"\nmin = [0.5, 0.2, 0.2]\nmax = [0.8, 0.8, 0.8]\n",
        dir.path(),
    );
    let one_cut = scene_of(
        "[[body]]\nshape = \"box\"\nmin = [0.2, 0.2, 0.2]\nmax = [0.8, 0.8, 0.8]\n",
        dir.path(),
    );
    let d = max_diff(
        &c.raycast(Some(&two_cuts), &cam, n).0,
        &c.raycast(Some(&one_cut), &cam, n).0,
    );
    assert!(d < 1e-6, "touching cuts: {d}");
}

/// [`common::look::uv_sphere`] as ASCII STL.
fn uv_sphere_stl(path: &Path, c: [f64; 3], r: f64, n: usize) {
    let (pts, tris) = common::look::uv_sphere(c, r, n);
    // ASCII STL: every triangle repeats its corners (the reader welds them; `{}` prints each
    // coordinate so it reads back exactly).
    let mut text = String::from("solid sphere\n");
    for t in &tris {
        text += " facet normal 0 0 0\n  outer loop\n";
        for &v in t {
            let p = pts[v];
            text += &format!("   vertex {} {} {}\n", p[0], p[1], p[2]);
        }
        text += "  endloop\n endfacet\n";
    }
    text += "endsolid sphere\n";
    std::fs::write(path, text).unwrap();
}

#[test]
fn a_tessellated_sphere_converges_to_the_analytic_sphere() {
    let n3 = [6, 6, 6];
    let mut m = structured_grid(n3, [0.0; 3], [1.0; 3]);
    jitter(&mut m, n3, 0.2, 9);
    let c = Ctx::new(&m);
    let dir = tempfile::tempdir().unwrap();
    let cam = cam_of(&m, 20.0, 30.0, false);
    let n = 48;
    let body = common::look::red_body_half_cut;
    let analytic = scene_of(
        &body("shape = \"sphere\"\ncenter = [0.5, 0.5, 0.5]\nradius = 0.4"),
        dir.path(),
    );
    let (ra, _) = c.raycast(Some(&analytic), &cam, n);
    let (pa, _) = c.pt(Some(&analytic), &cam, n);
    let mut prev_rc = f64::INFINITY;
    let mut prev_pt = f64::INFINITY;
    for k in [8, 16, 32, 64] {
        let f = dir.path().join(format!("s{k}.stl"));
        uv_sphere_stl(&f, [0.5, 0.5, 0.5], 0.4, k);
        let s = scene_of(
            &body(&format!("shape = \"surface\"\nfile = \"s{k}.stl\"")),
            dir.path(),
        );
        let (rs, _) = c.raycast(Some(&s), &cam, n);
        let (ps, _) = c.pt(Some(&s), &cam, n);
        assert!(!rs.has_nan() && !ps.has_nan());
        let (er, ep) = (
            rs.error_against(&ra, BG).rmse,
            ps.error_against(&pa, BG).rmse,
        );
        eprintln!("sphere of {k} segments: RMSE against the analytic sphere: ray cast {er:.5}, PT {ep:.5}");
        assert!(er < prev_rc && ep < prev_pt, "{k}: {er} {ep}");
        prev_rc = er;
        prev_pt = ep;
    }
    assert!(prev_rc < 0.01 && prev_pt < 0.01, "{prev_rc} {prev_pt}");
}

fn tetkit_cli(args: &[&str]) -> (bool, String, String) {
    common::tetkit(args).parts()
}

fn fixture(rel: &str) -> String {
    common::fixture(rel).display().to_string()
}

#[test]
fn cli_empty_scene_is_no_scene_and_bodies_report_their_codes() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = fixture("scenes/cube_mesh.vtk");
    let empty = dir.path().join("empty.toml");
    std::fs::write(&empty, "").unwrap();
    for method in ["pt", "raycast"] {
        let plain = dir.path().join(format!("plain_{method}.png"));
        let with = dir.path().join(format!("empty_{method}.png"));
        for (out, scene) in [(&plain, None), (&with, Some(&empty))] {
            let mut a = vec![
                "render",
                &mesh,
                "-o",
                out.to_str().unwrap(),
                "--size",
                "48x40",
                "--method",
                method,
                "--azimuth",
                "30",
                "-q",
            ];
            if let Some(s) = scene {
                a.extend(["--scene", s.to_str().unwrap()]);
            }
            let (ok, _, err) = tetkit_cli(&a);
            assert!(ok, "{err}");
        }
        assert_eq!(
            std::fs::read(&plain).unwrap(),
            std::fs::read(&with).unwrap(),
            "{method}: an empty scene must render exactly as no scene"
        );
    }

    // The README's scene (camera and default transfer function in the file, four bodies).
    let scene = fixture("scenes/example.toml");
    let mut reports = Vec::new();
    for method in ["pt", "raycast"] {
        let out = dir.path().join(format!("ex_{method}.png"));
        let (ok, stdout, err) = tetkit_cli(&[
            "render",
            &mesh,
            "--scene",
            &scene,
            "-o",
            out.to_str().unwrap(),
            "--size",
            "64x64",
            "--method",
            method,
            "--json",
            "-q",
        ]);
        assert!(ok, "{err}");
        let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
        let frame = &v["frames"][0]["regions"];
        let codes: Vec<String> = frame["codes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_str().unwrap().to_string())
            .collect();
        // Outside every body, inside the corner cut, inside the core sphere.
        for c in ["0000", "0001", "0010"] {
            assert!(codes.contains(&c.to_string()), "{method}: {codes:?}");
        }
        // Everything cut merges away; two drawn classes (default, the core's transfer) remain.
        assert_eq!(frame["drawn_classes"], 2, "{method}: {frame}");
        assert_eq!(frame["tables"], 2, "{method}: {frame}");
        assert!(frame["classes"].as_array().unwrap().len() < codes.len());
        reports.push(image::open(&out).unwrap().to_rgb8());
    }
    // PT and the reference agree on the README scene.
    let (a, b) = (&reports[0], &reports[1]);
    let worst = a
        .pixels()
        .zip(b.pixels())
        .flat_map(|(p, q)| (0..3).map(move |k| (p[k] as i32 - q[k] as i32).abs()))
        .max()
        .unwrap();
    assert!(
        worst <= 20,
        "PT vs ray cast on the README scene: {worst}/255"
    );

    // The command line overrides the scene's camera.
    let moved = dir.path().join("moved.png");
    let (ok, _, err) = tetkit_cli(&[
        "render",
        &mesh,
        "--scene",
        &scene,
        "-o",
        moved.to_str().unwrap(),
        "--size",
        "64x64",
        "--position",
        "0.5,0.5,4",
        "-q",
    ]);
    assert!(ok, "{err}");
    assert_ne!(image::open(&moved).unwrap().to_rgb8(), reports[0]);

    // A bad scene fails with its line, and leaves no image.
    let bad = dir.path().join("bad.toml");
    std::fs::write(
        &bad,
        "[[body]]\nshape = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1.0\ncolour = 3\n",
    )
    .unwrap();
    let out = dir.path().join("bad.png");
    let (ok, _, err) = tetkit_cli(&[
        "render",
        &mesh,
        "--scene",
        bad.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(err.contains("bad.toml") && err.contains("line 5"), "{err}");
    assert!(!out.exists());
    // A body's transfer function that cannot be built names the offending key's line inside
    // [body.transfer] (line 9), not the [[body]] line (3).
    std::fs::write(
        &bad,
        "# a scene\n\n[[body]]\nshape = \"sphere\"\ncenter = [0.5, 0.5, 0.5]\nradius = 0.3\naction = \"transfer\"\n[body.transfer]\ncolormap = \"no-such-map\"\n",
    )
    .unwrap();
    let (ok, _, err) = tetkit_cli(&[
        "render",
        &mesh,
        "--scene",
        bad.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(
        err.contains("bad.toml: line 9") && err.contains("no-such-map"),
        "{err}"
    );
    assert!(!out.exists());
}

#[test]
fn a_vtk_cube_surface_through_mesh_vertices_cuts_like_the_box_and_like_deleting_tets() {
    // The fixture mesh has vertices every 0.25; VTK's cube [0.25, 0.75]^3 (an STL) has its faces
    // on mesh faces, through mesh vertices and edges.
    let grid = formats::read(Path::new(&fixture("scenes/cube_mesh.vtk"))).unwrap();
    let (mut m, _, _) = tetkit::partition::input::tets_of(&grid, "cube_mesh").unwrap();
    // Scalars to [0, 1] for the test transfer function.
    let s: Vec<f64> = m
        .points
        .iter()
        .map(|p| (p[0] + 2.0 * p[1] + 3.0 * p[2]) / 6.0)
        .collect();
    m.point_data = Default::default();
    m.point_data.insert(formats::DataArray::new(
        "scalar",
        1,
        formats::ArrayData::Float64(s),
    ));
    m.cell_data = Default::default();
    let inside = |t: &[u32; 4]| {
        let c = [0, 1, 2].map(|k| t.iter().map(|&v| m.points[v as usize][k]).sum::<f64>() / 4.0);
        c.iter().all(|&x| x > 0.25 && x < 0.75)
    };
    let mut hollow = m.clone();
    hollow.tets.retain(|t| !inside(t));
    let surface = scene::parse(
        &format!(
            "[[body]]\nshape = \"surface\"\nfile = \"{}\"\n",
            fixture("scenes/surfaces/cube_ascii.stl")
        ),
        Path::new("s.toml"),
    )
    .unwrap();
    let boxed = scene::parse(
        "[[body]]\nshape = \"box\"\nmin = [0.25, 0.25, 0.25]\nmax = [0.75, 0.75, 0.75]\n",
        Path::new("b.toml"),
    )
    .unwrap();
    let full = Ctx::new(&m);
    let cut = Ctx::new(&hollow);
    // The cut cube is hidden inside the mesh: see it through a low opacity, head on (faces seen
    // edge-on) and from a corner.
    for (az, el) in [(0.0, 0.0), (35.0, 30.0)] {
        let cam = cam_of(&m, az, el, false);
        let n = 40;
        let (a, _) = full.raycast(Some(&surface), &cam, n);
        let (b, _) = full.raycast(Some(&boxed), &cam, n);
        let (c, _) = cut.raycast(None, &cam, n);
        assert!(
            max_diff(&a, &b) < 1e-6,
            "surface vs box {}",
            max_diff(&a, &b)
        );
        assert!(
            max_diff(&a, &c) < 1e-5,
            "surface vs deleted tets {}",
            max_diff(&a, &c)
        );
        assert!(max_diff(&a, &full.raycast(None, &cam, n).0) > 0.01);
        let (p, _) = full.pt(Some(&surface), &cam, n);
        no_holes(&p, &c, "VTK cube surface");
        let e = p.error_against(&c, BG);
        assert!(
            e.rmse < 0.004 && e.max < 0.06,
            "PT with the VTK cube: {e:?}"
        );
    }
}

#[test]
fn vtk_spheres_of_increasing_resolution_converge_to_the_analytic_sphere() {
    if !common::require_vtk("vtk_spheres_of_increasing_resolution_converge") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let code = r#"
import sys, vtk
for res in (8, 16, 32, 64):
    s = vtk.vtkSphereSource()
    s.SetCenter(0.5, 0.5, 0.5)
    s.SetRadius(0.4)
    s.SetThetaResolution(res)
    s.SetPhiResolution(res)
    w = vtk.vtkXMLPolyDataWriter()
    w.SetFileName(sys.argv[1] + "/vtk%d.vtp" % res)
    w.SetInputConnection(s.GetOutputPort())
    w.Write()
"#;
    common::vtk_python(code, &[dir.path().to_str().unwrap()]);
    let n3 = [6, 6, 6];
    let mut m = structured_grid(n3, [0.0; 3], [1.0; 3]);
    jitter(&mut m, n3, 0.2, 9);
    let c = Ctx::new(&m);
    let cam = cam_of(&m, 20.0, 30.0, false);
    let n = 48;
    let body = common::look::red_body_half_cut;
    let analytic = scene_of(
        &body("shape = \"sphere\"\ncenter = [0.5, 0.5, 0.5]\nradius = 0.4"),
        dir.path(),
    );
    let (ra, _) = c.raycast(Some(&analytic), &cam, n);
    let mut prev = f64::INFINITY;
    for k in [8, 16, 32, 64] {
        let s = scene_of(
            &body(&format!("shape = \"surface\"\nfile = \"vtk{k}.vtp\"")),
            dir.path(),
        );
        let (rs, _) = c.raycast(Some(&s), &cam, n);
        assert!(!rs.has_nan());
        let e = rs.error_against(&ra, BG).rmse;
        eprintln!("VTK sphere {k} x {k}: RMSE against the analytic sphere {e:.5}");
        assert!(e < prev, "{k}: {e} not below {prev}");
        prev = e;
    }
    assert!(prev < 0.01, "{prev}");
}

/// Two views where plain PT was seen 0.10 and 0.069 off the ray caster at single pixels, on a
/// branch without 323da7b (which decides a face's front/back from its unsnapped projection: a
/// nearly edge-on face could flip sign on the 1/256-pixel grid and drop its tet), so most likely
/// that bug. On main they measure max 2.8e-4 and 7.0e-4.
#[test]
fn plain_pt_matches_the_ray_caster_at_former_outlier_views() {
    let cases = [
        ([6usize, 6, 6], 0.2, 5u64, 40.0, 30.0, false, 48u32),
        ([6, 5, 6], 0.25, 7, 150.0, -35.0, true, 56),
    ];
    for (n3, amount, seed, az, el, parallel, n) in cases {
        let mut m = structured_grid(n3, [0.0; 3], [1.0; 3]);
        jitter(&mut m, n3, amount, seed);
        let c = Ctx::new(&m);
        let cam = cam_of(&m, az, el, parallel);
        let (reference, _) = c.raycast(None, &cam, n);
        let (img, _) = c.pt(None, &cam, n);
        no_holes(&img, &reference, "jittered grid");
        let e = img.error_against(&reference, BG);
        assert!(e.rmse < 5e-4 && e.max < 5e-3, "{n3:?} seed {seed}: {e:?}");
    }
}

/// The bodies' ray caster integrates exactly: asking it for the table lookup is refused by
/// name instead of silently ignored.
#[test]
fn a_table_lookup_asked_of_the_bodies_ray_caster_is_refused() {
    let mesh = common::fixture("scenes/cube_mesh.vtk");
    let scene = common::fixture("scenes/example.toml");
    let dir = common::tempdir();
    let out = dir.path().join("x.png");
    common::tetkit([
        "render".as_ref(),
        mesh.as_os_str(),
        "--scene".as_ref(),
        scene.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--method".as_ref(),
        "raycast".as_ref(),
        "--ray-integration".as_ref(),
        "preintegrated".as_ref(),
        "--size".as_ref(),
        "16x16".as_ref(),
    ])
    .assert_failure(&[
        "example.toml",
        "--ray-integration preintegrated is not supported",
    ]);
    assert!(!out.exists());
}
