//! Readers and writers for tetrahedral and mixed unstructured meshes: VTU/PVTU, legacy VTK, TetGen,
//! Medit; readers for Gmsh's .msh, for Exodus II (classic NetCDF and NetCDF-4), for VTKHDF
//! UnstructuredGrid (.vtkhdf, .hdf), for the VTK collections (.vtm,
//! .pvd) that name meshes, for VTK's structured data (.vti, .vtr, .vts and their legacy forms, as
//! voxels and hexahedra) and for polydata (.vtp).
//!
//! Everything is read into a [`Grid`] that keeps each array's name, element type, component count
//! and component names, and written back from it without conversion. Errors name the file and the
//! place (line, byte offset or array). Every write goes to a temporary file that is renamed into
//! place only when complete.

pub mod atomic;
pub mod collection;
pub mod error;
pub mod exodus;
pub mod grid;
#[cfg(test)]
mod highorder_tests;
pub mod legacy;
pub mod medit;
pub mod msh;
pub(crate) mod structured;
pub mod tetgen;
pub mod vtkhdf;
pub mod vtu;

pub use collection::{pvd, vtm};
pub use error::{FormatError, Place, Result};
pub use grid::{
    cell_type, ArrayData, Attribute, Attributes, Cells, DataArray, Grid, PolySection, Renamed,
    ScalarType,
};

use std::io::Write;
use std::path::Path;

/// Prints a warning on stderr, as every reader words it: something was read but not kept whole.
pub(crate) fn warn(msg: &str) {
    eprintln!("tetkit: warning: {msg}");
}

/// `bytes` as text, and when they are not UTF-8 (each bad sequence then becomes U+FFFD) what
/// they were, with every byte that is not printable ASCII written `\xNN`.
pub(crate) fn lossy_text(bytes: &[u8]) -> (String, Option<String>) {
    match std::str::from_utf8(bytes) {
        Ok(s) => (s.to_string(), None),
        Err(_) => {
            let mut raw = String::with_capacity(bytes.len() + 8);
            for &b in bytes.iter().take(80) {
                if b.is_ascii_graphic() || b == b' ' {
                    raw.push(b as char);
                } else {
                    raw.push_str(&format!("\\x{b:02x}"));
                }
            }
            if bytes.len() > 80 {
                raw.push_str("...");
            }
            (String::from_utf8_lossy(bytes).into_owned(), Some(raw))
        }
    }
}

/// [`lossy_text`], with a warning naming `file`, `place` and `what` when the text is not UTF-8:
/// the name is kept (lossily) rather than the file refused, but it will not be written back as
/// the file had it.
pub(crate) fn text_or_warn(bytes: &[u8], file: &str, place: &str, what: &str) -> String {
    let (s, raw) = lossy_text(bytes);
    if let Some(raw) = raw {
        warn(&format!(
            "{file}: {place}: {what} '{raw}' is not UTF-8; read as '{s}'"
        ));
    }
    s
}

/// A file format, chosen from the file name and checked against the content.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// VTK XML unstructured grid, `.vtu`.
    Vtu,
    /// VTK XML parallel unstructured grid, `.pvtu`, naming `.vtu` piece files.
    Pvtu,
    /// Legacy VTK, `.vtk`.
    Legacy,
    /// TetGen `.node` + `.ele` (+ `.face`, `.neigh`), named by any of them.
    TetGen,
    /// VTK XML multiblock, `.vtm`, naming data files whose meshes are merged (read only).
    Vtm,
    /// ParaView data collection, `.pvd`: a time series of data files (read only).
    Pvd,
    /// VTK XML image data, `.vti`: read as voxels (read only).
    Vti,
    /// VTK XML rectilinear grid, `.vtr`: read as voxels (read only).
    Vtr,
    /// VTK XML structured (curvilinear) grid, `.vts`: read as hexahedra (read only).
    Vts,
    /// VTK XML polydata, `.vtp`: vertices, lines, polygons and strips (read only).
    Vtp,
    /// VTK XML parallel structured data, `.pvti`, `.pvtr`, `.pvts`: pieces joined into one
    /// lattice (read only).
    PStructured,
    /// ASCII Medit (INRIA) `.mesh`, as MMG, TetGen `-g` and Gmsh write it.
    Medit,
    /// Gmsh mesh, `.msh` (MSH 4.1 and 2.2; read only).
    Msh,
    /// Exodus II, `.exo`, `.e`, `.ex2`, `.exii`, `.g`, `.gen` in classic NetCDF (read only).
    Exodus,
    /// VTKHDF UnstructuredGrid, `.vtkhdf`, `.hdf` (HDF5; read only).
    VtkHdf,
}

