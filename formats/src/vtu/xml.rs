//! The XML structure of a .vtu (or a .vtp, .vti, .vtr or .vts: they share the layout), read with
//! quick-xml events: which arrays exist, their attributes, and their inline text; stops at
//! `<AppendedData>` (binary follows, which is not XML).

use super::{ByteOrder, Compressor, HeaderType, Layout};
use crate::structured::Image;
use crate::{Attribute, FormatError, PolySection, Result, ScalarType};
use quick_xml::events::{BytesStart, Event};
use std::io::BufRead;

/// How an array's values are stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum DataFormat {
    Ascii,
    Binary,
    Appended,
}

/// Element type of an array in the file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ElemType {
    Num(ScalarType),
    String,
    /// vtkBitArray: one bit per value, packed most significant bit first in binary data; read
    /// as UInt8 0/1, as the legacy reader does.
    Bit,
}

/// One `<DataArray>` or `<Array>` element.
#[derive(Clone, Debug)]
pub(crate) struct ArrayXml {
    pub name: String,
    pub ty: ElemType,
    pub components: usize,
    /// Whether `NumberOfComponents` was written (meshio leaves it out of 3x3 tensors).
    pub components_given: bool,
    pub component_names: Vec<String>,
    /// `IdType="1"` (or `type="IdType"`): a vtkIdTypeArray.
    pub id_type: bool,
    pub tuples: Option<usize>,
    pub format: DataFormat,
    pub offset: Option<u64>,
    /// Inline text (ascii values or base64), as in the file.
    pub text: Vec<u8>,
    /// File offset of the first byte of `text`.
    pub text_pos: u64,
    /// File offset of the element's start tag.
    pub tag_pos: u64,
}

/// `<PointData>` or `<CellData>`.
#[derive(Clone, Debug, Default)]
pub(crate) struct AttributesXml {
    pub arrays: Vec<ArrayXml>,
    pub active: Vec<(Attribute, String)>,
}

/// The PolyData section a tag opens, and the `<Piece>` attribute that counts its cells.
fn poly_section(tag: &[u8]) -> Option<PolySection> {
    Some(match tag {
        b"Verts" => PolySection::Verts,
        b"Lines" => PolySection::Lines,
        b"Polys" => PolySection::Polys,
        b"Strips" => PolySection::Strips,
        _ => return None,
    })
}

fn count_attr(sec: PolySection) -> &'static str {
    match sec {
        PolySection::Verts => "NumberOfVerts",
        PolySection::Lines => "NumberOfLines",
        PolySection::Polys => "NumberOfPolys",
        PolySection::Strips => "NumberOfStrips",
    }
}

/// One `<Piece>`.
#[derive(Clone, Debug, Default)]
pub(crate) struct PieceXml {
    pub num_points: usize,
    /// NumberOfCells; for PolyData the sum of the four section counts.
    pub num_cells: usize,
    /// PolyData only: each section's cell count and its connectivity/offsets arrays.
    pub poly: Vec<(PolySection, usize, Vec<ArrayXml>)>,
    pub point_data: AttributesXml,
    pub cell_data: AttributesXml,
    pub points: Option<ArrayXml>,
    /// connectivity, offsets, types, faces, faceoffsets, in file order.
    pub cells: Vec<ArrayXml>,
    /// Structured data: the piece's `Extent` (i0 i1 j0 j1 k0 k1).
    pub extent: Option<[i64; 6]>,
    /// RectilinearGrid: the x, y and z coordinate arrays of `<Coordinates>`, in file order.
    pub coordinates: Vec<ArrayXml>,
    pub tag_pos: u64,
}

/// What a structured file's root type says about its points and cells.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum StructuredXml {
    /// ImageData: points from origin, spacing and direction.
    Image(Image),
    /// RectilinearGrid: points from three coordinate lists.
    Rectilinear,
    /// StructuredGrid: points given, cells implied.
    Curvilinear,
}

/// Where the appended block is.
#[derive(Clone, Copy, Debug)]
pub(crate) struct AppendedXml {
    pub raw: bool,
    /// File offset just after the `<AppendedData ...>` tag (the `_` marker follows, after blanks).
    pub tag_end: u64,
}

