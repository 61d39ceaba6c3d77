//! Shirley-Tuchman projection classes from the exact fixed-point signed areas of the four faces.

use super::{Projected, PtStats};

/// Shirley-Tuchman projection class of a tet.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProjClass {
    /// 3 + 1: one vertex projects inside the triangle of the other three.
    One,
    /// 2 + 2: two edges cross at the thick point; the silhouette is a quadrilateral.
    Two,
    /// 2 + 1 + one flat face: a vertex on the opposite edge.
    Three,
    /// 1 + 1 + two flat faces: two vertices coincide.
    Four,
    /// Zero projected area.
    Flat,
}

/// Face `i` is opposite vertex `i`; vertex orders make the four faces consistently oriented.
pub const FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];

#[inline]
pub(crate) fn orient2(a: (i64, i64), b: (i64, i64), c: (i64, i64)) -> i64 {
    (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
}

/// Projected signed areas of the four faces (twice the area, 1/256-pixel units squared).
#[inline]
pub fn face_areas(p: &[(i64, i64); 4]) -> [i64; 4] {
    let a = |f: [usize; 3]| orient2(p[f[0]], p[f[1]], p[f[2]]);
    [a(FACES[0]), a(FACES[1]), a(FACES[2]), a(FACES[3])]
}

/// The silhouette's corners (vertex indices), positively oriented, and how many there are (3 or
/// 4; a triangle repeats its first corner), from the signs of the four faces' projected areas
/// (`sign[i]` for face `i`: -1, 0 or 1) and `left(a, b, c)`, whether vertex `c` lies strictly
/// left of `a -> b`. `None` for a flat projection.
#[inline(always)]
pub(crate) fn silhouette(
    sign: [i8; 4],
    left: impl Fn(usize, usize, usize) -> bool,
) -> Option<([usize; 4], u8)> {
    let (mut pos, mut np) = ([0usize; 4], 0);
    let (mut neg, mut nn) = ([0usize; 4], 0);
    for (i, &si) in sign.iter().enumerate() {
        if si > 0 {
            pos[np] = i;
            np += 1;
        } else if si < 0 {
            neg[nn] = i;
            nn += 1;
        }
    }
    if np == 1 || nn == 1 {
        let lone = if np == 1 { pos[0] } else { neg[0] };
        let f = FACES[lone];
        Some(if sign[lone] > 0 {
            ([f[0], f[1], f[2], f[0]], 3)
        } else {
            ([f[0], f[2], f[1], f[0]], 3)
        })
    } else if np == 2 && nn == 2 {
        // 2 + 2: the positive faces i, j share edge k-l; diagonals i-j and k-l cross.
        let (i, j) = (pos[0], pos[1]);
        let (k, l) = (neg[0], neg[1]);
        Some(if left(i, k, j) {
            ([i, k, j, l], 4)
        } else {
            ([i, l, j, k], 4)
        })
    } else {
        None
    }
}

pub fn classify(d: &[i64; 4]) -> ProjClass {
    let pos = d.iter().filter(|&&v| v > 0).count();
    let neg = d.iter().filter(|&&v| v < 0).count();
    match (pos, neg) {
        (3, 1) | (1, 3) => ProjClass::One,
        (2, 2) => ProjClass::Two,
        (2, 1) | (1, 2) => ProjClass::Three,
        (1, 1) => ProjClass::Four,
        _ => ProjClass::Flat,
    }
}

pub(crate) fn class_index(c: ProjClass) -> usize {
    match c {
        ProjClass::One => 0,
        ProjClass::Two => 1,
        ProjClass::Three => 2,
        ProjClass::Four => 3,
        ProjClass::Flat => 4,
    }
}

/// Counts tet `p`'s projection class (or that it takes the clipping path), once per tet.
#[inline]
pub(crate) fn count_class(st: &mut PtStats, p: &[&Projected; 4]) {
    if p.iter().any(|q| !q.ok) {
        st.clipped += 1;
    } else {
        let c = classify(&face_areas(&p.map(|q| (q.fx, q.fy))));
        st.class[class_index(c)] += 1;
    }
}
