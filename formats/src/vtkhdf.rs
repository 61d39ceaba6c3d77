//! VTKHDF (`.vtkhdf`, `.hdf`) UnstructuredGrid files, read through the pure-Rust `hdf5-reader` crate into a [`Grid`].
//!
//! The root group `VTKHDF` carries `Version` and `Type`; its datasets `NumberOfPoints`,
//! `NumberOfCells` and `NumberOfConnectivityIds` have one entry per piece, and `Points`, `Types`,
//! `Offsets` (cells + 1 per piece) and `Connectivity` (ids relative to the piece's points) are the
//! pieces concatenated. The pieces are joined into one grid, each piece's ids shifted by the
//! points before it. `PointData`, `CellData` and `FieldData` hold one dataset per array (1-D: one
//! component; 2-D: tuples x components), each kept with its name, type and component count.
//! Temporal files (a `Steps` group, VTKHDF 2) give one step: the first, or `FILE.vtkhdf@K` /
//! `@last`; the step's parts, points, cells and array rows are found through the `Steps` offsets
//! as VTK's reader finds them, and its time is added as the field array `Time`, as VTK adds it.
//! Polyhedra (type 42) and other `Type`s are refused by name.

use crate::error::guard_panics;
use crate::exodus::is_hdf5;
use crate::pvd::Selector;
use crate::{
    cell_type, ArrayData, Attribute, Attributes, Cells, DataArray, FormatError, Grid, ScalarType,
};
use crate::{Place, Result};
use hdf5_reader::group::Group;
use hdf5_reader::{ByteOrder, Datatype, Hdf5File, OpenOptions, SliceInfo, SliceInfoElem};
use std::path::{Path, PathBuf};

/// File extensions read as VTKHDF.
pub const EXTENSIONS: [&str; 2] = ["vtkhdf", "hdf"];

/// Deflate expands at most 1032-fold; a read decoding more than this many times the file's size
/// comes from a corrupt header, and is refused before it allocates.
const MAX_EXPANSION: u64 = 1100;

/// The `Type`s the VTKHDF specification names; all but UnstructuredGrid are refused by name.
const OTHER_TYPES: [&str; 6] = [
    "ImageData",
    "PolyData",
    "HyperTreeGrid",
    "OverlappingAMR",
    "PartitionedDataSetCollection",
    "MultiBlockDataSet",
];

/// Whether `path` has one of the VTKHDF [`EXTENSIONS`] (any case).
pub fn has_extension(path: &Path) -> bool {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .is_some_and(|e| EXTENSIONS.contains(&e.as_str()))
}

/// Splits `FILE.vtkhdf@K` / `FILE.vtkhdf@last` (also `.hdf`) into the file and the time step;
/// `None` for any other path.
pub fn split_selector(path: &Path) -> Option<(PathBuf, Selector)> {
    crate::pvd::split_step(path, has_extension)
}

/// The times of a temporal file's steps (`Steps/Values`); empty for a static file. Only the
/// structures on the way to `Steps/Values` are read from the file, not the whole of it (a listing
/// after the grid was read should not read the file twice).
pub fn times(path: &Path) -> Result<Vec<f64>> {
    let len = std::fs::metadata(path)
        .map_err(|e| FormatError::io(path, e))?
        .len();
    let (options, max_read) = bounds(len);
    let file = guarded(path, &Place::File, || {
        Hdf5File::open_with_options(path, options)
    })?;
    let r = open(file, path, max_read)?;
    if !r.has_member("Steps")? {
        return Ok(Vec::new());
    }
    r.step_values(&r.steps_group()?)
}

/// Runs a call into `hdf5-reader`, its errors and panics ([`guard_panics`]: it parses HDF5's
/// structures from untrusted bytes) made errors naming the file and `place`.
fn guarded<R>(
    path: &Path,
    place: &Place,
    f: impl FnOnce() -> std::result::Result<R, hdf5_reader::error::Error>,
) -> Result<R> {
    guard_panics(f)
        .map_err(|m| FormatError::new(place.clone(), format!("HDF5: {m}")).with_file(path))
}

/// A dataset read whole: its shape and values in the file's own element type.
struct Read {
    shape: Vec<u64>,
    data: ArrayData,
}

/// An HDF5 file's `/VTKHDF` group, and the bounds on what reading it may allocate.
struct Reader<'a> {
    path: &'a Path,
    group: hdf5_reader::group::Group,
    /// The most bytes one read may decode.
    max_read: u64,
}

fn place_of(what: &str) -> Place {
    Place::Other(what.to_string())
}

/// Converts little- or big-endian bytes to values of `$t`.
macro_rules! decode {
    ($raw:expr, $t:ty, $order:expr) => {{
        const N: usize = std::mem::size_of::<$t>();
        $raw.chunks_exact(N)
            .map(|c| {
                let mut b = [0u8; N];
                b.copy_from_slice(c);
                match $order {
                    ByteOrder::LittleEndian => <$t>::from_le_bytes(b),
                    ByteOrder::BigEndian => <$t>::from_be_bytes(b),
                }
            })
            .collect::<Vec<$t>>()
    }};
}