#[derive(Clone, Debug)]
pub(crate) struct Document {
    /// `type="PolyData"` (a .vtp) rather than UnstructuredGrid.
    pub poly_data: bool,
    /// ImageData, RectilinearGrid or StructuredGrid (a .vti, .vtr or .vts).
    pub structured: Option<StructuredXml>,
    pub layout: Layout,
    pub field_data: Vec<ArrayXml>,
    pub pieces: Vec<PieceXml>,
    pub appended: Option<AppendedXml>,
    /// The root's `version` as (major, minor); (0, 1) when absent.
    pub version: (u32, u32),
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Ctx {
    File,
    Grid,
    FieldData,
    Piece,
    PointData,
    CellData,
    Points,
    Cells,
    Coordinates,
    Poly,
    Array,
    Other,
}

fn xml_err(pos: u64, e: impl std::fmt::Display) -> FormatError {
    FormatError::at_byte(pos, format!("malformed XML: {e}"))
}

/// Attributes of a start tag as (name, unescaped value).
fn attrs(e: &BytesStart, pos: u64) -> Result<Vec<(String, String)>> {
    let mut out = Vec::new();
    for a in e.attributes().with_checks(true) {
        let a = a.map_err(|err| xml_err(pos, err))?;
        let key = String::from_utf8_lossy(a.key.as_ref()).into_owned();
        let value = a.unescape_value().map_err(|err| xml_err(pos, err))?;
        out.push((key, value.into_owned()));
    }
    Ok(out)
}

fn get<'a>(attrs: &'a [(String, String)], key: &str) -> Option<&'a str> {
    attrs
        .iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.as_str())
}

pub(crate) fn parse_count(value: &str, what: &str, pos: u64) -> Result<usize> {
    value.trim().parse::<usize>().map_err(|_| {
        FormatError::at_byte(
            pos,
            format!("{what}=\"{value}\" is not a non-negative integer that fits this machine"),
        )
    })
}

fn layout_from(a: &[(String, String)], pos: u64) -> Result<Layout> {
    let order = match get(a, "byte_order").unwrap_or("LittleEndian") {
        "LittleEndian" => ByteOrder::LittleEndian,
        "BigEndian" => ByteOrder::BigEndian,
        other => {
            return Err(FormatError::at_byte(
                pos,
                format!("unknown byte_order \"{other}\""),
            ))
        }
    };
    let header = match get(a, "header_type").unwrap_or("UInt32") {
        "UInt32" => HeaderType::UInt32,
        "UInt64" => HeaderType::UInt64,
        other => {
            return Err(FormatError::at_byte(
                pos,
                format!("unsupported header_type \"{other}\" (UInt32 or UInt64)"),
            ))
        }
    };
    let name = get(a, "compressor").unwrap_or("");
    let compressor = Compressor::from_vtk_name(name)
        .ok_or_else(|| FormatError::at_byte(pos, format!("unknown compressor \"{name}\"")))?;
    Ok(Layout {
        header,
        order,
        compressor,
    })
}

fn array_from(a: &[(String, String)], pos: u64) -> Result<ArrayXml> {
    let name = get(a, "Name").unwrap_or("").to_string();
    let here = |msg: String| FormatError::at_byte(pos, format!("array '{name}': {msg}"));
    let ty_name = get(a, "type").ok_or_else(|| here("no type attribute".into()))?;
    let ty = match ty_name {
        "String" => ElemType::String,
        "Bit" => ElemType::Bit,
        // VTK 9 writes vtkIdTypeArray as Int64/Int32; older files may say IdType (64-bit builds).
        "IdType" => ElemType::Num(ScalarType::Int64),
        t => ElemType::Num(ScalarType::from_xml_name(t).ok_or_else(|| {
            here(format!(
                "unsupported type \"{t}\" (Int8..UInt64, Float32, Float64, Bit, String)"
            ))
        })?),
    };
    let components = match get(a, "NumberOfComponents") {
        Some(v) => parse_count(v, "NumberOfComponents", pos)?,
        None => 1,
    };
    if components == 0 {
        return Err(here("NumberOfComponents is 0".into()));
    }
    let mut component_names = Vec::new();
    for i in 0..components.min(4096) {
        match get(a, &format!("ComponentName{i}")) {
            Some(n) => {
                component_names.resize(i, String::new());
                component_names.push(n.to_string());
            }
            None => continue,
        }
    }
    if !component_names.is_empty() {
        // Names are looked up for the first 4096 components only; never size a list by an
        // unchecked count.
        if components > 4096 {
            return Err(here(format!(
                "{components} components with ComponentName attributes (at most 4096 are supported)"
            )));
        }
        component_names.resize(components, String::new());
    }
    let tuples = match get(a, "NumberOfTuples") {
        Some(v) => Some(parse_count(v, "NumberOfTuples", pos)?),
        None => None,
    };
    let format = match get(a, "format").unwrap_or("ascii") {
        "ascii" => DataFormat::Ascii,
        "binary" => DataFormat::Binary,
        "appended" => DataFormat::Appended,
        other => return Err(here(format!("unknown format \"{other}\""))),
    };
    let offset = match get(a, "offset") {
        Some(v) => Some(
            v.trim()
                .parse::<u64>()
                .map_err(|_| here(format!("offset=\"{v}\" is not a non-negative integer")))?,
        ),
        None => None,
    };
    if format == DataFormat::Appended && offset.is_none() {
        return Err(here("format=\"appended\" without an offset".into()));
    }
    Ok(ArrayXml {
        name,
        ty,
        components,
        components_given: get(a, "NumberOfComponents").is_some(),
        component_names,
        id_type: ty_name == "IdType" || get(a, "IdType").is_some_and(|v| v.trim() == "1"),
        tuples,
        format,
        offset,
        text: Vec::new(),
        text_pos: 0,
        tag_pos: pos,
    })
}

