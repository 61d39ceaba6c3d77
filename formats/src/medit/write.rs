//! Writing a [`Grid`] as an ASCII Medit file.

use super::{names, SECTIONS};
use crate::{cell_type, ArrayData, DataArray, FormatError, Grid, Result};
use std::io::Write;
use std::path::Path;

/// VTK's voxel and pixel number their points as a grid (x fastest); Medit's hexahedron and
/// quadrilateral go round each face, as VTK's hexahedron and quad do.
const HEX_FROM_VOXEL: [usize; 8] = [0, 1, 3, 2, 4, 5, 7, 6];
const QUAD_FROM_PIXEL: [usize; 4] = [0, 1, 3, 2];

/// The Medit section (index into [`SECTIONS`]) a VTK cell type goes to, if any.
fn section_of(t: u8) -> Option<usize> {
    let t = match t {
        cell_type::VOXEL => cell_type::HEXAHEDRON,
        cell_type::PIXEL => cell_type::QUAD,
        t => t,
    };
    SECTIONS.iter().position(|s| s.vtk == t)
}

/// A one-component integer array named `name`, if the data holds one.
fn int_array<'g>(arrays: &'g [DataArray], name: &str) -> Option<&'g DataArray> {
    arrays.iter().find(|a| {
        a.name == name && a.components == 1 && a.data.scalar_type().is_some_and(|t| !t.is_float())
    })
}

/// A one-component array of whole numbers named `name`: an integer array, or a float one whose
/// every value is whole (what a tool that stores everything as reals writes, meshio's
/// `medit:ref` read back from some formats, say), so the refs it holds are not dropped as
/// "an array Medit cannot hold".
fn whole_array<'g>(arrays: &'g [DataArray], name: &str) -> Option<&'g DataArray> {
    int_array(arrays, name).or_else(|| {
        arrays.iter().find(|a| {
            a.name == name
                && a.components == 1
                && a.data.scalar_type().is_some_and(|t| t.is_float())
                && (0..a.data.len()).all(|i| {
                    let v = a.data.get_f64(i);
                    v.fract() == 0.0 && v.is_finite()
                })
        })
    })
}

/// The cell array the cell refs come from, and its name when it is not `medit:ref`: Medit's own,
/// else the regions another format gave (Gmsh's physical groups, the `CellEntityIds` of VTK
/// files from Gmsh or FEniCS), which are what a Medit ref holds.
fn cell_ref_source(cd: &[DataArray]) -> (Option<&DataArray>, Option<&'static str>) {
    if let Some(a) = whole_array(cd, names::REF) {
        return (Some(a), None);
    }
    for name in [crate::msh::names::PHYSICAL, "CellEntityIds"] {
        if let Some(a) = whole_array(cd, name) {
            return (Some(a), Some(name));
        }
    }
    (None, None)
}

/// Values of an integer ref array as i32 (Medit refs are `int`), or an error naming the first
/// that does not fit.
fn refs(a: Option<&DataArray>, n: usize, what: &str) -> Result<Vec<i32>> {
    let Some(a) = a else {
        return Ok(vec![0; n]);
    };
    (0..n)
        .map(|i| {
            let v = a.data.get_f64(i);
            if v >= i32::MIN as f64 && v <= i32::MAX as f64 {
                Ok(v as i32)
            } else {
                Err(FormatError::in_array(
                    names::REF,
                    format!("{what} {i} has ref {v}, which does not fit a Medit (32-bit) ref"),
                ))
            }
        })
        .collect()
}

