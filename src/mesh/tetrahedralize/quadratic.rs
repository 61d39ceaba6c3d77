//! Quadratic cells completed with the nodes a linear split needs, placed by their own shape
//! functions: 20-node hexahedra gain face and body centres, 15-node wedges quad-face centres,
//! 13-node pyramids their base centre.

use super::cells::TQHEX_LATTICE;
use formats::grid::Element;
use formats::{cell_type as ct, ArrayData, Attributes, Cells, Grid};
use std::collections::HashMap;

/// A node added to a cell: a weighted sum of the cell's nodes, as `(local index, weight)`.
/// `face` marks a quad face's centre, which depends on that face's 8 nodes only and is shared by
/// the cells on the face.
struct Added {
    terms: Vec<(usize, f64)>,
    face: bool,
}

/// Centre of a quad face given by its corners and edge nodes (each edge node between two
/// consecutive corners): the 8-node quadrangle's shape functions there, corners -1/4 and edge
/// nodes 1/2. The 20-node hexahedron's, 15-node wedge's and 13-node pyramid's shape functions
/// restrict to these on a quad face (checked against VTK's `InterpolateFunctions`), so every
/// cell type puts a shared face's centre at the same place; on a flat face it is the centroid.
fn face_centre(corners: [usize; 4], edges: [usize; 4]) -> Added {
    let mut terms: Vec<(usize, f64)> = corners.iter().map(|&c| (c, -0.25)).collect();
    terms.extend(edges.iter().map(|&e| (e, 0.5)));
    Added { terms, face: true }
}

/// Node `k` (20..27) of the triquadratic hexahedron from the 20 nodes of the quadratic one: its
/// shape functions evaluated there. At a face centre see [`face_centre`]; at the body centre
/// every corner weighs -1/4 and every edge node 1/4 (the centroid of a straight cell).
fn hex_node(k: usize) -> Added {
    let l = TQHEX_LATTICE[k];
    let fixed: Vec<usize> = (0..3).filter(|&a| l[a] != 1).collect();
    let mut terms = Vec::new();
    for (n, m) in TQHEX_LATTICE.iter().enumerate().take(20) {
        if !fixed.iter().all(|&a| m[a] == l[a]) {
            continue;
        }
        let corner = m.iter().all(|&x| x != 1);
        let w = match (fixed.len(), corner) {
            (_, true) => -0.25,
            (0, false) => 0.25,
            _ => 0.5,
        };
        terms.push((n, w));
    }
    Added {
        terms,
        face: fixed.len() == 1,
    }
}

/// The quadratic wedge's quad faces `(corners, edge nodes)` in VTK's order, which is also the
/// order of the 18-node wedge's face centres 15, 16, 17 (corners 0-5; edges 6:01 7:12 8:20 9:34
/// 10:45 11:53 12:03 13:14 14:25).
const WEDGE_QUADS: [([usize; 4], [usize; 4]); 3] = [
    ([0, 1, 4, 3], [6, 13, 9, 12]),
    ([1, 2, 5, 4], [7, 14, 10, 13]),
    ([2, 0, 3, 5], [8, 12, 11, 14]),
];

/// The nodes a cell of type `t` lacks, in the order they are appended to it: the 27-node
/// hexahedron's 20..27, the 18-node wedge's 15..18, and the pyramid's base centre as node 13
/// (VTK has no 14-node pyramid; see `cells::sub_cells`). Empty for other types.
fn added_nodes(t: u8) -> Vec<Added> {
    match t {
        ct::QUADRATIC_HEXAHEDRON => (20..27).map(hex_node).collect(),
        ct::QUADRATIC_WEDGE => WEDGE_QUADS
            .iter()
            .map(|&(c, e)| face_centre(c, e))
            .collect(),
        // Base edges 5:01 6:12 7:23 8:30.
        ct::QUADRATIC_PYRAMID => vec![face_centre([0, 1, 2, 3], [5, 6, 7, 8])],
        _ => Vec::new(),
    }
}

