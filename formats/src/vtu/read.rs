//! Assembles a [`Grid`] from a parsed .vtu (or .vtp, whose verts, lines, polys and strips become
//! cells in that order, VTK's own cell numbering; or .vti/.vtr/.vts, whose lattice cells become
//! voxels or hexahedra, see [`crate::structured`]): arrays decoded in parallel, pieces merged in
//! order.

use super::decode::{self, Appended, Input};
use super::source::{Blob, FileBlob, MemBlob};
use super::xml::{self, ArrayXml, AttributesXml, Document, ElemType, PieceXml, StructuredXml};
use crate::structured::{self, Lattice};
use crate::{ArrayData, Attributes, Cells, DataArray, FormatError, Grid, Result};
use rayon::prelude::*;
use std::path::Path;

/// Parses a whole .vtu file held in memory. The grid is not validated here (see [`crate::read`]).
pub fn read(bytes: &[u8]) -> Result<Grid> {
    let doc = xml::parse(bytes)?;
    build(&doc, &MemBlob(bytes))
}

/// Reads a .vtu file: the XML through a buffered reader, the appended block with positioned
/// reads straight into the arrays (so the file is never held in memory beside the mesh). Errors
/// name the file. The grid is not validated here (see [`crate::read`]).
pub fn read_path(path: &Path) -> Result<Grid> {
    let io = |e: std::io::Error| FormatError::io(path, e);
    let file = std::fs::File::open(path).map_err(io)?;
    let len = file.metadata().map_err(io)?.len();
    let doc = xml::parse(std::io::BufReader::with_capacity(1 << 16, &file))
        .map_err(|e| e.with_file(path))?;
    let blob = FileBlob { file, len };
    build(&doc, &blob).map_err(|e| e.with_file(path))
}

/// Finds the `_` that starts the appended data, after the `<AppendedData>` tag and any blanks.
fn appended<'a>(doc: &Document, blob: &'a dyn Blob) -> Result<Option<Appended<'a>>> {
    let Some(app) = doc.appended else {
        return Ok(None);
    };
    let mut pos = app.tag_end;
    let mut buf = [0u8; 256];
    loop {
        let n = (blob.len().saturating_sub(pos)).min(buf.len() as u64) as usize;
        if n == 0 {
            return Err(FormatError::at_byte(
                app.tag_end,
                "<AppendedData> has no '_' marker (truncated?)",
            ));
        }
        blob.read_at(pos, &mut buf[..n])
            .map_err(|e| FormatError::at_byte(pos, e.to_string()))?;
        match buf[..n].iter().position(|b| !b.is_ascii_whitespace()) {
            Some(i) if buf[i] == b'_' => {
                pos += i as u64 + 1;
                break;
            }
            Some(i) => {
                return Err(FormatError::at_byte(
                    pos + i as u64,
                    "expected the '_' that starts the appended data",
                ))
            }
            None => pos += n as u64,
        }
    }
    // A file cut short inside its appended block still has intact XML; its missing end says so.
    let tail_len = blob.len().min(256);
    let mut tail = vec![0u8; tail_len as usize];
    blob.read_at(blob.len() - tail_len, &mut tail)
        .map_err(|e| FormatError::at_byte(blob.len(), e.to_string()))?;
    if !tail.trim_ascii_end().ends_with(b"</VTKFile>") {
        return Err(FormatError::at_byte(
            blob.len(),
            "the file does not end with </VTKFile> (truncated?)",
        ));
    }
    let mut offsets: Vec<u64> = all_arrays(doc).filter_map(|a| a.offset).collect();
    offsets.sort_unstable();
    offsets.dedup();
    Ok(Some(Appended {
        blob,
        start: pos,
        raw: app.raw,
        offsets,
    }))
}

fn all_arrays(doc: &Document) -> impl Iterator<Item = &ArrayXml> {
    doc.field_data.iter().chain(doc.pieces.iter().flat_map(|p| {
        p.point_data
            .arrays
            .iter()
            .chain(&p.cell_data.arrays)
            .chain(&p.points)
            .chain(&p.cells)
            .chain(&p.coordinates)
            .chain(p.poly.iter().flat_map(|s| &s.2))
    }))
}

