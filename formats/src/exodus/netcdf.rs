//! Classic NetCDF (CDF-1, CDF-2 64-bit offset, CDF-5) headers, and variables read from them.

use crate::{FormatError, Result};
use std::path::Path;

/// A NetCDF external type (`nc_type`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NcType {
    Byte,
    Char,
    Short,
    Int,
    Float,
    Double,
    UByte,
    UShort,
    UInt,
    Int64,
    UInt64,
}

impl NcType {
    fn from_code(code: u32, cdf5: bool) -> Option<NcType> {
        Some(match code {
            1 => NcType::Byte,
            2 => NcType::Char,
            3 => NcType::Short,
            4 => NcType::Int,
            5 => NcType::Float,
            6 => NcType::Double,
            // The unsigned and 64-bit types exist only in CDF-5.
            7 if cdf5 => NcType::UByte,
            8 if cdf5 => NcType::UShort,
            9 if cdf5 => NcType::UInt,
            10 if cdf5 => NcType::Int64,
            11 if cdf5 => NcType::UInt64,
            _ => return None,
        })
    }

    pub fn size(self) -> u64 {
        match self {
            NcType::Byte | NcType::Char | NcType::UByte => 1,
            NcType::Short | NcType::UShort => 2,
            NcType::Int | NcType::Float | NcType::UInt => 4,
            NcType::Double | NcType::Int64 | NcType::UInt64 => 8,
        }
    }
}

#[derive(Clone, Debug)]
pub struct Dim {
    pub name: String,
    /// 0 for the record (unlimited) dimension; its length is `numrecs`.
    pub len: u64,
}

#[derive(Clone, Debug)]
pub struct Attr {
    pub name: String,
    pub ty: NcType,
    /// The values, big-endian as stored.
    pub raw: Vec<u8>,
}

impl Attr {
    /// A text attribute's value, up to its first NUL.
    pub fn text(&self) -> Option<String> {
        (self.ty == NcType::Char).then(|| {
            let end = self
                .raw
                .iter()
                .position(|&b| b == 0)
                .unwrap_or(self.raw.len());
            String::from_utf8_lossy(&self.raw[..end]).into_owned()
        })
    }
}

#[derive(Clone, Debug)]
pub struct Var {
    pub name: String,
    pub dims: Vec<usize>,
    pub attrs: Vec<Attr>,
    pub ty: NcType,
    pub begin: u64,
    /// Where the variable's header entry is, for errors about it.
    pub header_at: u64,
}

/// A parsed header over the file's bytes.
pub struct File<'a> {
    pub bytes: &'a [u8],
    pub path: &'a Path,
    pub dims: Vec<Dim>,
    pub vars: Vec<Var>,
    pub numrecs: u64,
    /// Bytes from one record to the next, over all record variables.
    recsize: u64,
}

/// A variable's values converted to one Rust type.
pub trait FromNc: Copy {
    fn from_be(ty: NcType, b: &[u8]) -> Self;
}

fn be_f64(ty: NcType, b: &[u8]) -> f64 {
    let mut a = [0u8; 8];
    let n = ty.size() as usize;
    a[..n].copy_from_slice(&b[..n]);
    match ty {
        NcType::Byte => a[0] as i8 as f64,
        NcType::Char | NcType::UByte => a[0] as f64,
        NcType::Short => i16::from_be_bytes([a[0], a[1]]) as f64,
        NcType::UShort => u16::from_be_bytes([a[0], a[1]]) as f64,
        NcType::Int => i32::from_be_bytes([a[0], a[1], a[2], a[3]]) as f64,
        NcType::UInt => u32::from_be_bytes([a[0], a[1], a[2], a[3]]) as f64,
        NcType::Float => f32::from_be_bytes([a[0], a[1], a[2], a[3]]) as f64,
        NcType::Double => f64::from_be_bytes(a),
        NcType::Int64 => i64::from_be_bytes(a) as f64,
        NcType::UInt64 => u64::from_be_bytes(a) as f64,
    }
}

impl FromNc for f64 {
    fn from_be(ty: NcType, b: &[u8]) -> f64 {
        be_f64(ty, b)
    }
}

impl FromNc for i64 {
    fn from_be(ty: NcType, b: &[u8]) -> i64 {
        match ty {
            NcType::Int => i32::from_be_bytes([b[0], b[1], b[2], b[3]]) as i64,
            NcType::Int64 => i64::from_be_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]),
            NcType::UInt64 => {
                u64::from_be_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]) as i64
            }
            // Smaller integers are exact in f64; reals are truncated (and saturated).
            _ => be_f64(ty, b) as i64,
        }
    }
}

