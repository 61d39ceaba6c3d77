//! Line records of TetGen files: `#` comments anywhere, blank lines skipped, tabs or spaces
//! between fields; each record keeps its line number for errors.

use crate::FormatError;
use std::path::Path;

pub(crate) struct Records<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
    pub path: &'a Path,
}

impl<'a> Records<'a> {
    pub fn new(bytes: &'a [u8], path: &'a Path) -> Records<'a> {
        // A UTF-8 byte order mark (Windows editors save one) is not part of the first record, as
        // the legacy, Medit and VTU readers skip it.
        let pos = crate::bom_len(bytes);
        Records {
            bytes,
            pos,
            line: 0,
            path,
        }
    }

    pub fn remaining(&self) -> usize {
        self.bytes.len().saturating_sub(self.pos)
    }

    /// Fills `toks` with the next non-empty record's fields and returns its 1-based line number.
    pub fn next_into(&mut self, toks: &mut Vec<&'a [u8]>) -> Option<usize> {
        while self.pos < self.bytes.len() {
            let start = self.pos;
            let rest = &self.bytes[start..];
            let len = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
            // A last line without a newline ends at the end, not one past it.
            self.pos = (start + len + 1).min(self.bytes.len());
            self.line += 1;
            let mut line = &rest[..len];
            if let Some(h) = line.iter().position(|&b| b == b'#') {
                line = &line[..h];
            }
            toks.clear();
            toks.extend(
                line.split(|b| matches!(b, b' ' | b'\t' | b'\r' | 0x0b | 0x0c))
                    .filter(|t| !t.is_empty()),
            );
            if !toks.is_empty() {
                return Some(self.line);
            }
        }
        None
    }

    /// The next record, or an error naming what was expected at the end of the file.
    pub fn require(&mut self, toks: &mut Vec<&'a [u8]>, what: &str) -> Result<usize, FormatError> {
        self.next_into(toks).ok_or_else(|| {
            FormatError::at_line(
                self.line.max(1),
                format!("unexpected end of file, expected {what}"),
            )
            .with_file(self.path)
        })
    }

    pub fn err(&self, line: usize, message: impl Into<String>) -> FormatError {
        FormatError::at_line(line, message).with_file(self.path)
    }

    /// Field `k` of a record as an integer.
    pub fn int(
        &self,
        toks: &[&[u8]],
        k: usize,
        line: usize,
        what: &str,
    ) -> Result<i64, FormatError> {
        let t = self.field(toks, k, line, what)?;
        std::str::from_utf8(t)
            .ok()
            .and_then(|s| s.parse::<i64>().ok())
            .ok_or_else(|| self.err(line, format!("{what} is '{}', not an integer", show(t))))
    }

    /// Field `k` of a record as a boundary marker: an integer, or a number with an integral
    /// value (meshio writes markers as `0.0`, which TetGen reads as 0). A fractional marker is
    /// refused: TetGen would truncate it, silently merging different values.
    pub fn marker(
        &self,
        toks: &[&[u8]],
        k: usize,
        line: usize,
        what: &str,
    ) -> Result<i64, FormatError> {
        if let Ok(v) = self.int(toks, k, line, what) {
            return Ok(v);
        }
        let t = self.field(toks, k, line, what)?;
        std::str::from_utf8(t)
            .ok()
            .and_then(|s| s.parse::<f64>().ok())
            .filter(|v| v.fract() == 0.0 && v.abs() <= i64::MAX as f64)
            .map(|v| v as i64)
            .ok_or_else(|| self.err(line, format!("{what} is '{}', not an integer", show(t))))
    }

    /// Field `k` of a record as a non-negative count.
    pub fn count(
        &self,
        toks: &[&[u8]],
        k: usize,
        line: usize,
        what: &str,
    ) -> Result<usize, FormatError> {
        let v = self.int(toks, k, line, what)?;
        usize::try_from(v)
            .map_err(|_| self.err(line, format!("{what} is {v}, must not be negative")))
    }

    /// Field `k` of a record as a real number (TetGen reads with strtod).
    pub fn real(
        &self,
        toks: &[&[u8]],
        k: usize,
        line: usize,
        what: &str,
    ) -> Result<f64, FormatError> {
        let t = self.field(toks, k, line, what)?;
        std::str::from_utf8(t)
            .ok()
            .and_then(|s| s.parse::<f64>().ok())
            .ok_or_else(|| self.err(line, format!("{what} is '{}', not a number", show(t))))
    }

    fn field<'t>(
        &self,
        toks: &'t [&'a [u8]],
        k: usize,
        line: usize,
        what: &str,
    ) -> Result<&'a [u8], FormatError> {
        toks.get(k).copied().ok_or_else(|| {
            self.err(
                line,
                format!("missing {what} (field {} of the line)", k + 1),
            )
        })
    }
}

pub(crate) fn show(t: &[u8]) -> String {
    let s: String = String::from_utf8_lossy(&t[..t.len().min(40)])
        .chars()
        .flat_map(char::escape_default)
        .collect();
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comments_tabs_and_blank_lines() {
        let text = b"# header comment\n\n3\t3 0 # trailing\n  \t\n1 0.5\t2e3 -1\n";
        let p = Path::new("x.node");
        let mut r = Records::new(text, p);
        let mut t = Vec::new();
        assert_eq!(r.next_into(&mut t), Some(3));
        assert_eq!(t, vec![&b"3"[..], b"3", b"0"]);
        assert_eq!(r.next_into(&mut t), Some(5));
        assert_eq!(r.real(&t, 2, 5, "y").unwrap(), 2000.0);
        assert!(r.int(&t, 1, 5, "x").is_err());
        assert!(r.count(&t, 3, 5, "c").is_err());
        assert_eq!(r.next_into(&mut t), None);
    }
}
