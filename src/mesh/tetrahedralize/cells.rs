//! How one cell becomes tets: face tables, the smallest-vertex face rule, pulling from the
//! smallest vertex, the centre-point fallback, and the quadratic-tet and triquadratic-hex tables.
//!
//! The conformity argument: every polygonal face of every cell is triangulated the same way, as a
//! fan from its smallest global point id (for a quad: the diagonal through its smallest id). Two
//! cells sharing a face therefore agree on its triangles whatever else they do. A cell is then
//! filled by "pulling" from its smallest global vertex `v0`: one tet `(v0, t)` per face triangle
//! `t` not containing `v0`. Because every face through `v0` is fanned from `v0` (it is that face's
//! smallest id too), this cone covers the cell exactly when the cell is star-shaped from `v0`
//! (always for convex cells). This gives a hexahedron 6 tets, a wedge 3, a pyramid 2, an n-gonal
//! prism 3(n - 2), with no new point.
//!
//! Validity is checked exactly: every child's orientation is taken with Shewchuk's `orient3d`, and
//! all children must have the same non-zero sign (by the winding-number argument, same-signed
//! cones over a closed non-self-intersecting surface tile it without overlap). When the pulled
//! children fail that (a warped or non-convex cell), the cell is filled from a new centre point
//! (the mean of its vertices) instead, over the same face triangles, so conformity is kept; when the
//! mean does not see every face triangle from inside, the point deepest inside the cell's kernel (a
//! small linear program over the triangles' planes) is tried; if that fails too, the cell is not
//! star-shaped from any point and is reported as impossible to split.
//!
//! Cells written with repeated point ids (a hexahedron collapsed into a wedge or pyramid, as some
//! FEM codes write them) work too: fan triangles with a repeated id are dropped, which leaves
//! exactly the collapsed cell's faces.

use crate::geom::orient3d;

/// Faces of the linear cells, each with a consistent orientation (the same one for all faces of a
/// cell, so that the children of a positive cell are all positive).
pub const HEX_FACES: [&[usize]; 6] = [
    &[0, 3, 2, 1],
    &[4, 5, 6, 7],
    &[0, 1, 5, 4],
    &[1, 2, 6, 5],
    &[2, 3, 7, 6],
    &[3, 0, 4, 7],
];
pub const WEDGE_FACES: [&[usize]; 5] = [
    &[0, 1, 2],
    &[3, 5, 4],
    &[0, 3, 4, 1],
    &[1, 4, 5, 2],
    &[2, 5, 3, 0],
];
pub const PYRAMID_FACES: [&[usize]; 5] = [
    &[0, 3, 2, 1],
    &[0, 1, 4],
    &[1, 2, 4],
    &[2, 3, 4],
    &[3, 0, 4],
];

/// VTK voxel point order to hexahedron point order (voxels number their points like a raster).
pub const VOXEL_TO_HEX: [usize; 8] = [0, 1, 3, 2, 4, 5, 7, 6];

/// Faces of an n-gonal prism (bottom `0..n`, top `n..2n`), oriented like [`HEX_FACES`].
pub fn prism_faces(n: usize) -> Vec<Vec<usize>> {
    let mut f = Vec::with_capacity(n + 2);
    f.push((0..n).rev().collect());
    f.push((n..2 * n).collect());
    for i in 0..n {
        let j = (i + 1) % n;
        f.push(vec![i, j, n + j, n + i]);
    }
    f
}

/// The quadratic tetra's 8 children (VTK order: corners 0-3, then mid-edges 4:01 5:12 6:20 7:03
/// 8:13 9:23): four corner tets, and the inner octahedron cut along one of its three diagonals
/// `(p, q)`, the other four nodes listed around it so that `(p, q, r_i, r_i+1)` is positive for a
/// positive cell.
pub const QTET_CORNERS: [[usize; 4]; 4] = [[0, 4, 6, 7], [4, 1, 5, 8], [6, 5, 2, 9], [7, 8, 9, 3]];
pub const QTET_DIAGONALS: [([usize; 2], [usize; 4]); 3] = [
    ([4, 9], [6, 7, 8, 5]),
    ([5, 7], [4, 8, 9, 6]),
    ([6, 8], [4, 5, 9, 7]),
];

/// Lattice position (0..=2 per axis) of each node of VTK's triquadratic hexahedron (from
/// vtkTriQuadraticHexahedron's parametric coordinates times 2).
pub const TQHEX_LATTICE: [[u8; 3]; 27] = [
    [0, 0, 0],
    [2, 0, 0],
    [2, 2, 0],
    [0, 2, 0],
    [0, 0, 2],
    [2, 0, 2],
    [2, 2, 2],
    [0, 2, 2],
    [1, 0, 0],
    [2, 1, 0],
    [1, 2, 0],
    [0, 1, 0],
    [1, 0, 2],
    [2, 1, 2],
    [1, 2, 2],
    [0, 1, 2],
    [0, 0, 1],
    [2, 0, 1],
    [2, 2, 1],
    [0, 2, 1],
    [0, 1, 1],
    [2, 1, 1],
    [1, 0, 1],
    [1, 2, 1],
    [1, 1, 0],
    [1, 1, 2],
    [1, 1, 1],
];

