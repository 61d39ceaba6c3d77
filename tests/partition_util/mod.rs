//! Checks shared by the partition tests: volumes, leaf boxes, conformity, data carried.
#![allow(dead_code)]

use std::collections::{HashMap, HashSet};

use tetkit::formats::{ArrayData, DataArray};
use tetkit::geom::{orient3d, tet_volume};
use tetkit::mesh::generate::{jitter, structured_grid};
use tetkit::mesh::TetMesh;
use tetkit::partition::build::volume_sign;
use tetkit::partition::{Partitioned, LEAF_ID, ORIGINAL_CELL_ID};

/// 1 + 2x - 3y + z/2 relative to `origin`, as Float64 point data named `lin`.
pub fn add_linear_field(m: &mut TetMesh, origin: [f64; 3], scale: f64) {
    let v = m.points.iter().map(|p| lin(p, origin, scale)).collect();
    m.point_data
        .insert(DataArray::new("lin", 1, ArrayData::Float64(v)));
}

pub fn lin(p: &[f64; 3], o: [f64; 3], s: f64) -> f64 {
    1.0 + (2.0 * (p[0] - o[0]) - 3.0 * (p[1] - o[1]) + 0.5 * (p[2] - o[2])) / s
}

/// A jittered structured grid over `[min, min + size]` with the `lin` field.
pub fn jittered(n: [usize; 3], min: [f64; 3], size: [f64; 3], amount: f64, seed: u64) -> TetMesh {
    let max = [0, 1, 2].map(|a| min[a] + size[a]);
    let mut m = structured_grid(n, min, max);
    jitter(&mut m, n, amount, seed);
    let s = size.iter().cloned().fold(0.0, f64::max);
    add_linear_field(&mut m, min, s);
    m
}

fn faces(t: &[u32; 4]) -> [[u32; 3]; 4] {
    let mut f = [
        [t[0], t[1], t[2]],
        [t[0], t[1], t[3]],
        [t[0], t[2], t[3]],
        [t[1], t[2], t[3]],
    ];
    for x in &mut f {
        x.sort_unstable();
    }
    f
}

pub fn face_counts(tets: &[[u32; 4]]) -> HashMap<[u32; 3], u32> {
    let mut m = HashMap::new();
    for t in tets {
        for f in faces(t) {
            *m.entry(f).or_insert(0) += 1;
        }
    }
    m
}

fn int_array(m: &TetMesh, name: &str) -> Vec<i64> {
    let a = m
        .cell_data
        .get(name)
        .unwrap_or_else(|| panic!("no cell array {name}"));
    a.data.to_f64_vec().into_iter().map(|v| v as i64).collect()
}

