//! The three header lines of a legacy file: magic and version, title, ASCII or BINARY.

use super::cursor::{is_kw, show, Cursor};
use crate::FormatError;

/// What the header says.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Header {
    pub major: u32,
    pub minor: u32,
    pub title: String,
    pub binary: bool,
}

/// Parses the header and leaves the cursor at the start of the fourth line.
pub(crate) fn parse(cur: &mut Cursor<'_>) -> Result<Header, FormatError> {
    if cur.remaining() == 0 {
        return Err(cur.err(0, "the file is empty"));
    }
    let first = cur.line().to_vec();
    let first = &first[crate::bom_len(&first)..];
    let magic = b"# vtk DataFile Version";
    let n = first.len().min(magic.len());
    // The first line alone, and the start of the magic line or all of it: cut short.
    if cur.remaining() == 0 && first[..n].eq_ignore_ascii_case(&magic[..n]) {
        return Err(cur.err(
            0,
            format!(
                "unexpected end of file in the first line '{}' (truncated?)",
                show(first)
            ),
        ));
    }
    if first.len() < magic.len() || !first[..magic.len()].eq_ignore_ascii_case(magic) {
        return Err(cur.err(
            0,
            format!(
                "not a legacy VTK file: the first line is '{}', expected '# vtk DataFile Version x.y'",
                show(first)
            ),
        ));
    }
    let version = String::from_utf8_lossy(&first[magic.len()..])
        .trim()
        .to_string();
    let (major, minor) = version
        .split_once('.')
        .and_then(|(a, b)| Some((a.parse::<u32>().ok()?, b.parse::<u32>().ok()?)))
        .ok_or_else(|| {
            cur.err(
                0,
                format!("the version '{version}' is not of the form MAJOR.MINOR"),
            )
        })?;
    if (major, minor) > (5, 1) {
        return Err(cur.err(
            0,
            format!("version {major}.{minor} is newer than 5.1, the newest this reader knows"),
        ));
    }
    if cur.remaining() == 0 {
        return Err(cur.err(cur.pos, "unexpected end of file: no title line"));
    }
    let title = String::from_utf8_lossy(cur.line()).into_owned();
    let (p, t) = cur.require("ASCII or BINARY on the third line")?;
    let binary = if is_kw(&t, "ASCII") {
        false
    } else if is_kw(&t, "BINARY") {
        true
    } else {
        return Err(cur.err(
            p,
            format!(
                "expected ASCII or BINARY on the third line, found '{}'",
                show(&t)
            ),
        ));
    };
    cur.line();
    cur.binary = binary;
    Ok(Header {
        major,
        minor,
        title,
        binary,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_lines() {
        let mut c = Cursor::new(b"# vtk DataFile Version 5.1\nmy title\nBINARY\nDATASET");
        let h = parse(&mut c).unwrap();
        assert_eq!((h.major, h.minor, h.binary), (5, 1, true));
        assert_eq!(h.title, "my title");
        assert!(parse(&mut Cursor::new(b"# vtk DataFile Version 6.0\nt\nASCII\n")).is_err());
        assert!(parse(&mut Cursor::new(b"# vtk DataFile Version 4.2\nt\nTEXT\n")).is_err());
        assert!(parse(&mut Cursor::new(b"hello")).is_err());
    }
}
