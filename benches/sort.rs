//! Criterion benchmarks of the sort stage, plus two printed figures measured in the same run:
//! the paper's Table 1 (layers and sort time with 1, 2 and 4 leaves split along the view
//! direction) and the per-view sort time of a 1M-tet mesh against VTK's vtkCellCenterDepthSort
//! (scripts/vtk_depth_sort.py, run with /usr/bin/python3 on the same mesh and camera).
//!
//! Table 1 runs on three meshes: the 44^3 grid, a 40^3 grid with tunnels and a cavity (non-convex),
//! and TetGen's torus (when `tetgen` is installed). Also printed: per-view times on a non-convex
//! 1M-tet mesh from outside and from inside a tunnel, and the load average before and after.
//!
//! `cargo bench --bench sort` (TETKIT_BENCH_N=55 sets the 1M grids' cubes per side).

mod common;
use common::OrExit;

use criterion::{criterion_group, criterion_main, Criterion};
use std::time::Instant;

use tetkit::camera::Camera;
use tetkit::geom::Aabb;
use tetkit::mesh::generate::{jitter, structured_grid};
use tetkit::mesh::TetMesh;
use tetkit::partition::{KdNode, KdTree, Split};
use tetkit::sort::{Direction, Method, Sorter};

/// Slabs along `axis`: `leaves` (1, 2 or 4) equal parts of `bounds`, halved level by level.
fn slab_tree(leaves: usize, bounds: Aabb, axis: u8) -> Option<KdTree> {
    if leaves <= 1 {
        return None;
    }
    let a = axis as usize;
    let mut nodes = vec![KdNode {
        bounds,
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
            let mid = 0.5 * (b.min[a] + b.max[a]);
            let (l, r) = (nodes.len() as u32, nodes.len() as u32 + 1);
            let mut lb = b;
            lb.max[a] = mid;
            let mut rb = b;
            rb.min[a] = mid;
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
                axis,
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

/// One mesh's Table 1: layers (most of any leaf) and sort time for 1, 2 and 4 slabs along x, the
/// view direction of `cam`.
fn table1_on(name: &str, mesh: &TetMesh, cam: &Camera) {
    eprintln!(
        "\nTable 1 on {name}: {} tets, split along the view direction (x)",
        mesh.tets.len()
    );
    eprintln!("| leaves | layers (max per leaf) | layers % | sort time (s) | time % | non-convex leaves | extra constraints |");
    eprintln!("| --- | --- | --- | --- | --- | --- | --- |");
    let mut base = None;
    for leaves in [1, 2, 4] {
        let tree = slab_tree(leaves, mesh.bounds(), 0);
        let s = Sorter::new(mesh, tree.as_ref()).or_exit("building the sorter");
        let o = s.order(cam, Method::Kd, Direction::BackToFront);
        let t = median_time(7, || {
            std::hint::black_box(s.order(cam, Method::Kd, Direction::BackToFront));
        });
        let (l0, t0) = *base.get_or_insert((o.stats.layers as f64, t));
        eprintln!(
            "| {leaves} | {} | {:.1}% | {t:.4} | {:.1}% | {} | {} |",
            o.stats.layers,
            100.0 * o.stats.layers as f64 / l0,
            100.0 * t / t0,
            o.stats.nonconvex_leaves,
            o.stats.extra_constraints
        );
    }
}

/// A grid of `n^3` cubes with two tunnels along x and y and a cavity: non-convex, and its grid
/// planes (unjittered) hold the slab planes, so no tet crosses a leaf boundary.
fn holed_grid(n: usize, jittered: bool) -> TetMesh {
    let mut m = structured_grid([n, n, n], [0.0; 3], [1.0; 3]);
    if jittered {
        jitter(&mut m, [n, n, n], 0.2, 7);
    }
    let cube = m
        .cell_data
        .get("cube_id")
        .or_exit("the generated mesh's array 'cube_id'");
    let (lo, hi) = (n / 4, n / 4 + n / 8);
    let keep: Vec<usize> = (0..m.tets.len())
        .filter(|&t| {
            let c = cube.data.get_f64(t) as usize;
            let (i, j, k) = (c % n, (c / n) % n, c / (n * n));
            let tunnel_x = (lo..hi).contains(&j) && (lo..hi).contains(&k);
            let tunnel_y = (n - hi..n - lo).contains(&i) && (n - hi..n - lo).contains(&k);
            let cavity = (n / 2..n / 2 + n / 8).contains(&i)
                && (n / 2..n / 2 + n / 8).contains(&j)
                && (n / 2..n / 2 + n / 8).contains(&k);
            !(tunnel_x || tunnel_y || cavity)
        })
        .collect();
    let mut out = m.clone();
    out.tets = keep.iter().map(|&t| m.tets[t]).collect();
    out.cell_data = m.cell_data.gather(&keep);
    out
}

/// The TetGen torus (scripts/tetgen_surfaces.py, R = 1, r = 0.4) with about 200k tets, when the
/// `tetgen` binary is there.
fn tetgen_torus() -> Option<TetMesh> {
    let dir = std::env::temp_dir().join(format!("tetkit-sort-torus-{}", std::process::id()));
    std::fs::create_dir_all(&dir).ok()?;
    let ok = std::process::Command::new("/usr/bin/python3")
        .arg(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/scripts/tetgen_surfaces.py"
        ))
        .arg(&dir)
        .status()
        .ok()?
        .success()
        && std::process::Command::new("tetgen")
            .args(["-pq1.2a0.00004zQ", "torus.poly"])
            .current_dir(&dir)
            .status()
            .ok()?
            .success();
    // Only the tets: TetGen's boundary triangles and edges stay out.
    let _ = std::fs::remove_file(dir.join("torus.1.face"));
    let _ = std::fs::remove_file(dir.join("torus.1.edge"));
    let mesh = if ok {
        tetkit::formats::read(&dir.join("torus.1.ele"))
            .ok()
            .and_then(|g| TetMesh::from_grid(&g).ok())
    } else {
        None
    };
    let _ = std::fs::remove_dir_all(&dir);
    mesh
}

fn table1() {
    eprintln!(
        "\nThe paper's Table 1 (layers fall to 61% / 38%, sort time to 63.7% / 43.6% on average)"
    );
    let n = 44;
    let grid = structured_grid([n, n, n], [0.0; 3], [1.0; 3]);
    table1_on("the 44^3 grid", &grid, &camera_along_x());
    table1_on(
        "the 40^3 grid with tunnels and a cavity",
        &holed_grid(40, false),
        &camera_along_x(),
    );
    match tetgen_torus() {
        Some(t) => {
            let mut c = Camera {
                position: [-3.2, 0.23, 0.41],
                focal: [0.0, 0.0, 0.0],
                up: [0.0, 0.0, 1.0],
                view_angle: 40.0,
                parallel: false,
                parallel_scale: 1.0,
            };
            c.orthogonalize_up();
            table1_on(
                "the TetGen torus (leaves by tet centroid: tets cross the slab planes)",
                &t,
                &c,
            );
        }
        None => eprintln!("(tetgen not found: no torus table)"),
    }
}

/// Per-view kd time on a non-convex 1M-tet mesh (jittered grid with tunnels and a cavity), from
/// outside and from inside a tunnel: the extra constraints and big-integer fallbacks it needed.
fn nonconvex_per_view(n: usize) {
    let mesh = holed_grid(n, true);
    let s = Sorter::new(&mesh, None).or_exit("building the sorter");
    eprintln!(
        "\nNon-convex per view: {} tets (jittered {n}^3 grid, two tunnels and a cavity), one leaf",
        mesh.tets.len()
    );
    let lo = (n / 4) as f64 / n as f64;
    let w = (n / 8) as f64 / n as f64;
    let mut inside = Camera {
        position: [0.02, lo + 0.5 * w, lo + 0.5 * w],
        focal: [1.0, 0.6, 0.5],
        up: [0.0, 0.0, 1.0],
        view_angle: 60.0,
        parallel: false,
        parallel_scale: 1.0,
    };
    inside.orthogonalize_up();
    for (label, cam) in [("outside", camera_oblique()), ("eye in a tunnel", inside)] {
        for m in [Method::Kd, Method::Mpvo, Method::Centroid] {
            let o = s.order(&cam, m, Direction::BackToFront);
            let t = median_time(5, || {
                std::hint::black_box(s.order(&cam, m, Direction::BackToFront));
            });
            eprintln!(
                "  {label}: {m:?} {t:.4} s median of 5 ({} layers, {} extra constraints in {:.4} s, {} exact fallbacks, {} cycles)",
                o.stats.layers, o.stats.extra_constraints, o.stats.extra_seconds, o.stats.exact_fallbacks, o.stats.cycles
            );
        }
    }
}

/// CPU seconds this process has run, all threads (Linux schedstat; 0 elsewhere): on a shared
/// machine a steadier figure than wall time.
fn cpu_seconds() -> f64 {
    let Ok(dir) = std::fs::read_dir("/proc/self/task") else {
        return 0.0;
    };
    let ns: u64 = dir
        .flatten()
        .filter_map(|e| std::fs::read_to_string(e.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next()?.parse::<u64>().ok())
        .sum();
    ns as f64 * 1e-9
}

fn uptime() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

fn write_raw(mesh: &TetMesh, dir: &std::path::Path) -> (std::path::PathBuf, std::path::PathBuf) {
    std::fs::create_dir_all(dir).or_exit("writing the TetGen input");
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
    std::fs::write(&p, pts).or_exit("writing the TetGen input");
    std::fs::write(&t, tets).or_exit("writing the TetGen input");
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
    let s = Sorter::new(&mesh, None).or_exit("building the sorter");
    let setup = t0.elapsed().as_secs_f64();
    eprintln!(
        "\n1M-tet sort per view: {} tets (jittered {n}^3 grid), adjacency set-up {setup:.3} s once",
        mesh.tets.len()
    );
    let mut layers = 0;
    for m in [Method::Kd, Method::Mpvo, Method::Centroid] {
        let (mut best, c0) = (f64::INFINITY, cpu_seconds());
        let t = median_time(7, || {
            let s0 = Instant::now();
            let o = s.order(&cam, m, Direction::BackToFront);
            best = best.min(s0.elapsed().as_secs_f64());
            layers = o.stats.layers;
            std::hint::black_box(o);
        });
        let cpu = (cpu_seconds() - c0) / 7.0;
        eprintln!("  tetkit {m:?}: {t:.4} s median of 7, best {best:.4} s, CPU {cpu:.4} s per view (all threads) ({layers} layers)");
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
    eprintln!("\nLoad when the figures start (uptime): {}", uptime());
    table1();
    million_vs_vtk();
    nonconvex_per_view(
        std::env::var("TETKIT_BENCH_N")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(55),
    );
    eprintln!("\nLoad when the figures end (uptime): {}", uptime());
    let n = 30;
    let mut mesh = structured_grid([n, n, n], [0.0; 3], [1.0; 3]);
    jitter(&mut mesh, [n, n, n], 0.2, 1);
    let cam = camera_oblique();
    let s = Sorter::new(&mesh, None).or_exit("building the sorter");
    let mut g = c.benchmark_group("sort_162k_tets");
    g.sample_size(10);
    for m in [Method::Kd, Method::Mpvo, Method::Centroid] {
        g.bench_function(format!("{m:?}"), |b| {
            b.iter(|| std::hint::black_box(s.order(&cam, m, Direction::BackToFront)))
        });
    }
    g.bench_function("adjacency_setup", |b| {
        b.iter(|| {
            std::hint::black_box(
                Sorter::new(&mesh, None)
                    .or_exit("building the sorter")
                    .num_leaves(),
            )
        })
    });
    g.finish();
}

criterion_group!(sort_benches, benches);
criterion_main!(sort_benches);
