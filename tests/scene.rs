//! Scenes: the scene file (errors with lines), body surfaces from every format, exact crossings
//! against analytic bodies, and tet classification on meshes whose vertices lie on body surfaces.

mod common;

use std::path::{Path, PathBuf};

use tetkit::camera::Camera;
use tetkit::mesh::generate::structured_grid;
use tetkit::scene::{self, classify::classify, ray, Primitive, Shape};

fn fixture(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures/scenes/surfaces")
        .join(rel)
}

fn enclosed_volume(s: &scene::TriSurface) -> f64 {
    s.tris
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| s.points[i as usize]);
            tetkit::geom::dot(&a, &tetkit::geom::cross(&b, &c)) / 6.0
        })
        .sum()
}

#[test]
fn surfaces_from_every_format_are_closed_and_agree() {
    let stl = scene::surface::read(&fixture("sphere.stl")).unwrap();
    let vtp = scene::surface::read(&fixture("sphere.vtp")).unwrap();
    let vtp_ascii = scene::surface::read(&fixture("sphere_ascii.vtp")).unwrap();
    assert_eq!(stl.tris.len(), 320);
    assert_eq!(stl.points.len(), 162);
    assert_eq!(vtp.tris, vtp_ascii.tris);
    let v = enclosed_volume(&stl);
    let sphere = 4.0 / 3.0 * std::f64::consts::PI * 0.3f64.powi(3);
    assert!(v > 0.9 * sphere && v < sphere, "{v} vs {sphere}");
    assert!((enclosed_volume(&vtp) - v).abs() < 1e-6);
    let cube = scene::surface::read(&fixture("cube_ascii.stl")).unwrap();
    assert_eq!(enclosed_volume(&cube), 0.125);
    let cyl = scene::surface::read(&fixture("cylinder.obj")).unwrap();
    let vc = enclosed_volume(&cyl);
    // A 12-gon prism of circumradius 0.2 and height 0.8: 12/2 r^2 sin(30 deg) h.
    assert!((vc - 6.0 * 0.04 * 0.5 * 0.8).abs() < 1e-6, "{vc}");
    let cone = scene::surface::read(&fixture("cone.vtk")).unwrap();
    assert!(enclosed_volume(&cone) > 0.0);
    assert!(cone.contains(&[0.5, 0.5, 0.5]));
}

