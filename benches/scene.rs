//! Criterion benchmarks of scenes (seed 003's figures in our terms, before rendering): tet
//! classification on a 1M-tet mesh, and per-pixel region codes at 512 x 512 for a sphere cut
//! with and without bounding-box culling.
//!
//! `cargo bench --bench scene` (add `-- classify` or `-- pixels` to pick a group).

mod common;
use common::OrExit;

use criterion::{criterion_group, criterion_main, Criterion};
use std::path::Path;
use std::time::Duration;

use tetkit::camera::Camera;
use tetkit::mesh::generate::structured_grid;
use tetkit::scene::{self, classify::classify, merge, ray};

/// A 55^3-cube grid: 998,250 tets over [0, 1]^3.
fn mesh() -> tetkit::mesh::TetMesh {
    structured_grid([55, 55, 55], [0.0; 3], [1.0; 3])
}

fn uv_sphere_obj(dir: &Path, n: usize) -> std::path::PathBuf {
    let rings = n / 2;
    let (c, r) = ([0.5, 0.5, 0.5], 0.25);
    let mut text = format!("v {} {} {}\n", c[0], c[1], c[2] + r);
    for i in 1..rings {
        let th = std::f64::consts::PI * i as f64 / rings as f64;
        for j in 0..n {
            let ph = 2.0 * std::f64::consts::PI * j as f64 / n as f64;
            text += &format!(
                "v {} {} {}\n",
                c[0] + r * th.sin() * ph.cos(),
                c[1] + r * th.sin() * ph.sin(),
                c[2] + r * th.cos()
            );
        }
    }
    text += &format!("v {} {} {}\n", c[0], c[1], c[2] - r);
    let south = 1 + (rings - 1) * n + 1;
    let id = |i: usize, j: usize| 1 + (i - 1) * n + j % n + 1;
    for j in 0..n {
        text += &format!("f 1 {} {}\n", id(1, j), id(1, j + 1));
        text += &format!("f {south} {} {}\n", id(rings - 1, j + 1), id(rings - 1, j));
    }
    for i in 1..rings - 1 {
        for j in 0..n {
            text += &format!("f {} {} {}\n", id(i, j), id(i + 1, j), id(i + 1, j + 1));
            text += &format!("f {} {} {}\n", id(i, j), id(i + 1, j + 1), id(i, j + 1));
        }
    }
    let p = dir.join("sphere.obj");
    std::fs::write(&p, text).or_exit("writing the bench sphere");
    p
}

fn scenes(dir: &Path) -> Vec<(&'static str, scene::Scene)> {
    let obj = uv_sphere_obj(dir, 32);
    [
        ("sphere", "[[body]]\nshape = \"sphere\"\ncenter = [0.5, 0.5, 0.5]\nradius = 0.25\n".to_string()),
        ("box", "[[body]]\nshape = \"box\"\nmin = [0.3, 0.3, 0.3]\nmax = [0.7, 0.7, 0.7]\n".to_string()),
        ("cylinder", "[[body]]\nshape = \"cylinder\"\nstart = [0.5, 0.5, 0.1]\nend = [0.5, 0.5, 0.9]\nradius = 0.2\n".to_string()),
        ("surface_sphere_960_tris", format!("[[body]]\nshape = \"surface\"\nfile = \"{}\"\n", obj.display())),
    ]
    .into_iter()
    .map(|(n, t)| (n, scene::parse(&t, Path::new("bench.toml")).or_exit("bench scene")))
    .collect()
}

fn bench_classify(c: &mut Criterion) {
    let dir = tempfile::tempdir().or_exit("tempdir");
    let m = mesh();
    let mut g = c.benchmark_group("classify_1M_tets");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    for (name, s) in scenes(dir.path()) {
        g.bench_function(name, |b| b.iter(|| classify(&s, &m)));
    }
    g.finish();
}

fn bench_pixels(c: &mut Criterion) {
    let dir = tempfile::tempdir().or_exit("tempdir");
    let mut cam = Camera::default();
    cam.reset_to(&tetkit::geom::Aabb {
        min: [0.0; 3],
        max: [1.0; 3],
    });
    cam.azimuth(30.0);
    cam.elevation(20.0);
    let size = 512u32;
    let mut g = c.benchmark_group("region_codes_512x512");
    g.sample_size(10).measurement_time(Duration::from_secs(5));
    for (name, s) in scenes(dir.path()) {
        for culling in [false, true] {
            let mut v = ray::View::new(&s, cam, size, size);
            v.culling = culling;
            let label = format!("{name}/{}", if culling { "culled" } else { "all_pixels" });
            g.bench_function(label, |b| {
                b.iter(|| {
                    use rayon::prelude::*;
                    (0..size)
                        .into_par_iter()
                        .map(|y| {
                            let mut r = ray::RayRegions::default();
                            let mut n = 0usize;
                            for x in 0..size {
                                v.pixel(x as f64 + 0.5, y as f64 + 0.5, &mut r);
                                n += r.depths.len();
                            }
                            n
                        })
                        .sum::<usize>()
                })
            });
        }
    }
    g.finish();
    let codes = [0b010u8, 0b011, 0b001, 0b110, 0b111, 0b101];
    c.bench_function("merge_paper_example", |b| {
        b.iter(|| merge::merge(&codes, 3))
    });
    let many: Vec<u8> = (0..=255u8).filter(|c| c.count_ones() % 3 != 1).collect();
    c.bench_function("merge_8_bodies_171_codes", |b| {
        b.iter(|| merge::merge(&many, 8))
    });
}

criterion_group!(benches, bench_classify, bench_pixels);
criterion_main!(benches);
