//! Criterion benchmarks of rendering with scenes on a 1M-tet mesh at 512 x 512 (PT, kd order
//! computed once, pre-integrated tables built before timing): what a scene costs (none, an empty
//! scene, one small body, a body covering the image), and the paper's Table 2 in our terms
//! (1 to 4 region classes; a sphere cut without and with bounding-box culling).
//!
//! `cargo bench --bench scene_render` (add `-- cost` or `-- table2` to pick a group). The machine
//! is shared: compare ratios within one run, with `uptime` next to them.

mod common;
use common::OrExit;

use criterion::{criterion_group, criterion_main, Criterion};
use std::path::Path;
use std::time::Duration;

use tetkit::camera::Camera;
use tetkit::mesh::generate::structured_grid;
use tetkit::mesh::TetMesh;
use tetkit::render::cut::{self, BaseLook, SceneLook, ShaderCache};
use tetkit::render::field::Field;
use tetkit::render::integrate::Integration;
use tetkit::render::prepare::{self, TableSize};
use tetkit::render::pt::{self, View};
use tetkit::render::transfer::{named_colormap, OpacitySpec, TransferFunction};
use tetkit::scene::{self, Scene};
use tetkit::sort::{Direction, Method, Sorter};

const SIZE: u32 = 512;

struct Setup {
    mesh: TetMesh,
    field: Field,
    tf: TransferFunction,
    base: BaseLook,
    cam: Camera,
    order: Vec<u32>,
    lmax: f64,
}

fn setup() -> Setup {
    // A 55^3-cube grid: 998,250 tets over [0, 1]^3 (as benches/scene.rs).
    let mesh = structured_grid([55, 55, 55], [0.0; 3], [1.0; 3]);
    let field = Field::Point(
        mesh.point_data
            .get("scalar")
            .or_exit("generated scalar")
            .data
            .to_f64_vec(),
    );
    let unit = prepare::default_unit_distance(&mesh);
    let colors = named_colormap("cool-to-warm").or_exit("colormap");
    let tf = TransferFunction::build(
        &colors,
        Some(&OpacitySpec::parse("0:0.05,0.5:0.3,1:0.6").or_exit("opacity")),
        [0.0, 1.0],
        unit,
        64,
    )
    .or_exit("tf");
    let mut cam = Camera::default();
    cam.reset_to(&mesh.bounds());
    cam.azimuth(30.0);
    cam.elevation(20.0);
    let order = Sorter::new(&mesh, None)
        .or_exit("sorter")
        .order(&cam, Method::Kd, Direction::FrontToBack)
        .order;
    let lmax = prepare::longest_edge(&mesh);
    Setup {
        base: BaseLook {
            colors,
            range: [0.0, 1.0],
            unit_distance: unit,
            nodes: 64,
        },
        mesh,
        field,
        tf,
        cam,
        order,
        lmax,
    }
}

fn parse(text: &str) -> Scene {
    scene::parse(text, Path::new("bench.toml")).or_exit("bench scene")
}

/// A sphere body with its own colours and the default's opacity: the region classes then change
/// what is computed, not how much is drawn (a more opaque body would end rays early and hide the
/// cost).
fn tf_sphere(c: [f64; 3], r: f64, colormap: &str) -> String {
    format!(
        "[[body]]\nshape = \"sphere\"\ncenter = [{}, {}, {}]\nradius = {r}\naction = \"transfer\"\n\
         [body.transfer]\ncolormap = \"{colormap}\"\nopacity = [[0.0, 0.05], [0.5, 0.3], [1.0, 0.6]]\n",
        c[0], c[1], c[2]
    )
}

/// One PT frame: the plain path without bodies (what the CLI runs for no scene or an empty
/// one), else the scene path.
fn frame(s: &Setup, scene: Option<&Scene>, culling: bool, cache: &mut ShaderCache) -> f32 {
    let view = View::new(&s.cam, SIZE, SIZE);
    let img = match scene.filter(|sc| !sc.bodies.is_empty()) {
        None => {
            let sh = cache.default_shader().or_exit("default shader prebuilt");
            pt::render(&view, &s.mesh.points, &s.mesh.tets, &s.field, &s.order, sh).0
        }
        Some(sc) => {
            let mut look = SceneLook::new(sc, &s.tf, &s.base).or_exit("scene look");
            look.culling = culling;
            cut::pt_render(
                &view,
                &s.cam,
                &s.mesh.points,
                &s.mesh.tets,
                &s.field,
                &s.order,
                &look,
                cache,
            )
            .0
        }
    };
    img.pixels[img.pixels.len() / 2][3]
}

fn bench_scene(c: &mut Criterion, group: &str, cases: Vec<(&str, Option<Scene>, bool)>) {
    let s = setup();
    let mut g = c.benchmark_group(group);
    g.sample_size(10).measurement_time(Duration::from_secs(10));
    for (name, scene, culling) in &cases {
        // Tables are built once per session in the CLI too: build them before timing.
        let mut cache = ShaderCache::new(Integration::Preintegrated, TableSize::default(), s.lmax)
            .with_default(prepare::shader(
                &s.tf,
                Integration::Preintegrated,
                TableSize::default(),
                s.lmax,
            ));
        frame(&s, scene.as_ref(), *culling, &mut cache);
        g.bench_function(*name, |b| {
            b.iter(|| frame(&s, scene.as_ref(), *culling, &mut cache))
        });
    }
    g.finish();
}

fn bench_cost(c: &mut Criterion) {
    let cases = vec![
        ("no_scene", None, true),
        ("empty_scene", Some(parse("")), true),
        (
            "small_sphere_cut_r0.05",
            Some(parse(
                "[[body]]\nshape = \"sphere\"\ncenter = [0.5, 0.5, 0.5]\nradius = 0.05\n",
            )),
            true,
        ),
        (
            "box_cut_covering_the_image",
            Some(parse(
                "[[body]]\nshape = \"box\"\nmin = [-10.0, -10.0, 0.55]\nmax = [10.0, 10.0, 10.0]\n",
            )),
            true,
        ),
    ];
    bench_scene(c, "scene_cost_1M_tets_512", cases);
}

fn bench_table2(c: &mut Criterion) {
    let spheres = [
        ([0.3, 0.3, 0.5], "inferno"),
        ([0.7, 0.4, 0.5], "greens"),
        ([0.5, 0.75, 0.5], "purples"),
    ];
    let mut cases = vec![("classes_1_no_bodies", None, true)];
    let names = ["classes_2", "classes_3", "classes_4"];
    for k in 1..=3 {
        let text: String = spheres[..k]
            .iter()
            .map(|(c, m)| tf_sphere(*c, 0.18, m))
            .collect();
        cases.push((names[k - 1], Some(parse(&text)), true));
    }
    let cut = "[[body]]\nshape = \"sphere\"\ncenter = [0.5, 0.5, 0.5]\nradius = 0.3\n";
    cases.push(("sphere_cut_no_culling", Some(parse(cut)), false));
    cases.push(("sphere_cut_culled", Some(parse(cut)), true));
    bench_scene(c, "table2_1M_tets_512", cases);
}

criterion_group!(benches, bench_cost, bench_table2);
criterion_main!(benches);
