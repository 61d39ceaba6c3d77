//! Byte cursor over a legacy file: whitespace tokens without allocation, binary blocks, and error
//! places (line numbers in ASCII files, byte offsets in binary ones).

use crate::{FormatError, Place};

pub(crate) struct Cursor<'a> {
    pub bytes: &'a [u8],
    pub pos: usize,
    /// A BINARY file: errors name byte offsets, since line numbers mean nothing after raw data.
    pub binary: bool,
}

fn is_ws(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | b'\n' | 0x0b | 0x0c)
}

impl<'a> Cursor<'a> {
    pub fn new(bytes: &'a [u8]) -> Cursor<'a> {
        Cursor {
            bytes,
            pos: 0,
            binary: false,
        }
    }

    pub fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    pub fn skip_ws(&mut self) {
        while self.pos < self.bytes.len() && is_ws(self.bytes[self.pos]) {
            self.pos += 1;
        }
    }

    /// The next whitespace-separated token and where it starts, or `None` at the end.
    pub fn token(&mut self) -> Option<(usize, &'a [u8])> {
        self.skip_ws();
        let start = self.pos;
        while self.pos < self.bytes.len() && !is_ws(self.bytes[self.pos]) {
            self.pos += 1;
        }
        (self.pos > start).then(|| (start, &self.bytes[start..self.pos]))
    }

    /// The next token, or an error saying what was expected.
    pub fn expect(&mut self, what: &str) -> Result<(usize, &'a [u8]), FormatError> {
        match self.token() {
            Some(t) => Ok(t),
            None => Err(self.err(self.pos, format!("unexpected end of file, expected {what}"))),
        }
    }

    /// The next token as a non-negative count that fits in memory terms (`usize`).
    pub fn expect_count(&mut self, what: &str) -> Result<usize, FormatError> {
        let (p, t) = self.expect(what)?;
        parse_count(t).ok_or_else(|| {
            self.err(
                p,
                format!(
                    "expected {what} (a non-negative integer), found '{}'",
                    show(t)
                ),
            )
        })
    }

    /// Peeks at the next token without consuming it.
    pub fn peek(&mut self) -> Option<(usize, &'a [u8])> {
        let save = self.pos;
        let t = self.token();
        self.pos = save;
        t
    }

    /// The rest of the current line (without `\r\n`), consuming the newline.
    pub fn line(&mut self) -> &'a [u8] {
        let start = self.pos;
        let end = memchr_nl(&self.bytes[start..]).map_or(self.bytes.len(), |i| start + i);
        self.pos = (end + 1).min(self.bytes.len());
        let mut line = &self.bytes[start..end];
        if let Some(stripped) = line.strip_suffix(b"\r") {
            line = stripped;
        }
        line
    }

    /// Moves to the first byte after the end of the current line: where VTK starts binary data
    /// after a keyword line.
    pub fn begin_binary(&mut self) {
        match memchr_nl(&self.bytes[self.pos..]) {
            Some(i) => self.pos += i + 1,
            None => self.pos = self.bytes.len(),
        }
    }

    /// Takes `n` raw bytes, checking they are present.
    pub fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], FormatError> {
        if n > self.remaining() {
            return Err(self.err(
                self.pos,
                format!(
                    "{what}: needs {n} bytes of binary data but only {} remain (truncated file or wrong count)",
                    self.remaining()
                ),
            ));
        }
        let s = &self.bytes[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    /// Where value `k` of a block whose keyword line ends at or after `at` is: its byte offset in
    /// binary data (`size` bytes each), its token in text. Only errors call this.
    pub fn value_at(&self, at: usize, k: usize, size: usize) -> usize {
        if self.binary {
            let start = memchr_nl(&self.bytes[at.min(self.bytes.len())..])
                .map_or(self.bytes.len(), |i| at + i + 1);
            return start.saturating_add(k.saturating_mul(size));
        }
        let mut c = Cursor {
            bytes: self.bytes,
            pos: at,
            binary: false,
        };
        let mut p = at;
        for _ in 0..=k {
            match c.token() {
                Some((q, _)) => p = q,
                None => break,
            }
        }
        p
    }

    /// 1-based line number of byte `pos`.
    pub fn line_at(&self, pos: usize) -> usize {
        let end = pos.min(self.bytes.len());
        1 + self.bytes[..end].iter().filter(|&&b| b == b'\n').count()
    }

    /// An error at byte `pos`: a line number in ASCII files, a byte offset in binary ones.
    pub fn err(&self, pos: usize, message: impl Into<String>) -> FormatError {
        let place = if self.binary {
            Place::Byte(pos as u64)
        } else {
            Place::Line(self.line_at(pos))
        };
        FormatError::new(place, message)
    }
}

fn memchr_nl(s: &[u8]) -> Option<usize> {
    s.iter().position(|&b| b == b'\n')
}

/// Parses a decimal non-negative integer, refusing signs, junk and overflow.
pub(crate) fn parse_count(t: &[u8]) -> Option<usize> {
    if t.is_empty() || t.len() > 20 {
        return None;
    }
    let mut v: usize = 0;
    for &b in t {
        if !b.is_ascii_digit() {
            return None;
        }
        v = v.checked_mul(10)?.checked_add((b - b'0') as usize)?;
    }
    Some(v)
}

/// A token shown in an error, shortened and with odd bytes escaped.
pub(crate) fn show(t: &[u8]) -> String {
    let s: String = String::from_utf8_lossy(&t[..t.len().min(40)])
        .chars()
        .flat_map(char::escape_default)
        .collect();
    if t.len() > 40 {
        format!("{s}...")
    } else {
        s
    }
}

/// Case-insensitive keyword comparison (VTK lower-cases keywords before comparing).
pub(crate) fn is_kw(t: &[u8], kw: &str) -> bool {
    t.eq_ignore_ascii_case(kw.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_lines_and_counts() {
        let mut c = Cursor::new(b"  POINTS\t12 float\r\nabc\n");
        assert_eq!(c.token().map(|t| t.1), Some(&b"POINTS"[..]));
        assert_eq!(c.expect_count("n").ok(), Some(12));
        assert_eq!(c.token().map(|t| t.1), Some(&b"float"[..]));
        assert_eq!(c.line(), b"");
        assert_eq!(c.line_at(c.pos), 2);
        assert_eq!(c.line(), b"abc");
        assert_eq!(c.token(), None);
        assert_eq!(parse_count(b"18446744073709551616"), None);
        assert_eq!(parse_count(b"-1"), None);
        assert_eq!(parse_count(b"1099511627776"), Some(1 << 40));
    }

    #[test]
    fn take_checks_length() {
        let mut c = Cursor::new(b"x\nabc");
        c.binary = true;
        c.begin_binary();
        assert!(c.take(4, "data").is_err());
        assert_eq!(c.take(3, "data").ok(), Some(&b"abc"[..]));
    }
}
