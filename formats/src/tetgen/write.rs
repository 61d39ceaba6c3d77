//! Writing `.node`/`.ele` (+ `.face`, `.neigh`) beside each other, all or none.

use super::read::sibling;
use super::{names, TG_FROM_VTK_QUADRATIC_TETRA};
use crate::atomic::write_all_or_none;
use crate::{cell_type, ArrayData, DataArray, FormatError, Grid, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

/// TetGen column j of a 10-node tet holds VTK node `VTK_FROM_TG[j]`.
const VTK_FROM_TG: [usize; 10] = {
    let mut inv = [0usize; 10];
    let mut k = 0;
    while k < 10 {
        inv[TG_FROM_VTK_QUADRATIC_TETRA[k]] = k;
        k += 1;
    }
    inv
};

/// Writes `.node` and `.ele` beside `path` (all or none), `.face` when the mesh has triangle
/// cells and `.neigh` when it has a `neighbors` array `.neigh` can hold; see the module documentation for what TetGen files cannot hold. A `.face`
/// or `.neigh` of the same name left from an earlier mesh would be read back with the new files,
/// so it is removed once the new files are in place.
pub fn write(path: &Path, grid: &Grid) -> Result<()> {
    let stem = path.with_extension("");
    let plan = Plan::new(grid).map_err(|e| e.with_file(path))?;
    let mut targets: Vec<PathBuf> = vec![sibling(&stem, "node"), sibling(&stem, "ele")];
    // Which file each target is: node, ele, face, neigh.
    let mut files = vec![0u8, 1];
    if !plan.faces.is_empty() {
        targets.push(sibling(&stem, "face"));
        files.push(2);
    }
    if plan.neighbors.is_some() {
        targets.push(sibling(&stem, "neigh"));
        files.push(3);
    }
    write_all_or_none(&targets, |i, w| {
        let r = match files[i] {
            0 => plan.node(grid, w),
            1 => plan.ele(grid, w),
            2 => plan.face(grid, w),
            _ => plan.neigh(grid, w),
        };
        r.map_err(|e| WriteError(FormatError::io(&targets[i], e)))
    })
    .map_err(|e| e.0.with_file(path))?;
    for ext in ["face", "neigh"] {
        let stale = sibling(&stem, ext);
        if !targets.contains(&stale) && stale.exists() {
            std::fs::remove_file(&stale).map_err(|e| FormatError::io(&stale, e))?;
        }
    }
    Ok(())
}

/// What `write_all_or_none` needs: an error that I/O failures convert into.
struct WriteError(FormatError);

impl From<std::io::Error> for WriteError {
    fn from(e: std::io::Error) -> WriteError {
        WriteError(FormatError::whole(e.to_string()))
    }
}

impl From<crate::atomic::TargetError> for WriteError {
    fn from(e: crate::atomic::TargetError) -> WriteError {
        WriteError(FormatError::io(&e.path, e.source))
    }
}

/// Which cells and arrays go where.
struct Plan<'g> {
    tets: Vec<usize>,
    faces: Vec<usize>,
    order: usize,
    node_attrs: Vec<&'g DataArray>,
    node_marker: Option<&'g DataArray>,
    ele_attrs: Vec<&'g DataArray>,
    face_marker: Option<&'g DataArray>,
    /// The `neighbors` cell array, when every tet's four entries are -1 or a tet of the mesh
    /// (what `.neigh` holds); otherwise it goes to `.ele` as attribute columns.
    neighbors: Option<&'g DataArray>,
}

fn is_integer(a: &DataArray) -> bool {
    a.data.scalar_type().is_some_and(|t| !t.is_float())
}

/// The cell array whose values `.face` lines carry as their markers: `boundary_marker`, else a
/// Gmsh mesh's `gmsh:physical` (its physical surfaces), one integer per cell.
pub fn face_marker(grid: &Grid) -> Option<&DataArray> {
    let one_int = |name: &str| {
        grid.cell_data
            .arrays
            .iter()
            .find(|a| a.name == name && a.components == 1 && is_integer(a))
    };
    one_int(names::BOUNDARY_MARKER).or_else(|| one_int(crate::msh::names::PHYSICAL))
}