/// The extensions [`Format::from_path`] knows, for messages.
/// `(FILE, STEP)` when `path` is `FILE@STEP` for a format with time steps (.pvd, Exodus,
/// VTKHDF) whose STEP the selectors did not take (`@-1`, `@abc`, `@1.5`): what went wrong is the
/// step, not the extension.
fn bad_step(path: &Path) -> Option<(String, String)> {
    let s = path.to_str()?;
    let (file, step) = s.rsplit_once('@')?;
    let ext = Path::new(file)
        .extension()?
        .to_string_lossy()
        .to_ascii_lowercase();
    let stepped = ext == "pvd"
        || exodus::EXTENSIONS.contains(&ext.as_str())
        || vtkhdf::EXTENSIONS.contains(&ext.as_str());
    stepped.then(|| (file.to_string(), step.to_string()))
}

/// The extensions [`write`] takes.
const WRITTEN: &str = ".vtu, .pvtu, .vtk, .node/.ele (TetGen) or .mesh (Medit)";

const KNOWN: &str = ".vtu, .pvtu, .vtk, .node, .ele, .mesh, .msh, .exo, .vtkhdf, .hdf, .vtm, .pvd, .vti, .vtr, .vts, .pvti, .pvtr, .pvts or .vtp";

impl Format {
    /// The format a path's extension names.
    pub fn from_path(path: &Path) -> Result<Format> {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        match ext.as_str() {
            "vtu" => Ok(Format::Vtu),
            "pvtu" => Ok(Format::Pvtu),
            "vtk" => Ok(Format::Legacy),
            "node" | "ele" | "face" | "neigh" => Ok(Format::TetGen),
            "vtm" => Ok(Format::Vtm),
            "pvd" => Ok(Format::Pvd),
            "vti" => Ok(Format::Vti),
            "vtr" => Ok(Format::Vtr),
            "vts" => Ok(Format::Vts),
            "vtp" => Ok(Format::Vtp),
            "pvti" | "pvtr" | "pvts" => Ok(Format::PStructured),
            "mesh" => Ok(Format::Medit),
            "meshb" => Err(FormatError::whole(
                "binary Medit (.meshb) is not supported; tetkit reads and writes ASCII .mesh",
            )
            .with_file(path)),
            "msh" => Ok(Format::Msh),
            e if exodus::EXTENSIONS.contains(&e) => Ok(Format::Exodus),
            e if vtkhdf::EXTENSIONS.contains(&e) => Ok(Format::VtkHdf),
            other => Err(FormatError::whole(match bad_step(path) {
                Some((file, step)) => format!(
                    "bad time step '{step}' after {file}: expected a step number (0, 1, ...) or 'last'"
                ),
                None if other.is_empty() => format!("no file extension; expected {KNOWN}"),
                None => format!("unknown file extension '.{other}'; expected {KNOWN}"),
            })
            .with_file(path)),
        }
    }

    /// The format an output path names, refused up front when tetkit does not write it (the
    /// readers' list of extensions would offer formats that cannot be written).
    pub fn for_output(path: &Path) -> Result<Format> {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        match Format::from_path(path) {
            Ok(f) if f.read_only() => Err(read_only(f).with_file(path)),
            Ok(f) => Ok(f),
            Err(_) if ext.is_empty() => Err(FormatError::whole(format!(
                "no file extension; an output is one of {WRITTEN}"
            ))
            .with_file(path)),
            Err(_) if ext != "meshb" => Err(FormatError::whole(format!(
                "unknown file extension '.{ext}'; an output is one of {WRITTEN}"
            ))
            .with_file(path)),
            Err(e) => Err(e),
        }
    }

