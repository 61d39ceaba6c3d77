//! Exodus variables joined into multi-component arrays as VTK 9.1's vtkExodusIIReader joins them.

/// One array made of consecutive variables: its name and the variables' indices, in order.
#[derive(Debug, PartialEq)]
pub(crate) struct Glom {
    pub name: String,
    pub members: Vec<usize>,
}

/// Suffix sets tried at each variable: (endings, letters per ending), as VTK lists them.
/// Vectors x y, x y z and R Z; the symmetric tensor XX YY ZZ XY XZ YZ; the third-rank
/// symmetric tensor in four dimensions (20 components).
const SUFFIXES: [(&str, usize); 5] = [
    ("xy", 1),
    ("xyz", 1),
    ("rz", 1),
    ("xxyyzzxyxzyz", 2),
    (
        "xxxyyyzzzwwwxxyxxzxxwxyyxyzxywxzzxzwxwwyyzyywyzzyzwywwzzwzww",
        3,
    ),
];

/// Groups `names` as VTK does: from each variable not yet taken, every suffix set (and the
/// integration-point pattern) takes as many following variables as fit it, one ending each in
/// order (endings case-insensitive, the prefix the same exactly); a set counts only when all
/// its endings are there, the longest wins, and a variable no set takes stays a scalar. The
/// array is named by the common prefix (`vel_x vel_y vel_z` gives `vel_`); a name already
/// taken gets `_` appended until free. `joins(i)` is false for a variable that may not start
/// an array (an element variable no block holds, which VTK leaves a scalar).
pub(crate) fn glom(names: &[String], joins: impl Fn(usize) -> bool) -> Vec<Glom> {
    let mut out: Vec<Glom> = Vec::new();
    let mut i = 0;
    while i < names.len() {
        let rest = &names[i..];
        let mut best = (names[i].clone(), 1);
        if joins(i) {
            let found = SUFFIXES
                .iter()
                .map(|&(endings, rank)| suffix_run(rest, endings.as_bytes(), rank))
                .chain([integration_points(rest)]);
            for (prefix, n) in found.flatten() {
                if n > best.1 {
                    best = (prefix, n);
                }
            }
        }
        let (mut name, n) = best;
        while out.iter().any(|g| g.name == name) {
            name.push('_');
        }
        out.push(Glom {
            name,
            members: (i..i + n).collect(),
        });
        i += n;
    }
    out
}

/// The prefix and count when `names` starts with one variable per ending of `endings`
/// (`rank` letters each), all of them.
fn suffix_run(names: &[String], endings: &[u8], rank: usize) -> Option<(String, usize)> {
    let count = endings.len() / rank;
    let first = names[0].as_bytes();
    // ASCII endings, so the split is on a character boundary.
    let split = first.len().checked_sub(rank).filter(|&s| s > 0)?;
    let prefix = &first[..split];
    let fits = |name: &String, k: usize| {
        let b = name.as_bytes();
        b.len() == split + rank
            && b.starts_with(prefix)
            && b[split..].eq_ignore_ascii_case(&endings[k * rank..(k + 1) * rank])
    };
    let taken = names
        .iter()
        .take(count)
        .enumerate()
        .take_while(|&(k, name)| fits(name, k))
        .count();
    (taken == count).then(|| (names[0][..split].to_string(), count))
}