impl<'g> Plan<'g> {
    fn new(grid: &'g Grid) -> Result<Plan<'g>> {
        let mut plan = Plan {
            tets: Vec::new(),
            faces: Vec::new(),
            order: 0,
            node_attrs: Vec::new(),
            node_marker: None,
            ele_attrs: Vec::new(),
            face_marker: None,
            neighbors: None,
        };
        let mut face_order = 0;
        for (i, &t) in grid.cells.types.iter().enumerate() {
            let (order, is_tet) = match t {
                cell_type::TETRA => (4, true),
                cell_type::QUADRATIC_TETRA => (10, true),
                cell_type::TRIANGLE => (4, false),
                cell_type::QUADRATIC_TRIANGLE => (10, false),
                _ => {
                    return Err(FormatError::new(
                        crate::Place::Other(format!("cell {i}")),
                        format!(
                            "TetGen files hold tetrahedra and boundary triangles only; this is a {} (tetrahedralize first)",
                            cell_type::name(t)
                        ),
                    ))
                }
            };
            let slot = if is_tet {
                &mut plan.order
            } else {
                &mut face_order
            };
            if *slot != 0 && *slot != order {
                return Err(FormatError::new(
                    crate::Place::Other(format!("cell {i}")),
                    "TetGen files cannot mix linear and quadratic cells",
                ));
            }
            *slot = order;
            if is_tet {
                plan.tets.push(i);
            } else {
                plan.faces.push(i);
            }
        }
        if plan.order == 0 {
            plan.order = if face_order == 0 { 4 } else { face_order };
        }
        if face_order != 0 && face_order != plan.order {
            return Err(FormatError::whole(
                "TetGen files cannot mix linear and quadratic cells",
            ));
        }
        for a in &grid.point_data.arrays {
            if a.name == names::BOUNDARY_MARKER && a.components == 1 && is_integer(a) {
                plan.node_marker = Some(a);
            } else if a.data.scalar_type().is_some() {
                plan.node_attrs.push(a);
            }
        }
        // The `.face` markers; a Gmsh mesh's `gmsh:physical` marks its triangles and stays an
        // attribute column of its tets too, `boundary_marker` only marks.
        plan.face_marker = face_marker(grid);
        for a in &grid.cell_data.arrays {
            if plan
                .face_marker
                .is_some_and(|m| std::ptr::eq(m, a) && a.name == names::BOUNDARY_MARKER)
            {
                continue;
            }
            if a.name == names::NEIGHBORS && plan.holds_neighbors(grid, a) {
                plan.neighbors = Some(a);
            } else if a.data.scalar_type().is_some() {
                plan.ele_attrs.push(a);
            }
        }
        plan.ele_attrs.sort_by_key(|a| a.name != names::REGION);
        Ok(plan)
    }

    /// Whether `.neigh` can hold `a`: four integer components, each tet's entries -1 or the
    /// index of a tet cell.
    fn holds_neighbors(&self, grid: &Grid, a: &DataArray) -> bool {
        let is_tet =
            |v: f64| {
                v == -1.0
                    || (v >= 0.0
                        && v.fract() == 0.0
                        && grid.cells.types.get(v as usize).is_some_and(|&t| {
                            t == cell_type::TETRA || t == cell_type::QUADRATIC_TETRA
                        }))
            };
        a.components == 4
            && is_integer(a)
            && self
                .tets
                .iter()
                .all(|&i| (0..4).all(|k| is_tet(a.data.get_f64(i * 4 + k))))
    }

    fn columns(arrays: &[&DataArray]) -> usize {
        arrays.iter().map(|a| a.components).sum()
    }

    fn node(&self, grid: &Grid, w: &mut dyn Write) -> std::io::Result<()> {
        let n = grid.num_points();
        let na = Self::columns(&self.node_attrs);
        let mut line = Vec::with_capacity(256);
        writeln!(
            w,
            "# written by tetkit: <points> <dimension> <attributes> <boundary markers>"
        )?;
        writeln!(w, "{n} 3 {na} {}", self.node_marker.is_some() as u8)?;
        for i in 0..n {
            line.clear();
            let p = grid.point(i);
            write!(line, "{} {:?} {:?} {:?}", i + 1, p[0], p[1], p[2])?;
            for a in &self.node_attrs {
                put_tuple(&mut line, a, i);
            }
            if let Some(m) = self.node_marker {
                write!(line, " {}", m.data.get_f64(i))?;
            }
            line.push(b'\n');
            w.write_all(&line)?;
        }
        Ok(())
    }

    fn ele(&self, grid: &Grid, w: &mut dyn Write) -> std::io::Result<()> {
        let na = Self::columns(&self.ele_attrs);
        let mut line = Vec::with_capacity(256);
        writeln!(
            w,
            "# written by tetkit: <tetrahedra> <nodes per tetrahedron> <attributes>"
        )?;
        writeln!(w, "{} {} {na}", self.tets.len(), self.order)?;
        for (k, &i) in self.tets.iter().enumerate() {
            line.clear();
            let c = grid.cells.cell(i);
            write!(line, "{}", k + 1)?;
            if self.order == 4 {
                for &id in c {
                    write!(line, " {}", id + 1)?;
                }
            } else {
                for &j in &VTK_FROM_TG {
                    write!(line, " {}", c[j] + 1)?;
                }
            }
            for a in &self.ele_attrs {
                put_tuple(&mut line, a, i);
            }
            line.push(b'\n');
            w.write_all(&line)?;
        }
        Ok(())
    }

    fn face(&self, grid: &Grid, w: &mut dyn Write) -> std::io::Result<()> {
        writeln!(w, "# written by tetkit: <faces> <boundary markers>")?;
        writeln!(
            w,
            "{} {}",
            self.faces.len(),
            self.face_marker.is_some() as u8
        )?;
        let mut line = Vec::with_capacity(128);
        for (k, &i) in self.faces.iter().enumerate() {
            line.clear();
            write!(line, "{}", k + 1)?;
            for &id in grid.cells.cell(i) {
                write!(line, " {}", id + 1)?;
            }
            if let Some(m) = self.face_marker {
                write!(line, " {}", m.data.get_f64(i))?;
            }
            line.push(b'\n');
            w.write_all(&line)?;
        }
        Ok(())
    }
}

impl Plan<'_> {
    /// `.neigh`: per tet its four neighbours (opposite its four nodes, as read) by their
    /// numbers in `.ele`, -1 for none.
    fn neigh(&self, grid: &Grid, w: &mut dyn Write) -> std::io::Result<()> {
        let Some(a) = self.neighbors else {
            return Ok(());
        };
        let mut number = vec![-1i64; grid.num_cells()];
        for (k, &i) in self.tets.iter().enumerate() {
            number[i] = k as i64 + 1;
        }
        writeln!(
            w,
            "# written by tetkit: <tetrahedra> <neighbours per tetrahedron>"
        )?;
        writeln!(w, "{} 4", self.tets.len())?;
        let mut line = Vec::with_capacity(96);
        for (k, &i) in self.tets.iter().enumerate() {
            line.clear();
            write!(line, "{}", k + 1)?;
            for c in 0..4 {
                let v = a.data.get_f64(i * 4 + c);
                let n = if v < 0.0 { -1 } else { number[v as usize] };
                write!(line, " {n}")?;
            }
            line.push(b'\n');
            w.write_all(&line)?;
        }
        Ok(())
    }
}

/// Tuple `i` of an array as decimal reals (shortest text that reads back to the same f64).
fn put_tuple(line: &mut Vec<u8>, a: &DataArray, i: usize) {
    let c = a.components;
    for k in 0..c {
        let v = a.data.get_f64(i * c + k);
        let _ = match &a.data {
            ArrayData::Float32(_) | ArrayData::Float64(_) => write!(line, " {v:?}"),
            _ => write!(line, " {v}"),
        };
    }
}
