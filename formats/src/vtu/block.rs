//! Binary blocks as VTK lays them out: a size header, or a compression header (block count, block
//! size, last block size, compressed sizes) followed by independently compressed blocks. Every
//! declared size is checked against the bytes present before anything is allocated, and blocks are
//! inflated in parallel straight into their place in the destination array.

use super::source::Region;
use super::{ByteOrder, Compressor, HeaderType, Layout};
use crate::{FormatError, Result};
use rayon::prelude::*;

/// Uncompressed size of the blocks tetkit writes (VTK's default).
pub(crate) const BLOCK_SIZE: usize = 1 << 15;

/// Chunk size for parallel copies of uncompressed data.
const COPY_CHUNK: usize = 4 << 20;

/// Where one compressed block is and what it inflates to.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Block {
    pub src: u64,
    pub src_len: usize,
}

/// What an array's header announced, already checked against the bytes present.
#[derive(Clone, Debug)]
pub(crate) enum Plan {
    Raw {
        data: u64,
        len: u64,
    },
    Compressed {
        blocks: Vec<Block>,
        block_size: usize,
        total: u64,
    },
}

impl Plan {
    /// Uncompressed size of the data in bytes.
    pub fn total(&self) -> u64 {
        match self {
            Plan::Raw { len, .. } => *len,
            Plan::Compressed { total, .. } => *total,
        }
    }
}

fn header_value(bytes: &[u8], header: HeaderType, order: ByteOrder) -> u64 {
    match (header, order) {
        (HeaderType::UInt32, ByteOrder::LittleEndian) => {
            u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as u64
        }
        (HeaderType::UInt32, ByteOrder::BigEndian) => {
            u32::from_be_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as u64
        }
        (HeaderType::UInt64, ByteOrder::LittleEndian) => {
            u64::from_le_bytes(bytes[..8].try_into().unwrap_or([0; 8]))
        }
        (HeaderType::UInt64, ByteOrder::BigEndian) => {
            u64::from_be_bytes(bytes[..8].try_into().unwrap_or([0; 8]))
        }
    }
}

/// Reads and checks the header at the start of `region`.
pub(crate) fn plan(region: &Region, layout: &Layout, name: &str) -> Result<Plan> {
    let h = layout.header.size() as u64;
    let err = |rel: u64, msg: String| {
        FormatError::at_byte(region.pos(rel), format!("array '{name}': {msg}"))
    };
    let avail = region.len();
    let read_values = |rel: u64, count: u64| -> Result<Vec<u64>> {
        let need = count
            .checked_mul(h)
            .and_then(|n| n.checked_add(rel))
            .filter(|&end| end <= avail)
            .ok_or_else(|| {
                err(
                    rel,
                    format!("header of {count} values does not fit in the {avail} bytes present (truncated or wrong offset?)"),
                )
            })?;
        let bytes = region
            .bytes(rel, (need - rel) as usize)
            .map_err(|e| err(rel, e.to_string()))?;
        Ok(bytes
            .chunks_exact(h as usize)
            .map(|c| header_value(c, layout.header, layout.order))
            .collect())
    };
    if layout.compressor == Compressor::None {
        let len = read_values(0, 1)?[0];
        if len > avail - h {
            return Err(err(
                0,
                format!(
                    "header declares {len} bytes but only {} follow (truncated or wrong offset?)",
                    avail - h
                ),
            ));
        }
        return Ok(Plan::Raw { data: h, len });
    }
    let head = read_values(0, 3)?;
    let (nb, bs, last) = (head[0], head[1], head[2]);
    let sizes = read_values(3 * h, nb)?;
    if nb == 0 {
        return Ok(Plan::Compressed {
            blocks: Vec::new(),
            block_size: BLOCK_SIZE,
            total: 0,
        });
    }
    if bs == 0 || last > bs {
        return Err(err(
            0,
            format!("compression header has block size {bs} and last block size {last}"),
        ));
    }
    let block_size = usize::try_from(bs)
        .ok()
        .filter(|&b| b <= 1 << 30)
        .ok_or_else(|| err(0, format!("compression block size {bs} is too large")))?;
    let last_len = if last == 0 { bs } else { last };
    let total = (nb - 1)
        .checked_mul(bs)
        .and_then(|t| t.checked_add(last_len))
        .ok_or_else(|| err(0, format!("{nb} blocks of {bs} bytes overflow")))?;
    let mut src = (3 + nb) * h;
    let mut blocks = Vec::with_capacity(sizes.len());
    for (i, &s) in sizes.iter().enumerate() {
        let end = src.checked_add(s).filter(|&e| e <= avail).ok_or_else(|| {
            err(
                src,
                format!("compressed block {i} of {nb} declares {s} bytes, past the end of the data (truncated or wrong offset?)"),
            )
        })?;
        blocks.push(Block {
            src,
            src_len: s as usize,
        });
        src = end;
    }
    let packed = src - (3 + nb) * h;
    let ratio = max_ratio(layout.compressor);
    if total > packed.saturating_mul(ratio).saturating_add(1 << 16) {
        return Err(err(
            0,
            format!(
                "declares {total} bytes inflated from {packed} compressed bytes; refused as a decompression bomb (more than {ratio}:1)"
            ),
        ));
    }
    Ok(Plan::Compressed {
        blocks,
        block_size,
        total,
    })
}

