//! The in-memory unstructured grid: what VTK's vtkUnstructuredGrid holds, kept as the file had it.

use rayon::prelude::*;
use std::fmt;

/// Element type of a data array, named as VTK's XML formats name them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ScalarType {
    Int8,
    UInt8,
    Int16,
    UInt16,
    Int32,
    UInt32,
    Int64,
    UInt64,
    Float32,
    Float64,
}

impl ScalarType {
    pub const ALL: [ScalarType; 10] = [
        ScalarType::Int8,
        ScalarType::UInt8,
        ScalarType::Int16,
        ScalarType::UInt16,
        ScalarType::Int32,
        ScalarType::UInt32,
        ScalarType::Int64,
        ScalarType::UInt64,
        ScalarType::Float32,
        ScalarType::Float64,
    ];

    /// Size of one element in bytes.
    pub fn size(self) -> usize {
        match self {
            ScalarType::Int8 | ScalarType::UInt8 => 1,
            ScalarType::Int16 | ScalarType::UInt16 => 2,
            ScalarType::Int32 | ScalarType::UInt32 | ScalarType::Float32 => 4,
            ScalarType::Int64 | ScalarType::UInt64 | ScalarType::Float64 => 8,
        }
    }

    /// The `type="..."` name in VTK XML files.
    pub fn xml_name(self) -> &'static str {
        match self {
            ScalarType::Int8 => "Int8",
            ScalarType::UInt8 => "UInt8",
            ScalarType::Int16 => "Int16",
            ScalarType::UInt16 => "UInt16",
            ScalarType::Int32 => "Int32",
            ScalarType::UInt32 => "UInt32",
            ScalarType::Int64 => "Int64",
            ScalarType::UInt64 => "UInt64",
            ScalarType::Float32 => "Float32",
            ScalarType::Float64 => "Float64",
        }
    }

    /// Parses a VTK XML type name; `Char`/`UChar` style aliases are not VTK XML and are refused.
    pub fn from_xml_name(name: &str) -> Option<ScalarType> {
        ScalarType::ALL.into_iter().find(|t| t.xml_name() == name)
    }

    /// The data type keyword legacy VTK files use when writing this type.
    pub fn legacy_name(self) -> &'static str {
        match self {
            ScalarType::Int8 => "char",
            ScalarType::UInt8 => "unsigned_char",
            ScalarType::Int16 => "short",
            ScalarType::UInt16 => "unsigned_short",
            ScalarType::Int32 => "int",
            ScalarType::UInt32 => "unsigned_int",
            ScalarType::Int64 => "vtktypeint64",
            ScalarType::UInt64 => "vtktypeuint64",
            ScalarType::Float32 => "float",
            ScalarType::Float64 => "double",
        }
    }

    pub fn is_float(self) -> bool {
        matches!(self, ScalarType::Float32 | ScalarType::Float64)
    }
}

impl fmt::Display for ScalarType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.xml_name())
    }
}

/// The values of a data array, flat (tuple-major: all components of tuple 0, then tuple 1, ...).
#[derive(Clone, Debug, PartialEq)]
pub enum ArrayData {
    Int8(Vec<i8>),
    UInt8(Vec<u8>),
    Int16(Vec<i16>),
    UInt16(Vec<u16>),
    Int32(Vec<i32>),
    UInt32(Vec<u32>),
    Int64(Vec<i64>),
    UInt64(Vec<u64>),
    Float32(Vec<f32>),
    Float64(Vec<f64>),
    /// vtkStringArray (VTK XML `type="String"`), found in field data.
    String(Vec<String>),
}

/// Applies `$body` to the vector inside any numeric variant, binding it to `$v`;
/// `$string` handles the string variant.
#[macro_export]
macro_rules! with_numeric {
    ($data:expr, $v:ident => $body:expr, $s:ident => $string:expr) => {
        match $data {
            $crate::ArrayData::Int8($v) => $body,
            $crate::ArrayData::UInt8($v) => $body,
            $crate::ArrayData::Int16($v) => $body,
            $crate::ArrayData::UInt16($v) => $body,
            $crate::ArrayData::Int32($v) => $body,
            $crate::ArrayData::UInt32($v) => $body,
            $crate::ArrayData::Int64($v) => $body,
            $crate::ArrayData::UInt64($v) => $body,
            $crate::ArrayData::Float32($v) => $body,
            $crate::ArrayData::Float64($v) => $body,
            $crate::ArrayData::String($s) => $string,
        }
    };
}

/// Builds an array of the same variant (strings included) from the vector inside `$data`,
/// bound to `$v`: `$body` is generic over the element type.
macro_rules! map_values {
    ($data:expr, $v:ident => $body:expr) => {
        match $data {
            ArrayData::Int8($v) => ArrayData::Int8($body),
            ArrayData::UInt8($v) => ArrayData::UInt8($body),
            ArrayData::Int16($v) => ArrayData::Int16($body),
            ArrayData::UInt16($v) => ArrayData::UInt16($body),
            ArrayData::Int32($v) => ArrayData::Int32($body),
            ArrayData::UInt32($v) => ArrayData::UInt32($body),
            ArrayData::Int64($v) => ArrayData::Int64($body),
            ArrayData::UInt64($v) => ArrayData::UInt64($body),
            ArrayData::Float32($v) => ArrayData::Float32($body),
            ArrayData::Float64($v) => ArrayData::Float64($body),
            ArrayData::String($v) => ArrayData::String($body),
        }
    };
}

/// Numeric element types that arrays hold, with lossless-enough conversion to f64 for ranges and
/// interpolation.
pub trait Element: Copy + Send + Sync + 'static {
    fn to_f64(self) -> f64;
    /// Converts back, rounding and saturating for integer types.
    fn from_f64(v: f64) -> Self;
}

macro_rules! element_int {
    ($($t:ty),*) => {$(
        impl Element for $t {
            fn to_f64(self) -> f64 { self as f64 }
            fn from_f64(v: f64) -> Self { v.round() as $t }
        }
    )*};
}
element_int!(i8, u8, i16, u16, i32, u32, i64, u64);
impl Element for f32 {
    fn to_f64(self) -> f64 {
        self as f64
    }
    fn from_f64(v: f64) -> Self {
        v as f32
    }
}
impl Element for f64 {
    fn to_f64(self) -> f64 {
        self
    }
    fn from_f64(v: f64) -> Self {
        v
    }
}

