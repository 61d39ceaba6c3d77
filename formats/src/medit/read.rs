//! Reading an ASCII Medit file into a [`Grid`].

use super::tokens::{show, Tokens};
use super::{names, SECTIONS};
use crate::{ArrayData, Cells, DataArray, FormatError, Grid, Result};
use std::path::Path;

/// Reads a `.mesh` file. A binary `.meshb` is refused by [`crate::Format::from_path`].
pub fn read(path: &Path) -> Result<Grid> {
    let bytes = std::fs::read(path).map_err(|e| FormatError::io(path, e))?;
    read_bytes(&bytes, path)
}

/// Sections that carry no mesh (normals, tangents): skipped with a warning. Their records are
/// vectors (one real per dimension) or tuples of integers (vertex, normal/tangent and element
/// numbers).
const SKIPPED: [(&str, Record); 8] = [
    ("Normals", Record::PerDimension),
    ("Tangents", Record::PerDimension),
    ("NormalAtVertices", Record::Ints(2)),
    ("NormalAtTriangleVertices", Record::Ints(3)),
    ("NormalAtQuadrilateralVertices", Record::Ints(3)),
    ("TangentAtVertices", Record::Ints(2)),
    ("TangentAtEdgeVertices", Record::Ints(3)),
    ("TangentAtEdges", Record::Ints(3)),
];

#[derive(Clone, Copy)]
enum Record {
    PerDimension,
    Ints(usize),
}

/// Higher-order sections tetkit does not read (their node orders are not VTK's, and nothing
/// downstream needs them yet).
const HIGH_ORDER: [&str; 7] = [
    "EdgesP2",
    "TrianglesP2",
    "QuadrilateralsQ2",
    "TetrahedraP2",
    "HexahedraQ2",
    "PrismsP2",
    "PyramidsP2",
];

/// Where each element section's cells sit in the grid, for the `Required*` and `Ridges` lists
/// that number elements within a section.
#[derive(Clone, Copy)]
struct Placed {
    first: usize,
    count: usize,
}

#[derive(Default)]
struct State {
    dim: Option<usize>,
    /// Vertex count once `Vertices` is read.
    vertices: Option<usize>,
    xyz: Vec<f64>,
    vref: Vec<i32>,
    cells: Cells,
    cref: Vec<i32>,
    placed: [Option<Placed>; 7],
    corner: Option<Vec<usize>>,
    vrequired: Option<Vec<usize>>,
    ridge: Option<Vec<usize>>,
    crequired: Option<Vec<usize>>,
}

/// Room for `n` records of `per` values, bounded by what the rest of the file can hold (a value
/// takes at least 2 bytes), so a huge declared count reserves nothing the data does not back.
fn capacity(n: usize, t: &Tokens<'_>, per: usize) -> usize {
    n.saturating_mul(per).min(t.remaining() / 2 + 1)
}

fn count(t: &mut Tokens<'_>, keyword: &str) -> Result<(usize, usize)> {
    let what = format!("the number of {keyword}");
    let (n, line) = t.int(&what)?;
    let n = usize::try_from(n)
        .map_err(|_| t.err(line, format!("{what} is {n}, must not be negative")))?;
    Ok((n, line))
}

fn reference(t: &mut Tokens<'_>, what: &str) -> Result<i32> {
    let (r, line) = t.int(what)?;
    i32::try_from(r).map_err(|_| t.err(line, format!("{what} {r} does not fit 32 bits")))
}

