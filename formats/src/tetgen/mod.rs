//! TetGen `.node`/`.ele` (+ `.face`, `.neigh`) meshes.
//!
//! Reading (`read`): points from `.node` (Float64), with point arrays `node_attribute_K` (Float64)
//! and `boundary_marker` (Int32) when the file has them; tets from `.ele` (4 nodes: VTK_TETRA,
//! 10 nodes: VTK_QUADRATIC_TETRA with TetGen's edge-node order mapped to VTK's), with cell
//! arrays `region` (the first attribute, `-A`) and `ele_attribute_K` for further ones (Float64).
//! When `.face` is present its boundary faces are appended as TRIANGLE (or QUADRATIC_TRIANGLE)
//! cells after the tets, with their markers in the Int32 cell array `boundary_marker` (0 on
//! tets); real-valued tet arrays hold NaN on them. Stages that need tets only drop these 2-D
//! cells. When `.neigh` is present, the Int64 4-component cell array `neighbors` holds each tet's
//! neighbours as 0-based cell indices (-1: none; -1 on triangles). Numbering may start at 0 or 1.
//!
//! Writing (`write`): `.node` and `.ele` (and `.face` when the mesh has triangle cells), all or
//! none, numbered from 1 (TetGen's default). What cannot be represented: any cell other than
//! tets and boundary triangles (tetrahedralize first: the write fails); a mix of linear and
//! quadratic tets (fails); field data, string arrays and the names of attribute arrays (dropped:
//! every numeric point array becomes node attribute columns, one per component, and every
//! numeric cell array except `boundary_marker` and `neighbors` becomes `.ele` attribute columns,
//! `region` first); the values of cell arrays on boundary triangles other than `boundary_marker`
//! (a `.face` line holds only that marker; without `boundary_marker`, a Gmsh mesh's
//! `gmsh:physical` is written there, so its physical surfaces become the face markers); all values as decimal reals, so types are not kept (a reread gives Float64)
//! and integers beyond 2^53 are rounded (`convert` names each such array on stderr); `neighbors` is written as `.neigh` (each tet's
//! neighbours by their `.ele` numbers) when every entry is -1 or a tet of the mesh, else as
//! `.ele` attribute columns like any other array.

mod read;
mod records;
mod write;

pub use read::{read, read_parts};
pub use write::{face_marker, write};

/// Array names the reader gives and the writer looks for.
pub mod names {
    pub const BOUNDARY_MARKER: &str = "boundary_marker";
    pub const NEIGHBORS: &str = "neighbors";
    pub const REGION: &str = "region";

    /// Point array for `.node` attribute column `k`.
    pub fn node_attribute(k: usize) -> String {
        format!("node_attribute_{k}")
    }

    /// Cell array for `.ele` attribute column `k`: `region` for the first (TetGen's `-A`).
    pub fn ele_attribute(k: usize) -> String {
        if k == 0 {
            REGION.to_string()
        } else {
            format!("ele_attribute_{k}")
        }
    }
}

/// TetGen writes a 10-node tet's edge nodes for edges (2,3), (0,3), (0,1), (1,2), (1,3), (0,2);
/// VTK wants (0,1), (1,2), (0,2), (0,3), (1,3), (2,3). Entry k is the TetGen column of VTK node k.
pub(crate) const TG_FROM_VTK_QUADRATIC_TETRA: [usize; 10] = [0, 1, 2, 3, 6, 7, 9, 5, 8, 4];