    /// Parses a format name as given on the command line (`vtu`, `pvtu`, `vtk`, `tetgen`).
    pub fn from_name(name: &str) -> Option<Format> {
        match name.to_ascii_lowercase().as_str() {
            "vtu" => Some(Format::Vtu),
            "pvtu" => Some(Format::Pvtu),
            "vtk" | "legacy" => Some(Format::Legacy),
            "tetgen" | "node" | "ele" => Some(Format::TetGen),
            "vtm" => Some(Format::Vtm),
            "pvd" => Some(Format::Pvd),
            "vti" => Some(Format::Vti),
            "vtr" => Some(Format::Vtr),
            "vts" => Some(Format::Vts),
            "vtp" => Some(Format::Vtp),
            "medit" | "mesh" => Some(Format::Medit),
            "msh" | "gmsh" => Some(Format::Msh),
            "exodus" | "exo" => Some(Format::Exodus),
            "vtkhdf" | "hdf" => Some(Format::VtkHdf),
            _ => None,
        }
    }

    /// Formats tetkit reads but does not write.
    pub fn read_only(self) -> bool {
        matches!(
            self,
            Format::Vtm
                | Format::Pvd
                | Format::Vti
                | Format::Vtr
                | Format::Vts
                | Format::Vtp
                | Format::Msh
                | Format::Exodus
                | Format::VtkHdf
                | Format::PStructured
        )
    }

    pub fn name(self) -> &'static str {
        match self {
            Format::Vtu => "VTU",
            Format::Pvtu => "PVTU",
            Format::Legacy => "legacy VTK",
            Format::TetGen => "TetGen",
            Format::Vtm => "VTM",
            Format::Pvd => "PVD",
            Format::Vti => "VTI (image data)",
            Format::Vtr => "VTR (rectilinear grid)",
            Format::Vts => "VTS (structured grid)",
            Format::Vtp => "VTP (polydata)",
            Format::PStructured => "parallel structured data (.pvti/.pvtr/.pvts)",
            Format::Medit => "Medit",
            Format::Msh => "Gmsh MSH",
            Format::Exodus => "Exodus II",
            Format::VtkHdf => "VTKHDF",
        }
    }
}

/// Guesses the format from the first bytes: XML with `VTKFile type="UnstructuredGrid"` (VTU),
/// `type="PUnstructuredGrid"` (PVTU), `type="vtkMultiBlockDataSet"` (VTM), a `<Collection>`
/// The `type` attribute of the `<VTKFile ...>` element in `text`, when the element is there.
pub(crate) fn vtkfile_type(text: &str) -> Option<&str> {
    let start = text.find("<VTKFile")?;
    let tag = &text[start..];
    let tag = &tag[..tag.find('>')?];
    let mut rest = tag;
    while let Some(i) = rest.find("type") {
        let before = rest[..i].chars().last();
        let after = rest[i + 4..].trim_start();
        rest = &rest[i + 4..];
        // `type=` as a whole attribute name (not `byte_order`'s tail or `header_type`).
        if !matches!(before, Some(c) if c.is_whitespace()) {
            continue;
        }
        let Some(v) = after.strip_prefix('=') else {
            continue;
        };
        let v = v.trim_start();
        let q = v.chars().next()?;
        if q != '"' && q != '\'' {
            return None;
        }
        let v = &v[1..];
        return Some(&v[..v.find(q)?]);
    }
    None
}

/// The UTF-8 byte order mark Windows editors put before a text file's first byte.
pub(crate) const BOM: &[u8] = b"\xef\xbb\xbf";

/// Bytes of a leading [`BOM`] in `bytes` (3 or 0): the readers start past it, and count it in
/// the byte offsets they report.
pub(crate) fn bom_len(bytes: &[u8]) -> usize {
    if bytes.starts_with(BOM) {
        BOM.len()
    } else {
        0
    }
}

