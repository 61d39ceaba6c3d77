//! ASCII Medit `.mesh` files (INRIA's format, written by MMG, TetGen `-g`, Gmsh, CGAL, FreeFEM).
//!
//! Reading (`read`): `MeshVersionFormatted` 1 to 4 (for ASCII files the version only widens
//! integers to 64 bits, which the reader parses anyway), `Dimension` 3, or 2 with z = 0;
//! `Vertices` (Float64 points, refs in the Int32 point array `medit:ref`); `Edges`, `Triangles`,
//! `Quadrilaterals`, `Tetrahedra`, `Hexahedra`, `Prisms`, `Pyramids` as LINE, TRIANGLE, QUAD,
//! TETRA, HEXAHEDRON, WEDGE and PYRAMID cells, in the order of the sections in the file, nodes in
//! the order written, refs in the Int32 cell array `medit:ref`. `Corners` and `RequiredVertices`
//! become the UInt8 0/1 point arrays `medit:corner` and `medit:required`; `Ridges` (edge numbers)
//! the UInt8 cell array `medit:ridge`, and `RequiredEdges`, `RequiredTriangles`,
//! `RequiredQuadrilaterals` and `RequiredTetrahedra` the UInt8 cell array `medit:required`.
//! Normals and tangents (`Normals`, `NormalAtVertices`, ...) are skipped with a warning; P2/Q2
//! sections and unknown keywords are refused, naming the keyword and line.
//!
//! Node order: Medit's tetrahedra and hexahedra are ordered as VTK orders them (checked on TetGen
//! and Gmsh output: VTK finds positive volumes), and so are pyramids (base quad, its right-hand
//! normal towards the apex, then the apex), so their nodes are kept as written. A Medit prism is
//! Gmsh's reference prism: triangle (1 2 3) turns counter-clockwise seen from triangle (4 5 6);
//! VTK's wedge (as Gmsh's VTK writer and tetkit's tetrahedralization take it) turns the other
//! way, so nodes 2 and 3, and 5 and 6, are swapped on reading and on writing (the same swap Gmsh
//! makes between its prisms and VTK wedges when it writes `.vtk`). No tool at hand writes prisms or
//! pyramids to `.mesh` to check this against (Gmsh 4.8 drops both from `.mesh` output).
//!
//! Writing (`write`): `MeshVersionFormatted 2`, `Dimension 3`, vertices and the cell sections in
//! the order their types first appear in the grid (so a Medit file read and written keeps its
//! layout), refs from the arrays `medit:ref` (integers, or reals that are all whole; 0 without
//! them; a ref beyond 32 bits fails the write; cell refs from `gmsh:physical` or `CellEntityIds`
//! when there is no `medit:ref`, said on stderr), and the corner, required and ridge sections from the arrays the reader makes (when
//! the mesh has no edges or other cells to flag, they go over an empty `Edges` section, so every
//! file the reader accepts reads back as the same grid). Voxels and pixels are written as the hexahedra
//! and quads they are (reordered); other cell types (vertices, polylines, polygons, quadratic
//! cells, polyhedra...) are refused, naming the type and count. Every other array and field data
//! are dropped, each named in a warning on stderr.

mod read;
mod tokens;
mod write;

pub use read::{read, read_bytes};
pub use write::write;

use crate::cell_type;

/// Array names the reader gives and the writer looks for.
pub mod names {
    /// Point and cell array: Medit's reference number (region, boundary or entity tag).
    pub const REF: &str = "medit:ref";
    /// Point array: 1 on `Corners`.
    pub const CORNER: &str = "medit:corner";
    /// Point array (`RequiredVertices`) and cell array (`RequiredEdges`, ...): 1 where required.
    pub const REQUIRED: &str = "medit:required";
    /// Cell array: 1 on the edges `Ridges` names.
    pub const RIDGE: &str = "medit:ridge";
}

/// One element section: keyword, VTK cell type, nodes per element, and the keyword that flags
/// its elements as required (when Medit has one).
pub(crate) struct Section {
    pub keyword: &'static str,
    pub vtk: u8,
    pub nodes: usize,
    pub required: Option<&'static str>,
}

pub(crate) const SECTIONS: [Section; 7] = [
    Section {
        keyword: "Edges",
        vtk: cell_type::LINE,
        nodes: 2,
        required: Some("RequiredEdges"),
    },
    Section {
        keyword: "Triangles",
        vtk: cell_type::TRIANGLE,
        nodes: 3,
        required: Some("RequiredTriangles"),
    },
    Section {
        keyword: "Quadrilaterals",
        vtk: cell_type::QUAD,
        nodes: 4,
        required: Some("RequiredQuadrilaterals"),
    },
    Section {
        keyword: "Tetrahedra",
        vtk: cell_type::TETRA,
        nodes: 4,
        required: Some("RequiredTetrahedra"),
    },
    Section {
        keyword: "Hexahedra",
        vtk: cell_type::HEXAHEDRON,
        nodes: 8,
        required: None,
    },
    Section {
        keyword: "Prisms",
        vtk: cell_type::WEDGE,
        nodes: 6,
        required: None,
    },
    Section {
        keyword: "Pyramids",
        vtk: cell_type::PYRAMID,
        nodes: 5,
        required: None,
    },
];

/// Medit prism <-> VTK wedge (its own inverse): the triangles turn the other way.
pub(crate) fn swap_prism<T>(ids: &mut [T]) {
    ids.swap(1, 2);
    ids.swap(4, 5);
}
