//! GPU projected tetrahedra (wgpu, WGSL) against the CPU path on fixtures and degenerate views,
//! determinism, reuse across frames, and `tetkit render --device`. Under CI=true a missing adapter
//! fails these tests; elsewhere they are skipped with the reason printed.

mod common;

use std::path::Path;
use std::process::Command;

use tetkit::camera::Camera;
use tetkit::mesh::generate::structured_grid;
use tetkit::mesh::TetMesh;
use tetkit::render::field::Field;
use tetkit::render::gpu::{GpuContext, GpuRenderer, TargetFormat};
use tetkit::render::image::Image;
use tetkit::render::integrate::Integration;
use tetkit::render::prepare::{self, TableSize};
use tetkit::render::pt::{self, PtStats, Shader, View};
use tetkit::render::transfer::{named_colormap, TransferFunction};
use tetkit::sort::{Direction, Method, Sorter};

/// Largest per-channel difference allowed between GPU (Rgba32Float) and CPU images, measured on
/// llvmpipe: see `measured_tolerance` below and the README's GPU section.
const TOL: f32 = 2e-3;
/// The same with an Rgba16Float target (11-bit mantissas through every blend); measured 4.3e-3
/// on the cavity fixture.
const F16_TOL: f32 = 1e-2;

fn context() -> Option<GpuContext> {
    match GpuContext::new() {
        Ok(c) => {
            eprintln!("GPU: {}", c.describe());
            Some(c)
        }
        Err(e) => {
            if std::env::var("CI").is_ok_and(|v| v == "true") {
                panic!("CI=true and no GPU adapter (is mesa-vulkan-drivers installed?): {e:#}");
            }
            eprintln!("skipping GPU test: {e:#}");
            None
        }
    }
}

fn fixture(rel: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures")
        .join(rel)
        .display()
        .to_string()
}

fn load(rel: &str) -> TetMesh {
    let path = fixture(rel);
    let grid = tetkit::cli::read_input(Path::new(&path)).unwrap();
    tetkit::partition::input::tets_of(&grid, &path).unwrap().0
}

fn tf(range: [f64; 2], unit: f64) -> TransferFunction {
    common::look::viridis_tf("0:0.1,0.4:0.6,0.6:0.2,1:0.8", range, unit, 64)
}

fn shader_for(m: &TetMesh, field: &Field, mode: Integration) -> Shader {
    let t = tf(
        prepare::auto_range(field),
        prepare::default_unit_distance(m),
    );
    prepare::shader(&t, mode, TableSize::default(), prepare::longest_edge(m))
}

fn order(m: &TetMesh, cam: &Camera) -> Vec<u32> {
    Sorter::new(m, None)
        .unwrap()
        .order(cam, Method::Kd, Direction::FrontToBack)
        .order
}

fn cameras(m: &TetMesh) -> Vec<Camera> {
    let b = m.bounds();
    let c = b.center();
    let e = b.extent();
    let d = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
    let persp = Camera {
        position: [c[0] + 0.9 * d, c[1] - 1.3 * d, c[2] + 0.7 * d],
        focal: c,
        up: [0.0, 0.0, 1.0],
        view_angle: 30.0,
        ..Camera::default()
    };
    let par = Camera {
        position: [c[0] - 0.4 * d, c[1] + 0.3 * d, c[2] + 2.0 * d],
        focal: c,
        up: [0.0, 1.0, 0.0],
        parallel: true,
        parallel_scale: 0.6 * d,
        ..Camera::default()
    };
    vec![persp, par]
}

/// Max channel difference, and how many pixels differ by more than 1e-5.
fn diff(a: &Image, b: &Image) -> (f32, usize) {
    let mut worst = 0f32;
    let mut n = 0;
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        let d = (0..4).map(|k| (p[k] - q[k]).abs()).fold(0f32, f32::max);
        worst = worst.max(d);
        n += (d > 1e-5) as usize;
    }
    (worst, n)
}

struct Case {
    gpu: Image,
    cpu: Image,
    gstats: PtStats,
    cstats: PtStats,
}

