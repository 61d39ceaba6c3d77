//! The dataset part of a legacy file: DATASET, FIELD, POINTS, CELLS (4.2 counts-inline or 5.1
//! OFFSETS/CONNECTIVITY), CELL_TYPES, then the attribute sections; polyhedra's face streams are
//! turned into point lists plus the face arrays VTK keeps. A POLYDATA dataset's VERTICES, LINES,
//! POLYGONS and TRIANGLE_STRIPS become cells in that order (VTK's numbering); a structured data
//! set's lattice becomes voxels or hexahedra ([`super::lattice`]).

use super::attributes::{read_field, read_metadata, read_section, read_type};
use super::cursor::{is_kw, show, Cursor};
use super::header;
use super::lattice;
use super::values::{read_numeric, read_values, LegacyType};
use crate::{cell_type, ArrayData, Cells, DataArray, FormatError, Grid, PolySection, Result};
use rayon::prelude::*;
use std::path::Path;

/// Cells as the file gives them, before the types arrive.
enum RawCells {
    /// 4.2: `npts id id ...` per cell; `at` is where the block started (for errors).
    Counts { n: usize, data: Vec<i32>, at: usize },
    /// 5.1: offsets (cells + 1) and connectivity; `conn_at`/`conn_size` locate CONNECTIVITY's
    /// values for errors.
    Offsets {
        offsets: Vec<i64>,
        conn: Vec<i64>,
        at: usize,
        conn_at: usize,
        conn_size: usize,
    },
}

/// Parses a whole legacy .vtk file held in memory.
pub fn read(bytes: &[u8]) -> Result<Grid> {
    read_labelled(bytes, "<input>")
}

/// [`read`], naming the file `label` in warnings.
fn read_labelled(bytes: &[u8], label: &str) -> Result<Grid> {
    let mut cur = Cursor::new(bytes);
    cur.label = label.to_string();
    let head = header::parse(&mut cur)?;
    read_body(cur).map(|g| vtk_hex_order(g, &head))
}

/// Files before 5.1 hold higher-order hexahedra in VTK's old edge order: converted as VTK's
/// reader converts them (see [`Grid::swap_hex_edges_10_11`]).
fn vtk_hex_order(mut grid: Grid, head: &header::Header) -> Grid {
    if (head.major, head.minor) < (5, 1) {
        grid.swap_hex_edges_10_11();
    }
    grid
}

/// Reads a legacy file from disk. BINARY files are streamed, so each big block is copied once,
/// from the file straight into its array; ASCII files are read whole (their errors name lines).
pub fn read_path(path: &Path) -> Result<Grid> {
    let io = |e| FormatError::io(path, e);
    let file = std::fs::File::open(path).map_err(io)?;
    let len = file.metadata().map_err(io)?.len();
    let len = usize::try_from(len).map_err(|_| {
        FormatError::whole("the file is larger than memory can address").with_file(path)
    })?;
    let mut cur = Cursor::from_file(&file, len);
    cur.label = path.display().to_string();
    let head = header::parse(&mut cur).map_err(|e| e.with_file(path))?;
    if !head.binary {
        let bytes = std::fs::read(path).map_err(io)?;
        return read_labelled(&bytes, &cur.label).map_err(|e| e.with_file(path));
    }
    read_body(cur)
        .map(|g| vtk_hex_order(g, &head))
        .map_err(|e| e.with_file(path))
}

impl RawCells {
    fn count(&self) -> usize {
        match self {
            RawCells::Counts { n, .. } => *n,
            RawCells::Offsets { offsets, .. } => offsets.len().saturating_sub(1),
        }
    }
}

fn poly_keyword(t: &[u8]) -> Option<PolySection> {
    PolySection::ALL.into_iter().find(|s| {
        is_kw(
            t,
            match s {
                PolySection::Verts => "VERTICES",
                PolySection::Lines => "LINES",
                PolySection::Polys => "POLYGONS",
                PolySection::Strips => "TRIANGLE_STRIPS",
            },
        )
    })
}

