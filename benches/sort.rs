//! Criterion benchmarks of the sort stage, plus two printed figures measured in the same run:
//! the paper's Table 1 (layers and sort time with 1, 2 and 4 leaves split along the view
//! direction) and the per-view sort time of a 1M-tet mesh against VTK's vtkCellCenterDepthSort
//! (scripts/vtk_depth_sort.py, run with /usr/bin/python3 on the same mesh and camera).
//!
//! `cargo bench --bench sort` (TETKIT_BENCH_N=55 sets the 1M grid's cubes per side).

use criterion::{criterion_group, criterion_main, Criterion};
use std::time::Instant;

use tetkit::camera::Camera;
use tetkit::geom::Aabb;
use tetkit::mesh::generate::{jitter, structured_grid};
use tetkit::mesh::TetMesh;
use tetkit::partition::{KdNode, KdTree, Split};
use tetkit::sort::{Direction, Method, Sorter};

/// Slabs along x at grid planes: `leaves` (1, 2 or 4) equal parts of the unit cube.
fn slab_tree(leaves: usize) -> Option<KdTree> {
    if leaves <= 1 {
        return None;
    }
    let unit = Aabb {
        min: [0.0; 3],
        max: [1.0; 3],
    };
    let mut nodes = vec![KdNode {
        bounds: unit,
        depth: 0,
        parent: None,
        split: None,
        leaf_id: Some(0),
        tet_count: 0,
    }];
    // Split every leaf at its x middle until there are `leaves` leaves.
    while nodes.iter().filter(|n| n.leaf_id.is_some()).count() < leaves {
        let cur: Vec<usize> = (0..nodes.len())
            .filter(|&i| nodes[i].leaf_id.is_some())
            .collect();
        for i in cur {
            let b = nodes[i].bounds;
            let mid = 0.5 * (b.min[0] + b.max[0]);
            let (l, r) = (nodes.len() as u32, nodes.len() as u32 + 1);
            let mut lb = b;
            lb.max[0] = mid;
            let mut rb = b;
            rb.min[0] = mid;
            for bb in [lb, rb] {
                nodes.push(KdNode {
                    bounds: bb,
                    depth: nodes[i].depth + 1,
                    parent: Some(i as u32),
                    split: None,
                    leaf_id: Some(0),
                    tet_count: 0,
                });
            }
            nodes[i].leaf_id = None;
            nodes[i].split = Some(Split {
                axis: 0,
                position: mid,
                left: l,
                right: r,
            });
        }
    }
    // Leaf ids depth-first, left to right.
    let mut next = 0;
    let mut stack = vec![0usize];
    while let Some(i) = stack.pop() {
        match nodes[i].split {
            Some(s) => {
                stack.push(s.right as usize);
                stack.push(s.left as usize);
            }
            None => {
                nodes[i].leaf_id = Some(next);
                next += 1;
            }
        }
    }
    Some(KdTree { nodes })
}

fn camera_along_x() -> Camera {
    let mut c = Camera {
        position: [-1.6, 0.53, 0.47],
        focal: [0.5, 0.5, 0.5],
        up: [0.0, 0.0, 1.0],
        view_angle: 30.0,
        parallel: false,
        parallel_scale: 1.0,
    };
    c.orthogonalize_up();
    c
}

fn camera_oblique() -> Camera {
    let mut c = Camera {
        position: [2.4, 1.9, 1.6],
        focal: [0.5, 0.5, 0.5],
        up: [0.0, 0.0, 1.0],
        view_angle: 30.0,
        parallel: false,
        parallel_scale: 1.0,
    };
    c.orthogonalize_up();
    c
}

fn median_time(runs: usize, mut f: impl FnMut()) -> f64 {
    let mut t: Vec<f64> = (0..runs)
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed().as_secs_f64()
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[t.len() / 2]
}

fn table1() {
    let n = 44;
    let mesh = structured_grid([n, n, n], [0.0; 3], [1.0; 3]);
    let cam = camera_along_x();
    eprintln!(
        "\nTable 1 (paper: layers 61% / 38%, time 63.7% / 43.6%): {} tets, split along the view direction (x)",
        mesh.tets.len()
    );
    eprintln!("| leaves | layers (max per leaf) | layers % | sort time (s) | time % |");
    eprintln!("| --- | --- | --- | --- | --- |");
    let mut base = None;
    for leaves in [1, 2, 4] {
        let tree = slab_tree(leaves);
        let s = Sorter::new(&mesh, tree.as_ref()).unwrap();
        let o = s.order(&cam, Method::Kd, Direction::BackToFront);
        let t = median_time(7, || {
            std::hint::black_box(s.order(&cam, Method::Kd, Direction::BackToFront));
        });
        let (l0, t0) = *base.get_or_insert((o.stats.layers as f64, t));
        eprintln!(
            "| {leaves} | {} | {:.1}% | {t:.4} | {:.1}% |",
            o.stats.layers,
            100.0 * o.stats.layers as f64 / l0,
            100.0 * t / t0
        );
    }
}

