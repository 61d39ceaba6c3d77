//! Byte cursor over a legacy file: whitespace tokens without allocation, binary blocks read
//! straight into their destination, and error places (line numbers in ASCII files, byte offsets
//! in binary ones). The input is either a slice in memory or a file read through a small
//! window, so that big binary blocks are copied once, from the page cache into the array.

use crate::{FormatError, Place};
use std::borrow::Cow;
use std::io::Read;

/// Window growth when streaming from a file.
const CHUNK: u64 = 1 << 16;

pub(crate) struct Cursor<'a> {
    /// The input from absolute offset `base` on (all of it for input in memory).
    win: Cow<'a, [u8]>,
    base: usize,
    /// Newlines before `base` (for line numbers after the window moved).
    lines_before: usize,
    /// Absolute position in the input.
    pub pos: usize,
    /// Length of the whole input.
    len: usize,
    file: Option<Box<dyn Read + 'a>>,
    /// The same file, for positional reads of big blocks on several threads.
    positional: Option<&'a std::fs::File>,
    /// A BINARY file: errors name byte offsets, since line numbers mean nothing after raw data.
    pub binary: bool,
    /// `(keyword line position, data start)` of each binary block, to place errors in them.
    blocks: Vec<(usize, usize)>,
    /// Whether the last token ran into the end of the input: it may have been cut short.
    cut: bool,
    /// Where the last token starts.
    token_start: usize,
    /// The file, as warnings name it.
    pub label: String,
}

fn is_ws(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | b'\n' | 0x0b | 0x0c)
}