/// The values of `raw` as `dtype` says, or `None` for a type that is not a plain number.
fn decode(raw: &[u8], dtype: &Datatype) -> Option<ArrayData> {
    Some(match *dtype {
        Datatype::FixedPoint {
            size,
            signed,
            byte_order: o,
        } => match (size, signed) {
            (1, true) => ArrayData::Int8(raw.iter().map(|&b| b as i8).collect()),
            (1, false) => ArrayData::UInt8(raw.to_vec()),
            (2, true) => ArrayData::Int16(decode!(raw, i16, o)),
            (2, false) => ArrayData::UInt16(decode!(raw, u16, o)),
            (4, true) => ArrayData::Int32(decode!(raw, i32, o)),
            (4, false) => ArrayData::UInt32(decode!(raw, u32, o)),
            (8, true) => ArrayData::Int64(decode!(raw, i64, o)),
            (8, false) => ArrayData::UInt64(decode!(raw, u64, o)),
            _ => return None,
        },
        Datatype::FloatingPoint {
            size: 4,
            byte_order: o,
        } => ArrayData::Float32(decode!(raw, f32, o)),
        Datatype::FloatingPoint {
            size: 8,
            byte_order: o,
        } => ArrayData::Float64(decode!(raw, f64, o)),
        _ => return None,
    })
}

/// A short name for an HDF5 type that is not read as numbers.
fn type_words(dtype: &Datatype) -> String {
    match dtype {
        Datatype::FixedPoint { size, .. } => format!("{size}-byte integers"),
        Datatype::FloatingPoint { size, .. } => format!("{size}-byte floats"),
        Datatype::String { .. } => "strings".into(),
        Datatype::VarLen { .. } => "variable-length data".into(),
        Datatype::Compound { .. } => "a compound type".into(),
        Datatype::Array { .. } => "an HDF5 array type".into(),
        Datatype::Enum { .. } => "an enumeration (h5py writes booleans so)".into(),
        Datatype::Opaque { .. } => "opaque data".into(),
        Datatype::Reference { .. } => "references".into(),
        Datatype::Bitfield { .. } => "a bitfield".into(),
    }
}

fn is_string(dtype: &Datatype) -> bool {
    match dtype {
        Datatype::String { .. } => true,
        Datatype::VarLen { kind, .. } => matches!(kind, hdf5_reader::VarLenKind::String),
        _ => false,
    }
}

/// Trims the NUL or space padding of a fixed-length HDF5 string.
fn unpad(s: &str) -> &str {
    s.trim_end_matches(['\0', ' '])
}

impl<'a> Reader<'a> {
    fn err(&self, place: &str, msg: impl Into<String>) -> FormatError {
        FormatError::new(place_of(place), msg).with_file(self.path)
    }

    fn array_err(&self, name: &str, msg: impl Into<String>) -> FormatError {
        FormatError::in_array(name, msg).with_file(self.path)
    }

    /// The string value of attribute `name` of the VTKHDF group.
    fn attr_string(&self, name: &str) -> Result<String> {
        let place = place_of(&format!("attribute '{name}' of /VTKHDF"));
        let a = guarded(self.path, &place, || self.group.attribute(name))?;
        let s = guarded(self.path, &place, || {
            a.read_string().or_else(|_| {
                a.read_strings()
                    .map(|v| v.into_iter().next().unwrap_or_default())
            })
        })?;
        Ok(unpad(&s).to_string())
    }

    /// The integer values of attribute `name` of `group` (shown as `gname`).
    fn attr_ints(&self, group: &Group, gname: &str, name: &str) -> Result<Vec<i64>> {
        let place = place_of(&format!("attribute '{name}' of {gname}"));
        let a = guarded(self.path, &place, || group.attribute(name))?;
        // The attribute's own integer type, whichever h5py or VTK chose.
        fn wide<T: Into<i64>>(v: Vec<T>) -> Vec<i64> {
            v.into_iter().map(Into::into).collect()
        }
        guarded(self.path, &place, || {
            a.read_1d::<i64>()
                .or_else(|_| a.read_1d::<i32>().map(wide))
                .or_else(|_| a.read_1d::<u32>().map(wide))
                .or_else(|_| a.read_1d::<i16>().map(wide))
                .or_else(|_| a.read_1d::<u16>().map(wide))
                .or_else(|_| a.read_1d::<i8>().map(wide))
                .or_else(|_| a.read_1d::<u8>().map(wide))
        })
    }

    /// The `Steps` group of a temporal file.
    fn steps_group(&self) -> Result<Group> {
        guarded(self.path, &place_of("group /VTKHDF/Steps"), || {
            self.group.group("Steps")
        })
    }

    /// The time of each step (`Steps/Values`), checked against the `NSteps` attribute when
    /// there is one.
    fn step_values(&self, group: &Group) -> Result<Vec<f64>> {
        let values = self.dataset(group, "Values", "Steps/Values", false)?;
        if values.shape.len() != 1 {
            return Err(self.array_err(
                "Steps/Values",
                format!("has shape {:?}, expected one time per step", values.shape),
            ));
        }
        let values = values.data.to_f64_vec();
        let n = values.len();
        if let Ok(ns) = self.attr_ints(group, "/VTKHDF/Steps", "NSteps") {
            if ns.first().copied() != Some(n as i64) {
                return Err(self.err(
                    "attribute 'NSteps' of /VTKHDF/Steps",
                    format!("says {ns:?} steps, but Steps/Values has {n}"),
                ));
            }
        }
        Ok(values)
    }

