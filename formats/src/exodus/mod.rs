//! Exodus II meshes read into a [`Grid`]; read only. Classic NetCDF (CDF-1, CDF-2, CDF-5) is
//! parsed here (netcdf.rs); NetCDF-4 (HDF5, as meshio and SEACAS's netCDF-4 output write it) is
//! read through the pure-Rust `netcdf-reader` crate (nc4.rs); both answer read.rs alike.

mod glom;
mod nc4;
pub(crate) use nc4::is_hdf5;
mod netcdf;
mod read;
mod types;

#[cfg(test)]
mod tests;

use crate::pvd::Selector;
use crate::{FormatError, Grid, Result};
use std::path::{Path, PathBuf};

/// Array names the reader gives.
pub mod names {
    /// Cell array: the element block id (`eb_prop1`), as VTK's Exodus reader names it.
    pub const OBJECT_ID: &str = "ObjectId";
    /// Cell array from `elem_num_map` (1, 2, ... without one).
    pub const ELEMENT_ID: &str = "GlobalElementId";
    /// Point array from `node_num_map` (1, 2, ... without one).
    pub const NODE_ID: &str = "GlobalNodeId";
    /// Field data: the block names (`eb_names`) in block order.
    pub const BLOCK_NAMES: &str = "exodus:block_names";
    /// Field data: the times of all steps (`time_whole`; NaN where a step has none), present
    /// exactly when the file has steps.
    pub const TIME: &str = "exodus:time";
    /// Point arrays `nodeset:NAME`: 1 for the nodes of the node set.
    pub const NODE_SET_PREFIX: &str = "nodeset:";
}

/// The extensions Exodus files go by.
pub const EXTENSIONS: [&str; 6] = ["exo", "e", "ex2", "exii", "g", "gen"];

pub(crate) use crate::warn;

/// Whether `path` has one of the Exodus [`EXTENSIONS`] (any case).
pub fn has_extension(path: &Path) -> bool {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .is_some_and(|e| EXTENSIONS.contains(&e.as_str()))
}

/// Splits `FILE.exo@K` / `FILE.exo@last` into the file and the time step; `None` for any other
/// path.
pub fn split_selector(path: &Path) -> Option<(PathBuf, Selector)> {
    crate::pvd::split_step(path, has_extension)
}

/// The times of the file's steps (`time_whole`; NaN where a step has none), for listing.
pub fn times(path: &Path) -> Result<Vec<f64>> {
    let bytes = std::fs::read(path).map_err(|e| FormatError::io(path, e))?;
    read::times_of(&bytes, path)
}

/// Reads an Exodus II file from memory at time step `sel`; `path` names it in errors.
///
/// Points are the nodes (`coordx`/`coordy`/`coordz`, or the older `coord`; z = 0 in 2-D) in
/// their stored precision. Cells are the element blocks' elements, block by block as VTK's
/// reader numbers them, with Exodus's node order mapped to VTK's (HEX20, HEX27 and WEDGE15
/// differ). Cell arrays: `ObjectId` (Int32 block id), `GlobalElementId` (Int64, from
/// `elem_num_map`, or 1, 2, ... as Exodus numbers elements without one), the element variables
/// of step `sel` (NaN in blocks the truth table leaves out) and the element attributes
/// (`attrib{k}`, one array per `attrib_name{k}`, NaN in blocks without it); point arrays:
/// `GlobalNodeId` (Int64, from `node_num_map` or 1, 2, ...), the nodal variables of the step
/// and `nodeset:NAME` (UInt8) for each node set. Field data: `exodus:time` (all times, NaN
/// where a step has none; only in a file with steps), `exodus:block_names`, and each global
/// variable over all steps.
///
/// Nodal, element and global variables are joined into multi-component arrays as VTK 9.1's
/// vtkExodusIIReader joins them: consecutive variables with one prefix and the suffixes `x y`,
/// `x y z`, `R Z` (any case), the symmetric tensor `XX YY ZZ XY XZ YZ`, the 20-component third-rank
/// one, or integration points `VAR_CELL_GPnnn` filling their box, become one array named by the
/// prefix (`DISPLX DISPLY DISPLZ` is `DISPL`, `vel_x vel_y vel_z` is `vel_`), its components
/// named by the variables; a name already taken gets `_` appended. In a 2-D mesh a nodal or
/// element array of 2 components gets a third, 0, as in VTK. A component a block lacks is NaN
/// there. Values keep the stored type (Float32 or Float64; global variables Float64).
///
/// Side sets and node and side set variables are skipped with a warning; QA and info records
/// are skipped. NetCDF-4 (HDF5) files, also behind a user block of 512, 1024, ... bytes, read
/// exactly as their classic copies do: chunked, compressed (deflate, shuffle), NC_STRING names
/// and 64-bit integers alike; an HDF5 file that is not Exodus II is refused naming what it
/// lacks.
pub fn read_from(bytes: &[u8], path: &Path, sel: Selector) -> Result<Grid> {
    read::read(bytes, path, sel)
}