/// Whether the first keyword, past `#` comment lines and whitespace, is Medit's
/// `MeshVersionFormatted` (any case, as Medit tools accept).
fn medit_head(text: &str) -> bool {
    let mut rest = text.trim_start_matches('\u{feff}');
    loop {
        rest = rest.trim_start();
        match rest.strip_prefix('#') {
            Some(r) => rest = r.split_once('\n').map_or("", |(_, after)| after),
            None => break,
        }
    }
    let word = rest.split_ascii_whitespace().next().unwrap_or("");
    word.eq_ignore_ascii_case("MeshVersionFormatted")
}

/// Guesses the format from the first bytes: XML with `VTKFile type="UnstructuredGrid"` (VTU),
/// `type="PUnstructuredGrid"` (PVTU), `type="vtkMultiBlockDataSet"` (VTM), a `<Collection>`
/// (PVD), `# vtk DataFile` (legacy), `$MeshFormat` (Gmsh; `$NOD`, MSH 1, too, so that its
/// reader can refuse it by name), or classic NetCDF's `CDF\x01`, `CDF\x02`, `CDF\x05` (Exodus
/// II). TetGen files have no magic.
pub fn sniff(bytes: &[u8]) -> Option<Format> {
    if matches!(bytes.get(..4), Some(b"CDF\x01" | b"CDF\x02" | b"CDF\x05")) {
        return Some(Format::Exodus);
    }
    let head = &bytes[..bytes.len().min(4096)];
    let text = String::from_utf8_lossy(head);
    let trimmed = text.trim_start_matches('\u{feff}').trim_start();
    if trimmed.starts_with("# vtk DataFile") {
        return Some(Format::Legacy);
    }
    if medit_head(&text) {
        return Some(Format::Medit);
    }
    if trimmed.starts_with("$MeshFormat") || trimmed.starts_with("$NOD") {
        return Some(Format::Msh);
    }
    if trimmed.starts_with('<') {
        // The root's `type` decides: a VTU whose first lines quote another type's name (in a
        // string array or an information key) is still a VTU.
        if let Some(t) = vtkfile_type(&text) {
            return match t {
                "UnstructuredGrid" => Some(Format::Vtu),
                "PUnstructuredGrid" => Some(Format::Pvtu),
                "vtkMultiBlockDataSet" | "vtkMultiPieceDataSet" | "vtkMultiGroupDataSet" => {
                    Some(Format::Vtm)
                }
                "Collection" => Some(Format::Pvd),
                "ImageData" => Some(Format::Vti),
                "RectilinearGrid" => Some(Format::Vtr),
                "StructuredGrid" => Some(Format::Vts),
                "PolyData" => Some(Format::Vtp),
                "PImageData" | "PRectilinearGrid" | "PStructuredGrid" => Some(Format::PStructured),
                _ => None,
            };
        }
        if [
            "vtkMultiBlockDataSet",
            "vtkMultiPieceDataSet",
            "vtkMultiGroupDataSet",
        ]
        .iter()
        .any(|t| text.contains(t))
        {
            return Some(Format::Vtm);
        }
        if text.contains("<Collection") {
            return Some(Format::Pvd);
        }
        if text.contains("PUnstructuredGrid") {
            return Some(Format::Pvtu);
        }
        if text.contains("UnstructuredGrid") {
            return Some(Format::Vtu);
        }
    }
    None
}

/// How to encode the output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Encoding {
    /// VTU: all arrays raw in one `<AppendedData encoding="raw">` block (what ParaView writes).
    /// Legacy: binary (big endian).
    #[default]
    Appended,
    /// VTU: each array inline, base64. Legacy: binary (big endian).
    Binary,
    /// Text: VTU `format="ascii"`, legacy `ASCII`.
    Ascii,
}

/// Compression of VTU binary blocks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Compression {
    #[default]
    None,
    Zlib,
    Lz4,
    Lzma,
}

/// Legacy VTK file version to write.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LegacyVersion {
    /// `CELLS n size` with counts inline; read by every VTK.
    V42,
    /// `OFFSETS`/`CONNECTIVITY` (VTK 9 and later); what VTK 9 writes by default.
    #[default]
    V51,
}

/// Options for writers; each writer uses what applies to it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WriteOptions {
    pub encoding: Encoding,
    pub compression: Compression,
    pub legacy_version: LegacyVersion,
}

