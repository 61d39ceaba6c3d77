//! Library-level exactness of the visibility sorts, measured by the independent ray checker on
//! generated convex, non-convex and cyclic meshes, in perspective and orthographic views.

use tetkit::camera::Camera;
use tetkit::geom::Aabb;
use tetkit::mesh::generate::{jitter, structured_grid};
use tetkit::mesh::TetMesh;
use tetkit::partition::{KdNode, KdTree, Split};
use tetkit::sort::check::check_order;
use tetkit::sort::{Direction, Method, Sorter};

fn cam(position: [f64; 3], focal: [f64; 3], parallel: bool) -> Camera {
    let mut c = Camera {
        position,
        focal,
        up: [0.0, 0.0, 1.0],
        view_angle: 50.0,
        parallel,
        parallel_scale: 1.0,
    };
    if (c.direction()[2]).abs() > 0.99 {
        c.up = [0.0, 1.0, 0.0];
    }
    c.orthogonalize_up();
    c
}

/// Cameras around (and inside) the unit cube: perspective, orthographic, inside the bounding
/// box, and eyes exactly on grid planes (face planes of many tets).
fn cameras() -> Vec<Camera> {
    vec![
        cam([2.3, 1.7, 1.9], [0.5, 0.5, 0.5], false),
        cam([-1.1, 2.2, -0.7], [0.4, 0.6, 0.5], false),
        cam([2.3, -1.7, 0.9], [0.5, 0.5, 0.5], true),
        cam([0.3, 0.2, -2.0], [0.5, 0.45, 0.5], true),
        // Inside the bounding box (in a hole of the holed meshes, inside the grid otherwise).
        cam([0.55, 0.45, 0.52], [1.5, 0.9, 0.7], false),
        // Exactly on the plane x = 0.5 and z = 0.25 (grid planes).
        cam([0.5, -2.0, 0.25], [0.6, 0.5, 0.5], false),
        cam([0.5, 0.5, 3.0], [0.5, 0.5, 0.5], false),
    ]
}

fn keep_cubes(m: &TetMesh, keep: impl Fn(usize) -> bool) -> TetMesh {
    let cube = m.cell_data.get("cube_id").unwrap();
    let idx: Vec<usize> = (0..m.tets.len())
        .filter(|&t| keep(cube.data.get_f64(t) as usize))
        .collect();
    let mut out = m.clone();
    out.tets = idx.iter().map(|&t| m.tets[t]).collect();
    out.cell_data = m.cell_data.gather(&idx);
    out
}

/// A 6x6x6 grid with a tunnel along x, a cavity and a notch: holes, a cavity and concave edges.
fn holed() -> TetMesh {
    let n = 6;
    let mut m = structured_grid([n, n, n], [0.0; 3], [1.0; 3]);
    jitter(&mut m, [n, n, n], 0.15, 3);
    keep_cubes(&m, |c| {
        let (i, j, k) = (c % n, (c / n) % n, c / (n * n));
        let tunnel = (j == 2 || j == 3) && k == 2;
        let cavity = i == 4 && j == 4 && k == 4;
        let notch = i >= 4 && k == 0;
        let inner_room = (1..=2).contains(&i) && (2..=3).contains(&j) && (3..=4).contains(&k);
        !(tunnel || cavity || notch || inner_room)
    })
}

fn l_shape() -> TetMesh {
    let n = 5;
    let mut m = structured_grid([n, n, 3], [0.0; 3], [1.0; 3]);
    jitter(&mut m, [n, n, 3], 0.1, 11);
    keep_cubes(&m, |c| {
        let (i, j) = (c % n, (c / n) % n);
        !(i >= 2 && j >= 2)
    })
}