impl ArrayData {
    /// Element type, or `None` for strings.
    pub fn scalar_type(&self) -> Option<ScalarType> {
        Some(match self {
            ArrayData::Int8(_) => ScalarType::Int8,
            ArrayData::UInt8(_) => ScalarType::UInt8,
            ArrayData::Int16(_) => ScalarType::Int16,
            ArrayData::UInt16(_) => ScalarType::UInt16,
            ArrayData::Int32(_) => ScalarType::Int32,
            ArrayData::UInt32(_) => ScalarType::UInt32,
            ArrayData::Int64(_) => ScalarType::Int64,
            ArrayData::UInt64(_) => ScalarType::UInt64,
            ArrayData::Float32(_) => ScalarType::Float32,
            ArrayData::Float64(_) => ScalarType::Float64,
            ArrayData::String(_) => return None,
        })
    }

    /// Type name as written in VTK XML (`String` for strings).
    pub fn type_name(&self) -> &'static str {
        self.scalar_type().map_or("String", ScalarType::xml_name)
    }

    /// Number of values (tuples times components).
    pub fn len(&self) -> usize {
        with_numeric!(self, v => v.len(), s => s.len())
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// An empty array of the given type with room for `capacity` values.
    pub fn with_capacity(ty: ScalarType, capacity: usize) -> ArrayData {
        match ty {
            ScalarType::Int8 => ArrayData::Int8(Vec::with_capacity(capacity)),
            ScalarType::UInt8 => ArrayData::UInt8(Vec::with_capacity(capacity)),
            ScalarType::Int16 => ArrayData::Int16(Vec::with_capacity(capacity)),
            ScalarType::UInt16 => ArrayData::UInt16(Vec::with_capacity(capacity)),
            ScalarType::Int32 => ArrayData::Int32(Vec::with_capacity(capacity)),
            ScalarType::UInt32 => ArrayData::UInt32(Vec::with_capacity(capacity)),
            ScalarType::Int64 => ArrayData::Int64(Vec::with_capacity(capacity)),
            ScalarType::UInt64 => ArrayData::UInt64(Vec::with_capacity(capacity)),
            ScalarType::Float32 => ArrayData::Float32(Vec::with_capacity(capacity)),
            ScalarType::Float64 => ArrayData::Float64(Vec::with_capacity(capacity)),
        }
    }

    /// Integer values as i64, taking the buffer (an Int64 array is returned as it is): for ids,
    /// offsets and counts. `Err(None)` for floats and strings, `Err(Some(x))` for the first
    /// UInt64 value `x` past `i64::MAX`.
    pub fn into_i64(self) -> Result<Vec<i64>, Option<u64>> {
        Ok(match self {
            ArrayData::Int64(v) => v,
            ArrayData::Int32(v) => v.into_iter().map(i64::from).collect(),
            ArrayData::Int16(v) => v.into_iter().map(i64::from).collect(),
            ArrayData::Int8(v) => v.into_iter().map(i64::from).collect(),
            ArrayData::UInt32(v) => v.into_iter().map(i64::from).collect(),
            ArrayData::UInt16(v) => v.into_iter().map(i64::from).collect(),
            ArrayData::UInt8(v) => v.into_iter().map(i64::from).collect(),
            ArrayData::UInt64(v) => v
                .into_iter()
                .map(|x| i64::try_from(x).map_err(|_| Some(x)))
                .collect::<Result<_, _>>()?,
            _ => return Err(None),
        })
    }

    /// The values converted to type `ty` (as VTK converts a piece's array to the type its
    /// parallel file declares), and whether every value came through unchanged. Integers go
    /// between integer types exactly where they fit (saturating where not); anything involving a
    /// float goes through f64, rounded to the nearest integer for an integer target. Strings
    /// stay strings (`None` for them).
    pub fn converted(&self, ty: ScalarType) -> Option<(ArrayData, bool)> {
        fn ints(d: &ArrayData) -> Option<Vec<i128>> {
            Some(match d {
                ArrayData::Int8(v) => v.iter().map(|&x| x as i128).collect(),
                ArrayData::UInt8(v) => v.iter().map(|&x| x as i128).collect(),
                ArrayData::Int16(v) => v.iter().map(|&x| x as i128).collect(),
                ArrayData::UInt16(v) => v.iter().map(|&x| x as i128).collect(),
                ArrayData::Int32(v) => v.iter().map(|&x| x as i128).collect(),
                ArrayData::UInt32(v) => v.iter().map(|&x| x as i128).collect(),
                ArrayData::Int64(v) => v.iter().map(|&x| x as i128).collect(),
                ArrayData::UInt64(v) => v.iter().map(|&x| x as i128).collect(),
                _ => return None,
            })
        }
        if self.scalar_type()? == ty {
            return Some((self.clone(), true));
        }
        let mut exact = true;
        macro_rules! from_ints {
            ($v:expr, $t:ty, $var:ident) => {{
                let out: Vec<$t> = $v
                    .iter()
                    .map(|&x| {
                        <$t>::try_from(x).unwrap_or_else(|_| {
                            exact = false;
                            if x < 0 {
                                <$t>::MIN
                            } else {
                                <$t>::MAX
                            }
                        })
                    })
                    .collect();
                ArrayData::$var(out)
            }};
        }
        let out = match (ints(self), ty.is_float()) {
            (Some(v), false) => match ty {
                ScalarType::Int8 => from_ints!(v, i8, Int8),
                ScalarType::UInt8 => from_ints!(v, u8, UInt8),
                ScalarType::Int16 => from_ints!(v, i16, Int16),
                ScalarType::UInt16 => from_ints!(v, u16, UInt16),
                ScalarType::Int32 => from_ints!(v, i32, Int32),
                ScalarType::UInt32 => from_ints!(v, u32, UInt32),
                ScalarType::Int64 => from_ints!(v, i64, Int64),
                _ => from_ints!(v, u64, UInt64),
            },
            (source_ints, _) => {
                let v = self.to_f64_vec();
                let mut out = ArrayData::with_capacity(ty, v.len());
                with_numeric!(&mut out, o => {
                    for (i, &x) in v.iter().enumerate() {
                        let y = Element::from_f64(x);
                        let back = Element::to_f64(y);
                        // An integer source is compared as the integer it is (f64 cannot hold
                        // every 64-bit one), a float one as its value.
                        let same = match &source_ints {
                            Some(n) => back as i128 == n[i] && back.fract() == 0.0,
                            None => back == x || (back.is_nan() && x.is_nan()),
                        };
                        exact &= same;
                        o.push(y);
                    }
                }, _s => {});
                out
            }
        };
        Some((out, exact))
    }

    /// Value `i` as f64 (NaN for strings).
    pub fn get_f64(&self, i: usize) -> f64 {
        with_numeric!(self, v => v[i].to_f64(), _s => f64::NAN)
    }

    /// All values as f64 (empty for strings).
    pub fn to_f64_vec(&self) -> Vec<f64> {
        with_numeric!(self, v => v.iter().map(|x| x.to_f64()).collect(), _s => Vec::new())
    }

    /// The raw little-endian-in-memory bytes of a numeric array (native order), for hashing and
    /// bit-exact comparison. Strings give their UTF-8 bytes, each followed by a NUL.
    pub fn native_bytes(&self) -> Vec<u8> {
        with_numeric!(self, v => bytemuck::cast_slice(v).to_vec(), s => {
            let mut out = Vec::new();
            for x in s {
                out.extend_from_slice(x.as_bytes());
                out.push(0);
            }
            out
        })
    }

    /// The values' bytes in their own type, little endian whatever the machine (strings as for
    /// [`ArrayData::native_bytes`]): what checksums over files written on any machine compare.
    pub fn le_bytes(&self) -> Vec<u8> {
        fn le<T: Copy, const N: usize>(v: &[T], f: impl Fn(T) -> [u8; N]) -> Vec<u8> {
            v.iter().flat_map(|&x| f(x)).collect()
        }
        match self {
            ArrayData::Int8(v) => le(v, i8::to_le_bytes),
            ArrayData::UInt8(v) => v.clone(),
            ArrayData::Int16(v) => le(v, i16::to_le_bytes),
            ArrayData::UInt16(v) => le(v, u16::to_le_bytes),
            ArrayData::Int32(v) => le(v, i32::to_le_bytes),
            ArrayData::UInt32(v) => le(v, u32::to_le_bytes),
            ArrayData::Int64(v) => le(v, i64::to_le_bytes),
            ArrayData::UInt64(v) => le(v, u64::to_le_bytes),
            ArrayData::Float32(v) => le(v, f32::to_le_bytes),
            ArrayData::Float64(v) => le(v, f64::to_le_bytes),
            ArrayData::String(_) => self.native_bytes(),
        }
    }

    /// Bit-exact equality: NaN equals NaN with the same bits, -0.0 differs from 0.0.
    pub fn bit_eq(&self, other: &ArrayData) -> bool {
        self.scalar_type() == other.scalar_type()
            && self.len() == other.len()
            && self.native_bytes() == other.native_bytes()
    }

    /// Tuples `start .. start + count` (of `components` values each), taking the buffer: the
    /// whole array comes back as it is. Tuples past the end are not there to take.
    pub fn into_rows(self, components: usize, start: usize, count: usize) -> ArrayData {
        fn cut<T>(mut v: Vec<T>, a: usize, b: usize) -> Vec<T> {
            if a == 0 && b >= v.len() {
                return v;
            }
            v.truncate(b);
            v.drain(..a.min(v.len()));
            v
        }
        let (a, b) = (
            start.saturating_mul(components),
            start.saturating_add(count).saturating_mul(components),
        );
        map_values!(self, v => cut(v, a, b))
    }

    /// Tuples `idx[k]` (of `components` values each), in that order.
    pub fn gather(&self, components: usize, idx: &[usize]) -> ArrayData {
        fn g<T: Clone>(v: &[T], c: usize, idx: &[usize]) -> Vec<T> {
            let mut out = Vec::with_capacity(idx.len() * c);
            for &i in idx {
                out.extend_from_slice(&v[i * c..(i + 1) * c]);
            }
            out
        }
        map_values!(self, v => g(v, components, idx))
    }

    /// Appends one tuple per `(a, b, t)`: `(1 - t) * tuple[a] + t * tuple[b]`, computed in f64 and
    /// stored in the array's own type. Integer arrays (labels, ids, markers) are not blended: they
    /// take the tuple of the nearer endpoint (`a` when `t <= 0.5`). Strings take the nearer endpoint
    /// too.
    pub fn append_lerp(&mut self, components: usize, pairs: &[(usize, usize, f64)]) {
        fn lerp_into<T: Element>(
            v: &mut Vec<T>,
            c: usize,
            pairs: &[(usize, usize, f64)],
            blend: bool,
        ) {
            v.reserve(pairs.len() * c);
            for &(a, b, t) in pairs {
                for k in 0..c {
                    let x = if blend {
                        let va = v[a * c + k].to_f64();
                        let vb = v[b * c + k].to_f64();
                        T::from_f64(va + t * (vb - va))
                    } else if t <= 0.5 {
                        v[a * c + k]
                    } else {
                        v[b * c + k]
                    };
                    v.push(x);
                }
            }
        }
        match self {
            ArrayData::Float32(v) => lerp_into(v, components, pairs, true),
            ArrayData::Float64(v) => lerp_into(v, components, pairs, true),
            ArrayData::String(v) => {
                for &(a, b, t) in pairs {
                    let src = if t <= 0.5 { a } else { b };
                    for k in 0..components {
                        let x = v[src * components + k].clone();
                        v.push(x);
                    }
                }
            }
            other => with_numeric!(other, v => lerp_into(v, components, pairs, false), _s => {}),
        }
    }

    /// Smallest and largest finite value over all values (for `info`), or `None`.
    pub fn range(&self) -> Option<(f64, f64)> {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        with_numeric!(self, v => for x in v.iter() {
            let x = x.to_f64();
            if x.is_finite() {
                lo = lo.min(x);
                hi = hi.max(x);
            }
        }, _s => {});
        (lo <= hi).then_some((lo, hi))
    }
}