fn read_file(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).map_err(|e| FormatError::io(path, e))
}

/// Reads a mesh, choosing the reader by extension and checking the content agrees. A `.pvd`,
/// Exodus or temporal VTKHDF file gives its first time step; `FILE.pvd@K` / `FILE.exo@K` /
/// `FILE.vtkhdf@K` (or `@last`) step K (see [`pvd::split_selector`],
/// [`exodus::split_selector`], [`vtkhdf::split_selector`]).
pub fn read(path: &Path) -> Result<Grid> {
    if let Some((file, sel)) = pvd::split_selector(path) {
        check_sniff(&file, Format::Pvd, &read_head(&file)?)?;
        return checked(pvd::read_selected(&file, sel)?, path);
    }
    if let Some((file, sel)) = vtkhdf::split_selector(path) {
        let bytes = read_file(&file)?;
        check_vtkhdf_sniff(&file, &bytes)?;
        return checked(vtkhdf::read_vec_at(bytes, &file, sel)?, path);
    }
    if let Some((file, sel)) = exodus::split_selector(path) {
        let bytes = read_file(&file)?;
        check_exodus_sniff(&file, &bytes)?;
        return checked(exodus::read_from(&bytes, &file, sel)?, path);
    }
    let format = Format::from_path(path)?;
    let grid = match format {
        Format::Vtm => {
            check_sniff(path, format, &read_head(path)?)?;
            collection::read_vtm(path)?
        }
        Format::Pvd => {
            check_sniff(path, format, &read_head(path)?)?;
            pvd::read_step(path, 0)?
        }
        Format::TetGen => tetgen::read(path)?,
        Format::Medit => {
            let bytes = read_file(path)?;
            check_sniff(path, format, &bytes)?;
            medit::read_bytes(&bytes, path)?
        }
        Format::Pvtu | Format::PStructured => {
            let bytes = read_file(path)?;
            check_sniff(path, format, &bytes)?;
            vtu::pvtu::read(path, &bytes)?
        }
        Format::Vtu | Format::Vti | Format::Vtr | Format::Vts | Format::Vtp => {
            check_sniff(path, format, &read_head(path)?)?;
            vtu::read_path(path)?
        }
        Format::Legacy => {
            check_sniff(path, format, &read_head(path)?)?;
            legacy::read_path(path)?
        }
        Format::Msh => {
            check_sniff(path, format, &read_head(path)?)?;
            msh::read_path(path)?
        }
        Format::Exodus => {
            let bytes = read_file(path)?;
            check_exodus_sniff(path, &bytes)?;
            exodus::read_from(&bytes, path, pvd::Selector::Index(0))?
        }
        Format::VtkHdf => {
            let bytes = read_file(path)?;
            check_vtkhdf_sniff(path, &bytes)?;
            vtkhdf::read_vec(bytes, path)?
        }
    };
    checked(grid, path)
}

fn checked(mut grid: Grid, path: &Path) -> Result<Grid> {
    unique_names(&mut grid, path);
    grid.validate()
        .map_err(|m| FormatError::whole(format!("invalid mesh: {m}")).with_file(path))?;
    Ok(grid)
}

/// Renames arrays that repeat a name in their set (see [`Grid::rename_duplicates`]), each with
/// a warning naming the file: every reader's grid passes here.
fn unique_names(grid: &mut Grid, path: &Path) {
    for r in grid.rename_duplicates() {
        warn(&format!("{}: {r}", path.display()));
    }
}

/// An `.exo` whose content is another format's is refused as such; content of no known format
/// (NetCDF-4's HDF5, which is not sniffed: HDF5 holds many formats) is left to the Exodus
/// reader, which reads NetCDF-4 and says what else it is.
fn check_exodus_sniff(path: &Path, bytes: &[u8]) -> Result<()> {
    match sniff(bytes) {
        None => Ok(()),
        Some(_) => check_sniff(path, Format::Exodus, bytes),
    }
}