const STREAMING: u64 = 0xFFFF_FFFF;
const NC_DIMENSION: u32 = 0x0A;
const NC_VARIABLE: u32 = 0x0B;
const NC_ATTRIBUTE: u32 = 0x0C;

struct Header<'a> {
    bytes: &'a [u8],
    pos: usize,
    path: &'a Path,
    /// CDF-5: counts are 8 bytes.
    cdf5: bool,
    /// CDF-2 and CDF-5: offsets are 8 bytes.
    long_offsets: bool,
}

impl Header<'_> {
    fn err(&self, at: usize, msg: impl Into<String>) -> FormatError {
        FormatError::at_byte(at as u64, msg).with_file(self.path)
    }

    fn take(&mut self, n: u64, what: &str) -> Result<&[u8]> {
        let at = self.pos;
        let end = usize::try_from(n)
            .ok()
            .and_then(|n| at.checked_add(n))
            .filter(|&e| e <= self.bytes.len())
            .ok_or_else(|| {
                self.err(
                    at,
                    format!(
                        "the header ends inside {what} ({n} bytes wanted, {} left)",
                        self.bytes.len() - at.min(self.bytes.len())
                    ),
                )
            })?;
        self.pos = end;
        Ok(&self.bytes[at..end])
    }

    fn u32(&mut self, what: &str) -> Result<u32> {
        let b = self.take(4, what)?;
        Ok(u32::from_be_bytes([b[0], b[1], b[2], b[3]]))
    }

    fn u64(&mut self, what: &str) -> Result<u64> {
        let b = self.take(8, what)?;
        Ok(u64::from_be_bytes([
            b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7],
        ]))
    }

    /// A count: 4 bytes (CDF-1/2, must be non-negative) or 8 (CDF-5).
    fn count(&mut self, what: &str) -> Result<u64> {
        let at = self.pos;
        let n = if self.cdf5 {
            self.u64(what)?
        } else {
            self.u32(what)? as u64
        };
        if n > i64::MAX as u64 || (!self.cdf5 && n > i32::MAX as u64) {
            return Err(self.err(at, format!("{what} is negative")));
        }
        Ok(n)
    }

    /// A count of things each taking at least `min_bytes` of the header: larger than the rest of
    /// the file could hold is an error, so that no allocation follows a corrupt count.
    fn list_len(&mut self, what: &str, min_bytes: u64) -> Result<usize> {
        let at = self.pos;
        let n = self.count(what)?;
        let left = (self.bytes.len() - self.pos) as u64;
        if n.saturating_mul(min_bytes.max(1)) > left {
            return Err(self.err(
                at,
                format!("{what} is {n}, more than the {left} bytes left could hold"),
            ));
        }
        Ok(n as usize)
    }

    fn skip_pad(&mut self, n: u64, what: &str) -> Result<()> {
        let pad = (4 - n % 4) % 4;
        self.take(pad, what).map(|_| ())
    }

    fn name(&mut self, what: &str) -> Result<String> {
        let n = self.list_len(&format!("the length of {what}'s name"), 1)?;
        let raw = self.take(n as u64, what)?;
        let s = String::from_utf8_lossy(raw).into_owned();
        self.skip_pad(n as u64, what)?;
        Ok(s)
    }

    fn nc_type(&mut self, what: &str) -> Result<NcType> {
        let at = self.pos;
        let code = self.u32(what)?;
        NcType::from_code(code, self.cdf5)
            .ok_or_else(|| self.err(at, format!("{what} has an unknown nc_type {code}")))
    }

    /// The tag of a list, or `None` for ABSENT (two zeros).
    fn list_tag(&mut self, want: u32, what: &str) -> Result<Option<usize>> {
        let at = self.pos;
        let tag = self.u32(what)?;
        if tag == 0 {
            let n = self.count(what)?;
            if n != 0 {
                return Err(self.err(at, format!("{what}: an absent list with {n} entries")));
            }
            return Ok(None);
        }
        if tag != want {
            return Err(self.err(
                at,
                format!("expected {what} (tag {want:#x}) but found tag {tag:#x}"),
            ));
        }
        // Each entry takes at least 8 bytes (a name length and a value).
        Ok(Some(self.list_len(&format!("the number of {what}"), 8)?))
    }

    fn attrs(&mut self, owner: &str) -> Result<Vec<Attr>> {
        let what = format!("the attributes of {owner}");
        let n = self.list_tag(NC_ATTRIBUTE, &what)?.unwrap_or(0);
        let mut out = Vec::with_capacity(n);
        for _ in 0..n {
            let name = self.name(&format!("an attribute of {owner}"))?;
            let label = format!("attribute '{name}' of {owner}");
            let ty = self.nc_type(&label)?;
            let count = self.list_len(&format!("the length of {label}"), ty.size())? as u64;
            let raw = self.take(count * ty.size(), &label)?.to_vec();
            self.skip_pad(count * ty.size(), &label)?;
            out.push(Attr { name, ty, raw });
        }
        Ok(out)
    }
}

