//! Legacy VTK (.vtk) unstructured grids: versions up to 4.2 and 5.1, ASCII and big-endian binary.

use crate::{FormatError, Grid, Result, WriteOptions};
use std::io::Write;

/// Parses a whole legacy .vtk file held in memory.
pub fn read(_bytes: &[u8]) -> Result<Grid> {
    Err(FormatError::whole(
        "legacy VTK reading is not implemented yet",
    ))
}

/// Writes `grid` as legacy VTK (binary unless the encoding is ascii).
pub fn write(_w: &mut dyn Write, _grid: &Grid, _opts: &WriteOptions) -> Result<()> {
    Err(FormatError::whole(
        "legacy VTK writing is not implemented yet",
    ))
}