fn violations(mesh: &TetMesh, tree: Option<&KdTree>, method: Method, c: &Camera) -> usize {
    let sorter = Sorter::new(mesh, tree).unwrap();
    let mut total = 0;
    for dir in [Direction::BackToFront, Direction::FrontToBack] {
        let o = sorter.order(c, method, dir);
        let mut seen = vec![false; mesh.tets.len()];
        for &t in &o.order {
            assert!(!seen[t as usize], "tet {t} twice");
            seen[t as usize] = true;
        }
        assert!(seen.iter().all(|&s| s), "order is not a permutation");
        let r = check_order(mesh, c, &o.ranks(), dir == Direction::FrontToBack, 48, 48);
        if r.violations > 0 && method == Method::Kd {
            eprintln!("{dir:?} {:?} {:?}", o.stats, r);
        }
        total += r.violations;
    }
    total
}

/// A tree splitting the unit cube at x = 0.5 (and y = 0.5 below each side when `four`).
fn grid_tree(four: bool) -> KdTree {
    let b = |min: [f64; 3], max: [f64; 3]| Aabb { min, max };
    let node = |bounds, depth, parent, split, leaf_id| KdNode {
        bounds,
        depth,
        parent,
        split,
        leaf_id,
        tet_count: 0,
    };
    let sp = |axis, left, right| {
        Some(Split {
            axis,
            position: 0.5,
            left,
            right,
        })
    };
    if !four {
        return KdTree {
            nodes: vec![
                node(b([0.0; 3], [1.0; 3]), 0, None, sp(0, 1, 2), None),
                node(b([0.0; 3], [0.5, 1.0, 1.0]), 1, Some(0), None, Some(0)),
                node(b([0.5, 0.0, 0.0], [1.0; 3]), 1, Some(0), None, Some(1)),
            ],
        };
    }
    KdTree {
        nodes: vec![
            node(b([0.0; 3], [1.0; 3]), 0, None, sp(0, 1, 2), None),
            node(b([0.0; 3], [0.5, 1.0, 1.0]), 1, Some(0), sp(1, 3, 4), None),
            node(b([0.5, 0.0, 0.0], [1.0; 3]), 1, Some(0), sp(1, 5, 6), None),
            node(b([0.0; 3], [0.5, 0.5, 1.0]), 2, Some(1), None, Some(0)),
            node(
                b([0.0, 0.5, 0.0], [0.5, 1.0, 1.0]),
                2,
                Some(1),
                None,
                Some(1),
            ),
            node(
                b([0.5, 0.0, 0.0], [1.0, 0.5, 1.0]),
                2,
                Some(2),
                None,
                Some(2),
            ),
            node(b([0.5, 0.5, 0.0], [1.0; 3]), 2, Some(2), None, Some(3)),
        ],
    }
}

#[test]
fn convex_grid_kd_and_mpvo_exact_centroid_not() {
    let n = [6, 6, 4];
    let mut m = structured_grid(n, [0.0; 3], [1.0; 3]);
    jitter(&mut m, n, 0.2, 5);
    let mut centroid = 0;
    for c in cameras() {
        assert_eq!(violations(&m, None, Method::Mpvo, &c), 0, "mpvo {c:?}");
        assert_eq!(violations(&m, None, Method::Kd, &c), 0, "kd {c:?}");
        centroid += violations(&m, None, Method::Centroid, &c);
    }
    eprintln!("centroid violations on the convex jittered grid: {centroid}");
    assert!(centroid > 0, "centroid was expected to misorder some pairs");
}

#[test]
fn kd_with_two_and_four_leaves_is_exact() {
    // Grid planes at 0.5 (n even, no jitter there) so no tet crosses a split plane.
    let n = [6, 6, 4];
    let m = structured_grid(n, [0.0; 3], [1.0; 3]);
    for four in [false, true] {
        let tree = grid_tree(four);
        let s = Sorter::new(&m, Some(&tree)).unwrap();
        assert_eq!(s.num_leaves(), if four { 4 } else { 2 });
        assert_eq!(s.nonconvex_leaves(), 0);
        for c in cameras() {
            assert_eq!(violations(&m, Some(&tree), Method::Kd, &c), 0, "{c:?}");
        }
    }
}