/// A named data array: what vtkDataArray holds.
#[derive(Clone, Debug, PartialEq)]
pub struct DataArray {
    pub name: String,
    /// Values per tuple (VTK's NumberOfComponents), at least 1.
    pub components: usize,
    /// VTK's ComponentName0.. when the file names them; empty otherwise.
    pub component_names: Vec<String>,
    /// VTK's vtkIdTypeArray (ids: `vtkOriginalCellIds`, say), written `IdType="1"` in XML and
    /// `vtkIdType` in legacy files; the data stays the integers the file held (Int64 or Int32).
    pub id_type: bool,
    pub data: ArrayData,
}

impl DataArray {
    pub fn new(name: impl Into<String>, components: usize, data: ArrayData) -> DataArray {
        DataArray {
            name: name.into(),
            components,
            component_names: Vec::new(),
            id_type: false,
            data,
        }
    }

    /// Number of tuples.
    pub fn tuples(&self) -> usize {
        self.data.len().checked_div(self.components).unwrap_or(0)
    }

    /// Same name, type, components, component names and bit-identical values.
    pub fn bit_eq(&self, other: &DataArray) -> bool {
        self.name == other.name
            && self.components == other.components
            && self.component_names == other.component_names
            && self.data.bit_eq(&other.data)
    }

    /// Range of the values, or of the tuple magnitude (L2 norm) when `components > 1`, as ParaView
    /// shows it. `None` when no value is finite.
    pub fn magnitude_range(&self) -> Option<(f64, f64)> {
        if self.components <= 1 {
            return self.data.range();
        }
        let c = self.components;
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for t in 0..self.tuples() {
            let m = (0..c)
                .map(|k| self.data.get_f64(t * c + k).powi(2))
                .sum::<f64>()
                .sqrt();
            if m.is_finite() {
                lo = lo.min(m);
                hi = hi.max(m);
            }
        }
        (lo <= hi).then_some((lo, hi))
    }
}