fn build(doc: &Document, blob: &dyn Blob) -> Result<Grid> {
    let inp = Input {
        layout: doc.layout,
        appended: appended(doc, blob)?,
    };
    let field_data = doc
        .field_data
        .par_iter()
        .map(|a| {
            let need = match a.tuples {
                Some(t) => Some(values(a, t)?),
                None => None,
            };
            array(&inp, a, need)
        })
        .collect::<Result<Vec<_>>>()?;
    let pieces = doc
        .pieces
        .iter()
        .enumerate()
        .map(|(i, p)| {
            match doc.structured {
                Some(s) => structured_piece(&inp, p, s),
                None => piece(&inp, p),
            }
            .map_err(|e| in_piece(e, i, doc.pieces.len()))
        })
        .collect::<Result<Vec<_>>>()?;
    let mut grid = merge(pieces)?;
    grid.field_data = field_data;
    // Files before 2.2 hold higher-order hexahedra in VTK's old edge order: converted as
    // VTK's reader converts them.
    if doc.version < (2, 2) {
        grid.swap_hex_edges_10_11();
    }
    if let (Some(kind), true) = (doc.structured, doc.pieces.len() > 1) {
        let extents: Vec<[i64; 6]> = doc.pieces.iter().filter_map(|p| p.extent).collect();
        let (lattice, image) = match &kind {
            StructuredXml::Image(img) => (Lattice::Axis, Some(img)),
            StructuredXml::Rectilinear => (Lattice::Axis, None),
            StructuredXml::Curvilinear => (Lattice::Curvilinear, None),
        };
        let at = doc.pieces[0].tag_pos;
        grid = structured::join_pieces(&extents, grid, lattice, image)
            .map_err(|m| FormatError::at_byte(at, m))?;
    }
    Ok(grid)
}

fn in_piece(mut e: FormatError, i: usize, n: usize) -> FormatError {
    if n > 1 {
        e.message = format!("piece {i}: {}", e.message);
    }
    e
}

/// `tuples * components`, overflow-checked.
fn values(a: &ArrayXml, tuples: usize) -> Result<usize> {
    tuples.checked_mul(a.components).ok_or_else(|| {
        FormatError::at_byte(
            a.tag_pos,
            format!(
                "array '{}': {tuples} tuples x {} components overflow",
                a.name, a.components
            ),
        )
    })
}

fn array(inp: &Input, a: &ArrayXml, need: Option<usize>) -> Result<DataArray> {
    let data = match a.ty {
        ElemType::String => ArrayData::String(decode::strings(inp, a, need)?),
        ElemType::Num(_) => decode::numeric(inp, a, need)?,
        ElemType::Bit => ArrayData::UInt8(decode::bits(inp, a, need)?),
    };
    if need.is_none() && data.len() % a.components != 0 {
        return Err(FormatError::at_byte(
            a.tag_pos,
            format!(
                "array '{}': {} values are not a whole number of {}-component tuples",
                a.name,
                data.len(),
                a.components
            ),
        ));
    }
    Ok(DataArray {
        name: a.name.clone(),
        components: a.components,
        component_names: a.component_names.clone(),
        id_type: a.id_type,
        data,
    })
}

/// A numeric array written without `NumberOfComponents` whose values are a whole multiple of
/// the tuples: meshio writes an (n, 3, 3) tensor so, 9 n values under a 1-component header.
/// VTK keeps the first n values and drops the rest; the data says how many components there
/// are, so they are kept whole.
fn implicit_components(inp: &Input, a: &ArrayXml, tuples: usize) -> Result<DataArray> {
    let mut d = array(inp, a, None)?;
    let n = d.data.len();
    if n == tuples {
        return Ok(d);
    }
    if n < tuples || n % tuples != 0 {
        return Err(FormatError::at_byte(
            a.tag_pos,
            format!(
                "array '{}': has {n} values, expected {tuples} (one per tuple; no NumberOfComponents is given, and {n} is not a whole multiple of {tuples})",
                a.name
            ),
        ));
    }
    d.components = n / tuples;
    if !d.component_names.is_empty() {
        d.component_names.resize(d.components, String::new());
    }
    Ok(d)
}

fn attributes(inp: &Input, x: &AttributesXml, tuples: usize) -> Result<Attributes> {
    let arrays = x
        .arrays
        .par_iter()
        .map(|a| {
            if a.components_given || tuples == 0 || !matches!(a.ty, ElemType::Num(_)) {
                array(inp, a, Some(values(a, tuples)?))
            } else {
                implicit_components(inp, a, tuples)
            }
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(Attributes {
        arrays,
        active: x.active.clone(),
        lookup_tables: Vec::new(),
    })
}

fn cell_array<'a>(p: &'a PieceXml, name: &str) -> Option<&'a ArrayXml> {
    p.cells.iter().find(|a| a.name == name)
}