    /// The `Steps` group: its times and per-step datasets, their lengths checked against
    /// `Values`, and the per-array offset groups VTK's reader knows, each with its members.
    fn steps(&self) -> Result<Steps> {
        let group = self.steps_group()?;
        let values = self.step_values(&group)?;
        let n = values.len() as u64;
        let ints = |name: &str| self.step_ints(&group, name, &format!("Steps/{name}"), n);
        let (kinds, _) = guarded(self.path, &place_of("group /VTKHDF/Steps"), || {
            group.member_names()
        })?;
        let mut per_array = Vec::new();
        for kind in kinds
            .into_iter()
            .filter(|k| PER_ARRAY.contains(&k.as_str()))
        {
            let gname = format!("group /VTKHDF/Steps/{kind}");
            let g = guarded(self.path, &place_of(&gname), || group.group(&kind))?;
            let (_, names) = guarded(self.path, &place_of(&gname), || g.member_names())?;
            per_array.push((kind, g, names));
        }
        Ok(Steps {
            part_offsets: ints("PartOffsets")?,
            parts: ints("NumberOfParts")?,
            point_offsets: ints("PointOffsets")?,
            cell_offsets: ints("CellOffsets")?,
            conn_offsets: ints("ConnectivityIdOffsets")?,
            values,
            per_array,
        })
    }

    /// One integer per step from dataset `name` of `group` (shown as `shown`): 1-D of `n`
    /// entries, or `n` rows of which the first column is taken (an UnstructuredGrid's
    /// `CellOffsets` may be `n x 1`; PolyData's have a column per cell kind).
    fn step_ints(&self, group: &Group, name: &str, shown: &str, n: u64) -> Result<Vec<i64>> {
        let (v, rows, cols) = self.int_table(group, name, shown)?;
        if rows != n {
            return Err(self.array_err(
                shown,
                format!("has {rows} rows, expected {n} (one per time step)"),
            ));
        }
        Ok(v.into_iter().step_by(cols).collect())
    }

    /// Row of dataset `Steps/<kind>/<name>` at the window's step, when the file has it.
    fn step_row(&self, w: &Window, kind: &str, name: &str) -> Result<Option<Vec<i64>>> {
        let Some((k, _)) = &w.step else {
            return Ok(None);
        };
        let Some((_, g, _)) = w
            .per_array
            .iter()
            .find(|(kd, _, names)| kd == kind && names.iter().any(|m| m == name))
        else {
            return Ok(None);
        };
        let shown = format!("Steps/{kind}/{name}");
        let (v, rows, cols) = self.int_table(g, name, &shown)?;
        if *k as u64 >= rows {
            return Err(self.array_err(&shown, format!("has {rows} rows, none for time step {k}")));
        }
        Ok(Some(v[*k * cols..(*k + 1) * cols].to_vec()))
    }

    /// An integer dataset of 1 or 2 dimensions (shown as `shown`): its values, rows and
    /// columns (at least one).
    fn int_table(&self, group: &Group, name: &str, shown: &str) -> Result<(Vec<i64>, u64, usize)> {
        let r = self.dataset(group, name, shown, false)?;
        let (rows, cols) = match r.shape.as_slice() {
            [n] => (*n, 1),
            [n, c] if *c >= 1 => (*n, *c as usize),
            s => {
                return Err(self.array_err(
                    shown,
                    format!("has shape {s:?}, expected 1-D or rows x columns"),
                ))
            }
        };
        let ty = r.data.type_name();
        let v = r
            .data
            .into_i64()
            .map_err(|_| self.array_err(shown, format!("holds {ty} values, expected integers")))?;
        Ok((v, rows, cols))
    }

    /// Reads dataset `name` of `group` (shown as `shown` in messages) whole, as numbers, or as
    /// strings when `strings` allows them.
    fn dataset(&self, group: &Group, name: &str, shown: &str, strings: bool) -> Result<Read> {
        self.dataset_with(group, name, shown, strings, |_| Ok(Take::All))?
            .ok_or_else(|| self.array_err(shown, "was not read"))
    }

    /// [`Reader::dataset`], reading what `take` picks from the dataset's shape (checking it):
    /// all of it, a run of rows (for a temporal step: only those rows are decoded) or nothing.
    fn dataset_with(
        &self,
        group: &Group,
        name: &str,
        shown: &str,
        strings: bool,
        take: impl FnOnce(&[u64]) -> Result<Take>,
    ) -> Result<Option<Read>> {
        let place = Place::Array(shown.to_string());
        let ds = guarded(self.path, &place, || group.dataset(name))?;
        let shape = ds.shape().to_vec();
        let dtype = ds.dtype().clone();
        let elem = match &dtype {
            Datatype::FixedPoint { size, .. } | Datatype::FloatingPoint { size, .. } => {
                u64::from(*size)
            }
            _ => 1,
        };
        let n = shape
            .iter()
            .try_fold(1u64, |acc, &d| acc.checked_mul(d))
            .filter(|&n| n.saturating_mul(elem) <= self.max_read)
            .ok_or_else(|| {
                self.array_err(
                    shown,
                    format!("its shape {shape:?} is more than a file of this size could hold"),
                )
            })?;
        if is_string(&dtype) {
            if !strings {
                return Err(self.array_err(
                    shown,
                    "holds strings; tetkit reads strings only in FieldData",
                ));
            }
            if shape.len() > 1 {
                return Err(self.array_err(
                    shown,
                    format!("holds strings in shape {shape:?}; only 1-D string arrays are read"),
                ));
            }
        } else if decode(&[], &dtype).is_none() {
            return Err(self.array_err(
                shown,
                format!("holds {}, not numbers tetkit reads", type_words(&dtype)),
            ));
        }
        let (start, count) = match take(&shape)? {
            Take::Nothing => return Ok(None),
            Take::All => (0, shape.first().copied().unwrap_or(1)),
            Take::Rows(start, count) => (start, count),
        };
        let whole = start == 0 && shape.first().map_or(true, |&rows| rows == count);
        if is_string(&dtype) {
            let s = guarded(self.path, &place, || ds.read_strings())?;
            if s.len() as u64 != n {
                return Err(
                    self.array_err(shown, format!("{} strings read, {n} expected", s.len()))
                );
            }
            let data = ArrayData::String(s.iter().map(|x| unpad(x).to_string()).collect());
            let mut shape = shape;
            if let Some(rows) = shape.first_mut() {
                *rows = count;
            }
            return Ok(Some(Read {
                shape,
                data: data.into_rows(1, start as usize, count as usize),
            }));
        }
        if !whole {
            return self
                .rows_of(&ds, &place, shape, &dtype, start, count)
                .map(Some);
        }
        let raw = guarded(self.path, &place, || ds.read_raw_bytes())?;
        if raw.len() as u64 != n.saturating_mul(elem) {
            return Err(self.array_err(
                shown,
                format!(
                    "{} bytes read, {} expected",
                    raw.len(),
                    n.saturating_mul(elem)
                ),
            ));
        }
        let data = decode(&raw, &dtype).ok_or_else(|| {
            self.array_err(
                shown,
                format!("holds {}, not numbers tetkit reads", type_words(&dtype)),
            )
        })?;
        Ok(Some(Read { shape, data }))
    }