fn both(
    gpu: &mut GpuRenderer,
    m: &TetMesh,
    field: &Field,
    shader: &Shader,
    cam: &Camera,
    ord: &[u32],
    n: u32,
) -> Case {
    let view = View::new(cam, n, n);
    let (g, gstats, _) = gpu.render(&view, ord).unwrap();
    let (c, cstats, _) = pt::render(&view, &m.points, &m.tets, field, ord, shader);
    assert!(!g.has_nan());
    Case {
        gpu: g,
        cpu: c,
        gstats,
        cstats,
    }
}

fn check(what: &str, c: &Case, tol: f32) -> f32 {
    let (worst, n) = diff(&c.gpu, &c.cpu);
    let covered = c.cpu.pixels.iter().filter(|p| p[3] > 0.0).count();
    eprintln!(
        "{what}: max channel difference {worst:.3e}, {n} of {} pixels over 1e-5 ({covered} covered)",
        c.cpu.pixels.len()
    );
    assert!(covered > 0, "{what}: nothing drawn");
    assert!(
        worst <= tol,
        "{what}: GPU and CPU differ by {worst} (> {tol})"
    );
    // Beyond float rounding only where a pixel centre lies within rounding of a silhouette edge.
    assert!(
        n * 100 <= covered,
        "{what}: {n} pixels differ by more than 1e-5 (over 1% of {covered})"
    );
    // The scene path counts classes per tile of the tets it draws; only the plain path counts
    // each tet once.
    if !what.starts_with("cut scene") {
        assert_eq!(c.gstats.class, c.cstats.class, "{what}: projection classes");
        assert_eq!(c.gstats.clipped, c.cstats.clipped, "{what}: clipped");
    }
    worst
}

#[test]
fn adapter_blends_f32_under_ci() {
    let Some(ctx) = context() else { return };
    if std::env::var("CI").is_ok_and(|v| v == "true") {
        // CI installs Mesa's lavapipe, which offers FLOAT32_BLENDABLE.
        assert_eq!(ctx.format, TargetFormat::Rgba32Float, "{}", ctx.describe());
    }
}

#[test]
fn fixtures_match_the_cpu_in_every_mode() {
    let Some(ctx) = context() else { return };
    let mut ctx = Some(ctx);
    let mut worst = 0f32;
    for (rel, scalar) in [
        ("gmsh/cavity.vtk", Some("coord:r")),
        ("tetgen/regions.1.ele", None),
        ("tetgen/sphere.1.ele", Some("coord:x")),
    ] {
        let m = load(rel);
        let (_, field) = Field::select(&m, scalar).unwrap();
        for mode in Integration::ALL {
            let shader = shader_for(&m, &field, mode);
            let c = match ctx.take() {
                Some(c) => c,
                None => GpuContext::new().unwrap(),
            };
            let mut gpu = GpuRenderer::new(c, &m.points, &m.tets, &field, &shader).unwrap();
            for (ci, cam) in cameras(&m).iter().enumerate() {
                let ord = order(&m, cam);
                let case = both(&mut gpu, &m, &field, &shader, cam, &ord, 64);
                worst = worst.max(check(
                    &format!("{rel} {} camera {ci}", mode.name()),
                    &case,
                    TOL,
                ));
            }
        }
    }
    eprintln!("fixtures: worst channel difference {worst:.3e}");
}

fn single_tet(apex: [f64; 3]) -> TetMesh {
    let mut m = structured_grid([2, 2, 2], [0.0; 3], [1.0; 3]);
    m.points = vec![[-0.8, -0.6, 0.0], [0.8, -0.6, 0.0], [0.0, 0.8, 0.0], apex];
    m.tets = vec![[0, 1, 2, 3]];
    m.point_data = Default::default();
    m.cell_data = Default::default();
    m
}

fn axis_cameras() -> Vec<Camera> {
    vec![
        Camera {
            position: [0.0, 0.0, 10.0],
            parallel: true,
            parallel_scale: 1.0,
            ..Camera::default()
        },
        Camera {
            position: [0.0, 0.0, 4.0],
            view_angle: 30.0,
            ..Camera::default()
        },
    ]
}