#[test]
fn nonconvex_meshes_kd_exact() {
    for (name, m) in [("holed", holed()), ("L", l_shape())] {
        let mut mpvo = 0;
        let mut centroid = 0;
        for c in cameras() {
            assert_eq!(violations(&m, None, Method::Kd, &c), 0, "{name} kd {c:?}");
            mpvo += violations(&m, None, Method::Mpvo, &c);
            centroid += violations(&m, None, Method::Centroid, &c);
        }
        eprintln!("{name}: mpvo violations {mpvo}, centroid violations {centroid}");
        assert!(centroid > 0);
        if name == "holed" {
            assert!(mpvo > 0, "adjacency alone should fail on the holed mesh");
        }
    }
}

#[test]
fn nonconvex_with_leaves_kd_exact() {
    let n = 6;
    let m = structured_grid([n, n, n], [0.0; 3], [1.0; 3]);
    let m = keep_cubes(&m, |c| {
        let (i, j, k) = (c % n, (c / n) % n, c / (n * n));
        !((j == 1 || j == 4) && (k == 1 || k == 4)) && !(i == 2 && j == 2 && k == 3)
    });
    let tree = grid_tree(true);
    let s = Sorter::new(&m, Some(&tree)).unwrap();
    assert!(s.nonconvex_leaves() > 0);
    for c in cameras() {
        assert_eq!(violations(&m, Some(&tree), Method::Kd, &c), 0, "{c:?}");
    }
}

/// Three long thin tets over each other like a pinwheel: each lies above the next where they
/// cross, so no order of whole tets is right from above.
fn pinwheel() -> TetMesh {
    let mut points = Vec::new();
    let mut tets = Vec::new();
    for i in 0..3 {
        let a = i as f64 * 2.0 * std::f64::consts::PI / 3.0;
        let (dx, dy) = (a.cos(), a.sin());
        let (nx, ny) = (-dy, dx);
        // From high at one end to low at the other, offset sideways so the three cross.
        let base = points.len() as u32;
        let c = [0.3 * nx, 0.3 * ny];
        points.push([c[0] - dx + 0.15 * nx, c[1] - dy + 0.15 * ny, 1.0]);
        points.push([c[0] - dx - 0.15 * nx, c[1] - dy - 0.15 * ny, 1.0]);
        points.push([c[0] + dx, c[1] + dy, 0.0]);
        points.push([c[0] + dx, c[1] + dy, 0.1]);
        tets.push([base, base + 1, base + 2, base + 3]);
    }
    TetMesh {
        points,
        tets,
        ..Default::default()
    }
}

#[test]
fn visibility_cycle_is_reported_and_order_is_a_permutation() {
    let m = pinwheel();
    let c = cam([0.0, 0.0, 5.0], [0.0, 0.0, 0.5], true);
    let s = Sorter::new(&m, None).unwrap();
    for dir in [Direction::BackToFront, Direction::FrontToBack] {
        let o = s.order(&c, Method::Kd, dir);
        assert!(o.stats.cycles >= 1, "{:?}", o.stats);
        assert_eq!(o.stats.cycle_tets, 3, "{:?}", o.stats);
        let mut sorted = o.order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, vec![0, 1, 2]);
        // A true cycle: whatever the order, some ray sees a pair in the wrong order.
        let r = check_order(&m, &c, &o.ranks(), dir == Direction::FrontToBack, 64, 64);
        assert!(r.violations > 0, "{r:?}");
    }
}

/// The grid with tunnels of `nonconvex_with_leaves_kd_exact`, not jittered: its grid planes
/// (multiples of 1/6) are face planes, so eyes snapped onto them sit exactly on many faces.
fn tunnels() -> TetMesh {
    let n = 6;
    let m = structured_grid([n, n, n], [0.0; 3], [1.0; 3]);
    keep_cubes(&m, |c| {
        let (i, j, k) = (c % n, (c / n) % n, c / (n * n));
        !((j == 1 || j == 4) && (k == 1 || k == 4)) && !(i == 2 && j == 2 && k == 3)
    })
}

