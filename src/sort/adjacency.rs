//! View-independent face adjacency of a tet mesh: the neighbour across each face and which side
//! of the face (by its sorted vertex ids) each tet lies on, built once in parallel.

use rayon::prelude::*;

use crate::geom::orient3d;

/// No neighbour across this face (mesh boundary).
pub const NONE: u32 = u32::MAX;

/// Face `i` of a tet is the one opposite its vertex `i`.
pub fn face_vertices(tet: &[u32; 4], i: usize) -> [u32; 3] {
    let mut f = [0u32; 3];
    let mut k = 0;
    for (j, &v) in tet.iter().enumerate() {
        if j != i {
            f[k] = v;
            k += 1;
        }
    }
    f
}

/// Face `i`'s vertex ids sorted ascending: the canonical triple both neighbours evaluate
/// predicates on, so they get bit-identical (hence exactly opposite) answers.
pub fn sorted_face(tet: &[u32; 4], i: usize) -> [u32; 3] {
    let mut f = face_vertices(tet, i);
    if f[0] > f[1] {
        f.swap(0, 1);
    }
    if f[1] > f[2] {
        f.swap(1, 2);
    }
    if f[0] > f[1] {
        f.swap(0, 1);
    }
    f
}

#[derive(Clone, Debug, Default)]
pub struct Adjacency {
    /// Neighbour across face `i` (opposite vertex `i`), or [`NONE`].
    pub neighbors: Vec<[u32; 4]>,
    /// Bit `i` set when the tet lies on the positive `orient3d` side of its sorted face `i`
    /// (that is, `orient3d(sorted face, own opposite vertex) > 0`). Made consistent across every
    /// shared face: the two tets always get opposite bits, even for flat or inverted tets, so the
    /// per-view "who is in front" is one decision per face.
    pub positive_side: Vec<u8>,
    /// Faces shared by more than two tets (a non-manifold input: duplicated or overlapping
    /// tets). Their tets on one side are paired with those on the other in id order; the rest
    /// get no neighbour.
    pub nonmanifold_faces: usize,
    /// Tets with zero volume (all four points coplanar).
    pub flat_tets: usize,
}

