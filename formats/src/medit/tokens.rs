//! Whitespace-separated tokens of an ASCII Medit file, each with its line number; `#` starts a
//! comment that runs to the end of the line.

use crate::FormatError;
use std::path::Path;

pub(crate) struct Tokens<'a> {
    bytes: &'a [u8],
    pos: usize,
    /// Line of the byte at `pos` (1-based).
    line: usize,
    /// Line of the last token returned, for "ends after line N" messages.
    last_line: usize,
    path: &'a Path,
}

impl<'a> Tokens<'a> {
    pub fn new(bytes: &'a [u8], path: &'a Path) -> Tokens<'a> {
        // A UTF-8 byte order mark is not a token.
        let pos = crate::bom_len(bytes);
        Tokens {
            bytes,
            pos,
            line: 1,
            last_line: 1,
            path,
        }
    }

    /// Bytes not yet read: what bounds how much a declared count may reserve.
    pub fn remaining(&self) -> usize {
        self.bytes.len().saturating_sub(self.pos)
    }

    /// The next token and its line, or `None` at the end of the file.
    pub fn next_token(&mut self) -> Option<(&'a [u8], usize)> {
        let b = self.bytes;
        loop {
            match b.get(self.pos)? {
                b'\n' => {
                    self.line += 1;
                    self.pos += 1;
                }
                b'#' => {
                    while self.pos < b.len() && b[self.pos] != b'\n' {
                        self.pos += 1;
                    }
                }
                c if c.is_ascii_whitespace() || *c == 0x0b => self.pos += 1,
                _ => break,
            }
        }
        let start = self.pos;
        while self.pos < b.len() && !b[self.pos].is_ascii_whitespace() && b[self.pos] != b'#' {
            self.pos += 1;
        }
        self.last_line = self.line;
        Some((&b[start..self.pos], self.line))
    }

    /// The next token, or an error saying the file ends where `what` was expected.
    pub fn require(&mut self, what: &str) -> Result<(&'a [u8], usize), FormatError> {
        let last = self.last_line;
        self.next_token().ok_or_else(|| {
            self.err(
                last,
                format!("the file ends (truncated?) where {what} was expected"),
            )
        })
    }

    /// The next token as an integer.
    pub fn int(&mut self, what: &str) -> Result<(i64, usize), FormatError> {
        let (t, line) = self.require(what)?;
        let v = std::str::from_utf8(t)
            .ok()
            .and_then(|s| s.parse::<i64>().ok())
            .ok_or_else(|| self.err(line, format!("{what} is '{}', not an integer", show(t))))?;
        Ok((v, line))
    }

    /// The next token as a real number (Medit tools read with `%lf`, so `1`, `1.5`, `-2e-3`).
    pub fn real(&mut self, what: &str) -> Result<(f64, usize), FormatError> {
        let (t, line) = self.require(what)?;
        let v = std::str::from_utf8(t)
            .ok()
            .and_then(|s| s.parse::<f64>().ok())
            .ok_or_else(|| self.err(line, format!("{what} is '{}', not a number", show(t))))?;
        Ok((v, line))
    }

    /// Line of the last token read: where a file that ends too early is reported.
    pub fn last_line(&self) -> usize {
        self.last_line
    }

    pub fn path(&self) -> &'a Path {
        self.path
    }

    pub fn err(&self, line: usize, message: impl Into<String>) -> FormatError {
        FormatError::at_line(line, message).with_file(self.path)
    }
}

/// A token as text for messages: at most 40 bytes, escaped.
pub(crate) fn show(t: &[u8]) -> String {
    String::from_utf8_lossy(&t[..t.len().min(40)])
        .chars()
        .flat_map(char::escape_default)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comments_and_line_numbers() {
        let text = b"# head\nMeshVersionFormatted 2 # trailing\r\n\n Dimension\n3#x\n";
        let mut t = Tokens::new(text, Path::new("x.mesh"));
        let toks: Vec<(String, usize)> = std::iter::from_fn(|| t.next_token())
            .map(|(b, l)| (String::from_utf8_lossy(b).into_owned(), l))
            .collect();
        assert_eq!(
            toks,
            vec![
                ("MeshVersionFormatted".into(), 2),
                ("2".into(), 2),
                ("Dimension".into(), 4),
                ("3".into(), 5)
            ]
        );
    }

    #[test]
    fn numbers_and_the_end() {
        let mut t = Tokens::new(b"12 x 1.5e3", Path::new("x.mesh"));
        assert_eq!(t.int("a count").unwrap(), (12, 1));
        let e = t.int("a count").unwrap_err().to_string();
        assert!(e.contains("line 1") && e.contains("'x'"), "{e}");
        assert_eq!(t.real("x").unwrap(), (1500.0, 1));
        let e = t.real("a coordinate").unwrap_err().to_string();
        assert!(e.contains("ends") && e.contains("a coordinate"), "{e}");
    }
}