/// The 8 linear hexahedra (as local node indices) of a triquadratic hexahedron.
pub fn tqhex_sub_hexes() -> [[usize; 8]; 8] {
    let mut at = [[[0usize; 3]; 3]; 3];
    for (n, l) in TQHEX_LATTICE.iter().enumerate() {
        at[l[0] as usize][l[1] as usize][l[2] as usize] = n;
    }
    const CORNER: [[usize; 3]; 8] = [
        [0, 0, 0],
        [1, 0, 0],
        [1, 1, 0],
        [0, 1, 0],
        [0, 0, 1],
        [1, 0, 1],
        [1, 1, 1],
        [0, 1, 1],
    ];
    let mut out = [[0usize; 8]; 8];
    for (s, sub) in out.iter_mut().enumerate() {
        let o = [s & 1, (s >> 1) & 1, (s >> 2) & 1];
        for (c, slot) in sub.iter_mut().enumerate() {
            let d = CORNER[c];
            *slot = at[o[0] + d[0]][o[1] + d[1]][o[2] + d[2]];
        }
    }
    out
}

/// Faces of a tet, oriented like [`HEX_FACES`] (for a tet among a cell's linear pieces).
pub const TET_FACES: [&[usize]; 4] = [&[0, 2, 1], &[0, 1, 3], &[1, 2, 3], &[2, 0, 3]];

/// A linear piece of a quadratic cell: its nodes (local indices) and the face table they fit.
pub type SubCell = (Vec<usize>, &'static [&'static [usize]]);

/// Triangle `(c0, c1, c2)` with mid-edge nodes `(m01, m12, m20)`, numbered 0..6 in that order,
/// cut into 4 by its mid-edge nodes, each turning the way the triangle does.
const TRIANGLE_IN_4: [[usize; 3]; 4] = [[0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5]];

/// The layers of the quadratic wedges, as triangles `(c0 c1 c2 m01 m12 m20)` from bottom to top
/// (VTK: corners 0-5, edges 6:01 7:12 8:20 9:34 10:45 11:53 12:03 13:14 14:25, quad-face
/// centres 15:0143 16:1254 17:2035): the 18-node wedge has a middle layer of its vertical edges'
/// mid nodes and its face centres; the 12-node one has none.
const WEDGE18_LAYERS: [[usize; 6]; 3] = [
    [0, 1, 2, 6, 7, 8],
    [12, 13, 14, 15, 16, 17],
    [3, 4, 5, 9, 10, 11],
];
const WEDGE12_LAYERS: [[usize; 6]; 2] = [[0, 1, 2, 6, 7, 8], [3, 4, 5, 9, 10, 11]];

/// The quadratic pyramid (VTK: base 0-3, apex 4, edges 5:01 6:12 7:23 8:30 9:04 10:14 11:24
/// 12:34) with its base centre as node 13, cut like a refined pyramid: 4 pyramids on the base
/// corners, one at the apex, one upside down from the base centre to the 4 mid-height nodes, and
/// a tet under each base edge between them.
const PYRAMID14_PYRAMIDS: [[usize; 5]; 6] = [
    [0, 5, 13, 8, 9],
    [5, 1, 6, 13, 10],
    [13, 6, 2, 7, 11],
    [8, 13, 7, 3, 12],
    [9, 10, 11, 12, 4],
    [9, 12, 11, 10, 13],
];
const PYRAMID14_TETS: [[usize; 4]; 4] = [
    [5, 13, 9, 10],
    [6, 13, 10, 11],
    [7, 13, 11, 12],
    [8, 13, 12, 9],
];

/// The linear cells a quadratic 3-D cell is cut into, over its nodes once completed (the
/// 20-node hexahedron, 15-node wedge and 13-node pyramid get the nodes they lack first; see
/// `quadratic.rs`): 8 hexahedra, 8 wedges (4 for the 12-node wedge), 6 pyramids and 4 tets. Every
/// piece is then split like a linear cell, so the pieces' quad faces take the global diagonal
/// rule too and neighbours stay conforming. Empty for other types.
pub fn sub_cells(t: u8) -> Vec<SubCell> {
    use formats::cell_type as ct;
    let wedges = |layers: &[[usize; 6]]| -> Vec<SubCell> {
        let mut out = Vec::new();
        for pair in layers.windows(2) {
            for tri in TRIANGLE_IN_4 {
                let mut w: Vec<usize> = tri.iter().map(|&k| pair[0][k]).collect();
                w.extend(tri.iter().map(|&k| pair[1][k]));
                out.push((w, &WEDGE_FACES[..]));
            }
        }
        out
    };
    match t {
        ct::QUADRATIC_HEXAHEDRON | ct::TRIQUADRATIC_HEXAHEDRON => tqhex_sub_hexes()
            .iter()
            .map(|h| (h.to_vec(), &HEX_FACES[..]))
            .collect(),
        ct::QUADRATIC_WEDGE | ct::BIQUADRATIC_QUADRATIC_WEDGE => wedges(&WEDGE18_LAYERS),
        ct::QUADRATIC_LINEAR_WEDGE => wedges(&WEDGE12_LAYERS),
        ct::QUADRATIC_PYRAMID => {
            let mut out: Vec<SubCell> = PYRAMID14_PYRAMIDS
                .iter()
                .map(|p| (p.to_vec(), &PYRAMID_FACES[..]))
                .collect();
            out.extend(PYRAMID14_TETS.iter().map(|t| (t.to_vec(), &TET_FACES[..])));
            out
        }
        _ => Vec::new(),
    }
}