impl<'a> File<'a> {
    /// Parses the header of a classic NetCDF file.
    pub fn parse(bytes: &'a [u8], path: &'a Path) -> Result<File<'a>> {
        let (cdf5, long_offsets) = match bytes.get(..4) {
            Some(b"CDF\x01") => (false, false),
            Some(b"CDF\x02") => (false, true),
            Some(b"CDF\x05") => (true, true),
            _ => {
                return Err(FormatError::at_byte(
                    0,
                    "not a NetCDF file: neither classic (no CDF\\x01, CDF\\x02 or CDF\\x05 \
                         magic) nor NetCDF-4 (no HDF5 signature at byte 0, 512, 1024, ...)",
                )
                .with_file(path))
            }
        };
        let mut h = Header {
            bytes,
            pos: 4,
            path,
            cdf5,
            long_offsets,
        };
        let at = h.pos;
        let mut numrecs = if cdf5 {
            h.u64("numrecs")?
        } else {
            h.u32("numrecs")? as u64
        };
        let streaming = numrecs == STREAMING || (cdf5 && numrecs == u64::MAX);
        if !streaming && numrecs > i64::MAX as u64 {
            return Err(h.err(at, format!("numrecs {numrecs} is negative")));
        }
        let ndims = h.list_tag(NC_DIMENSION, "dimensions")?.unwrap_or(0);
        let mut dims = Vec::with_capacity(ndims);
        for _ in 0..ndims {
            let name = h.name("a dimension")?;
            let len = h.count(&format!("the length of dimension '{name}'"))?;
            dims.push(Dim { name, len });
        }
        // The global attributes (title, version, word sizes) are not needed to read the mesh.
        h.attrs("the file")?;
        let nvars = h.list_tag(NC_VARIABLE, "variables")?.unwrap_or(0);
        let mut vars = Vec::with_capacity(nvars);
        for _ in 0..nvars {
            let header_at = h.pos as u64;
            let name = h.name("a variable")?;
            let nd = h.list_len(&format!("the rank of variable '{name}'"), 4)?;
            let mut vdims = Vec::with_capacity(nd);
            for k in 0..nd {
                let at = h.pos;
                let id = h.count(&format!("dimension {k} of variable '{name}'"))?;
                let id = usize::try_from(id)
                    .ok()
                    .filter(|&i| i < dims.len())
                    .ok_or_else(|| {
                        h.err(
                            at,
                            format!(
                                "variable '{name}' names dimension id {id}, but the file has {}",
                                dims.len()
                            ),
                        )
                    })?;
                if k > 0 && dims[id].len == 0 {
                    return Err(h.err(
                        at,
                        format!("variable '{name}' has the record dimension other than first"),
                    ));
                }
                vdims.push(id);
            }
            let vattrs = h.attrs(&format!("variable '{name}'"))?;
            let ty = h.nc_type(&format!("variable '{name}'"))?;
            // vsize is recomputed from the shape: writers store 2^32-1 for large variables.
            if h.cdf5 {
                h.u64("vsize")?;
            } else {
                h.u32("vsize")?;
            }
            let begin = if h.long_offsets {
                h.u64(&format!("the offset of variable '{name}'"))?
            } else {
                h.u32(&format!("the offset of variable '{name}'"))? as u64
            };
            vars.push(Var {
                name,
                dims: vdims,
                attrs: vattrs,
                ty,
                begin,
                header_at,
            });
        }
        let mut f = File {
            bytes,
            path,
            dims,
            vars,
            numrecs: 0,
            recsize: 0,
        };
        let rec_vars: Vec<usize> = (0..f.vars.len()).filter(|&i| f.is_record(i)).collect();
        let mut recsize: u64 = 0;
        for &i in &rec_vars {
            let size = f.slab_bytes(i)?;
            // A lone record variable is not padded between records.
            let padded = if rec_vars.len() == 1 {
                size
            } else {
                size.div_ceil(4).saturating_mul(4)
            };
            recsize = recsize.saturating_add(padded);
        }
        f.recsize = recsize;
        if streaming {
            // Writers that stream leave numrecs unknown: the records that fit the file count.
            let first = rec_vars.iter().map(|&i| f.vars[i].begin).min().unwrap_or(0);
            numrecs = (bytes.len() as u64)
                .saturating_sub(first)
                .checked_div(recsize)
                .unwrap_or(0);
        }
        // Records that the file cannot hold mean a corrupt numrecs; refusing it here keeps every
        // loop over the steps bounded by the file's size.
        let first = rec_vars.iter().map(|&i| f.vars[i].begin).min().unwrap_or(0);
        let fits = match recsize {
            0 => numrecs <= bytes.len() as u64,
            r => numrecs
                .checked_mul(r)
                .and_then(|n| n.checked_add(first))
                .is_some_and(|end| end <= bytes.len() as u64),
        };
        if !fits {
            return Err(FormatError::at_byte(
                4,
                format!(
                    "numrecs {numrecs} records of {recsize} bytes from byte {first} run past the end of the file ({} bytes)",
                    bytes.len()
                ),
            )
            .with_file(path));
        }
        f.numrecs = numrecs;
        Ok(f)
    }

    pub fn is_record(&self, var: usize) -> bool {
        self.vars[var]
            .dims
            .first()
            .is_some_and(|&d| self.dims[d].len == 0)
    }

    pub fn var(&self, name: &str) -> Option<usize> {
        self.vars.iter().position(|v| v.name == name)
    }

    pub fn dim(&self, name: &str) -> Option<u64> {
        self.dims.iter().find(|d| d.name == name).map(
            |d| {
                if d.len == 0 {
                    self.numrecs
                } else {
                    d.len
                }
            },
        )
    }

    pub fn err_var(&self, var: usize, msg: impl Into<String>) -> FormatError {
        let v = &self.vars[var];
        FormatError::at_byte(
            v.header_at,
            format!("variable '{}': {}", v.name, msg.into()),
        )
        .with_file(self.path)
    }

    /// The variable's shape, the record dimension as `numrecs`.
    pub fn shape(&self, var: usize) -> Vec<u64> {
        self.vars[var]
            .dims
            .iter()
            .map(|&d| match self.dims[d].len {
                0 => self.numrecs,
                n => n,
            })
            .collect()
    }

    /// Values in one record (or in the whole of a fixed variable).
    fn slab_values(&self, var: usize) -> Result<u64> {
        let v = &self.vars[var];
        let skip = usize::from(self.is_record(var));
        v.dims[skip..].iter().try_fold(1u64, |acc, &d| {
            acc.checked_mul(self.dims[d].len)
                .ok_or_else(|| self.err_var(var, "the shape overflows"))
        })
    }

    fn slab_bytes(&self, var: usize) -> Result<u64> {
        self.slab_values(var)?
            .checked_mul(self.vars[var].ty.size())
            .ok_or_else(|| self.err_var(var, "the size overflows"))
    }

    /// Record `rec`'s values of a record variable, or all values of a fixed one (`rec` 0).
    fn slab(&self, var: usize, rec: u64) -> Result<&'a [u8]> {
        let v = &self.vars[var];
        let len = self.slab_bytes(var)?;
        let start = if self.is_record(var) {
            if rec >= self.numrecs {
                return Err(self.err_var(
                    var,
                    format!("there is no record {rec}: the file has {}", self.numrecs),
                ));
            }
            rec.checked_mul(self.recsize)
                .and_then(|o| o.checked_add(v.begin))
        } else {
            Some(v.begin)
        };
        let range = start
            .and_then(|s| Some((s, s.checked_add(len)?)))
            .filter(|&(_, e)| e <= self.bytes.len() as u64);
        let Some((s, e)) = range else {
            return Err(self.err_var(
                var,
                format!(
                    "its data (offset {}, record {rec}, {len} bytes) runs past the end of the file ({} bytes)",
                    v.begin,
                    self.bytes.len()
                ),
            ));
        };
        Ok(&self.bytes[s as usize..e as usize])
    }

    /// Record `rec` of a record variable, or a whole fixed variable, converted to `T`.
    pub fn values<T: FromNc>(&self, var: usize, rec: u64) -> Result<Vec<T>> {
        let ty = self.vars[var].ty;
        if ty == NcType::Char {
            return Err(self.err_var(var, "holds text where numbers are expected"));
        }
        let raw = self.slab(var, rec)?;
        Ok(raw
            .chunks_exact(ty.size() as usize)
            .map(|b| T::from_be(ty, b))
            .collect())
    }

    /// A fixed 2-D char variable as strings, one per row, each up to its first NUL.
    pub fn strings(&self, var: usize) -> Result<Vec<String>> {
        let v = &self.vars[var];
        if v.ty != NcType::Char || v.dims.len() != 2 || self.is_record(var) {
            return Err(self.err_var(var, "is not a 2-D array of text"));
        }
        let raw = self.slab(var, 0)?;
        let width = self.dims[v.dims[1]].len as usize;
        if width == 0 {
            return Err(self.err_var(var, "holds strings of length 0"));
        }
        Ok(raw.chunks_exact(width).map(text_row).collect())
    }
}