/// The role an array plays in its data set (VTK's active attributes: `Scalars="name"` on XML
/// PointData, or the SCALARS/VECTORS/... keyword in legacy files).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Attribute {
    Scalars,
    Vectors,
    Normals,
    Tensors,
    TCoords,
    GlobalIds,
    PedigreeIds,
}

impl Attribute {
    pub const ALL: [Attribute; 7] = [
        Attribute::Scalars,
        Attribute::Vectors,
        Attribute::Normals,
        Attribute::Tensors,
        Attribute::TCoords,
        Attribute::GlobalIds,
        Attribute::PedigreeIds,
    ];

    /// The XML attribute name on `<PointData>`/`<CellData>`.
    pub fn xml_name(self) -> &'static str {
        match self {
            Attribute::Scalars => "Scalars",
            Attribute::Vectors => "Vectors",
            Attribute::Normals => "Normals",
            Attribute::Tensors => "Tensors",
            Attribute::TCoords => "TCoords",
            Attribute::GlobalIds => "GlobalIds",
            Attribute::PedigreeIds => "PedigreeIds",
        }
    }
}

/// Point data or cell data: arrays with one tuple per point (cell), plus which are active.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Attributes {
    pub arrays: Vec<DataArray>,
    /// Active attributes by array name; legacy files also carry a lookup table name per SCALARS
    /// array, kept in `lookup_tables`.
    pub active: Vec<(Attribute, String)>,
    /// `(array name, lookup table name)` from legacy `SCALARS ... LOOKUP_TABLE name` lines other than
    /// `default`.
    pub lookup_tables: Vec<(String, String)>,
}

impl Attributes {
    pub fn get(&self, name: &str) -> Option<&DataArray> {
        self.arrays.iter().find(|a| a.name == name)
    }

    pub fn get_mut(&mut self, name: &str) -> Option<&mut DataArray> {
        self.arrays.iter_mut().find(|a| a.name == name)
    }

    /// Adds the array, replacing one of the same name.
    pub fn insert(&mut self, array: DataArray) {
        match self.arrays.iter_mut().find(|a| a.name == array.name) {
            Some(slot) => *slot = array,
            None => self.arrays.push(array),
        }
    }

    /// The array named active for `role`, if any.
    pub fn active(&self, role: Attribute) -> Option<&DataArray> {
        let name = self.active.iter().find(|(r, _)| *r == role)?;
        self.get(&name.1)
    }

    /// Every array gathered at tuples `idx` (cell data copied to child cells, say).
    pub fn gather(&self, idx: &[usize]) -> Attributes {
        Attributes {
            arrays: self
                .arrays
                .iter()
                .map(|a| DataArray {
                    name: a.name.clone(),
                    components: a.components,
                    component_names: a.component_names.clone(),
                    id_type: a.id_type,
                    data: a.data.gather(a.components, idx),
                })
                .collect(),
            active: self.active.clone(),
            lookup_tables: self.lookup_tables.clone(),
        }
    }

    /// Appends interpolated tuples to every array; see [`ArrayData::append_lerp`].
    pub fn append_lerp(&mut self, pairs: &[(usize, usize, f64)]) {
        for a in &mut self.arrays {
            a.data.append_lerp(a.components, pairs);
        }
    }
}

/// VTK cell type ids (vtkCellType.h).
pub mod cell_type {
    pub const EMPTY_CELL: u8 = 0;
    pub const VERTEX: u8 = 1;
    pub const POLY_VERTEX: u8 = 2;
    pub const LINE: u8 = 3;
    pub const POLY_LINE: u8 = 4;
    pub const TRIANGLE: u8 = 5;
    pub const TRIANGLE_STRIP: u8 = 6;
    pub const POLYGON: u8 = 7;
    pub const PIXEL: u8 = 8;
    pub const QUAD: u8 = 9;
    pub const TETRA: u8 = 10;
    pub const VOXEL: u8 = 11;
    pub const HEXAHEDRON: u8 = 12;
    pub const WEDGE: u8 = 13;
    pub const PYRAMID: u8 = 14;
    pub const PENTAGONAL_PRISM: u8 = 15;
    pub const HEXAGONAL_PRISM: u8 = 16;
    pub const QUADRATIC_EDGE: u8 = 21;
    pub const QUADRATIC_TRIANGLE: u8 = 22;
    pub const QUADRATIC_QUAD: u8 = 23;
    pub const QUADRATIC_TETRA: u8 = 24;
    pub const QUADRATIC_HEXAHEDRON: u8 = 25;
    pub const QUADRATIC_WEDGE: u8 = 26;
    pub const QUADRATIC_PYRAMID: u8 = 27;
    pub const BIQUADRATIC_QUAD: u8 = 28;
    pub const TRIQUADRATIC_HEXAHEDRON: u8 = 29;
    pub const QUADRATIC_LINEAR_QUAD: u8 = 30;
    pub const QUADRATIC_LINEAR_WEDGE: u8 = 31;
    pub const BIQUADRATIC_QUADRATIC_WEDGE: u8 = 32;
    pub const BIQUADRATIC_QUADRATIC_HEXAHEDRON: u8 = 33;
    pub const BIQUADRATIC_TRIANGLE: u8 = 34;
    pub const CUBIC_LINE: u8 = 35;
    pub const QUADRATIC_POLYGON: u8 = 36;
    pub const TRIQUADRATIC_PYRAMID: u8 = 37;
    pub const CONVEX_POINT_SET: u8 = 41;
    pub const POLYHEDRON: u8 = 42;
    pub const LAGRANGE_CURVE: u8 = 68;
    pub const LAGRANGE_TRIANGLE: u8 = 69;
    pub const LAGRANGE_QUADRILATERAL: u8 = 70;
    pub const LAGRANGE_TETRAHEDRON: u8 = 71;
    pub const LAGRANGE_HEXAHEDRON: u8 = 72;
    pub const LAGRANGE_WEDGE: u8 = 73;
    pub const LAGRANGE_PYRAMID: u8 = 74;
    pub const BEZIER_CURVE: u8 = 75;
    pub const BEZIER_TRIANGLE: u8 = 76;
    pub const BEZIER_QUADRILATERAL: u8 = 77;
    pub const BEZIER_TETRAHEDRON: u8 = 78;
    pub const BEZIER_HEXAHEDRON: u8 = 79;
    pub const BEZIER_WEDGE: u8 = 80;
    pub const BEZIER_PYRAMID: u8 = 81;

