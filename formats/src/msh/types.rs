//! Gmsh element types 1-19 as VTK cell types, with each one's node order mapped to VTK's.

use crate::cell_type as ct;

/// One Gmsh element type as tetkit reads it.
#[derive(Debug)]
pub(crate) struct ElementType {
    /// Nodes the element has in the file.
    pub nodes: usize,
    pub vtk: u8,
    /// Entry k is the Gmsh node (0-based, in the file's order) that becomes VTK node k. Shorter
    /// than `nodes` when a node has no place in the VTK cell (the 14-node pyramid's base centre).
    pub from_gmsh: &'static [usize],
}

const fn identity<const N: usize>() -> [usize; N] {
    let mut a = [0; N];
    let mut i = 0;
    while i < N {
        a[i] = i;
        i += 1;
    }
    a
}

static ID1: [usize; 1] = identity();
static ID2: [usize; 2] = identity();
static ID3: [usize; 3] = identity();
static ID4: [usize; 4] = identity();
static ID5: [usize; 5] = identity();
static ID6: [usize; 6] = identity();
static ID8: [usize; 8] = identity();
static ID9: [usize; 9] = identity();

/// Gmsh numbers a tet's edge nodes on edges 01 12 20 30 32 31; VTK wants 01 12 20 03 13 23.
static TET10: [usize; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8];

/// Gmsh's hexahedron edges: 8:01 9:03 10:04 11:12 12:15 13:23 14:26 15:37 16:45 17:47 18:56
/// 19:67; VTK's: 01 12 23 30, then 45 56 67 74, then 04 15 26 37. Faces: Gmsh 20:z- 21:y- 22:x-
/// 23:x+ 24:y+ 25:z+; VTK x- x+ y- y+ z- z+. The corners agree.
static HEX27: [usize; 27] = [
    0, 1, 2, 3, 4, 5, 6, 7, // corners
    8, 11, 13, 9, // bottom edges
    16, 18, 19, 17, // top edges
    10, 12, 14, 15, // vertical edges
    22, 23, 21, 24, 20, 25, 26, // faces and centre
];

/// Gmsh's prism has (0,1,2) turning counterclockwise seen from (3,4,5), VTK's wedge the other
/// way, so corners are taken as 0 2 1 3 5 4. Gmsh's edges: 6:01 7:02 8:03 9:12 10:14 11:25
/// 12:34 13:35 14:45; VTK's, on the flipped corners: (g0,g2) (g2,g1) (g1,g0) (g3,g5) (g5,g4)
/// (g4,g3) (g0,g3) (g2,g5) (g1,g4). Quad faces: Gmsh 15:0143 16:0253 17:1254; VTK's (v0 v1 v4
/// v3) = g0 g2 g5 g3, (v1 v2 v5 v4) = g2 g1 g4 g5, (v2 v0 v3 v5) = g1 g0 g3 g4.
static PRISM6: [usize; 6] = [0, 2, 1, 3, 5, 4];
static PRISM18: [usize; 18] = [
    0, 2, 1, 3, 5, 4, // corners, flipped
    7, 9, 6, 13, 14, 12, 8, 11, 10, // edges
    16, 17, 15, // quad faces
];

/// Gmsh's pyramid edges: 5:01 6:03 7:04 8:12 9:14 10:23 11:24 12:34 (13: base centre); VTK's:
/// 01 12 23 30 04 14 24 34. The corners agree.
static PYRAMID13: [usize; 13] = [0, 1, 2, 3, 4, 5, 8, 10, 6, 7, 9, 11, 12];

