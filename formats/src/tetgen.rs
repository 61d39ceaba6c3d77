//! TetGen .node/.ele (+ .face, .neigh) meshes.

use crate::{FormatError, Grid, Result};
use std::path::Path;

/// Reads the mesh named by any of its files (`mesh.1.node`, `mesh.1.ele`, ...).
pub fn read(path: &Path) -> Result<Grid> {
    Err(FormatError::whole("TetGen reading is not implemented yet").with_file(path))
}

/// Writes `.node` and `.ele` beside `path` (both or neither).
pub fn write(path: &Path, _grid: &Grid) -> Result<()> {
    Err(FormatError::whole("TetGen writing is not implemented yet").with_file(path))
}