/// Writes `grid` as ASCII Medit to `w`; `label` names the output in warnings about what the
/// format cannot carry. Fails, before writing anything, on cell types Medit lacks.
pub fn write(w: &mut dyn Write, grid: &Grid, label: &Path) -> Result<()> {
    let n = grid.num_cells();
    // Which section each cell goes to, and the sections in the order their types first appear.
    let mut section = Vec::with_capacity(n);
    let mut order: Vec<usize> = Vec::new();
    let mut refused: Vec<(u8, usize)> = Vec::new();
    for &t in &grid.cells.types {
        match section_of(t) {
            Some(k) => {
                if !order.contains(&k) {
                    order.push(k);
                }
                section.push(k);
            }
            None => {
                match refused.iter_mut().find(|(x, _)| *x == t) {
                    Some((_, c)) => *c += 1,
                    None => refused.push((t, 1)),
                }
                section.push(usize::MAX);
            }
        }
    }
    if !refused.is_empty() {
        let list: Vec<String> = refused
            .iter()
            .map(|&(t, c)| format!("{c} {} cells", cell_type::name(t)))
            .collect();
        return Err(FormatError::whole(format!(
            "Medit files hold edges, triangles, quadrilaterals, tetrahedra, hexahedra, prisms and pyramids only; this mesh has {} (tetkit convert --tetrahedralize splits 3-D cells into tets)",
            list.join(", ")
        )));
    }
    let np = grid.num_points();
    let pd = &grid.point_data.arrays;
    let cd = &grid.cell_data.arrays;
    let vref_src = whole_array(pd, names::REF);
    let (cref_src, cref_from) = cell_ref_source(cd);
    let vref = refs(vref_src, np, "point")?;
    let cref = refs(cref_src, n, "cell")?;
    let corner = int_array(pd, names::CORNER);
    let vrequired = int_array(pd, names::REQUIRED);
    let ridge = int_array(cd, names::RIDGE);
    let crequired = int_array(cd, names::REQUIRED);
    let on = |a: Option<&DataArray>, i: usize| a.is_some_and(|a| a.data.get_f64(i) != 0.0);

    let mut lost: Vec<String> = Vec::new();
    let kept = |a: &DataArray, set: &[Option<&DataArray>]| {
        set.iter().any(|k| k.is_some_and(|k| std::ptr::eq(k, a)))
    };
    for a in pd {
        if !kept(a, &[vref_src, corner, vrequired]) {
            lost.push(format!("point array '{}'", a.name));
        }
    }
    for a in cd {
        if !kept(a, &[cref_src, ridge, crequired]) {
            lost.push(format!("cell array '{}'", a.name));
        }
    }
    lost.extend(
        grid.field_data
            .iter()
            .map(|a| format!("field data '{}'", a.name)),
    );
    // Flags Medit has no keyword for: said, not silently lost.
    let stray_ridges = (0..n)
        .filter(|&i| on(ridge, i) && SECTIONS[section[i]].vtk != cell_type::LINE)
        .count();
    if stray_ridges > 0 {
        lost.push(format!(
            "'{}' on {stray_ridges} cells that are not edges",
            names::RIDGE
        ));
    }
    let stray_required = (0..n)
        .filter(|&i| on(crequired, i) && SECTIONS[section[i]].required.is_none())
        .count();
    if stray_required > 0 {
        lost.push(format!(
            "'{}' on {stray_required} hexahedra, prisms or pyramids (Medit cannot flag them)",
            names::REQUIRED
        ));
    }
    // Ridges number edges, and Required* the elements of a section Medit can flag: with none in
    // the mesh, the flags go over an empty Edges section, so the array still reads back.
    let edges = section_index(&SECTIONS, cell_type::LINE);
    let flaggable = order.iter().any(|&k| SECTIONS[k].required.is_some());
    if (ridge.is_some() || (crequired.is_some() && !flaggable)) && !order.contains(&edges) {
        order.push(edges);
    }
    let voxels = grid
        .cells
        .types
        .iter()
        .filter(|&&t| t == cell_type::VOXEL || t == cell_type::PIXEL)
        .count();

    let io = |e: std::io::Error| FormatError::whole(e.to_string());
    let mut out = std::io::BufWriter::new(w);
    writeln!(out, "MeshVersionFormatted 2\n\nDimension 3\n").map_err(io)?;
    writeln!(out, "Vertices\n{np}").map_err(io)?;
    let mut line = String::with_capacity(128);
    use std::fmt::Write as _;
    for (i, r) in vref.iter().enumerate() {
        line.clear();
        // `{:?}` is the shortest text that reads back to the same value.
        let _ = match &grid.points.data {
            ArrayData::Float32(v) => {
                writeln!(
                    line,
                    "{:?} {:?} {:?} {r}",
                    v[3 * i],
                    v[3 * i + 1],
                    v[3 * i + 2]
                )
            }
            _ => {
                let p = grid.point(i);
                writeln!(line, "{:?} {:?} {:?} {r}", p[0], p[1], p[2])
            }
        };
        out.write_all(line.as_bytes()).map_err(io)?;
    }
    // Within-section numbers of the written cells, for Ridges and Required*.
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); SECTIONS.len()];
    for (i, &k) in section.iter().enumerate() {
        members[k].push(i);
    }
    for &k in &order {
        let sec = &SECTIONS[k];
        writeln!(out, "\n{}\n{}", sec.keyword, members[k].len()).map_err(io)?;
        for &i in &members[k] {
            line.clear();
            let c = grid.cells.cell(i);
            let ids: Vec<i64> = match grid.cells.types[i] {
                cell_type::VOXEL => HEX_FROM_VOXEL.iter().map(|&j| c[j]).collect(),
                cell_type::PIXEL => QUAD_FROM_PIXEL.iter().map(|&j| c[j]).collect(),
                cell_type::WEDGE => {
                    let mut v = c.to_vec();
                    super::swap_prism(&mut v);
                    v
                }
                _ => c.to_vec(),
            };
            for id in ids {
                let _ = write!(line, "{} ", id + 1);
            }
            let _ = writeln!(line, "{}", cref[i]);
            out.write_all(line.as_bytes()).map_err(io)?;
        }
    }
    let list = |out: &mut dyn Write, keyword: &str, numbers: Vec<usize>| {
        writeln!(out, "\n{keyword}\n{}", numbers.len())?;
        for x in numbers {
            writeln!(out, "{}", x + 1)?;
        }
        Ok::<(), std::io::Error>(())
    };
    if corner.is_some() {
        list(
            &mut out,
            "Corners",
            (0..np).filter(|&i| on(corner, i)).collect(),
        )
        .map_err(io)?;
    }
    if vrequired.is_some() {
        let v = (0..np).filter(|&i| on(vrequired, i)).collect();
        list(&mut out, "RequiredVertices", v).map_err(io)?;
    }
    if ridge.is_some() {
        let v = within(&members[edges], |i| on(ridge, i));
        list(&mut out, "Ridges", v).map_err(io)?;
    }
    if crequired.is_some() {
        for &k in &order {
            if let Some(kw) = SECTIONS[k].required {
                let v = within(&members[k], |i| on(crequired, i));
                list(&mut out, kw, v).map_err(io)?;
            }
        }
    }
    writeln!(out, "\nEnd").map_err(io)?;
    out.flush().map_err(io)?;
    if let Some(name) = cref_from {
        eprintln!(
            "tetkit: note: {}: cell refs written from '{name}' (the mesh has no '{}'); they read back as '{}'",
            label.display(),
            names::REF,
            names::REF
        );
    }
    if voxels > 0 {
        eprintln!(
            "tetkit: note: {}: {voxels} voxels/pixels written as Medit hexahedra/quadrilaterals (read back as such)",
            label.display()
        );
    }
    if !lost.is_empty() {
        crate::warn(&format!(
            "{}: Medit files cannot hold {}: dropped",
            label.display(),
            lost.join(", ")
        ));
    }
    Ok(())
}

