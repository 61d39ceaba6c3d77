//! The tetrahedral mesh every later stage works on: f64 points, tets as point-id quadruples, and
//! the input's data arrays carried along.

use anyhow::{bail, Result};
use formats::{cell_type, ArrayData, Attributes, DataArray, Grid};

use crate::geom::Aabb;

/// Linear tetrahedra with their data. Point `i` of `points` has tuple `i` of every point data
/// array; tet `j` has tuple `j` of every cell data array.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TetMesh {
    pub points: Vec<[f64; 3]>,
    pub tets: Vec<[u32; 4]>,
    pub point_data: Attributes,
    pub cell_data: Attributes,
    pub field_data: Vec<DataArray>,
}

impl TetMesh {
    /// Takes the tets of a grid. Every cell must be a linear tetrahedron (tetrahedralize first);
    /// the error names the first cell that is not.
    pub fn from_grid(grid: &Grid) -> Result<TetMesh> {
        let n = grid.num_cells();
        let mut tets = Vec::with_capacity(n);
        for i in 0..n {
            let t = grid.cells.types[i];
            if t != cell_type::TETRA {
                bail!(
                    "cell {i} is a {} (type {t}); only linear tetrahedra are accepted here (tetrahedralize first)",
                    cell_type::name(t)
                );
            }
            let c = grid.cells.cell(i);
            let mut q = [0u32; 4];
            for (k, &id) in c.iter().enumerate() {
                q[k] = u32::try_from(id)
                    .map_err(|_| anyhow::anyhow!("cell {i}: point id {id} does not fit 32 bits"))?;
            }
            tets.push(q);
        }
        Ok(TetMesh {
            points: grid.points_f64(),
            tets,
            point_data: grid.point_data.clone(),
            cell_data: grid.cell_data.clone(),
            field_data: grid.field_data.clone(),
        })
    }

    /// Back to a grid: Float64 points named `Points`, every cell a VTK_TETRA.
    pub fn to_grid(&self) -> Grid {
        let mut cells = formats::Cells::new();
        cells.types = vec![cell_type::TETRA; self.tets.len()];
        cells.connectivity = self
            .tets
            .iter()
            .flat_map(|t| t.iter().map(|&v| v as i64))
            .collect();
        cells.offsets = (0..=self.tets.len() as i64).map(|i| 4 * i).collect();
        Grid {
            points: DataArray::new(
                "Points",
                3,
                ArrayData::Float64(self.points.iter().flatten().copied().collect()),
            ),
            cells,
            point_data: self.point_data.clone(),
            cell_data: self.cell_data.clone(),
            field_data: self.field_data.clone(),
        }
    }

    pub fn tet_points(&self, t: usize) -> [[f64; 3]; 4] {
        self.tets[t].map(|v| self.points[v as usize])
    }

    pub fn bounds(&self) -> Aabb {
        Aabb::of_points(self.points.iter())
    }
}

pub mod generate;
pub mod tetrahedralize;
