//! Splitting non-tet cells (hexahedra, voxels, wedges, pyramids, quadratic tets) into conforming
//! linear tets, carrying cell data to the children.

use anyhow::{bail, Result};
use formats::Grid;

/// What tetrahedralization did, for the user.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TetrahedralizeReport {
    /// `(cell type, cells of that type that were split)`.
    pub split: Vec<(u8, usize)>,
    /// 2-D and lower cells dropped (only when `keep_lower` is false).
    pub dropped: usize,
    pub tets_out: usize,
}

/// Splits every 3-D cell into linear tets. `keep_lower`: keep 0-, 1- and 2-D cells as they are
/// (convert) instead of dropping them (stages that need only tets).
pub fn tetrahedralize(_grid: &Grid, _keep_lower: bool) -> Result<(Grid, TetrahedralizeReport)> {
    bail!("tetrahedralization is not implemented yet")
}
