//! 20-node hexahedra completed to 27 nodes (face and body centres from the serendipity shape
//! functions), so that they split as triquadratic hexahedra do.

use super::cells::TQHEX_LATTICE;
use formats::grid::Element;
use formats::{cell_type as ct, ArrayData, Attributes, Cells, Grid};

/// Weights of the 20 nodes of VTK's quadratic hexahedron at node `k` (20..27) of the
/// triquadratic one: its shape functions evaluated there. At a face centre the face's corners
/// weigh -1/4 and its edge nodes 1/2; at the body centre every corner -1/4 and every edge node
/// 1/4. On a straight-sided cell these are the face and cell centroids.
fn weights(k: usize) -> [f64; 20] {
    let l = TQHEX_LATTICE[k];
    let fixed: Vec<usize> = (0..3).filter(|&a| l[a] != 1).collect();
    let mut w = [0.0; 20];
    for (n, slot) in w.iter_mut().enumerate() {
        let m = TQHEX_LATTICE[n];
        if !fixed.iter().all(|&a| m[a] == l[a]) {
            continue;
        }
        let corner = m.iter().all(|&x| x != 1);
        *slot = match (fixed.len(), corner) {
            (_, true) => -0.25,
            (0, false) => 0.25,
            _ => 0.5,
        };
    }
    w
}

/// `grid` with every 20-node hexahedron made a 27-node one (a new point per face, shared by the
/// cells that share the face, and one per body, appended after the existing points in cell
/// order), and how many there were; `None` when there are
/// none. New points' float point data take the same weighted sum as their coordinates; integer
/// and string arrays (labels, ids) the tuple of the smallest-id corner the point depends on, as
/// tetrahedralization's centre points do.
pub fn complete_hex20(grid: &Grid) -> Option<(Grid, usize)> {
    let count = grid
        .cells
        .types
        .iter()
        .filter(|&&t| t == ct::QUADRATIC_HEXAHEDRON)
        .count();
    if count == 0 {
        return None;
    }
    let w: Vec<[f64; 20]> = (20..27).map(weights).collect();
    let np = grid.num_points() as i64;
    // Each new point: its weights over the cell's 20 ids.
    let mut new: Vec<([i64; 20], usize)> = Vec::with_capacity(count * 7);
    let mut faces: std::collections::HashMap<Vec<i64>, i64> = std::collections::HashMap::new();
    let mut cells = Cells::new();
    cells.types.reserve(grid.num_cells());
    for c in 0..grid.num_cells() {
        let t = grid.cells.types[c];
        let ids = grid.cells.cell(c);
        if t != ct::QUADRATIC_HEXAHEDRON {
            cells.push(t, ids);
            continue;
        }
        let mut full: Vec<i64> = ids.to_vec();
        let mut twenty = [0i64; 20];
        twenty.copy_from_slice(&ids[..20]);
        for (k, wk) in w.iter().enumerate() {
            // A face centre depends on that face's 8 nodes only: cells sharing the face share
            // the point, so the split stays conforming across it.
            let mut key: Vec<i64> = twenty
                .iter()
                .zip(wk)
                .filter(|(_, &x)| x != 0.0)
                .map(|(&p, _)| p)
                .collect();
            key.sort_unstable();
            let id = if key.len() == 8 {
                *faces.entry(key).or_insert_with(|| {
                    new.push((twenty, k));
                    np + new.len() as i64 - 1
                })
            } else {
                new.push((twenty, k));
                np + new.len() as i64 - 1
            };
            full.push(id);
        }
        cells.push(ct::TRIQUADRATIC_HEXAHEDRON, &full);
    }
    cells.polyhedron_faces = grid.cells.polyhedron_faces.clone();
    let mut out = grid.clone();
    out.cells = cells;
    append(&mut out.points.data, 3, &new, &w);
    append_point_data(&mut out.point_data, &new, &w);
    Some((out, count))
}

fn append(data: &mut ArrayData, c: usize, new: &[([i64; 20], usize)], w: &[[f64; 20]]) {
    fn sum<T: Element>(v: &mut Vec<T>, c: usize, new: &[([i64; 20], usize)], w: &[[f64; 20]]) {
        v.reserve(new.len() * c);
        for (ids, k) in new {
            for comp in 0..c {
                let s: f64 = ids
                    .iter()
                    .zip(&w[*k])
                    .filter(|(_, &x)| x != 0.0)
                    .map(|(&p, &x)| x * v[p as usize * c + comp].to_f64())
                    .sum();
                v.push(T::from_f64(s));
            }
        }
    }
    fn first<T: Clone>(v: &mut Vec<T>, c: usize, new: &[([i64; 20], usize)], w: &[[f64; 20]]) {
        for (ids, k) in new {
            // The smallest-id corner among the nodes the point depends on.
            let p = ids
                .iter()
                .zip(&w[*k])
                .filter(|(_, &x)| x < 0.0)
                .map(|(&p, _)| p)
                .min()
                .unwrap_or(ids[0]) as usize;
            for comp in 0..c {
                let x = v[p * c + comp].clone();
                v.push(x);
            }
        }
    }
    match data {
        ArrayData::Float32(v) => sum(v, c, new, w),
        ArrayData::Float64(v) => sum(v, c, new, w),
        ArrayData::Int8(v) => first(v, c, new, w),
        ArrayData::UInt8(v) => first(v, c, new, w),
        ArrayData::Int16(v) => first(v, c, new, w),
        ArrayData::UInt16(v) => first(v, c, new, w),
        ArrayData::Int32(v) => first(v, c, new, w),
        ArrayData::UInt32(v) => first(v, c, new, w),
        ArrayData::Int64(v) => first(v, c, new, w),
        ArrayData::UInt64(v) => first(v, c, new, w),
        ArrayData::String(v) => first(v, c, new, w),
    }
}

