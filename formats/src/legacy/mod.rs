//! Legacy VTK (.vtk) unstructured grids: versions up to 4.2 and 5.1, ASCII and big-endian binary.
//! Polydata and the structured data sets (STRUCTURED_POINTS, STRUCTURED_GRID, RECTILINEAR_GRID)
//! are read too, as the cells VTK gives them; only UNSTRUCTURED_GRID is written.
//!
//! What is kept: points in their file type; cells (4.2 `CELLS n size` and 5.1
//! `OFFSETS`/`CONNECTIVITY`, polyhedra as face streams); every POINT_DATA/CELL_DATA array with its
//! name, type, component count and component names (from METADATA); which array is the active
//! SCALARS/VECTORS/NORMALS/TENSORS/TEXTURE_COORDINATES/GLOBAL_IDS/PEDIGREE_IDS; lookup table names;
//! inline LOOKUP_TABLE blocks (as field data named `lookup_table:NAME`, 4 Float32 components);
//! dataset-level FIELD arrays (strings too).
//! What is not kept: the title line; METADATA INFORMATION keys (skipped); `bit` arrays become
//! UInt8 0/1 and `vtkIdType` arrays Int64 (what VTK holds in memory); COLOR_SCALARS become
//! UInt8 SCALARS.

mod attributes;
mod cursor;
mod encode;
mod header;
mod lattice;
mod names;
mod read;
#[cfg(test)]
mod truncation_tests;
mod values;
mod write;

pub use attributes::LOOKUP_TABLE_PREFIX;
pub use read::{read, read_path};
pub use write::write;