/// Largest inflation ratio a compressor can reach on real data (deflate tops out near 1032:1 and
/// LZ4 near 255:1; LZMA has no tight bound, so a generous one): a header claiming more is a bomb.
fn max_ratio(c: Compressor) -> u64 {
    match c {
        Compressor::None => 1,
        Compressor::Zlib => 1100,
        Compressor::Lz4 => 260,
        Compressor::Lzma => 8192,
    }
}

/// Fills `dst` (exactly `plan.total()` bytes) with the data, in parallel.
pub(crate) fn fill(
    region: &Region,
    layout: &Layout,
    plan: &Plan,
    dst: &mut [u8],
    name: &str,
) -> Result<()> {
    debug_assert_eq!(dst.len() as u64, plan.total());
    match plan {
        Plan::Raw { data, .. } => {
            dst.par_chunks_mut(COPY_CHUNK)
                .enumerate()
                .try_for_each(|(i, c)| {
                    prefault(c);
                    let rel = data + (i * COPY_CHUNK) as u64;
                    region.read_at(rel, c).map_err(|e| {
                        FormatError::at_byte(region.pos(rel), format!("array '{name}': {e}"))
                    })
                })
        }
        Plan::Compressed {
            blocks, block_size, ..
        } => {
            dst.par_chunks_mut(COPY_CHUNK).for_each(prefault);
            dst.par_chunks_mut(*block_size)
                .zip(blocks.par_iter())
                .enumerate()
                .try_for_each(|(i, (out, b))| {
                    let at = region.pos(b.src);
                    let src = region.bytes(b.src, b.src_len).map_err(|e| {
                        FormatError::at_byte(at, format!("array '{name}': block {i}: {e}"))
                    })?;
                    inflate(layout.compressor, &src, out).map_err(|m| {
                        FormatError::at_byte(
                            at,
                            format!("array '{name}': compressed block {i}: {m}"),
                        )
                    })
                })
        }
    }
}

