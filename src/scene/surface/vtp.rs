//! VTK XML PolyData (.vtp) reader: points and polygons in ascii, inline base64 binary, or
//! appended (raw or base64) data, uncompressed or zlib-compressed, UInt32 or UInt64 headers.

use base64::Engine;
use formats::FormatError;
use quick_xml::events::{BytesStart, Event};
use std::io::Read;

use super::RawSurface;

#[derive(Default)]
struct ArrayRef {
    ty: String,
    format: String,
    components: usize,
    offset: usize,
    text: String,
    name: String,
    /// Byte position of the element, for errors.
    at: u64,
}

struct Layout {
    header64: bool,
    zlib: bool,
}

fn attr(e: &BytesStart, key: &str) -> Option<String> {
    e.attributes()
        .flatten()
        .find(|a| a.key.as_ref() == key.as_bytes())
        .map(|a| String::from_utf8_lossy(&a.value).into_owned())
}

pub(super) fn read(bytes: &[u8]) -> Result<RawSurface, FormatError> {
    // Raw appended data is not XML: parse only what precedes it.
    let app_tag = find(bytes, b"<AppendedData");
    let (xml, appended) = match app_tag {
        Some(p) => {
            let start = bytes[p..]
                .iter()
                .position(|&b| b == b'_')
                .map(|i| p + i + 1)
                .ok_or_else(|| {
                    FormatError::at_byte(p as u64, "<AppendedData> without '_' marker")
                })?;
            let tag_end = bytes[p..]
                .iter()
                .position(|&b| b == b'>')
                .map_or(p, |i| p + i);
            let encoding = String::from_utf8_lossy(&bytes[p..tag_end]).contains("base64");
            (&bytes[..p], Some((start, encoding)))
        }
        None => (bytes, None),
    };
    let mut reader = quick_xml::Reader::from_reader(xml);
    let mut buf = Vec::new();
    let mut layout = Layout {
        header64: false,
        zlib: false,
    };
    let mut section = String::new();
    let mut current: Option<ArrayRef> = None;
    let mut points_arr: Option<ArrayRef> = None;
    let mut conn: Option<ArrayRef> = None;
    let mut offs: Option<ArrayRef> = None;
    let mut strips: Option<ArrayRef> = None;
    let mut saw_file = false;
    loop {
        let pos = reader.buffer_position();
        let ev = reader
            .read_event_into(&mut buf)
            .map_err(|e| FormatError::at_byte(pos, format!("XML error: {e}")))?;
        match ev {
            Event::Start(ref e) | Event::Empty(ref e) => {
                let empty = matches!(ev, Event::Empty(_));
                let name = String::from_utf8_lossy(e.name().as_ref()).into_owned();
                match name.as_str() {
                    "VTKFile" => {
                        saw_file = true;
                        let ty = attr(e, "type").unwrap_or_default();
                        if ty != "PolyData" {
                            return Err(FormatError::at_byte(
                                pos,
                                format!("a body surface must be VTKFile type=\"PolyData\", found \"{ty}\""),
                            ));
                        }
                        if attr(e, "byte_order").is_some_and(|b| b == "BigEndian") {
                            return Err(FormatError::at_byte(
                                pos,
                                "big-endian .vtp is not supported",
                            ));
                        }
                        layout.header64 = attr(e, "header_type").is_some_and(|h| h == "UInt64");
                        match attr(e, "compressor").as_deref() {
                            None | Some("") => {}
                            Some("vtkZLibDataCompressor") => layout.zlib = true,
                            Some(other) => {
                                return Err(FormatError::at_byte(
                                    pos,
                                    format!("compressor {other} is not supported for surfaces (use zlib or none)"),
                                ))
                            }
                        }
                    }
                    "Points" | "Polys" | "Strips" | "Verts" | "Lines" | "PointData"
                    | "CellData" | "FieldData" => section = name,
                    "DataArray" => {
                        current = Some(ArrayRef {
                            ty: attr(e, "type").unwrap_or_default(),
                            format: attr(e, "format").unwrap_or_else(|| "ascii".into()),
                            components: attr(e, "NumberOfComponents")
                                .and_then(|s| s.parse().ok())
                                .unwrap_or(1),
                            offset: attr(e, "offset").and_then(|s| s.parse().ok()).unwrap_or(0),
                            text: String::new(),
                            name: attr(e, "Name").unwrap_or_default(),
                            at: pos,
                        });
                        if empty {
                            finish(
                                &section,
                                current.take(),
                                &mut points_arr,
                                &mut conn,
                                &mut offs,
                                &mut strips,
                            )?;
                        }
                    }
                    _ => {}
                }
            }
            Event::Text(t) => {
                if let Some(c) = current.as_mut() {
                    c.text.push_str(&String::from_utf8_lossy(t.as_ref()));
                }
            }
            Event::End(e) => {
                let name = String::from_utf8_lossy(e.name().as_ref()).into_owned();
                if name == "DataArray" {
                    finish(
                        &section,
                        current.take(),
                        &mut points_arr,
                        &mut conn,
                        &mut offs,
                        &mut strips,
                    )?;
                } else if name == section {
                    section.clear();
                }
            }
            Event::Eof => break,
            _ => {}
        }
        buf.clear();
    }
    if !saw_file {
        return Err(FormatError::at_byte(0, "not a VTK XML file (no <VTKFile>)"));
    }
    if let Some(st) = &strips {
        if !values(st, &layout, bytes, appended)?.is_empty() {
            return Err(FormatError::at_byte(
                st.at,
                "triangle strips are not supported in a body surface (write polygons)",
            ));
        }
    }
    let pts = points_arr.ok_or_else(|| FormatError::whole("no <Points> array"))?;
    if pts.components != 3 {
        return Err(FormatError::in_array(&pts.name, "points need 3 components"));
    }
    let pv = values(&pts, &layout, bytes, appended)?;
    let points: Vec<[f64; 3]> = pv.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let (Some(conn), Some(offs)) = (conn, offs) else {
        return Err(FormatError::whole(
            "no <Polys> with connectivity and offsets arrays",
        ));
    };
    let cv = values(&conn, &layout, bytes, appended)?;
    let ov = values(&offs, &layout, bytes, appended)?;
    let mut polys = Vec::with_capacity(ov.len());
    let mut prev = 0usize;
    for (i, &o) in ov.iter().enumerate() {
        let o = o as usize;
        if o < prev || o > cv.len() {
            return Err(FormatError::in_array(
                "offsets",
                format!("offset {i} = {o} out of range"),
            ));
        }
        let mut ids = Vec::with_capacity(o - prev);
        for &v in &cv[prev..o] {
            if v < 0.0 || v as usize >= points.len() {
                return Err(FormatError::in_array(
                    "connectivity",
                    format!("point id {v} out of range ({} points)", points.len()),
                ));
            }
            ids.push(v as u32);
        }
        polys.push(ids);
        prev = o;
    }
    Ok(RawSurface { points, polys })
}

