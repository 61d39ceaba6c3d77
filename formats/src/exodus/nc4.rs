//! NetCDF-4 (HDF5) files read through the pure-Rust `netcdf-reader` crate, answering the
//! Exodus reader's questions ([`Source`]) exactly as the classic [`super::netcdf::File`] does.

use super::netcdf::{text_row, FromNc, NcType, Source};
use crate::error::guard_panics;
use crate::{FormatError, Result};
use netcdf_reader::{NcFile, NcOpenOptions, NcReadable, NcSliceInfo, NcSliceInfoElem};
use std::path::Path;

/// The HDF5 format signature.
const SIGNATURE: &[u8; 8] = b"\x89HDF\r\n\x1a\n";

/// Deflate expands at most 1032-fold; a read decoding more than this many times the file's size
/// comes from a corrupt header, and is refused before it allocates.
const MAX_EXPANSION: u64 = 1100;

/// Whether `bytes` are an HDF5 file: the signature at byte 0, or after a user block of 512,
/// 1024, 2048, ... bytes.
pub fn is_hdf5(bytes: &[u8]) -> bool {
    std::iter::successors(Some(0usize), |&o| {
        if o == 0 {
            Some(512)
        } else {
            o.checked_mul(2)
        }
    })
    .take_while(|&o| o.saturating_add(SIGNATURE.len()) <= bytes.len())
    .any(|o| &bytes[o..o + SIGNATURE.len()] == SIGNATURE)
}

struct Var {
    name: String,
    /// `None` for NC_STRING and the user-defined types.
    ty: Option<NcType>,
    string: bool,
    record: bool,
    shape: Vec<u64>,
    attrs: Vec<(String, Option<String>)>,
}

/// A NetCDF-4 file's root group.
pub struct Nc4<'a> {
    file: NcFile,
    path: &'a Path,
    dims: Vec<(String, u64)>,
    vars: Vec<Var>,
    numrecs: u64,
    /// The most bytes one read may decode.
    max_read: u64,
}

fn ty_of(t: &netcdf_reader::NcType) -> Option<NcType> {
    use netcdf_reader::NcType as T;
    Some(match t {
        T::Byte => NcType::Byte,
        T::Char => NcType::Char,
        T::Short => NcType::Short,
        T::Int => NcType::Int,
        T::Float => NcType::Float,
        T::Double => NcType::Double,
        T::UByte => NcType::UByte,
        T::UShort => NcType::UShort,
        T::UInt => NcType::UInt,
        T::Int64 => NcType::Int64,
        T::UInt64 => NcType::UInt64,
        _ => return None,
    })
}

/// Values whose big-endian bytes [`FromNc`] converts, as it does the classic file's.
trait BeBytes: NcReadable + Copy {
    fn be(self, out: &mut [u8; 8]);
}

macro_rules! be_bytes {
    ($($t:ty),*) => {$(
        impl BeBytes for $t {
            fn be(self, out: &mut [u8; 8]) {
                let b = self.to_be_bytes();
                out[..b.len()].copy_from_slice(&b);
            }
        }
    )*};
}
be_bytes!(i8, u8, i16, u16, i32, u32, i64, u64, f32, f64);