/// A vertex of a child tet: an existing point id, or the cell's new centre point.
pub const CENTRE: i64 = -1;

/// Sign of the volume of tet `(a, b, c, d)` (positive for VTK's reference tet), exact.
pub fn volume_sign(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> i8 {
    // robust's orient3d is positive when d lies below abc, i.e. for negative volume.
    let o = orient3d(a, b, c, d);
    if o < 0.0 {
        1
    } else if o > 0.0 {
        -1
    } else {
        0
    }
}

/// Triangles of a face as a fan from its smallest id, keeping the face's orientation.
pub fn fan_from_min(face: &[i64], out: &mut Vec<[i64; 3]>) {
    let n = face.len();
    let Some((m, _)) = face.iter().enumerate().min_by_key(|&(_, &v)| v) else {
        return;
    };
    for k in 1..n.saturating_sub(1) {
        let t = [face[m], face[(m + k) % n], face[(m + k + 1) % n]];
        if !degenerate(&t) {
            out.push(t);
        }
    }
}

/// A triangle with a repeated point id: what a collapsed face (a hexahedron written with repeated
/// nodes for a wedge, say) leaves in a fan. It has no area and no neighbour needs it.
fn degenerate(t: &[i64; 3]) -> bool {
    t[0] == t[1] || t[1] == t[2] || t[0] == t[2]
}

/// Why a cell could not be split.
#[derive(Debug, Clone, PartialEq)]
pub enum SplitError {
    /// Neither pulling nor a centre point gives same-signed non-zero children.
    Invalid,
}

/// Children of one cell, all positively oriented.
#[derive(Debug, Default, Clone, PartialEq)]
pub struct Split {
    pub tets: Vec<[i64; 4]>,
    /// Set when the children use [`CENTRE`]: the new point's coordinates (already rounded to the
    /// points' stored type).
    pub centre: Option<[f64; 3]>,
    /// The cell was inverted (all children negative before flipping).
    pub inverted: bool,
}

/// Makes every child positive when all have the same non-zero sign; returns whether they were
/// negative, or `None` when signs are mixed or zero.
fn orient_all(tets: &mut [[i64; 4]], pos: &dyn Fn(i64) -> [f64; 3]) -> Option<bool> {
    let mut sign = 0i8;
    for t in tets.iter() {
        let s = volume_sign(&pos(t[0]), &pos(t[1]), &pos(t[2]), &pos(t[3]));
        if s == 0 || (sign != 0 && s != sign) {
            return None;
        }
        sign = s;
    }
    if sign < 0 {
        for t in tets.iter_mut() {
            t.swap(2, 3);
        }
    }
    Some(sign < 0)
}

/// Splits a polytope given by its faces (global ids, consistently oriented), pulling from the
/// smallest vertex, or from a centre point when pulling is invalid. `pos` gives a point's
/// coordinates; `round` rounds a new point to the stored point type.
pub fn split_polytope(
    faces: &[Vec<i64>],
    pos: &dyn Fn(i64) -> [f64; 3],
    round: &dyn Fn([f64; 3]) -> [f64; 3],
) -> Result<Split, SplitError> {
    let mut tris = Vec::with_capacity(2 * faces.len());
    for f in faces {
        fan_from_min(f, &mut tris);
    }
    split_tris(&tris, pos, round)
}

/// Fills a closed surface given as triangles (fans from each face's smallest id): pulling first,
/// then a centre point.
fn split_tris(
    tris: &[[i64; 3]],
    pos: &dyn Fn(i64) -> [f64; 3],
    round: &dyn Fn([f64; 3]) -> [f64; 3],
) -> Result<Split, SplitError> {
    let v0 = tris
        .iter()
        .flatten()
        .copied()
        .min()
        .ok_or(SplitError::Invalid)?;
    let mut tets: Vec<[i64; 4]> = tris
        .iter()
        .filter(|t| !t.contains(&v0))
        .map(|t| [t[0], t[2], t[1], v0])
        .collect();
    if !tets.is_empty() {
        if let Some(inverted) = orient_all(&mut tets, pos) {
            return Ok(Split {
                tets,
                centre: None,
                inverted,
            });
        }
    }
    // Centre point: the mean of the distinct vertices.
    let mut verts: Vec<i64> = tris.iter().flatten().copied().collect();
    verts.sort_unstable();
    verts.dedup();
    let mut c = [0.0f64; 3];
    for &v in &verts {
        let p = pos(v);
        for k in 0..3 {
            c[k] += p[k];
        }
    }
    let mean = c.map(|x| x / verts.len() as f64);
    let cone = |c: [f64; 3]| {
        let with_centre = |id: i64| if id == CENTRE { c } else { pos(id) };
        let mut tets: Vec<[i64; 4]> = tris.iter().map(|t| [t[0], t[2], t[1], CENTRE]).collect();
        orient_all(&mut tets, &with_centre).map(|inverted| Split {
            tets,
            centre: Some(c),
            inverted,
        })
    };
    if let Some(s) = cone(round(mean)) {
        return Ok(s);
    }
    // A warped cell can be star-shaped from some point but not from its vertices' mean: try the
    // point deepest inside the kernel (where every face triangle sees the point on its inner
    // side). The exact orientation test above still decides.
    kernel_centre(tris, pos, mean)
        .and_then(|k| cone(round(k)))
        .ok_or(SplitError::Invalid)
}

/// The Chebyshev centre of the kernel of a closed triangulated surface: the point `x` that
/// maximizes the smallest distance to the face triangles' planes, all on their inner side (for
/// either orientation of the surface), found as the best vertex of the small linear program
/// over `(x, t)` (every 4 planes tight). `None` when the kernel has no interior. Coordinates are
/// taken relative to `origin` so that offsets like 1e7 do not cost digits.
fn kernel_centre(
    tris: &[[i64; 3]],
    pos: &dyn Fn(i64) -> [f64; 3],
    origin: [f64; 3],
) -> Option<[f64; 3]> {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    // Child (t0, t2, t1, x) has volume n . (x - p0) with n = (p2 - p0) x (p1 - p0): one row
    // [n / |n|, -1] . (x, t) >= n . p0 / |n| per triangle, for one orientation sign.
    let mut rows: Vec<([f64; 4], f64)> = Vec::with_capacity(tris.len());
    for t in tris {
        let [p0, p1, p2] = t.map(|id| sub(pos(id), origin));
        let (a, b) = (sub(p2, p0), sub(p1, p0));
        let n = [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ];
        let len = dot(n, n).sqrt();
        if !(len > 0.0 && len.is_finite()) {
            return None;
        }
        let u = n.map(|x| x / len);
        rows.push(([u[0], u[1], u[2], -1.0], dot(u, p0)));
    }
    let m = rows.len();
    // Cells have at most 32 face triangles; the fallback is rare, so enumerating vertices is fine.
    if !(4..=32).contains(&m) {
        return None;
    }
    let mut best: Option<([f64; 3], f64)> = None;
    for sign in [1.0, -1.0] {
        let row = |i: usize| {
            let (a, b) = rows[i];
            ([sign * a[0], sign * a[1], sign * a[2], -1.0], sign * b)
        };
        for i in 0..m {
            for j in i + 1..m {
                for k in j + 1..m {
                    for l in k + 1..m {
                        let Some(v) = solve4([row(i), row(j), row(k), row(l)]) else {
                            continue;
                        };
                        if v[3] <= best.map_or(0.0, |b| b.1) {
                            continue;
                        }
                        let tol = 1e-12 * (1.0 + v[..3].iter().map(|x| x.abs()).sum::<f64>());
                        let feasible = (0..m).all(|q| {
                            let (a, b) = row(q);
                            a[0] * v[0] + a[1] * v[1] + a[2] * v[2] + a[3] * v[3] >= b - tol
                        });
                        if feasible {
                            best = Some(([v[0], v[1], v[2]], v[3]));
                        }
                    }
                }
            }
        }
    }
    best.map(|(x, _)| [x[0] + origin[0], x[1] + origin[1], x[2] + origin[2]])
}

/// Solves the 4x4 system `a_i . v = b_i` by Gaussian elimination with partial pivoting; `None`
/// when it is singular or the result is not finite.
fn solve4(rows: [([f64; 4], f64); 4]) -> Option<[f64; 4]> {
    let mut a = rows.map(|(r, b)| [r[0], r[1], r[2], r[3], b]);
    for c in 0..4 {
        let p = (c..4).max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs()))?;
        if a[p][c].abs() < 1e-12 {
            return None;
        }
        a.swap(c, p);
        for r in c + 1..4 {
            let (pivot, f) = (a[c], a[r][c] / a[c][c]);
            for (x, p) in a[r].iter_mut().zip(pivot).skip(c) {
                *x -= f * p;
            }
        }
    }
    let mut v = [0.0; 4];
    for c in (0..4).rev() {
        let s: f64 = (c + 1..4).map(|k| a[c][k] * v[k]).sum();
        v[c] = (a[c][4] - s) / a[c][c];
    }
    v.iter().all(|x| x.is_finite()).then_some(v)
}

