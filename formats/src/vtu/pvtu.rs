//! Parallel VTU (.pvtu): a small XML file naming .vtu pieces, read into one merged grid, and
//! written as that file plus a folder of pieces (all files appear, or none do).

use crate::atomic::write_all_or_none;
use crate::{FormatError, Grid, Result, WriteOptions};
use quick_xml::escape::escape;
use quick_xml::events::Event;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The `Source` of every `<Piece>` of a .pvtu, in order.
fn piece_sources(bytes: &[u8]) -> Result<Vec<String>> {
    let mut reader = quick_xml::Reader::from_reader(bytes);
    let mut buf = Vec::new();
    let mut sources = Vec::new();
    let mut root_ok = false;
    loop {
        let pos = reader.buffer_position();
        buf.clear();
        let ev = reader.read_event_into(&mut buf).map_err(|e| {
            FormatError::at_byte(reader.error_position(), format!("malformed XML: {e}"))
        })?;
        match ev {
            Event::DocType(_) => return Err(FormatError::at_byte(
                pos,
                "a DOCTYPE declaration is not allowed in a VTK file (refused: entity expansion)",
            )),
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
                        other => {
                            return Err(FormatError::at_byte(
                                pos,
                                format!(
                                    "VTKFile type is {:?}, expected \"PUnstructuredGrid\"",
                                    other.unwrap_or("(none)")
                                ),
                            ))
                        }
                    },
                    b"Piece" => {
                        let src = get(b"Source")?.ok_or_else(|| {
                            FormatError::at_byte(pos, "<Piece> without a Source attribute")
                        })?;
                        sources.push(src);
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
            "no <VTKFile type=\"PUnstructuredGrid\">",
        ));
    }
    Ok(sources)
}

/// Reads a .pvtu (its bytes already read from `path`) and all its pieces, merged in piece order.
/// Piece paths are relative to the .pvtu's folder; a missing piece is an error naming it.
pub fn read(path: &Path, bytes: &[u8]) -> Result<Grid> {
    let sources = piece_sources(bytes).map_err(|e| e.with_file(path))?;
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
        // A piece is read as a .vtu; one naming a .pvtu (itself, or another collection) would
        // fail with "this is a parallel file: name it .pvtu", which blames the wrong file.
        if p.extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("pvtu"))
        {
            return Err(FormatError::new(
                crate::Place::Other(format!("piece {i}")),
                format!(
                    "piece file '{}' is a .pvtu itself; pieces must be .vtu files",
                    p.display()
                ),
            )
            .with_file(path));
        }
        grids.push(super::read_path(&p)?);
    }
    let field = grids
        .first()
        .map(|g| g.field_data.clone())
        .unwrap_or_default();
    let mut g = super::read::merge(grids).map_err(|e| e.with_file(path))?;
    g.field_data = field;
    Ok(g)
}

fn p_array(s: &mut String, indent: &str, a: &crate::DataArray) {
    let _ = write!(
        s,
        "{indent}<PDataArray type=\"{}\" Name=\"{}\"",
        a.data.type_name(),
        escape(a.name.as_str())
    );
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
            escape(format!("{stem}/{n}"))
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