fn append_point_data(pd: &mut Attributes, new: &[([i64; 20], usize)], w: &[[f64; 20]]) {
    for a in &mut pd.arrays {
        append(&mut a.data, a.components, new, w);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use formats::DataArray;

    #[test]
    fn weights_sum_to_one_and_give_centroids_of_a_straight_cell() {
        for k in 20..27 {
            let s: f64 = weights(k).iter().sum();
            assert!((s - 1.0).abs() < 1e-15, "node {k}: {s}");
        }
        // A 2 x 3 x 4 box with straight edges: the new nodes are at the lattice points.
        let corner = |n: usize| TQHEX_LATTICE[n].map(|x| x as f64);
        let mut pts = Vec::new();
        for n in 0..20 {
            let p = corner(n);
            pts.extend_from_slice(&[p[0], 1.5 * p[1], 2.0 * p[2]]);
        }
        let ids: Vec<i64> = (0..20).collect();
        let mut g = Grid {
            points: DataArray::new("Points", 3, ArrayData::Float64(pts.clone())),
            ..Grid::default()
        };
        g.cells.push(ct::QUADRATIC_HEXAHEDRON, &ids);
        // A linear field and an integer label.
        let f: Vec<f64> = pts.chunks(3).map(|p| p[0] + 2.0 * p[1] - p[2]).collect();
        g.point_data
            .insert(DataArray::new("f", 1, ArrayData::Float64(f)));
        g.point_data.insert(DataArray::new(
            "label",
            1,
            ArrayData::Int32((0..20).rev().collect()),
        ));
        let (c, n) = complete_hex20(&g).unwrap();
        assert_eq!(n, 1);
        assert_eq!(c.cells.types, vec![ct::TRIQUADRATIC_HEXAHEDRON]);
        assert_eq!(c.cells.cell(0), &(0..27).collect::<Vec<i64>>()[..]);
        let p = c.points_f64();
        let fd = c.point_data.get("f").unwrap().data.to_f64_vec();
        for k in 20..27 {
            let want = corner(k);
            let want = [want[0], 1.5 * want[1], 2.0 * want[2]];
            for a in 0..3 {
                assert!((p[k][a] - want[a]).abs() < 1e-12, "node {k}: {:?}", p[k]);
            }
            let fv = want[0] + 2.0 * want[1] - want[2];
            assert!((fd[k] - fv).abs() < 1e-12, "node {k}: f {}", fd[k]);
        }
        // Labels come from the smallest-id corner the point depends on (corner 0 everywhere
        // except the faces away from it).
        let ArrayData::Int32(l) = &c.point_data.get("label").unwrap().data else {
            panic!("label type");
        };
        assert_eq!(l[26], 19);
        assert!(complete_hex20(&Grid::default()).is_none());
    }

    #[test]
    fn cells_sharing_a_face_share_its_centre() {
        // Two straight 1 x 1 x 1 hex20s side by side along x, sharing the face x = 1.
        let corner = |n: usize| TQHEX_LATTICE[n].map(|x| 0.5 * x as f64);
        let mut pts: Vec<[f64; 3]> = (0..20).map(corner).collect();
        let mut second = Vec::new();
        for n in 0..20 {
            let p = corner(n);
            let q = [p[0] + 1.0, p[1], p[2]];
            match pts.iter().position(|x| *x == q) {
                Some(i) => second.push(i as i64),
                None => {
                    pts.push(q);
                    second.push(pts.len() as i64 - 1);
                }
            }
        }
        let mut g = Grid {
            points: DataArray::new(
                "Points",
                3,
                ArrayData::Float64(pts.iter().flatten().copied().collect()),
            ),
            ..Grid::default()
        };
        g.cells
            .push(ct::QUADRATIC_HEXAHEDRON, &(0..20).collect::<Vec<i64>>());
        g.cells.push(ct::QUADRATIC_HEXAHEDRON, &second);
        let np = g.num_points();
        let (c, _) = complete_hex20(&g).unwrap();
        // 7 + 7 new points, less the shared face centre.
        assert_eq!(c.num_points(), np + 13);
        let a: std::collections::HashSet<i64> = c.cells.cell(0)[20..].iter().copied().collect();
        let b: std::collections::HashSet<i64> = c.cells.cell(1)[20..].iter().copied().collect();
        assert_eq!(a.intersection(&b).count(), 1);
    }
}