/// Everything after the header.
fn read_body(mut cur: Cursor<'_>) -> Result<Grid> {
    let mut grid = Grid::default();
    let mut have_dataset = false;
    // POLYDATA: each section's cells as read, and where its keyword was.
    let mut poly: Option<Vec<(PolySection, RawCells, usize)>> = None;
    let mut have_points = false;
    let mut raw: Option<RawCells> = None;
    let mut types: Option<(Vec<u8>, usize)> = None;
    // STRUCTURED_POINTS, STRUCTURED_GRID or RECTILINEAR_GRID.
    let mut lattice: Option<lattice::State> = None;
    while let Some((p, t)) = cur.keyword("a keyword")? {
        let t = &t[..];
        if is_kw(t, "DATASET") {
            let (q, kind) = cur.require("the dataset type")?;
            if have_dataset {
                return Err(cur.err(p, "a second DATASET line"));
            }
            if is_kw(&kind, "POLYDATA") {
                poly = Some(Vec::new());
            } else if let Some(k) = lattice::Kind::from_keyword(&kind) {
                lattice = Some(lattice::State::new(k, p));
            } else if !is_kw(&kind, "UNSTRUCTURED_GRID") {
                return Err(cur.err(
                    q,
                    format!(
                        "dataset type '{}' is not supported: UNSTRUCTURED_GRID, POLYDATA, STRUCTURED_POINTS, STRUCTURED_GRID and RECTILINEAR_GRID are read",
                        show(&kind)
                    ),
                ));
            }
            have_dataset = true;
        } else if !have_dataset && !is_kw(t, "FIELD") {
            return Err(cur.err(
                p,
                format!("expected DATASET UNSTRUCTURED_GRID, found '{}'", show(t)),
            ));
        } else if is_kw(t, "FIELD") {
            grid.field_data.extend(read_field(&mut cur)?);
        } else if match lattice.as_mut() {
            Some(l) => l.keyword(&mut cur, p, t)?,
            None => false,
        } {
            // A structured data set's DIMENSIONS, ORIGIN, SPACING or coordinates: read.
        } else if is_kw(t, "POINTS")
            && lattice
                .as_ref()
                .map_or(true, |l| l.kind == lattice::Kind::Grid)
        {
            let n = cur.expect_count("the number of points")?;
            let ty = read_type(&mut cur, "POINTS")?;
            if matches!(ty, LegacyType::String) {
                return Err(cur.err(p, "POINTS cannot be strings"));
            }
            let total = n
                .checked_mul(3)
                .ok_or_else(|| cur.err(p, format!("{n} points overflows")))?;
            let at = cur.pos;
            let data = read_numeric(&mut cur, ty, total, "POINTS")?;
            // Grid::validate refuses these too, but only here is the place known.
            if let Some(k) = first_non_finite(&data) {
                return Err(cur.err(
                    cur.value_at(at, k, ty.binary_size()),
                    format!(
                        "POINTS: coordinate {k} (point {}) is {}, not finite",
                        k / 3,
                        data.get_f64(k)
                    ),
                ));
            }
            let mut points = DataArray::new("Points", 3, data);
            if let Some(names) = read_metadata(&mut cur, 3)? {
                points.component_names = names;
            }
            grid.points = points;
            have_points = true;
        } else if let (Some(secs), Some(sec)) = (poly.as_mut(), poly_keyword(t)) {
            if secs.iter().any(|x| x.0 == sec) {
                return Err(cur.err(p, format!("a second {} section", show(t))));
            }
            secs.push((sec, read_cells(&mut cur, p)?, p));
        } else if poly.is_none() && lattice.is_none() && is_kw(t, "CELLS") {
            raw = Some(read_cells(&mut cur, p)?);
        } else if poly.is_none() && lattice.is_none() && is_kw(t, "CELL_TYPES") {
            let n = cur.expect_count("the number of cell types")?;
            let at = cur.pos;
            let v: Vec<i32> = read_values(&mut cur, n, "CELL_TYPES")?;
            let known = |x: i32| u8::try_from(x).is_ok_and(cell_type::is_known);
            if let Some(i) = first_where(&v, |&x| !known(x)) {
                return Err(cur.err(
                    cur.value_at(at, i, 4),
                    format!("CELL_TYPES: cell {i} has unknown type {}", v[i]),
                ));
            }
            types = Some((v.par_iter().map(|&x| x as u8).collect(), p));
        } else if is_kw(t, "POINT_DATA") || is_kw(t, "CELL_DATA") {
            let point = is_kw(t, "POINT_DATA");
            let n = cur.expect_count("the number of tuples")?;
            let expected = if let Some(l) = &lattice {
                let (np, nc) = l.counts(&cur, p)?;
                if point {
                    np
                } else {
                    nc
                }
            } else if point {
                grid.num_points()
            } else if let Some(secs) = &poly {
                secs.iter().map(|x| x.1.count()).sum()
            } else {
                types.as_ref().map_or(0, |t| t.0.len())
            };
            if n != expected {
                return Err(cur.err(
                    p,
                    format!(
                        "{} {n} does not match the {expected} {} the file declares",
                        if point { "POINT_DATA" } else { "CELL_DATA" },
                        if point { "points" } else { "cells" }
                    ),
                ));
            }
            let attrs = if point {
                &mut grid.point_data
            } else {
                &mut grid.cell_data
            };
            read_section(&mut cur, n, attrs, &mut grid.field_data)?;
        } else {
            return Err(cur.err(
                p,
                format!(
                    "unknown keyword '{}' in {}",
                    show(t),
                    match (&poly, &lattice) {
                        (Some(_), _) => "a POLYDATA",
                        (None, Some(l)) => l.kind.name(),
                        (None, None) => "an UNSTRUCTURED_GRID",
                    }
                ),
            ));
        }
    }
    if !have_dataset {
        return Err(cur.err(cur.pos, "no DATASET line before the end of the file"));
    }
    if let Some(l) = lattice {
        l.finish(&cur, &mut grid, have_points)?;
        return Ok(grid);
    }
    if !have_points && raw.is_some() {
        return Err(cur.err(
            cur.pos,
            "CELLS given but no POINTS before the end of the file",
        ));
    }
    if let Some(secs) = poly {
        if !have_points && !secs.is_empty() {
            return Err(cur.err(
                cur.pos,
                "cells given but no POINTS before the end of the file",
            ));
        }
        grid.cells = poly_cells(&cur, secs, grid.num_points())?;
        return Ok(grid);
    }
    grid.cells = match (raw, types) {
        (None, None) => Cells::new(),
        (Some(_), None) => {
            return Err(cur.err(
                cur.pos,
                "CELLS given but no CELL_TYPES before the end of the file",
            ))
        }
        (None, Some((t, p))) if !t.is_empty() => {
            return Err(cur.err(
                p,
                "CELL_TYPES given but no CELLS before the end of the file",
            ))
        }
        (None, Some(_)) => Cells::new(),
        (Some(raw), Some((t, p))) => assemble(&cur, raw, t, p, grid.num_points())?,
    };
    Ok(grid)
}

