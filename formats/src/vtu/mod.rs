//! VTK XML unstructured grid (.vtu): every encoding, compressor, header type and byte order.

pub mod pvtu;

use crate::{FormatError, Grid, Result, WriteOptions};
use std::io::Write;

/// Parses a whole .vtu file held in memory.
pub fn read(_bytes: &[u8]) -> Result<Grid> {
    Err(FormatError::whole("VTU reading is not implemented yet"))
}

/// Writes `grid` as .vtu with the given encoding and compression.
pub fn write(_w: &mut dyn Write, _grid: &Grid, _opts: &WriteOptions) -> Result<()> {
    Err(FormatError::whole("VTU writing is not implemented yet"))
}