/// The types that have face-centre nodes of their own, with the type whose added nodes name
/// them: a 27-node hexahedron's node `20 + j` is the 20-node one's added node `j`, an 18-node
/// wedge's `15 + j` the 15-node one's.
const COMPLETE: [(u8, u8, usize); 2] = [
    (ct::TRIQUADRATIC_HEXAHEDRON, ct::QUADRATIC_HEXAHEDRON, 20),
    (ct::BIQUADRATIC_QUADRATIC_WEDGE, ct::QUADRATIC_WEDGE, 15),
];

/// New points as weighted sums of existing ones: point `k`'s terms are
/// `terms[ends[k - 1]..ends[k]]`, sorted by point id.
#[derive(Default)]
struct NewPoints {
    terms: Vec<(i64, f64)>,
    ends: Vec<usize>,
}

impl NewPoints {
    fn iter(&self) -> impl Iterator<Item = &[(i64, f64)]> {
        let starts = std::iter::once(0).chain(self.ends.iter().copied());
        starts.zip(&self.ends).map(|(s, &e)| &self.terms[s..e])
    }
}

/// `grid` with the nodes of [`added_nodes`] appended to every 20-node hexahedron, 15-node wedge
/// and 13-node pyramid (which keep their type: the result is only for splitting), the new
/// points appended after the existing ones in cell order; `None` when there are no such cells.
///
/// A face centre is one point for all the cells on that face, keyed by the face's 8 sorted ids,
/// so the split stays conforming: a wedge and a hexahedron sharing a quad face get the same
/// point, and a face that already has a centre node (in a 27-node hexahedron or 18-node wedge
/// beside it) uses that node. New points' float point data take the same weighted sum as their
/// coordinates (summed in point-id order, so the point is the same whichever cell makes it);
/// integer and string arrays (labels, ids) the tuple of the smallest-id corner the point depends
/// on, as tetrahedralization's centre points do.
pub fn complete(grid: &Grid) -> Option<Grid> {
    let types = &grid.cells.types;
    let incomplete = |t: u8| {
        matches!(
            t,
            ct::QUADRATIC_HEXAHEDRON | ct::QUADRATIC_WEDGE | ct::QUADRATIC_PYRAMID
        )
    };
    if !types.iter().any(|&t| incomplete(t)) {
        return None;
    }
    let added: Vec<Vec<Added>> = (0..=255u8).map(added_nodes).collect();
    let face_key = |ids: &[i64], a: &Added| -> Vec<i64> {
        let mut key: Vec<i64> = a.terms.iter().map(|&(l, _)| ids[l]).collect();
        key.sort_unstable();
        key
    };
    let mut faces: HashMap<Vec<i64>, i64> = HashMap::new();
    for (c, &t) in types.iter().enumerate() {
        if let Some(&(_, from, first)) = COMPLETE.iter().find(|x| x.0 == t) {
            let ids = grid.cells.cell(c);
            for (j, a) in added[from as usize].iter().enumerate() {
                if a.face {
                    faces.entry(face_key(ids, a)).or_insert(ids[first + j]);
                }
            }
        }
    }
    let np = grid.num_points() as i64;
    let mut new = NewPoints::default();
    let mut cells = Cells::new();
    cells.types.reserve(grid.num_cells());
    for (c, &t) in types.iter().enumerate() {
        let ids = grid.cells.cell(c);
        let mut full: Vec<i64> = ids.to_vec();
        for a in &added[t as usize] {
            let mut make = || {
                let start = new.terms.len();
                new.terms.extend(a.terms.iter().map(|&(l, w)| (ids[l], w)));
                new.terms[start..].sort_by_key(|&(p, _)| p);
                new.ends.push(new.terms.len());
                np + new.ends.len() as i64 - 1
            };
            let id = if a.face {
                *faces.entry(face_key(ids, a)).or_insert_with(make)
            } else {
                make()
            };
            full.push(id);
        }
        cells.push(t, &full);
    }
    cells.polyhedron_faces = grid.cells.polyhedron_faces.clone();
    // Field by field: cloning the whole grid would copy its cells only to drop them.
    let mut out = Grid {
        points: grid.points.clone(),
        cells,
        point_data: grid.point_data.clone(),
        cell_data: grid.cell_data.clone(),
        field_data: grid.field_data.clone(),
    };
    append(&mut out.points.data, 3, &new);
    append_point_data(&mut out.point_data, &new);
    Some(out)
}