/// A POLYDATA's sections as one cell list in VTK's order, each cell typed by its section and
/// size. Each section is checked like CELLS (counts, ids in range) on its own.
fn poly_cells(
    cur: &Cursor<'_>,
    mut secs: Vec<(PolySection, RawCells, usize)>,
    np: usize,
) -> Result<Cells> {
    secs.sort_by_key(|x| PolySection::ALL.iter().position(|s| *s == x.0));
    let mut out = Cells::new();
    for (sec, raw, at) in secs {
        let n = raw.count();
        // Any non-polyhedron type serves while checking; the real types follow from the sizes.
        let c = assemble(cur, raw, vec![cell_type::POLYGON; n], at, np)?;
        let base = *out.offsets.last().unwrap_or(&0);
        for w in c.offsets.windows(2) {
            if w[1] == w[0] {
                return Err(cur.err(at, format!("{sec:?}: a cell with no points")));
            }
            out.types.push(sec.cell_type((w[1] - w[0]) as usize));
            out.offsets.push(base + w[1]);
        }
        out.connectivity.extend_from_slice(&c.connectivity);
    }
    Ok(out)
}

/// Scans in parallel blocks, each a plain loop the compiler can vectorize (rayon's
/// `position_first` pays for early exit on every element).
const SCAN: usize = 1 << 16;