#[test]
fn degenerate_projections_match_the_cpu() {
    let Some(ctx) = context() else { return };
    let mut ctx = Some(ctx);
    let mut next = || ctx.take().unwrap_or_else(|| GpuContext::new().unwrap());
    // Class 1 (apex inside), class 3 (apex over an edge: a face seen edge-on), class 4 (apex over
    // a vertex: an edge seen end-on) under the parallel camera, and a class-2 tet.
    let cases: Vec<(TetMesh, Option<usize>)> = vec![
        (single_tet([0.0, 0.0, 0.7]), Some(0)),
        (single_tet([0.0, -0.6, 0.7]), Some(2)),
        (single_tet([0.0, 0.8, 0.7]), Some(3)),
        (
            {
                let mut m = single_tet([0.0; 3]);
                m.points = vec![
                    [-0.8, 0.0, 0.0],
                    [0.8, 0.0, 0.0],
                    [0.0, -0.8, 0.7],
                    [0.0, 0.8, 0.7],
                ];
                m
            },
            Some(1),
        ),
    ];
    let s = Field::Point(vec![0.1, 0.9, 0.5, 0.3]);
    for (i, (m, class)) in cases.iter().enumerate() {
        let shader = prepare::shader(
            &tf([0.0, 1.0], 0.5),
            Integration::Preintegrated,
            TableSize::default(),
            prepare::longest_edge(m),
        );
        let mut gpu = GpuRenderer::new(next(), &m.points, &m.tets, &s, &shader).unwrap();
        for (ci, cam) in axis_cameras().iter().enumerate() {
            let c = both(&mut gpu, m, &s, &shader, cam, &[0], 48);
            check(&format!("tet {i} camera {ci}"), &c, TOL);
            if ci == 0 {
                if let Some(k) = class {
                    assert_eq!(c.gstats.class[*k], 1, "tet {i}: {:?}", c.gstats);
                }
            }
        }
    }
    // An axis-aligned grid seen along an axis: every side face parallel to the view, every
    // vertical edge end-on, shared edges on pixel centres (owner rule and coverage must agree).
    let m = structured_grid([4, 4, 3], [-0.75, -0.75, -0.5], [0.75, 0.75, 0.5]);
    let field = common::look::point_field(&m);
    let shader = prepare::shader(
        &tf([0.0, 1.0], 0.5),
        Integration::Preintegrated,
        TableSize::default(),
        prepare::longest_edge(&m),
    );
    let mut gpu = GpuRenderer::new(next(), &m.points, &m.tets, &field, &shader).unwrap();
    for (ci, cam) in axis_cameras().iter().enumerate() {
        let ord = order(&m, cam);
        let c = both(&mut gpu, &m, &field, &shader, cam, &ord, 40);
        check(&format!("axis grid camera {ci}"), &c, TOL);
    }
}

#[test]
fn frames_are_deterministic_and_buffers_reused() {
    let Some(ctx) = context() else { return };
    let m = load("gmsh/cavity.vtk");
    let (_, field) = Field::select(&m, Some("coord:z")).unwrap();
    let shader = shader_for(&m, &field, Integration::Preintegrated);
    let mut gpu = GpuRenderer::new(ctx, &m.points, &m.tets, &field, &shader).unwrap();
    let cams = cameras(&m);
    let render = |gpu: &mut GpuRenderer, cam: &Camera| {
        gpu.render(&View::new(cam, 64, 48), &order(&m, cam))
            .unwrap()
            .0
    };
    let a = render(&mut gpu, &cams[0]);
    let b = render(&mut gpu, &cams[1]);
    let a2 = render(&mut gpu, &cams[0]);
    assert_eq!(
        a.pixels, a2.pixels,
        "same camera, same bits after another frame"
    );
    assert_ne!(a.pixels, b.pixels);
}