#[test]
fn broken_surfaces_name_file_and_edge() {
    let e = scene::surface::read(&fixture("open.stl"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("open.stl") && e.contains("open") && e.contains("edge ("),
        "{e}"
    );
    let e = scene::surface::read(&fixture("flipped.obj"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("flipped.obj") && e.contains("oriented"), "{e}");
}

fn parse_err(text: &str) -> String {
    scene::parse(text, &fixture("x.toml"))
        .unwrap_err()
        .to_string()
}

#[test]
fn scene_errors_name_file_and_line() {
    assert!(scene::parse("", Path::new("empty.toml"))
        .unwrap()
        .bodies
        .is_empty());
    let e = parse_err(
        "[[body]]\nshape = \"box\"\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 1.0]\ncolour = 3\n",
    );
    assert!(e.contains("x.toml: line 5") && e.contains("colour"), "{e}");
    let e = parse_err("\n[[body]]\nshape = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = -1.0\n");
    assert!(e.contains("line 5") && e.contains("radius"), "{e}");
    // Past 1e150 a radius's square overflows: refused, not drawn as no cut.
    let e = parse_err("[[body]]\nshape = \"sphere\"\ncenter = [0.5, 0.5, 0.5]\nradius = 1e300\n");
    assert!(e.contains("line 4") && e.contains("beyond 1e150"), "{e}");
    let e = parse_err("[[body]]\nshape = \"sphere\"\ncenter = [1e300, 0.0, 0.0]\nradius = 1.0\n");
    assert!(e.contains("line 3") && e.contains("beyond 1e150"), "{e}");
    let e = parse_err("[[body]]\nshape = \"blob\"\n");
    assert!(e.contains("line 2") && e.contains("blob"), "{e}");
    let e = parse_err("[[body]]\nshape = \"box\"\nmin = [0.0, 0.0, 0.0]\n");
    assert!(e.contains("line 1") && e.contains("max"), "{e}");
    let e = parse_err(
        "[[body]]\nshape = \"box\"\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 1.0]\nradius = 2.0\n",
    );
    assert!(
        e.contains("line 5") && e.contains("does not take 'radius'"),
        "{e}"
    );
    let mut nine = String::new();
    for i in 0..9 {
        nine +=
            &format!("[[body]]\nshape = \"sphere\"\ncenter = [{i}.0, 0.0, 0.0]\nradius = 1.0\n\n");
    }
    let e = parse_err(&nine);
    assert!(e.contains("line 41") && e.contains("at most 8"), "{e}");
    let e = parse_err("[[body]]\nshape = \"surface\"\nfile = \"missing.stl\"\n");
    assert!(e.contains("line 3") && e.contains("missing.stl"), "{e}");
    let e = parse_err("# an open surface\n[[body]]\nshape = \"surface\"\nfile = \"open.stl\"\n");
    assert!(
        e.contains("x.toml: line 4") && e.contains("open.stl") && e.contains("edge"),
        "{e}"
    );
    let e = parse_err("[[body]]\nshape = \"box\"\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 1.0]\naction = \"transfer\"\n");
    assert!(e.contains("line 1") && e.contains("[body.transfer]"), "{e}");
    let e = parse_err("rule = \"xor\"\n");
    assert!(e.contains("line 1") && e.contains("xor"), "{e}");
    let e = parse_err("[camera]\nview_angle = 200.0\n");
    assert!(e.contains("line 2"), "{e}");
    let e = parse_err("[transfer]\nopacity = [[0.5, 0.2], [0.1, 0.3]]\n");
    assert!(e.contains("line 2") && e.contains("decrease"), "{e}");
}

/// A body's transfer function: the error names the offending key's line inside
/// `[body.transfer]`, not the `[[body]]` line (nor the table header's).
#[test]
fn body_transfer_errors_name_the_offending_line() {
    let body = |keys: &str| {
        format!(
            "[[body]]\nshape = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\n\
             action = \"transfer\"\n[body.transfer]\n{keys}"
        )
    };
    for (keys, line, what) in [
        (
            "colormap = \"viridis\"\nopacity = [[0.5, 0.2], [0.1, 0.3]]\n",
            8,
            "decrease",
        ),
        ("opacity = [[0.0, 1.5]]\n", 7, "[0, 1]"),
        ("colormap = \"no-such-map\"\n", 7, "no-such-map"),
        (
            "range = [1.0, 0.0]\ncolormap = \"viridis\"\n",
            7,
            "min < max",
        ),
        (
            "colormap = \"viridis\"\nunit_distance = -2.0\n",
            8,
            "unit_distance",
        ),
        (
            "colormap = \"viridis\"\npreset = \"missing.json\"\n",
            8,
            "not both",
        ),
        ("preset = \"missing.json\"\n", 7, "missing.json"),
        // A point of three numbers was cut to two, an empty list meant the default ramp.
        (
            "opacity = [[0.0, 0.1, 3.0], [3.0, 0.5]]\n",
            7,
            "expected two numbers [scalar, opacity], found 3",
        ),
        ("opacity = [[0.0, 0.1], [1.0]]\n", 7, "point 1 [1.0]"),
        ("opacity = []\n", 7, "no points"),
    ] {
        let e = parse_err(&body(keys));
        assert!(
            e.contains(&format!("x.toml: line {line}:")) && e.contains(what),
            "{keys:?}: {e}"
        );
    }
    // A second body: lines count from the top of the file.
    let two = format!(
        "[[body]]\nshape = \"box\"\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 1.0]\n\n{}",
        body("colormap = \"viridis\"\nopacity = [[0.0, 0.5], [1.0, 2.0]]\n")
    );
    let e = parse_err(&two);
    assert!(e.contains("x.toml: line 13:"), "{e}");
}

#[test]
fn the_issue_form_and_a_full_scene_parse() {
    let s = scene::parse(
        "[[body]]\nshape = \"box\"\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 1.0]\naction = \"cut\"\n",
        Path::new("a.toml"),
    )
    .unwrap();
    assert_eq!(s.bodies.len(), 1);
    let text = std::fs::read_to_string(fixture("../example.toml")).unwrap();
    let s = scene::parse(&text, &fixture("../example.toml")).unwrap();
    assert_eq!(s.bodies.len(), 4);
    assert_eq!(s.rule, scene::Rule::Precedence);
    assert!(s.camera.position.is_some() && s.transfer.is_some());
    assert!(matches!(s.bodies[3].shape, Shape::Surface(_)));
    match &s.bodies[1].action {
        scene::Action::Transfer(t) => assert_eq!(t.opacity.len(), 4),
        a => panic!("{a:?}"),
    }
}

/// [`common::look::uv_sphere`] as a surface body (written as OBJ and read back).
fn uv_sphere(c: [f64; 3], r: f64, n: usize) -> scene::TriSurface {
    let (pts, tris) = common::look::uv_sphere(c, r, n);
    let text: String = pts
        .iter()
        .map(|p| format!("v {} {} {}\n", p[0], p[1], p[2]))
        .collect::<String>()
        + &tris
            .iter()
            .map(|t| format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1))
            .collect::<String>();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.obj");
    std::fs::write(&path, text).unwrap();
    scene::surface::read(&path).unwrap()
}

#[test]
fn tessellated_sphere_converges_to_the_analytic_one() {
    let cam = Camera {
        position: [0.3, 0.2, 4.0],
        focal: [0.0, 0.0, 0.0],
        up: [0.0, 1.0, 0.0],
        view_angle: 30.0,
        parallel: false,
        parallel_scale: 1.0,
    };
    let analytic = Primitive::Sphere {
        center: [0.0; 3],
        radius: 1.0,
    };
    let mut prev = f64::INFINITY;
    for n in [8, 16, 32, 64] {
        let s = uv_sphere([0.0; 3], 1.0, n);
        let mut worst = 0.0f64;
        let mut hits = Vec::new();
        let size = 40;
        for py in 0..size {
            for px in 0..size {
                let (o, d) = cam.pixel_ray(px as f64 + 0.5, py as f64 + 0.5, size, size);
                hits.clear();
                s.crossings(&o, &d, &mut hits);
                hits.sort_by(f64::total_cmp);
                assert!(
                    hits.len() % 2 == 0,
                    "odd crossings at pixel {px},{py}: {hits:?}"
                );
                let span = analytic.line_span(&o, &d);
                // Rays near the silhouette may miss the polyhedron while hitting the sphere;
                // compare the depths where both are hit.
                // (Depth errors blow up at grazing incidence, so only rays well inside the
                // silhouette are compared.)
                if let (Some((a, b)), 2) = (span, hits.len()) {
                    if b - a < 0.5 {
                        continue;
                    }
                    worst = worst.max((hits[0] - a).abs()).max((hits[1] - b).abs());
                }
            }
        }
        // Chord error of the tessellation: 1 - cos(pi / n) in radius, and depth errors of the
        // same order away from the silhouette; it must shrink as n grows.
        eprintln!("n {n}: worst depth error {worst}");
        assert!(worst < prev, "n {n}: worst {worst} not below {prev}");
        prev = worst;
    }
    assert!(prev < 0.01, "{prev}");
}

#[test]
fn surface_through_mesh_vertices_marks_exactly_the_inside() {
    // A 4^3 grid of unit cubes; a box and a cube surface with faces on grid planes.
    let mesh = structured_grid([4, 4, 4], [0.0; 3], [4.0; 3]);
    let text = format!(
        "[[body]]\nshape = \"box\"\nmin = [1.0, 1.0, 1.0]\nmax = [3.0, 3.0, 2.0]\n\
         [[body]]\nshape = \"surface\"\nfile = \"{}\"\n\
         [[body]]\nshape = \"box\"\nmin = [3.0, 1.0, 1.0]\nmax = [4.0, 3.0, 2.0]\n\
         [[body]]\nshape = \"sphere\"\ncenter = [40.0, 0.0, 0.0]\nradius = 1.0\n",
        fixture("cube_ascii.stl").display()
    );
    let s = scene::parse(&text, Path::new("t.toml")).unwrap();
    let codes = classify(&s, &mesh);
    let vol = |bit: u8| -> f64 {
        (0..mesh.tets.len())
            .filter(|&t| codes[t] >> bit & 1 == 1)
            .map(|t| {
                let p = mesh.tet_points(t);
                tetkit::geom::tet_volume(&p[0], &p[1], &p[2], &p[3]).abs()
            })
            .sum()
    };
    // Exactly the 2 x 2 x 1 cubes inside the box: nothing merely touching it.
    assert!((vol(0) - 4.0).abs() < 1e-12, "{}", vol(0));
    // The cube surface spans [0.25, 0.75]^3: inside the first grid cube only (no vertex on it).
    assert!(codes.iter().all(|&c| c & 2 == 0 || c & 1 == 0));
    assert!(vol(1) > 0.0 && vol(1) <= 1.0 + 1e-12);
    // Bodies 0 and 2 touch along x = 3: no tet is in both, the second holds 2 cubes.
    assert!(codes.iter().all(|&c| c & 0b101 != 0b101));
    assert!((vol(2) - 2.0).abs() < 1e-12);
    // Outside the mesh: no tet.
    assert_eq!(vol(3), 0.0);
}

#[test]
fn surface_and_box_with_the_same_faces_classify_alike() {
    // A closed surface with faces exactly on grid planes through mesh vertices and edges.
    let mesh = structured_grid([6, 6, 6], [0.0; 3], [1.5; 3]);
    let dir = tempfile::tempdir().unwrap();
    let stl = dir.path().join("b.stl");
    let (lo, hi) = ([0.25, 0.5, 0.25], [1.0, 1.25, 0.75]);
    let c = |i: usize| {
        [
            if i & 1 == 0 { lo[0] } else { hi[0] },
            if i & 2 == 0 { lo[1] } else { hi[1] },
            if i & 4 == 0 { lo[2] } else { hi[2] },
        ]
    };
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let mut text = String::from("solid b\n");
    for q in quads {
        for t in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
            text += "facet normal 0 0 0\nouter loop\n";
            for v in t {
                let p = c(v);
                text += &format!("vertex {} {} {}\n", p[0], p[1], p[2]);
            }
            text += "endloop\nendfacet\n";
        }
    }
    text += "endsolid b\n";
    std::fs::write(&stl, text).unwrap();
    let scene_text = format!(
        "[[body]]\nshape = \"surface\"\nfile = \"{}\"\n[[body]]\nshape = \"box\"\nmin = {lo:?}\nmax = {hi:?}\n",
        stl.display()
    );
    let s = scene::parse(&scene_text, Path::new("t.toml")).unwrap();
    let codes = classify(&s, &mesh);
    assert!(
        codes.iter().all(|&c| c == 0 || c == 3),
        "surface and box disagree"
    );
    assert_eq!(codes.iter().filter(|&&c| c == 3).count(), 6 * 3 * 3 * 2);
    // Pixel rays: the surface's crossings equal the box's, also through edges and vertices.
    let cam = Camera {
        position: [0.0, 0.0, 3.0],
        focal: [0.625, 0.875, 0.5],
        up: [0.0, 1.0, 0.0],
        view_angle: 30.0,
        parallel: true,
        parallel_scale: 1.0,
    };
    let v = ray::View::new(&s, cam, 16, 16);
    let mut r = ray::RayRegions::default();
    for py in 0..=32 {
        for px in 0..=32 {
            v.pixel(px as f64 * 0.5, py as f64 * 0.5, &mut r);
            assert_eq!(r.start, 0);
            // Both bodies cross at the same places (the crossing depths are rounded separately,
            // so they may differ in the last bit): every piece longer than that is 0 or 3.
            r.pieces(0.0, 10.0, |a, b, c| {
                assert!(b - a < 1e-12 || c == 0 || c == 3, "{r:?}")
            });
        }
    }
}