fn write_raw(mesh: &TetMesh, dir: &std::path::Path) -> (std::path::PathBuf, std::path::PathBuf) {
    std::fs::create_dir_all(dir).unwrap();
    let p = dir.join("points.f64");
    let t = dir.join("tets.i64");
    let pts: Vec<u8> = mesh
        .points
        .iter()
        .flatten()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    let tets: Vec<u8> = mesh
        .tets
        .iter()
        .flatten()
        .flat_map(|&v| (v as i64).to_le_bytes())
        .collect();
    std::fs::write(&p, pts).unwrap();
    std::fs::write(&t, tets).unwrap();
    (p, t)
}

fn million_vs_vtk() {
    let n: usize = std::env::var("TETKIT_BENCH_N")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(55);
    let mut mesh = structured_grid([n, n, n], [0.0; 3], [1.0; 3]);
    jitter(&mut mesh, [n, n, n], 0.2, 1);
    let cam = camera_oblique();
    let t0 = Instant::now();
    let s = Sorter::new(&mesh, None).unwrap();
    let setup = t0.elapsed().as_secs_f64();
    eprintln!(
        "\n1M-tet sort per view: {} tets (jittered {n}^3 grid), adjacency set-up {setup:.3} s once",
        mesh.tets.len()
    );
    let mut layers = 0;
    for m in [Method::Kd, Method::Mpvo, Method::Centroid] {
        let t = median_time(7, || {
            let o = s.order(&cam, m, Direction::BackToFront);
            layers = o.stats.layers;
            std::hint::black_box(o);
        });
        eprintln!("  tetkit {m:?}: {t:.4} s median of 7 ({layers} layers)");
    }
    let dir = std::env::temp_dir().join(format!("tetkit-sort-bench-{}", std::process::id()));
    let (p, t) = write_raw(&mesh, &dir);
    let v = |x: [f64; 3]| format!("{},{},{}", x[0], x[1], x[2]);
    let out = std::process::Command::new("/usr/bin/python3")
        .arg(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/scripts/vtk_depth_sort.py"
        ))
        .arg(&p)
        .arg(&t)
        .arg(format!("--position={}", v(cam.position)))
        .arg(format!("--focal={}", v(cam.focal)))
        .arg(format!("--up={}", v(cam.up)))
        .arg("--repeat=3")
        .output();
    let _ = std::fs::remove_dir_all(&dir);
    match out {
        Ok(o) if o.status.success() => {
            let j: serde_json::Value =
                serde_json::from_slice(&o.stdout).unwrap_or(serde_json::Value::Null);
            let mut secs: Vec<f64> = j["seconds"]
                .as_array()
                .map(|a| a.iter().filter_map(|x| x.as_f64()).collect())
                .unwrap_or_default();
            secs.sort_by(f64::total_cmp);
            if let Some(m) = secs.get(secs.len() / 2) {
                eprintln!("  VTK vtkCellCenterDepthSort (same mesh and camera, same run): {m:.4} s median of {}", secs.len());
            }
        }
        Ok(o) => eprintln!(
            "  VTK baseline failed: {}",
            String::from_utf8_lossy(&o.stderr)
        ),
        Err(e) => eprintln!("  VTK baseline not run: {e}"),
    }
}

fn benches(c: &mut Criterion) {
    table1();
    million_vs_vtk();
    let n = 30;
    let mut mesh = structured_grid([n, n, n], [0.0; 3], [1.0; 3]);
    jitter(&mut mesh, [n, n, n], 0.2, 1);
    let cam = camera_oblique();
    let s = Sorter::new(&mesh, None).unwrap();
    let mut g = c.benchmark_group("sort_162k_tets");
    g.sample_size(10);
    for m in [Method::Kd, Method::Mpvo, Method::Centroid] {
        g.bench_function(format!("{m:?}"), |b| {
            b.iter(|| std::hint::black_box(s.order(&cam, m, Direction::BackToFront)))
        });
    }
    g.bench_function("adjacency_setup", |b| {
        b.iter(|| std::hint::black_box(Sorter::new(&mesh, None).unwrap().num_leaves()))
    });
    g.finish();
}

criterion_group!(sort_benches, benches);
criterion_main!(sort_benches);