/// Splits a cell whose faces are given as local-index tables (at most 8 points per face and 32
/// triangles in all, which every linear VTK cell meets); no allocation but the result's.
pub fn split_table(
    ids: &[i64],
    faces: &[&[usize]],
    pos: &dyn Fn(i64) -> [f64; 3],
    round: &dyn Fn([f64; 3]) -> [f64; 3],
) -> Result<Split, SplitError> {
    let mut tris = [[0i64; 3]; 32];
    let mut n = 0;
    for f in faces {
        let k = f.len();
        let m = (0..k).min_by_key(|&j| ids[f[j]]).unwrap_or(0);
        for j in 1..k.saturating_sub(1) {
            tris[n] = [ids[f[m]], ids[f[(m + j) % k]], ids[f[(m + j + 1) % k]]];
            n += !degenerate(&tris[n]) as usize;
        }
    }
    // Each corner is fetched once: the children look every corner up several times, and on a
    // big mesh with scattered ids each lookup would be a cache miss.
    let mut corners = [[0.0f64; 3]; 12];
    let m = ids.len().min(12);
    for (c, &id) in corners.iter_mut().zip(&ids[..m]) {
        *c = pos(id);
    }
    let cached = |id: i64| match ids[..m].iter().position(|&x| x == id) {
        Some(k) => corners[k],
        None => pos(id),
    };
    split_tris(&tris[..n], &cached, round)
}