mod random_views {
    use super::*;
    use proptest::prelude::*;
    use std::sync::OnceLock;

    fn meshes() -> &'static [(TetMesh, Option<KdTree>)] {
        static M: OnceLock<Vec<(TetMesh, Option<KdTree>)>> = OnceLock::new();
        M.get_or_init(|| {
            vec![
                (holed(), None),
                (l_shape(), None),
                (tunnels(), Some(grid_tree(true))),
            ]
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(32))]

        /// Eyes anywhere around and inside the non-convex meshes (in tunnels, cavities, inside
        /// the tets), some snapped exactly onto face planes, perspective or orthographic: the kd
        /// order agrees with every checked ray unless the view has a genuine cycle.
        #[test]
        fn kd_is_exact_from_random_eyes(
            eye in prop::array::uniform3(-0.6f64..1.6),
            look in prop::array::uniform3(0.1f64..0.9),
            parallel in any::<bool>(),
            snap in 0usize..4,
            plane in 0usize..7,
        ) {
            let mut eye = eye;
            if snap > 0 {
                // Exactly on x, y or z = plane / 6 (boundary planes at 0 and 1).
                eye[snap - 1] = plane as f64 / 6.0;
            }
            prop_assume!((0..3).any(|k| (eye[k] - look[k]).abs() > 0.05));
            let c = cam(eye, look, parallel);
            for (m, tree) in meshes() {
                let sorter = Sorter::new(m, tree.as_ref()).unwrap();
                for dir in [Direction::BackToFront, Direction::FrontToBack] {
                    let o = sorter.order(&c, Method::Kd, dir);
                    let mut sorted = o.order.clone();
                    sorted.sort_unstable();
                    prop_assert!(sorted.iter().enumerate().all(|(i, &t)| t as usize == i));
                    let r = check_order(m, &c, &o.ranks(), dir == Direction::FrontToBack, 40, 40);
                    if o.stats.cycles == 0 {
                        prop_assert_eq!(r.violations, 0, "{:?} {:?} {:?}", c, o.stats, r);
                    }
                }
            }
        }
    }
}

/// Identical order, layers and counts under 1 and 2 threads (leaves and frontiers in parallel),
/// for one leaf and for four, convex and not.
#[test]
fn order_is_identical_under_any_thread_count() {
    let n = 14;
    let mut grid = structured_grid([n, n, n], [0.0; 3], [1.0; 3]);
    jitter(&mut grid, [n, n, n], 0.2, 5);
    let meshes = [
        (grid, None),
        (holed(), Some(grid_tree(true))),
        (tunnels(), None),
    ];
    let pool = |k| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(k)
            .build()
            .unwrap()
    };
    let (one, two) = (pool(1), pool(2));
    for (m, tree) in &meshes {
        let s = Sorter::new(m, tree.as_ref()).unwrap();
        for c in cameras() {
            for method in [Method::Kd, Method::Mpvo] {
                let run = |p: &rayon::ThreadPool| {
                    let o = p.install(|| s.order(&c, method, Direction::FrontToBack));
                    (o.order, o.layer, o.stats.layers, o.stats.face_constraints)
                };
                assert_eq!(run(&one), run(&two), "{method:?} {c:?}");
            }
        }
    }
}

/// A tree whose planes are grid planes holds every tet of the plain grid inside its leaf; on the
/// jittered grid the same planes cut tets, which the stats count (and the order may misplace).
#[test]
fn tets_crossing_their_leaf_box_are_counted() {
    let c = cam([2.3, 1.7, 1.9], [0.5, 0.5, 0.5], false);
    let count = |m: &TetMesh, method| {
        let s = Sorter::new(m, Some(&grid_tree(true))).unwrap();
        (
            s.tets_outside_leaf(),
            s.order(&c, method, Direction::BackToFront)
                .stats
                .tets_outside_leaf,
        )
    };
    assert_eq!(count(&tunnels(), Method::Kd), (0, 0));
    let h = holed();
    let (n, in_stats) = count(&h, Method::Kd);
    assert!(n > 0 && in_stats == n, "{n} {in_stats}");
    // Every counted tet has a vertex on each side of x = 0.5 or y = 0.5.
    let crossing = h
        .tets
        .iter()
        .filter(|t| {
            (0..2).any(|k| {
                let side = |v: &u32| h.points[*v as usize][k] > 0.5;
                t.iter().any(side)
                    && !t.iter().all(side)
                    && t.iter().any(|v| h.points[*v as usize][k] < 0.5)
            })
        })
        .count();
    assert_eq!(n, crossing);
    assert_eq!(count(&h, Method::Mpvo).1, 0);
}

