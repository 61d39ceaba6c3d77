//! Base64 as VTK writes it: standard alphabet, whitespace anywhere, and several padded streams
//! back to back (VTK encodes a compressed block's header and its data separately).

const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
const INVALID: u8 = 0xFF;
const PAD: u8 = 0xFE;
const SPACE: u8 = 0xFD;

const TABLE: [u8; 256] = {
    let mut t = [INVALID; 256];
    let mut i = 0;
    while i < 64 {
        t[ALPHABET[i] as usize] = i as u8;
        i += 1;
    }
    t[b'=' as usize] = PAD;
    t[b' ' as usize] = SPACE;
    t[b'\n' as usize] = SPACE;
    t[b'\r' as usize] = SPACE;
    t[b'\t' as usize] = SPACE;
    t
};

/// A decoding failure at byte `at` of the text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Base64Error {
    pub at: usize,
    pub message: String,
}

/// Decodes base64 text incrementally, so a reader can take a header, look at it, then take
/// exactly the bytes it announces.
pub struct Decoder<'a> {
    text: &'a [u8],
    pos: usize,
    pending: [u8; 3],
    pending_start: usize,
    pending_end: usize,
}

impl<'a> Decoder<'a> {
    pub fn new(text: &'a [u8]) -> Decoder<'a> {
        Decoder {
            text,
            pos: 0,
            pending: [0; 3],
            pending_start: 0,
            pending_end: 0,
        }
    }

    /// Index in the text of the next character not yet consumed.
    pub fn position(&self) -> usize {
        self.pos
    }

    /// True when only whitespace is left and nothing is buffered.
    pub fn at_end(&mut self) -> bool {
        while self.pos < self.text.len() && TABLE[self.text[self.pos] as usize] == SPACE {
            self.pos += 1;
        }
        self.pending_start == self.pending_end && self.pos == self.text.len()
    }

    /// Fills `out` completely, or fails naming where the text ran out or went wrong.
    pub fn read_exact(&mut self, out: &mut [u8]) -> Result<(), Base64Error> {
        let mut o = 0;
        while o < out.len() && self.pending_start < self.pending_end {
            out[o] = self.pending[self.pending_start];
            self.pending_start += 1;
            o += 1;
        }
        while o < out.len() {
            // Fast path: four alphabet characters in a row decode straight into `out`.
            if out.len() - o >= 3 && self.pos + 4 <= self.text.len() {
                let q = &self.text[self.pos..self.pos + 4];
                let (a, b, c, d) = (
                    TABLE[q[0] as usize],
                    TABLE[q[1] as usize],
                    TABLE[q[2] as usize],
                    TABLE[q[3] as usize],
                );
                if (a | b | c | d) < 64 {
                    let v = (a as u32) << 18 | (b as u32) << 12 | (c as u32) << 6 | d as u32;
                    out[o] = (v >> 16) as u8;
                    out[o + 1] = (v >> 8) as u8;
                    out[o + 2] = v as u8;
                    o += 3;
                    self.pos += 4;
                    continue;
                }
            }
            let n = self.quad()?;
            self.pending_start = 0;
            self.pending_end = n;
            while o < out.len() && self.pending_start < self.pending_end {
                out[o] = self.pending[self.pending_start];
                self.pending_start += 1;
                o += 1;
            }
        }
        Ok(())
    }

    /// Decodes everything that is left.
    pub fn read_to_end(&mut self) -> Result<Vec<u8>, Base64Error> {
        let mut out = Vec::with_capacity((self.text.len() - self.pos) / 4 * 3 + 3);
        out.extend_from_slice(&self.pending[self.pending_start..self.pending_end]);
        self.pending_start = self.pending_end;
        while !self.at_end() {
            let n = self.quad()?;
            out.extend_from_slice(&self.pending[..n]);
        }
        Ok(out)
    }

    /// Decodes one group of four characters (skipping whitespace) into `pending`; returns how many
    /// bytes it gave (1 to 3: padding ends a stream, and another may follow).
    fn quad(&mut self) -> Result<usize, Base64Error> {
        let mut v = [0u8; 4];
        let mut k = 0;
        let start = self.pos;
        while k < 4 {
            let Some(&ch) = self.text.get(self.pos) else {
                return Err(Base64Error {
                    at: self.pos,
                    message: if k == 0 {
                        "base64 data ends before the announced size".into()
                    } else {
                        format!("base64 data ends inside a group of 4 (started at {start})")
                    },
                });
            };
            let t = TABLE[ch as usize];
            self.pos += 1;
            match t {
                SPACE => continue,
                INVALID => {
                    return Err(Base64Error {
                        at: self.pos - 1,
                        message: format!("byte 0x{ch:02x} is not base64"),
                    })
                }
                _ => {
                    v[k] = t;
                    k += 1;
                }
            }
        }
        let pads = v.iter().rev().take_while(|&&x| x == PAD).count();
        if pads > 2 || v[..4 - pads].contains(&PAD) {
            return Err(Base64Error {
                at: start,
                message: "misplaced '=' padding in base64".into(),
            });
        }
        let val = v[..4 - pads]
            .iter()
            .enumerate()
            .fold(0u32, |acc, (i, &x)| acc | (x as u32) << (18 - 6 * i));
        self.pending = [(val >> 16) as u8, (val >> 8) as u8, val as u8];
        Ok(3 - pads)
    }
}

/// Appends the base64 encoding of `data` (with padding) to `out`.
pub fn encode_into(out: &mut Vec<u8>, data: &[u8]) {
    out.reserve(data.len().div_ceil(3) * 4);
    let mut chunks = data.chunks_exact(3);
    for c in &mut chunks {
        let v = (c[0] as u32) << 16 | (c[1] as u32) << 8 | c[2] as u32;
        out.extend_from_slice(&[
            ALPHABET[(v >> 18) as usize & 63],
            ALPHABET[(v >> 12) as usize & 63],
            ALPHABET[(v >> 6) as usize & 63],
            ALPHABET[v as usize & 63],
        ]);
    }
    let rest = chunks.remainder();
    if !rest.is_empty() {
        let b1 = rest.get(1).copied().unwrap_or(0);
        let v = (rest[0] as u32) << 16 | (b1 as u32) << 8;
        out.push(ALPHABET[(v >> 18) as usize & 63]);
        out.push(ALPHABET[(v >> 12) as usize & 63]);
        out.push(if rest.len() == 2 {
            ALPHABET[(v >> 6) as usize & 63]
        } else {
            b'='
        });
        out.push(b'=');
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn enc(d: &[u8]) -> Vec<u8> {
        let mut v = Vec::new();
        encode_into(&mut v, d);
        v
    }

    #[test]
    fn round_trips_every_length() {
        for n in 0..40usize {
            let d: Vec<u8> = (0..n).map(|i| (i * 37 + 11) as u8).collect();
            let e = enc(&d);
            assert_eq!(Decoder::new(&e).read_to_end().unwrap(), d, "length {n}");
        }
    }

    #[test]
    fn concatenated_streams_and_whitespace() {
        let mut t = enc(b"ab");
        t.extend_from_slice(b"\n  ");
        t.extend(enc(b"hello world"));
        let mut d = Decoder::new(&t);
        let mut h = [0u8; 2];
        d.read_exact(&mut h).unwrap();
        assert_eq!(&h, b"ab");
        assert_eq!(d.read_to_end().unwrap(), b"hello world");
    }

    #[test]
    fn matches_vtk_text() {
        // From a VTK 9.1 file: header (UInt32 14) and "hello\0wo rld\0\0" in one stream.
        let got = Decoder::new(b"DgAAAGhlbGxvAHdvIHJsZAAA")
            .read_to_end()
            .unwrap();
        assert_eq!(got, b"\x0e\0\0\0hello\0wo rld\0\0");
    }

    #[test]
    fn errors_name_the_place() {
        let e = Decoder::new(b"AAAA AA!A").read_to_end().unwrap_err();
        assert_eq!(e.at, 7);
        let e = Decoder::new(b"AAAAA").read_to_end().unwrap_err();
        assert!(e.message.contains("inside a group"), "{}", e.message);
        let e = Decoder::new(b"A===").read_to_end().unwrap_err();
        assert!(e.message.contains("padding"));
        let mut out = [0u8; 4];
        assert!(Decoder::new(b"AAAA").read_exact(&mut out).is_err());
    }
}