fn missing(p: &PieceXml, what: &str) -> FormatError {
    FormatError::at_byte(p.tag_pos, format!("<Piece> has no '{what}' array"))
}

/// A PolyData piece's four sections as one cell list: offsets (n+1), connectivity, and each
/// cell's type from its section and size ([`crate::PolySection::cell_type`]).
fn poly_cells(inp: &Input, p: &PieceXml) -> Result<(Vec<i64>, Vec<i64>, Vec<u8>)> {
    let mut offsets = vec![0i64];
    let mut connectivity = Vec::new();
    let mut types = Vec::new();
    for (sec, n, arrays) in &p.poly {
        if *n == 0 {
            continue;
        }
        let find = |name: &str| {
            arrays.iter().find(|a| a.name == name).ok_or_else(|| {
                FormatError::at_byte(
                    p.tag_pos,
                    format!("<{sec:?}> of this piece has no '{name}' array"),
                )
            })
        };
        let (oa, ca) = (find("offsets")?, find("connectivity")?);
        let off = decode::ids(inp, oa, *n, 1)?;
        let last = usize::try_from(off[*n]).map_err(|_| {
            FormatError::at_byte(
                oa.tag_pos,
                format!("array 'offsets': last offset is {}", off[*n]),
            )
        })?;
        let conn = decode::ids(inp, ca, last, 0)?;
        let base = connectivity.len() as i64;
        for w in off.windows(2) {
            let size = w[1] - w[0];
            if size < 1 || w[1] as usize > last {
                return Err(FormatError::at_byte(
                    oa.tag_pos,
                    format!("array 'offsets' of <{sec:?}>: offsets must increase (a cell of {size} points)"),
                ));
            }
            types.push(sec.cell_type(size as usize));
            offsets.push(base + w[1]);
        }
        connectivity.extend_from_slice(&conn);
    }
    Ok((offsets, connectivity, types))
}

/// Decodes one piece of image data or a rectilinear or structured grid: points from the
/// geometry the file gives, cells from the extent.
fn structured_piece(inp: &Input, p: &PieceXml, kind: StructuredXml) -> Result<Grid> {
    let (np, nc) = (p.num_points, p.num_cells);
    let extent = p
        .extent
        .ok_or_else(|| FormatError::at_byte(p.tag_pos, "a structured <Piece> without an Extent"))?;
    let dims = structured::dims(extent).map_err(|m| FormatError::at_byte(p.tag_pos, m))?;
    let (points, lattice) = match kind {
        StructuredXml::Image(image) => (
            structured::image_points(&image, extent, dims)
                .map_err(|m| FormatError::at_byte(p.tag_pos, m))?,
            Lattice::Axis,
        ),
        StructuredXml::Rectilinear => {
            let Some(d) = dims else {
                return empty_piece(inp, p);
            };
            if p.coordinates.len() != 3 {
                return Err(FormatError::at_byte(
                    p.tag_pos,
                    format!(
                        "<Coordinates> holds {} arrays, expected 3 (x, y and z)",
                        p.coordinates.len()
                    ),
                ));
            }
            let axes = p
                .coordinates
                .par_iter()
                .zip(d.to_vec())
                .map(|(a, n)| {
                    if a.components != 1 {
                        return Err(FormatError::at_byte(
                            a.tag_pos,
                            format!(
                                "coordinate array '{}' has {} components, expected 1",
                                a.name, a.components
                            ),
                        ));
                    }
                    let d = array(inp, a, Some(n))?;
                    if d.data.scalar_type().is_none() {
                        return Err(FormatError::at_byte(
                            a.tag_pos,
                            format!("coordinate array '{}' must be numeric", a.name),
                        ));
                    }
                    Ok(d.data)
                })
                .collect::<Result<Vec<_>>>()?;
            (
                structured::rectilinear_points([&axes[0], &axes[1], &axes[2]])
                    .map_err(|m| FormatError::at_byte(p.tag_pos, m))?,
                Lattice::Axis,
            )
        }
        StructuredXml::Curvilinear => (points_of(inp, p)?, Lattice::Curvilinear),
    };
    let (pd, cd) = rayon::join(
        || attributes(inp, &p.point_data, np),
        || attributes(inp, &p.cell_data, nc),
    );
    let cells = structured::cells(dims, lattice).map_err(|m| FormatError::at_byte(p.tag_pos, m))?;
    debug_assert_eq!(cells.len(), nc);
    Ok(Grid {
        points,
        cells,
        point_data: pd?,
        cell_data: cd?,
        field_data: Vec::new(),
    })
}

