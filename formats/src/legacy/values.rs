//! Legacy data type keywords and reading arrays of them: ASCII tokens or big-endian binary,
//! decoded in parallel, with every declared size checked against the bytes present.

use super::cursor::{is_kw, show, Cursor};
use crate::{ArrayData, FormatError, ScalarType};
use rayon::prelude::*;

/// A data type keyword as legacy files spell it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum LegacyType {
    /// Packed bits in binary, 0/1 in ASCII; kept as UInt8 (VTK XML has no bit type).
    Bit,
    Num(ScalarType),
    /// `vtkIdType`: VTK writes it as 32-bit int and reads it back as 64-bit ids.
    IdType,
    /// `string` / `utf8_string` (field data only).
    String,
}

impl LegacyType {
    /// Bytes per value in binary files (for error offsets; bits and strings have no fixed size).
    pub fn binary_size(self) -> usize {
        match self {
            LegacyType::Num(t) => t.size(),
            LegacyType::IdType => 4,
            LegacyType::Bit | LegacyType::String => 1,
        }
    }

    pub fn parse(t: &[u8]) -> Option<LegacyType> {
        use ScalarType::*;
        let n = |s| LegacyType::Num(s);
        // The fixed-size `vtktype*` names: VTK writes the 64-bit ones, meshio (and newer VTK
        // readers) every one of them.
        let table: [(&str, LegacyType); 27] = [
            ("bit", LegacyType::Bit),
            ("char", n(Int8)),
            ("signed_char", n(Int8)),
            ("unsigned_char", n(UInt8)),
            ("short", n(Int16)),
            ("unsigned_short", n(UInt16)),
            ("int", n(Int32)),
            ("unsigned_int", n(UInt32)),
            ("vtktypeint8", n(Int8)),
            ("vtktypeuint8", n(UInt8)),
            ("vtktypeint16", n(Int16)),
            ("vtktypeuint16", n(UInt16)),
            ("vtktypeint32", n(Int32)),
            ("vtktypeuint32", n(UInt32)),
            // `long` is 8 bytes on the LP64 systems VTK runs on.
            ("long", n(Int64)),
            ("unsigned_long", n(UInt64)),
            ("long_long", n(Int64)),
            ("unsigned_long_long", n(UInt64)),
            ("vtktypeint64", n(Int64)),
            ("vtktypeuint64", n(UInt64)),
            ("float", n(Float32)),
            ("double", n(Float64)),
            ("vtktypefloat32", n(Float32)),
            ("vtktypefloat64", n(Float64)),
            ("vtkidtype", LegacyType::IdType),
            ("string", LegacyType::String),
            ("utf8_string", LegacyType::String),
        ];
        table.iter().find(|(k, _)| is_kw(t, k)).map(|&(_, v)| v)
    }
}

/// A numeric element as legacy files store it.
pub(crate) trait Value: bytemuck::Pod + Send + Sync + 'static {
    const SIZE: usize = std::mem::size_of::<Self>();
    /// The value whose big-endian bytes this native value holds.
    fn be_to_native(self) -> Self;
    fn parse_ascii(t: &[u8]) -> Option<Self>;
}

macro_rules! value_int {
    ($($t:ty),*) => {$(
        impl Value for $t {
            fn be_to_native(self) -> Self {
                <$t>::from_be(self)
            }
            fn parse_ascii(t: &[u8]) -> Option<Self> {
                std::str::from_utf8(t).ok()?.parse().ok()
            }
        }
    )*};
}
value_int!(i8, u8, i16, u16, i32, u32, i64, u64);

macro_rules! value_float {
    ($($t:ty, $bits:ty),*) => {$(
        impl Value for $t {
            fn be_to_native(self) -> Self {
                <$t>::from_bits(<$bits>::from_be(self.to_bits()))
            }
            fn parse_ascii(t: &[u8]) -> Option<Self> {
                let s = std::str::from_utf8(t).ok()?;
                // C++ streams and printf write "nan", "-nan", "inf" and "1.#INF" variants.
                match s.parse() {
                    Ok(v) => Some(v),
                    Err(_) => match s.to_ascii_lowercase().trim_start_matches(['+', '-']) {
                        "nan" | "nan(ind)" | "1.#qnan" | "1.#ind" => Some(<$t>::NAN),
                        _ => None,
                    },
                }
            }
        }
    )*};
}
value_float!(f32, u32, f64, u64);

/// Below this many bytes swapping is not worth a thread hop.
const PAR_MIN: usize = 1 << 16;