    /// The VTK name of a cell type (`VTK_TETRA` without the prefix, lower case).
    pub fn name(t: u8) -> &'static str {
        match t {
            EMPTY_CELL => "empty",
            VERTEX => "vertex",
            POLY_VERTEX => "poly_vertex",
            LINE => "line",
            POLY_LINE => "poly_line",
            TRIANGLE => "triangle",
            TRIANGLE_STRIP => "triangle_strip",
            POLYGON => "polygon",
            PIXEL => "pixel",
            QUAD => "quad",
            TETRA => "tetra",
            VOXEL => "voxel",
            HEXAHEDRON => "hexahedron",
            WEDGE => "wedge",
            PYRAMID => "pyramid",
            PENTAGONAL_PRISM => "pentagonal_prism",
            HEXAGONAL_PRISM => "hexagonal_prism",
            QUADRATIC_EDGE => "quadratic_edge",
            QUADRATIC_TRIANGLE => "quadratic_triangle",
            QUADRATIC_QUAD => "quadratic_quad",
            QUADRATIC_TETRA => "quadratic_tetra",
            QUADRATIC_HEXAHEDRON => "quadratic_hexahedron",
            QUADRATIC_WEDGE => "quadratic_wedge",
            QUADRATIC_PYRAMID => "quadratic_pyramid",
            BIQUADRATIC_QUAD => "biquadratic_quad",
            TRIQUADRATIC_HEXAHEDRON => "triquadratic_hexahedron",
            QUADRATIC_LINEAR_QUAD => "quadratic_linear_quad",
            QUADRATIC_LINEAR_WEDGE => "quadratic_linear_wedge",
            BIQUADRATIC_QUADRATIC_WEDGE => "biquadratic_quadratic_wedge",
            BIQUADRATIC_QUADRATIC_HEXAHEDRON => "biquadratic_quadratic_hexahedron",
            BIQUADRATIC_TRIANGLE => "biquadratic_triangle",
            CUBIC_LINE => "cubic_line",
            QUADRATIC_POLYGON => "quadratic_polygon",
            TRIQUADRATIC_PYRAMID => "triquadratic_pyramid",
            CONVEX_POINT_SET => "convex_point_set",
            POLYHEDRON => "polyhedron",
            LAGRANGE_CURVE => "lagrange_curve",
            LAGRANGE_TRIANGLE => "lagrange_triangle",
            LAGRANGE_QUADRILATERAL => "lagrange_quadrilateral",
            LAGRANGE_TETRAHEDRON => "lagrange_tetrahedron",
            LAGRANGE_HEXAHEDRON => "lagrange_hexahedron",
            LAGRANGE_WEDGE => "lagrange_wedge",
            LAGRANGE_PYRAMID => "lagrange_pyramid",
            BEZIER_CURVE => "bezier_curve",
            BEZIER_TRIANGLE => "bezier_triangle",
            BEZIER_QUADRILATERAL => "bezier_quadrilateral",
            BEZIER_TETRAHEDRON => "bezier_tetrahedron",
            BEZIER_HEXAHEDRON => "bezier_hexahedron",
            BEZIER_WEDGE => "bezier_wedge",
            BEZIER_PYRAMID => "bezier_pyramid",
            _ => "unknown",
        }
    }

    /// Number of points a cell of this type has, or `None` for variable-size types
    /// (poly vertex, poly line, strip, polygon, polyhedron, quadratic polygon, convex point set,
    /// Lagrange and Bezier cells) and unknown ids.
    pub fn fixed_size(t: u8) -> Option<usize> {
        Some(match t {
            EMPTY_CELL => 0,
            VERTEX => 1,
            LINE => 2,
            TRIANGLE => 3,
            PIXEL | QUAD | TETRA => 4,
            PYRAMID => 5,
            WEDGE => 6,
            VOXEL | HEXAHEDRON => 8,
            PENTAGONAL_PRISM => 10,
            HEXAGONAL_PRISM => 12,
            QUADRATIC_EDGE => 3,
            QUADRATIC_TRIANGLE => 6,
            QUADRATIC_QUAD => 8,
            QUADRATIC_TETRA => 10,
            QUADRATIC_HEXAHEDRON => 20,
            QUADRATIC_WEDGE => 15,
            QUADRATIC_PYRAMID => 13,
            BIQUADRATIC_QUAD => 9,
            TRIQUADRATIC_HEXAHEDRON => 27,
            QUADRATIC_LINEAR_QUAD => 6,
            QUADRATIC_LINEAR_WEDGE => 12,
            BIQUADRATIC_QUADRATIC_WEDGE => 18,
            BIQUADRATIC_QUADRATIC_HEXAHEDRON => 24,
            BIQUADRATIC_TRIANGLE => 7,
            CUBIC_LINE => 4,
            TRIQUADRATIC_PYRAMID => 19,
            _ => return None,
        })
    }

    /// Whether `t` is a cell type id this crate knows.
    pub fn is_known(t: u8) -> bool {
        fixed_size(t).is_some()
            || is_higher_order(t)
            || matches!(
                t,
                POLY_VERTEX
                    | POLY_LINE
                    | TRIANGLE_STRIP
                    | POLYGON
                    | QUADRATIC_POLYGON
                    | POLYHEDRON
                    | CONVEX_POINT_SET
            )
    }

    /// Whether `t` is a Lagrange cell (types 68-74).
    pub fn is_lagrange(t: u8) -> bool {
        (LAGRANGE_CURVE..=LAGRANGE_PYRAMID).contains(&t)
    }

    /// Whether `t` is a Bezier cell (types 75-81).
    pub fn is_bezier(t: u8) -> bool {
        (BEZIER_CURVE..=BEZIER_PYRAMID).contains(&t)
    }

    /// Whether `t` is an arbitrary-order Lagrange or Bezier cell, whose order the file gives only
    /// through its point count (or a `HigherOrderDegrees` cell array).
    pub fn is_higher_order(t: u8) -> bool {
        is_lagrange(t) || is_bezier(t)
    }

    /// The linear cell with the same shape as a Lagrange or Bezier cell (line, triangle, quad,
    /// tetra, hexahedron, wedge, pyramid), or `None` for other types. VTK lists a higher-order
    /// cell's corners first, in its linear counterpart's order, so the first
    /// `fixed_size(linear_counterpart(t))` point ids of such a cell are its corners (Lagrange) or
    /// its corner control points, which Bezier cells interpolate.
    pub fn linear_counterpart(t: u8) -> Option<u8> {
        let shape = if is_lagrange(t) {
            t - LAGRANGE_CURVE
        } else if is_bezier(t) {
            t - BEZIER_CURVE
        } else {
            return None;
        };
        [LINE, TRIANGLE, QUAD, TETRA, HEXAHEDRON, WEDGE, PYRAMID]
            .get(shape as usize)
            .copied()
    }

    /// The fewest points a variable-size cell of type `t` can have, where the type sets one:
    /// the corners of a Lagrange or Bezier cell's shape (order 1), and 4 for a convex point set
    /// (the fewest that enclose a volume). `None` for other types, whose sizes are not checked.
    pub fn min_size(t: u8) -> Option<usize> {
        if t == CONVEX_POINT_SET {
            return Some(4);
        }
        linear_counterpart(t).and_then(fixed_size)
    }

    /// Topological dimension: 0 points, 1 lines, 2 surfaces, 3 solids.
    pub fn dimension(t: u8) -> u8 {
        match t {
            EMPTY_CELL | VERTEX | POLY_VERTEX => 0,
            LINE | POLY_LINE | QUADRATIC_EDGE | CUBIC_LINE | LAGRANGE_CURVE | BEZIER_CURVE => 1,
            TRIANGLE
            | TRIANGLE_STRIP
            | POLYGON
            | PIXEL
            | QUAD
            | QUADRATIC_TRIANGLE
            | QUADRATIC_QUAD
            | BIQUADRATIC_QUAD
            | QUADRATIC_LINEAR_QUAD
            | BIQUADRATIC_TRIANGLE
            | QUADRATIC_POLYGON
            | LAGRANGE_TRIANGLE
            | LAGRANGE_QUADRILATERAL
            | BEZIER_TRIANGLE
            | BEZIER_QUADRILATERAL => 2,
            _ => 3,
        }
    }
}