    /// Rows `start .. start + count` (within the dataset, checked by the caller's `take`) of a
    /// numeric dataset of `shape` and `dtype`, decoded alone (a hyperslab read).
    fn rows_of(
        &self,
        ds: &hdf5_reader::Dataset,
        place: &Place,
        mut shape: Vec<u64>,
        dtype: &Datatype,
        start: u64,
        count: u64,
    ) -> Result<Read> {
        let rows = shape.first().copied().unwrap_or(0);
        if !start.checked_add(count).is_some_and(|end| end <= rows) {
            return Err(FormatError::new(
                place.clone(),
                format!(
                    "rows {start} to {} asked of {rows}",
                    start.saturating_add(count)
                ),
            )
            .with_file(self.path));
        }
        if let Some(r) = shape.first_mut() {
            *r = count;
        }
        let ty = decode(&[], dtype)
            .and_then(|d| d.scalar_type())
            .ok_or_else(|| FormatError::new(place.clone(), "not numbers").with_file(self.path))?;
        if count == 0 {
            return Ok(Read {
                shape,
                data: ArrayData::with_capacity(ty, 0),
            });
        }
        let mut sel = SliceInfo::all(shape.len());
        sel.selections[0] = SliceInfoElem::Slice {
            start,
            end: start + count,
            step: 1,
        };
        fn get<T: hdf5_reader::H5Type>(
            ds: &hdf5_reader::Dataset,
            sel: &SliceInfo,
        ) -> std::result::Result<Vec<T>, hdf5_reader::error::Error> {
            Ok(ds.read_slice::<T>(sel)?.into_iter().collect())
        }
        let data = guarded(self.path, place, || {
            Ok(match ty {
                ScalarType::Int8 => ArrayData::Int8(get(ds, &sel)?),
                ScalarType::UInt8 => ArrayData::UInt8(get(ds, &sel)?),
                ScalarType::Int16 => ArrayData::Int16(get(ds, &sel)?),
                ScalarType::UInt16 => ArrayData::UInt16(get(ds, &sel)?),
                ScalarType::Int32 => ArrayData::Int32(get(ds, &sel)?),
                ScalarType::UInt32 => ArrayData::UInt32(get(ds, &sel)?),
                ScalarType::Int64 => ArrayData::Int64(get(ds, &sel)?),
                ScalarType::UInt64 => ArrayData::UInt64(get(ds, &sel)?),
                ScalarType::Float32 => ArrayData::Float32(get(ds, &sel)?),
                ScalarType::Float64 => ArrayData::Float64(get(ds, &sel)?),
            })
        })?;
        let want = shape.iter().product::<u64>();
        if data.len() as u64 != want {
            return Err(FormatError::new(
                place.clone(),
                format!("{} values read, {want} expected", data.len()),
            )
            .with_file(self.path));
        }
        Ok(Read { shape, data })
    }

    /// A 1-D integer dataset of `/VTKHDF` of `len` entries (any length when `None`), as i64.
    fn ints(&self, name: &str, len: Option<u64>) -> Result<Vec<i64>> {
        self.ints_with(name, |rows| match len {
            Some(len) if rows != len => {
                Err(self.array_err(name, format!("has {rows} entries, expected {len}")))
            }
            _ => Ok(Take::All),
        })
    }

    /// A 1-D integer dataset of `/VTKHDF`, what `take` picks from its length, as i64.
    fn ints_with(&self, name: &str, take: impl FnOnce(u64) -> Result<Take>) -> Result<Vec<i64>> {
        let r = self
            .dataset_with(&self.group, name, name, false, |shape| match shape {
                [rows] => take(*rows),
                s => Err(self.array_err(name, format!("has shape {s:?}, expected 1-D"))),
            })?
            .ok_or_else(|| self.array_err(name, "was not read"))?;
        let ty = r.data.type_name();
        r.data.into_i64().map_err(|_| {
            self.array_err(
                name,
                format!("holds {ty} values, expected integers (below 2^63)"),
            )
        })
    }