/// Maps a fresh buffer's pages in one call (Linux MADV_POPULATE_WRITE) before it is filled:
/// faulting them in one at a time during the copy was the largest cost of reading raw data.
fn prefault(buf: &mut [u8]) {
    #[cfg(target_os = "linux")]
    {
        const PAGE: usize = 4096;
        let start = buf.as_mut_ptr() as usize;
        let aligned = (start + PAGE - 1) & !(PAGE - 1);
        let end = (start + buf.len()) & !(PAGE - 1);
        if end > aligned {
            // SAFETY: the range lies inside `buf`, which we own mutably; populating only maps
            // (zeroed or existing) pages and changes no contents. Failure (old kernels) is fine.
            unsafe {
                libc::madvise(
                    aligned as *mut libc::c_void,
                    end - aligned,
                    libc::MADV_POPULATE_WRITE,
                );
            }
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = buf;
}

/// Inflates one block into `out`, which must come out exactly full.
fn inflate(c: Compressor, src: &[u8], out: &mut [u8]) -> std::result::Result<(), String> {
    let want = out.len();
    match c {
        Compressor::None => Err("not compressed".into()),
        Compressor::Zlib => {
            let mut d = flate2::Decompress::new(true);
            let status = d
                .decompress(src, out, flate2::FlushDecompress::Finish)
                .map_err(|e| format!("zlib: {e}"))?;
            let got = d.total_out();
            match status {
                flate2::Status::StreamEnd if got == want as u64 => Ok(()),
                flate2::Status::StreamEnd => Err(format!(
                    "inflates to {got} bytes, the header declares {want}"
                )),
                _ if got == want as u64 => Err(format!(
                    "inflates to more than the {want} bytes the header declares"
                )),
                _ => Err(format!("zlib stream ends early: {got} of {want} bytes")),
            }
        }
        Compressor::Lz4 => match lz4_flex::block::decompress_into(src, out) {
            Ok(n) if n == want => Ok(()),
            Ok(n) => Err(format!("inflates to {n} bytes, the header declares {want}")),
            Err(e) => Err(format!("lz4: {e}")),
        },
        Compressor::Lzma => {
            // The memory limit bounds what a hostile dictionary size can make liblzma allocate.
            let mut s = xz2::stream::Stream::new_stream_decoder(256 << 20, 0)
                .map_err(|e| format!("lzma: {e}"))?;
            let status = s
                .process(src, out, xz2::stream::Action::Finish)
                .map_err(|e| format!("lzma: {e}"))?;
            let got = s.total_out();
            match status {
                xz2::stream::Status::StreamEnd if got == want as u64 => Ok(()),
                xz2::stream::Status::StreamEnd => Err(format!(
                    "inflates to {got} bytes, the header declares {want}"
                )),
                _ if got == want as u64 => Err(format!(
                    "inflates to more than the {want} bytes the header declares"
                )),
                _ => Err(format!("lzma stream ends early: {got} of {want} bytes")),
            }
        }
    }
}

/// An encoded array: the header bytes, then data pieces to write one after another.
pub(crate) struct Encoded<'a> {
    pub header: Vec<u8>,
    pub data: Vec<std::borrow::Cow<'a, [u8]>>,
}

impl Encoded<'_> {
    pub fn len(&self) -> usize {
        self.header.len() + self.data.iter().map(|d| d.len()).sum::<usize>()
    }
}

fn put_header(out: &mut Vec<u8>, v: u64, layout: &Layout) -> std::result::Result<(), String> {
    match layout.header {
        HeaderType::UInt32 => {
            let v =
                u32::try_from(v).map_err(|_| format!("{v} bytes do not fit a UInt32 header"))?;
            match layout.order {
                ByteOrder::LittleEndian => out.extend_from_slice(&v.to_le_bytes()),
                ByteOrder::BigEndian => out.extend_from_slice(&v.to_be_bytes()),
            }
        }
        HeaderType::UInt64 => match layout.order {
            ByteOrder::LittleEndian => out.extend_from_slice(&v.to_le_bytes()),
            ByteOrder::BigEndian => out.extend_from_slice(&v.to_be_bytes()),
        },
    }
    Ok(())
}

/// Encodes `data` (already in the layout's byte order) with the layout's compressor, blocks
/// compressed in parallel.
pub(crate) fn encode<'a>(
    data: &'a [u8],
    layout: &Layout,
    level: u32,
) -> std::result::Result<Encoded<'a>, String> {
    let mut header = Vec::new();
    if layout.compressor == Compressor::None {
        put_header(&mut header, data.len() as u64, layout)?;
        return Ok(Encoded {
            header,
            data: vec![std::borrow::Cow::Borrowed(data)],
        });
    }
    let blocks: Vec<Vec<u8>> = data
        .par_chunks(BLOCK_SIZE)
        .map(|c| deflate(layout.compressor, c, level))
        .collect::<std::result::Result<_, _>>()?;
    put_header(&mut header, blocks.len() as u64, layout)?;
    put_header(&mut header, BLOCK_SIZE as u64, layout)?;
    put_header(&mut header, (data.len() % BLOCK_SIZE) as u64, layout)?;
    for b in &blocks {
        put_header(&mut header, b.len() as u64, layout)?;
    }
    Ok(Encoded {
        header,
        data: blocks.into_iter().map(std::borrow::Cow::Owned).collect(),
    })
}

