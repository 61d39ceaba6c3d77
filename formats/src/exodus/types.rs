//! Exodus element types (`elem_type` and nodes per element) as VTK cell types, with node orders.

use crate::cell_type as ct;

/// A VTK cell type and, where Exodus orders nodes differently, `perm[k]` = the Exodus node that
/// is VTK's node k.
#[derive(Debug)]
pub(crate) struct CellKind {
    pub vtk: u8,
    pub perm: Option<&'static [usize]>,
}

/// HEX20: Exodus puts the vertical edges (nodes 12-15) before the top edges (16-19); VTK after.
const HEX20: [usize; 20] = [
    0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 16, 17, 18, 19, 12, 13, 14, 15,
];
/// HEX27: the HEX20 swap, then Exodus's centre (20) and faces -z, +z, -x, +x, -y, +y (21-26)
/// become VTK's faces -x, +x, -y, +y, -z, +z (20-25) and centre (26).
const HEX27: [usize; 27] = [
    0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 16, 17, 18, 19, 12, 13, 14, 15, 23, 24, 25, 26, 21, 22,
    20,
];
/// WEDGE15: Exodus puts the vertical edges (9-11) before the top triangle's edges (12-14).
const WEDGE15: [usize; 15] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 13, 14, 9, 10, 11];

/// The family of an `elem_type`, case-insensitive, by its first three letters as VTK's
/// vtkExodusIIReader matches them (so `TETRAHEDRON`, `QUADRILATERAL`, `EDGE2` and `TRISHELL3`
/// read as VTK reads them); any trailing node count is split off. `SHELL` is a quadrilateral,
/// or a triangle with 3 nodes per element (as VTK reads `SHELL3`); `STRAIGHT` (2 nodes) a bar.
fn family(elem_type: &str, nodes: usize) -> Option<(&'static str, Option<usize>)> {
    let t = elem_type.trim().to_ascii_uppercase();
    let digits = t.len() - t.trim_end_matches(|c: char| c.is_ascii_digit()).len();
    let (name, count) = t.split_at(t.len() - digits);
    let count = count.parse::<usize>().ok();
    if name.starts_with("STRAIGHT") {
        return Some(("bar", count));
    }
    let fam = match name.get(..3)? {
        "TET" => "tetra",
        "HEX" => "hex",
        "WED" => "wedge",
        "PYR" => "pyramid",
        "TRI" => "tri",
        "QUA" => "quad",
        "SHE" if nodes == 3 => "tri",
        "SHE" => "quad",
        "BAR" | "BEA" | "TRU" | "EDG" => "bar",
        "SPH" | "CIR" => "sphere",
        _ => return None,
    };
    Some((fam, count))
}

