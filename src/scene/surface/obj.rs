//! Wavefront OBJ reader: `v` and `f` records (with `v/vt/vn` forms and negative indices);
//! everything else (normals, texture coordinates, groups, materials) is ignored.

use formats::FormatError;

use super::{parse_xyz, RawSurface};

pub(super) fn read(bytes: &[u8]) -> Result<RawSurface, FormatError> {
    let text = std::str::from_utf8(bytes)
        .map_err(|e| FormatError::at_byte(e.valid_up_to() as u64, "OBJ is not UTF-8 text"))?;
    let mut points = Vec::new();
    let mut polys = Vec::new();
    for (ln, line) in text.lines().enumerate() {
        let line_no = ln + 1;
        let line = line.split('#').next().unwrap_or("");
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                points.push(parse_xyz(&mut words, line_no, "'v'")?);
            }
            Some("f") => {
                let mut ids = Vec::new();
                for w in words {
                    let first = w.split('/').next().unwrap_or("");
                    let i: i64 = first.parse().map_err(|_| {
                        FormatError::at_line(line_no, format!("'{w}' is not a vertex index"))
                    })?;
                    let n = points.len() as i64;
                    let id = if i > 0 { i - 1 } else { n + i };
                    if i == 0 || id < 0 || id >= n {
                        return Err(FormatError::at_line(
                            line_no,
                            format!("vertex index {i} out of range (1..={n} defined so far)"),
                        ));
                    }
                    ids.push(id as u32);
                }
                if ids.len() < 3 {
                    return Err(FormatError::at_line(
                        line_no,
                        "a face needs at least 3 vertices",
                    ));
                }
                polys.push(ids);
            }
            _ => {}
        }
    }
    Ok(RawSurface { points, polys })
}