/// Index of the first element where `bad` holds.
fn first_where<T: Sync>(v: &[T], bad: impl Fn(&T) -> bool + Sync) -> Option<usize> {
    v.par_chunks(SCAN)
        .enumerate()
        .filter_map(|(b, c)| c.iter().position(&bad).map(|k| b * SCAN + k))
        .min()
}

/// Index `i` of the first `v[i + 1] < v[i]`.
fn first_decrease(v: &[i64]) -> Option<usize> {
    let n = v.len().saturating_sub(1);
    (0..n.div_ceil(SCAN))
        .into_par_iter()
        .filter_map(|b| {
            let a = b * SCAN;
            let w = &v[a..(a + SCAN + 1).min(v.len())];
            w.windows(2).position(|p| p[1] < p[0]).map(|k| a + k)
        })
        .min()
}

fn first_non_finite(d: &ArrayData) -> Option<usize> {
    match d {
        ArrayData::Float32(v) => v.iter().position(|x| !x.is_finite()),
        ArrayData::Float64(v) => v.iter().position(|x| !x.is_finite()),
        _ => None,
    }
}

fn to_i64(cur: &Cursor<'_>, at: usize, what: &str, data: ArrayData) -> Result<Vec<i64>> {
    data.into_i64().map_err(|e| match e {
        Some(x) => cur.err(at, format!("{what}: {x} is too large")),
        None => cur.err(at, format!("{what} must have an integer type")),
    })
}

/// `CELLS a b`: 4.2 has `a` cells in `b` integers; 5.1 has `a` offsets and `b` connectivity
/// entries in OFFSETS and CONNECTIVITY arrays that follow.
fn read_cells(cur: &mut Cursor<'_>, at: usize) -> Result<RawCells> {
    let a = cur.expect_count("the CELLS count")?;
    let b = cur.expect_count("the CELLS size")?;
    match cur.peek_keyword("OFFSETS or the cell list")? {
        Some((_, t)) if is_kw(&t, "OFFSETS") => {
            cur.token();
            let ty = read_type(cur, "OFFSETS")?;
            let q = cur.pos;
            let offsets = read_numeric(cur, ty, a, "OFFSETS")?;
            let offsets = to_i64(cur, q, "OFFSETS", offsets)?;
            read_metadata(cur, 1)?;
            let (q, t) = cur.require("CONNECTIVITY")?;
            if !is_kw(&t, "CONNECTIVITY") {
                return Err(cur.err(
                    q,
                    format!("expected CONNECTIVITY after OFFSETS, found '{}'", show(&t)),
                ));
            }
            let ty = read_type(cur, "CONNECTIVITY")?;
            let conn_at = cur.pos;
            let conn = read_numeric(cur, ty, b, "CONNECTIVITY")?;
            let conn = to_i64(cur, conn_at, "CONNECTIVITY", conn)?;
            read_metadata(cur, 1)?;
            Ok(RawCells::Offsets {
                offsets,
                conn,
                at,
                conn_at,
                conn_size: ty.binary_size(),
            })
        }
        _ => {
            // Each cell takes at least its count entry.
            if a > b {
                return Err(cur.err(at, format!("CELLS declares {a} cells in {b} integers")));
            }
            let at = cur.pos;
            let data: Vec<i32> = read_values(cur, b, "CELLS")?;
            Ok(RawCells::Counts { n: a, data, at })
        }
    }
}