/// The cell for a block, or an error message saying why it cannot be read.
pub(crate) fn cell_kind(elem_type: &str, nodes: usize) -> Result<CellKind, String> {
    let up = elem_type.trim().to_ascii_uppercase();
    if up.starts_with("NSIDED") || up.starts_with("NFACED") {
        return Err(format!(
            "element type '{elem_type}' (arbitrary polygons and polyhedra) is not supported"
        ));
    }
    let Some((fam, named)) = family(elem_type, nodes) else {
        return Err(format!("unknown element type '{elem_type}'"));
    };
    // A count in the name must agree with the block's nodes per element; without one the count
    // decides (VTK's writer names a 20-node hexahedron plain `hexahedron`).
    if let Some(n) = named.filter(|&n| n != nodes) {
        return Err(format!(
            "element type '{elem_type}' names {n} nodes but the block has {nodes} per element"
        ));
    }
    let plain = |vtk| Ok(CellKind { vtk, perm: None });
    match (fam, nodes) {
        ("tetra", 4) => plain(ct::TETRA),
        ("tetra", 10) => plain(ct::QUADRATIC_TETRA),
        ("hex", 8) => plain(ct::HEXAHEDRON),
        ("hex", 20) => Ok(CellKind {
            vtk: ct::QUADRATIC_HEXAHEDRON,
            perm: Some(&HEX20),
        }),
        ("hex", 27) => Ok(CellKind {
            vtk: ct::TRIQUADRATIC_HEXAHEDRON,
            perm: Some(&HEX27),
        }),
        ("wedge", 6) => plain(ct::WEDGE),
        ("wedge", 15) => Ok(CellKind {
            vtk: ct::QUADRATIC_WEDGE,
            perm: Some(&WEDGE15),
        }),
        ("pyramid", 5) => plain(ct::PYRAMID),
        ("pyramid", 13) => plain(ct::QUADRATIC_PYRAMID),
        ("tri", 3) => plain(ct::TRIANGLE),
        ("tri", 6) => plain(ct::QUADRATIC_TRIANGLE),
        ("quad", 4) => plain(ct::QUAD),
        ("quad", 8) => plain(ct::QUADRATIC_QUAD),
        ("quad", 9) => plain(ct::BIQUADRATIC_QUAD),
        ("bar", 2) => plain(ct::LINE),
        ("bar", 3) => plain(ct::QUADRATIC_EDGE),
        ("sphere", 1) => plain(ct::VERTEX),
        _ => Err(format!(
            "element type '{elem_type}' with {nodes} nodes per element is not supported"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aliases_and_counts() {
        for (t, n, vtk) in [
            ("TETRA", 4, ct::TETRA),
            ("tet4", 4, ct::TETRA),
            ("TETRA10", 10, ct::QUADRATIC_TETRA),
            ("hexahedron", 20, ct::QUADRATIC_HEXAHEDRON),
            ("HEX27", 27, ct::TRIQUADRATIC_HEXAHEDRON),
            ("WEDGE", 6, ct::WEDGE),
            ("pyramid13", 13, ct::QUADRATIC_PYRAMID),
            ("TRISHELL3", 3, ct::TRIANGLE),
            ("triangle", 6, ct::QUADRATIC_TRIANGLE),
            ("SHELL4", 4, ct::QUAD),
            ("SHELL9", 9, ct::BIQUADRATIC_QUAD),
            ("truss", 2, ct::LINE),
            ("BEAM3", 3, ct::QUADRATIC_EDGE),
            ("circle", 1, ct::VERTEX),
            // Named as VTK's reader matches them: by the first three letters.
            ("TETRAHEDRON", 4, ct::TETRA),
            ("hexahedron", 8, ct::HEXAHEDRON),
            ("QUADRILATERAL", 4, ct::QUAD),
            ("Quadrilateral8", 8, ct::QUADRATIC_QUAD),
            ("SHELL3", 3, ct::TRIANGLE),
            ("EDGE2", 2, ct::LINE),
            ("edge3", 3, ct::QUADRATIC_EDGE),
            ("STRAIGHT2", 2, ct::LINE),
            ("WEDGE6", 6, ct::WEDGE),
            ("PYRAMID5", 5, ct::PYRAMID),
        ] {
            assert_eq!(cell_kind(t, n).unwrap().vtk, vtk, "{t}");
        }
        assert!(cell_kind("NSIDED", 0).unwrap_err().contains("polygons"));
        assert!(cell_kind("HEX8", 20).unwrap_err().contains("names 8 nodes"));
        assert!(cell_kind("blob", 3).unwrap_err().contains("unknown"));
        assert!(cell_kind("TE", 4).unwrap_err().contains("unknown"));
        assert!(cell_kind("", 4).unwrap_err().contains("unknown"));
        assert!(cell_kind("TETRA", 8).unwrap_err().contains("8 nodes"));
    }

    #[test]
    fn permutations_are_permutations() {
        for p in [&HEX20[..], &HEX27[..], &WEDGE15[..]] {
            let mut s = p.to_vec();
            s.sort();
            assert_eq!(s, (0..p.len()).collect::<Vec<_>>());
        }
    }
}