fn append(data: &mut ArrayData, c: usize, new: &NewPoints) {
    fn sum<T: Element>(v: &mut Vec<T>, c: usize, new: &NewPoints) {
        v.reserve(new.ends.len() * c);
        for terms in new.iter() {
            for comp in 0..c {
                let s: f64 = terms
                    .iter()
                    .map(|&(p, w)| w * v[p as usize * c + comp].to_f64())
                    .sum();
                v.push(T::from_f64(s));
            }
        }
    }
    fn first<T: Clone>(v: &mut Vec<T>, c: usize, new: &NewPoints) {
        for terms in new.iter() {
            // The smallest-id corner (corners are the negative weights) the point depends on.
            let p = terms
                .iter()
                .filter(|&&(_, w)| w < 0.0)
                .map(|&(p, _)| p)
                .min()
                .unwrap_or(terms[0].0) as usize;
            for comp in 0..c {
                let x = v[p * c + comp].clone();
                v.push(x);
            }
        }
    }
    match data {
        ArrayData::Float32(v) => sum(v, c, new),
        ArrayData::Float64(v) => sum(v, c, new),
        ArrayData::Int8(v) => first(v, c, new),
        ArrayData::UInt8(v) => first(v, c, new),
        ArrayData::Int16(v) => first(v, c, new),
        ArrayData::UInt16(v) => first(v, c, new),
        ArrayData::Int32(v) => first(v, c, new),
        ArrayData::UInt32(v) => first(v, c, new),
        ArrayData::Int64(v) => first(v, c, new),
        ArrayData::UInt64(v) => first(v, c, new),
        ArrayData::String(v) => first(v, c, new),
    }
}

