//! Criterion benchmarks of the render stage: one PT frame (kd + preintegrated, and VTK-like
//! centroid + average) and one ray-cast frame on a jittered tetrahedralized grid, 512x512, with
//! the per-mesh setup (adjacency, leaves, tables, grids) outside the timed loop.
//! Sizes: TETKIT_BENCH_CUBES=n gives 6 n^3 tets (default 24: 83k tets).

mod common;
use common::OrExit;

use criterion::{criterion_group, criterion_main, Criterion};
use tetkit::camera::Camera;
use tetkit::locate::{GridParams, Topology};
use tetkit::mesh::generate::{jitter, structured_grid};
use tetkit::render::field::Field;
use tetkit::render::integrate::Integration;
use tetkit::render::prepare::{self, TableSize};
use tetkit::render::pt::{self, View};
use tetkit::render::raycast::RayCaster;
use tetkit::render::transfer::{named_colormap, OpacitySpec, TransferFunction};
use tetkit::sort::{Direction, Method, Sorter};

fn bench(c: &mut Criterion) {
    let n: usize = std::env::var("TETKIT_BENCH_CUBES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(24);
    let mut m = structured_grid([n; 3], [0.0; 3], [1.0; 3]);
    jitter(&mut m, [n; 3], 0.2, 5);
    let field = Field::Point(
        m.point_data
            .get("scalar")
            .or_exit("the generated mesh's array 'scalar'")
            .data
            .to_f64_vec(),
    );
    let tf = TransferFunction::build(
        &named_colormap("cool-to-warm").or_exit("colormap"),
        Some(&OpacitySpec::parse("ramp").or_exit("opacity")),
        [0.0, 1.0],
        prepare::default_unit_distance(&m),
        256,
    )
    .or_exit("transfer function");
    let mut cam = Camera::default();
    cam.reset_to(&m.bounds());
    cam.azimuth(30.0);
    cam.elevation(20.0);
    let view = View::new(&cam, 512, 512);
    let sorter = Sorter::new(&m, None).or_exit("building the sorter");
    let lmax = prepare::longest_edge(&m);
    let pre = prepare::shader(&tf, Integration::Preintegrated, TableSize::default(), lmax);
    let avg = prepare::shader(&tf, Integration::Average, TableSize::default(), lmax);
    let mut g = c.benchmark_group(format!("render_{}k_tets", m.tets.len() / 1000));
    g.sample_size(10);
    g.bench_function("pt_kd_preintegrated_frame", |b| {
        b.iter(|| {
            let o = sorter.order(&cam, Method::Kd, Direction::FrontToBack);
            pt::render(&view, &m.points, &m.tets, &field, &o.order, &pre)
        })
    });
    let order = sorter.order(&cam, Method::Kd, Direction::FrontToBack).order;
    g.bench_function("pt_raster_only_preintegrated", |b| {
        b.iter(|| pt::render(&view, &m.points, &m.tets, &field, &order, &pre))
    });
    g.bench_function("pt_centroid_average_frame", |b| {
        b.iter(|| {
            let o = sorter.order(&cam, Method::Centroid, Direction::FrontToBack);
            pt::render(&view, &m.points, &m.tets, &field, &o.order, &avg)
        })
    });
    g.bench_function("preintegration_table_128x128x64", |b| {
        b.iter(|| prepare::shader(&tf, Integration::Preintegrated, TableSize::default(), lmax))
    });
    let topo = Topology::build(&m.tets);
    let rc = RayCaster::new(&m.points, &m.tets, &field, &topo, GridParams::default());
    g.bench_function("raycast_frame", |b| {
        b.iter(|| rc.render(&tf, &cam, 512, 512))
    });
    g.bench_function("grid_build_tets", |b| {
        b.iter(|| tetkit::locate::TetLocator::build(&m.points, &m.tets, GridParams::default()))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