fn section_index(sections: &[super::Section], vtk: u8) -> usize {
    sections.iter().position(|s| s.vtk == vtk).unwrap_or(0)
}

/// Positions (within `members`, a section's cells in written order) of the cells with `pred`.
fn within(members: &[usize], pred: impl Fn(usize) -> bool) -> Vec<usize> {
    members
        .iter()
        .enumerate()
        .filter(|&(_, &i)| pred(i))
        .map(|(k, _)| k)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Cells;

    fn to_text(g: &Grid) -> Result<String> {
        let mut out = Vec::new();
        write(&mut out, g, Path::new("t.mesh"))?;
        Ok(String::from_utf8(out).unwrap())
    }

    fn back(g: &Grid) -> Grid {
        let text = to_text(g).unwrap();
        super::super::read_bytes(text.as_bytes(), Path::new("t.mesh")).unwrap()
    }

    #[test]
    fn read_write_read_is_identity() {
        let text = "MeshVersionFormatted 2\nDimension 3\nVertices\n6\n\
            0 0 0 1\n1 0 0 2\n0 1 0 3\n0 0 1 4\n0.1 0.30000000000000004 1e-300 5\n1 1 1 -6\n\
            Tetrahedra 2 1 2 3 4 10 2 3 4 5 -20\n\
            Triangles 2 1 2 3 1 1 3 4 2\nEdges 2 1 2 0 5 6 9\n\
            Pyramids 1 1 2 3 4 5 3\nPrisms 1 1 2 3 4 5 6 4\nHexahedra 0\nQuadrilaterals 1 1 2 3 4 8\n\
            Corners 1 6 RequiredVertices 2 1 2 Ridges 1 2 RequiredEdges 1 1 \
            RequiredTetrahedra 1 2 RequiredTriangles 0 End";
        let g = super::super::read_bytes(text.as_bytes(), Path::new("t.mesh")).unwrap();
        let g2 = back(&g);
        assert_eq!(g, g2);
        // And the text itself is stable from the first write on.
        assert_eq!(to_text(&g).unwrap(), to_text(&g2).unwrap());
        assert!(to_text(&g)
            .unwrap()
            .contains("0.1 0.30000000000000004 1e-300 5\n"));
    }

    fn tet_grid() -> Grid {
        let mut g = Grid {
            points: DataArray::new(
                "Points",
                3,
                ArrayData::Float32(vec![0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 0.1]),
            ),
            cells: Cells::new(),
            ..Grid::default()
        };
        g.cells.push(cell_type::TETRA, &[0, 1, 2, 3]);
        g
    }

    #[test]
    fn refs_default_to_zero_and_other_arrays_are_dropped() {
        let mut g = tet_grid();
        g.point_data
            .arrays
            .push(DataArray::new("T", 1, ArrayData::Float64(vec![1.0; 4])));
        // Reals that are not whole are no refs (whole ones are taken: tests/medit_fixtures.rs).
        g.cell_data
            .arrays
            .push(DataArray::new(names::REF, 1, ArrayData::Float64(vec![3.5])));
        let text = to_text(&g).unwrap();
        assert!(
            text.contains("\n0.1 0.0 0.0 0\n") || text.contains("0.0 0.0 0.1 0\n"),
            "{text}"
        );
        assert!(text.contains("\n1 2 3 4 0\n"), "{text}");
        let b = back(&g);
        assert_eq!(b.points.data.get_f64(11) as f32, 0.1f32);
        assert_eq!(
            b.cell_data.get(names::REF).unwrap().data,
            ArrayData::Int32(vec![0])
        );
    }

    #[test]
    fn refs_of_any_integer_type() {
        let mut g = tet_grid();
        g.cell_data
            .arrays
            .push(DataArray::new(names::REF, 1, ArrayData::Int64(vec![-7])));
        assert!(to_text(&g).unwrap().contains("\n1 2 3 4 -7\n"));
        g.cell_data.arrays[0].data = ArrayData::Int64(vec![1 << 40]);
        let e = to_text(&g).unwrap_err().to_string();
        assert!(e.contains("medit:ref") && e.contains("32-bit"), "{e}");
    }

    #[test]
    fn cells_medit_lacks_are_refused_by_type_and_count() {
        let mut g = tet_grid();
        g.cells.push(cell_type::VERTEX, &[0]);
        g.cells.push(cell_type::VERTEX, &[1]);
        g.cells.push(cell_type::POLYGON, &[0, 1, 2]);
        let mut out = Vec::new();
        let e = write(&mut out, &g, Path::new("t.mesh"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("2 vertex cells") && e.contains("1 polygon cells"),
            "{e}"
        );
        assert!(out.is_empty(), "nothing written before the refusal");
    }

    #[test]
    fn voxels_and_pixels_become_hexahedra_and_quads() {
        let mut xyz = Vec::new();
        for k in 0..2 {
            for j in 0..2 {
                for i in 0..2 {
                    xyz.extend([i as f64, j as f64, k as f64]);
                }
            }
        }
        let mut g = Grid {
            points: DataArray::new("Points", 3, ArrayData::Float64(xyz)),
            ..Grid::default()
        };
        g.cells.push(cell_type::VOXEL, &[0, 1, 2, 3, 4, 5, 6, 7]);
        g.cells.push(cell_type::PIXEL, &[0, 1, 2, 3]);
        let b = back(&g);
        assert_eq!(b.cells.types, vec![cell_type::HEXAHEDRON, cell_type::QUAD]);
        assert_eq!(b.cells.cell(0), &[0, 1, 3, 2, 4, 5, 7, 6]);
        assert_eq!(b.cells.cell(1), &[0, 1, 3, 2]);
    }

    #[test]
    fn vertices_alone_read_back_the_same() {
        let text = "MeshVersionFormatted 2 Dimension 3 Vertices 1 1 2 3 4 Tetrahedra 0 End";
        let g = super::super::read_bytes(text.as_bytes(), Path::new("t.mesh")).unwrap();
        assert!(g.cell_data.arrays.is_empty());
        assert_eq!(back(&g), g);
    }

    #[test]
    fn flags_without_cells_to_flag_still_read_back() {
        let text = "MeshVersionFormatted 2 Dimension 3 Vertices 8 0 0 0 0 1 0 0 0 1 1 0 0 0 1 0 0 \
            0 0 1 0 1 0 1 0 1 1 1 0 0 1 1 0 Edges 0 Ridges 0 RequiredEdges 0 \
            Hexahedra 1 1 2 3 4 5 6 7 8 9 End";
        let g = super::super::read_bytes(text.as_bytes(), Path::new("t.mesh")).unwrap();
        assert!(g.cell_data.get(names::RIDGE).is_some());
        assert!(g.cell_data.get(names::REQUIRED).is_some());
        assert_eq!(back(&g), g);
    }

    /// What the fuzz target (fuzz/fuzz_targets/medit.rs) checks, on seeded mutations of two
    /// fixtures: never a panic, and whatever reads writes and reads back as the same grid.
    #[test]
    fn mutated_fixtures_read_or_fail_cleanly_and_round_trip() {
        let seeds: [&[u8]; 2] = [
            include_bytes!("../../../fixtures/medit/hand_mixed.mesh"),
            include_bytes!("../../../fixtures/medit/gmsh_hex.mesh"),
        ];
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut next = |n: usize| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x % n as u64) as usize
        };
        let (mut read, mut refused) = (0, 0);
        for k in 0..3000 {
            let mut v = seeds[k % 2].to_vec();
            for _ in 0..1 + next(3) {
                let at = next(v.len());
                match next(4) {
                    0 => {
                        v.remove(at);
                    }
                    1 => v.insert(at, b"0123456789 -\n#eE."[next(17)]),
                    2 => v.truncate(at),
                    _ => {
                        let b = next(v.len());
                        v.swap(at, b);
                    }
                }
                if v.is_empty() {
                    v.push(b' ');
                }
            }
            match super::super::read_bytes(&v, Path::new("m.mesh")) {
                Ok(g) => {
                    read += 1;
                    let text = String::from_utf8_lossy(&v);
                    g.validate().unwrap_or_else(|e| panic!("{e}: {text}"));
                    assert_eq!(back(&g), g, "{text}");
                }
                Err(e) => {
                    refused += 1;
                    assert!(e.to_string().starts_with("m.mesh: "), "{e}");
                }
            }
        }
        assert!(read > 0 && refused > 0, "{read} read, {refused} refused");
    }

    #[test]
    fn sections_follow_first_appearance() {
        let mut g = tet_grid();
        g.cells.push(cell_type::TRIANGLE, &[0, 1, 2]);
        g.cells.push(cell_type::TETRA, &[0, 2, 1, 3]);
        let text = to_text(&g).unwrap();
        let t = text.find("Tetrahedra\n2\n").unwrap();
        let f = text.find("Triangles\n1\n").unwrap();
        assert!(t < f, "{text}");
        let b = back(&g);
        assert_eq!(
            b.cells.types,
            vec![cell_type::TETRA, cell_type::TETRA, cell_type::TRIANGLE]
        );
    }
}