/// A VTKHDF file is HDF5, which [`sniff`] does not name (HDF5 holds many formats): content
/// that [`sniff`] names is refused as that format, and the VTKHDF reader says what else is wrong.
fn check_vtkhdf_sniff(path: &Path, bytes: &[u8]) -> Result<()> {
    match sniff(bytes) {
        Some(found) if !exodus::is_hdf5(bytes) => Err(FormatError::whole(format!(
            "the extension says {} but the content is {}",
            Format::VtkHdf.name(),
            found.name()
        ))
        .with_file(path)),
        _ => Ok(()),
    }
}

/// The first 4 KiB of a file, enough to sniff its format without reading it all.
pub(crate) fn read_head(path: &Path) -> Result<Vec<u8>> {
    use std::io::Read;
    let mut head = Vec::with_capacity(4096);
    std::fs::File::open(path)
        .and_then(|f| f.take(4096).read_to_end(&mut head))
        .map_err(|e| FormatError::io(path, e))?;
    Ok(head)
}

fn check_sniff(path: &Path, format: Format, bytes: &[u8]) -> Result<()> {
    match sniff(bytes) {
        Some(found) if found == format => Ok(()),
        Some(found) => Err(FormatError::whole(format!(
            "the extension says {} but the content is {}",
            format.name(),
            found.name()
        ))
        .with_file(path)),
        None => Err(FormatError::at_byte(
            0,
            format!(
                "the extension says {} but the content does not start like one",
                format.name()
            ),
        )
        .with_file(path)),
    }
}

/// Reads a single-file format from memory (stdin, say). `format` `None` sniffs the content.
/// TetGen, PVTU, VTM and PVD need sibling files and cannot be read this way.
pub fn read_bytes(bytes: &[u8], format: Format) -> Result<Grid> {
    let mut grid = match format {
        Format::Vtu | Format::Vti | Format::Vtr | Format::Vts | Format::Vtp => vtu::read(bytes)?,
        Format::Legacy => legacy::read(bytes)?,
        Format::Medit => medit::read_bytes(bytes, Path::new("<input>"))?,
        Format::Msh => msh::read_from(bytes, None)?,
        Format::Exodus => exodus::read_from(bytes, Path::new("<input>"), pvd::Selector::Index(0))?,
        Format::VtkHdf => vtkhdf::read_from(bytes, Path::new("<input>"))?,
        Format::Pvtu | Format::TetGen | Format::Vtm | Format::Pvd | Format::PStructured => {
            return Err(FormatError::whole(format!(
                "{} needs files beside it and cannot be read from a stream",
                format.name()
            )))
        }
    };
    unique_names(&mut grid, Path::new("<input>"));
    grid.validate()
        .map_err(|m| FormatError::whole(format!("invalid mesh: {m}")))?;
    Ok(grid)
}

/// Writes a mesh atomically, choosing the writer by extension. TetGen writes `.node` and `.ele`
/// beside each other (both or neither).
pub fn write(path: &Path, grid: &Grid, opts: &WriteOptions) -> Result<()> {
    let format = Format::for_output(path)?;
    grid.validate().map_err(|m| {
        FormatError::whole(format!("refusing to write an invalid mesh: {m}")).with_file(path)
    })?;
    match format {
        Format::TetGen => tetgen::write(path, grid),
        Format::Pvtu => vtu::pvtu::write(path, std::slice::from_ref(grid), opts),
        Format::Vtu | Format::Legacy | Format::Medit => {
            let mut f = atomic::AtomicFile::create(path).map_err(|e| FormatError::io(path, e))?;
            match format {
                // The Medit writer names the file in its warnings about dropped arrays.
                Format::Medit => medit::write(&mut f, grid, path),
                _ => write_to(&mut f, format, grid, opts),
            }
            .map_err(|e| e.with_file(path))?;
            f.commit().map_err(|e| FormatError::io(path, e))
        }
        _ => Err(read_only(format).with_file(path)),
    }
}

fn read_only(format: Format) -> FormatError {
    FormatError::whole(format!(
        "tetkit reads {} but does not write it; write {WRITTEN}",
        format.name()
    ))
}