/// A piece with an empty extent: no points, no cells, its (empty) arrays kept by name.
fn empty_piece(inp: &Input, p: &PieceXml) -> Result<Grid> {
    Ok(Grid {
        points: DataArray::new("Points", 3, ArrayData::Float64(Vec::new())),
        cells: Cells::new(),
        point_data: attributes(inp, &p.point_data, 0)?,
        cell_data: attributes(inp, &p.cell_data, 0)?,
        field_data: Vec::new(),
    })
}

/// The piece's `<Points>` array, checked: three numeric components per point.
fn points_of(inp: &Input, p: &PieceXml) -> Result<DataArray> {
    let np = p.num_points;
    Ok(match &p.points {
        Some(a) => {
            if a.components != 3 {
                return Err(FormatError::at_byte(
                    a.tag_pos,
                    format!(
                        "array '{}' (Points) has {} components, expected 3",
                        a.name, a.components
                    ),
                ));
            }
            let need = np.checked_mul(3).ok_or_else(|| {
                FormatError::at_byte(p.tag_pos, format!("NumberOfPoints {np} is too large"))
            })?;
            let d = array(inp, a, Some(need))?;
            if d.data.scalar_type().is_none() {
                return Err(FormatError::at_byte(a.tag_pos, "Points must be numeric"));
            }
            d
        }
        None if np == 0 => DataArray::new("Points", 3, ArrayData::Float32(Vec::new())),
        None => return Err(FormatError::at_byte(p.tag_pos, "<Piece> has no <Points>")),
    })
}

/// Decodes one piece: offsets then connectivity on one side, everything else on the other.
fn piece(inp: &Input, p: &PieceXml) -> Result<Grid> {
    let (np, nc) = (p.num_points, p.num_cells);
    let poly_data = !p.poly.is_empty();
    // Offsets, connectivity, and (PolyData only) the types the sections imply.
    type Decoded = (Vec<i64>, Vec<i64>, Option<Vec<u8>>);
    let cells = || -> Result<Decoded> {
        if nc == 0 {
            return Ok((vec![0], Vec::new(), None));
        }
        if poly_data {
            let (o, c, t) = poly_cells(inp, p)?;
            return Ok((o, c, Some(t)));
        }
        let oa = cell_array(p, "offsets").ok_or_else(|| missing(p, "offsets"))?;
        let ca = cell_array(p, "connectivity").ok_or_else(|| missing(p, "connectivity"))?;
        let offsets = decode::ids(inp, oa, nc, 1)?;
        let last = offsets[nc];
        // Monotonic offsets are checked by validate; here the last one only sizes connectivity.
        let n = usize::try_from(last).map_err(|_| {
            FormatError::at_byte(
                oa.tag_pos,
                format!("array 'offsets': last offset is {last}"),
            )
        })?;
        let connectivity = decode::ids(inp, ca, n, 0)?;
        Ok((offsets, connectivity, None))
    };
    let rest = || -> Result<_> {
        let points = points_of(inp, p)?;
        let types = if nc == 0 || poly_data {
            Vec::new()
        } else {
            let ta = cell_array(p, "types").ok_or_else(|| missing(p, "types"))?;
            match decode::numeric(inp, ta, Some(nc))? {
                ArrayData::UInt8(v) => v,
                other => {
                    let mut v = Vec::with_capacity(nc);
                    for i in 0..nc {
                        let x = other.get_f64(i);
                        if !(0.0..=255.0).contains(&x) || x.fract() != 0.0 {
                            return Err(FormatError::at_byte(
                                ta.tag_pos,
                                format!("array 'types': value {i} is {x}, not a cell type"),
                            ));
                        }
                        v.push(x as u8);
                    }
                    v
                }
            }
        };
        let faces = match (cell_array(p, "faces"), cell_array(p, "faceoffsets")) {
            (Some(fa), Some(fo)) => {
                let fo_v = decode::ids(inp, fo, nc, 0)?;
                let n = fo_v.iter().copied().max().unwrap_or(0).max(0);
                let n = usize::try_from(n)
                    .map_err(|_| FormatError::at_byte(fo.tag_pos, "bad faceoffsets"))?;
                let f_v = decode::ids(inp, fa, n, 0)?;
                check_faces(&f_v, &fo_v, np)
                    .map_err(|m| FormatError::at_byte(fa.tag_pos, format!("array 'faces': {m}")))?;
                Some((f_v, fo_v))
            }
            (None, None) => None,
            _ => {
                return Err(FormatError::at_byte(
                    p.tag_pos,
                    "<Cells> has only one of 'faces' and 'faceoffsets'",
                ))
            }
        };
        let (pd, cd) = rayon::join(
            || attributes(inp, &p.point_data, np),
            || attributes(inp, &p.cell_data, nc),
        );
        Ok((points, types, faces, pd?, cd?))
    };
    let (c, r) = rayon::join(cells, rest);
    let (offsets, connectivity, poly_types) = c?;
    let (points, types, polyhedron_faces, point_data, cell_data) = r?;
    let types = poly_types.unwrap_or(types);
    Ok(Grid {
        points,
        cells: Cells {
            types,
            offsets,
            connectivity,
            polyhedron_faces,
        },
        point_data,
        cell_data,
        field_data: Vec::new(),
    })
}

