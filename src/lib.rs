//! tetkit: tetrahedral volume meshes read losslessly, partitioned with a K-D tree, sorted exactly
//! for any camera, and rendered with projected tetrahedra.
//!
//! Data flows one way: [`formats`] (files) -> [`mesh`] (tets with their arrays) -> [`partition`]
//! (K-D tree, split tets) -> [`sort`] (visibility order) -> [`render`]; [`locate`] is the O(N)
//! hierarchical grid that finds cells and ray entry faces. The CLI in [`cli`] is a thin
//! layer over these calls.

pub mod camera;
pub mod cli;
pub mod geom;
pub mod locate;
pub(crate) mod mem;
pub mod mesh;
pub mod partition;
pub mod render;
pub mod scene;
pub mod sort;

pub use formats;