/// Builds offsets/connectivity from the raw cells, checking every count and point id against
/// what is there, and expands polyhedron face streams.
fn assemble(
    cur: &Cursor<'_>,
    raw: RawCells,
    types: Vec<u8>,
    types_at: usize,
    np: usize,
) -> Result<Cells> {
    let np = np as i64;
    let out_of_range = |x: i64| x < 0 || x >= np;
    let count_check = |ncells: usize| {
        if types.len() != ncells {
            return Err(cur.err(
                types_at,
                format!("CELL_TYPES has {} entries for {ncells} cells", types.len()),
            ));
        }
        Ok(())
    };
    let (offsets, conn, at) = match raw {
        RawCells::Offsets {
            offsets,
            conn,
            at,
            conn_at,
            conn_size,
        } => {
            let offsets = if offsets.is_empty() { vec![0] } else { offsets };
            if offsets[0] != 0 {
                return Err(cur.err(at, format!("OFFSETS starts at {}, expected 0", offsets[0])));
            }
            if let Some(i) = first_decrease(&offsets) {
                return Err(cur.err(
                    at,
                    format!(
                        "OFFSETS decrease at cell {i} ({} then {})",
                        offsets[i],
                        offsets[i + 1]
                    ),
                ));
            }
            let last = *offsets.last().unwrap_or(&0);
            if last != conn.len() as i64 {
                return Err(cur.err(
                    at,
                    format!(
                        "OFFSETS end at {last} but CONNECTIVITY has {} entries",
                        conn.len()
                    ),
                ));
            }
            count_check(offsets.len() - 1)?;
            let bad = if types.contains(&cell_type::POLYHEDRON) {
                (0..types.len())
                    .filter(|&i| types[i] != cell_type::POLYHEDRON)
                    .find_map(|i| {
                        let (s, e) = (offsets[i] as usize, offsets[i + 1] as usize);
                        conn[s..e]
                            .iter()
                            .position(|&x| out_of_range(x))
                            .map(|m| s + m)
                    })
            } else {
                conn.iter().position(|&x| out_of_range(x))
            };
            if let Some(k) = bad {
                return Err(cur.err(
                    cur.value_at(conn_at, k, conn_size),
                    format!(
                        "CONNECTIVITY: point id {} is out of range ({})",
                        conn[k],
                        crate::error::numbered(np as u64, "point", 0)
                    ),
                ));
            }
            (offsets, conn, at)
        }
        RawCells::Counts { n, data, at } => {
            count_check(n)?;
            let (offsets, conn) = split_counts(cur, &data, &types, at, np)?;
            (offsets, conn, at)
        }
    };
    if !types.contains(&cell_type::POLYHEDRON) {
        return Ok(Cells {
            types,
            offsets,
            connectivity: conn,
            polyhedron_faces: None,
        });
    }
    expand_polyhedra(cur, at, types, &offsets, &conn, np)
}