/// Integration-point values `VAR_CELLTYPE_GPnnn` (one digit per parametric direction, as many
/// as the cell type has: 2 for quad and tri, 3 for hex, tet, wedge and pyramid): the run of
/// distinct points that fills the box between the smallest and largest digits, named
/// `VAR_CELLTYPE`.
fn integration_points(names: &[String]) -> Option<(String, usize)> {
    let (head, digits) = names[0].rsplit_once("_GP")?;
    let (_, cell) = head.rsplit_once('_')?;
    let cell = cell.to_ascii_lowercase();
    let rank = [
        ("quad", 2),
        ("hex", 3),
        ("tet", 3),
        ("tri", 2),
        ("wedge", 3),
        ("pyr", 3),
    ]
    .iter()
    .find(|(t, _)| cell.contains(t))?
    .1;
    let point = |d: &str| -> Option<Vec<u8>> {
        (d.len() == rank && d.bytes().all(|c| c.is_ascii_digit())).then(|| d.bytes().collect())
    };
    let first = point(digits)?;
    let (mut lo, mut hi) = (first.clone(), first.clone());
    let mut seen = vec![first];
    for name in &names[1..] {
        // VTK checks the length and the prefix, not the `_GP` between them.
        let Some(tail) = name
            .strip_prefix(head)
            .filter(|t| t.len() == rank + 3)
            .and_then(|t| t.get(3..))
        else {
            break;
        };
        let Some(p) = point(tail).filter(|p| !seen.contains(p)) else {
            break;
        };
        for k in 0..rank {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
        seen.push(p);
    }
    let full: usize = (0..rank).map(|k| usize::from(hi[k] - lo[k]) + 1).product();
    (full == seen.len()).then(|| (head.to_string(), seen.len()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(names: &[&str]) -> Vec<(String, usize)> {
        let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
        glom(&names, |_| true)
            .into_iter()
            .map(|g| (g.name, g.members.len()))
            .collect()
    }

    fn want(v: &[(&str, usize)]) -> Vec<(String, usize)> {
        v.iter().map(|&(s, n)| (s.to_string(), n)).collect()
    }

    // Each case as VTK 9.1's vtkExodusIIReader joined it (fixtures/newuser/exodus_vectors.exo and
    // files written the same way).
    #[test]
    fn vectors_and_tensors_as_vtk_joins_them() {
        assert_eq!(
            run(&["DISPLX", "DISPLY", "DISPLZ", "vel_x", "vel_y", "vel_z", "sig_R", "sig_Z"]),
            want(&[("DISPL", 3), ("vel_", 3), ("sig_", 2)])
        );
        // Mixed case in the endings, not in the prefix; x y without z is a 2-vector.
        assert_eq!(
            run(&["a_X", "a_y", "a_Z", "p_x", "p_y", "m_X", "M_Y", "vx", "Vy"]),
            want(&[
                ("a_", 3),
                ("p_", 2),
                ("m_X", 1),
                ("M_Y", 1),
                ("vx", 1),
                ("Vy", 1)
            ])
        );
        // Out of order, interrupted, or missing a component: scalars.
        assert_eq!(
            run(&["q_x", "q_z", "w_x", "other", "w_y", "w_z", "u_r", "u_theta", "u_z"]),
            want(&[
                ("q_x", 1),
                ("q_z", 1),
                ("w_x", 1),
                ("other", 1),
                ("w_y", 1),
                ("w_z", 1),
                ("u_r", 1),
                ("u_theta", 1),
                ("u_z", 1)
            ])
        );
        // The tensor in VTK's order only; ZX instead of XZ leaves six scalars.
        let t = ["T_XX", "T_YY", "T_ZZ", "T_XY", "T_XZ", "T_YZ"];
        assert_eq!(run(&t), want(&[("T_", 6)]));
        let s = ["S_XX", "S_YY", "S_ZZ", "S_XY", "S_YZ", "S_ZX"];
        assert_eq!(run(&s).len(), 6);
        // VTK's own writer stores a tensor as XX XY XZ YY YZ ZZ, which reads back as a vector
        // `tenX` and three scalars.
        assert_eq!(
            run(&["tenXX", "tenXY", "tenXZ", "tenYY", "tenYZ", "tenZZ"]),
            want(&[("tenX", 3), ("tenYY", 1), ("tenYZ", 1), ("tenZZ", 1)])
        );
        // The name needs a prefix.
        assert_eq!(
            run(&["x", "y", "_x", "_y", "_z"]),
            want(&[("x", 1), ("y", 1), ("_", 3)])
        );
    }

    #[test]
    fn taken_names_get_an_underscore() {
        assert_eq!(
            run(&["d_", "d_x", "d_y", "d_z", "e_x", "e_y", "e_z", "e_"]),
            want(&[("d_", 1), ("d__", 3), ("e_", 3), ("e__", 1)])
        );
        assert_eq!(run(&["t", "t"]), want(&[("t", 1), ("t_", 1)]));
    }

    #[test]
    fn integration_points_fill_their_box() {
        let hex: Vec<String> = ["111", "211", "121", "221", "112", "212", "122", "222"]
            .iter()
            .map(|p| format!("s_hex_GP{p}"))
            .collect();
        let mut names: Vec<&str> = hex.iter().map(String::as_str).collect();
        names.extend([
            "q_tet_GP1",
            "q_quad_GP11",
            "q_quad_GP12",
            "q_quad_GP21",
            "q_quad_GP22",
        ]);
        assert_eq!(
            run(&names),
            want(&[("s_hex", 8), ("q_tet_GP1", 1), ("q_quad", 4)])
        );
        // Three points of a 2 x 2 box do not fill it.
        assert_eq!(run(&["q_quad_GP11", "q_quad_GP12", "q_quad_GP21"]).len(), 3);
    }

    #[test]
    fn a_variable_that_may_not_join_stays_a_scalar() {
        let names: Vec<String> = ["a_x", "a_y"].iter().map(|s| s.to_string()).collect();
        let g = glom(&names, |i| i != 0);
        assert_eq!(g.len(), 2);
    }
}
