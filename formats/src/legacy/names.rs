//! The %XX escaping VTK applies to array names and strings in legacy files.

/// The bytes `%XX` escapes stand for.
pub(crate) fn unescape(t: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(t.len());
    let mut i = 0;
    while i < t.len() {
        if t[i] == b'%' && i + 2 < t.len() {
            let hex = |b: u8| (b as char).to_digit(16);
            if let (Some(h), Some(l)) = (hex(t[i + 1]), hex(t[i + 2])) {
                out.push((h * 16 + l) as u8);
                i += 3;
                continue;
            }
        }
        out.push(t[i]);
        i += 1;
    }
    out
}

/// Escapes what would break a whitespace-separated token or a line: whitespace, `%`, `"`,
/// control and non-ASCII bytes (as vtkDataWriter::EncodeString does).
/// Names that read as keywords where an array name may stand (`METADATA` after any array,
/// `NULL_ARRAY` in FIELD blocks) get their first byte escaped too.
pub(crate) fn encode(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let keyword = ["METADATA", "NULL_ARRAY"]
        .iter()
        .any(|k| s.eq_ignore_ascii_case(k));
    for (i, &b) in s.as_bytes().iter().enumerate() {
        if b.is_ascii_graphic() && b != b'%' && b != b'"' && !(keyword && i == 0) {
            out.push(b as char);
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip() {
        assert_eq!(encode("metadata"), "%6Detadata");
        for s in [
            "a b",
            "100%",
            "é\t\"x\"",
            "",
            "%2",
            "METADATA",
            "null_array",
        ] {
            assert_eq!(unescape(encode(s).as_bytes()), s.as_bytes());
        }
        assert_eq!(unescape(b"a%20b%zz%4"), b"a b%zz%4");
    }
}