/// 4.2's `npts id id ...` stream into offsets and connectivity. The counts are walked once
/// (they decide where every cell starts), then ids are copied and checked in parallel: cell i's
/// ids start at `offsets[i] + i + 1` in the stream.
fn split_counts(
    cur: &Cursor<'_>,
    data: &[i32],
    types: &[u8],
    at: usize,
    np: i64,
) -> Result<(Vec<i64>, Vec<i64>)> {
    let n = types.len();
    let mut offsets = Vec::with_capacity(n + 1);
    offsets.push(0i64);
    let mut k = 0usize;
    for i in 0..n {
        let npts = data
            .get(k)
            .copied()
            .ok_or_else(|| cur.err(at, format!("CELLS: the data ends before cell {i} of {n}")))?;
        let end = usize::try_from(npts)
            .ok()
            .and_then(|m| (k + 1).checked_add(m))
            .filter(|&e| e <= data.len())
            .ok_or_else(|| {
                cur.err(
                    at,
                    format!("CELLS: cell {i} declares {npts} points, more than the block holds"),
                )
            })?;
        offsets.push((end - i - 1) as i64);
        k = end;
    }
    if k != data.len() {
        return Err(cur.err(
            at,
            format!(
                "CELLS: {n} cells use {k} of the {} declared integers",
                data.len()
            ),
        ));
    }
    let mut conn: Vec<i64> = bytemuck::zeroed_vec(data.len() - n);
    // Cells in blocks; each block owns a contiguous piece of `conn`.
    const BLOCK: usize = 1 << 15;
    let mut pieces = Vec::with_capacity(n / BLOCK + 1);
    let mut rest: &mut [i64] = &mut conn;
    for c0 in (0..n).step_by(BLOCK) {
        let c1 = (c0 + BLOCK).min(n);
        let (piece, tail) = rest.split_at_mut((offsets[c1] - offsets[c0]) as usize);
        pieces.push((c0, c1, piece));
        rest = tail;
    }
    let bad = pieces
        .into_par_iter()
        .filter_map(|(c0, c1, piece)| {
            let first = offsets[c0] as usize;
            for i in c0..c1 {
                let (s, e) = (offsets[i] as usize, offsets[i + 1] as usize);
                let src = &data[s + i + 1..e + i + 1];
                let dst = &mut piece[s - first..e - first];
                for (d, &x) in dst.iter_mut().zip(src) {
                    *d = x as i64;
                }
                if types[i] != cell_type::POLYHEDRON {
                    if let Some(m) = dst.iter().position(|&x| x < 0 || x >= np) {
                        return Some((i, s + i + 1 + m, dst[m]));
                    }
                }
            }
            None
        })
        .min();
    if let Some((i, k, x)) = bad {
        return Err(cur.err(
            cur.value_at(at, k, 4),
            format!(
                "CELLS: cell {i} has point id {x}, out of range ({})",
                crate::error::numbered(np as u64, "point", 0)
            ),
        ));
    }
    Ok((offsets, conn))
}

/// A polyhedron's entry is its face stream `nfaces, n0, ids.., n1, ids..`; VTK keeps the sorted
/// unique point ids as the cell's points and the stream as its faces.
fn expand_polyhedra(
    cur: &Cursor<'_>,
    at: usize,
    types: Vec<u8>,
    offsets: &[i64],
    conn: &[i64],
    np: i64,
) -> Result<Cells> {
    let mut cells = Cells::new();
    let mut faces = Vec::new();
    let mut face_offsets = Vec::with_capacity(types.len());
    for (i, &t) in types.iter().enumerate() {
        let s = &conn[offsets[i] as usize..offsets[i + 1] as usize];
        if t != cell_type::POLYHEDRON {
            cells.push(t, s);
            face_offsets.push(-1);
            continue;
        }
        let bad = |m: &str| cur.err(at, format!("polyhedron cell {i}: {m}"));
        let nf = *s.first().ok_or_else(|| bad("empty face stream"))?;
        let nf = usize::try_from(nf).map_err(|_| bad("negative face count"))?;
        let mut k = 1usize;
        let mut ids = Vec::new();
        for f in 0..nf {
            let nfp = *s
                .get(k)
                .ok_or_else(|| bad(&format!("the stream ends before face {f}")))?;
            let end = usize::try_from(nfp)
                .ok()
                .and_then(|m| (k + 1).checked_add(m))
                .filter(|&e| e <= s.len())
                .ok_or_else(|| {
                    bad(&format!(
                        "face {f} declares {nfp} points, more than the stream holds"
                    ))
                })?;
            let face = &s[k + 1..end];
            if let Some(&x) = face.iter().find(|&&x| x < 0 || x >= np) {
                return Err(bad(&format!(
                    "face {f} has point id {x}, out of range ({})",
                    crate::error::numbered(np as u64, "point", 0)
                )));
            }
            ids.extend_from_slice(face);
            k = end;
        }
        if k != s.len() {
            return Err(bad(&format!("{} entries after the last face", s.len() - k)));
        }
        ids.sort_unstable();
        ids.dedup();
        cells.push(t, &ids);
        faces.extend_from_slice(s);
        face_offsets.push(faces.len() as i64);
    }
    cells.polyhedron_faces = Some((faces, face_offsets));
    Ok(cells)
}
