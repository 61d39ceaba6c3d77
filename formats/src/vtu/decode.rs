//! One array's values from its XML element: ascii text, inline base64, or the appended block,
//! into a typed vector allocated only after its declared size was checked against what the mesh
//! needs and the bytes present.

use super::base64::Decoder;
use super::block::{self, Plan};
use super::source::{Blob, Region, Src};
use super::xml::{ArrayXml, DataFormat, ElemType};
use super::{ByteOrder, Layout};
use crate::{ArrayData, FormatError, Result, ScalarType};
use rayon::prelude::*;

/// The appended block of a file.
pub(crate) struct Appended<'a> {
    pub blob: &'a dyn Blob,
    /// File offset of the first byte after the `_` marker.
    pub start: u64,
    pub raw: bool,
    /// Every array offset, sorted: an appended base64 array ends where the next one starts.
    pub offsets: Vec<u64>,
}

/// What every array of one file is read with.
pub(crate) struct Input<'a> {
    pub layout: Layout,
    pub appended: Option<Appended<'a>>,
}

fn err_at(pos: u64, a: &ArrayXml, msg: impl std::fmt::Display) -> FormatError {
    FormatError::at_byte(pos, format!("array '{}': {msg}", a.name))
}

/// Finds the array's binary bytes (decoding base64 where needed), reads its header, and hands both
/// to `f`.
fn with_binary<R>(
    inp: &Input,
    a: &ArrayXml,
    f: impl FnOnce(&Region, &Plan) -> Result<R>,
) -> Result<R> {
    let decoded: Vec<u8>;
    let region = match a.format {
        DataFormat::Ascii => return Err(err_at(a.tag_pos, a, "is ascii, not binary")),
        DataFormat::Binary => {
            decoded = Decoder::new(&a.text)
                .read_to_end()
                .map_err(|e| err_at(a.text_pos + e.at as u64, a, e.message))?;
            Region::in_memory(&decoded, a.text_pos)
        }
        DataFormat::Appended => {
            let app = inp.appended.as_ref().ok_or_else(|| {
                err_at(
                    a.tag_pos,
                    a,
                    "format=\"appended\" but the file has no <AppendedData>",
                )
            })?;
            let off = a.offset.unwrap_or(0);
            let total = app.blob.len() - app.start;
            if off >= total {
                return Err(err_at(
                    a.tag_pos,
                    a,
                    format!("offset {off} is past the end of the appended data ({total} bytes)"),
                ));
            }
            let start = app.start + off;
            if app.raw {
                Region {
                    blob: Src::Blob(app.blob),
                    start,
                    end: app.blob.len(),
                    file_pos: start,
                }
            } else {
                let end = app
                    .offsets
                    .iter()
                    .find(|&&o| o > off)
                    .map_or(app.blob.len(), |&o| app.start + o);
                let whole = Region {
                    blob: Src::Blob(app.blob),
                    start,
                    end,
                    file_pos: start,
                };
                let text = whole
                    .bytes(0, (end - start) as usize)
                    .map_err(|e| err_at(start, a, e))?;
                let text = match text.iter().position(|&b| b == b'<') {
                    Some(p) => &text[..p],
                    None => &text[..],
                };
                decoded = Decoder::new(text)
                    .read_to_end()
                    .map_err(|e| err_at(start + e.at as u64, a, e.message))?;
                Region::in_memory(&decoded, start)
            }
        }
    };
    let plan = block::plan(&region, &inp.layout, &a.name)?;
    f(&region, &plan)
}

/// Number of values the data holds, checked against what the mesh needs (`need`, in values);
/// when that is unknown the compression ratio cap of `block::plan` bounds it.
fn checked_count(
    a: &ArrayXml,
    region: &Region,
    plan: &Plan,
    size: usize,
    need: Option<usize>,
) -> Result<usize> {
    let total = plan.total();
    if let Some(n) = need {
        let want = (n as u64).checked_mul(size as u64);
        if want != Some(total) {
            return Err(err_at(
                region.file_pos,
                a,
                format!(
                    "declares {total} bytes of data, but {n} values of {size} bytes are needed"
                ),
            ));
        }
        return Ok(n);
    }
    if total % size as u64 != 0 {
        return Err(err_at(
            region.file_pos,
            a,
            format!("{total} bytes is not a whole number of {size}-byte values"),
        ));
    }
    usize::try_from(total / size as u64)
        .map_err(|_| err_at(region.file_pos, a, "too large for this machine"))
}