    /// The tuples `start, count` of array `name` (shown as `shown`, `total` tuples of
    /// `components`) that `rows` reads; `None` when the step has none of it (field data sized 0).
    fn array_rows(
        &self,
        name: &str,
        shown: &str,
        rows: Rows,
        total: u64,
        components: u64,
        w: &Window,
    ) -> Result<Option<(u64, u64)>> {
        let first = |kind: &str| -> Result<Option<u64>> {
            match self.step_row(w, kind, name)? {
                None => Ok(None),
                Some(v) => u64::try_from(v[0]).map(Some).map_err(|_| {
                    self.array_err(
                        &format!("Steps/{kind}/{name}"),
                        format!("has a negative offset {} at {}", v[0], w.step_name()),
                    )
                }),
            }
        };
        let (start, count) = match rows {
            Rows::All(None) => (0, total),
            Rows::All(Some(n)) => {
                if total != n {
                    let what = if shown.starts_with("PointData") {
                        "points"
                    } else {
                        "cells"
                    };
                    return Err(self.array_err(
                        shown,
                        format!("has {total} tuples, but the file has {n} {what}"),
                    ));
                }
                (0, n)
            }
            Rows::Step {
                base,
                count,
                offsets,
            } => (first(offsets)?.unwrap_or(base), count),
            Rows::Field => match first("FieldDataOffsets")? {
                None => (0, total),
                Some(start) => match self.step_row(w, "FieldDataSizes", name)? {
                    Some(v) if v.len() >= 2 => {
                        if v[0] == 0 && v[1] == 0 {
                            return Ok(None);
                        }
                        if v[0] != components as i64 || v[1] < 0 {
                            return Err(self.array_err(
                                &format!("Steps/FieldDataSizes/{name}"),
                                format!(
                                    "gives {} components and {} tuples at {}, but {shown} has {components} components",
                                    v[0],
                                    v[1],
                                    w.step_name()
                                ),
                            ));
                        }
                        (start, v[1] as u64)
                    }
                    // Before `FieldDataSizes`, VTK read one tuple a step.
                    _ => (start, 1),
                },
            },
        };
        if !start.checked_add(count).is_some_and(|end| end <= total) {
            return Err(self.array_err(
                shown,
                format!(
                    "has {total} tuples, but {} reads tuples {start} to {}",
                    w.step_name(),
                    start.saturating_add(count)
                ),
            ));
        }
        Ok(Some((start, count)))
    }

    fn has_member(&self, name: &str) -> Result<bool> {
        let place = place_of("/VTKHDF");
        let (groups, datasets) = guarded(self.path, &place, || self.group.member_names())?;
        Ok(groups.iter().chain(&datasets).any(|m| m == name))
    }

    /// The arrays of group `gname` (PointData, CellData, FieldData), the tuples `rows` says of
    /// each, in the order HDF5 lists them.
    fn arrays(&self, gname: &str, rows: Rows, w: &Window) -> Result<(Vec<DataArray>, Attributes)> {
        let mut attrs = Attributes::default();
        if !self.has_member(gname)? {
            return Ok((Vec::new(), attrs));
        }
        let place = place_of(&format!("group /VTKHDF/{gname}"));
        let g = guarded(self.path, &place, || self.group.group(gname))?;
        let (groups, names) = guarded(self.path, &place, || g.member_names())?;
        if let Some(sub) = groups.first() {
            return Err(self.err(
                &format!("group /VTKHDF/{gname}"),
                format!("holds a group '{sub}' where arrays are expected; it is not read"),
            ));
        }
        let field = matches!(rows, Rows::All(None) | Rows::Field);
        let mut out = Vec::with_capacity(names.len());
        for name in names {
            let shown = format!("{gname}/{name}");
            let mut components = 1;
            let picked = self.dataset_with(&g, &name, &shown, field, |shape| {
                let (c, total) = match shape {
                    [t] => (1, *t),
                    [t, c] => (*c, *t),
                    s => {
                        return Err(self.array_err(
                            &shown,
                            format!("has shape {s:?}; arrays are 1-D or 2-D (tuples x components)"),
                        ))
                    }
                };
                if c == 0 {
                    return Err(self.array_err(&shown, "has 0 components"));
                }
                components = c;
                Ok(match self.array_rows(&name, &shown, rows, total, c, w)? {
                    None => Take::Nothing,
                    Some((start, count)) => Take::Rows(start, count),
                })
            })?;
            let Some(r) = picked else {
                continue;
            };
            let components = usize::try_from(components)
                .map_err(|_| self.array_err(&shown, "has too many components"))?;
            out.push(DataArray::new(name, components, r.data));
        }
        // Active attributes, when the group names them as VTK XML does (`Scalars="name"`).
        if !field {
            for role in Attribute::ALL {
                let Ok(a) = guarded(self.path, &place, || g.attribute(role.xml_name())) else {
                    continue;
                };
                if let Ok(s) = guarded(self.path, &place, || a.read_string()) {
                    let s = unpad(&s).to_string();
                    if out.iter().any(|x| x.name == s) {
                        attrs.active.push((role, s));
                    }
                }
            }
        }
        Ok((out, attrs))
    }
}

/// Reads the VTKHDF UnstructuredGrid file in `bytes` (a temporal file's first step); `path`
/// names it in errors.
pub fn read_from(bytes: &[u8], path: &Path) -> Result<Grid> {
    read_from_at(bytes, path, Selector::Index(0))
}

/// [`read_from`] at time step `sel` of a temporal file (a static file has only step 0).
pub fn read_from_at(bytes: &[u8], path: &Path, sel: Selector) -> Result<Grid> {
    let (options, max_read) = options_for(bytes, path)?;
    let file = guarded(path, &Place::File, || {
        Hdf5File::from_bytes_with_options(bytes, options)
    })?;
    read_file(file, path, max_read, sel)
}

