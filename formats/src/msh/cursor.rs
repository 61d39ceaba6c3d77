//! The read position in an MSH file: ASCII tokens, binary values, and errors at a line or byte.

use crate::FormatError;
use std::path::Path;

pub(crate) struct Cursor<'a> {
    bytes: &'a [u8],
    pub pos: usize,
    path: Option<&'a Path>,
    /// Binary data follows section headers; errors then give byte offsets, which a hex dump can
    /// find, rather than line numbers, which mean little in binary data.
    pub binary: bool,
    pub big_endian: bool,
    /// Bytes of a `size_t` in binary MSH 4.1 (the header's data-size).
    pub size_t: usize,
}

fn is_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | b'\n' | 0x0b | 0x0c)
}

impl<'a> Cursor<'a> {
    pub fn new(bytes: &'a [u8], path: Option<&'a Path>) -> Cursor<'a> {
        Cursor {
            bytes,
            // A UTF-8 byte order mark (a Windows editor's save) is not a token; positions stay
            // offsets in the whole file.
            pos: crate::bom_len(bytes),
            path,
            binary: false,
            big_endian: false,
            size_t: 8,
        }
    }

    /// 1-based line of byte `pos`.
    fn line_of(&self, pos: usize) -> usize {
        let end = pos.min(self.bytes.len());
        1 + self.bytes[..end].iter().filter(|&&b| b == b'\n').count()
    }

    pub fn err_at(&self, pos: usize, message: impl Into<String>) -> FormatError {
        let e = if self.binary {
            FormatError::at_byte(pos as u64, message)
        } else {
            // `pos` is often where the reader stood before the token it names: the token's line
            // is that of the next non-blank byte (or `pos` itself at the end of the file).
            let mut p = pos;
            while p < self.bytes.len() && is_space(self.bytes[p]) {
                p += 1;
            }
            let p = if p < self.bytes.len() { p } else { pos };
            FormatError::at_line(self.line_of(p), message)
        };
        match self.path {
            Some(p) => e.with_file(p),
            None => e,
        }
    }

    pub fn err(&self, message: impl Into<String>) -> FormatError {
        self.err_at(self.pos, message)
    }

    /// The file's name for warnings.
    pub fn file_name(&self) -> String {
        self.path
            .map_or_else(|| "<input>".to_string(), |p| p.display().to_string())
    }

    pub fn remaining(&self) -> usize {
        self.bytes.len().saturating_sub(self.pos)
    }

    /// Room to reserve for `n` items of at least `min_bytes` each: never more than the rest of
    /// the file could hold, so a huge declared count fails on the data, not on the allocation.
    pub fn cap(&self, n: u64, min_bytes: usize) -> usize {
        let fit = self.remaining() / min_bytes.max(1) + 1;
        usize::try_from(n).map_or(fit, |n| n.min(fit))
    }

    pub fn skip_space(&mut self) {
        while self.pos < self.bytes.len() && is_space(self.bytes[self.pos]) {
            self.pos += 1;
        }
    }

    /// Whether only white space is left.
    pub fn at_end(&mut self) -> bool {
        self.skip_space();
        self.pos >= self.bytes.len()
    }

    /// The next white-space separated token.
    pub fn token(&mut self, what: &str) -> Result<&'a [u8], FormatError> {
        self.skip_space();
        let start = self.pos;
        while self.pos < self.bytes.len() && !is_space(self.bytes[self.pos]) {
            self.pos += 1;
        }
        if start == self.pos {
            return Err(self.err(format!("unexpected end of file, expected {what}")));
        }
        Ok(&self.bytes[start..self.pos])
    }

    fn parsed<T: std::str::FromStr>(&mut self, what: &str, kind: &str) -> Result<T, FormatError> {
        let t = self.token(what)?;
        let start = self.pos - t.len();
        std::str::from_utf8(t)
            .ok()
            .and_then(|s| s.parse::<T>().ok())
            .ok_or_else(|| self.err_at(start, format!("{what} is '{}', not {kind}", show(t))))
    }

    /// An ASCII integer token.
    pub fn ascii_int(&mut self, what: &str) -> Result<i64, FormatError> {
        self.parsed(what, "an integer")
    }

    /// An ASCII non-negative integer token.
    pub fn ascii_count(&mut self, what: &str) -> Result<u64, FormatError> {
        self.parsed(what, "a non-negative integer")
    }

    /// An ASCII real token.
    pub fn ascii_real(&mut self, what: &str) -> Result<f64, FormatError> {
        self.parsed(what, "a number")
    }

    /// Ends the current line: only blanks may be left on it. Binary data starts after it.
    pub fn end_line(&mut self) -> Result<(), FormatError> {
        while self.pos < self.bytes.len() && matches!(self.bytes[self.pos], b' ' | b'\t' | b'\r') {
            self.pos += 1;
        }
        match self.bytes.get(self.pos) {
            Some(b'\n') => {
                self.pos += 1;
                Ok(())
            }
            None => Ok(()),
            Some(_) => Err(self.err("unexpected text at the end of the line")),
        }
    }

    /// The rest of the current line (without its line end); moves past it.
    pub fn rest_of_line(&mut self) -> &'a [u8] {
        let start = self.pos;
        while self.pos < self.bytes.len() && self.bytes[self.pos] != b'\n' {
            self.pos += 1;
        }
        let mut line = &self.bytes[start..self.pos];
        if self.pos < self.bytes.len() {
            self.pos += 1;
        }
        while let Some((&b'\r', rest)) = line.split_last() {
            line = rest;
        }
        line
    }

    /// A `"quoted"` string on the current line (Gmsh's names and view string tags).
    pub fn quoted(&mut self, what: &str) -> Result<String, FormatError> {
        self.skip_space();
        let start = self.pos;
        if self.bytes.get(self.pos) != Some(&b'"') {
            let t = self.token(what)?;
            return Err(self.err_at(
                start,
                format!("{what} is '{}', not a \"quoted\" string", show(t)),
            ));
        }
        let rest = &self.bytes[start + 1..];
        let len = rest
            .iter()
            .position(|&b| b == b'"' || b == b'\n')
            .filter(|&i| rest[i] == b'"')
            .ok_or_else(|| {
                self.err_at(start, format!("{what} has no closing quote on its line"))
            })?;
        self.pos = start + 1 + len + 1;
        let place = format!("byte {start}");
        Ok(crate::text_or_warn(
            &rest[..len],
            &self.file_name(),
            &place,
            what,
        ))
    }

    /// Expects the `$EndNAME` line of a section.
    pub fn expect_end(&mut self, section: &str) -> Result<(), FormatError> {
        let want = format!("$End{section}");
        self.skip_space();
        let start = self.pos;
        let t = self.token(&want)?;
        if t != want.as_bytes() {
            return Err(self.err_at(start, format!("expected {want}, found '{}'", show(t))));
        }
        Ok(())
    }

    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], FormatError> {
        if self.remaining() < n {
            return Err(self.err(format!(
                "the file ends in the middle of {what} ({n} bytes needed, {} left)",
                self.remaining()
            )));
        }
        let s = &self.bytes[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    pub fn bin_i32(&mut self, what: &str) -> Result<i32, FormatError> {
        let b: [u8; 4] = self.take(4, what)?.try_into().map_err(|_| self.err(what))?;
        Ok(if self.big_endian {
            i32::from_be_bytes(b)
        } else {
            i32::from_le_bytes(b)
        })
    }

    pub fn bin_f64(&mut self, what: &str) -> Result<f64, FormatError> {
        let b: [u8; 8] = self.take(8, what)?.try_into().map_err(|_| self.err(what))?;
        Ok(if self.big_endian {
            f64::from_be_bytes(b)
        } else {
            f64::from_le_bytes(b)
        })
    }

    /// A binary `size_t` of the header's data-size (4 or 8 bytes).
    pub fn bin_size(&mut self, what: &str) -> Result<u64, FormatError> {
        if self.size_t == 4 {
            let b: [u8; 4] = self.take(4, what)?.try_into().map_err(|_| self.err(what))?;
            return Ok(u64::from(if self.big_endian {
                u32::from_be_bytes(b)
            } else {
                u32::from_le_bytes(b)
            }));
        }
        let b: [u8; 8] = self.take(8, what)?.try_into().map_err(|_| self.err(what))?;
        Ok(if self.big_endian {
            u64::from_be_bytes(b)
        } else {
            u64::from_le_bytes(b)
        })
    }

    /// An `int` value: binary in binary files, a token in ASCII ones.
    pub fn int(&mut self, what: &str) -> Result<i64, FormatError> {
        if self.binary {
            return self.bin_i32(what).map(i64::from);
        }
        let start = self.pos;
        let v = self.ascii_int(what)?;
        if i32::try_from(v).is_err() {
            return Err(self.err_at(start, format!("{what} {v} does not fit 32 bits")));
        }
        Ok(v)
    }

    /// A `size_t` value (counts and tags in MSH 4.1).
    pub fn size(&mut self, what: &str) -> Result<u64, FormatError> {
        if self.binary {
            self.bin_size(what)
        } else {
            self.ascii_count(what)
        }
    }

    /// A `double` value.
    pub fn real(&mut self, what: &str) -> Result<f64, FormatError> {
        if self.binary {
            self.bin_f64(what)
        } else {
            self.ascii_real(what)
        }
    }

    /// Moves past the `$EndNAME` line of a section it does not read, as Gmsh does: the first
    /// line that is exactly `$EndNAME`.
    pub fn skip_section(&mut self, name: &str) -> Result<(), FormatError> {
        let start = self.pos;
        let want = format!("$End{name}");
        while self.pos < self.bytes.len() {
            let line = self.rest_of_line();
            if line.trim_ascii() == want.as_bytes() {
                return Ok(());
            }
        }
        Err(self.err_at(start, format!("section ${name} has no {want} line")))
    }
}

/// A token as it may be shown in a message: at most 40 bytes, escaped.
pub(crate) fn show(t: &[u8]) -> String {
    String::from_utf8_lossy(&t[..t.len().min(40)])
        .chars()
        .flat_map(char::escape_default)
        .collect()
}