fn finish(
    section: &str,
    arr: Option<ArrayRef>,
    points: &mut Option<ArrayRef>,
    conn: &mut Option<ArrayRef>,
    offs: &mut Option<ArrayRef>,
    strips: &mut Option<ArrayRef>,
) -> Result<(), FormatError> {
    let Some(a) = arr else { return Ok(()) };
    match section {
        "Points" => *points = Some(a),
        "Polys" if a.name == "connectivity" => *conn = Some(a),
        "Polys" if a.name == "offsets" => *offs = Some(a),
        "Strips" if a.name == "offsets" => *strips = Some(a),
        _ => {}
    }
    Ok(())
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

fn b64(text: &[u8]) -> Result<Vec<u8>, String> {
    base64::engine::general_purpose::STANDARD
        .decode(text)
        .map_err(|e| format!("bad base64: {e}"))
}

fn b64_chars(n: usize) -> usize {
    n.div_ceil(3) * 4
}

fn header_ints(bytes: &[u8], wide: bool) -> Vec<usize> {
    if wide {
        bytes
            .chunks_exact(8)
            .map(|c| u64::from_le_bytes(c.try_into().unwrap_or([0; 8])) as usize)
            .collect()
    } else {
        bytes
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as usize)
            .collect()
    }
}

/// Decodes one binary array block (header + data) from raw bytes or base64 text.
fn decode_block(src: &[u8], base64: bool, layout: &Layout) -> Result<Vec<u8>, String> {
    let hs = if layout.header64 { 8 } else { 4 };
    let take = |from: usize, n: usize| -> Result<Vec<u8>, String> {
        if base64 {
            let chars = b64_chars(n);
            let s = src.get(from..from + chars).ok_or("data ends early")?;
            let mut v = b64(s)?;
            v.truncate(n);
            Ok(v)
        } else {
            src.get(from..from + n)
                .map(<[u8]>::to_vec)
                .ok_or_else(|| "data ends early".into())
        }
    };
    if !layout.zlib {
        let first = header_ints(&take(0, hs)?, layout.header64)[0];
        if base64 {
            let all = take(0, hs + first)?;
            return Ok(all[hs..].to_vec());
        }
        return take(hs, first);
    }
    let nblocks = header_ints(&take(0, hs)?, layout.header64)[0];
    let hlen = (3 + nblocks) * hs;
    let header = header_ints(&take(0, hlen)?, layout.header64);
    let sizes = &header[3..];
    let total: usize = sizes.iter().sum();
    let data_at = if base64 { b64_chars(hlen) } else { hlen };
    let data = take(data_at, total)?;
    let mut out = Vec::new();
    let mut at = 0;
    for &s in sizes {
        let mut z = flate2::read::ZlibDecoder::new(&data[at..at + s]);
        z.read_to_end(&mut out).map_err(|e| format!("zlib: {e}"))?;
        at += s;
    }
    Ok(out)
}