/// Checks polyhedron face streams: each polyhedron's stream (between the previous non-negative
/// face offset and its own) is `nfaces, (npts, ids...) * nfaces`, ids in `0..np`.
pub(crate) fn check_faces(
    faces: &[i64],
    faceoffsets: &[i64],
    np: usize,
) -> std::result::Result<(), String> {
    let mut start = 0usize;
    for (cell, &end) in faceoffsets.iter().enumerate() {
        if end < 0 {
            continue;
        }
        let end = end as usize;
        if end < start || end > faces.len() {
            return Err(format!(
                "cell {cell}: face offset {end} is out of order or past the end"
            ));
        }
        let s = &faces[start..end];
        let bad = || format!("cell {cell}: malformed face stream");
        let nf = *s.first().ok_or_else(bad)?;
        let mut k = 1usize;
        for _ in 0..nf.max(0) {
            let n = usize::try_from(*s.get(k).ok_or_else(bad)?).map_err(|_| bad())?;
            let ids = s.get(k + 1..k + 1 + n).ok_or_else(bad)?;
            if let Some(&id) = ids.iter().find(|&&id| id < 0 || id as usize >= np) {
                return Err(format!(
                    "cell {cell}: point id {id} out of range ({})",
                    crate::error::numbered(np as u64, "point", 0)
                ));
            }
            k += 1 + n;
        }
        if k != s.len() || nf < 0 {
            return Err(bad());
        }
        start = end;
    }
    Ok(())
}

fn concat(mut parts: Vec<ArrayData>, what: &str) -> Result<ArrayData> {
    // An empty piece holds no values, so its type says nothing (VTK writes an empty piece's
    // points as Float32 whatever the others are).
    if parts.iter().any(|p| !p.is_empty()) {
        parts.retain(|p| !p.is_empty());
    }
    let mut it = parts.into_iter();
    let mut first = it.next().unwrap_or(ArrayData::Float64(Vec::new()));
    for (i, p) in it.enumerate() {
        match (&mut first, p) {
            (ArrayData::Int8(a), ArrayData::Int8(b)) => a.extend(b),
            (ArrayData::UInt8(a), ArrayData::UInt8(b)) => a.extend(b),
            (ArrayData::Int16(a), ArrayData::Int16(b)) => a.extend(b),
            (ArrayData::UInt16(a), ArrayData::UInt16(b)) => a.extend(b),
            (ArrayData::Int32(a), ArrayData::Int32(b)) => a.extend(b),
            (ArrayData::UInt32(a), ArrayData::UInt32(b)) => a.extend(b),
            (ArrayData::Int64(a), ArrayData::Int64(b)) => a.extend(b),
            (ArrayData::UInt64(a), ArrayData::UInt64(b)) => a.extend(b),
            (ArrayData::Float32(a), ArrayData::Float32(b)) => a.extend(b),
            (ArrayData::Float64(a), ArrayData::Float64(b)) => a.extend(b),
            (ArrayData::String(a), ArrayData::String(b)) => a.extend(b),
            (a, b) => {
                return Err(FormatError::new(
                    crate::Place::Array(what.to_string()),
                    format!(
                        "piece {} has type {} but piece 0 has {}",
                        i + 1,
                        b.type_name(),
                        a.type_name()
                    ),
                ))
            }
        }
    }
    Ok(first)
}