#[test]
fn culling_and_triangle_bins_change_no_code() {
    // Bodies seen by a camera inside one of them, and by an orthographic one.
    let text = format!(
        "[[body]]\nshape = \"surface\"\nfile = \"{}\"\n\
         [[body]]\nshape = \"box\"\nmin = [0.4, 0.4, 0.4]\nmax = [0.9, 0.6, 0.7]\n\
         [[body]]\nshape = \"cone\"\nstart = [0.5, 0.0, 0.5]\nend = [0.5, 0.5, 0.5]\nstart_radius = 0.3\nend_radius = 0.0\n",
        fixture("sphere.stl").display()
    );
    let s = scene::parse(&text, Path::new("t.toml")).unwrap();
    for cam in [
        Camera {
            position: [0.5, 0.45, 0.55],
            focal: [0.0, 0.0, 0.0],
            up: [0.0, 1.0, 0.0],
            view_angle: 60.0,
            parallel: false,
            parallel_scale: 1.0,
        },
        Camera {
            position: [2.0, 1.5, 3.0],
            focal: [0.5, 0.5, 0.5],
            up: [0.0, 1.0, 0.0],
            view_angle: 30.0,
            parallel: false,
            parallel_scale: 1.0,
        },
        Camera {
            position: [2.0, 1.5, 3.0],
            focal: [0.5, 0.5, 0.5],
            up: [0.0, 0.0, 1.0],
            view_angle: 30.0,
            parallel: true,
            parallel_scale: 0.6,
        },
    ] {
        let culled = ray::View::new(&s, cam, 48, 40);
        let mut all = ray::View::new(&s, cam, 48, 40);
        all.culling = false;
        let (mut a, mut b) = (ray::RayRegions::default(), ray::RayRegions::default());
        let mut crossings = 0;
        for py in 0..40 {
            for px in 0..48 {
                let (x, y) = (px as f64 + 0.5, py as f64 + 0.5);
                culled.pixel(x, y, &mut a);
                all.pixel(x, y, &mut b);
                assert_eq!(
                    (a.start, &a.depths, &a.codes),
                    (b.start, &b.depths, &b.codes)
                );
                crossings += a.depths.len();
            }
        }
        assert!(crossings > 100, "{crossings}");
    }
    // The camera inside the sphere surface starts with its bit set at every pixel.
    let v = ray::View::new(
        &s,
        Camera {
            position: [0.5, 0.45, 0.55],
            focal: [0.0, 0.0, 0.0],
            up: [0.0, 1.0, 0.0],
            view_angle: 60.0,
            parallel: false,
            parallel_scale: 1.0,
        },
        8,
        8,
    );
    let mut r = ray::RayRegions::default();
    v.pixel(3.5, 4.5, &mut r);
    assert_eq!(r.start & 1, 1);
}
