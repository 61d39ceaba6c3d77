//! Rendering fixtures shared by the render, GPU and scene tests: transfer functions, the point
//! field, orbit cameras, the box-cut-and-two-level-sphere scene, and UV spheres.

use tetkit::camera::Camera;
use tetkit::mesh::TetMesh;
use tetkit::render::field::Field;
use tetkit::render::transfer::{named_colormap, OpacitySpec, TransferFunction};

/// Viridis with the piecewise-linear opacity `opacity` (`s:a,...` as `--opacity` takes).
pub fn viridis_tf(opacity: &str, range: [f64; 2], unit: f64, nodes: usize) -> TransferFunction {
    TransferFunction::build(
        &named_colormap("viridis").unwrap(),
        Some(&OpacitySpec::parse(opacity).unwrap()),
        range,
        unit,
        nodes,
    )
    .unwrap()
}

/// The generated meshes' point array `scalar`.
pub fn point_field(m: &TetMesh) -> Field {
    Field::Point(m.point_data.get("scalar").unwrap().data.to_f64_vec())
}

/// The camera reset to the mesh, turned by `az` and `el` degrees, magnified by `zoom`.
pub fn orbit_camera(m: &TetMesh, az: f64, el: f64, parallel: bool, zoom: f64) -> Camera {
    let mut cam = Camera {
        parallel,
        ..Camera::default()
    };
    cam.reset_to(&m.bounds());
    cam.azimuth(az);
    cam.elevation(el);
    cam.zoom(zoom);
    cam
}

/// A box cut from `x = box_min_x` (above y = 0.62, beyond z = 0.55) and a sphere with the
/// paper's two-level opacity (0.07 below the threshold 0.5, 0.93 above) in inferno.
pub fn box_cut_and_two_level_sphere(box_min_x: f64) -> String {
    format!(
        r#"
[[body]]
shape = "box"
min = [{box_min_x:?}, -1.0, 0.55]
max = [2.0, 0.62, 2.0]
action = "cut"
[[body]]
shape = "sphere"
center = [0.45, 0.5, 0.5]
radius = 0.33
action = "transfer"
[body.transfer]
colormap = "inferno"
opacity = [[0.0, 0.07], [0.5, 0.07], [0.5, 0.93], [1.0, 0.93]]
"#
    )
}

/// A body given by `shape` (its shape keys) drawn opaque red, and a box cutting away x > 0.5:
/// the scene the tessellated-sphere convergence tests compare against the analytic sphere.
pub fn red_body_half_cut(shape: &str) -> String {
    format!("[[body]]\n{shape}\naction = \"transfer\"\n[body.transfer]\ncolormap = \"reds\"\nopacity = [[0.0, 0.95], [1.0, 0.95]]\n[[body]]\nshape = \"box\"\nmin = [0.5, -1.0, -1.0]\nmax = [2.0, 2.0, 2.0]\n")
}

/// A UV sphere with `n` segments around and `n / 2` rings: points and outward triangles.
pub fn uv_sphere(c: [f64; 3], r: f64, n: usize) -> (Vec<[f64; 3]>, Vec<[usize; 3]>) {
    let rings = n / 2;
    let mut pts = vec![[c[0], c[1], c[2] + r]];
    for i in 1..rings {
        let th = std::f64::consts::PI * i as f64 / rings as f64;
        for j in 0..n {
            let ph = 2.0 * std::f64::consts::PI * j as f64 / n as f64;
            pts.push([
                c[0] + r * th.sin() * ph.cos(),
                c[1] + r * th.sin() * ph.sin(),
                c[2] + r * th.cos(),
            ]);
        }
    }
    pts.push([c[0], c[1], c[2] - r]);
    let south = pts.len() - 1;
    let id = |i: usize, j: usize| 1 + (i - 1) * n + j % n;
    let mut tris = Vec::new();
    for j in 0..n {
        tris.push([0, id(1, j), id(1, j + 1)]);
        tris.push([south, id(rings - 1, j + 1), id(rings - 1, j)]);
    }
    for i in 1..rings - 1 {
        for j in 0..n {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (pts, tris)
}
