//! Legacy VTK POLYDATA reader (ascii and binary; `POLYGONS` in the 4.2 layout with inline counts
//! and in the 5.1 layout with `OFFSETS`/`CONNECTIVITY`). Point and cell data are not needed for a
//! body and are skipped.

use formats::FormatError;

use super::RawSurface;

struct Cursor<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
    binary: bool,
}

impl<'a> Cursor<'a> {
    fn err(&self, msg: impl Into<String>) -> FormatError {
        if self.binary {
            FormatError::at_byte(self.pos as u64, msg)
        } else {
            FormatError::at_line(self.line, msg)
        }
    }

    /// The next non-blank line, trimmed; `None` at the end.
    fn next_line(&mut self) -> Option<&'a str> {
        while self.pos < self.bytes.len() {
            let start = self.pos;
            let end = self.bytes[start..]
                .iter()
                .position(|&b| b == b'\n')
                .map_or(self.bytes.len(), |i| start + i);
            self.pos = (end + 1).min(self.bytes.len()).max(end);
            self.line += 1;
            let s = std::str::from_utf8(&self.bytes[start..end])
                .unwrap_or("")
                .trim();
            if !s.is_empty() {
                return Some(s);
            }
        }
        None
    }

    fn ascii_token(&mut self) -> Option<&'a str> {
        while self.pos < self.bytes.len() && self.bytes[self.pos].is_ascii_whitespace() {
            if self.bytes[self.pos] == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
        if self.pos >= self.bytes.len() {
            return None;
        }
        let start = self.pos;
        while self.pos < self.bytes.len() && !self.bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        std::str::from_utf8(&self.bytes[start..self.pos]).ok()
    }

    /// `n` numbers of legacy type `ty`, as f64.
    fn values(&mut self, n: usize, ty: &str) -> Result<Vec<f64>, FormatError> {
        let size = match ty {
            "float" | "int" | "unsigned_int" => 4,
            "double" | "long" | "unsigned_long" | "vtktypeint64" | "vtktypeuint64" => 8,
            "short" | "unsigned_short" => 2,
            "char" | "unsigned_char" | "bit" => 1,
            _ => return Err(self.err(format!("unknown data type '{ty}'"))),
        };
        let mut out = Vec::with_capacity(n.min(1 << 24));
        if self.binary {
            let need = n
                .checked_mul(size)
                .ok_or_else(|| self.err("count too large"))?;
            if self.pos + need > self.bytes.len() {
                return Err(self.err(format!(
                    "{n} binary {ty} values need {need} bytes; the file ends first"
                )));
            }
            for i in 0..n {
                let b = &self.bytes[self.pos + i * size..self.pos + (i + 1) * size];
                let v = match ty {
                    "float" => f32::from_be_bytes([b[0], b[1], b[2], b[3]]) as f64,
                    "double" => f64::from_be_bytes(b.try_into().unwrap_or([0; 8])),
                    "int" => i32::from_be_bytes([b[0], b[1], b[2], b[3]]) as f64,
                    "unsigned_int" => u32::from_be_bytes([b[0], b[1], b[2], b[3]]) as f64,
                    "long" | "vtktypeint64" => {
                        i64::from_be_bytes(b.try_into().unwrap_or([0; 8])) as f64
                    }
                    "unsigned_long" | "vtktypeuint64" => {
                        u64::from_be_bytes(b.try_into().unwrap_or([0; 8])) as f64
                    }
                    "short" => i16::from_be_bytes([b[0], b[1]]) as f64,
                    "unsigned_short" => u16::from_be_bytes([b[0], b[1]]) as f64,
                    "char" => b[0] as i8 as f64,
                    _ => b[0] as f64,
                };
                out.push(v);
            }
            self.pos += need;
        } else {
            for _ in 0..n {
                let t = self.ascii_token().ok_or_else(|| {
                    self.err(format!(
                        "expected {n} values of type {ty}; the file ends first"
                    ))
                })?;
                // Newlines consumed so far, plus one: the token's own line.
                let line = self.line + 1;
                let v: f64 = t
                    .parse()
                    .map_err(|_| FormatError::at_line(line, format!("'{t}' is not a number")))?;
                out.push(v);
            }
        }
        Ok(out)
    }
}

fn count(cur: &Cursor, w: Option<&str>, what: &str) -> Result<usize, FormatError> {
    w.and_then(|s| s.parse::<usize>().ok())
        .ok_or_else(|| cur.err(format!("{what}: expected a count")))
}

fn id(cur: &Cursor, v: f64, n_points: usize) -> Result<u32, FormatError> {
    if v < 0.0 || v.fract() != 0.0 || v as usize >= n_points {
        return Err(cur.err(format!("point id {v} out of range ({n_points} points)")));
    }
    Ok(v as u32)
}