/// The four cell sections of VTK PolyData (XML `<Verts>`... or legacy `VERTICES`...), in the
/// order VTK numbers their cells; a PolyData read as a [`Grid`] lists its cells in this order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PolySection {
    Verts,
    Lines,
    Polys,
    Strips,
}

impl PolySection {
    pub const ALL: [PolySection; 4] = [Self::Verts, Self::Lines, Self::Polys, Self::Strips];

    /// The cell type of a cell of `size` points in this section: a 1-point vert is a vertex, a
    /// 2-point line a line, a 3-point poly a triangle and a 4-point one a quad; longer ones are
    /// poly-vertices, poly-lines and polygons; a strip is a triangle strip.
    pub fn cell_type(self, size: usize) -> u8 {
        match (self, size) {
            (Self::Verts, 1) => cell_type::VERTEX,
            (Self::Verts, _) => cell_type::POLY_VERTEX,
            (Self::Lines, 2) => cell_type::LINE,
            (Self::Lines, _) => cell_type::POLY_LINE,
            (Self::Polys, 3) => cell_type::TRIANGLE,
            (Self::Polys, 4) => cell_type::QUAD,
            (Self::Polys, _) => cell_type::POLYGON,
            (Self::Strips, _) => cell_type::TRIANGLE_STRIP,
        }
    }
}

/// Cells as VTK 9 stores them: a type per cell, and each cell's point ids in `connectivity`
/// between `offsets[i]` and `offsets[i + 1]`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Cells {
    pub types: Vec<u8>,
    /// `types.len() + 1` entries, starting at 0 and ending at `connectivity.len()`.
    pub offsets: Vec<i64>,
    pub connectivity: Vec<i64>,
    /// VTK_POLYHEDRON face streams (XML `faces`/`faceoffsets`), kept verbatim when present:
    /// `faceoffsets[i]` is the end of cell i's stream in `faces`, or -1 for non-polyhedra.
    pub polyhedron_faces: Option<(Vec<i64>, Vec<i64>)>,
}

impl Cells {
    pub fn new() -> Cells {
        Cells {
            types: Vec::new(),
            offsets: vec![0],
            connectivity: Vec::new(),
            polyhedron_faces: None,
        }
    }

    pub fn len(&self) -> usize {
        self.types.len()
    }

    pub fn is_empty(&self) -> bool {
        self.types.is_empty()
    }

    /// Point ids of cell `i`.
    pub fn cell(&self, i: usize) -> &[i64] {
        &self.connectivity[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    /// Appends a cell.
    pub fn push(&mut self, ty: u8, ids: &[i64]) {
        if self.offsets.is_empty() {
            self.offsets.push(0);
        }
        self.types.push(ty);
        self.connectivity.extend_from_slice(ids);
        self.offsets.push(self.connectivity.len() as i64);
    }
}

impl Grid {
    /// Whether any cell is a Lagrange or Bezier hexahedron, whose node order depends on the
    /// file's version (see [`Grid::swap_hex_edges_10_11`]).
    pub fn has_higher_order_hexahedra(&self) -> bool {
        self.cells
            .types
            .iter()
            .any(|&t| t == cell_type::LAGRANGE_HEXAHEDRON || t == cell_type::BEZIER_HEXAHEDRON)
    }

    /// Swaps the nodes of edges 10 and 11 of every Lagrange and Bezier hexahedron. VTK 9.0
    /// swapped those two edges' places; its readers convert files older than XML 2.2 and legacy
    /// 5.1 on reading (measured on VTK 9.1: a 64-node hexahedron's ids 28-29 and 30-31 trade
    /// places), so tetkit does the same there, and again when writing legacy 4.2. The orders
    /// come from the cell array `HigherOrderDegrees` when it has three components, else from a
    /// cube node count; a cell with neither is left as it is (VTK cannot place its edges
    /// either).
    pub fn swap_hex_edges_10_11(&mut self) {
        if !self.has_higher_order_hexahedra() {
            return;
        }
        let degrees = self
            .cell_data
            .get("HigherOrderDegrees")
            .filter(|a| a.components == 3 && a.data.len() == 3 * self.cells.len())
            .map(|a| a.data.to_f64_vec());
        for i in 0..self.cells.len() {
            let t = self.cells.types[i];
            if t != cell_type::LAGRANGE_HEXAHEDRON && t != cell_type::BEZIER_HEXAHEDRON {
                continue;
            }
            let (a, b) = (
                self.cells.offsets[i] as usize,
                self.cells.offsets[i + 1] as usize,
            );
            let n = b - a;
            let p = match &degrees {
                Some(d) => [d[3 * i], d[3 * i + 1], d[3 * i + 2]].map(|x| x.max(1.0) as usize),
                None => {
                    let k = (n as f64).cbrt().round() as usize;
                    if k < 2 || k * k * k != n {
                        continue;
                    }
                    [k - 1; 3]
                }
            };
            // Edges 0-7 run along x and y (four each), 8-11 along z.
            let m = p[2] - 1;
            let e10 = 8 + 4 * (p[0] - 1) + 4 * (p[1] - 1) + 2 * m;
            if m == 0 || e10 + 2 * m > n {
                continue;
            }
            let ids = &mut self.cells.connectivity[a..b];
            for k in 0..m {
                ids.swap(e10 + k, e10 + m + k);
            }
        }
    }
}

/// An array that [`Grid::rename_duplicates`] renamed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Renamed {
    /// `point`, `cell` or `field`.
    pub set: &'static str,
    /// The name it shared with an earlier array.
    pub name: String,
    /// Its new name.
    pub new_name: String,
    /// The earlier array's type and its own (`Float32`, `String`, ...).
    pub first_type: &'static str,
    pub its_type: &'static str,
}

impl fmt::Display for Renamed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} data has two arrays named '{}' ({} and {}); the second is read as '{}'",
            self.set, self.name, self.first_type, self.its_type, self.new_name
        )
    }
}