/// The element type, or why it is refused.
pub(crate) fn element_type(t: i64) -> Result<ElementType, String> {
    // The comment on each line is Gmsh's name for the type.
    let e = |nodes, vtk, from_gmsh: &'static [usize]| {
        Ok(ElementType {
            nodes,
            vtk,
            from_gmsh,
        })
    };
    match t {
        1 => e(2, ct::LINE, &ID2), // 2-node line
        2 => e(3, ct::TRIANGLE, &ID3), // 3-node triangle
        3 => e(4, ct::QUAD, &ID4), // 4-node quadrangle
        4 => e(4, ct::TETRA, &ID4), // 4-node tetrahedron
        5 => e(8, ct::HEXAHEDRON, &ID8), // 8-node hexahedron
        6 => e(6, ct::WEDGE, &PRISM6), // 6-node prism
        7 => e(5, ct::PYRAMID, &ID5), // 5-node pyramid
        8 => e(3, ct::QUADRATIC_EDGE, &ID3), // 3-node line
        9 => e(6, ct::QUADRATIC_TRIANGLE, &ID6), // 6-node triangle
        10 => e(9, ct::BIQUADRATIC_QUAD, &ID9), // 9-node quadrangle
        11 => e(10, ct::QUADRATIC_TETRA, &TET10), // 10-node tetrahedron
        12 => e(27, ct::TRIQUADRATIC_HEXAHEDRON, &HEX27), // 27-node hexahedron
        13 => e(18, ct::BIQUADRATIC_QUADRATIC_WEDGE, &PRISM18), // 18-node prism
        14 => e(14, ct::QUADRATIC_PYRAMID, &PYRAMID13), // 14-node pyramid
        15 => e(1, ct::VERTEX, &ID1), // point
        16 => e(8, ct::QUADRATIC_QUAD, &ID8), // 8-node quadrangle
        17 => e(20, ct::QUADRATIC_HEXAHEDRON, &HEX27[..20]), // 20-node hexahedron
        18 => e(15, ct::QUADRATIC_WEDGE, &PRISM18[..15]), // 15-node prism
        19 => e(13, ct::QUADRATIC_PYRAMID, &PYRAMID13), // 13-node pyramid
        _ => Err(match higher_order(t) {
            Some((name, order)) => format!(
                "element type {t} ({name}) is of order {order}; tetkit reads Gmsh elements up to order 2 (types 1-19)"
            ),
            None => format!(
                "element type {t} is not one tetkit reads: it reads types 1-19 (points, lines, triangles, quadrangles, tetrahedra, hexahedra, prisms and pyramids up to order 2)"
            ),
        }),
    }
}

/// Names and orders of Gmsh's higher-order types, for the message that refuses them.
fn higher_order(t: i64) -> Option<(&'static str, u32)> {
    Some(match t {
        20 => ("9-node triangle", 3),
        21 => ("10-node triangle", 3),
        22 => ("12-node triangle", 4),
        23 => ("15-node triangle", 4),
        24 => ("15-node incomplete triangle", 5),
        25 => ("21-node triangle", 5),
        26 => ("4-node line", 3),
        27 => ("5-node line", 4),
        28 => ("6-node line", 5),
        29 => ("20-node tetrahedron", 3),
        30 => ("35-node tetrahedron", 4),
        31 => ("56-node tetrahedron", 5),
        36 => ("16-node quadrangle", 3),
        37 => ("25-node quadrangle", 4),
        38 => ("36-node quadrangle", 5),
        39 => ("12-node quadrangle", 3),
        40 => ("16-node incomplete quadrangle", 4),
        41 => ("20-node incomplete quadrangle", 5),
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_map_is_a_permutation_of_the_vtk_cell() {
        for t in 1..=19 {
            let e = element_type(t).unwrap();
            assert_eq!(ct::fixed_size(e.vtk), Some(e.from_gmsh.len()), "type {t}");
            let mut seen = vec![false; e.nodes];
            for &g in e.from_gmsh {
                assert!(!seen[g], "type {t} uses node {g} twice");
                seen[g] = true;
            }
            assert_eq!(
                e.from_gmsh.len() + usize::from(t == 14),
                e.nodes,
                "type {t}"
            );
        }
        assert!(element_type(29).unwrap_err().contains("order 3"));
        assert!(element_type(0).unwrap_err().contains("types 1-19"));
    }
}