pub(super) fn read(bytes: &[u8]) -> Result<RawSurface, FormatError> {
    let mut cur = Cursor {
        bytes,
        pos: 0,
        line: 0,
        binary: false,
    };
    let head = cur.next_line().unwrap_or("");
    if !head.starts_with("# vtk DataFile") {
        return Err(FormatError::at_line(
            1,
            "not a legacy VTK file (no '# vtk DataFile' header)",
        ));
    }
    let _title = cur.next_line();
    match cur.next_line().map(str::to_ascii_uppercase).as_deref() {
        Some("ASCII") => {}
        Some("BINARY") => {}
        other => {
            return Err(cur.err(format!("expected ASCII or BINARY, found {other:?}")));
        }
    }
    let binary_file = bytes.split(|&b| b == b'\n').nth(2).is_some_and(|l| {
        String::from_utf8_lossy(l)
            .trim()
            .eq_ignore_ascii_case("BINARY")
    });
    let ds = cur.next_line().unwrap_or("");
    let mut w = ds.split_whitespace();
    if w.next().map(str::to_ascii_uppercase).as_deref() != Some("DATASET")
        || w.next().map(str::to_ascii_uppercase).as_deref() != Some("POLYDATA")
    {
        return Err(cur.err(format!(
            "a body surface must be 'DATASET POLYDATA', found '{ds}'"
        )));
    }
    let mut points: Vec<[f64; 3]> = Vec::new();
    let mut polys = Vec::new();
    while let Some(line) = cur.next_line() {
        let mut w = line.split_whitespace();
        let key = w.next().unwrap_or("").to_ascii_uppercase();
        match key.as_str() {
            "POINTS" => {
                let n = count(&cur, w.next(), "POINTS")?;
                let ty = w.next().unwrap_or("float").to_string();
                cur.binary = binary_file;
                let v = cur.values(3 * n, &ty)?;
                cur.binary = false;
                points = v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
            }
            "POLYGONS" | "TRIANGLE_STRIPS" | "LINES" | "VERTICES" => {
                let a = count(&cur, w.next(), &key)?;
                let b = count(&cur, w.next(), &key)?;
                let cells = read_cells(&mut cur, a, b, binary_file)?;
                match key.as_str() {
                    "POLYGONS" => {
                        for c in cells {
                            let ids = c
                                .iter()
                                .map(|&v| id(&cur, v, points.len()))
                                .collect::<Result<Vec<_>, _>>()?;
                            polys.push(ids);
                        }
                    }
                    "TRIANGLE_STRIPS" => {
                        for c in cells {
                            let ids = c
                                .iter()
                                .map(|&v| id(&cur, v, points.len()))
                                .collect::<Result<Vec<_>, _>>()?;
                            for k in 0..ids.len().saturating_sub(2) {
                                // Every other triangle of a strip is reversed to keep orientation.
                                if k % 2 == 0 {
                                    polys.push(vec![ids[k], ids[k + 1], ids[k + 2]]);
                                } else {
                                    polys.push(vec![ids[k + 1], ids[k], ids[k + 2]]);
                                }
                            }
                        }
                    }
                    _ => {}
                }
            }
            "METADATA" | "INFORMATION" | "NAME" | "DATA" => {}
            "POINT_DATA" | "CELL_DATA" | "FIELD" => break,
            _ => {}
        }
    }
    Ok(RawSurface { points, polys })
}

/// Cells in either layout: 4.2 (`n size`, then `count id id ...` per cell) or 5.1 (`n_offsets
/// n_conn`, then `OFFSETS type` and `CONNECTIVITY type` arrays).
fn read_cells(
    cur: &mut Cursor,
    a: usize,
    b: usize,
    binary: bool,
) -> Result<Vec<Vec<f64>>, FormatError> {
    let save = (cur.pos, cur.line);
    let next = cur.next_line().unwrap_or("");
    if next.to_ascii_uppercase().starts_with("OFFSETS") {
        let ty = next
            .split_whitespace()
            .nth(1)
            .unwrap_or("vtktypeint64")
            .to_string();
        cur.binary = binary;
        let offsets = cur.values(a, &ty)?;
        cur.binary = false;
        let conn_line = cur.next_line().unwrap_or("");
        if !conn_line.to_ascii_uppercase().starts_with("CONNECTIVITY") {
            return Err(cur.err(format!("expected CONNECTIVITY, found '{conn_line}'")));
        }
        let ty = conn_line
            .split_whitespace()
            .nth(1)
            .unwrap_or("vtktypeint64")
            .to_string();
        cur.binary = binary;
        let conn = cur.values(b, &ty)?;
        cur.binary = false;
        let mut cells = Vec::new();
        for k in 0..a.saturating_sub(1) {
            let (s, e) = (offsets[k] as usize, offsets[k + 1] as usize);
            if s > e || e > conn.len() {
                return Err(cur.err(format!("offset {k} ({s}..{e}) out of range")));
            }
            cells.push(conn[s..e].to_vec());
        }
        return Ok(cells);
    }
    cur.pos = save.0;
    cur.line = save.1;
    cur.binary = binary;
    let flat = cur.values(b, if binary { "int" } else { "vtktypeint64" })?;
    cur.binary = false;
    let mut cells = Vec::with_capacity(a);
    let mut i = 0;
    for _ in 0..a {
        let n = *flat
            .get(i)
            .ok_or_else(|| cur.err("cell list shorter than its size"))? as usize;
        if i + 1 + n > flat.len() {
            return Err(cur.err("cell list shorter than its size"));
        }
        cells.push(flat[i + 1..i + 1 + n].to_vec());
        i += 1 + n;
    }
    Ok(cells)
}