impl<'a> Cursor<'a> {
    pub fn new(bytes: &'a [u8]) -> Cursor<'a> {
        Cursor {
            win: Cow::Borrowed(bytes),
            base: 0,
            lines_before: 0,
            pos: 0,
            len: bytes.len(),
            file: None,
            positional: None,
            binary: false,
            blocks: Vec::new(),
            cut: false,
            token_start: 0,
            label: "<input>".into(),
        }
    }

    /// Streams `len` bytes from `file`.
    pub fn from_reader(file: Box<dyn Read + 'a>, len: usize) -> Cursor<'a> {
        Cursor {
            win: Cow::Owned(Vec::new()),
            base: 0,
            lines_before: 0,
            pos: 0,
            len,
            file: Some(file),
            positional: None,
            binary: false,
            blocks: Vec::new(),
            cut: false,
            token_start: 0,
            label: "<input>".into(),
        }
    }

    /// Streams a file from its start; big blocks are read by several threads at once.
    pub fn from_file(file: &'a std::fs::File, len: usize) -> Cursor<'a> {
        let mut c = Cursor::from_reader(Box::new(file), len);
        c.positional = Some(file);
        c
    }

    pub fn remaining(&self) -> usize {
        self.len.saturating_sub(self.pos)
    }

    /// Extends the window with more of the file, dropping what lies before `keep`; false at the
    /// end of the input. A file shorter than it said ends the input where it ends.
    fn fill(&mut self, keep: usize) -> bool {
        let Some(file) = self.file.as_mut() else {
            return false;
        };
        let end = self.base + self.win.len();
        if end >= self.len {
            return false;
        }
        let keep = keep.clamp(self.base, end);
        let drop = keep - self.base;
        self.lines_before += self.win[..drop].iter().filter(|&&b| b == b'\n').count();
        let mut v = self.win[drop..].to_vec();
        let want = CHUNK.min((self.len - end) as u64);
        let got = Read::by_ref(file)
            .take(want)
            .read_to_end(&mut v)
            .unwrap_or(0);
        self.win = Cow::Owned(v);
        self.base = keep;
        if got == 0 {
            self.len = self.base + self.win.len();
            return false;
        }
        true
    }

    /// The next whitespace-separated token and where it starts, or `None` at the end.
    pub fn token(&mut self) -> Option<(usize, &[u8])> {
        let entry = self.pos;
        loop {
            let i = self.pos - self.base;
            match self.win[i..].iter().position(|&b| !is_ws(b)) {
                Some(k) => {
                    self.pos += k;
                    break;
                }
                None => {
                    self.pos = self.base + self.win.len();
                    if !self.fill(entry) {
                        return None;
                    }
                }
            }
        }
        let start = self.pos;
        self.token_start = start;
        self.cut = false;
        loop {
            let i = self.pos - self.base;
            match self.win[i..].iter().position(|&b| is_ws(b)) {
                Some(k) => {
                    self.pos += k;
                    break;
                }
                None => {
                    self.pos = self.base + self.win.len();
                    if !self.fill(start) {
                        self.cut = true;
                        break;
                    }
                }
            }
        }
        Some((start, &self.win[start - self.base..self.pos - self.base]))
    }

    /// [`Cursor::token`] with whether it ran into the end of the input, so that it may be the
    /// first bytes of a longer word or number. Only an ASCII file's last data value may end
    /// there: VTK ends every keyword, name and count with whitespace.
    pub fn token_cut(&mut self) -> Option<(usize, &[u8], bool)> {
        self.token()?;
        let (start, end) = (self.token_start, self.pos);
        Some((
            start,
            &self.win[start - self.base..end - self.base],
            self.cut,
        ))
    }

    /// Text read at byte `at` (a %-encoded name when `escaped`, else raw bytes) as a String.
    /// Bytes that are not UTF-8 become U+FFFD, with a warning naming the file, the byte and
    /// `what` was read, since the name written back will differ from the file's.
    pub fn name(&self, at: usize, t: &[u8], escaped: bool, what: &str) -> String {
        let raw = if escaped {
            super::names::unescape(t)
        } else {
            t.to_vec()
        };
        crate::text_or_warn(&raw, &self.label, &format!("byte {at}"), what)
    }

    /// The error for token `t` at `p` that ran into the end of the input while `what` was read:
    /// a truncated file, not a misspelt word.
    pub fn cut_err(&self, p: usize, t: &[u8], what: &str) -> FormatError {
        self.err(
            p,
            format!(
                "unexpected end of file in '{}' while reading {what} (the file ends there: truncated?)",
                show(t)
            ),
        )
    }

    /// The next token (copied: keywords, names and counts only), or an error saying what was
    /// expected; a token cut by the end of the file is an unexpected end of file too.
    pub fn require(&mut self, what: &str) -> Result<(usize, Vec<u8>), FormatError> {
        match self.token() {
            Some((p, t)) => {
                let t = t.to_vec();
                if self.cut {
                    return Err(self.cut_err(p, &t, what));
                }
                Ok((p, t))
            }
            None => Err(self.err(self.pos, format!("unexpected end of file, expected {what}"))),
        }
    }

    /// The next keyword, `None` at the end of the input; one cut by the end of the file is an
    /// error, as in [`Cursor::require`].
    pub fn keyword(&mut self, what: &str) -> Result<Option<(usize, Vec<u8>)>, FormatError> {
        match self.token() {
            Some((p, t)) => {
                let t = t.to_vec();
                if self.cut {
                    return Err(self.cut_err(p, &t, what));
                }
                Ok(Some((p, t)))
            }
            None => Ok(None),
        }
    }

    /// Peeks at the next keyword without consuming it, as [`Cursor::keyword`] reads it.
    pub fn peek_keyword(&mut self, what: &str) -> Result<Option<(usize, Vec<u8>)>, FormatError> {
        let save = self.pos;
        let t = self.keyword(what);
        self.pos = save;
        t
    }

    /// The next token as a non-negative count that fits in memory terms (`usize`).
    pub fn expect_count(&mut self, what: &str) -> Result<usize, FormatError> {
        let (p, t) = self.require(what)?;
        match parse_count(&t) {
            Some(n) => Ok(n),
            None => {
                let m = format!(
                    "expected {what} (a non-negative integer), found '{}'",
                    show(&t)
                );
                Err(self.err(p, m))
            }
        }
    }

    /// Whether the byte just consumed is a newline: after [`Cursor::line`] at the end of the
    /// input, false when the last line had none (a file cut inside it, often).
    pub fn after_newline(&self) -> bool {
        self.pos > self.base && self.win.get(self.pos - self.base - 1) == Some(&b'\n')
    }

    /// The rest of the current line (without `\r\n`), consuming the newline.
    pub fn line(&mut self) -> &[u8] {
        let start = self.pos;
        let end;
        loop {
            let i = self.pos - self.base;
            match self.win[i..].iter().position(|&b| b == b'\n') {
                Some(k) => {
                    end = self.pos + k;
                    self.pos = end + 1;
                    break;
                }
                None => {
                    self.pos = self.base + self.win.len();
                    if !self.fill(start) {
                        end = self.pos;
                        break;
                    }
                }
            }
        }
        let line = &self.win[start - self.base..end - self.base];
        line.strip_suffix(b"\r").unwrap_or(line)
    }

    /// Moves to the first byte after the end of the current line: where VTK starts binary data
    /// after a keyword line.
    pub fn begin_binary(&mut self) {
        let at = self.pos;
        self.line();
        self.blocks.push((at, self.pos));
    }

    /// Fills `dst` with the next bytes, checking they are present.
    pub fn read_into(&mut self, dst: &mut [u8], what: &str) -> Result<(), FormatError> {
        let n = dst.len();
        if n > self.remaining() {
            return Err(self.err(
                self.pos,
                format!(
                    "{what}: needs {n} bytes of binary data but only {} remain (truncated file or wrong count)",
                    self.remaining()
                ),
            ));
        }
        let i = self.pos - self.base;
        let have = (self.win.len() - i).min(n);
        dst[..have].copy_from_slice(&self.win[i..i + have]);
        if have < n {
            let at = self.pos + have;
            let rest = &mut dst[have..];
            let result = match self.positional {
                Some(f) if rest.len() >= PARALLEL_READ => read_parallel(f, rest, at as u64),
                _ => match self.file.as_mut() {
                    Some(file) => file.read_exact(rest),
                    None => Err(std::io::ErrorKind::UnexpectedEof.into()),
                },
            };
            if let Err(e) = result {
                return Err(FormatError::new(
                    Place::Byte(at as u64),
                    format!("{what}: reading failed ({e}); was the file truncated?"),
                ));
            }
            // The window lies wholly behind us now.
            self.lines_before += self.win.iter().filter(|&&b| b == b'\n').count();
            self.win = Cow::Owned(Vec::new());
            self.base = self.pos + n;
        }
        self.pos += n;
        Ok(())
    }

    /// The next `n` bytes as a vector (small blocks: bits, string lengths and strings).
    pub fn take(&mut self, n: usize, what: &str) -> Result<Vec<u8>, FormatError> {
        if n > self.remaining() {
            return Err(self.err(
                self.pos,
                format!(
                    "{what}: needs {n} bytes but only {} remain",
                    self.remaining()
                ),
            ));
        }
        let mut v = vec![0u8; n];
        self.read_into(&mut v, what)?;
        Ok(v)
    }

    /// Where value `k` of a block whose keyword line ends at `at` is: its byte offset in binary
    /// data (`size` bytes each), its token in text. Only errors call this.
    pub fn value_at(&self, at: usize, k: usize, size: usize) -> usize {
        if self.binary {
            let start = self
                .blocks
                .iter()
                .rev()
                .find(|b| b.0 == at)
                .map_or(at, |b| b.1);
            return start.saturating_add(k.saturating_mul(size));
        }
        if at < self.base {
            return at;
        }
        let mut c = Cursor::new(&self.win);
        c.pos = at - self.base;
        let mut p = at;
        for _ in 0..=k {
            match c.token() {
                Some((q, _)) => p = q + self.base,
                None => break,
            }
        }
        p
    }

    /// 1-based line number of byte `pos`. Blocks read straight from a file are not counted:
    /// only BINARY files stream, and their errors name byte offsets instead.
    pub fn line_at(&self, pos: usize) -> usize {
        let end = pos.clamp(self.base, self.base + self.win.len()) - self.base;
        1 + self.lines_before + self.win[..end].iter().filter(|&&b| b == b'\n').count()
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

/// Blocks at least this big are read in parallel pieces of `PIECE` bytes.
const PARALLEL_READ: usize = 8 << 20;
const PIECE: usize = 4 << 20;

/// Reads `dst` from `file` at `offset` with positional reads on several threads: the kernel's
/// copy and the page faults of fresh memory are the cost of a big read, and both run in
/// parallel this way. Leaves the file's own position just after the block.
fn read_parallel(file: &std::fs::File, dst: &mut [u8], offset: u64) -> std::io::Result<()> {
    use rayon::prelude::*;
    use std::io::{Seek, SeekFrom};
    use std::os::unix::fs::FileExt;
    dst.par_chunks_mut(PIECE)
        .enumerate()
        .try_for_each(|(i, piece)| file.read_exact_at(piece, offset + (i * PIECE) as u64))?;
    let mut f = file;
    f.seek(SeekFrom::Start(offset + dst.len() as u64))?;
    Ok(())
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
        assert_eq!(c.token().map(|t| t.1.to_vec()), Some(b"POINTS".to_vec()));
        assert_eq!(c.expect_count("n").ok(), Some(12));
        assert_eq!(c.token().map(|t| t.1.to_vec()), Some(b"float".to_vec()));
        assert_eq!(c.line(), b"");
        assert_eq!(c.line_at(c.pos), 2);
        assert_eq!(c.line(), b"abc");
        assert!(c.token().is_none());
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
        assert_eq!(c.take(3, "data").ok(), Some(b"abc".to_vec()));
    }

    /// A reader that hands out a few bytes per call, to cross every window edge.
    struct Trickle<'a>(&'a [u8]);
    impl Read for Trickle<'_> {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            let n = buf.len().min(self.0.len()).min(3);
            buf[..n].copy_from_slice(&self.0[..n]);
            self.0 = &self.0[n..];
            Ok(n)
        }
    }

    #[test]
    fn streaming_matches_memory() {
        let mut text = b"# head\nPOINTS  123456 float\nxy\n".to_vec();
        text.extend((0..200_000u32).map(|i| (i % 251) as u8));
        text.extend_from_slice(b"\nCELL_TYPES 3\ntail line\n");
        for short in [false, true] {
            let len = text.len() + if short { 50 } else { 0 };
            let mut c = Cursor::from_reader(Box::new(Trickle(&text)), len);
            assert_eq!(c.line(), b"# head");
            assert_eq!(c.require("kw").unwrap().1, b"POINTS");
            assert_eq!(c.expect_count("n").unwrap(), 123456);
            assert!(matches!(c.peek_keyword("type"), Ok(Some((_, t))) if t == b"float"));
            assert_eq!(c.require("type").unwrap().1, b"float");
            assert_eq!(c.line_at(c.pos), 2);
            c.begin_binary();
            assert_eq!(c.line(), b"xy");
            let mut block = vec![0u8; 200_000];
            c.read_into(&mut block, "block").unwrap();
            assert_eq!(block[1000], (1000 % 251) as u8);
            assert_eq!(c.require("kw").unwrap().1, b"CELL_TYPES");
            assert_eq!(c.expect_count("n").unwrap(), 3);
            c.line();
            assert_eq!(c.line(), b"tail line");
            assert!(c.token().is_none());
            let mut more = [0u8; 10];
            assert!(c.read_into(&mut more, "more").is_err());
        }
    }
}