/// Six integers, as `Extent` and `WholeExtent` hold; `None` when the attribute is absent.
fn extent_from(a: &[(String, String)], key: &str, pos: u64) -> Result<Option<[i64; 6]>> {
    get(a, key).map(|v| parse_extent(v, key, pos)).transpose()
}

/// The six integers of an extent attribute's value `v` (attribute `key`, for the error).
pub(crate) fn parse_extent(v: &str, key: &str, pos: u64) -> Result<[i64; 6]> {
    let bad = || FormatError::at_byte(pos, format!("{key}=\"{v}\" is not six integers"));
    let nums = v
        .split_whitespace()
        .map(|t| t.parse::<i64>().map_err(|_| bad()))
        .collect::<Result<Vec<_>>>()?;
    <[i64; 6]>::try_from(nums).map_err(|_| bad())
}

/// `n` finite numbers from an attribute, or `default` when it is absent.
fn floats<const N: usize>(
    a: &[(String, String)],
    key: &str,
    default: [f64; N],
    pos: u64,
) -> Result<[f64; N]> {
    let Some(v) = get(a, key) else {
        return Ok(default);
    };
    let bad = || FormatError::at_byte(pos, format!("{key}=\"{v}\" is not {N} finite numbers"));
    let nums = v
        .split_whitespace()
        .map(|t| {
            t.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(bad)
        })
        .collect::<Result<Vec<_>>>()?;
    <[f64; N]>::try_from(nums).map_err(|_| bad())
}

/// The geometry attributes of `<ImageData>` (VTK 9 adds `Direction`; older files have none).
fn image_from(a: &[(String, String)], pos: u64) -> Result<Image> {
    let d = Image::default();
    Ok(Image {
        origin: floats(a, "Origin", d.origin, pos)?,
        spacing: floats(a, "Spacing", d.spacing, pos)?,
        direction: floats(a, "Direction", d.direction, pos)?,
    })
}

fn active_from(a: &[(String, String)]) -> Vec<(Attribute, String)> {
    Attribute::ALL
        .iter()
        .filter_map(|&r| get(a, r.xml_name()).map(|n| (r, n.to_string())))
        .collect()
}

