//! Parallel VTU (.pvtu): a small XML file naming .vtu pieces, read into one merged grid, and
//! written as that file plus a folder of pieces (all files appear, or none do). The parallel
//! structured files (.pvti, .pvtr, .pvts) are read the same way, their pieces joined by extent
//! into one lattice.

use super::write::escape;
use crate::atomic::write_all_or_none;
use crate::structured::{self, Lattice};
use crate::{FormatError, Grid, Result, WriteOptions};
use quick_xml::events::Event;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// An array a .pvtu declares in `<PPointData>` or `<PCellData>`. Its `type` is not compared with
/// the pieces': VTK's writer declares vtkIdType arrays as `type="Int32" IdType="1"` over Int64
/// pieces; the pieces must agree with one another, which merging checks.
struct Declared {
    name: String,
    components: usize,
    /// The declared `type`, when it names one: pieces of another type are converted to it.
    ty: Option<crate::ScalarType>,
}

/// What a .pvtu says: its pieces' `Source`s in order, and the point and cell arrays it declares
/// (the only ones VTK reads from the pieces).
#[derive(Default)]
struct Index {
    sources: Vec<String>,
    point: Vec<Declared>,
    cell: Vec<Declared>,
    /// The type `<PPoints>` declares for the points.
    points_ty: Option<crate::ScalarType>,
    /// Parallel structured data: the serial type its pieces are, and each piece's `Extent`.
    structured: Option<(&'static str, Lattice)>,
    extents: Vec<[i64; 6]>,
}

/// The serial type and cell kind of a parallel structured root type.
fn structured_kind(root: &str) -> Option<(&'static str, Lattice)> {
    Some(match root {
        "PImageData" => ("ImageData", Lattice::Axis),
        "PRectilinearGrid" => ("RectilinearGrid", Lattice::Axis),
        "PStructuredGrid" => ("StructuredGrid", Lattice::Curvilinear),
        _ => return None,
    })
}

/// Where a `<PDataArray>` belongs.
#[derive(Clone, Copy, PartialEq)]
enum Section {
    None,
    Point,
    Cell,
    Points,
}

fn piece_sources(bytes: &[u8]) -> Result<Index> {
    let mut reader = quick_xml::Reader::from_reader(bytes);
    let mut buf = Vec::new();
    let mut index = Index::default();
    let mut section = Section::None;
    let mut root_ok = false;
    loop {
        let pos = reader.buffer_position();
        buf.clear();
        let ev = reader.read_event_into(&mut buf).map_err(|e| {
            FormatError::at_byte(reader.error_position(), format!("malformed XML: {e}"))
        })?;
        // A self-closing <PPointData/> declares nothing and opens no section.
        let empty = matches!(ev, Event::Empty(_));
        match ev {
            Event::DocType(_) => return Err(FormatError::at_byte(
                pos,
                "a DOCTYPE declaration is not allowed in a VTK file (refused: entity expansion)",
            )),
            Event::End(e) => {
                if matches!(
                    e.local_name().as_ref(),
                    b"PPointData" | b"PCellData" | b"PPoints"
                ) {
                    section = Section::None;
                }
            }
            Event::Start(e) | Event::Empty(e) => {
                let get = |key: &[u8]| -> Result<Option<String>> {
                    for a in e.attributes().with_checks(true) {
                        let a = a.map_err(|err| {
                            FormatError::at_byte(pos, format!("malformed XML: {err}"))
                        })?;
                        if a.key.as_ref() == key {
                            let v = a.unescape_value().map_err(|err| {
                                FormatError::at_byte(pos, format!("malformed XML: {err}"))
                            })?;
                            return Ok(Some(v.into_owned()));
                        }
                    }
                    Ok(None)
                };
                match e.local_name().as_ref() {
                    b"VTKFile" => match get(b"type")?.as_deref() {
                        Some("PUnstructuredGrid") => root_ok = true,
                        Some(t) if structured_kind(t).is_some() => {
                            root_ok = true;
                            index.structured = structured_kind(t);
                        }
                        other => {
                            return Err(FormatError::at_byte(
                                pos,
                                format!(
                                    "VTKFile type is {:?}, expected \"PUnstructuredGrid\", \"PImageData\", \"PRectilinearGrid\" or \"PStructuredGrid\"",
                                    other.unwrap_or("(none)")
                                ),
                            ))
                        }
                    },
                    b"Piece" => {
                        let src = get(b"Source")?.ok_or_else(|| {
                            FormatError::at_byte(pos, "<Piece> without a Source attribute")
                        })?;
                        if index.structured.is_some() {
                            let e = get(b"Extent")?.ok_or_else(|| {
                                FormatError::at_byte(pos, "a structured <Piece> without an Extent")
                            })?;
                            index.extents.push(super::xml::parse_extent(&e, "Extent", pos)?);
                        }
                        index.sources.push(src);
                    }
                    b"PPointData" if !empty => section = Section::Point,
                    b"PCellData" if !empty => section = Section::Cell,
                    b"PPoints" if !empty => section = Section::Points,
                    b"PDataArray" if section != Section::None => {
                        let name = get(b"Name")?.unwrap_or_default();
                        let components = match get(b"NumberOfComponents")? {
                            None => 1,
                            Some(c) => c.trim().parse().map_err(|_| {
                                FormatError::at_byte(
                                    pos,
                                    format!("<PDataArray Name=\"{name}\">: NumberOfComponents '{c}' is not a count"),
                                )
                            })?,
                        };
                        let ty = get(b"type")?
                            .as_deref()
                            .and_then(crate::ScalarType::from_xml_name);
                        let d = Declared {
                            name,
                            components,
                            ty,
                        };
                        match section {
                            Section::Point => index.point.push(d),
                            Section::Points => index.points_ty = d.ty,
                            _ => index.cell.push(d),
                        }
                    }
                    _ => {}
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    if !root_ok {
        return Err(FormatError::at_byte(
            0,
            "no <VTKFile type=\"PUnstructuredGrid\"> (or PImageData, PRectilinearGrid, PStructuredGrid)",
        ));
    }
    Ok(index)
}

/// Keeps of a piece's `attrs` the arrays the .pvtu declares, in its order, as VTK's reader does;
/// the undeclared ones are added to `dropped` (warned about once, after all pieces).
fn declared_only(
    attrs: &mut crate::Attributes,
    declared: &[Declared],
    what: &str,
    piece: usize,
    piece_path: &Path,
    dropped: &mut Vec<(String, Vec<usize>)>,
) -> Result<()> {
    let mut kept = Vec::with_capacity(declared.len());
    for d in declared {
        let Some(i) = attrs.arrays.iter().position(|a| a.name == d.name) else {
            return Err(FormatError::new(
                crate::Place::Other(format!("piece {piece}")),
                format!(
                    "'{}' has no {what} array '{}', which the .pvtu declares in <P{}Data>",
                    piece_path.display(),
                    d.name,
                    if what == "point" { "Point" } else { "Cell" }
                ),
            ));
        };
        let a = attrs.arrays.swap_remove(i);
        if a.components != d.components {
            return Err(FormatError::new(
                crate::Place::Other(format!("piece {piece}")),
                format!(
                    "'{}': {what} array '{}' has {} components but the .pvtu declares {}",
                    piece_path.display(),
                    a.name,
                    a.components,
                    d.components
                ),
            ));
        }
        kept.push(as_declared(a, d.ty, what, piece, piece_path));
    }
    for a in attrs.arrays.drain(..) {
        match dropped.iter_mut().find(|(n, _)| *n == a.name) {
            Some((_, pieces)) => pieces.push(piece),
            None => dropped.push((a.name, vec![piece])),
        }
    }
    attrs.arrays = kept;
    let names: Vec<&str> = attrs.arrays.iter().map(|a| a.name.as_str()).collect();
    attrs.active.retain(|(_, n)| names.contains(&n.as_str()));
    attrs
        .lookup_tables
        .retain(|(n, _)| names.contains(&n.as_str()));
    Ok(())
}

/// `a` converted to the type the .pvtu declares for it (`ty`), as VTK's reader converts a
/// piece's array, with a warning when a value changed on the way.
fn as_declared(
    mut a: crate::DataArray,
    ty: Option<crate::ScalarType>,
    what: &str,
    piece: usize,
    piece_path: &Path,
) -> crate::DataArray {
    let Some(ty) = ty else { return a };
    if a.data.scalar_type() == Some(ty) {
        return a;
    }
    if let Some((data, exact)) = a.data.converted(ty) {
        if !exact {
            eprintln!(
                "tetkit: warning: '{}' (piece {piece}): {what} array '{}' is {} but the .pvtu declares {}; converted as VTK does, and some values changed",
                piece_path.display(),
                a.name,
                a.data.type_name(),
                ty.xml_name()
            );
        }
        a.data = data;
    }
    a
}

fn warn_dropped(path: &Path, what: &str, dropped: &[(String, Vec<usize>)]) {
    for (name, pieces) in dropped {
        let list: Vec<String> = pieces.iter().map(|p| p.to_string()).collect();
        eprintln!(
            "tetkit: warning: {}: {what} array '{name}' of piece {} is not declared in <P{}Data>; dropped, as VTK drops it",
            path.display(),
            list.join(", "),
            if what == "point" { "Point" } else { "Cell" }
        );
    }
}

/// Reads a .pvtu (its bytes already read from `path`) and all its pieces, merged in piece order.
/// Piece paths are relative to the .pvtu's folder; a missing piece is an error naming it. Only
/// the arrays the .pvtu declares are read, as VTK does: a piece lacking one is refused, and
/// undeclared ones are dropped with a warning on stderr.
pub fn read(path: &Path, bytes: &[u8]) -> Result<Grid> {
    let index = piece_sources(bytes).map_err(|e| e.with_file(path))?;
    let sources = &index.sources;
    let (mut drop_point, mut drop_cell) = (Vec::new(), Vec::new());
    let dir = path.parent().unwrap_or(Path::new(""));
    let mut grids = Vec::with_capacity(sources.len());
    for (i, s) in sources.iter().enumerate() {
        let p = dir.join(s);
        if !p.is_file() {
            return Err(FormatError::new(
                crate::Place::Other(format!("piece {i}")),
                format!("piece file '{}' ({s}) does not exist", p.display()),
            )
            .with_file(path));
        }
        // A piece is read as a serial file of the parallel file's own type; one naming a parallel
        // file (itself, or another collection) would fail with a message blaming the wrong file.
        let want = index
            .structured
            .map_or("UnstructuredGrid", |(serial, _)| serial);
        let head = crate::read_head(&p)?;
        let found = crate::vtkfile_type(&String::from_utf8_lossy(&head)).map(str::to_string);
        if found.as_deref() != Some(want) {
            return Err(FormatError::new(
                crate::Place::Other(format!("piece {i}")),
                format!(
                    "piece file '{}' is {}; pieces must be .{} files ({want})",
                    p.display(),
                    found.map_or("not a VTK XML file".to_string(), |t| format!("of type {t}")),
                    match want {
                        "ImageData" => "vti",
                        "RectilinearGrid" => "vtr",
                        "StructuredGrid" => "vts",
                        _ => "vtu",
                    }
                ),
            )
            .with_file(path));
        }
        let mut g = super::read_path(&p)?;
        if let Some(e) = index.extents.get(i) {
            let counted = structured::dims(*e).and_then(structured::counts);
            let fits = counted
                .as_ref()
                .is_ok_and(|&(np, nc)| np == g.num_points() && nc == g.num_cells());
            if !fits {
                return Err(FormatError::new(
                    crate::Place::Other(format!("piece {i}")),
                    format!(
                        "the piece's Extent {e:?} does not match '{}' ({} points, {} cells)",
                        p.display(),
                        g.num_points(),
                        g.num_cells()
                    ),
                )
                .with_file(path));
            }
        }
        declared_only(
            &mut g.point_data,
            &index.point,
            "point",
            i,
            &p,
            &mut drop_point,
        )
        .and_then(|()| declared_only(&mut g.cell_data, &index.cell, "cell", i, &p, &mut drop_cell))
        .map_err(|e| e.with_file(path))?;
        // Points of the declared type too (an empty piece's default Float32 among Float64
        // pieces, as VTK writes it).
        let ty = match index.points_ty {
            None if g.num_points() == 0 => grids
                .first()
                .and_then(|g: &Grid| g.points.data.scalar_type()),
            declared => declared,
        };
        g.points = as_declared(g.points, ty, "points", i, &p);
        grids.push(g);
    }
    warn_dropped(path, "point", &drop_point);
    warn_dropped(path, "cell", &drop_cell);
    let field = grids
        .first()
        .map(|g| g.field_data.clone())
        .unwrap_or_default();
    let mut g = super::read::merge(grids).map_err(|e| e.with_file(path))?;
    g.field_data = field;
    if let Some((_, lattice)) = index.structured {
        // Each piece's points came from its own file, so they are gathered, not recomputed.
        g = structured::join_pieces(&index.extents, g, lattice, None)
            .map_err(|m| FormatError::whole(m).with_file(path))?;
    }
    Ok(g)
}

fn p_array(s: &mut String, indent: &str, a: &crate::DataArray) {
    let _ = write!(
        s,
        "{indent}<PDataArray type=\"{}\" Name=\"{}\"",
        a.data.type_name(),
        escape(a.name.as_str())
    );
    if a.id_type && super::write::id_type_ok(&a.data) {
        s.push_str(" IdType=\"1\"");
    }
    if a.components != 1 {
        let _ = write!(s, " NumberOfComponents=\"{}\"", a.components);
    }
    for (i, n) in a.component_names.iter().enumerate() {
        if !n.is_empty() {
            let _ = write!(s, " ComponentName{i}=\"{}\"", escape(n.as_str()));
        }
    }
    s.push_str("/>\n");
}

/// Writes `pieces` as `path` plus one .vtu per piece in a folder named after the file's stem,
/// as ParaView does; all files appear or none do, and a folder this call created is removed
/// again on failure.
pub fn write(path: &Path, pieces: &[Grid], opts: &WriteOptions) -> Result<()> {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .filter(|s| !s.is_empty())
        .ok_or_else(|| FormatError::whole("output path has no file name").with_file(path))?;
    let Some(first) = pieces.first() else {
        return Err(FormatError::whole("no pieces to write").with_file(path));
    };
    let dir = path.parent().unwrap_or(Path::new(""));
    let folder = dir.join(&stem);
    let created = !folder.exists();
    if created {
        std::fs::create_dir_all(&folder).map_err(|e| FormatError::io(&folder, e))?;
    }
    let names: Vec<String> = (0..pieces.len())
        .map(|i| format!("{stem}_{i}.vtu"))
        .collect();
    let mut targets: Vec<PathBuf> = names.iter().map(|n| folder.join(n)).collect();
    targets.push(path.to_path_buf());

    let mut x = String::new();
    x.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"0.1\"");
    let _ = writeln!(
        x,
        " byte_order=\"{}\" header_type=\"UInt64\">\n  <PUnstructuredGrid GhostLevel=\"0\">",
        if cfg!(target_endian = "big") {
            "BigEndian"
        } else {
            "LittleEndian"
        }
    );
    // The active attributes, as ParaView reads them from the .pvtu (not from the pieces).
    let _ = writeln!(
        x,
        "    <PPointData{}>",
        super::write::active_attrs(&first.point_data)
    );
    for a in &first.point_data.arrays {
        p_array(&mut x, "      ", a);
    }
    let _ = writeln!(
        x,
        "    </PPointData>\n    <PCellData{}>",
        super::write::active_attrs(&first.cell_data)
    );
    for a in &first.cell_data.arrays {
        p_array(&mut x, "      ", a);
    }
    x.push_str("    </PCellData>\n    <PPoints>\n");
    p_array(&mut x, "      ", &first.points);
    x.push_str("    </PPoints>\n");
    for n in &names {
        let _ = writeln!(
            x,
            "    <Piece Source=\"{}\"/>",
            escape(&format!("{stem}/{n}"))
        );
    }
    x.push_str("  </PUnstructuredGrid>\n</VTKFile>\n");

    let result = write_all_or_none(&targets, |i, w| -> std::result::Result<(), WriteError> {
        if i < pieces.len() {
            pieces[i]
                .validate()
                .map_err(|m| FormatError::whole(format!("refusing to write an invalid mesh: {m}")))
                .and_then(|()| super::write(w, &pieces[i], opts))
                .map_err(|e| WriteError(e.with_file(&targets[i])))
        } else {
            Ok(w.write_all(x.as_bytes())?)
        }
    });
    if result.is_err() && created {
        let _ = std::fs::remove_dir(&folder);
    }
    result.map_err(|e| e.0.with_file(path))
}

/// A write failure; io errors from creating or renaming files get the .pvtu's name later.
struct WriteError(FormatError);

impl From<std::io::Error> for WriteError {
    fn from(e: std::io::Error) -> WriteError {
        WriteError(FormatError::whole(e.to_string()))
    }
}

impl From<crate::atomic::TargetError> for WriteError {
    fn from(e: crate::atomic::TargetError) -> WriteError {
        WriteError(FormatError::io(&e.path, e.source))
    }
}