/// Turns big-endian values read into `v` into native ones, in parallel when the block is large.
pub(crate) fn swap_be<T: Value>(v: &mut [T]) {
    if cfg!(target_endian = "big") {
        return;
    }
    if v.len() * T::SIZE >= PAR_MIN {
        v.par_chunks_mut(PAR_MIN / T::SIZE)
            .for_each(|c| c.iter_mut().for_each(|x| *x = x.be_to_native()));
    } else {
        v.iter_mut().for_each(|x| *x = x.be_to_native());
    }
}

/// Reads `n` values: binary data starting after the current line, or `n` ASCII tokens.
pub(crate) fn read_values<T: Value>(
    cur: &mut Cursor<'_>,
    n: usize,
    what: &str,
) -> Result<Vec<T>, FormatError> {
    if cur.binary {
        cur.begin_binary();
        let start = cur.pos;
        let bytes = n
            .checked_mul(T::SIZE)
            .ok_or_else(|| cur.err(start, format!("{what}: {n} values is too many (overflow)")))?;
        if bytes > cur.remaining() {
            return Err(cur.err(
                start,
                format!(
                    "{what}: needs {bytes} bytes of binary data but only {} remain (truncated file or wrong count)",
                    cur.remaining()
                ),
            ));
        }
        // Zeroed allocation maps fresh pages lazily; the read fills them once, from the file.
        let mut v: Vec<T> = bytemuck::zeroed_vec(n);
        cur.read_into(bytemuck::cast_slice_mut(&mut v), what)?;
        swap_be(&mut v);
        return Ok(v);
    }
    read_ascii(cur, n, what, T::parse_ascii)
}

/// Reads `n` ASCII tokens with `parse`; the declared count only bounds the reservation by the
/// bytes left, since each value takes at least two bytes (digit and separator).
pub(crate) fn read_ascii<T>(
    cur: &mut Cursor<'_>,
    n: usize,
    what: &str,
    parse: impl Fn(&[u8]) -> Option<T>,
) -> Result<Vec<T>, FormatError> {
    if n > cur.remaining() {
        return Err(cur.err(
            cur.pos,
            format!(
                "{what}: declares {n} values but only {} bytes remain (truncated file or wrong count)",
                cur.remaining()
            ),
        ));
    }
    let mut out = Vec::with_capacity(n.min(cur.remaining() / 2 + 1));
    for i in 0..n {
        let binary = cur.binary;
        let Some((p, t, cut)) = cur.token_cut() else {
            return Err(cur.err(
                cur.pos,
                format!("{what}: unexpected end of file after {i} of {n} values"),
            ));
        };
        // An ASCII file's last value may lack its newline (VTK reads it so); anything else that
        // runs into the end was cut.
        if cut && (binary || i + 1 < n) {
            let t = t.to_vec();
            return Err(cur.cut_err(p, &t, &format!("{what}, value {i} of {n}")));
        }
        match parse(t) {
            Some(v) => out.push(v),
            None => {
                let t = t.to_vec();
                return Err(cur.err(
                    p,
                    format!(
                        "{what}: value {i} of {n} is '{}', not a number of the declared type",
                        show(&t)
                    ),
                ));
            }
        }
    }
    Ok(out)
}

/// Reads `n` values of a numeric legacy type into the matching array variant.
pub(crate) fn read_numeric(
    cur: &mut Cursor<'_>,
    ty: LegacyType,
    n: usize,
    what: &str,
) -> Result<ArrayData, FormatError> {
    use ScalarType as S;
    Ok(match ty {
        LegacyType::Num(S::Int8) => ArrayData::Int8(read_values(cur, n, what)?),
        LegacyType::Num(S::UInt8) => ArrayData::UInt8(read_values(cur, n, what)?),
        LegacyType::Num(S::Int16) => ArrayData::Int16(read_values(cur, n, what)?),
        LegacyType::Num(S::UInt16) => ArrayData::UInt16(read_values(cur, n, what)?),
        LegacyType::Num(S::Int32) => ArrayData::Int32(read_values(cur, n, what)?),
        LegacyType::Num(S::UInt32) => ArrayData::UInt32(read_values(cur, n, what)?),
        LegacyType::Num(S::Int64) => ArrayData::Int64(read_values(cur, n, what)?),
        LegacyType::Num(S::UInt64) => ArrayData::UInt64(read_values(cur, n, what)?),
        LegacyType::Num(S::Float32) => ArrayData::Float32(read_values(cur, n, what)?),
        LegacyType::Num(S::Float64) => ArrayData::Float64(read_values(cur, n, what)?),
        LegacyType::IdType => {
            let v: Vec<i32> = read_values(cur, n, what)?;
            ArrayData::Int64(v.into_iter().map(i64::from).collect())
        }
        LegacyType::Bit => ArrayData::UInt8(read_bits(cur, n, what)?),
        LegacyType::String => ArrayData::String(read_strings(cur, n, what)?),
    })
}