/// Distance of `p` from the plane through `a`, `b`, `c`, relative to nothing (absolute).
fn plane_distance(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], p: &[f64; 3]) -> f64 {
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let w = [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
    (w[0] * n[0] + w[1] * n[1] + w[2] * n[2]).abs() / len
}

/// The exact linear field a test put in `lin`.
pub type LinearField = dyn Fn(&[f64; 3]) -> f64;

/// Every property the issue asks of a partition of `input` (tets positively oriented or not;
/// `vol_tol` is the relative tolerance for volume sums, `geo_tol` the absolute one for points
/// lying on faces). `conforming_input`: the input shares faces by point ids.
pub fn check_partition(
    input: &TetMesh,
    out: &Partitioned,
    lin_fn: Option<&LinearField>,
    vol_tol: f64,
    geo_tol: f64,
    conforming_input: bool,
) {
    let m = &out.mesh;
    let n_old = input.points.len();
    // Old points and their data are unchanged (bit for bit).
    assert_eq!(&m.points[..n_old], &input.points[..]);
    for a in &input.point_data.arrays {
        let b = m.point_data.get(&a.name).expect("point array kept");
        assert_eq!(b.data.scalar_type(), a.data.scalar_type());
        assert_eq!(b.components, a.components);
        let c = a.components;
        let head = b.data.gather(c, &(0..n_old).collect::<Vec<_>>());
        assert!(
            head.bit_eq(&a.data),
            "point array {} changed at old points",
            a.name
        );
        assert_eq!(b.tuples(), m.points.len());
    }
    // Linear fields are interpolated exactly (up to rounding).
    if let (Some(l), Some(f)) = (m.point_data.get("lin"), lin_fn) {
        let v = l.data.to_f64_vec();
        for (i, p) in m.points.iter().enumerate().skip(n_old) {
            let expect = f(p);
            assert!(
                (v[i] - expect).abs() <= 1e-12f64.max(geo_tol) * expect.abs().max(1.0),
                "lin at new point {i}: {} vs {expect}",
                v[i]
            );
        }
    }
    // No duplicate points made.
    let mut seen = HashSet::new();
    let dup_in = input.points.len()
        - input
            .points
            .iter()
            .map(|p| p.map(f64::to_bits))
            .collect::<HashSet<_>>()
            .len();
    let mut dups = 0;
    for p in &m.points {
        if !seen.insert(p.map(f64::to_bits)) {
            dups += 1;
        }
    }
    if dup_in == 0 {
        assert_eq!(dups, 0, "duplicate points in the output");
    }
    // Arrays.
    let leaf = int_array(m, LEAF_ID);
    let orig = int_array(m, ORIGINAL_CELL_ID);
    assert_eq!(leaf.len(), m.tets.len());
    assert_eq!(orig.len(), m.tets.len());
    for a in &input.cell_data.arrays {
        let b = m.cell_data.get(&a.name).expect("cell array kept");
        let idx: Vec<usize> = orig.iter().map(|&o| o as usize).collect();
        assert!(
            b.data.bit_eq(&a.data.gather(a.components, &idx)),
            "cell array {} not copied",
            a.name
        );
    }
    // Every sub-tet positive and inside its leaf box (exact comparisons); leaves grouped in order.
    let leaf_nodes = out.tree.leaf_nodes();
    assert_eq!(out.tree.num_leaves(), out.report.leaves);
    let mut last = 0;
    for (t, q) in m.tets.iter().enumerate() {
        let p = q.map(|v| m.points[v as usize]);
        let o = orig[t] as usize;
        let src = input.tets[o].map(|v| input.points[v as usize]);
        if volume_sign(&src) != 0.0 {
            assert!(volume_sign(&p) > 0.0, "sub-tet {t} {q:?} is not positive");
        }
        let l = leaf[t];
        assert!(l >= last, "tets not grouped by leaf");
        last = l;
        let b = out.tree.nodes[leaf_nodes[l as usize] as usize].bounds;
        for x in &p {
            assert!(
                b.contains(x),
                "sub-tet {t} vertex {x:?} outside leaf {l} box {b:?}"
            );
        }
    }
    // Tree counts match.
    for (l, &node) in leaf_nodes.iter().enumerate() {
        let c = leaf.iter().filter(|&&x| x == l as i64).count() as u64;
        assert_eq!(out.tree.nodes[node as usize].tet_count, c);
    }
    assert_eq!(out.tree.nodes[0].tet_count as usize, m.tets.len());
    // Volumes add up per original tet.
    let mut sums = vec![0.0f64; input.tets.len()];
    for (t, q) in m.tets.iter().enumerate() {
        let p = q.map(|v| m.points[v as usize]);
        sums[orig[t] as usize] += tet_volume(&p[0], &p[1], &p[2], &p[3]);
    }
    for (o, q) in input.tets.iter().enumerate() {
        let p = q.map(|v| input.points[v as usize]);
        let v = tet_volume(&p[0], &p[1], &p[2], &p[3]).abs();
        assert!(
            (sums[o] - v).abs() <= vol_tol * v,
            "original tet {o}: pieces {} vs {v} (rel {})",
            sums[o],
            (sums[o] - v).abs() / v
        );
    }
    if !conforming_input {
        return;
    }
    // Conforming: no face in more than two tets; faces in one tet lie on the input's boundary.
    let fin = face_counts(&input.tets);
    let boundary_in: Vec<[u32; 3]> = fin.iter().filter(|x| *x.1 == 1).map(|x| *x.0).collect();
    let mut by_tet: HashMap<usize, Vec<[u32; 3]>> = HashMap::new();
    for (o, q) in input.tets.iter().enumerate() {
        for f in faces(q) {
            if fin[&f] == 1 {
                by_tet.entry(o).or_default().push(f);
            }
        }
    }
    let fout = face_counts(&m.tets);
    assert!(
        fout.values().all(|&c| c <= 2),
        "a face shared by more than two tets"
    );
    let mut area_out = 0.0;
    for (t, q) in m.tets.iter().enumerate() {
        for f in faces(q) {
            if fout[&f] != 1 {
                continue;
            }
            let p = f.map(|v| m.points[v as usize]);
            area_out += area(&p);
            let cands = by_tet
                .get(&(orig[t] as usize))
                .map(Vec::as_slice)
                .unwrap_or(&[]);
            let on = cands.iter().any(|g| {
                let a = g.map(|v| input.points[v as usize]);
                p.iter().all(|x| {
                    orient3d(&a[0], &a[1], &a[2], x) == 0.0
                        || plane_distance(&a[0], &a[1], &a[2], x) <= geo_tol
                })
            });
            assert!(
                on,
                "boundary face {f:?} of sub-tet {t} is not on the input's boundary"
            );
        }
    }
    let area_in: f64 = boundary_in
        .iter()
        .map(|f| area(&f.map(|v| input.points[v as usize])))
        .sum();
    assert!(
        (area_out - area_in).abs() <= 1e-9 * area_in,
        "boundary area {area_out} vs {area_in}"
    );
}

fn area(p: &[[f64; 3]; 3]) -> f64 {
    let u = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
    let v = [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]];
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
}