/// Reads a Medit file from memory; `path` names it in errors.
pub fn read_bytes(bytes: &[u8], path: &Path) -> Result<Grid> {
    let mut t = Tokens::new(bytes, path);
    let mut s = State {
        cells: Cells::new(),
        ..State::default()
    };
    let mut version = false;
    loop {
        let Some((kw, line)) = t.next_token() else {
            return Err(t.err(t.last_line(), "the file ends without End (truncated?)"));
        };
        let key = String::from_utf8_lossy(kw).to_ascii_lowercase();
        if !version && key != "meshversionformatted" {
            return Err(t.err(
                line,
                format!(
                    "'{}' before MeshVersionFormatted, which a Medit file starts with",
                    show(kw)
                ),
            ));
        }
        match key.as_str() {
            "end" => break,
            "meshversionformatted" => {
                if version {
                    return Err(t.err(line, "a second MeshVersionFormatted"));
                }
                let (v, vline) = t.int("the MeshVersionFormatted version")?;
                // 1: single-precision reals, 2: double, 3: 64-bit integers, 4: 64-bit everything;
                // in ASCII only the width of integers changes, and they are read as 64 bits anyway.
                if !(1..=4).contains(&v) {
                    return Err(t.err(
                        vline,
                        format!("MeshVersionFormatted {v}: expected 1, 2, 3 or 4"),
                    ));
                }
                version = true;
            }
            "dimension" => {
                if s.dim.is_some() {
                    return Err(t.err(line, "a second Dimension"));
                }
                let (d, dline) = t.int("the dimension")?;
                if d != 2 && d != 3 {
                    return Err(t.err(
                        dline,
                        format!("Dimension {d}: tetkit reads 3-D meshes (and 2-D ones, at z = 0)"),
                    ));
                }
                s.dim = Some(d as usize);
            }
            "vertices" => read_vertices(&mut t, &mut s, line)?,
            "corners" => {
                let list = vertex_list(&mut t, &s, "Corners", line)?;
                s.corner.get_or_insert_with(Vec::new).extend(list);
            }
            "requiredvertices" => {
                let list = vertex_list(&mut t, &s, "RequiredVertices", line)?;
                s.vrequired.get_or_insert_with(Vec::new).extend(list);
            }
            "ridges" => {
                let list = element_list(&mut t, &s, 0, "Ridges", line)?;
                s.ridge.get_or_insert_with(Vec::new).extend(list);
            }
            _ => {
                if let Some(k) = SECTIONS
                    .iter()
                    .position(|x| x.keyword.eq_ignore_ascii_case(&key))
                {
                    read_elements(&mut t, &mut s, k, line)?;
                } else if let Some(k) = SECTIONS
                    .iter()
                    .position(|x| x.required.is_some_and(|r| r.eq_ignore_ascii_case(&key)))
                {
                    let kw = SECTIONS[k].required.unwrap_or_default();
                    let list = element_list(&mut t, &s, k, kw, line)?;
                    s.crequired.get_or_insert_with(Vec::new).extend(list);
                } else if let Some((name, rec)) =
                    SKIPPED.iter().find(|(n, _)| n.eq_ignore_ascii_case(&key))
                {
                    skip(&mut t, &s, name, *rec, line)?;
                } else if let Some(name) = HIGH_ORDER.iter().find(|n| n.eq_ignore_ascii_case(&key))
                {
                    return Err(t.err(
                        line,
                        format!(
                            "{name}: tetkit reads linear Medit elements only, not P2/Q2 sections"
                        ),
                    ));
                } else {
                    return Err(t.err(
                        line,
                        format!("unknown Medit keyword '{}' (Medit sections have no length to skip them by)", show(kw)),
                    ));
                }
            }
        }
    }
    if let Some((tok, line)) = t.next_token() {
        return Err(t.err(line, format!("'{}' after End", show(tok))));
    }
    finish(s)
}

fn dimension(t: &Tokens<'_>, s: &State, keyword: &str, line: usize) -> Result<usize> {
    s.dim
        .ok_or_else(|| t.err(line, format!("{keyword} before Dimension")))
}

fn vertex_count(t: &Tokens<'_>, s: &State, keyword: &str, line: usize) -> Result<usize> {
    s.vertices.ok_or_else(|| {
        t.err(
            line,
            format!("{keyword} before Vertices (tetkit needs the vertices first)"),
        )
    })
}

fn read_vertices(t: &mut Tokens<'_>, s: &mut State, line: usize) -> Result<()> {
    let dim = dimension(t, s, "Vertices", line)?;
    if s.vertices.is_some() {
        return Err(t.err(line, "a second Vertices section"));
    }
    let (n, _) = count(t, "Vertices")?;
    s.xyz = Vec::with_capacity(capacity(n, t, 3));
    s.vref = Vec::with_capacity(capacity(n, t, 1));
    for i in 1..=n {
        for k in 0..dim {
            let (v, vline) = t.real(&format!("coordinate {} of vertex {i} of {n}", k + 1))?;
            if !v.is_finite() {
                return Err(t.err(vline, format!("vertex {i}: coordinate {v} is not finite")));
            }
            s.xyz.push(v);
        }
        if dim == 2 {
            s.xyz.push(0.0);
        }
        s.vref
            .push(reference(t, &format!("the ref of vertex {i}"))?);
    }
    s.vertices = Some(n);
    Ok(())
}

