//! PT against the ray-cast reference: every projection class, snapped faces, cracks, the eye inside the mesh, schedules.

use super::*;
use crate::camera::Camera;
use crate::locate::{GridParams, Topology};
use crate::mesh::generate::{jitter, structured_grid};
use crate::render::integrate::PreintTable;
use crate::render::raycast::RayCaster;
use crate::render::transfer::{named_colormap, OpacitySpec, TransferFunction};

fn tf() -> TransferFunction {
    TransferFunction::build(
        &named_colormap("viridis").unwrap(),
        Some(&OpacitySpec::parse("0:0.2,0.5:0.7,1:0.4").unwrap()),
        [0.0, 1.0],
        0.5,
        9,
    )
    .unwrap()
}

/// PT against the ray caster on the same view: max channel error, and that every pixel the
/// reference covers is covered (no holes) and nothing is NaN.
fn compare(
    points: &[[f64; 3]],
    tets: &[[u32; 4]],
    s: &[f64],
    cam: &Camera,
    n: u32,
) -> (f64, PtStats) {
    compare_with(points, tets, s, cam, n, &tf())
}

fn compare_with(
    points: &[[f64; 3]],
    tets: &[[u32; 4]],
    s: &[f64],
    cam: &Camera,
    n: u32,
    tf: &TransferFunction,
) -> (f64, PtStats) {
    let field = Field::Point(s.to_vec());
    let tf = tf.clone();
    let topo = Topology::build(tets);
    let rc = RayCaster::new(points, tets, &field, &topo, GridParams::default());
    let (reference, _) = rc.render(&tf, cam, n, n);
    let lmax = 3.0;
    let shader = Shader::Pre(PreintTable::build(&tf, 129, 65, lmax));
    let order: Vec<u32> = (0..tets.len() as u32).collect();
    let (img, stats, _) = render(&View::new(cam, n, n), points, tets, &field, &order, &shader);
    (worst_against(&img, &reference), stats)
}

/// Largest channel difference of `img` from `reference`, after checking that `img` has no NaN
/// and no hole where the reference has any opacity.
fn worst_against(img: &Image, reference: &Image) -> f64 {
    assert!(!img.has_nan());
    let mut worst = 0.0f64;
    for (i, (a, b)) in img.pixels.iter().zip(&reference.pixels).enumerate() {
        if b[3] > 1e-3 {
            assert!(a[3] > 0.0, "hole at pixel {i}: reference {b:?}");
        }
        for k in 0..4 {
            worst = worst.max((a[k] - b[k]).abs() as f64);
        }
    }
    worst
}

fn cams() -> Vec<Camera> {
    let par = Camera {
        position: [0.0, 0.0, 10.0],
        parallel: true,
        parallel_scale: 1.0,
        ..Camera::default()
    };
    let persp = Camera {
        position: [0.0, 0.0, 4.0],
        view_angle: 30.0,
        ..Camera::default()
    };
    vec![par, persp]
}

#[test]
fn every_projection_class_matches_the_ray_caster() {
    let base = [[-0.8, -0.6, 0.0], [0.8, -0.6, 0.0], [0.0, 0.8, 0.0]];
    let cases: [([f64; 3], usize); 3] = [
        ([0.0, 0.0, 0.7], 0),  // class 1: apex inside the base
        ([0.0, -0.6, 0.7], 2), // class 3 (parallel): apex over an edge, a face seen edge-on
        ([0.0, 0.8, 0.7], 3),  // class 4 (parallel): apex over a vertex, an edge seen end-on
    ];
    for (apex, class) in cases {
        let pts = vec![base[0], base[1], base[2], apex];
        let tets = [[0u32, 1, 2, 3]];
        let s = [0.1, 0.9, 0.5, 0.3];
        for (ci, cam) in cams().iter().enumerate() {
            let (err, st) = compare(&pts, &tets, &s, cam, 48);
            if ci == 0 {
                assert_eq!(st.class[class], 1, "apex {apex:?}: {st:?}");
            }
            assert!(err < 0.01, "apex {apex:?} camera {ci}: error {err}");
        }
    }
    // Class 2: two edges cross.
    let pts = vec![
        [-0.8, 0.0, 0.0],
        [0.8, 0.0, 0.0],
        [0.0, -0.8, 0.7],
        [0.0, 0.8, 0.7],
    ];
    for (ci, cam) in cams().iter().enumerate() {
        let (err, st) = compare(&pts, &[[0, 1, 2, 3]], &[0.0, 1.0, 0.2, 0.6], cam, 48);
        assert_eq!(st.class[1], 1, "{st:?}");
        assert!(err < 0.01, "class 2 camera {ci}: error {err}");
    }
    // Flat: all four points on one line of sight plane (a tet seen exactly edge-on in both
    // directions collapses to a segment): nothing drawn, nothing NaN.
    let flat = vec![
        [0.0, -0.5, 0.0],
        [0.0, 0.5, 0.0],
        [0.0, -0.2, 0.7],
        [0.0, 0.3, 0.4],
    ];
    let (_, st) = compare(
        &flat,
        &[[0, 1, 2, 3]],
        &[0.0, 1.0, 0.2, 0.6],
        &cams()[0],
        32,
    );
    assert_eq!(st.class[4], 1);
}

