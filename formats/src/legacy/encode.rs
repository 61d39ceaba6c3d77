//! Writing values: big-endian binary (encoded in parallel, in bounded blocks) or ASCII text that
//! reads back to the same bits (shortest round-trip decimal for floats).

use rayon::prelude::*;
use std::io::{self, Write};

/// A numeric element as legacy files store it.
pub(crate) trait Encode: Copy + Send + Sync {
    const SIZE: usize;
    fn put_be(self, out: &mut [u8]);
    fn put_ascii(self, out: &mut Vec<u8>);
}

macro_rules! encode_int {
    ($($t:ty),*) => {$(
        impl Encode for $t {
            const SIZE: usize = std::mem::size_of::<$t>();
            fn put_be(self, out: &mut [u8]) {
                out.copy_from_slice(&self.to_be_bytes());
            }
            fn put_ascii(self, out: &mut Vec<u8>) {
                let _ = write!(out, "{self}");
            }
        }
    )*};
}
encode_int!(i8, u8, i16, u16, i32, u32, i64, u64);

macro_rules! encode_float {
    ($($t:ty),*) => {$(
        impl Encode for $t {
            const SIZE: usize = std::mem::size_of::<$t>();
            fn put_be(self, out: &mut [u8]) {
                out.copy_from_slice(&self.to_be_bytes());
            }
            fn put_ascii(self, out: &mut Vec<u8>) {
                // Debug is the shortest text that parses back to the same value, with an
                // exponent for very large or small magnitudes (Display would spell out 1e300).
                if self.is_nan() {
                    out.extend_from_slice(b"nan");
                } else {
                    let _ = write!(out, "{self:?}");
                }
            }
        }
    )*};
}
encode_float!(f32, f64);

/// Values per block: bounds the temporary buffer, and each block is split across threads.
const BLOCK: usize = 1 << 21;
const PAR_CHUNK: usize = 1 << 15;

/// Writes `vals` as big-endian binary followed by a newline, or as ASCII, nine values a line.
pub(crate) fn put_values<T: Encode>(w: &mut dyn Write, vals: &[T], binary: bool) -> io::Result<()> {
    if binary {
        let mut buf = Vec::new();
        for block in vals.chunks(BLOCK) {
            buf.clear();
            buf.resize(block.len() * T::SIZE, 0);
            if block.len() > PAR_CHUNK {
                buf.par_chunks_mut(PAR_CHUNK * T::SIZE)
                    .zip(block.par_chunks(PAR_CHUNK))
                    .for_each(|(b, v)| encode_into(b, v));
            } else {
                encode_into(&mut buf, block);
            }
            w.write_all(&buf)?;
        }
        return w.write_all(b"\n");
    }
    let mut line = Vec::with_capacity(256);
    for row in vals.chunks(9) {
        line.clear();
        for (k, &v) in row.iter().enumerate() {
            if k > 0 {
                line.push(b' ');
            }
            v.put_ascii(&mut line);
        }
        line.push(b'\n');
        w.write_all(&line)?;
    }
    if vals.is_empty() {
        w.write_all(b"\n")?;
    }
    Ok(())
}

fn encode_into<T: Encode>(out: &mut [u8], vals: &[T]) {
    for (o, &v) in out.chunks_exact_mut(T::SIZE).zip(vals) {
        v.put_be(o);
    }
}

/// Strings: one %-encoded string a line in ASCII; in binary, each prefixed by its length in the
/// variable-width big-endian form vtkDataWriter uses, then a newline after the last.
pub(crate) fn put_strings(w: &mut dyn Write, vals: &[String], binary: bool) -> io::Result<()> {
    if !binary {
        for s in vals {
            w.write_all(super::names::encode(s).as_bytes())?;
            w.write_all(b"\n")?;
        }
        return Ok(());
    }
    for s in vals {
        let n = s.len() as u64;
        if n < 1 << 6 {
            w.write_all(&[0xc0 | n as u8])?;
        } else if n < 1 << 14 {
            w.write_all(&(0x8000 | n as u16).to_be_bytes())?;
        } else if n < 1 << 30 {
            w.write_all(&(0x4000_0000 | n as u32).to_be_bytes())?;
        } else {
            w.write_all(&n.to_be_bytes())?;
        }
        w.write_all(s.as_bytes())?;
    }
    w.write_all(b"\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ascii_floats_round_trip() {
        let vals = [0.1f64, 1e300, -2.5e-300, 3.0, f64::MIN_POSITIVE, -0.0];
        let mut out = Vec::new();
        put_values(&mut out, &vals, false).unwrap();
        let back: Vec<f64> = String::from_utf8(out)
            .unwrap()
            .split_whitespace()
            .map(|t| t.parse().unwrap())
            .collect();
        assert_eq!(
            back.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
            vals.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
        );
    }

    #[test]
    fn binary_is_big_endian_in_parallel_blocks() {
        let vals: Vec<u32> = (0..100_000).collect();
        let mut out = Vec::new();
        put_values(&mut out, &vals, true).unwrap();
        assert_eq!(out.len(), 400_001);
        assert_eq!(&out[4 * 70_000..4 * 70_001], &70_000u32.to_be_bytes());
    }
}