/// One row of a char array (or one NC_STRING) as a name: up to its first NUL, trailing blanks
/// dropped.
pub fn text_row(row: &[u8]) -> String {
    let end = row.iter().position(|&b| b == 0).unwrap_or(row.len());
    String::from_utf8_lossy(&row[..end]).trim_end().to_string()
}

/// What the Exodus reader asks of a NetCDF file: the classic [`File`] and the NetCDF-4
/// [`super::nc4::Nc4`] answer alike, so that both read to the same grid. Variables are named by
/// their index.
pub trait Source {
    /// The file's name, for errors.
    fn path(&self) -> &Path;
    /// The number of records (time steps): the record (unlimited) dimension's length.
    fn numrecs(&self) -> u64;
    /// A dimension's length (the record dimension's: [`Source::numrecs`]).
    fn dim(&self, name: &str) -> Option<u64>;
    fn num_dims(&self) -> usize;
    fn var(&self, name: &str) -> Option<usize>;
    fn num_vars(&self) -> usize;
    /// The variable's type; `None` for a type classic NetCDF lacks (NC_STRING, user-defined).
    fn ty(&self, var: usize) -> Option<NcType>;
    /// Whether the variable's first dimension is the record dimension.
    fn is_record(&self, var: usize) -> bool;
    /// The variable's shape, the record dimension as `numrecs`.
    fn shape(&self, var: usize) -> Vec<u64>;
    /// A text attribute of the variable.
    fn attr_text(&self, var: usize, name: &str) -> Option<String>;
    /// Record `rec` of a record variable, or a whole fixed variable (`rec` 0), converted to `T`
    /// as [`FromNc`] converts the classic file's values.
    fn values<T: FromNc>(&self, var: usize, rec: u64) -> Result<Vec<T>>;
    /// A fixed 2-D char variable (or 1-D NC_STRING one) as strings, one per row (see
    /// [`text_row`]).
    fn strings(&self, var: usize) -> Result<Vec<String>>;
    /// An error about the variable, naming it and the file.
    fn err_var(&self, var: usize, msg: impl Into<String>) -> FormatError;
}

