//! Parallel VTU (.pvtu): a small XML file naming .vtu pieces, read into one merged grid.

use crate::{FormatError, Grid, Result, WriteOptions};
use std::path::Path;

/// Reads a .pvtu (its bytes already read from `path`) and all its pieces, merged in piece order.
pub fn read(path: &Path, _bytes: &[u8]) -> Result<Grid> {
    Err(FormatError::whole("PVTU reading is not implemented yet").with_file(path))
}

/// Writes `pieces` as `path` plus one .vtu per piece in a folder named after the file's stem,
/// as ParaView does; all files appear or none do.
pub fn write(path: &Path, _pieces: &[Grid], _opts: &WriteOptions) -> Result<()> {
    Err(FormatError::whole("PVTU writing is not implemented yet").with_file(path))
}