fn values(
    a: &ArrayRef,
    layout: &Layout,
    file: &[u8],
    appended: Option<(usize, bool)>,
) -> Result<Vec<f64>, FormatError> {
    let err =
        |m: String| FormatError::in_array(if a.name.is_empty() { "Points" } else { &a.name }, m);
    if a.format == "ascii" {
        return a
            .text
            .split_whitespace()
            .map(|t| {
                t.parse::<f64>()
                    .map_err(|_| err(format!("'{t}' is not a number")))
            })
            .collect();
    }
    let bytes = match a.format.as_str() {
        "binary" => {
            let text: Vec<u8> = a
                .text
                .bytes()
                .filter(|b| !b.is_ascii_whitespace())
                .collect();
            decode_block(&text, true, layout).map_err(err)?
        }
        "appended" => {
            let (start, enc) =
                appended.ok_or_else(|| err("format=\"appended\" but no <AppendedData>".into()))?;
            let src = file
                .get(start + a.offset..)
                .ok_or_else(|| err("offset past the end".into()))?;
            decode_block(src, enc, layout).map_err(err)?
        }
        other => return Err(err(format!("unknown format \"{other}\""))),
    };
    let conv = |size: usize, f: &dyn Fn(&[u8]) -> f64| -> Vec<f64> {
        bytes.chunks_exact(size).map(f).collect()
    };
    Ok(match a.ty.as_str() {
        "Float32" => conv(4, &|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f64),
        "Float64" => conv(8, &|c| f64::from_le_bytes(c.try_into().unwrap_or([0; 8]))),
        "Int32" => conv(4, &|c| i32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f64),
        "UInt32" => conv(4, &|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f64),
        "Int64" => conv(8, &|c| {
            i64::from_le_bytes(c.try_into().unwrap_or([0; 8])) as f64
        }),
        "UInt64" => conv(8, &|c| {
            u64::from_le_bytes(c.try_into().unwrap_or([0; 8])) as f64
        }),
        "Int16" => conv(2, &|c| i16::from_le_bytes([c[0], c[1]]) as f64),
        "UInt16" => conv(2, &|c| u16::from_le_bytes([c[0], c[1]]) as f64),
        "Int8" => conv(1, &|c| c[0] as i8 as f64),
        "UInt8" => conv(1, &|c| c[0] as f64),
        other => return Err(err(format!("unsupported type \"{other}\""))),
    })
}