impl Adjacency {
    /// Builds adjacency by sorting all `4n` face keys in parallel.
    pub fn build(points: &[[f64; 3]], tets: &[[u32; 4]]) -> Adjacency {
        let n = tets.len();
        let mut keys: Vec<(u32, u32, u32, u32)> = (0..n)
            .into_par_iter()
            .flat_map_iter(|t| {
                let tet = &tets[t];
                (0..4).map(move |i| {
                    let f = sorted_face(tet, i);
                    (f[0], f[1], f[2], (t as u32) << 2 | i as u32)
                })
            })
            .collect();
        keys.par_sort_unstable();
        // Per tet, bit `i` of the first mask: on the positive `orient3d` side of its sorted face
        // `i`; of the second: on the negative side (neither: a flat tet's face). One exact test
        // per face and tet serves the face matching below and the sides kept.
        let sides: Vec<(u8, u8)> = (0..n)
            .into_par_iter()
            .map(|t| {
                let tet = &tets[t];
                let (mut pos, mut neg) = (0u8, 0u8);
                for i in 0..4 {
                    let f = sorted_face(tet, i);
                    let s = orient3d(
                        &points[f[0] as usize],
                        &points[f[1] as usize],
                        &points[f[2] as usize],
                        &points[tet[i] as usize],
                    );
                    pos |= ((s > 0.0) as u8) << i;
                    neg |= ((s < 0.0) as u8) << i;
                }
                (pos, neg)
            })
            .collect();
        // The sign (1, -1, 0) of a face key's tet on its side of the face.
        let side = |key: u32| {
            let (t, i) = ((key >> 2) as usize, key & 3);
            let (pos, neg) = sides[t];
            (pos >> i & 1) as i8 - (neg >> i & 1) as i8
        };
        let mut neighbors = vec![[NONE; 4]; n];
        let mut nonmanifold = 0usize;
        let mut k = 0;
        while k < keys.len() {
            let mut e = k + 1;
            while e < keys.len()
                && (keys[e].0, keys[e].1, keys[e].2) == (keys[k].0, keys[k].1, keys[k].2)
            {
                e += 1;
            }
            if e - k > 2 {
                nonmanifold += 1;
            }
            if e - k >= 2 {
                // Two tets strictly on the same side of a face overlap (the same tet twice, or a
                // boundary face of a mesh appended to itself): neither is in front of the other
                // across it, so the face stays boundary to both; a flat tet (sign 0) still pairs.
                // More than two tets on a face (duplicated or overlapping tets): left as
                // boundary faces they made every such face a non-convex leaf's boundary, whose
                // pairwise screen constraints grow with the square of the tets (a doubled grid
                // of 17k tets sorted in 35 s). So the tets on one side are paired with those on
                // the other in id order: a doubled mesh becomes two copies each joined as the original was.
                let mut join = |a: u32, b: u32| {
                    neighbors[(a >> 2) as usize][(a & 3) as usize] = b >> 2;
                    neighbors[(b >> 2) as usize][(b & 3) as usize] = a >> 2;
                };
                let group = &keys[k..e];
                if e - k == 2 {
                    let (a, b) = (group[0].3, group[1].3);
                    if side(a) != side(b) || side(a) == 0 {
                        join(a, b);
                    }
                } else {
                    let of = |sign: i8| group.iter().map(|g| g.3).filter(move |&g| side(g) == sign);
                    for (a, b) in of(1).zip(of(-1)) {
                        join(a, b);
                    }
                }
            }
            k = e;
        }
        drop(keys);
        let flat_tets = sides.iter().filter(|s| s.0 | s.1 == 0).count();
        let mut positive_side: Vec<u8> = sides.into_iter().map(|s| s.0).collect();
        // Two tets on the same side of their shared face (an inverted or flat tet): let the lower
        // id decide, so the face still gives one consistent constraint.
        for t in 0..n {
            for i in 0..4 {
                let m = neighbors[t][i];
                if m == NONE || (m as usize) < t {
                    continue;
                }
                let m = m as usize;
                let Some(j) = (0..4).find(|&j| neighbors[m][j] == t as u32) else {
                    continue;
                };
                let mine = positive_side[t] >> i & 1;
                let theirs = positive_side[m] >> j & 1;
                if mine == theirs {
                    positive_side[m] ^= 1 << j;
                }
            }
        }
        Adjacency {
            neighbors,
            positive_side,
            nonmanifold_faces: nonmanifold,
            flat_tets,
        }
    }

    /// Number of faces with a neighbour (each counted once).
    pub fn shared_faces(&self) -> usize {
        self.neighbors
            .iter()
            .map(|n| n.iter().filter(|&&m| m != NONE).count())
            .sum::<usize>()
            / 2
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::structured_grid;

    #[test]
    fn grid_adjacency_is_symmetric_with_opposite_sides() {
        let m = structured_grid([3, 2, 2], [0.0; 3], [1.0; 3]);
        let a = Adjacency::build(&m.points, &m.tets);
        let mut boundary = 0;
        for t in 0..m.tets.len() {
            for i in 0..4 {
                let n = a.neighbors[t][i];
                if n == NONE {
                    boundary += 1;
                    continue;
                }
                let j = (0..4)
                    .find(|&j| a.neighbors[n as usize][j] == t as u32)
                    .unwrap();
                assert_eq!(
                    sorted_face(&m.tets[t], i),
                    sorted_face(&m.tets[n as usize], j)
                );
                assert_ne!(
                    a.positive_side[t] >> i & 1,
                    a.positive_side[n as usize] >> j & 1
                );
            }
        }
        // 2 * (3*2 + 3*2 + 2*2) squares, two triangles each
        assert_eq!(boundary, 2 * 2 * (6 + 6 + 4));
        assert_eq!(a.flat_tets, 0);
    }
}