fn merge_attributes(parts: Vec<Attributes>, what: &str) -> Result<Attributes> {
    let mut it = parts.into_iter();
    let Some(first) = it.next() else {
        return Ok(Attributes::default());
    };
    let rest: Vec<Attributes> = it.collect();
    if rest.is_empty() {
        return Ok(first);
    }
    let mut out = Attributes {
        arrays: Vec::new(),
        active: first.active.clone(),
        lookup_tables: Vec::new(),
    };
    let mut rest: Vec<Vec<DataArray>> = rest.into_iter().map(|a| a.arrays).collect();
    for (k, r) in rest.iter().enumerate() {
        if r.len() != first.arrays.len() {
            return Err(FormatError::whole(format!(
                "piece {} has {} {what} arrays but piece 0 has {}",
                k + 1,
                r.len(),
                first.arrays.len()
            )));
        }
    }
    for a in first.arrays {
        let mut parts = vec![a.data];
        for (k, r) in rest.iter_mut().enumerate() {
            let pos = r.iter().position(|b| b.name == a.name).ok_or_else(|| {
                FormatError::whole(format!(
                    "piece {} has no {what} array '{}' (piece 0 has)",
                    k + 1,
                    a.name
                ))
            })?;
            let b = r.swap_remove(pos);
            if b.components != a.components {
                return Err(FormatError::in_array(
                    &a.name,
                    format!(
                        "piece {} has {} components, piece 0 has {}",
                        k + 1,
                        b.components,
                        a.components
                    ),
                ));
            }
            parts.push(b.data);
        }
        out.arrays.push(DataArray {
            data: concat(parts, &a.name)?,
            ..DataArray::new(a.name, a.components, ArrayData::UInt8(Vec::new()))
        });
        let last = out.arrays.len() - 1;
        out.arrays[last].component_names = a.component_names;
        out.arrays[last].id_type = a.id_type;
    }
    Ok(out)
}

/// Concatenates pieces: point ids of piece k shift by the points of pieces before it.
pub(crate) fn merge(mut pieces: Vec<Grid>) -> Result<Grid> {
    if pieces.len() <= 1 {
        return Ok(pieces.pop().unwrap_or_default());
    }
    let any_faces = pieces.iter().any(|p| p.cells.polyhedron_faces.is_some());
    let mut cells = Cells::new();
    let mut faces: Vec<i64> = Vec::new();
    let mut faceoffsets: Vec<i64> = Vec::new();
    let mut point_base = 0i64;
    let mut points = Vec::new();
    let mut pds = Vec::new();
    let mut cds = Vec::new();
    let points_name = pieces[0].points.name.clone();
    for p in pieces {
        let conn_base = cells.connectivity.len() as i64;
        cells.types.extend_from_slice(&p.cells.types);
        cells
            .offsets
            .extend(p.cells.offsets[1..].iter().map(|&o| o + conn_base));
        cells
            .connectivity
            .extend(p.cells.connectivity.iter().map(|&c| c + point_base));
        if any_faces {
            let face_base = faces.len() as i64;
            match &p.cells.polyhedron_faces {
                Some((f, fo)) => {
                    shift_faces(f, fo, point_base, &mut faces);
                    faceoffsets.extend(fo.iter().map(|&o| if o < 0 { o } else { o + face_base }));
                }
                None => faceoffsets.extend(std::iter::repeat(-1).take(p.cells.types.len())),
            }
        }
        point_base += p.num_points() as i64;
        points.push(p.points.data);
        pds.push(p.point_data);
        cds.push(p.cell_data);
    }
    if any_faces {
        cells.polyhedron_faces = Some((faces, faceoffsets));
    }
    Ok(Grid {
        points: DataArray::new(points_name, 3, concat(points, "Points")?),
        cells,
        point_data: merge_attributes(pds, "point data")?,
        cell_data: merge_attributes(cds, "cell data")?,
        field_data: Vec::new(),
    })
}

/// Appends `f` to `out` with every point id (not the counts) shifted by `base`.
fn shift_faces(f: &[i64], fo: &[i64], base: i64, out: &mut Vec<i64>) {
    let mut start = 0usize;
    for &end in fo {
        if end < 0 {
            continue;
        }
        let s = &f[start..end as usize];
        let mut k = 0;
        if let Some(&nf) = s.first() {
            out.push(nf);
            k = 1;
            for _ in 0..nf {
                let n = s[k] as usize;
                out.push(s[k]);
                out.extend(s[k + 1..k + 1 + n].iter().map(|&id| id + base));
                k += 1 + n;
            }
        }
        debug_assert_eq!(k, s.len());
        start = end as usize;
    }
}
