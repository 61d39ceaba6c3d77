//! Preparing any mesh for the partition: tets kept, other 3-D cells tetrahedralized, lower cells
//! dropped, and each tet's input cell remembered.

use anyhow::{Context, Result};
use formats::{cell_type, Grid};

use super::ORIGINAL_CELL_ID;
use crate::mesh::TetMesh;

/// Keeps the tets of `grid`: drops 0-, 1- and 2-D cells (saying how many), tetrahedralizes other
/// 3-D cells. Returns the mesh, for each of its tets the input cell it came from, and notes for
/// the user (what was dropped or split).
pub fn tets_of(grid: &Grid, name: &str) -> Result<(TetMesh, Vec<i64>, Vec<String>)> {
    let mut notes = Vec::new();
    let n = grid.num_cells();
    let all_tets_3d = (0..n).all(|i| {
        let t = grid.cells.types[i];
        t == cell_type::TETRA || cell_type::dimension(t) < 3
    });
    if !all_tets_3d {
        let (tets, report) = crate::mesh::tetrahedralize::tetrahedralize(grid, false)
            .with_context(|| format!("{name}: tetrahedralizing"))?;
        for (t, k) in &report.split {
            notes.push(format!(
                "{name}: split {k} {} cells into tets",
                cell_type::name(*t)
            ));
        }
        if report.dropped > 0 {
            notes.push(format!(
                "{name}: dropped {} cells of dimension 0-2",
                report.dropped
            ));
        }
        if report.inverted > 0 {
            notes.push(format!(
                "{name}: {} cells had negative volume; their tets were reoriented",
                report.inverted
            ));
        }
        let ids = match tets.cell_data.get(ORIGINAL_CELL_ID) {
            Some(a) => a.data.to_f64_vec().into_iter().map(|v| v as i64).collect(),
            None => (0..tets.num_cells() as i64).collect(),
        };
        let mesh = TetMesh::from_grid(&tets).with_context(|| name.to_string())?;
        return Ok((mesh, ids, notes));
    }
    let keep: Vec<usize> = (0..n)
        .filter(|&i| grid.cells.types[i] == cell_type::TETRA)
        .collect();
    let dropped = n - keep.len();
    let mesh = if dropped > 0 {
        notes.push(format!(
            "{name}: dropped {dropped} cells of dimension 0-2 (kept {} tets)",
            keep.len()
        ));
        let mut g = grid.clone();
        let mut cells = formats::Cells::new();
        for &i in &keep {
            cells.push(cell_type::TETRA, grid.cells.cell(i));
        }
        g.cells = cells;
        g.cell_data = grid.cell_data.gather(&keep);
        TetMesh::from_grid(&g)
    } else {
        TetMesh::from_grid(grid)
    }
    .with_context(|| name.to_string())?;
    // An input that already carries integer original_cell_id (a tetrahedralized or split mesh)
    // keeps pointing at the first mesh.
    let carried = grid
        .cell_data
        .get(ORIGINAL_CELL_ID)
        .filter(|a| a.components == 1 && a.data.scalar_type().is_some_and(|t| !t.is_float()));
    let ids = match carried {
        Some(a) => keep.iter().map(|&i| a.data.get_f64(i) as i64).collect(),
        None => keep.into_iter().map(|i| i as i64).collect(),
    };
    Ok((mesh, ids, notes))
}
