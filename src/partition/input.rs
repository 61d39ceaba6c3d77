//! Preparing any mesh for the partition: tets kept, other 3-D cells tetrahedralized, lower cells
//! dropped, and each tet's input cell remembered.

use anyhow::{Context, Result};
use formats::{cell_type, Grid};

use super::ORIGINAL_CELL_ID;
use crate::mesh::TetMesh;

/// The `vtkGhostType` cell bits of cells ParaView does not draw: DUPLICATECELL (1: a copy of a
/// cell another piece owns, written with ghost levels) and HIDDENCELL (32).
const GHOST_NOT_DRAWN: u8 = 1 | 32;

/// `grid` without the cells its `vtkGhostType` cell array marks as another piece's duplicates or
/// as hidden, and the indices of the cells kept; `None` when no cell is marked. Drawing, sorting
/// or partitioning a duplicate would count its volume twice (a ParaView .pvtu saved with ghost
/// levels repeats each piece's neighbours), so the view commands drop them as ParaView does.
pub fn without_ghost_cells(grid: &Grid) -> Option<(Grid, Vec<usize>)> {
    let ghost = grid
        .cell_data
        .get("vtkGhostType")
        .filter(|a| a.components == 1 && a.data.scalar_type().is_some_and(|t| !t.is_float()))?;
    let n = grid.num_cells();
    if ghost.data.len() != n {
        return None;
    }
    let drawn = |i: usize| (ghost.data.get_f64(i) as i64 as u8) & GHOST_NOT_DRAWN == 0;
    if (0..n).all(drawn) {
        return None;
    }
    let keep: Vec<usize> = (0..n).filter(|&i| drawn(i)).collect();
    Some((keep_cells(grid, &keep), keep))
}

/// The cells of `grid` at `keep` (in that order), with their cell data and polyhedron faces;
/// points, point data and field data unchanged.
pub fn keep_cells(grid: &Grid, keep: &[usize]) -> Grid {
    let n = grid.num_cells();
    let mut cells = formats::Cells::new();
    for &i in keep {
        cells.push(grid.cells.types[i], grid.cells.cell(i));
    }
    if let Some((faces, ends)) = &grid.cells.polyhedron_faces {
        // Cell i's face stream runs from the previous polyhedron's end to its own.
        let mut starts = Vec::with_capacity(n);
        let mut at = 0i64;
        for &e in ends.iter().take(n) {
            starts.push(at);
            if e >= 0 {
                at = e;
            }
        }
        let (mut f, mut o) = (Vec::new(), Vec::with_capacity(keep.len()));
        for &i in keep {
            // A validated grid's streams are in order; a stream that is not stays out.
            let stream = ends
                .get(i)
                .filter(|&&e| e >= 0)
                .and_then(|&e| faces.get(starts[i] as usize..e as usize));
            match stream {
                Some(st) => {
                    f.extend_from_slice(st);
                    o.push(f.len() as i64);
                }
                None => o.push(-1),
            }
        }
        cells.polyhedron_faces = Some((f, o));
    }
    let mut g = grid.clone();
    g.cells = cells;
    g.cell_data = grid.cell_data.gather(keep);
    g
}

/// Whether `grid` carries integer `original_cell_id`s (a tetrahedralized or split mesh), which
/// the view commands keep pointing at the first mesh.
fn carries_ids(grid: &Grid) -> bool {
    grid.cell_data
        .get(ORIGINAL_CELL_ID)
        .is_some_and(|a| a.components == 1 && a.data.scalar_type().is_some_and(|t| !t.is_float()))
}

/// Keeps the tets of `grid`: drops ghost cells ([`without_ghost_cells`]) and 0-, 1- and 2-D
/// cells (saying how many), tetrahedralizes other 3-D cells. Returns the mesh, for each of its
/// tets the input cell it came from, and notes for the user (what was dropped or split).
pub fn tets_of(grid: &Grid, name: &str) -> Result<(TetMesh, Vec<i64>, Vec<String>)> {
    if let Some((drawn, keep)) = without_ghost_cells(grid) {
        let (mesh, ids, mut notes) = tets_of(&drawn, name)?;
        let ids = if carries_ids(&drawn) {
            ids
        } else {
            ids.into_iter().map(|i| keep[i as usize] as i64).collect()
        };
        notes.insert(0, ghost_note(name, grid.num_cells() - keep.len()));
        return Ok((mesh, ids, notes));
    }
    let mut notes = Vec::new();
    let n = grid.num_cells();
    let all_tets_3d = (0..n).all(|i| {
        let t = grid.cells.types[i];
        t == cell_type::TETRA || cell_type::dimension(t) < 3
    });
    if !all_tets_3d {
        let (tets, report) = crate::mesh::tetrahedralize::tetrahedralize(grid, false)
            .with_context(|| format!("{name}: tetrahedralizing"))?;
        for &(t, k) in &report.split {
            notes.push(format!(
                "{name}: {}",
                crate::mesh::tetrahedralize::TetrahedralizeReport::split_line(t, k)
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

/// What the view commands say when they drop ghost cells.
pub fn ghost_note(name: &str, dropped: usize) -> String {
    format!(
        "{name}: dropped {dropped} ghost cells (vtkGhostType: duplicates of another piece's cells, or hidden), as ParaView does"
    )
}