/// Reads the XML part of a .vtu from `r` (positioned at the start of the file).
pub(crate) fn parse<R: BufRead>(mut r: R) -> Result<Document> {
    // A UTF-8 byte order mark is skipped here, not by quick-xml, whose positions would then not
    // count it: every byte offset below (the appended data's start above all) is of the file.
    let bom = r.fill_buf().map_or(0, crate::bom_len);
    r.consume(bom);
    let bom = bom as u64;
    let mut reader = quick_xml::Reader::from_reader(r);
    reader.config_mut().trim_text(false);
    reader.config_mut().check_end_names = true;
    let mut buf = Vec::new();
    let mut stack: Vec<Ctx> = Vec::new();
    let mut doc = Document {
        poly_data: false,
        structured: None,
        layout: Layout {
            header: HeaderType::UInt32,
            order: ByteOrder::LittleEndian,
            compressor: Compressor::None,
        },
        field_data: Vec::new(),
        pieces: Vec::new(),
        appended: None,
        version: (0, 1),
    };
    let mut seen_root = false;
    // The array whose text is being collected, and the context it belongs to.
    let mut current: Option<(ArrayXml, Ctx)> = None;
    // The PolyData cell section last opened (its arrays attach to it).
    let mut section: Option<PolySection> = None;
    loop {
        let pos = reader.buffer_position() + bom;
        buf.clear();
        let ev = reader
            .read_event_into(&mut buf)
            .map_err(|e| xml_err(reader.error_position() + bom, e))?;
        let (e, empty) = match ev {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::End(_) => {
                let top = stack.pop();
                if top == Some(Ctx::Array) {
                    if let Some((a, parent)) = current.take() {
                        attach(&mut doc, parent, section, a, pos)?;
                    }
                }
                continue;
            }
            Event::Text(t) => {
                if let (Some(Ctx::Array), Some((a, _))) = (stack.last(), current.as_mut()) {
                    if a.text.is_empty() {
                        a.text_pos = pos;
                    }
                    a.text.extend_from_slice(t.as_ref());
                }
                continue;
            }
            Event::CData(t) => {
                if let (Some(Ctx::Array), Some((a, _))) = (stack.last(), current.as_mut()) {
                    if a.text.is_empty() {
                        a.text_pos = pos + 9;
                    }
                    a.text.extend_from_slice(t.as_ref());
                }
                continue;
            }
            Event::DocType(_) => return Err(FormatError::at_byte(
                pos,
                "a DOCTYPE declaration is not allowed in a VTK file (refused: entity expansion)",
            )),
            Event::Eof => break,
            Event::Comment(_) | Event::Decl(_) | Event::PI(_) => continue,
        };
        let local = e.local_name();
        let tag = local.as_ref();
        let parent = stack.last().copied();
        let a = attrs(&e, pos)?;
        let ctx = match (parent, tag) {
            (None, b"VTKFile") => {
                if seen_root {
                    return Err(FormatError::at_byte(pos, "a second <VTKFile> element"));
                }
                seen_root = true;
                match get(&a, "type") {
                    Some("UnstructuredGrid") => {}
                    Some("PolyData") => doc.poly_data = true,
                    Some("ImageData") => {
                        doc.structured = Some(StructuredXml::Image(Image::default()))
                    }
                    Some("RectilinearGrid") => doc.structured = Some(StructuredXml::Rectilinear),
                    Some("StructuredGrid") => doc.structured = Some(StructuredXml::Curvilinear),
                    Some(t @ ("PImageData" | "PRectilinearGrid" | "PStructuredGrid")) => {
                        return Err(FormatError::at_byte(
                            pos,
                            format!(
                                "this is a parallel file ({t}): name it .pvti, .pvtr or .pvts"
                            ),
                        ))
                    }
                    Some("PUnstructuredGrid") => {
                        return Err(FormatError::at_byte(
                            pos,
                            "this is a parallel file (PUnstructuredGrid): name it .pvtu",
                        ))
                    }
                    other => {
                        return Err(FormatError::at_byte(
                            pos,
                            format!(
                            "VTKFile type is {:?}, expected \"UnstructuredGrid\", \"PolyData\", \"ImageData\", \"RectilinearGrid\" or \"StructuredGrid\"",
                            other.unwrap_or("(none)")
                        ),
                        ))
                    }
                }
                doc.layout = layout_from(&a, pos)?;
                if let Some((ma, mi)) = get(&a, "version").and_then(|v| v.trim().split_once('.')) {
                    if let (Ok(ma), Ok(mi)) = (ma.parse(), mi.parse()) {
                        doc.version = (ma, mi);
                    }
                }
                Ctx::File
            }
            (None, _) => {
                return Err(FormatError::at_byte(
                    pos,
                    format!(
                        "root element is <{}>, expected <VTKFile>",
                        String::from_utf8_lossy(tag)
                    ),
                ))
            }
            (Some(Ctx::File), b"UnstructuredGrid")
                if !doc.poly_data && doc.structured.is_none() =>
            {
                Ctx::Grid
            }
            (Some(Ctx::File), b"PolyData") if doc.poly_data => Ctx::Grid,
            (Some(Ctx::File), b"ImageData")
                if matches!(doc.structured, Some(StructuredXml::Image(_))) =>
            {
                doc.structured = Some(StructuredXml::Image(image_from(&a, pos)?));
                Ctx::Grid
            }
            (Some(Ctx::File), b"RectilinearGrid")
                if doc.structured == Some(StructuredXml::Rectilinear) =>
            {
                Ctx::Grid
            }
            (Some(Ctx::File), b"StructuredGrid")
                if doc.structured == Some(StructuredXml::Curvilinear) =>
            {
                Ctx::Grid
            }
            (Some(Ctx::File), b"AppendedData") => {
                let raw = match get(&a, "encoding").unwrap_or("raw") {
                    "raw" => true,
                    "base64" => false,
                    other => {
                        return Err(FormatError::at_byte(
                            pos,
                            format!("unknown AppendedData encoding \"{other}\""),
                        ))
                    }
                };
                if empty {
                    break;
                }
                doc.appended = Some(AppendedXml {
                    raw,
                    tag_end: reader.buffer_position() + bom,
                });
                break;
            }
            (Some(Ctx::Grid), b"FieldData") | (Some(Ctx::Piece), b"FieldData") => Ctx::FieldData,
            (Some(Ctx::Grid), b"Piece") => {
                let np = parse_count(
                    get(&a, "NumberOfPoints").unwrap_or("0"),
                    "NumberOfPoints",
                    pos,
                )?;
                let mut poly = Vec::new();
                let mut extent = None;
                let (np, nc) = if doc.structured.is_some() {
                    let e = extent_from(&a, "Extent", pos)?.ok_or_else(|| {
                        FormatError::at_byte(pos, "a structured <Piece> without an Extent")
                    })?;
                    extent = Some(e);
                    crate::structured::dims(e)
                        .and_then(crate::structured::counts)
                        .map_err(|m| FormatError::at_byte(pos, format!("Extent: {m}")))?
                } else if doc.poly_data {
                    let mut total = 0usize;
                    for sec in PolySection::ALL {
                        let what = count_attr(sec);
                        let n = parse_count(get(&a, what).unwrap_or("0"), what, pos)?;
                        total = total.checked_add(n).ok_or_else(|| {
                            FormatError::at_byte(pos, "the piece's cell counts overflow")
                        })?;
                        poly.push((sec, n, Vec::new()));
                    }
                    (np, total)
                } else {
                    let nc = parse_count(
                        get(&a, "NumberOfCells").unwrap_or("0"),
                        "NumberOfCells",
                        pos,
                    )?;
                    (np, nc)
                };
                doc.pieces.push(PieceXml {
                    num_points: np,
                    num_cells: nc,
                    poly,
                    extent,
                    tag_pos: pos,
                    ..PieceXml::default()
                });
                Ctx::Piece
            }
            (Some(Ctx::Piece), b"PointData") => {
                last_piece(&mut doc, pos)?.point_data.active = active_from(&a);
                Ctx::PointData
            }
            (Some(Ctx::Piece), b"CellData") => {
                last_piece(&mut doc, pos)?.cell_data.active = active_from(&a);
                Ctx::CellData
            }
            (Some(Ctx::Piece), b"Points") => Ctx::Points,
            (Some(Ctx::Piece), b"Cells") if !doc.poly_data && doc.structured.is_none() => {
                Ctx::Cells
            }
            (Some(Ctx::Piece), b"Coordinates")
                if doc.structured == Some(StructuredXml::Rectilinear) =>
            {
                Ctx::Coordinates
            }
            (Some(Ctx::Piece), t) if doc.poly_data && poly_section(t).is_some() => {
                section = poly_section(t);
                Ctx::Poly
            }
            (
                Some(
                    p @ (Ctx::FieldData
                    | Ctx::PointData
                    | Ctx::CellData
                    | Ctx::Points
                    | Ctx::Cells
                    | Ctx::Coordinates
                    | Ctx::Poly),
                ),
                b"DataArray" | b"Array",
            ) => {
                let arr = array_from(&a, pos)?;
                if empty {
                    attach(&mut doc, p, section, arr, pos)?;
                    continue;
                }
                current = Some((arr, p));
                Ctx::Array
            }
            _ => Ctx::Other,
        };
        if !empty {
            stack.push(ctx);
        }
    }
    if !seen_root {
        return Err(FormatError::at_byte(0, "no <VTKFile> element"));
    }
    if doc.appended.is_none() && !stack.is_empty() {
        return Err(FormatError::at_byte(
            reader.buffer_position() + bom,
            "the file ends before its XML is closed (truncated?)",
        ));
    }
    Ok(doc)
}