/// [`read_from`] taking the file's bytes, which the HDF5 reader keeps rather than copies (a
/// whole file less at the peak).
pub fn read_vec(bytes: Vec<u8>, path: &Path) -> Result<Grid> {
    read_vec_at(bytes, path, Selector::Index(0))
}

/// [`read_vec`] at time step `sel`.
pub fn read_vec_at(bytes: Vec<u8>, path: &Path, sel: Selector) -> Result<Grid> {
    let (options, max_read) = options_for(&bytes, path)?;
    let file = guarded(path, &Place::File, move || {
        Hdf5File::from_vec_with_options(bytes, options)
    })?;
    read_file(file, path, max_read, sel)
}

/// The HDF5 reader's bounds for a file of `bytes` (what a read may decode, at most
/// [`MAX_EXPANSION`] times the file), after checking it is HDF5 at all.
fn options_for(bytes: &[u8], path: &Path) -> Result<(OpenOptions, u64)> {
    if !is_hdf5(bytes) {
        return Err(
            FormatError::at_byte(0, "not an HDF5 file (no HDF5 signature), so not VTKHDF")
                .with_file(path),
        );
    }
    Ok(bounds(bytes.len() as u64))
}

/// The HDF5 reader's bounds for a file of `len` bytes: what one read may decode.
fn bounds(len: u64) -> (OpenOptions, u64) {
    let max_read = len.saturating_mul(MAX_EXPANSION).max(1 << 20);
    let limit = usize::try_from(max_read).unwrap_or(usize::MAX);
    let options = OpenOptions {
        max_read_bytes: limit,
        max_chunk_bytes: limit.min(hdf5_reader::DEFAULT_MAX_CHUNK_BYTES),
        ..OpenOptions::default()
    };
    (options, max_read)
}

/// The `/VTKHDF` group of an opened file, after checking its `Type` and `Version`.
fn open(file: Hdf5File, path: &Path, max_read: u64) -> Result<Reader<'_>> {
    let whole = Place::File;
    let root = guarded(path, &whole, || file.root_group())?;
    let (groups, _) = guarded(path, &whole, || root.member_names())?;
    if !groups.iter().any(|g| g == "VTKHDF") {
        return Err(
            FormatError::whole("an HDF5 file without a /VTKHDF group: not a VTKHDF file")
                .with_file(path),
        );
    }
    let group = guarded(path, &place_of("group /VTKHDF"), || root.group("VTKHDF"))?;
    let r = Reader {
        path,
        group,
        max_read,
    };
    let ty = r.attr_string("Type")?;
    if ty != "UnstructuredGrid" {
        let what = if OTHER_TYPES.contains(&ty.as_str()) {
            format!("VTKHDF {ty} is not read; tetkit reads VTKHDF UnstructuredGrid only")
        } else {
            format!("unknown VTKHDF Type '{ty}'; tetkit reads UnstructuredGrid")
        };
        return Err(r.err("attribute 'Type' of /VTKHDF", what));
    }
    let version = r.attr_ints(&r.group, "/VTKHDF", "Version")?;
    match version.first() {
        Some(1 | 2) => {}
        _ => {
            return Err(r.err(
                "attribute 'Version' of /VTKHDF",
                format!("version {version:?}; tetkit reads VTKHDF versions 1.x and 2.x"),
            ))
        }
    }
    Ok(r)
}

/// Reads step `sel` of the grid of an opened VTKHDF file.
fn read_file(file: Hdf5File, path: &Path, max_read: u64, sel: Selector) -> Result<Grid> {
    let r = open(file, path, max_read)?;
    let w = if r.has_member("Steps")? {
        r.steps()?.window(&r, sel)?
    } else {
        if let Selector::Index(k @ 1..) = sel {
            return Err(r.err(
                "/VTKHDF",
                format!("there is no time step {k}: the file is not temporal (no Steps group)"),
            ));
        }
        Window::default()
    };
    read_grid(&r, &w)
}

/// The `Steps` group of a temporal file: per step, where its parts, points, cells and
/// connectivity ids start.
struct Steps {
    values: Vec<f64>,
    /// The per-array offset groups ([`PER_ARRAY`]) the file has, with their members' names.
    per_array: Vec<(String, Group, Vec<String>)>,
    part_offsets: Vec<i64>,
    parts: Vec<i64>,
    point_offsets: Vec<i64>,
    cell_offsets: Vec<i64>,
    conn_offsets: Vec<i64>,
}

impl Steps {
    /// Where step `sel` lies.
    fn window(self, r: &Reader, sel: Selector) -> Result<Window> {
        let n = self.values.len();
        let k = sel.index_of(n);
        if k >= n {
            return Err(r.err(
                "group /VTKHDF/Steps",
                format!(
                    "there is no time step {k}: the file has {n}{}",
                    if n > 0 {
                        format!(" (0 to {})", n - 1)
                    } else {
                        String::new()
                    }
                ),
            ));
        }
        let at = |name: &str, v: &[i64]| {
            u64::try_from(v[k]).map_err(|_| {
                r.array_err(
                    &format!("Steps/{name}"),
                    format!("step {k} has a negative offset {}", v[k]),
                )
            })
        };
        Ok(Window {
            part0: at("PartOffsets", &self.part_offsets)?,
            parts: Some(at("NumberOfParts", &self.parts)?),
            point0: at("PointOffsets", &self.point_offsets)?,
            cell0: at("CellOffsets", &self.cell_offsets)?,
            conn0: at("ConnectivityIdOffsets", &self.conn_offsets)?,
            step: Some((k, self.values[k])),
            per_array: self.per_array,
        })
    }
}