fn read_elements(t: &mut Tokens<'_>, s: &mut State, k: usize, line: usize) -> Result<()> {
    let sec = &SECTIONS[k];
    let nv = vertex_count(t, s, sec.keyword, line)?;
    if s.placed[k].is_some() {
        return Err(t.err(line, format!("a second {} section", sec.keyword)));
    }
    let (n, _) = count(t, sec.keyword)?;
    let first = s.cells.len();
    let room = capacity(n, t, sec.nodes + 1);
    s.cells.connectivity.reserve(room);
    s.cells.types.reserve(room / (sec.nodes + 1));
    s.cells.offsets.reserve(room / (sec.nodes + 1));
    s.cref.reserve(room / (sec.nodes + 1));
    let mut ids = [0i64; 8];
    for e in 1..=n {
        for (j, id) in ids.iter_mut().take(sec.nodes).enumerate() {
            let (v, vline) = t.int(&format!(
                "vertex {} of {} element {e} of {n}",
                j + 1,
                sec.keyword
            ))?;
            if v < 1 || v as u64 > nv as u64 {
                return Err(t.err(
                    vline,
                    format!(
                        "{} element {e}: vertex number {v} is out of range (the file has {nv} vertices, numbered from 1)",
                        sec.keyword
                    ),
                ));
            }
            *id = v - 1;
        }
        if sec.vtk == crate::cell_type::WEDGE {
            super::swap_prism(&mut ids);
        }
        s.cells.push(sec.vtk, &ids[..sec.nodes]);
        s.cref.push(reference(
            t,
            &format!("the ref of {} element {e}", sec.keyword),
        )?);
    }
    s.placed[k] = Some(Placed { first, count: n });
    Ok(())
}

/// `Corners`/`RequiredVertices`: 0-based vertex indices.
fn vertex_list(t: &mut Tokens<'_>, s: &State, keyword: &str, line: usize) -> Result<Vec<usize>> {
    let nv = vertex_count(t, s, keyword, line)?;
    let (n, _) = count(t, keyword)?;
    let mut out = Vec::with_capacity(capacity(n, t, 1));
    for i in 1..=n {
        let (v, vline) = t.int(&format!("entry {i} of {keyword}"))?;
        if v < 1 || v as u64 > nv as u64 {
            return Err(t.err(
                vline,
                format!("{keyword} entry {i}: vertex number {v} is out of range (the file has {nv} vertices, numbered from 1)"),
            ));
        }
        out.push(v as usize - 1);
    }
    Ok(out)
}

/// `Ridges`/`Required<Elements>`: grid cell indices of elements numbered within section `k`.
fn element_list(
    t: &mut Tokens<'_>,
    s: &State,
    k: usize,
    keyword: &str,
    line: usize,
) -> Result<Vec<usize>> {
    let sec = SECTIONS[k].keyword;
    let placed = s.placed[k].ok_or_else(|| {
        t.err(
            line,
            format!("{keyword} before the {sec} it numbers (tetkit needs the {sec} first)"),
        )
    })?;
    let (n, _) = count(t, keyword)?;
    let mut out = Vec::with_capacity(capacity(n, t, 1));
    for i in 1..=n {
        let (v, vline) = t.int(&format!("entry {i} of {keyword}"))?;
        if v < 1 || v as u64 > placed.count as u64 {
            return Err(t.err(
                vline,
                format!(
                    "{keyword} entry {i}: {sec} number {v} is out of range (the file has {} {sec}, numbered from 1)",
                    placed.count
                ),
            ));
        }
        out.push(placed.first + v as usize - 1);
    }
    Ok(out)
}

/// Reads past a section tetkit does not keep, checking its records are numbers.
fn skip(t: &mut Tokens<'_>, s: &State, name: &str, rec: Record, line: usize) -> Result<()> {
    let per = match rec {
        Record::PerDimension => dimension(t, s, name, line)?,
        Record::Ints(k) => k,
    };
    let (n, _) = count(t, name)?;
    for i in 1..=n {
        for _ in 0..per {
            match rec {
                Record::PerDimension => {
                    t.real(&format!("a value of {name} entry {i}"))?;
                }
                Record::Ints(_) => {
                    t.int(&format!("a value of {name} entry {i}"))?;
                }
            }
        }
    }
    crate::warn(&format!(
        "{}: line {line}: {name} ({n} entries) skipped: tetkit does not keep Medit normals or tangents",
        t.path().display()
    ));
    Ok(())
}

fn flags(n: usize, on: &[usize]) -> ArrayData {
    let mut v = vec![0u8; n];
    for &i in on {
        v[i] = 1;
    }
    ArrayData::UInt8(v)
}