fn last_piece(doc: &mut Document, pos: u64) -> Result<&mut PieceXml> {
    doc.pieces
        .last_mut()
        .ok_or_else(|| FormatError::at_byte(pos, "data outside a <Piece>"))
}

fn attach(
    doc: &mut Document,
    parent: Ctx,
    section: Option<PolySection>,
    a: ArrayXml,
    pos: u64,
) -> Result<()> {
    match parent {
        Ctx::FieldData => doc.field_data.push(a),
        Ctx::PointData => last_piece(doc, pos)?.point_data.arrays.push(a),
        Ctx::CellData => last_piece(doc, pos)?.cell_data.arrays.push(a),
        Ctx::Points => {
            let p = last_piece(doc, pos)?;
            if p.points.is_some() {
                return Err(FormatError::at_byte(
                    a.tag_pos,
                    "a second array inside <Points>",
                ));
            }
            p.points = Some(a);
        }
        Ctx::Cells => last_piece(doc, pos)?.cells.push(a),
        Ctx::Coordinates => last_piece(doc, pos)?.coordinates.push(a),
        Ctx::Poly => {
            let p = last_piece(doc, pos)?;
            if let Some(entry) = p.poly.iter_mut().find(|e| Some(e.0) == section) {
                entry.2.push(a);
            }
        }
        _ => {}
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOC: &str = r#"<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" byte_order="BigEndian" header_type="UInt64" compressor="vtkLZ4DataCompressor">
  <UnstructuredGrid>
    <FieldData><Array type="String" Name="s" NumberOfTuples="2" format="ascii">104 0 0</Array></FieldData>
    <Piece NumberOfPoints="2" NumberOfCells="0">
      <PointData Scalars="t &amp; u">
        <DataArray type="Float32" Name="t &amp; u" NumberOfComponents="2" ComponentName1="b" format="ascii">
          1 2 3 4
          <InformationKey name="L2_NORM_RANGE"><Value index="0">99</Value></InformationKey>
        </DataArray>
      </PointData>
      <Points><DataArray type="Float64" NumberOfComponents="3" format="appended" offset="0"/></Points>
    </Piece>
  </UnstructuredGrid>
  <AppendedData encoding="raw">
   _binary"#;

    #[test]
    fn structure_attributes_and_text() {
        let d = parse(DOC.as_bytes()).unwrap();
        assert_eq!(d.layout.order, ByteOrder::BigEndian);
        assert_eq!(d.layout.header, HeaderType::UInt64);
        assert_eq!(d.layout.compressor, Compressor::Lz4);
        assert_eq!(d.field_data[0].ty, ElemType::String);
        let p = &d.pieces[0];
        let a = &p.point_data.arrays[0];
        assert_eq!(a.name, "t & u");
        assert_eq!(a.component_names, vec!["".to_string(), "b".to_string()]);
        // The InformationKey's text is not part of the array's values.
        let text = String::from_utf8(a.text.clone()).unwrap();
        assert_eq!(
            text.split_whitespace().collect::<Vec<_>>(),
            ["1", "2", "3", "4"]
        );
        assert_eq!(&DOC.as_bytes()[a.text_pos as usize..][..1], b"\n");
        assert_eq!(
            p.point_data.active,
            vec![(Attribute::Scalars, "t & u".to_string())]
        );
        assert_eq!(p.points.as_ref().unwrap().offset, Some(0));
        let app = d.appended.unwrap();
        assert!(app.raw);
        assert!(DOC[app.tag_end as usize..]
            .trim_start()
            .starts_with("_binary"));
    }

    #[test]
    fn refusals() {
        let doctype = DOC.replacen("<VTKFile", "<!DOCTYPE x [<!ENTITY a \"b\">]><VTKFile", 1);
        assert!(parse(doctype.as_bytes())
            .unwrap_err()
            .message
            .contains("DOCTYPE"));
        let pvtu = DOC.replacen("\"UnstructuredGrid\"", "\"PUnstructuredGrid\"", 1);
        assert!(parse(pvtu.as_bytes())
            .unwrap_err()
            .message
            .contains(".pvtu"));
        let bad = DOC.replacen("UInt64", "UInt16", 1);
        assert!(parse(bad.as_bytes())
            .unwrap_err()
            .message
            .contains("header_type"));
        let cut = &DOC[..DOC.find("<AppendedData").unwrap()];
        assert!(parse(cut.as_bytes())
            .unwrap_err()
            .message
            .contains("truncated"));
    }
}
