//! STL reader, ascii and binary (told apart by the binary size rule, not the `solid` keyword,
//! which some binary writers put in the header too).

use formats::FormatError;

use super::{parse_xyz, RawSurface};

pub(super) fn read(bytes: &[u8]) -> Result<RawSurface, FormatError> {
    if bytes.len() >= 84 {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
        if 84 + 50 * n == bytes.len() as u64 {
            return read_binary(bytes, n as usize);
        }
    }
    let head = String::from_utf8_lossy(&bytes[..bytes.len().min(512)]);
    if head.trim_start().starts_with("solid") {
        return read_ascii(bytes);
    }
    Err(FormatError::at_byte(
        0,
        format!(
            "neither ascii STL (no 'solid' keyword) nor binary STL ({} bytes does not match 84 + 50 x the triangle count in the header)",
            bytes.len()
        ),
    ))
}

fn read_binary(bytes: &[u8], n: usize) -> Result<RawSurface, FormatError> {
    let mut points = Vec::with_capacity(3 * n);
    let mut polys = Vec::with_capacity(n);
    for i in 0..n {
        let rec = &bytes[84 + 50 * i..84 + 50 * (i + 1)];
        for v in 0..3 {
            let at = 12 + 12 * v;
            let p = [0, 1, 2].map(|k| {
                let o = at + 4 * k;
                f32::from_le_bytes([rec[o], rec[o + 1], rec[o + 2], rec[o + 3]]) as f64
            });
            if !p.iter().all(|x| x.is_finite()) {
                return Err(FormatError::at_byte(
                    (84 + 50 * i + at) as u64,
                    format!("triangle {i}: vertex {v} is not finite"),
                ));
            }
            points.push(p);
        }
        polys.push(vec![3 * i as u32, 3 * i as u32 + 1, 3 * i as u32 + 2]);
    }
    Ok(RawSurface { points, polys })
}

fn read_ascii(bytes: &[u8]) -> Result<RawSurface, FormatError> {
    let text = std::str::from_utf8(bytes)
        .map_err(|e| FormatError::at_byte(e.valid_up_to() as u64, "ascii STL is not UTF-8 text"))?;
    let mut points = Vec::new();
    let mut polys = Vec::new();
    let mut in_loop: Option<(usize, Vec<u32>)> = None;
    for (ln, line) in text.lines().enumerate() {
        let line_no = ln + 1;
        let mut words = line.split_whitespace();
        let Some(key) = words.next() else { continue };
        match key {
            "solid" | "endsolid" | "facet" | "endfacet" => {}
            "outer" => {
                if in_loop.is_some() {
                    return Err(FormatError::at_line(line_no, "'outer loop' inside a loop"));
                }
                in_loop = Some((line_no, Vec::new()));
            }
            "vertex" => {
                let Some((_, ids)) = in_loop.as_mut() else {
                    return Err(FormatError::at_line(
                        line_no,
                        "'vertex' outside 'outer loop'",
                    ));
                };
                let p = parse_xyz(&mut words, line_no, "'vertex'")?;
                ids.push(points.len() as u32);
                points.push(p);
            }
            "endloop" => {
                let Some((start, ids)) = in_loop.take() else {
                    return Err(FormatError::at_line(
                        line_no,
                        "'endloop' without 'outer loop'",
                    ));
                };
                if ids.len() < 3 {
                    return Err(FormatError::at_line(
                        start,
                        format!("a facet loop with {} vertices", ids.len()),
                    ));
                }
                polys.push(ids);
            }
            other => {
                return Err(FormatError::at_line(
                    line_no,
                    format!("unexpected '{other}' in ascii STL"),
                ))
            }
        }
    }
    if let Some((start, _)) = in_loop {
        return Err(FormatError::at_line(
            start,
            "facet loop never closed (no 'endloop')",
        ));
    }
    Ok(RawSurface { points, polys })
}
