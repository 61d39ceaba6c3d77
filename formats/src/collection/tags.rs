//! The elements of a small VTK XML index file (.vtm, .pvd), with their attributes and byte offsets.

use crate::{FormatError, Result};
use quick_xml::events::{BytesStart, Event};

/// Whether an element opens, is self-closing, or closes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    Open,
    Empty,
    Close,
}

/// One element: its local name, attributes (unescaped), and the byte where it starts.
#[derive(Clone, Debug)]
pub(crate) struct Tag {
    pub name: String,
    pub attrs: Vec<(String, String)>,
    pub pos: u64,
    pub kind: Kind,
}

impl Tag {
    pub fn get(&self, key: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }
}

fn attrs(e: &BytesStart, pos: u64) -> Result<Vec<(String, String)>> {
    let mut out = Vec::new();
    for a in e.attributes().with_checks(true) {
        let a = a.map_err(|err| FormatError::at_byte(pos, format!("malformed XML: {err}")))?;
        let v = a
            .unescape_value()
            .map_err(|err| FormatError::at_byte(pos, format!("malformed XML: {err}")))?;
        out.push((
            String::from_utf8_lossy(a.key.local_name().as_ref()).into_owned(),
            v.into_owned(),
        ));
    }
    Ok(out)
}

/// Every element of `bytes` in document order; malformed XML and DOCTYPEs (entity expansion) are
/// refused at their byte.
pub(crate) fn tags(bytes: &[u8]) -> Result<Vec<Tag>> {
    let mut reader = quick_xml::Reader::from_reader(bytes);
    reader.config_mut().check_end_names = true;
    let mut buf = Vec::new();
    let mut out = Vec::new();
    loop {
        let pos = reader.buffer_position();
        buf.clear();
        let ev = reader.read_event_into(&mut buf).map_err(|e| {
            FormatError::at_byte(reader.error_position(), format!("malformed XML: {e}"))
        })?;
        let name = |n: &[u8]| String::from_utf8_lossy(n).into_owned();
        match ev {
            Event::DocType(_) => return Err(FormatError::at_byte(
                pos,
                "a DOCTYPE declaration is not allowed in a VTK file (refused: entity expansion)",
            )),
            Event::Start(e) => out.push(Tag {
                name: name(e.local_name().as_ref()),
                attrs: attrs(&e, pos)?,
                pos,
                kind: Kind::Open,
            }),
            Event::Empty(e) => out.push(Tag {
                name: name(e.local_name().as_ref()),
                attrs: attrs(&e, pos)?,
                pos,
                kind: Kind::Empty,
            }),
            Event::End(e) => out.push(Tag {
                name: name(e.local_name().as_ref()),
                attrs: Vec::new(),
                pos,
                kind: Kind::Close,
            }),
            Event::Eof => break,
            _ => {}
        }
    }
    Ok(out)
}

/// Checks the root is `<VTKFile type="{want}">`.
pub(crate) fn check_root(tags: &[Tag], want: &[&str]) -> Result<()> {
    let Some(root) = tags.first() else {
        return Err(FormatError::at_byte(0, "no XML elements (empty file?)"));
    };
    if root.name != "VTKFile" {
        return Err(FormatError::at_byte(
            root.pos,
            format!("the root element is <{}>, expected <VTKFile>", root.name),
        ));
    }
    match root.get("type") {
        Some(t) if want.contains(&t) => Ok(()),
        other => Err(FormatError::at_byte(
            root.pos,
            format!(
                "VTKFile type is {:?}, expected \"{}\"",
                other.unwrap_or("(none)"),
                want.join("\" or \"")
            ),
        )),
    }
}