impl Source for File<'_> {
    fn path(&self) -> &Path {
        self.path
    }
    fn numrecs(&self) -> u64 {
        self.numrecs
    }
    fn dim(&self, name: &str) -> Option<u64> {
        File::dim(self, name)
    }
    fn num_dims(&self) -> usize {
        self.dims.len()
    }
    fn var(&self, name: &str) -> Option<usize> {
        File::var(self, name)
    }
    fn num_vars(&self) -> usize {
        self.vars.len()
    }
    fn ty(&self, var: usize) -> Option<NcType> {
        Some(self.vars[var].ty)
    }
    fn is_record(&self, var: usize) -> bool {
        File::is_record(self, var)
    }
    fn shape(&self, var: usize) -> Vec<u64> {
        File::shape(self, var)
    }
    fn attr_text(&self, var: usize, name: &str) -> Option<String> {
        self.vars[var]
            .attrs
            .iter()
            .find(|a| a.name == name)
            .and_then(Attr::text)
    }
    fn values<T: FromNc>(&self, var: usize, rec: u64) -> Result<Vec<T>> {
        File::values(self, var, rec)
    }
    fn strings(&self, var: usize) -> Result<Vec<String>> {
        File::strings(self, var)
    }
    fn err_var(&self, var: usize, msg: impl Into<String>) -> FormatError {
        File::err_var(self, var, msg)
    }
}