fn append_point_data(pd: &mut Attributes, new: &NewPoints) {
    for a in &mut pd.arrays {
        append(&mut a.data, a.components, new);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use formats::DataArray;

    /// VTK's edges of each type, as corner pairs, in the order of its mid-edge nodes.
    fn edges(t: u8) -> &'static [[usize; 2]] {
        match t {
            ct::QUADRATIC_HEXAHEDRON => &[
                [0, 1],
                [1, 2],
                [2, 3],
                [3, 0],
                [4, 5],
                [5, 6],
                [6, 7],
                [7, 4],
                [0, 4],
                [1, 5],
                [2, 6],
                [3, 7],
            ],
            ct::QUADRATIC_WEDGE => &[
                [0, 1],
                [1, 2],
                [2, 0],
                [3, 4],
                [4, 5],
                [5, 3],
                [0, 3],
                [1, 4],
                [2, 5],
            ],
            _ => &[
                [0, 1],
                [1, 2],
                [2, 3],
                [3, 0],
                [0, 4],
                [1, 4],
                [2, 4],
                [3, 4],
            ],
        }
    }

    /// A straight-sided cell of type `t` on `corners`: mid-edge nodes at the edges' midpoints.
    fn straight(t: u8, corners: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let mut p = corners.to_vec();
        for &[a, b] in edges(t) {
            p.push([0, 1, 2].map(|k| 0.5 * (corners[a][k] + corners[b][k])));
        }
        p
    }

    /// A grid of `cells`, given by their nodes' coordinates; equal coordinates are one point.
    fn grid(cells: &[(u8, Vec<[f64; 3]>)]) -> Grid {
        let mut pts: Vec<[f64; 3]> = Vec::new();
        let mut g = Grid::default();
        for (t, nodes) in cells {
            let ids: Vec<i64> = nodes
                .iter()
                .map(|q| {
                    let i = pts.iter().position(|x| x == q).unwrap_or_else(|| {
                        pts.push(*q);
                        pts.len() - 1
                    });
                    i as i64
                })
                .collect();
            g.cells.push(*t, &ids);
        }
        g.points = DataArray::new(
            "Points",
            3,
            ArrayData::Float64(pts.iter().flatten().copied().collect()),
        );
        g
    }

    const HEX: [[f64; 3]; 8] = [
        [0., 0., 0.],
        [1., 0., 0.],
        [1., 1., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
        [1., 0., 1.],
        [1., 1., 1.],
        [0., 1., 1.],
    ];
    const WEDGE: [[f64; 3]; 6] = [
        [0., 0., 0.],
        [1., 0., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
        [1., 0., 1.],
        [0., 1., 1.],
    ];
    const PYRAMID: [[f64; 3]; 5] = [
        [0., 0., 0.],
        [1., 0., 0.],
        [1., 1., 0.],
        [0., 1., 0.],
        [0.3, 0.4, 1.],
    ];

    /// An affine map, so that nothing lines up with the axes by luck.
    fn skew(p: [f64; 3]) -> [f64; 3] {
        [
            2.0 * p[0] + 0.5 * p[1] + 1.0,
            1.5 * p[1] - 0.25 * p[2] - 2.0,
            3.0 * p[2] + 0.125 * p[0] + 0.5,
        ]
    }

    #[test]
    fn weights_sum_to_one_and_give_centroids_of_a_straight_cell() {
        for (t, corners) in [
            (ct::QUADRATIC_HEXAHEDRON, &HEX[..]),
            (ct::QUADRATIC_WEDGE, &WEDGE[..]),
            (ct::QUADRATIC_PYRAMID, &PYRAMID[..]),
        ] {
            let added = added_nodes(t);
            for a in &added {
                let s: f64 = a.terms.iter().map(|&(_, w)| w).sum();
                assert!((s - 1.0).abs() < 1e-15, "type {t}: {s}");
            }
            let corners: Vec<[f64; 3]> = corners.iter().map(|&p| skew(p)).collect();
            let nodes = straight(t, &corners);
            let mut g = grid(&[(t, nodes.clone())]);
            // A linear field and an integer label.
            let f: Vec<f64> = nodes.iter().map(|p| p[0] + 2.0 * p[1] - p[2]).collect();
            g.point_data
                .insert(DataArray::new("f", 1, ArrayData::Float64(f)));
            let n = nodes.len() as i32;
            g.point_data.insert(DataArray::new(
                "label",
                1,
                ArrayData::Int32((0..n).rev().collect()),
            ));
            let Some(c) = complete(&g) else {
                panic!("type {t}: nothing completed");
            };
            assert_eq!(c.cells.types, vec![t]);
            let ids = c.cells.cell(0);
            assert_eq!(ids.len(), nodes.len() + added.len());
            let p = c.points_f64();
            let (Some(f), Some(label)) = (c.point_data.get("f"), c.point_data.get("label")) else {
                panic!("type {t}: point data lost");
            };
            let fd = f.data.to_f64_vec();
            let ArrayData::Int32(label) = &label.data else {
                panic!("label type");
            };
            for (a, &id) in added.iter().zip(&ids[nodes.len()..]) {
                // The centroid of the corners the point depends on (a face's 4, the body's 8).
                let cs: Vec<usize> = a
                    .terms
                    .iter()
                    .filter(|&&(_, w)| w < 0.0)
                    .map(|&(l, _)| l)
                    .collect();
                let want = [0, 1, 2]
                    .map(|k| cs.iter().map(|&l| nodes[l][k]).sum::<f64>() / cs.len() as f64);
                let got = p[id as usize];
                for k in 0..3 {
                    assert!(
                        (got[k] - want[k]).abs() < 1e-12,
                        "type {t}: {got:?} {want:?}"
                    );
                }
                let fv = want[0] + 2.0 * want[1] - want[2];
                assert!(
                    (fd[id as usize] - fv).abs() < 1e-12,
                    "type {t}: f {}",
                    fd[id as usize]
                );
                // The label of the smallest-id corner (labels count down from n - 1).
                let min = cs.iter().copied().fold(usize::MAX, usize::min) as i32;
                assert_eq!(label[id as usize], n - 1 - min);
            }
        }
        assert!(complete(&Grid::default()).is_none());
    }

    /// The quad face x = 1 of the unit hexahedron is shared by a hexahedron on each side of it
    /// and by a wedge: each pair makes one centre point for it.
    #[test]
    fn cells_sharing_a_face_share_its_centre() {
        let hex = |dx: f64| -> Vec<[f64; 3]> {
            let c: Vec<[f64; 3]> = HEX.iter().map(|p| [p[0] + dx, p[1], p[2]]).collect();
            straight(ct::QUADRATIC_HEXAHEDRON, &c)
        };
        // A wedge whose face (0, 1, 4, 3) is x = 1.
        let wedge_corners = [
            [1., 0., 0.],
            [1., 1., 0.],
            [2., 0., 0.],
            [1., 0., 1.],
            [1., 1., 1.],
            [2., 0., 1.],
        ];
        let wedge = straight(ct::QUADRATIC_WEDGE, &wedge_corners);
        // A second wedge on the wedge's face (1, 2, 5, 4).
        let other = straight(
            ct::QUADRATIC_WEDGE,
            &[
                [2., 1., 0.],
                [2., 0., 0.],
                [1., 1., 0.],
                [2., 1., 1.],
                [2., 0., 1.],
                [1., 1., 1.],
            ],
        );
        let shared = |cells: &[(u8, Vec<[f64; 3]>)], added: usize| {
            let g = grid(cells);
            let Some(c) = complete(&g) else {
                panic!("nothing completed");
            };
            assert_eq!(c.num_points(), g.num_points() + added - 1);
            let new = |i: usize| -> std::collections::HashSet<i64> {
                c.cells.cell(i)[g.cells.cell(i).len()..]
                    .iter()
                    .copied()
                    .collect()
            };
            assert_eq!(new(0).intersection(&new(1)).count(), 1);
        };
        let hex20 = ct::QUADRATIC_HEXAHEDRON;
        let wedge15 = ct::QUADRATIC_WEDGE;
        shared(&[(hex20, hex(0.0)), (hex20, hex(1.0))], 14);
        shared(&[(hex20, hex(0.0)), (wedge15, wedge.clone())], 10);
        shared(&[(wedge15, wedge.clone()), (hex20, hex(0.0))], 10);
        shared(&[(wedge15, wedge.clone()), (wedge15, other)], 6);
        // A pyramid on the hexahedron's face z = 1 (its base, upside down).
        let pyramid = straight(
            ct::QUADRATIC_PYRAMID,
            &[
                [0., 0., 1.],
                [0., 1., 1.],
                [1., 1., 1.],
                [1., 0., 1.],
                [0.5, 0.5, 2.],
            ],
        );
        shared(
            &[(hex20, hex(0.0)), (ct::QUADRATIC_PYRAMID, pyramid.clone())],
            8,
        );

        // Beside an 18-node wedge, the 15-node one takes the existing face centre.
        let mut wedge18 = wedge.clone();
        for (c, _) in WEDGE_QUADS {
            wedge18
                .push([0, 1, 2].map(|k| c.iter().map(|&l| wedge_corners[l][k]).sum::<f64>() / 4.0));
        }
        let g = grid(&[
            (ct::BIQUADRATIC_QUADRATIC_WEDGE, wedge18),
            (hex20, hex(0.0)),
        ]);
        let Some(c) = complete(&g) else {
            panic!("nothing completed");
        };
        assert_eq!(c.num_points(), g.num_points() + 6);
        assert!(c.cells.cell(1)[20..].contains(&c.cells.cell(0)[15]));
    }
}