#[test]
fn face_flipped_by_snapping_keeps_its_tet() {
    // Face [0, 3, 2] is seen nearly edge-on: its projected area is +282 (1/256 px)^2 unsnapped
    // but -1023 on the fixed-point grid. From a Gmsh mesh (fixtures/gmsh/cavity.vtk, tet 420).
    let pts = vec![
        [0.8588713258240279, 0.0, 0.2507062282134793],
        [1.0, 0.1220084679281462, 0.1220084679281462],
        [0.8779915320718535, 0.0, 0.1220084679281463],
        [0.7853681295419649, 0.2159403721809315, 0.2454360734388493],
    ];
    let c = [0.5, 0.5, 0.5];
    let d = 3f64.sqrt();
    let cam = Camera {
        position: [c[0] - 0.4 * d, c[1] + 0.3 * d, c[2] + 2.0 * d],
        focal: c,
        up: [0.0, 1.0, 0.0],
        parallel: true,
        parallel_scale: 0.6 * d,
        ..Camera::default()
    };
    let proj = project_points(&View::new(&cam, 64, 64), &pts);
    let d = face_areas(&[0, 1, 2, 3].map(|k| (proj[k].fx, proj[k].fy)));
    assert!(d[1] < 0, "the snapped face must flip for this test: {d:?}");
    let (err, _) = compare(&pts, &[[0, 1, 2, 3]], &[0.2, 0.9, 0.4, 0.7], &cam, 64);
    assert!(err < 0.01, "error {err}");
}

#[test]
fn axis_aligned_grid_has_no_cracks() {
    // Every face of this grid is parallel or perpendicular to the view, every vertical edge
    // is seen end-on: classes 3 and 4 everywhere, and shared edges lie on pixel centres.
    let m = structured_grid([4, 4, 3], [-0.75, -0.75, -0.5], [0.75, 0.75, 0.5]);
    let s: Vec<f64> = m.point_data.get("scalar").unwrap().data.to_f64_vec();
    // One colour, varying opacity: compositing then commutes, so the mesh order is as good
    // as a visibility order and only coverage and per-fragment values are tested.
    let c = [0.9, 0.5, 0.2];
    let tf = TransferFunction::build(
        &crate::render::transfer::ColorSource::Relative(vec![(0.0, c), (1.0, c)]),
        Some(&OpacitySpec::parse("0:0.1,1:0.8").unwrap()),
        [0.0, 1.0],
        0.5,
        9,
    )
    .unwrap();
    for cam in cams() {
        let (err, st) = compare_with(&m.points, &m.tets, &s, &cam, 40, &tf);
        assert!(err < 0.01, "grid error {err} {st:?}");
    }
}

/// PT of `m` from `cam` in the MPVO order, with a schedule, against the ray caster.
fn against_reference(
    m: &crate::mesh::TetMesh,
    cam: &Camera,
    n: u32,
    schedule: Schedule,
) -> (f64, PtStats, Image) {
    use crate::sort::{Direction, Method, Sorter};
    let s: Vec<f64> = m.point_data.get("scalar").unwrap().data.to_f64_vec();
    let field = Field::Point(s);
    let tf = tf();
    let topo = Topology::build(&m.tets);
    let rc = RayCaster::new(&m.points, &m.tets, &field, &topo, GridParams::default());
    let (reference, _) = rc.render(&tf, cam, n, n);
    let sorter = Sorter::new(m, None).unwrap();
    let order = sorter
        .order(cam, Method::Mpvo, Direction::FrontToBack)
        .order;
    let lmax = crate::render::prepare::longest_edge(m) * 1.0001;
    let shader = Shader::Pre(PreintTable::build(&tf, 257, 65, lmax));
    let view = View::new(cam, n, n);
    let (img, stats, _) = render_with(&view, &m.points, &m.tets, &field, &order, &shader, schedule);
    (worst_against(&img, &reference), stats, img)
}

#[test]
fn eye_inside_the_mesh_matches_the_ray_caster() {
    // The eye inside a tet of a jittered grid, looking along a generic direction: the tets
    // around the eye reach behind it and take the per-pixel clipping path; the whole image
    // is covered and matches the reference.
    let mut m = structured_grid([3, 3, 3], [0.0; 3], [1.0; 3]);
    jitter(&mut m, [3, 3, 3], 0.15, 11);
    let cam = Camera {
        position: [0.47, 0.52, 0.45],
        focal: [0.9, 0.7, -0.3],
        view_angle: 70.0,
        ..Camera::default()
    };
    for schedule in [Schedule::Tiles, Schedule::Chunks] {
        let (err, st, img) = against_reference(&m, &cam, 40, schedule);
        assert!(st.clipped > 0, "{st:?}");
        assert!(
            img.pixels.iter().all(|p| p[3] > 0.0),
            "the eye is inside: every pixel sees the mesh"
        );
        assert!(err < 0.005, "{schedule:?}: error {err} {st:?}");
    }
}

#[test]
fn schedules_agree() {
    let mut m = structured_grid([4, 4, 4], [0.0; 3], [1.0; 3]);
    jitter(&mut m, [4, 4, 4], 0.2, 3);
    let mut cam = Camera::default();
    cam.reset_to(&m.bounds());
    cam.azimuth(25.0);
    cam.elevation(15.0);
    let (e1, _, a) = against_reference(&m, &cam, 48, Schedule::Tiles);
    let (e2, _, b) = against_reference(&m, &cam, 48, Schedule::Chunks);
    assert!(e1 < 0.02 && e2 < 0.02, "{e1} {e2}");
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        for k in 0..4 {
            assert!((p[k] - q[k]).abs() < 1e-5, "{p:?} {q:?}");
        }
    }
}