/// Compresses one block into a scratch buffer and returns an exactly sized copy, so the blocks
/// of a large array hold no spare capacity (growing vectors left the zlib writer at 1.5x the mesh).
fn deflate(c: Compressor, src: &[u8], level: u32) -> std::result::Result<Vec<u8>, String> {
    let mut scratch = vec![0u8; src.len() + src.len() / 2 + 4096];
    let n = match c {
        Compressor::None => return Ok(src.to_vec()),
        Compressor::Zlib => {
            let mut z = flate2::Compress::new(flate2::Compression::new(level.min(9)), true);
            match z.compress(src, &mut scratch, flate2::FlushCompress::Finish) {
                Ok(flate2::Status::StreamEnd) => z.total_out() as usize,
                Ok(s) => return Err(format!("zlib: block did not fit its bound ({s:?})")),
                Err(e) => return Err(format!("zlib: {e}")),
            }
        }
        Compressor::Lz4 => {
            lz4_flex::block::compress_into(src, &mut scratch).map_err(|e| format!("lz4: {e}"))?
        }
        Compressor::Lzma => {
            let mut x =
                xz2::stream::Stream::new_easy_encoder(level.min(9), xz2::stream::Check::Crc32)
                    .map_err(|e| format!("lzma: {e}"))?;
            match x.process(src, &mut scratch, xz2::stream::Action::Finish) {
                Ok(xz2::stream::Status::StreamEnd) => x.total_out() as usize,
                Ok(s) => return Err(format!("lzma: block did not fit its bound ({s:?})")),
                Err(e) => return Err(format!("lzma: {e}")),
            }
        }
    };
    Ok(scratch[..n].to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layouts() -> Vec<Layout> {
        let mut v = Vec::new();
        for compressor in [
            Compressor::None,
            Compressor::Zlib,
            Compressor::Lz4,
            Compressor::Lzma,
        ] {
            for header in [HeaderType::UInt32, HeaderType::UInt64] {
                for order in [ByteOrder::LittleEndian, ByteOrder::BigEndian] {
                    v.push(Layout {
                        header,
                        order,
                        compressor,
                    });
                }
            }
        }
        v
    }

    #[test]
    fn encode_then_plan_and_fill_round_trips_every_layout() {
        for n in [
            0usize,
            1,
            7,
            BLOCK_SIZE - 1,
            BLOCK_SIZE,
            BLOCK_SIZE + 1,
            3 * BLOCK_SIZE + 5,
        ] {
            let data: Vec<u8> = (0..n).map(|i| (i * 7 % 251) as u8).collect();
            for layout in layouts() {
                let e = encode(&data, &layout, 2).unwrap();
                let mut bytes = e.header.clone();
                for d in &e.data {
                    bytes.extend_from_slice(d);
                }
                let region = Region::in_memory(&bytes, 0);
                let plan = plan(&region, &layout, "a").unwrap();
                assert_eq!(plan.total(), n as u64, "{layout:?}");
                let mut out = vec![0u8; n];
                fill(&region, &layout, &plan, &mut out, "a").unwrap();
                assert_eq!(out, data, "{layout:?} n={n}");
            }
        }
    }

    #[test]
    fn a_cut_short_block_is_an_error_not_a_panic() {
        let data = vec![5u8; 3 * BLOCK_SIZE];
        for layout in layouts() {
            let e = encode(&data, &layout, 2).unwrap();
            let mut bytes = e.header.clone();
            for d in &e.data {
                bytes.extend_from_slice(d);
            }
            for cut in [
                0,
                3,
                e.header.len() - 1,
                e.header.len() + 1,
                bytes.len() - 1,
            ] {
                let region = Region::in_memory(&bytes[..cut], 0);
                let r = plan(&region, &layout, "a");
                assert!(r.is_err(), "{layout:?} cut {cut}");
            }
        }
    }
}