/// The raw bytes of a numeric vector, for filling in place.
fn bytes_mut(d: &mut ArrayData) -> &mut [u8] {
    crate::with_numeric!(d, v => bytemuck::cast_slice_mut(v.as_mut_slice()), _s => &mut [])
}

/// A zeroed vector of `n` values: calloc, so the pages are fresh and written once, by the fill.
/// (madvise(MADV_HUGEPAGE) was tried: it halves repeated reads but the first read in a process
/// took 3x longer, and a command reads once.)
fn zero_vec<T: Clone + Default>(n: usize) -> Vec<T> {
    vec![T::default(); n]
}

fn zeroed(ty: ScalarType, n: usize) -> ArrayData {
    match ty {
        ScalarType::Int8 => ArrayData::Int8(zero_vec(n)),
        ScalarType::UInt8 => ArrayData::UInt8(zero_vec(n)),
        ScalarType::Int16 => ArrayData::Int16(zero_vec(n)),
        ScalarType::UInt16 => ArrayData::UInt16(zero_vec(n)),
        ScalarType::Int32 => ArrayData::Int32(zero_vec(n)),
        ScalarType::UInt32 => ArrayData::UInt32(zero_vec(n)),
        ScalarType::Int64 => ArrayData::Int64(zero_vec(n)),
        ScalarType::UInt64 => ArrayData::UInt64(zero_vec(n)),
        ScalarType::Float32 => ArrayData::Float32(zero_vec(n)),
        ScalarType::Float64 => ArrayData::Float64(zero_vec(n)),
    }
}

/// Reverses the byte order of every `size`-byte value in `bytes` (aligned: they come from a typed
/// vector).
pub(crate) fn swap_in_place(bytes: &mut [u8], size: usize) {
    const CH: usize = 1 << 16;
    match size {
        2 => bytemuck::cast_slice_mut::<u8, u16>(bytes)
            .par_chunks_mut(CH)
            .for_each(|c| c.iter_mut().for_each(|x| *x = x.swap_bytes())),
        4 => bytemuck::cast_slice_mut::<u8, u32>(bytes)
            .par_chunks_mut(CH)
            .for_each(|c| c.iter_mut().for_each(|x| *x = x.swap_bytes())),
        8 => bytemuck::cast_slice_mut::<u8, u64>(bytes)
            .par_chunks_mut(CH)
            .for_each(|c| c.iter_mut().for_each(|x| *x = x.swap_bytes())),
        _ => {}
    }
}

fn fill_typed(
    inp: &Input,
    a: &ArrayXml,
    region: &Region,
    plan: &Plan,
    dst: &mut [u8],
    size: usize,
) -> Result<()> {
    block::fill(region, &inp.layout, plan, dst, &a.name)?;
    if inp.layout.order != ByteOrder::native() {
        swap_in_place(dst, size);
    }
    Ok(())
}

/// A numeric array of exactly `need` values (when known).
pub(crate) fn numeric(inp: &Input, a: &ArrayXml, need: Option<usize>) -> Result<ArrayData> {
    let ty = match a.ty {
        ElemType::Num(ty) => ty,
        ElemType::String => {
            return Err(err_at(
                a.tag_pos,
                a,
                "is a String array where numbers are needed",
            ))
        }
        ElemType::Bit => ScalarType::UInt8,
    };
    if a.ty == ElemType::Bit {
        return bits(inp, a, need).map(ArrayData::UInt8);
    }
    if a.format == DataFormat::Ascii {
        return ascii(a, ty, need);
    }
    with_binary(inp, a, |region, plan| {
        let n = checked_count(a, region, plan, ty.size(), need)?;
        let mut data = zeroed(ty, n);
        fill_typed(inp, a, region, plan, bytes_mut(&mut data), ty.size())?;
        Ok(data)
    })
}