/// The groups of `Steps` that hold one dataset per array: where each array's rows start at each
/// step, and a field array's size at each step.
const PER_ARRAY: [&str; 4] = [
    "PointDataOffsets",
    "CellDataOffsets",
    "FieldDataOffsets",
    "FieldDataSizes",
];

/// Where the step read lies in the file's datasets; the default is a static file's whole.
#[derive(Default)]
struct Window {
    /// The step's index and time, for a temporal file.
    step: Option<(usize, f64)>,
    /// The `Steps` groups of per-array offsets and sizes, with their members' names.
    per_array: Vec<(String, Group, Vec<String>)>,
    /// The step's first part, and how many it has (all of the file's when `None`).
    part0: u64,
    parts: Option<u64>,
    /// The step's first row of `Points`, of `Types` and of `Connectivity`.
    point0: u64,
    cell0: u64,
    conn0: u64,
}

impl Window {
    /// "time step K" of a temporal file (messages name the step they read), else "the file".
    fn step_name(&self) -> String {
        self.step
            .as_ref()
            .map_or_else(|| "the file".into(), |(k, _)| format!("time step {k}"))
    }
}

/// What [`Reader::dataset_with`] reads of a dataset.
enum Take {
    All,
    /// Rows `start, count`.
    Rows(u64, u64),
    Nothing,
}

/// Which tuples of each array of a group a read takes.
#[derive(Clone, Copy)]
enum Rows<'a> {
    /// Every tuple; exactly `n` of them when given (a static file's arrays).
    All(Option<u64>),
    /// `count` tuples from the step's row of each array: `Steps/<offsets>/<name>` at the step,
    /// else `base` (the step's first point or cell), as VTK's reader places them.
    Step {
        base: u64,
        count: u64,
        offsets: &'a str,
    },
    /// A temporal file's field data: `Steps/FieldDataOffsets` and `Steps/FieldDataSizes` at the
    /// step; an array without an offset is read whole.
    Field,
}

/// Sums per-piece counts, refusing negative ones and overflow.
fn total(r: &Reader, name: &str, counts: &[i64]) -> Result<u64> {
    let mut sum = 0u64;
    for (k, &c) in counts.iter().enumerate() {
        let c = u64::try_from(c)
            .map_err(|_| r.array_err(name, format!("piece {k} has a negative count {c}")))?;
        sum = sum
            .checked_add(c)
            .filter(|&s| s <= r.max_read)
            .ok_or_else(|| {
                r.array_err(name, "the counts add up to more than the file could hold")
            })?;
    }
    Ok(sum)
}

