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

    /// The tets with each point id replaced by the lowest id of the points at the same
    /// coordinates (-0 and 0 alike), or `None` when no tet uses two coincident points' ids.
    /// Per-element output (every cell its own points, as DG codes write) and appended pieces
    /// store a shared face twice; with ids welded the two tets are neighbours across it.
    pub fn welded_tets(&self) -> Option<Vec<[u32; 4]>> {
        use rayon::prelude::*;
        let key = |i: u32| self.points[i as usize].map(|c| (c + 0.0).to_bits());
        let mut ids: Vec<u32> = (0..self.points.len() as u32).collect();
        ids.par_sort_unstable_by_key(|&i| (key(i), i));
        let mut canon: Vec<u32> = (0..self.points.len() as u32).collect();
        let mut any = false;
        for w in ids.windows(2) {
            if key(w[0]) == key(w[1]) {
                canon[w[1] as usize] = canon[w[0] as usize];
                any = true;
            }
        }
        any.then(|| {
            self.tets
                .par_iter()
                .map(|t| t.map(|v| canon.get(v as usize).copied().unwrap_or(v)))
                .collect()
        })
    }

    pub fn bounds(&self) -> Aabb {
        Aabb::of_points(self.points.iter())
    }
}

pub mod generate;
pub mod tetrahedralize;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn welded_tets_map_coincident_points_to_the_lowest_id() {
        let mut m = TetMesh {
            points: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                [1.0, 1.0, 1.0],
            ],
            tets: vec![[0, 1, 2, 3], [1, 2, 3, 4]],
            ..Default::default()
        };
        assert_eq!(m.welded_tets(), None);
        // The second tet stored apart: copies of points 1, 2, 3 (one with -0 for 0).
        m.points
            .extend([[1.0, 0.0, 0.0], [0.0, 1.0, -0.0], [0.0, 0.0, 1.0]]);
        m.tets[1] = [5, 6, 7, 4];
        assert_eq!(m.welded_tets(), Some(vec![[0, 1, 2, 3], [1, 2, 3, 4]]));
    }
}
