//! Property tests of the partition: random tets against random planes, random meshes against
//! both plane searches. Volumes add up, sub-tets stay in their leaf boxes (exact comparisons), the
//! result is conforming, old point data is untouched and linear fields are interpolated exactly.

mod partition_util;

use proptest::prelude::*;
use tetkit::geom::tet_volume;
use tetkit::mesh::TetMesh;
use tetkit::partition::build::volume_sign;
use tetkit::partition::split::{case_counts, edge_point, side, split_tet};
use tetkit::partition::{partition, PartitionOptions, SearchParams, Stop, Strategy as Search};

use partition_util::{check_partition, jittered, lin};

fn coord() -> impl Strategy<Value = f64> {
    // Small integers make vertex-on-plane and edge-on-plane cases common; the fraction makes
    // general positions.
    prop_oneof![(-4i32..5).prop_map(f64::from), -4.0f64..4.0]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn random_tet_random_plane(
        p in proptest::array::uniform4(proptest::array::uniform3(coord())),
        axis in 0usize..3,
        pick in 0usize..5,
        frac in 0.0f64..1.0,
    ) {
        let p = if volume_sign(&p) < 0.0 { [p[0], p[1], p[3], p[2]] } else { p };
        prop_assume!(volume_sign(&p) > 0.0);
        // The plane: through a vertex (pick < 4) or anywhere in the tet's range.
        let lo = p.iter().map(|x| x[axis]).fold(f64::INFINITY, f64::min);
        let hi = p.iter().map(|x| x[axis]).fold(f64::NEG_INFINITY, f64::max);
        let pos = if pick < 4 { p[pick][axis] } else { lo + frac * (hi - lo) };
        let sides = p.map(|x| side(x[axis], pos));
        let mut points = p.to_vec();
        let mut mids = std::collections::HashMap::new();
        for i in 0..4 {
            for j in i + 1..4 {
                if sides[i] * sides[j] == -1 {
                    let (q, _, _) = edge_point(&p[i], &p[j], axis, pos);
                    mids.insert((i as u32, j as u32), points.len() as u32);
                    points.push(q);
                }
            }
        }
        let mut out = Vec::new();
        split_tet([0, 1, 2, 3], sides, &|a, b| mids[&(a, b)], &mut out);
        let c = |s: i8| sides.iter().filter(|&&x| x == s).count() as u8;
        let (l, r) = case_counts(c(-1), c(0), c(1));
        prop_assert_eq!(out.len(), (l + r) as usize);
        let whole = tet_volume(&p[0], &p[1], &p[2], &p[3]);
        let mut sum = 0.0;
        for (t, s) in &out {
            let q = t.map(|v| points[v as usize]);
            prop_assert!(volume_sign(&q) > 0.0, "piece {:?} of {:?} at {} not positive", t, p, pos);
            for x in &q {
                prop_assert!(side(x[axis], pos) * s >= 0, "piece on the wrong side");
            }
            sum += tet_volume(&q[0], &q[1], &q[2], &q[3]);
        }
        // 1e-12 relative, plus the rounding bound of a float determinant: each volume is computed
        // with an absolute error of a few ulps of (longest edge)^3, which dominates for flat tets
        // (a 9-unit tet of volume 9e-4 differs by 1.5e-15, i.e. 1.7e-12 relative).
        let longest = (0..4)
            .flat_map(|i| (i + 1..4).map(move |j| (i, j)))
            .map(|(i, j)| (0..3).map(|k| (p[i][k] - p[j][k]).powi(2)).sum::<f64>().sqrt())
            .fold(0.0f64, f64::max);
        let tol = 1e-12 * whole + 32.0 * f64::EPSILON * longest.powi(3) / 6.0;
        prop_assert!((sum - whole).abs() <= tol, "{} vs {} (tolerance {})", sum, whole, tol);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn random_meshes_partition_correctly(
        n in proptest::array::uniform3(1usize..5),
        min in proptest::array::uniform3(-10.0f64..10.0),
        size in proptest::array::uniform3(0.5f64..4.0),
        amount in 0.0f64..0.24,
        seed in any::<u64>(),
        leaves in 1usize..9,
        cost in any::<bool>(),
        eps in 0.2f64..1.9,
    ) {
        let mesh: TetMesh = jittered(n, min, size, amount, seed);
        let s = size.iter().cloned().fold(0.0, f64::max);
        let opts = PartitionOptions {
            stop: Stop::Leaves(leaves),
            search: SearchParams {
                strategy: if cost { Search::Cost } else { Search::Paper },
                candidates: 7,
                phi: 10.0,
                eps,
                balance_weight: 0.5,
            },
        };
        let out = partition(&mesh, &opts).unwrap();
        prop_assert!(out.report.leaves <= leaves);
        let f = move |p: &[f64; 3]| lin(p, min, s);
        check_partition(&mesh, &out, Some(&f), 1e-12, 1e-12 * s, true);
    }
}