/// A quadratic tetra's 8 linear children (no new point); tries the octahedron's diagonals from
/// the shortest.
pub fn split_quadratic_tet(
    ids: &[i64],
    pos: &dyn Fn(i64) -> [f64; 3],
) -> Result<Split, SplitError> {
    let mut diags: Vec<(f64, usize)> = QTET_DIAGONALS
        .iter()
        .enumerate()
        .map(|(i, (d, _))| {
            let (a, b) = (pos(ids[d[0]]), pos(ids[d[1]]));
            ((0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>(), i)
        })
        .collect();
    diags.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    for (_, i) in diags {
        let (d, ring) = QTET_DIAGONALS[i];
        let mut tets: Vec<[i64; 4]> = QTET_CORNERS.iter().map(|t| t.map(|l| ids[l])).collect();
        for k in 0..4 {
            tets.push([ids[d[0]], ids[d[1]], ids[ring[k]], ids[ring[(k + 1) % 4]]]);
        }
        if let Some(inverted) = orient_all(&mut tets, pos) {
            return Ok(Split {
                tets,
                centre: None,
                inverted,
            });
        }
    }
    Err(SplitError::Invalid)
}

/// A linear tet, flipped if negative. `None` when it is flat (zero volume, exactly).
pub fn orient_tet(ids: [i64; 4], pos: &dyn Fn(i64) -> [f64; 3]) -> Option<([i64; 4], bool)> {
    let mut t = [ids];
    orient_all(&mut t, pos).map(|inv| (t[0], inv))
}

/// Orients a polyhedron's faces consistently (each shared edge walked once each way), flipping
/// faces as needed starting from face 0. `Err` names what is wrong: an edge not shared by exactly
/// two faces, or a non-orientable surface.
pub fn orient_polyhedron_faces(faces: &mut [Vec<i64>]) -> Result<(), String> {
    use std::collections::HashMap;
    let mut edges: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (fi, f) in faces.iter().enumerate() {
        if f.len() < 3 {
            return Err(format!("face {fi} has {} points", f.len()));
        }
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            edges.entry((a.min(b), a.max(b))).or_default().push(fi);
        }
    }
    if let Some(((a, b), fs)) = edges.iter().find(|(_, fs)| fs.len() != 2) {
        return Err(format!(
            "edge {a}-{b} belongs to {} faces; a closed polyhedron needs 2",
            fs.len()
        ));
    }
    let directed =
        |f: &[i64], a: i64, b: i64| (0..f.len()).any(|k| f[k] == a && f[(k + 1) % f.len()] == b);
    let mut done = vec![false; faces.len()];
    let mut stack = vec![0usize];
    done[0] = true;
    while let Some(fi) = stack.pop() {
        let f = faces[fi].clone();
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            for &g in &edges[&(a.min(b), a.max(b))] {
                if g == fi {
                    continue;
                }
                if !done[g] {
                    if directed(&faces[g], a, b) {
                        faces[g].reverse();
                    }
                    done[g] = true;
                    stack.push(g);
                } else if directed(&faces[g], a, b) {
                    return Err("the faces cannot be oriented consistently".into());
                }
            }
        }
    }
    if let Some(fi) = done.iter().position(|d| !d) {
        return Err(format!("face {fi} is not connected to face 0"));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::tet_volume;

    fn pos_of(pts: &[[f64; 3]]) -> impl Fn(i64) -> [f64; 3] + '_ {
        move |i| pts[i as usize]
    }
    fn no_round(p: [f64; 3]) -> [f64; 3] {
        p
    }
    fn volume(tets: &[[i64; 4]], pos: &dyn Fn(i64) -> [f64; 3]) -> f64 {
        tets.iter()
            .map(|t| {
                let p = t.map(&pos);
                assert_eq!(volume_sign(&p[0], &p[1], &p[2], &p[3]), 1, "child {t:?}");
                tet_volume(&p[0], &p[1], &p[2], &p[3])
            })
            .sum()
    }
    const CUBE: [[f64; 3]; 8] = [
        [0., 0., 0.],
        [1., 0., 0.],
        [1., 1., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
        [1., 0., 1.],
        [1., 1., 1.],
        [0., 1., 1.],
    ];

    #[test]
    fn hex_is_six_positive_tets_for_every_numbering() {
        // Every rotation of which corner is smallest: permute ids by relabelling.
        for shift in 0..8i64 {
            let ids: Vec<i64> = (0..8).map(|i| (i + shift) % 8).collect();
            let mut pts = [[0.0; 3]; 8];
            for (l, &g) in ids.iter().enumerate() {
                pts[g as usize] = CUBE[l];
            }
            let pos = pos_of(&pts);
            let s = split_table(&ids, &HEX_FACES, &pos, &no_round).unwrap();
            assert_eq!(s.tets.len(), 6);
            assert!(!s.inverted);
            assert!(s.centre.is_none());
            assert!((volume(&s.tets, &pos) - 1.0).abs() < 1e-15);
        }
    }

    #[test]
    fn mirrored_hex_is_flipped() {
        let ids: Vec<i64> = vec![4, 5, 6, 7, 0, 1, 2, 3];
        let pos = pos_of(&CUBE);
        let s = split_table(&ids, &HEX_FACES, &pos, &no_round).unwrap();
        assert!(s.inverted);
        assert!((volume(&s.tets, &pos) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn wedge_pyramid_prisms() {
        // VTK's positive wedge has (0, 1, 2) clockwise seen from (3, 4, 5) (its parametric
        // element is negative by its own measure: vtkCellSizeFilter gives it -0.5).
        let w = [
            [0., 0., 0.],
            [0., 1., 0.],
            [1., 0., 0.],
            [0., 0., 1.],
            [0., 1., 1.],
            [1., 0., 1.],
        ];
        for ids in [[0i64, 1, 2, 3, 4, 5], [3, 1, 5, 0, 4, 2]] {
            let mut pts = [[0.0; 3]; 6];
            for (l, &g) in ids.iter().enumerate() {
                pts[g as usize] = w[l];
            }
            let pos = pos_of(&pts);
            let s = split_table(&ids, &WEDGE_FACES, &pos, &no_round).unwrap();
            assert_eq!(s.tets.len(), 3);
            assert!(!s.inverted);
            assert!((volume(&s.tets, &pos) - 0.5).abs() < 1e-15);
        }
        let p = [
            [0., 0., 0.],
            [1., 0., 0.],
            [1., 1., 0.],
            [0., 1., 0.],
            [0.5, 0.5, 1.],
        ];
        for ids in [[0i64, 1, 2, 3, 4], [1, 2, 3, 4, 0], [4, 2, 1, 3, 0]] {
            let mut pts = [[0.0; 3]; 5];
            for (l, &g) in ids.iter().enumerate() {
                pts[g as usize] = p[l];
            }
            let pos = pos_of(&pts);
            let s = split_table(&ids, &PYRAMID_FACES, &pos, &no_round).unwrap();
            assert_eq!(s.tets.len(), 2);
            assert!(!s.inverted);
            assert!((volume(&s.tets, &pos) - 1.0 / 3.0).abs() < 1e-15);
        }
        for n in [5usize, 6] {
            let mut pts = Vec::new();
            for z in [0.0, 1.0] {
                for i in 0..n {
                    let a = std::f64::consts::TAU * i as f64 / n as f64;
                    pts.push([a.cos(), a.sin(), z]);
                }
            }
            let ids: Vec<i64> = (0..2 * n as i64).collect();
            let faces = prism_faces(n);
            let faces: Vec<&[usize]> = faces.iter().map(|f| f.as_slice()).collect();
            let pos = pos_of(&pts);
            let s = split_table(&ids, &faces, &pos, &no_round).unwrap();
            assert_eq!(s.tets.len(), 3 * (n - 2));
            assert!(!s.inverted);
            let area = 0.5 * n as f64 * (std::f64::consts::TAU / n as f64).sin();
            assert!((volume(&s.tets, &pos) - area).abs() < 1e-12);
        }
    }

    #[test]
    fn twisted_hexes_fall_back_to_a_centre_point() {
        // Twisting the top face makes the side faces warp until pulling from corner 0 inverts a
        // child; the centre point then still works, until the twist is too strong for any fan.
        let ids: Vec<i64> = (0..8).collect();
        let mut used_centre = 0;
        for step in 0..18 {
            let a = step as f64 * 5f64.to_radians();
            let mut pts = CUBE;
            for p in pts.iter_mut().skip(4) {
                let (x, y) = (p[0] - 0.5, p[1] - 0.5);
                *p = [
                    0.5 + x * a.cos() - y * a.sin(),
                    0.5 + x * a.sin() + y * a.cos(),
                    1.0,
                ];
            }
            let pos = pos_of(&pts);
            if let Ok(s) = split_table(&ids, &HEX_FACES, &pos, &no_round) {
                let c = s.centre.unwrap_or([f64::NAN; 3]);
                used_centre += s.centre.is_some() as usize;
                let pc = |i: i64| if i == CENTRE { c } else { pts[i as usize] };
                volume(&s.tets, &pc);
            }
        }
        assert!(used_centre > 0);
        // A flat hex cannot be split at all.
        let flat: Vec<[f64; 3]> = CUBE.iter().map(|p| [p[0], p[1], 0.0]).collect();
        let pos = pos_of(&flat);
        assert_eq!(
            split_table(&ids, &HEX_FACES, &pos, &no_round),
            Err(SplitError::Invalid)
        );
    }

    #[test]
    fn warped_hex_seen_from_no_vertex_nor_its_mean_uses_its_kernel() {
        // A hex with randomly dragged corners (found by a search): pulling from corner 0 and the
        // vertices' mean both invert a child, but the cell is star-shaped from elsewhere.
        const WARPED: [[f64; 3]; 8] = [
            [0.02, -0.32, 0.33],
            [0.31, 0.46, -0.64],
            [0.89, 1.28, 0.46],
            [-0.15, 2.05, 0.01],
            [0.06, -0.23, 0.93],
            [0.82, 0.28, 0.92],
            [1.02, 0.45, 1.39],
            [0.72, 0.64, 1.23],
        ];
        let ids: Vec<i64> = (0..8).collect();
        let mut tris = Vec::new();
        for f in HEX_FACES {
            fan_from_min(&f.iter().map(|&i| i as i64).collect::<Vec<_>>(), &mut tris);
        }
        for offset in [0.0, 1e7] {
            let pts = WARPED.map(|p| p.map(|x| x + offset));
            let pos = pos_of(&pts);
            let cone_ok = |x: [f64; 3]| {
                let signs: Vec<i8> = tris
                    .iter()
                    .map(|t| {
                        volume_sign(
                            &pts[t[0] as usize],
                            &pts[t[2] as usize],
                            &pts[t[1] as usize],
                            &x,
                        )
                    })
                    .collect();
                signs.iter().all(|&s| s != 0 && s == signs[0])
            };
            let mut mean = [0.0; 3];
            for p in &pts {
                for k in 0..3 {
                    mean[k] += p[k] / 8.0;
                }
            }
            assert!(!cone_ok(pts[0]) && !cone_ok(mean), "offset {offset}");
            let s = split_table(&ids, &HEX_FACES, &pos, &no_round)
                .unwrap_or_else(|e| panic!("offset {offset}: {e:?}"));
            let c = s.centre.unwrap_or([f64::NAN; 3]);
            assert!(cone_ok(c) && c != mean, "offset {offset}: centre {c:?}");
            assert_eq!(s.tets.len(), tris.len());
            let pc = |i: i64| if i == CENTRE { c } else { pts[i as usize] };
            // Every child positive (checked inside), and together they fill the cell.
            let filled = volume(&s.tets, &pc);
            let enclosed: f64 = tris
                .iter()
                .map(|t| {
                    let p = t.map(|i| pts[i as usize]);
                    tet_volume(&p[0], &p[2], &p[1], &pts[0])
                })
                .sum();
            assert!(
                (filled - enclosed.abs()).abs() < 1e-9 * (1.0 + offset),
                "offset {offset}: {filled} vs {enclosed}"
            );
        }
    }

    #[test]
    fn quadratic_tet_reference_is_eight_positive_tets() {
        let c = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]];
        let mut pts = c.to_vec();
        for (a, b) in [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)] {
            pts.push([0, 1, 2].map(|k| 0.5 * (c[a][k] + c[b][k])));
        }
        let ids: Vec<i64> = (0..10).collect();
        let pos = pos_of(&pts);
        for (i, (d, ring)) in QTET_DIAGONALS.iter().enumerate() {
            for k in 0..4 {
                let t = [d[0], d[1], ring[k], ring[(k + 1) % 4]].map(|l| pts[l]);
                assert!(
                    tet_volume(&t[0], &t[1], &t[2], &t[3]) > 0.0,
                    "diagonal {i} child {k}"
                );
            }
        }
        for t in QTET_CORNERS {
            let t = t.map(|l| pts[l]);
            assert!(tet_volume(&t[0], &t[1], &t[2], &t[3]) > 0.0);
        }
        let s = split_quadratic_tet(&ids, &pos).unwrap();
        assert_eq!(s.tets.len(), 8);
        assert!((volume(&s.tets, &pos) - 1.0 / 6.0).abs() < 1e-15);
    }

    #[test]
    fn triquadratic_hex_sub_hexes_tile_the_lattice() {
        let subs = tqhex_sub_hexes();
        let mut seen = std::collections::HashSet::new();
        for s in subs {
            let l0 = TQHEX_LATTICE[s[0]];
            for (c, &n) in s.iter().enumerate() {
                let l = TQHEX_LATTICE[n];
                let d = [(c & 1) ^ ((c >> 1) & 1), (c >> 1) & 1, c >> 2];
                assert_eq!(
                    [0, 1, 2].map(|k| l[k] as usize - l0[k] as usize),
                    d,
                    "sub-hex {s:?}"
                );
            }
            assert!(seen.insert(l0));
        }
        assert_eq!(seen.len(), 8);
    }

    #[test]
    fn quadratic_cells_pieces_fill_the_cell() -> Result<(), SplitError> {
        use formats::cell_type as ct;
        // Straight cells under an affine map of determinant 8.984375 (so nothing is axis-aligned):
        // mid-edge nodes at the edges' midpoints, face centres at the faces' centroids.
        let skew = |p: [f64; 3]| {
            [
                2.0 * p[0] + 0.5 * p[1] + 1.0,
                1.5 * p[1] - 0.25 * p[2] - 2.0,
                3.0 * p[2] + 0.125 * p[0] + 0.5,
            ]
        };
        let det = 8.984375;
        let mean = |c: &[[f64; 3]], of: &[usize]| {
            [0, 1, 2].map(|k| of.iter().map(|&l| c[l][k]).sum::<f64>() / of.len() as f64)
        };
        // VTK's positive wedge (see `wedge_pyramid_prisms`) and a skewed pyramid.
        let w = [
            [0., 0., 0.],
            [0., 1., 0.],
            [1., 0., 0.],
            [0., 0., 1.],
            [0., 1., 1.],
            [1., 0., 1.],
        ];
        let wedge_nodes: Vec<[f64; 3]> = [
            &[0][..],
            &[1],
            &[2],
            &[3],
            &[4],
            &[5],
            &[0, 1],
            &[1, 2],
            &[2, 0],
            &[3, 4],
            &[4, 5],
            &[5, 3],
            &[0, 3],
            &[1, 4],
            &[2, 5],
            &[0, 1, 4, 3],
            &[1, 2, 5, 4],
            &[2, 0, 3, 5],
        ]
        .iter()
        .map(|of| mean(&w, of))
        .collect();
        let p = [
            [0., 0., 0.],
            [1., 0., 0.],
            [1., 1., 0.],
            [0., 1., 0.],
            [0.3, 0.4, 1.],
        ];
        let pyramid_nodes: Vec<[f64; 3]> = [
            &[0][..],
            &[1],
            &[2],
            &[3],
            &[4],
            &[0, 1],
            &[1, 2],
            &[2, 3],
            &[3, 0],
            &[0, 4],
            &[1, 4],
            &[2, 4],
            &[3, 4],
            &[0, 1, 2, 3],
        ]
        .iter()
        .map(|of| mean(&p, of))
        .collect();
        let hex_nodes: Vec<[f64; 3]> = TQHEX_LATTICE
            .iter()
            .map(|l| l.map(|x| 0.5 * x as f64))
            .collect();
        let twelve: Vec<[f64; 3]> = wedge_nodes[..12].to_vec();
        for (t, nodes, size, pieces) in [
            (ct::TRIQUADRATIC_HEXAHEDRON, hex_nodes, 1.0, 8),
            (ct::BIQUADRATIC_QUADRATIC_WEDGE, wedge_nodes, 0.5, 8),
            (ct::QUADRATIC_LINEAR_WEDGE, twelve, 0.5, 4),
            (ct::QUADRATIC_PYRAMID, pyramid_nodes, 1.0 / 3.0, 10),
        ] {
            let subs = sub_cells(t);
            assert_eq!(subs.len(), pieces, "type {t}");
            let n = nodes.len();
            // Global ids in both orders, so that the fans start at different corners.
            for reversed in [false, true] {
                let id = |l: usize| {
                    if reversed {
                        (n - 1 - l) as i64
                    } else {
                        l as i64
                    }
                };
                let mut pts = vec![[0.0; 3]; n];
                for (l, q) in nodes.iter().enumerate() {
                    pts[id(l) as usize] = skew(*q);
                }
                let pos = pos_of(&pts);
                let mut total = 0.0;
                for (local, faces) in &subs {
                    let ids: Vec<i64> = local.iter().map(|&l| id(l)).collect();
                    let s = split_table(&ids, faces, &pos, &no_round)?;
                    assert!(
                        !s.inverted && s.centre.is_none(),
                        "type {t}: piece {local:?}"
                    );
                    total += volume(&s.tets, &pos);
                }
                assert!((total - det * size).abs() < 1e-13, "type {t}: {total}");
            }
        }
        Ok(())
    }

    #[test]
    fn polyhedron_faces_get_oriented() {
        // A cube as a polyhedron with two faces given the wrong way round.
        let mut faces: Vec<Vec<i64>> = HEX_FACES
            .iter()
            .map(|f| f.iter().map(|&l| l as i64).collect())
            .collect();
        faces[1].reverse();
        faces[4].reverse();
        orient_polyhedron_faces(&mut faces).unwrap();
        let pos = pos_of(&CUBE);
        let s = split_polytope(&faces, &pos, &no_round).unwrap();
        assert!((volume(&s.tets, &pos) - 1.0).abs() < 1e-15);
        // An open box is refused.
        let mut open = faces[..5].to_vec();
        assert!(orient_polyhedron_faces(&mut open).is_err());
    }
}