fn tetkit(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_tetkit"))
        .args(args)
        .output()
        .expect("running tetkit");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn cli_device_gpu_matches_cpu_png_and_orbits() {
    if context().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mesh = fixture("gmsh/lshape.vtk");
    let run = |device: &str, out: &Path, extra: &[&str]| {
        let mut args = vec![
            "render",
            &mesh,
            "-o",
            out.to_str().unwrap(),
            "--size",
            "80x60",
            "--azimuth",
            "30",
            "--elevation",
            "20",
            "--device",
            device,
        ];
        args.extend_from_slice(extra);
        let (ok, err) = tetkit(&args);
        assert!(ok, "{device}: {err}");
        err
    };
    let cpu = dir.path().join("cpu.png");
    let gpu = dir.path().join("gpu.png");
    run("cpu", &cpu, &[]);
    let err = run("gpu", &gpu, &[]);
    assert!(err.contains("GPU: "), "{err}");
    let a = image::open(&cpu).unwrap().to_rgb8();
    let b = image::open(&gpu).unwrap().to_rgb8();
    assert_eq!(a.dimensions(), b.dimensions());
    let worst = a
        .as_raw()
        .iter()
        .zip(b.as_raw())
        .map(|(x, y)| x.abs_diff(*y))
        .max()
        .unwrap();
    assert!(worst <= 1, "8-bit PNGs differ by {worst}");

    let orbit = dir.path().join("orbit.png");
    let err = run("gpu", &orbit, &["--orbit", "3"]);
    for i in 0..3 {
        assert!(
            dir.path().join(format!("orbit_{i:04}.png")).exists(),
            "{err}"
        );
    }
    assert!(err.contains("frame 2"), "{err}");
    let auto = dir.path().join("auto.png");
    run("auto", &auto, &["--quiet"]);
    assert!(auto.exists());
}

#[test]
fn cut_scene_matches_the_cpu() {
    use tetkit::mesh::generate::jitter;
    use tetkit::render::cut::{self, BaseLook, SceneLook, ShaderCache};
    use tetkit::render::gpu::SceneTables;
    let Some(ctx) = context() else { return };
    let n = [6, 4, 4];
    let mut m = structured_grid(n, [0.0; 3], [1.5, 1.0, 1.0]);
    jitter(&mut m, n, 0.2, 5);
    let field = common::look::point_field(&m);
    let t = tf([0.0, 1.0], prepare::default_unit_distance(&m));
    let base = BaseLook {
        colors: named_colormap("viridis").unwrap(),
        range: [0.0, 1.0],
        unit_distance: prepare::default_unit_distance(&m),
        nodes: 64,
    };
    // A box cut, a sphere with its own two-level transfer function, and a sphere cut seen
    // through both.
    let text = common::look::box_cut_and_two_level_sphere(0.9)
        + "[[body]]\nshape = \"sphere\"\ncenter = [1.1, 0.4, 0.3]\nradius = 0.2\naction = \"cut\"\n";
    let dir = tempfile::tempdir().unwrap();
    let scene = tetkit::scene::parse(&text, &dir.path().join("scene.toml")).unwrap();
    let look = SceneLook::new(&scene, &t, &base).unwrap();
    let lmax = prepare::longest_edge(&m);
    let mut ctx = Some(ctx);
    for mode in [Integration::Preintegrated, Integration::Average] {
        let plain = prepare::shader(&t, mode, TableSize::default(), lmax);
        let c = ctx.take().unwrap_or_else(|| GpuContext::new().unwrap());
        let mut gpu = GpuRenderer::new(c, &m.points, &m.tets, &field, &plain).unwrap();
        let mut tables = SceneTables::new(mode, TableSize::default(), lmax);
        let mut cache = ShaderCache::new(mode, TableSize::default(), lmax);
        for (ci, cam) in cameras(&m).iter().enumerate() {
            let ord = order(&m, cam);
            let view = View::new(cam, 64, 64);
            let (g, gstats, _, st) = gpu
                .render_scene(&view, cam, &ord, &look, &mut tables)
                .unwrap();
            let (c, cstats, rep) = cut::pt_render(
                &view, cam, &m.points, &m.tets, &field, &ord, &look, &mut cache,
            );
            assert!(st.pixels_with_crossings > 0 && st.layers >= 2, "{st:?}");
            assert_eq!(st.pixels_with_crossings, rep.pixels_with_crossings);
            let case = Case {
                gpu: g,
                cpu: c,
                gstats,
                cstats,
            };
            check(
                &format!("cut scene {} camera {ci}", mode.name()),
                &case,
                TOL,
            );
            // The cut shows: the plain image differs where bodies are.
            let (p, _, _) = gpu.render(&view, &ord).unwrap();
            assert!(diff(&p, &case.gpu).0 > 0.05);
        }
    }
}

#[test]
fn cli_scene_on_the_gpu_matches_the_cpu() {
    if context().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mesh = fixture("scenes/cube_mesh.vtk");
    let scene = fixture("scenes/example.toml");
    let mut pngs = Vec::new();
    for device in ["cpu", "gpu"] {
        let out = dir.path().join(format!("{device}.png"));
        let (ok, err) = tetkit(&[
            "render",
            &mesh,
            "--scene",
            &scene,
            "-o",
            out.to_str().unwrap(),
            "--size",
            "64x64",
            "--device",
            device,
        ]);
        assert!(ok, "{device}: {err}");
        if device == "gpu" {
            assert!(err.contains("GPU: ") && err.contains("crossings"), "{err}");
        }
        pngs.push(image::open(&out).unwrap().to_rgb8());
    }
    let worst = pngs[0]
        .as_raw()
        .iter()
        .zip(pngs[1].as_raw())
        .map(|(x, y)| x.abs_diff(*y))
        .max()
        .unwrap();
    assert!(worst <= 1, "scene PNGs differ by {worst}");
}

#[test]
fn half_float_target_stays_close() {
    // Adapters without FLOAT32_BLENDABLE composite into Rgba16Float; forced here on any adapter.
    let Some(mut ctx) = context() else { return };
    ctx.format = TargetFormat::Rgba16Float;
    let m = load("gmsh/cavity.vtk");
    let (_, field) = Field::select(&m, Some("coord:r")).unwrap();
    let shader = shader_for(&m, &field, Integration::Preintegrated);
    let mut gpu = GpuRenderer::new(ctx, &m.points, &m.tets, &field, &shader).unwrap();
    for (ci, cam) in cameras(&m).iter().enumerate() {
        let ord = order(&m, cam);
        let c = both(&mut gpu, &m, &field, &shader, cam, &ord, 64);
        let (worst, n) = diff(&c.gpu, &c.cpu);
        eprintln!(
            "Rgba16Float camera {ci}: max channel difference {worst:.3e}, {n} pixels over 1e-5"
        );
        assert!(worst <= F16_TOL, "Rgba16Float camera {ci}: {worst}");
    }
}

#[test]
fn without_an_adapter_auto_falls_back_and_gpu_fails() {
    // No adapter: a backend this build does not include.
    let dir = tempfile::tempdir().unwrap();
    let mesh = fixture("gmsh/lshape.vtk");
    let run = |device: &str, out: &Path| {
        let o = Command::new(env!("CARGO_BIN_EXE_tetkit"))
            .env("WGPU_BACKEND", "dx12")
            .args(["render", &mesh, "-o", out.to_str().unwrap()])
            .args(["--size", "32x32", "--device", device])
            .output()
            .expect("running tetkit");
        (
            o.status.success(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    let auto = dir.path().join("auto.png");
    let (ok, err) = run("auto", &auto);
    assert!(ok, "{err}");
    assert!(auto.exists());
    let lines: Vec<&str> = err
        .lines()
        .filter(|l| l.contains("--device auto"))
        .collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(lines[0].contains("rendering on the CPU"), "{err}");
    let gpu = dir.path().join("gpu.png");
    let (ok, err) = run("gpu", &gpu);
    assert!(!ok, "--device gpu without an adapter must fail");
    assert!(err.contains("no GPU adapter"), "{err}");
    assert!(!gpu.exists(), "no output file on failure");
}