fn rename_in(set: &'static str, arrays: &mut [DataArray], out: &mut Vec<Renamed>) {
    let mut taken: std::collections::HashSet<String> =
        arrays.iter().map(|a| a.name.clone()).collect();
    let mut seen: std::collections::HashMap<String, &'static str> = Default::default();
    for a in arrays.iter_mut() {
        let Some(&first_type) = seen.get(&a.name) else {
            seen.insert(a.name.clone(), a.data.type_name());
            continue;
        };
        let new_name = (2u64..)
            .map(|k| format!("{} ({k})", a.name))
            .find(|n| !taken.contains(n))
            .unwrap_or_default();
        taken.insert(new_name.clone());
        seen.insert(new_name.clone(), a.data.type_name());
        out.push(Renamed {
            set,
            name: std::mem::replace(&mut a.name, new_name.clone()),
            new_name,
            first_type,
            its_type: a.data.type_name(),
        });
    }
}

/// The smallest `i < n` with `bad(i)`, scanning chunks of 64 Ki indices in parallel.
fn first_where(n: usize, bad: impl Fn(usize) -> bool + Sync) -> Option<usize> {
    const CHUNK: usize = 1 << 16;
    (0..n.div_ceil(CHUNK))
        .into_par_iter()
        .find_map_first(|k| (k * CHUNK..n.min((k + 1) * CHUNK)).find(|&i| bad(i)))
}

/// An unstructured grid: points, cells, and the point, cell and field data arrays that go with them.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// Point coordinates: 3 components, in the file's own type (usually Float32 or Float64).
    pub points: DataArray,
    pub cells: Cells,
    pub point_data: Attributes,
    pub cell_data: Attributes,
    /// Field data (VTK `<FieldData>` or legacy dataset-level `FIELD`): arrays of any length.
    pub field_data: Vec<DataArray>,
}

impl Default for Grid {
    fn default() -> Self {
        Grid {
            points: DataArray::new("Points", 3, ArrayData::Float64(Vec::new())),
            cells: Cells::new(),
            point_data: Attributes::default(),
            cell_data: Attributes::default(),
            field_data: Vec::new(),
        }
    }
}

impl Grid {
    pub fn num_points(&self) -> usize {
        self.points.tuples()
    }

    pub fn num_cells(&self) -> usize {
        self.cells.len()
    }

    /// Point `i` as f64.
    pub fn point(&self, i: usize) -> [f64; 3] {
        let d = &self.points.data;
        [d.get_f64(3 * i), d.get_f64(3 * i + 1), d.get_f64(3 * i + 2)]
    }

    /// All points as f64 triples.
    pub fn points_f64(&self) -> Vec<[f64; 3]> {
        match &self.points.data {
            ArrayData::Float64(v) => v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
            ArrayData::Float32(v) => v
                .chunks_exact(3)
                .map(|c| [c[0] as f64, c[1] as f64, c[2] as f64])
                .collect(),
            _ => (0..self.num_points()).map(|i| self.point(i)).collect(),
        }
    }

