//! Visibility cycles in a connected, conforming mesh: TetGen's box mesh around three long tets
//! that lie over one another in a pinwheel (fixtures/sort/pinwheel.1.ele, made by
//! scripts/make_sort_fixtures.sh). Seen from above the cycle is detected (strongly connected
//! components), counted in the library result and in `--json`, broken deterministically, and
//! every tet is placed exactly once. Seen from the side the same mesh has no cycle and `kd` is
//! exact.

mod common;

use common::{fixture, tempdir, tetkit};
use serde_json::Value;
use tetkit::camera::Camera;
use tetkit::mesh::TetMesh;
use tetkit::sort::check::check_order;
use tetkit::sort::{Direction, Method, Sorter};

fn pinwheel() -> (TetMesh, Vec<u32>) {
    let g = tetkit::formats::read(&fixture("sort/pinwheel.1.ele")).unwrap();
    let mesh = TetMesh::from_grid(&g).unwrap();
    let region = g.cell_data.get("region").expect("region attribute (-A)");
    let regions: Vec<u32> = (0..mesh.tets.len())
        .map(|t| region.data.get_f64(t) as u32)
        .collect();
    (mesh, regions)
}

fn cam(position: [f64; 3], focal: [f64; 3], parallel: bool) -> Camera {
    let mut c = Camera {
        position,
        focal,
        up: [0.0, 1.0, 0.0],
        view_angle: 40.0,
        parallel,
        parallel_scale: 1.7,
    };
    c.orthogonalize_up();
    c
}

/// Views from above (and one from below), where the three long tets overlap in a cycle.
fn cycle_views() -> Vec<Camera> {
    vec![
        cam([0.0, 0.0, 5.0], [0.0, 0.0, 0.5], true),
        cam([0.0, 0.0, 5.0], [0.0, 0.0, 0.5], false),
        cam([0.2, -0.3, 4.0], [0.0, 0.0, 0.5], false),
        cam([0.1, 0.05, -4.0], [0.0, 0.0, 0.5], true),
    ]
}

fn is_permutation(order: &[u32], n: usize) -> bool {
    let mut seen = vec![false; n];
    order.len() == n
        && order
            .iter()
            .all(|&t| (t as usize) < n && !std::mem::replace(&mut seen[t as usize], true))
}

#[test]
fn cycle_in_a_connected_mesh_is_detected_counted_and_broken() {
    let (mesh, regions) = pinwheel();
    let n = mesh.tets.len();
    // The three long tets survived as single tets of the conforming mesh.
    for r in 1..=3 {
        assert_eq!(regions.iter().filter(|&&x| x == r).count(), 1, "region {r}");
    }
    let sorter = Sorter::new(&mesh, None).unwrap();
    assert_eq!(sorter.nonconvex_leaves(), 0, "the box is convex");
    for c in cycle_views() {
        for method in [Method::Kd, Method::Mpvo] {
            for dir in [Direction::BackToFront, Direction::FrontToBack] {
                let o = sorter.order(&c, method, dir);
                let s = &o.stats;
                assert!(s.cycles >= 1, "{method:?} {dir:?} {c:?}: {s:?}");
                assert!(s.cycle_tets >= 3, "{s:?}");
                assert!(s.broken_constraints >= 1, "{s:?}");
                assert!(is_permutation(&o.order, n), "{method:?} {dir:?}");
                assert!(o.layer.iter().all(|&l| l < s.layers), "{s:?}");
                // Deterministic: the same order from this sorter and from a fresh one.
                assert_eq!(sorter.order(&c, method, dir).order, o.order);
                assert_eq!(
                    Sorter::new(&mesh, None)
                        .unwrap()
                        .order(&c, method, dir)
                        .order,
                    o.order
                );
                // A genuine cycle: no order of whole tets is right along every ray.
                let r = check_order(&mesh, &c, &o.ranks(), dir == Direction::FrontToBack, 64, 64);
                assert!(r.violations > 0, "{method:?} {dir:?} {c:?}: {r:?}");
            }
        }
    }
}

#[test]
fn seen_from_the_side_there_is_no_cycle_and_kd_is_exact() {
    let (mesh, _) = pinwheel();
    let sorter = Sorter::new(&mesh, None).unwrap();
    for c in [
        cam([5.0, 0.3, 0.5], [0.0, 0.0, 0.5], false),
        cam([0.3, 5.0, 0.6], [0.0, 0.0, 0.5], true),
        cam([3.0, 3.0, 2.0], [0.0, 0.0, 0.5], false),
    ] {
        for dir in [Direction::BackToFront, Direction::FrontToBack] {
            let o = sorter.order(&c, Method::Kd, dir);
            assert_eq!(o.stats.cycles, 0, "{c:?}: {:?}", o.stats);
            assert!(is_permutation(&o.order, mesh.tets.len()));
            let r = check_order(&mesh, &c, &o.ranks(), dir == Direction::FrontToBack, 64, 64);
            assert!(r.crossings > 0);
            assert_eq!(r.violations, 0, "{c:?}: {r:?}");
        }
    }
}

#[test]
fn cli_reports_the_cycle_and_writes_a_permutation() {
    let dir = tempdir();
    let out = dir.path().join("ordered.vtu");
    let input = fixture("sort/pinwheel.1.ele");
    let view = [
        "--position=0,0,5",
        "--focal=0,0,0.5",
        "--up=0,1,0",
        "--parallel",
    ];
    let mut args = vec![
        "sort",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--json",
    ];
    args.extend_from_slice(&view);
    let r = tetkit(&args);
    r.assert_success();
    let j: Value = serde_json::from_slice(&r.stdout).unwrap();
    let s = &j["stats"];
    assert!(s["cycles"].as_u64().unwrap() >= 1, "{j}");
    assert!(s["cycle_tets"].as_u64().unwrap() >= 3, "{j}");
    assert!(s["broken_constraints"].as_u64().unwrap() >= 1, "{j}");
    let n = s["tets"].as_u64().unwrap() as usize;
    let g = tetkit::formats::read(&out).unwrap();
    let rank = g.cell_data.get("visibility_order").unwrap();
    let mut ranks: Vec<usize> = (0..n).map(|t| rank.data.get_f64(t) as usize).collect();
    ranks.sort_unstable();
    assert_eq!(ranks, (0..n).collect::<Vec<_>>());
    // The same count from check-order, which also finds the violations the cycle forces.
    let mut args = vec![
        "check-order",
        input.to_str().unwrap(),
        "--rays=2500",
        "--json",
    ];
    args.extend_from_slice(&view);
    let r = tetkit(&args);
    r.assert_success();
    let c: Value = serde_json::from_slice(&r.stdout).unwrap();
    assert_eq!(c["sort_stats"]["cycles"], s["cycles"], "{c}");
    assert!(c["report"]["violations"].as_u64().unwrap() > 0, "{c}");
}