impl<'a> Nc4<'a> {
    /// Opens the HDF5 file in `bytes` (see [`is_hdf5`]) and reads its root group's dimensions
    /// and variables.
    pub fn open(bytes: &[u8], path: &'a Path) -> Result<Nc4<'a>> {
        let max_read = (bytes.len() as u64)
            .saturating_mul(MAX_EXPANSION)
            .max(1 << 20);
        let options = NcOpenOptions {
            max_read_bytes: usize::try_from(max_read).unwrap_or(usize::MAX),
            ..NcOpenOptions::default()
        };
        let (file, dims, vars) = guarded(path, || {
            let file = NcFile::from_bytes_with_options(bytes, options)?;
            let dims = file
                .dimensions()?
                .iter()
                .map(|d| (d.name.clone(), d.size, d.is_unlimited))
                .collect::<Vec<_>>();
            let vars = file
                .variables()?
                .iter()
                .map(|v| Var {
                    name: v.name.clone(),
                    ty: ty_of(&v.dtype),
                    string: matches!(v.dtype, netcdf_reader::NcType::String),
                    record: v.dimensions.first().is_some_and(|d| d.is_unlimited),
                    shape: v.shape(),
                    attrs: v
                        .attributes
                        .iter()
                        .map(|a| (a.name.clone(), a.value.as_string()))
                        .collect(),
                })
                .collect::<Vec<_>>();
            Ok((file, dims, vars))
        })?;
        // Exodus has one unlimited dimension, time_step; the records are its length.
        let numrecs = dims.iter().filter(|d| d.2).map(|d| d.1).max().unwrap_or(0);
        // Each record read decodes at least a value: more records than reads may decode is a
        // corrupt length, refused here to keep every loop over the steps bounded.
        if numrecs > max_read / 8 {
            return Err(FormatError::whole(format!(
                "NetCDF-4: the unlimited dimension's length {numrecs} is more than a file of {} bytes could hold",
                bytes.len()
            ))
            .with_file(path));
        }
        Ok(Nc4 {
            file,
            path,
            dims: dims.into_iter().map(|(n, len, _)| (n, len)).collect(),
            vars,
            numrecs,
            max_read,
        })
    }

    /// The selection of record `rec` (or of all of a fixed variable), and how many values it
    /// holds.
    fn selection(&self, var: usize, rec: u64) -> Result<(NcSliceInfo, u64)> {
        let v = &self.vars[var];
        let mut sel = NcSliceInfo::all(v.shape.len());
        let dims = if v.record {
            if rec >= self.numrecs {
                return Err(self.err_var(
                    var,
                    format!("there is no record {rec}: the file has {}", self.numrecs),
                ));
            }
            sel.selections[0] = NcSliceInfoElem::Index(rec);
            &v.shape[1..]
        } else {
            &v.shape[..]
        };
        let n = dims
            .iter()
            .try_fold(1u64, |acc, &d| acc.checked_mul(d))
            .filter(|&n| n.saturating_mul(8) <= self.max_read)
            .ok_or_else(|| {
                self.err_var(
                    var,
                    format!(
                        "its shape {:?} is more than a file of this size could hold",
                        v.shape
                    ),
                )
            })?;
        Ok((sel, n))
    }

    fn read<S: BeBytes, T: FromNc>(&self, var: usize, rec: u64, ty: NcType) -> Result<Vec<T>> {
        let (sel, n) = self.selection(var, rec)?;
        let name = &self.vars[var].name;
        let a = guarded(self.path, || self.file.read_variable_slice::<S>(name, &sel))
            .map_err(|e| self.err_var(var, e.message))?;
        if a.len() as u64 != n {
            return Err(self.err_var(var, format!("{} values read, {n} expected", a.len())));
        }
        let mut b = [0u8; 8];
        Ok(a.iter()
            .map(|&x| {
                x.be(&mut b);
                T::from_be(ty, &b)
            })
            .collect())
    }
}

/// Runs a call into the `netcdf-reader` crate, its errors and panics made errors naming the
/// file. The crate returns errors for corrupt files: every truncation and every flipped byte of
/// two fixtures gave an error or the same grid's shape, no panic (tests.rs). It still parses
/// HDF5's structures deep down from untrusted bytes, so [`guard_panics`] stays as a guard; a
/// panic's message would also go to stderr through the panic hook.
fn guarded<R>(
    path: &Path,
    f: impl FnOnce() -> std::result::Result<R, netcdf_reader::Error>,
) -> Result<R> {
    guard_panics(f).map_err(|m| FormatError::whole(format!("NetCDF-4 (HDF5): {m}")).with_file(path))
}

impl Source for Nc4<'_> {
    fn path(&self) -> &Path {
        self.path
    }
    fn numrecs(&self) -> u64 {
        self.numrecs
    }
    fn dim(&self, name: &str) -> Option<u64> {
        self.dims.iter().find(|d| d.0 == name).map(|d| d.1)
    }
    fn num_dims(&self) -> usize {
        self.dims.len()
    }
    fn var(&self, name: &str) -> Option<usize> {
        self.vars.iter().position(|v| v.name == name)
    }
    fn num_vars(&self) -> usize {
        self.vars.len()
    }
    fn ty(&self, var: usize) -> Option<NcType> {
        self.vars[var].ty
    }
    fn is_record(&self, var: usize) -> bool {
        self.vars[var].record
    }
    fn shape(&self, var: usize) -> Vec<u64> {
        let v = &self.vars[var];
        let mut s = v.shape.clone();
        if v.record {
            s[0] = self.numrecs;
        }
        s
    }
    fn attr_text(&self, var: usize, name: &str) -> Option<String> {
        self.vars[var]
            .attrs
            .iter()
            .find(|a| a.0 == name)
            .and_then(|a| a.1.clone())
    }
    fn values<T: FromNc>(&self, var: usize, rec: u64) -> Result<Vec<T>> {
        // NC_STRING (no classic type) and char arrays alike.
        let text = || Err(self.err_var(var, "holds text where numbers are expected"));
        let Some(ty) = self.vars[var].ty else {
            return text();
        };
        match ty {
            NcType::Char => text(),
            NcType::Byte => self.read::<i8, T>(var, rec, ty),
            NcType::UByte => self.read::<u8, T>(var, rec, ty),
            NcType::Short => self.read::<i16, T>(var, rec, ty),
            NcType::UShort => self.read::<u16, T>(var, rec, ty),
            NcType::Int => self.read::<i32, T>(var, rec, ty),
            NcType::UInt => self.read::<u32, T>(var, rec, ty),
            NcType::Float => self.read::<f32, T>(var, rec, ty),
            NcType::Double => self.read::<f64, T>(var, rec, ty),
            NcType::Int64 => self.read::<i64, T>(var, rec, ty),
            NcType::UInt64 => self.read::<u64, T>(var, rec, ty),
        }
    }
    fn strings(&self, var: usize) -> Result<Vec<String>> {
        let v = &self.vars[var];
        let name = &v.name;
        if v.string && v.shape.len() == 1 && !v.record {
            let (_, n) = self.selection(var, 0)?;
            let s = guarded(self.path, || self.file.read_variable_as_strings(name))
                .map_err(|e| self.err_var(var, e.message))?;
            if s.len() as u64 != n {
                return Err(self.err_var(var, format!("{} strings read, {n} expected", s.len())));
            }
            return Ok(s.iter().map(|s| text_row(s.as_bytes())).collect());
        }
        if v.ty != Some(NcType::Char) || v.shape.len() != 2 || v.record {
            return Err(self.err_var(var, "is not a 2-D array of text"));
        }
        let (_, n) = self.selection(var, 0)?;
        let width = v.shape[1] as usize;
        if width == 0 {
            return Err(self.err_var(var, "holds strings of length 0"));
        }
        let raw = guarded(self.path, || self.file.read_variable_raw_bytes(name))
            .map_err(|e| self.err_var(var, e.message))?;
        if raw.len() as u64 != n {
            return Err(self.err_var(var, format!("{} bytes read, {n} expected", raw.len())));
        }
        Ok(raw.chunks_exact(width).map(text_row).collect())
    }
    fn err_var(&self, var: usize, msg: impl Into<String>) -> FormatError {
        let msg = msg.into();
        FormatError::whole(format!("variable '{}': {msg}", self.vars[var].name))
            .with_file(self.path)
    }
}