/// Point ids, offsets or face streams as i64: `lead` zeros, then exactly `n` values. Int64 data
/// is read in place; other integer types are converted, refusing values that do not fit.
pub(crate) fn ids(inp: &Input, a: &ArrayXml, n: usize, lead: usize) -> Result<Vec<i64>> {
    let total = n
        .checked_add(lead)
        .ok_or_else(|| err_at(a.tag_pos, a, "too large"))?;
    if a.ty == ElemType::Num(ScalarType::Int64) && a.format != DataFormat::Ascii {
        return with_binary(inp, a, |region, plan| {
            checked_count(a, region, plan, 8, Some(n))?;
            let mut v: Vec<i64> = zero_vec(total);
            fill_typed(
                inp,
                a,
                region,
                plan,
                bytemuck::cast_slice_mut(&mut v[lead..]),
                8,
            )?;
            Ok(v)
        });
    }
    let data = numeric(inp, a, Some(n))?;
    let mut v = Vec::with_capacity(total);
    v.resize(lead, 0);
    let bad = |i: usize| err_at(a.tag_pos, a, format!("value {i} is not an integer id"));
    match data {
        ArrayData::Float32(_) | ArrayData::Float64(_) | ArrayData::String(_) => {
            return Err(err_at(
                a.tag_pos,
                a,
                format!("has type {}, expected an integer type", data.type_name()),
            ))
        }
        ArrayData::UInt64(d) => {
            for (i, x) in d.into_iter().enumerate() {
                v.push(i64::try_from(x).map_err(|_| bad(i))?);
            }
        }
        ArrayData::Int64(d) => v.extend(d),
        ArrayData::Int32(d) => v.extend(d.into_iter().map(i64::from)),
        ArrayData::UInt32(d) => v.extend(d.into_iter().map(i64::from)),
        ArrayData::Int16(d) => v.extend(d.into_iter().map(i64::from)),
        ArrayData::UInt16(d) => v.extend(d.into_iter().map(i64::from)),
        ArrayData::Int8(d) => v.extend(d.into_iter().map(i64::from)),
        ArrayData::UInt8(d) => v.extend(d.into_iter().map(i64::from)),
    }
    Ok(v)
}

/// A Bit array (vtkBitArray) as one 0/1 byte per value. Ascii data lists the values; binary data
/// packs them eight to a byte, most significant bit first, in `ceil(n / 8)` bytes, so the value
/// count cannot be inferred from the data: it must be known (`NumberOfTuples` or the mesh).
pub(crate) fn bits(inp: &Input, a: &ArrayXml, need: Option<usize>) -> Result<Vec<u8>> {
    if a.format == DataFormat::Ascii {
        let ArrayData::UInt8(v) = ascii(a, ScalarType::UInt8, need)? else {
            return Err(err_at(a.text_pos, a, "ascii bits did not parse as bytes"));
        };
        if let Some(i) = v.iter().position(|&b| b > 1) {
            return Err(err_at(
                a.text_pos,
                a,
                format!("value {i} ({}) of a Bit array is not 0 or 1", v[i]),
            ));
        }
        return Ok(v);
    }
    let Some(n) = need else {
        return Err(err_at(
            a.tag_pos,
            a,
            "a binary Bit array needs NumberOfTuples (its bytes do not say how many bits are used)",
        ));
    };
    let packed = with_binary(inp, a, |region, plan| {
        let bytes = n.div_ceil(8);
        if plan.total() != bytes as u64 {
            return Err(err_at(
                region.file_pos,
                a,
                format!(
                    "declares {} bytes of data, but {n} bits need {bytes} bytes",
                    plan.total()
                ),
            ));
        }
        let mut v = vec![0u8; bytes];
        block::fill(region, &inp.layout, plan, &mut v, &a.name)?;
        Ok(v)
    })?;
    Ok((0..n).map(|i| (packed[i / 8] >> (7 - i % 8)) & 1).collect())
}

