//! Writing `.node`/`.ele` (+ `.face`).

use crate::{FormatError, Grid, Result};
use std::path::Path;

/// Writes `.node` and `.ele` beside `path` (both or neither).
pub fn write(path: &Path, _grid: &Grid) -> Result<()> {
    Err(FormatError::whole("TetGen writing is not implemented yet").with_file(path))
}
