//! Partition benchmarks and figures.
//!
//! Prints tet growth against the number of leaves (1, 2, 4, 8, 16) for both plane searches on a
//! regular and a jittered tetrahedralized structured grid and on every mesh file named in
//! `TETKIT_PARTITION_MESHES` (colon-separated; default: the TetGen torus and the Gmsh block with a
//! hole from fixtures/; scripts/partition_figures.sh makes larger ones), then times 1M tets into 8
//! leaves with criterion. Run: `cargo bench --bench partition`.

use std::path::PathBuf;

use criterion::{criterion_group, Criterion};
use tetkit::mesh::generate::{jitter, structured_grid};
use tetkit::mesh::TetMesh;
use tetkit::partition::input::tets_of;
use tetkit::partition::{partition, PartitionOptions, SearchParams, Stop, Strategy};

fn opts(strategy: Strategy, leaves: usize) -> PartitionOptions {
    PartitionOptions {
        stop: Stop::Leaves(leaves),
        search: SearchParams {
            strategy,
            ..PartitionOptions::default().search
        },
    }
}

/// A structured grid of about `tets` tets over a 2 x 1 x 1 box, jittered by `amount` cells.
fn grid(tets: usize, amount: f64) -> TetMesh {
    let k = ((tets as f64 / 12.0).cbrt()).round().max(1.0) as usize;
    let n = [2 * k, k, k];
    let mut m = structured_grid(n, [0.0; 3], [2.0, 1.0, 1.0]);
    if amount > 0.0 {
        jitter(&mut m, n, amount, 42);
    }
    m
}

fn growth_table(name: &str, mesh: &TetMesh) {
    println!("\n{name}: {} tets", mesh.tets.len());
    println!("strategy  leaves  growth  balance  seconds");
    for strategy in [Strategy::Paper, Strategy::Cost] {
        for leaves in [1, 2, 4, 8, 16] {
            match partition(mesh, &opts(strategy, leaves)) {
                Ok(p) => {
                    let r = &p.report;
                    let got = if r.leaves == leaves {
                        String::new()
                    } else {
                        format!("  (stopped at {} leaves: no plane qualified)", r.leaves)
                    };
                    println!(
                        "{:<8}  {:>6}  {:>6.3}  {:>7.3}  {:>7.3}{got}",
                        format!("{strategy:?}").to_lowercase(),
                        leaves,
                        r.growth,
                        r.balance,
                        r.seconds
                    );
                }
                Err(e) => println!("{strategy:?} {leaves}: error {e:#}"),
            }
        }
    }
}

fn figures() {
    let n = std::env::var("TETKIT_GRID_TETS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(200_000);
    growth_table("regular structured grid", &grid(n, 0.0));
    growth_table("jittered structured grid (0.2 cell)", &grid(n, 0.2));
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let files: Vec<PathBuf> = match std::env::var("TETKIT_PARTITION_MESHES") {
        Ok(s) => s
            .split(':')
            .filter(|x| !x.is_empty())
            .map(PathBuf::from)
            .collect(),
        Err(_) => vec![
            root.join("fixtures/tetgen/torus.1.ele"),
            root.join("fixtures/gmsh/block_hole.vtk"),
        ],
    };
    for f in files {
        let name = f.display().to_string();
        let mesh = formats::read(&f)
            .map_err(anyhow::Error::from)
            .and_then(|g| tets_of(&g, &name));
        match mesh {
            Ok((m, _, _)) => growth_table(&name, &m),
            Err(e) => println!("\n{name}: cannot read: {e:#}"),
        }
    }
}

fn bench(c: &mut Criterion) {
    let regular = grid(1_000_000, 0.0);
    let jittered = grid(1_000_000, 0.2);
    let mut g = c.benchmark_group("partition_1M_tets_8_leaves");
    g.sample_size(10);
    for (name, mesh) in [("regular", &regular), ("jittered", &jittered)] {
        for strategy in [Strategy::Paper, Strategy::Cost] {
            let id = format!("{name}_{}", format!("{strategy:?}").to_lowercase());
            g.bench_function(id, |b| {
                b.iter(|| partition(mesh, &opts(strategy, 8)).map(|p| p.report.tets_after))
            });
        }
    }
    g.finish();
}

criterion_group!(benches, bench);

fn main() {
    figures();
    benches();
    Criterion::default().configure_from_args().final_summary();
}