/// Bit arrays: packed most-significant bit first in binary, 0/1 tokens in ASCII.
fn read_bits(cur: &mut Cursor<'_>, n: usize, what: &str) -> Result<Vec<u8>, FormatError> {
    if cur.binary {
        cur.begin_binary();
        let src = cur.take(n.div_ceil(8), what)?;
        return Ok((0..n).map(|i| (src[i / 8] >> (7 - i % 8)) & 1).collect());
    }
    read_ascii(cur, n, what, |t| match t {
        b"0" => Some(0),
        b"1" => Some(1),
        _ => None,
    })
}

/// String arrays: one %-encoded string per line in ASCII; in binary each string is preceded by
/// a big-endian length whose top two bits say its width (11: 6-bit in 1 byte, 10: 14-bit in 2,
/// 01: 30-bit in 4, 00: 62-bit in 8), as vtkDataWriter writes them.
fn read_strings(cur: &mut Cursor<'_>, n: usize, what: &str) -> Result<Vec<String>, FormatError> {
    if n > cur.remaining() {
        return Err(cur.err(
            cur.pos,
            format!(
                "{what}: declares {n} strings but only {} bytes remain",
                cur.remaining()
            ),
        ));
    }
    // Each string is at least one byte, but a String is 24: grow instead of trusting `n`.
    let mut out = Vec::with_capacity(n.min(4096));
    if cur.binary {
        cur.begin_binary();
        for i in 0..n {
            let at = cur.pos;
            let first = cur.take(1, what)?[0];
            let len = match first >> 6 {
                3 => (first & 0x3f) as u64,
                2 => {
                    let b = cur.take(1, what)?;
                    (u16::from_be_bytes([first, b[0]]) & 0x3fff) as u64
                }
                1 => {
                    let b = cur.take(3, what)?;
                    (u32::from_be_bytes([first, b[0], b[1], b[2]]) & 0x3fff_ffff) as u64
                }
                _ => {
                    let b = cur.take(7, what)?;
                    let mut a = [first; 8];
                    a[1..].copy_from_slice(&b);
                    u64::from_be_bytes(a)
                }
            };
            let len = usize::try_from(len)
                .ok()
                .filter(|&l| l <= cur.remaining())
                .ok_or_else(|| {
                    cur.err(
                        at,
                        format!("{what}: string {i} declares {len} bytes, more than remain"),
                    )
                })?;
            let at = cur.pos;
            let s = cur.take(len, what)?;
            out.push(cur.name(at, &s, false, &format!("{what}: string {i}")));
        }
        return Ok(out);
    }
    // The strings start on the line after the array header.
    cur.line();
    for i in 0..n {
        if cur.remaining() == 0 {
            return Err(cur.err(
                cur.pos,
                format!("{what}: unexpected end of file after {i} of {n} strings"),
            ));
        }
        let at = cur.pos;
        let line = cur.line().to_vec();
        out.push(cur.name(at, &line, true, &format!("{what}: string {i}")));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binary_big_endian_and_parallel() {
        let vals: Vec<i64> = (0..100_000).map(|i| i * 7 - 3).collect();
        let mut bytes = b"CONNECTIVITY vtktypeint64\n".to_vec();
        for v in &vals {
            bytes.extend_from_slice(&v.to_be_bytes());
        }
        let mut c = Cursor::new(&bytes);
        c.binary = true;
        c.token();
        c.token();
        let got: Vec<i64> = read_values(&mut c, vals.len(), "x").unwrap();
        assert_eq!(got, vals);
    }

    #[test]
    fn ascii_errors_name_the_line() {
        let mut c = Cursor::new(b"1 2\n3 x 5\n");
        let e = read_values::<i32>(&mut c, 5, "ids").unwrap_err();
        assert_eq!(e.place, crate::Place::Line(2));
        let mut c = Cursor::new(b"1 2");
        assert!(read_values::<i32>(&mut c, 1 << 40, "ids").is_err());
        let mut c = Cursor::new(b"nan -nan inf 1e3");
        let v: Vec<f64> = read_values(&mut c, 4, "f").unwrap();
        assert!(v[0].is_nan() && v[1].is_nan() && v[2].is_infinite() && v[3] == 1000.0);
    }

    #[test]
    fn binary_strings_with_length_prefixes() {
        let mut bytes = b"names 1 2 string\n".to_vec();
        bytes.push(0xc3);
        bytes.extend_from_slice(b"a b");
        bytes.extend_from_slice(&(0x8000u16 | 100).to_be_bytes());
        bytes.extend_from_slice(&[b'x'; 100]);
        let mut c = Cursor::new(&bytes);
        c.binary = true;
        let v = read_strings(&mut c, 2, "names").unwrap();
        assert_eq!(v[0], "a b");
        assert_eq!(v[1].len(), 100);
    }
}