fn read_grid(r: &Reader, w: &Window) -> Result<Grid> {
    let np_all = r.ints("NumberOfPoints", None)?;
    let listed = np_all.len() as u64;
    let nc_all = r.ints("NumberOfCells", Some(listed))?;
    let nconn_all = r.ints("NumberOfConnectivityIds", Some(listed))?;
    // The step's parts (a static file's are all of them).
    let pieces = w.parts.unwrap_or(listed);
    let part0 = w.part0;
    if !part0.checked_add(pieces).is_some_and(|end| end <= listed) {
        return Err(r.array_err(
            "NumberOfPoints",
            format!(
                "lists {listed} parts, but {} reads parts {part0} to {}",
                w.step_name(),
                part0.saturating_add(pieces)
            ),
        ));
    }
    if pieces == 0 {
        let what = if w.step.is_some() {
            format!("{} has no parts", w.step_name())
        } else {
            "is empty: the file has no pieces".to_string()
        };
        return Err(r.array_err("NumberOfPoints", what));
    }
    let parts = part0 as usize..(part0 + pieces) as usize;
    let (np, nc, nconn) = (
        &np_all[parts.clone()],
        &nc_all[parts.clone()],
        &nconn_all[parts],
    );
    let np_total = total(r, "NumberOfPoints", np)?;
    let nc_total = total(r, "NumberOfCells", nc)?;
    let nconn_total = total(r, "NumberOfConnectivityIds", nconn)?;
    let temporal = w.step.is_some();
    // Rows `start .. start + count` of a dataset of `have` rows: all of them in a static file.
    let window = |name: &str, have: u64, start: u64, count: u64, unit: &str| -> Result<()> {
        let fits = if temporal {
            start.checked_add(count).is_some_and(|end| end <= have)
        } else {
            have == count
        };
        if fits {
            return Ok(());
        }
        Err(r.array_err(
            name,
            if temporal {
                format!(
                    "has {have} {unit}, but {} reads {unit} {start} to {}",
                    w.step_name(),
                    start.saturating_add(count)
                )
            } else {
                format!("has {have} {unit}, expected {count}")
            },
        ))
    };

    // Rows `start, count` of dataset `name`, whose shape past its rows must be `tail`.
    let rows_of = |name: &str, tail: &[u64], start: u64, count: u64, unit: &str, want: &str| {
        r.dataset_with(&r.group, name, name, false, |shape| match shape {
            [rows, rest @ ..] if rest == tail => {
                window(name, *rows, start, count, unit)?;
                Ok(Take::Rows(start, count))
            }
            s => Err(r.array_err(name, format!("has shape {s:?}, expected {want}"))),
        })?
        .ok_or_else(|| r.array_err(name, "was not read"))
    };
    let points = rows_of(
        "Points",
        &[3],
        w.point0,
        np_total,
        "rows",
        &format!("[{np_total}, 3] (NumberOfPoints x 3)"),
    )?;
    let types = rows_of(
        "Types",
        &[],
        w.cell0,
        nc_total,
        "entries",
        &format!("[{nc_total}] (one per cell)"),
    )?
    .data;
    let types: Vec<u8> = match types {
        ArrayData::UInt8(v) => v,
        other => {
            let ty = other.type_name();
            other
                .into_i64()
                .ok()
                .and_then(|v| v.into_iter().map(|t| u8::try_from(t).ok()).collect())
                .ok_or_else(|| {
                    r.array_err(
                        "Types",
                        format!("holds {ty} values, expected cell type ids 0..255"),
                    )
                })?
        }
    };
    // Each part's offsets have one entry more than its cells: the step's start past those of
    // the parts before it, as VTK's reader counts.
    let off0 = w.cell0.saturating_add(part0);
    let offsets = r.ints_with("Offsets", |rows| {
        window("Offsets", rows, off0, nc_total + pieces, "entries")?;
        Ok(Take::Rows(off0, nc_total + pieces))
    })?;
    let conn = r.ints_with("Connectivity", |rows| {
        window("Connectivity", rows, w.conn0, nconn_total, "entries")?;
        Ok(Take::Rows(w.conn0, nconn_total))
    })?;

    // Join the pieces: each piece's offsets start at 0 and its ids count its own points.
    let mut cells = Cells {
        types,
        offsets: Vec::with_capacity(offsets.len()),
        connectivity: Vec::with_capacity(conn.len()),
        polyhedron_faces: None,
    };
    cells.offsets.push(0);
    let (mut p0, mut c0, mut o0, mut k0) = (0i64, 0usize, 0usize, 0i64);
    for k in 0..np.len() {
        let (npk, nck, nconnk) = (np[k], nc[k] as usize, nconn[k] as usize);
        let off = &offsets[o0..o0 + nck + 1];
        if off[0] != 0 {
            return Err(r.array_err(
                "Offsets",
                format!("piece {k}'s offsets start at {}, expected 0", off[0]),
            ));
        }
        // Structure first (offsets that decrease also give wrong sizes), then cell by cell.
        for i in 0..nck {
            let (a, b) = (off[i], off[i + 1]);
            if b < a {
                return Err(r.array_err(
                    "Offsets",
                    format!(
                        "offsets decrease at cell {} (piece {k}): {a} then {b}",
                        c0 + i
                    ),
                ));
            }
            if b as u64 > nconnk as u64 {
                return Err(r.array_err(
                    "Offsets",
                    format!(
                        "cell {} (piece {k}) ends at {b}, past the piece's {nconnk} connectivity ids",
                        c0 + i
                    ),
                ));
            }
        }
        for i in 0..nck {
            let cell = c0 + i;
            let (a, b) = (off[i], off[i + 1]);
            let t = cells.types[cell];
            if t == cell_type::POLYHEDRON {
                return Err(r.array_err(
                    "Types",
                    format!(
                        "cell {cell} is a polyhedron (type 42); VTKHDF polyhedra (FaceConnectivity) are not read"
                    ),
                ));
            }
            if let Some(n) = cell_type::fixed_size(t) {
                if (b - a) as usize != n {
                    return Err(r.array_err(
                        "Offsets",
                        format!(
                            "cell {cell} is a {} with {} points, expected {n}",
                            cell_type::name(t),
                            b - a
                        ),
                    ));
                }
            }
            cells.offsets.push(k0 + b);
        }
        if off[nck] as u64 != nconnk as u64 {
            return Err(r.array_err(
                "Offsets",
                format!(
                    "piece {k}'s offsets end at {}, but it has {nconnk} connectivity ids",
                    off[nck]
                ),
            ));
        }
        for (j, &id) in conn[k0 as usize..k0 as usize + nconnk].iter().enumerate() {
            if id < 0 || id >= npk {
                return Err(r.array_err(
                    "Connectivity",
                    format!(
                        "entry {} is point id {id}, outside piece {k}'s points ({})",
                        k0 as usize + j,
                        crate::error::numbered(npk as u64, "point", 0)
                    ),
                ));
            }
            cells.connectivity.push(p0 + id);
        }
        p0 += npk;
        c0 += nck;
        o0 += nck + 1;
        k0 += nconnk as i64;
    }

    let (point_rows, cell_rows, field_rows) = if temporal {
        (
            Rows::Step {
                base: w.point0,
                count: np_total,
                offsets: "PointDataOffsets",
            },
            Rows::Step {
                base: w.cell0,
                count: nc_total,
                offsets: "CellDataOffsets",
            },
            Rows::Field,
        )
    } else {
        (
            Rows::All(Some(np_total)),
            Rows::All(Some(nc_total)),
            Rows::All(None),
        )
    };
    let (pd, mut point_data) = r.arrays("PointData", point_rows, w)?;
    let (cd, mut cell_data) = r.arrays("CellData", cell_rows, w)?;
    let (mut field_data, _) = r.arrays("FieldData", field_rows, w)?;
    point_data.arrays = pd;
    cell_data.arrays = cd;
    // VTK's reader gives a temporal file's step its time as the field array `Time`.
    if let Some((_, t)) = &w.step {
        if !field_data.iter().any(|a| a.name == "Time") {
            field_data.push(DataArray::new("Time", 1, ArrayData::Float64(vec![*t])));
        }
    }
    Ok(Grid {
        points: DataArray::new("Points", 3, points.data),
        cells,
        point_data,
        cell_data,
        field_data,
    })
}

#[cfg(test)]
mod tests;