/// A String array: NUL-terminated UTF-8 strings (binary), or their byte values (ascii).
pub(crate) fn strings(inp: &Input, a: &ArrayXml, need: Option<usize>) -> Result<Vec<String>> {
    let bytes: Vec<u8> = if a.format == DataFormat::Ascii {
        // VTK writes each byte as a (signed) char: UTF-8 lead bytes come out negative.
        match ascii(a, ScalarType::Int16, None)? {
            ArrayData::Int16(v) => {
                let mut out = Vec::with_capacity(v.len());
                for (i, x) in v.into_iter().enumerate() {
                    if !(-128..=255).contains(&x) {
                        return Err(err_at(
                            a.text_pos,
                            a,
                            format!("value {i} ({x}) is not a byte"),
                        ));
                    }
                    out.push(x as u8);
                }
                out
            }
            _ => Vec::new(),
        }
    } else {
        with_binary(inp, a, |region, plan| {
            let n = checked_count(a, region, plan, 1, None)?;
            let mut v = vec![0u8; n];
            block::fill(region, &inp.layout, plan, &mut v, &a.name)?;
            Ok(v)
        })?
    };
    let mut out = Vec::with_capacity(need.unwrap_or(0).min(bytes.len()));
    let mut rest = &bytes[..];
    while let Some(p) = rest.iter().position(|&b| b == 0) {
        let s = std::str::from_utf8(&rest[..p])
            .map_err(|_| err_at(a.tag_pos, a, format!("string {} is not UTF-8", out.len())))?;
        out.push(s.to_string());
        rest = &rest[p + 1..];
    }
    if !rest.is_empty() {
        return Err(err_at(
            a.tag_pos,
            a,
            "the last string has no NUL terminator",
        ));
    }
    if let Some(n) = need {
        if out.len() != n {
            return Err(err_at(
                a.tag_pos,
                a,
                format!("holds {} strings, expected {n}", out.len()),
            ));
        }
    }
    Ok(out)
}

/// Parses whitespace-separated values. Floats accept VTK's `NaN`, `Infinity` and `-Infinity`.
fn ascii(a: &ArrayXml, ty: ScalarType, need: Option<usize>) -> Result<ArrayData> {
    let text = std::str::from_utf8(&a.text).map_err(|e| {
        err_at(
            a.text_pos + e.valid_up_to() as u64,
            a,
            "ascii data is not text",
        )
    })?;
    // Never trust a declared count for an allocation: at most one value per two bytes of text.
    let cap = need.unwrap_or(0).min(text.len() / 2 + 1);
    fn parse<T: std::str::FromStr>(
        a: &ArrayXml,
        text: &str,
        cap: usize,
        ty: ScalarType,
    ) -> Result<Vec<T>> {
        let mut v = Vec::with_capacity(cap);
        for tok in text.split_ascii_whitespace() {
            match tok.parse::<T>() {
                Ok(x) => v.push(x),
                Err(_) => {
                    let at = tok.as_ptr() as usize - text.as_ptr() as usize;
                    return Err(err_at(
                        a.text_pos + at as u64,
                        a,
                        format!(
                            "'{}' is not a valid {ty} value",
                            tok.chars().take(40).collect::<String>()
                        ),
                    ));
                }
            }
        }
        Ok(v)
    }
    let data = match ty {
        ScalarType::Int8 => ArrayData::Int8(parse(a, text, cap, ty)?),
        ScalarType::UInt8 => ArrayData::UInt8(parse(a, text, cap, ty)?),
        ScalarType::Int16 => ArrayData::Int16(parse(a, text, cap, ty)?),
        ScalarType::UInt16 => ArrayData::UInt16(parse(a, text, cap, ty)?),
        ScalarType::Int32 => ArrayData::Int32(parse(a, text, cap, ty)?),
        ScalarType::UInt32 => ArrayData::UInt32(parse(a, text, cap, ty)?),
        ScalarType::Int64 => ArrayData::Int64(parse(a, text, cap, ty)?),
        ScalarType::UInt64 => ArrayData::UInt64(parse(a, text, cap, ty)?),
        ScalarType::Float32 => ArrayData::Float32(parse(a, text, cap, ty)?),
        ScalarType::Float64 => ArrayData::Float64(parse(a, text, cap, ty)?),
    };
    if let Some(n) = need {
        if data.len() != n {
            // An element with no text has no text position: name its tag.
            let pos = if a.text.is_empty() {
                a.tag_pos
            } else {
                a.text_pos
            };
            return Err(err_at(
                pos,
                a,
                format!("has {} ascii values, expected {n}", data.len()),
            ));
        }
    }
    Ok(data)
}