    /// Axis-aligned bounds `[xmin, xmax, ymin, ymax, zmin, zmax]` over finite points, as VTK
    /// orders them; `None` for an empty grid.
    pub fn bounds(&self) -> Option<[f64; 6]> {
        let mut b = [
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for i in 0..self.num_points() {
            let p = self.point(i);
            if p.iter().all(|x| x.is_finite()) {
                for k in 0..3 {
                    b[2 * k] = b[2 * k].min(p[k]);
                    b[2 * k + 1] = b[2 * k + 1].max(p[k]);
                }
            }
        }
        (b[0] <= b[1]).then_some(b)
    }

    /// Checks the structure: every coordinate is finite (NaN or infinite points make every later
    /// stage meaningless, so they are refused at the door); offsets start at 0, never decrease and end at the connectivity length;
    /// every cell type is known and has its fixed point count (or, for Lagrange, Bezier and convex
    /// point set cells, at least their minimum); every point id is in range; every
    /// point (cell) data array has one tuple per point (cell); points have 3 components.
    /// The message names the array or cell that is wrong.
    pub fn validate(&self) -> Result<(), String> {
        if self.points.components != 3 {
            return Err(format!(
                "Points has {} components, expected 3",
                self.points.components
            ));
        }
        if self.points.data.scalar_type().is_none() {
            return Err("Points must be numeric".into());
        }
        if self.points.data.len() % 3 != 0 {
            return Err(format!(
                "Points has {} values, not a multiple of 3",
                self.points.data.len()
            ));
        }
        // Each check runs over large chunks in parallel and reports the first offender, as a
        // sequential scan would: validate runs on every read, and on a 5M-tet mesh a serial pass
        // costs a fifth of the I/O. (Per-element parallel iterators cost more than they gain.)
        let first_bad_point = match &self.points.data {
            ArrayData::Float32(v) => first_where(v.len() / 3, |i| {
                v[3 * i..3 * i + 3].iter().any(|x| !x.is_finite())
            }),
            ArrayData::Float64(v) => first_where(v.len() / 3, |i| {
                v[3 * i..3 * i + 3].iter().any(|x| !x.is_finite())
            }),
            _ => None,
        };
        if let Some(i) = first_bad_point {
            return Err(format!(
                "point {i} has a non-finite coordinate {:?}",
                self.point(i)
            ));
        }
        let np = self.num_points() as i64;
        let c = &self.cells;
        if c.offsets.len() != c.types.len() + 1 {
            return Err(format!(
                "offsets has {} entries for {} cells (expected cells + 1)",
                c.offsets.len(),
                c.types.len()
            ));
        }
        if c.offsets[0] != 0 {
            return Err(format!("offsets start at {}, expected 0", c.offsets[0]));
        }
        if *c.offsets.last().unwrap_or(&0) != c.connectivity.len() as i64 {
            return Err(format!(
                "offsets end at {}, but connectivity has {} entries",
                c.offsets.last().unwrap_or(&0),
                c.connectivity.len()
            ));
        }
        let cell_ok = |i: usize| {
            let (a, b) = (c.offsets[i], c.offsets[i + 1]);
            let t = c.types[i];
            b >= a
                && cell_type::is_known(t)
                && match cell_type::fixed_size(t) {
                    Some(n) => (b - a) as usize == n,
                    None => cell_type::min_size(t).map_or(true, |m| (b - a) as usize >= m),
                }
        };
        if let Some(i) = first_where(c.types.len(), |i| !cell_ok(i)) {
            let (a, b) = (c.offsets[i], c.offsets[i + 1]);
            if b < a {
                return Err(format!("offsets decrease at cell {i} ({a} then {b})"));
            }
            let t = c.types[i];
            if !cell_type::is_known(t) {
                return Err(format!("cell {i} has unknown cell type {t}"));
            }
            if let Some(n) = cell_type::fixed_size(t) {
                if (b - a) as usize != n {
                    return Err(format!(
                        "cell {i} is a {} with {} points, expected {n}",
                        cell_type::name(t),
                        b - a
                    ));
                }
            }
            if let Some(m) = cell_type::min_size(t) {
                return Err(format!(
                    "cell {i} is a {} with {} points, expected at least {m}",
                    cell_type::name(t),
                    b - a
                ));
            }
        }
        if let Some(bad) = first_where(c.connectivity.len(), |k| {
            let p = c.connectivity[k];
            p < 0 || p >= np
        }) {
            return Err(format!(
                "connectivity entry {bad} is point id {}, out of range ({})",
                c.connectivity[bad],
                crate::error::numbered(np as u64, "point", 0)
            ));
        }
        let nc = c.types.len();
        for (what, set, n) in [
            ("point", &self.point_data, np as usize),
            ("cell", &self.cell_data, nc),
        ] {
            for a in &set.arrays {
                if a.components == 0 {
                    return Err(format!("{what} data array '{}' has 0 components", a.name));
                }
                if a.data.len() != n * a.components {
                    return Err(format!(
                        "{what} data array '{}' has {} values, expected {n} tuples x {} components",
                        a.name,
                        a.data.len(),
                        a.components
                    ));
                }
            }
        }
        Ok(())
    }

    /// Gives every point, cell and field data array a name no other array of its set has: VTK
    /// keeps one array per name, so a file that repeats a name would be written back ambiguous.
    /// The first array keeps the name, a later one becomes `NAME (2)` (or the first free
    /// `NAME (k)`); values, type and components are untouched. Each set keeps at most one
    /// active array per role, the first named, which is the array that kept its name.
    pub fn rename_duplicates(&mut self) -> Vec<Renamed> {
        let mut out = Vec::new();
        for (set, attrs) in [
            ("point", &mut self.point_data),
            ("cell", &mut self.cell_data),
        ] {
            rename_in(set, &mut attrs.arrays, &mut out);
            let mut seen = Vec::new();
            attrs.active.retain(|(role, _)| {
                let first = !seen.contains(role);
                seen.push(*role);
                first
            });
        }
        rename_in("field", &mut self.field_data, &mut out);
        out
    }

    /// Number of cells of each type, sorted by type id.
    pub fn cell_type_counts(&self) -> Vec<(u8, usize)> {
        let mut counts = [0usize; 256];
        for &t in &self.cells.types {
            counts[t as usize] += 1;
        }
        (0..256)
            .filter(|&t| counts[t] > 0)
            .map(|t| (t as u8, counts[t]))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conversion_keeps_what_fits_and_says_when_a_value_changed(
    ) -> std::result::Result<(), &'static str> {
        let f = ArrayData::Float32(vec![0.25, -3.5, f32::NAN]);
        let (g, exact) = f.converted(ScalarType::Float64).ok_or("strings")?;
        assert!(exact);
        assert_eq!(g.get_f64(1), -3.5);
        assert!(g.get_f64(2).is_nan());
        let (g, exact) = ArrayData::Int64(vec![7, -(1 << 40)])
            .converted(ScalarType::Int32)
            .ok_or("strings")?;
        assert!(!exact);
        assert!(matches!(g, ArrayData::Int32(ref v) if v == &[7, i32::MIN]));
        let (g, exact) = ArrayData::UInt32(vec![u32::MAX])
            .converted(ScalarType::Int64)
            .ok_or("strings")?;
        assert!(exact);
        assert_eq!(g.get_f64(0), u32::MAX as f64);
        let (_, exact) = ArrayData::UInt64(vec![u64::MAX])
            .converted(ScalarType::Float64)
            .ok_or("strings")?;
        assert!(!exact, "u64::MAX does not survive f64");
        let (g, exact) = ArrayData::Float64(vec![2.5, 1e300])
            .converted(ScalarType::Int16)
            .ok_or("strings")?;
        assert!(!exact);
        assert!(matches!(g, ArrayData::Int16(ref v) if v == &[3, i16::MAX]));
        assert!(ArrayData::String(vec!["a".into()])
            .converted(ScalarType::Int8)
            .is_none());
        Ok(())
    }

    fn arr(name: &str, data: ArrayData) -> DataArray {
        DataArray::new(name, 1, data)
    }

    #[test]
    fn repeated_names_are_made_unique_keeping_the_first_and_every_value() {
        let mut g = Grid::default();
        g.point_data.arrays = vec![
            arr("p", ArrayData::Float32(vec![])),
            arr("p (2)", ArrayData::Int8(vec![])),
            arr("p", ArrayData::Float64(vec![])),
            arr("p", ArrayData::Int32(vec![])),
            arr("q", ArrayData::Int32(vec![])),
        ];
        g.point_data.active = vec![
            (Attribute::Scalars, "p".into()),
            (Attribute::Scalars, "p".into()),
            (Attribute::Vectors, "q".into()),
        ];
        g.cell_data.arrays = vec![arr("c", ArrayData::Int32(vec![]))];
        g.field_data = vec![
            arr("f", ArrayData::String(vec![])),
            arr("f", ArrayData::UInt8(vec![])),
        ];
        let before = g.clone();
        let r = g.rename_duplicates();
        let names: Vec<&str> = g
            .point_data
            .arrays
            .iter()
            .map(|a| a.name.as_str())
            .collect();
        assert_eq!(names, ["p", "p (2)", "p (3)", "p (4)", "q"]);
        assert_eq!(g.field_data[1].name, "f (2)");
        assert_eq!(g.cell_data, before.cell_data);
        for (a, b) in g.point_data.arrays.iter().zip(&before.point_data.arrays) {
            assert!(a.data.bit_eq(&b.data) && a.components == b.components);
        }
        assert_eq!(
            g.point_data.active,
            vec![
                (Attribute::Scalars, "p".to_string()),
                (Attribute::Vectors, "q".to_string())
            ]
        );
        assert_eq!(r.len(), 3);
        assert_eq!(
            r[0].to_string(),
            "point data has two arrays named 'p' (Float32 and Float64); the second is read as 'p (3)'"
        );
        assert_eq!(
            r[2].to_string(),
            "field data has two arrays named 'f' (String and UInt8); the second is read as 'f (2)'"
        );
        assert!(g.rename_duplicates().is_empty());
    }
}