/// Writes a single-file format to a stream (stdout, say).
pub fn write_to(w: &mut dyn Write, format: Format, grid: &Grid, opts: &WriteOptions) -> Result<()> {
    match format {
        Format::Vtu => vtu::write(w, grid, opts),
        Format::Legacy => legacy::write(w, grid, opts),
        Format::Medit => medit::write(w, grid, Path::new("<output>")),
        Format::Pvtu | Format::TetGen => Err(FormatError::whole(format!(
            "{} writes several files and cannot be written to a stream",
            format.name()
        ))),
        _ => Err(read_only(format)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sniff_goes_by_the_root_type() {
        let vtu = br#"<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">
<UnstructuredGrid><FieldData><Array type="String" Name="note">vtkMultiBlockDataSet Collection</Array>"#;
        assert_eq!(sniff(vtu), Some(Format::Vtu));
        let vtm = b"<VTKFile byte_order='LittleEndian' type='vtkMultiBlockDataSet'>";
        assert_eq!(sniff(vtm), Some(Format::Vtm));
        assert_eq!(
            sniff(b"<VTKFile type=\"Collection\" version=\"0.1\">"),
            Some(Format::Pvd)
        );
        assert_eq!(
            sniff(b"<VTKFile type = \"PUnstructuredGrid\">"),
            Some(Format::Pvtu)
        );
        assert_eq!(sniff(b"<VTKFile type=\"PolyData\">"), Some(Format::Vtp));
        assert_eq!(sniff(b"<VTKFile type=\"ImageData\">"), Some(Format::Vti));
        assert_eq!(sniff(b"<VTKFile type=\"Table\">"), None);
        assert_eq!(sniff(b"# vtk DataFile Version 4.2\n"), Some(Format::Legacy));
    }

    #[test]
    fn exodus_is_sniffed_by_the_netcdf_magic() {
        for m in [b"CDF\x01", b"CDF\x02", b"CDF\x05"] {
            assert_eq!(sniff(m), Some(Format::Exodus));
        }
        assert_eq!(sniff(b"CDF\x03"), None);
        assert_eq!(sniff(b"\x89HDF\r\n"), None);
        for ext in ["exo", "E", "ex2", "exii", "g", "gen"] {
            let p = format!("a.{ext}");
            assert_eq!(Format::from_path(Path::new(&p)).unwrap(), Format::Exodus);
        }
        assert_eq!(Format::from_name("exodus"), Some(Format::Exodus));
        assert!(Format::Exodus.read_only());
    }

    #[test]
    fn vtkhdf_is_named_by_its_extension_and_read_only() -> Result<()> {
        for ext in ["vtkhdf", "HDF", "hdf"] {
            let p = format!("a.{ext}");
            assert_eq!(Format::from_path(Path::new(&p))?, Format::VtkHdf);
        }
        assert_eq!(Format::from_name("vtkhdf"), Some(Format::VtkHdf));
        assert!(Format::VtkHdf.read_only());
        assert_eq!(Format::VtkHdf.name(), "VTKHDF");
        // HDF5 holds many formats: the extension decides, the content is not sniffed.
        assert_eq!(sniff(b"\x89HDF\r\n\x1a\n"), None);
        let e = write(
            Path::new("out.vtkhdf"),
            &Grid::default(),
            &WriteOptions::default(),
        )
        .err();
        assert!(e.is_some_and(|e| e.to_string().contains("does not write")));
        Ok(())
    }

    /// A tet whose point, cell and field data repeat names, as some writers do.
    fn repeated_names() -> Grid {
        let mut g = Grid::default();
        g.points.data = ArrayData::Float64(vec![0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1.]);
        g.cells.push(cell_type::TETRA, &[0, 1, 2, 3]);
        let p32 = DataArray::new("p_f64", 1, ArrayData::Float32(vec![1.0, 2.0, 3.0, 4.0]));
        let p64 = DataArray::new("p_f64", 1, ArrayData::Float64(vec![5.0, 6.0, 7.0, 8.0]));
        g.point_data.arrays = vec![p32, p64];
        g.point_data.active = vec![(Attribute::Scalars, "p_f64".into())];
        g.cell_data.arrays = vec![
            DataArray::new("c", 1, ArrayData::Int32(vec![1])),
            DataArray::new("c", 3, ArrayData::Float64(vec![1.0, 2.0, 3.0])),
        ];
        g.field_data = vec![
            DataArray::new("f", 1, ArrayData::Int64(vec![7, 8])),
            DataArray::new("f", 1, ArrayData::Float32(vec![0.5])),
        ];
        g
    }

    #[test]
    fn every_reader_renames_repeated_array_names() -> Result<()> {
        let g = repeated_names();
        let opts = WriteOptions {
            encoding: Encoding::Ascii,
            ..WriteOptions::default()
        };
        for format in [Format::Vtu, Format::Legacy] {
            let mut bytes = Vec::new();
            write_to(&mut bytes, format, &g, &opts)?;
            let back = read_bytes(&bytes, format)?;
            let names = |a: &[DataArray]| a.iter().map(|a| a.name.clone()).collect::<Vec<_>>();
            assert_eq!(
                names(&back.point_data.arrays),
                ["p_f64", "p_f64 (2)"],
                "{format:?}"
            );
            assert_eq!(names(&back.cell_data.arrays), ["c", "c (2)"], "{format:?}");
            assert_eq!(names(&back.field_data), ["f", "f (2)"], "{format:?}");
            let second = back.point_data.get("p_f64 (2)");
            assert!(second.is_some_and(|a| a.data == ArrayData::Float64(vec![5.0, 6.0, 7.0, 8.0])));
            let c2 = back.cell_data.get("c (2)");
            assert!(c2.is_some_and(|a| a.components == 3));
            let active = back.point_data.active(Attribute::Scalars);
            assert!(
                active.is_some_and(|a| a.data.type_name() == "Float32"),
                "{format:?}"
            );
            assert_eq!(back.point_data.active.len(), 1, "{format:?}");
        }
        // Through a file too, the path the command line takes.
        let dir = tempfile::tempdir().map_err(|e| FormatError::whole(e.to_string()))?;
        let path = dir.path().join("dup.vtu");
        write(&path, &g, &opts)?;
        let back = read(&path)?;
        assert!(back.point_data.get("p_f64 (2)").is_some());
        Ok(())
    }

    #[test]
    fn text_that_is_not_utf8_is_kept_lossily_and_shown_as_written() -> Result<()> {
        assert_eq!(lossy_text(b"label"), ("label".to_string(), None));
        let (s, raw) = lossy_text(b"lab\xe9l \x01");
        assert_eq!(s, "lab\u{fffd}l \u{1}");
        assert_eq!(raw.as_deref(), Some("lab\\xe9l \\x01"));
        // The user's file: a FIELD array named lab\xe9l (its title line is not UTF-8 either).
        let file = b"# vtk DataFile Version 4.2\nt\xe9st\nASCII\nDATASET UNSTRUCTURED_GRID\n\
POINTS 4 float\n0 0 0 1 0 0 0 1 0 0 0 1\nCELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\n\
CELL_DATA 1\nFIELD f 1\nlab\xe9l 1 1 string\nv\xe9lue\n";
        let g = read_bytes(file, Format::Legacy)?;
        let a = g.cell_data.get("lab\u{fffd}l");
        assert!(a.is_some_and(|a| a.data == ArrayData::String(vec!["v\u{fffd}lue".into()])));
        Ok(())
    }

    #[test]
    fn medit_is_sniffed_by_its_first_keyword() {
        assert_eq!(sniff(b"MeshVersionFormatted 2\n"), Some(Format::Medit));
        assert_eq!(
            sniff(b"# made by x\n\n  # more\n meshversionformatted\n1"),
            Some(Format::Medit)
        );
        assert_eq!(sniff(b"Dimension 3\nMeshVersionFormatted 2"), None);
        assert_eq!(
            Format::from_path(Path::new("a.MESH")).unwrap(),
            Format::Medit
        );
        let e = Format::from_path(Path::new("a.meshb")).unwrap_err();
        assert!(e.to_string().contains("binary Medit"), "{e}");
        assert_eq!(Format::from_name("medit"), Some(Format::Medit));
    }
}