/// A mesh appended to itself (vtkAppendFilter run on one grid twice, points merged): every
/// interior face has four tets and every boundary face two on one side. Left as boundary faces
/// they made the leaf non-convex with constraints between every pair of overlapping faces
/// (17,280 tets: 2.5M constraints, 9.4 s, and 252 cycles from boundary copies paired as if
/// across each other). Paired by side, the two copies sort as the single grid does: no extra
/// constraints, no cycles, the same number of layers, each copy in the order of the original.
#[test]
fn a_mesh_appended_to_itself_sorts_as_the_single_mesh() {
    let n = [5, 4, 3];
    let mut single = structured_grid(n, [0.0; 3], [1.0, 0.8, 0.6]);
    jitter(&mut single, n, 0.2, 7);
    single.cell_data = Default::default();
    let mut double = single.clone();
    double.tets.extend(single.tets.clone());
    let c = cam([2.5, -1.7, 1.3], [0.5, 0.4, 0.3], false);
    let one = Sorter::new(&single, None).map(|s| s.order(&c, Method::Kd, Direction::FrontToBack));
    let two = Sorter::new(&double, None);
    assert!(one.is_ok() && two.is_ok());
    let (Ok(one), Ok(two)) = (one, two) else {
        return;
    };
    assert!(two.nonmanifold_faces() > 0);
    let o = two.order(&c, Method::Kd, Direction::FrontToBack);
    assert_eq!(o.stats.extra_constraints, 0);
    assert_eq!(o.stats.cycles, 0);
    assert_eq!(o.stats.layers, one.stats.layers);
    assert_eq!(o.order.len(), double.tets.len());
    // Each copy's tets, in the doubled order, are an exact order of the single mesh.
    let nt = single.tets.len() as u32;
    for copy in 0..2 {
        let mut rank = vec![u32::MAX; nt as usize];
        for (k, &t) in o.order.iter().filter(|&&t| t / nt == copy).enumerate() {
            rank[(t % nt) as usize] = k as u32;
        }
        assert!(
            rank.iter().all(|&r| r != u32::MAX),
            "copy {copy} incomplete"
        );
        let r = check_order(&single, &c, &rank, true, 48, 48);
        assert_eq!(r.violations, 0, "copy {copy}: {r:?}");
    }
}

/// Tets of zero volume (a repeated vertex, `[a, b, c, a]`, as some exporters write collapsed
/// cells) hold no segment of any ray: the checker leaves them out. Clipping rays against their
/// degenerate planes gave them made-up intervals: a grid with 200 of them showed 1644
/// violations of a kd order that has none.
#[test]
fn zero_volume_tets_make_no_violations() {
    let n = [12, 12, 12];
    let mut m = structured_grid(n, [0.0; 3], [1.0; 3]);
    m.cell_data = Default::default();
    for t in 0..200 {
        let [a, b, c, _] = m.tets[t];
        m.tets.push([a, b, c, a]);
    }
    let s = Sorter::new(&m, None);
    assert!(s.is_ok());
    let Ok(s) = s else { return };
    for c in cameras() {
        let o = s.order(&c, Method::Kd, Direction::FrontToBack);
        let r = check_order(&m, &c, &o.ranks(), true, 64, 64);
        assert_eq!(r.violations, 0, "{c:?}: {r:?}");
    }
}