fn finish(s: State) -> Result<Grid> {
    let mut g = Grid {
        cells: s.cells,
        ..Grid::default()
    };
    let np = s.vertices.unwrap_or(0);
    g.points = DataArray::new("Points", 3, ArrayData::Float64(s.xyz));
    if s.vertices.is_some() {
        g.point_data
            .arrays
            .push(DataArray::new(names::REF, 1, ArrayData::Int32(s.vref)));
    }
    if let Some(c) = &s.corner {
        g.point_data
            .arrays
            .push(DataArray::new(names::CORNER, 1, flags(np, c)));
    }
    if let Some(c) = &s.vrequired {
        g.point_data
            .arrays
            .push(DataArray::new(names::REQUIRED, 1, flags(np, c)));
    }
    let nc = g.cells.len();
    // Without cells there is nothing to attach cell arrays to (and the writer writes no empty
    // element sections), so a mesh of vertices reads back the same after a write.
    if nc == 0 {
        return Ok(g);
    }
    g.cell_data
        .arrays
        .push(DataArray::new(names::REF, 1, ArrayData::Int32(s.cref)));
    if let Some(c) = &s.ridge {
        g.cell_data
            .arrays
            .push(DataArray::new(names::RIDGE, 1, flags(nc, c)));
    }
    if let Some(c) = &s.crequired {
        g.cell_data
            .arrays
            .push(DataArray::new(names::REQUIRED, 1, flags(nc, c)));
    }
    Ok(g)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cell_type;

    fn read(text: &str) -> Result<Grid> {
        read_bytes(text.as_bytes(), Path::new("t.mesh"))
    }

    /// The error for `text`, which must name the file and contain every needle.
    #[track_caller]
    fn refused(text: &str, needles: &[&str]) {
        let e = read(text).expect_err("should be refused").to_string();
        assert!(e.starts_with("t.mesh: "), "{e}");
        for n in needles {
            assert!(e.contains(n), "{e:?} lacks {n:?}");
        }
    }

    const CUBE: &str = "# two elements\nMeshVersionFormatted 2\nDimension\n3\nVertices\n5\n\
        0 0 0 1\n1 0 0 2\n0 1 0 3\n0 0 1 4\n1 1 1 5\n\
        edges 1\n1 2 7\n\
        Triangles\n2\n1 2 3 10\n1 3 4 11\n\
        Tetrahedra 1 1 2 3 4 -3\n\
        Corners 2 1 5\nRequiredVertices 1 2\nRidges 1 1\nRequiredTriangles\n1\n2\n\
        NormalAtVertices 1 1 1\nNormals 1 0 0 1\nEND\n";

    #[test]
    fn sections_refs_and_flags() {
        let g = read(CUBE).unwrap();
        g.validate().unwrap();
        assert_eq!(g.num_points(), 5);
        assert_eq!(g.point(4), [1.0, 1.0, 1.0]);
        assert_eq!(
            g.cells.types,
            vec![
                cell_type::LINE,
                cell_type::TRIANGLE,
                cell_type::TRIANGLE,
                cell_type::TETRA
            ]
        );
        assert_eq!(g.cells.cell(3), &[0, 1, 2, 3]);
        let p = &g.point_data;
        assert_eq!(
            p.get(names::REF).unwrap().data,
            ArrayData::Int32(vec![1, 2, 3, 4, 5])
        );
        assert_eq!(
            p.get(names::CORNER).unwrap().data,
            ArrayData::UInt8(vec![1, 0, 0, 0, 1])
        );
        assert_eq!(
            p.get(names::REQUIRED).unwrap().data,
            ArrayData::UInt8(vec![0, 1, 0, 0, 0])
        );
        let c = &g.cell_data;
        assert_eq!(
            c.get(names::REF).unwrap().data,
            ArrayData::Int32(vec![7, 10, 11, -3])
        );
        assert_eq!(
            c.get(names::RIDGE).unwrap().data,
            ArrayData::UInt8(vec![1, 0, 0, 0])
        );
        assert_eq!(
            c.get(names::REQUIRED).unwrap().data,
            ArrayData::UInt8(vec![0, 0, 1, 0])
        );
    }

    #[test]
    fn two_dimensions_at_z_zero() {
        let g = read("MeshVersionFormatted 1 Dimension 2 Vertices 3 0 0 0 1 0 0 0 1 0 Triangles 1 1 2 3 4 End").unwrap();
        assert_eq!(g.point(1), [1.0, 0.0, 0.0]);
        assert_eq!(g.cells.types, vec![cell_type::TRIANGLE]);
    }

    #[test]
    fn huge_counts_reserve_nothing() {
        refused(
            "MeshVersionFormatted 2\nDimension 3\nVertices\n9223372036854775807\n0 0 0 0\n",
            &["line 5", "ends", "vertex 2"],
        );
        refused(
            "MeshVersionFormatted 2 Dimension 3 Vertices 1 0 0 0 0\nTetrahedra 4000000000000\n",
            &["line 2", "ends", "Tetrahedra element 1"],
        );
    }

    #[test]
    fn every_error_names_its_place() {
        let head = "MeshVersionFormatted 2\nDimension 3\nVertices\n3\n0 0 0 0\n1 0 0 0\n0 1 0 0\n";
        let cases: Vec<(String, Vec<&str>)> = vec![
            ("".into(), vec!["without End"]),
            (
                "Dimension 3\n".into(),
                vec!["line 1", "before MeshVersionFormatted"],
            ),
            (
                "MeshVersionFormatted 7\n".into(),
                vec!["line 1", "MeshVersionFormatted 7"],
            ),
            (
                "MeshVersionFormatted 2 Dimension 4\n".into(),
                vec!["Dimension 4"],
            ),
            (
                "MeshVersionFormatted 2 Vertices 1 0 0 0 0\n".into(),
                vec!["Vertices before Dimension"],
            ),
            (
                "MeshVersionFormatted 2 Dimension 3 Triangles 0 End".into(),
                vec!["Triangles before Vertices"],
            ),
            (head.to_string(), vec!["line 7", "without End"]),
            (
                format!("{head}Triangles\n1\n1 2 3\n"),
                vec!["line 10", "ref of Triangles element 1"],
            ),
            (
                format!("{head}Triangles\n1\n1 2 4 0\nEnd\n"),
                vec![
                    "line 10",
                    "Triangles element 1",
                    "vertex number 4",
                    "out of range",
                ],
            ),
            (
                format!("{head}Triangles\n1\n1 0 3 0\nEnd\n"),
                vec!["line 10", "vertex number 0"],
            ),
            (
                format!("{head}Triangles\n1\n1 -2 3 0\nEnd\n"),
                vec!["vertex number -2"],
            ),
            (
                format!("{head}Triangles\n-1\nEnd\n"),
                vec!["line 9", "must not be negative"],
            ),
            (
                format!("{head}Triangles\nx\nEnd\n"),
                vec!["line 9", "'x', not an integer"],
            ),
            (
                format!("{head}Triangles\n1\n1 2.5 3 0\nEnd\n"),
                vec!["line 10", "'2.5'"],
            ),
            (
                format!("{head}Triangles 1 1 2 3 3000000000 End"),
                vec!["does not fit 32 bits"],
            ),
            (
                format!("{head}Corners 1 4 End"),
                vec!["Corners entry 1", "vertex number 4"],
            ),
            (
                format!("{head}Ridges 1 1 End"),
                vec!["Ridges before the Edges"],
            ),
            (
                format!("{head}Edges 1 1 2 0 Ridges 1 2 End"),
                vec!["Ridges entry 1", "Edges number 2"],
            ),
            (
                format!("{head}Edges 1 1 2 0 RequiredEdges 1 0 End"),
                vec!["RequiredEdges entry 1"],
            ),
            (
                format!("{head}TetrahedraP2 0 End"),
                vec!["line 8", "TetrahedraP2", "P2"],
            ),
            (
                format!("{head}Foo 0 End"),
                vec!["line 8", "unknown Medit keyword 'Foo'"],
            ),
            (format!("{head}Vertices 0 End"), vec!["second Vertices"]),
            (format!("{head}Edges 0 Edges 0 End"), vec!["second Edges"]),
            (format!("{head}End\nVertices"), vec!["line 9", "after End"]),
            (
                "MeshVersionFormatted 2 Dimension 3 Vertices 1 0 nan 0 0 End".into(),
                vec!["not finite"],
            ),
            (
                "MeshVersionFormatted 2 Dimension 3 Vertices 1 0 zz 0 0 End".into(),
                vec!["coordinate 2 of vertex 1", "'zz', not a number"],
            ),
            (
                format!("{head}Normals 1 0 0 End"),
                vec!["'End', not a number"],
            ),
        ];
        for (text, needles) in cases {
            let e = read(&text).expect_err(&text).to_string();
            assert!(e.starts_with("t.mesh: "), "{e}");
            for n in needles {
                assert!(e.contains(n), "{text:?}: {e:?} lacks {n:?}");
            }
        }
    }

    #[test]
    fn case_and_layout_do_not_matter() {
        let g = read("meshversionformatted 3\n# c\nDIMENSION 3 VERTICES 1 0.5 -2e-3 1E2 9 end")
            .unwrap();
        assert_eq!(g.point(0), [0.5, -0.002, 100.0]);
        assert!(g.cell_data.arrays.is_empty());
    }
}
