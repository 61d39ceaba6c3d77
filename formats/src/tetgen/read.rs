//! Reading `.node`, `.ele`, `.face` and `.neigh` into a [`Grid`].

use super::records::Records;
use super::{names, TG_FROM_VTK_QUADRATIC_TETRA};
use crate::error::numbered;
use crate::{cell_type, ArrayData, Cells, DataArray, FormatError, Grid, Result};
use std::path::{Path, PathBuf};

/// The files of one mesh: `stem.node`, `stem.ele`, ...
pub(crate) fn sibling(stem: &Path, ext: &str) -> PathBuf {
    let mut s = stem.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

fn load(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).map_err(|e| FormatError::io(path, e))
}

/// Reads the mesh named by any of its files (`mesh.1.node`, `mesh.1.ele`, ...): the `.node`
/// file must exist; `.ele`, `.face` and `.neigh` are read when present (a `.node` alone gives
/// points without cells).
pub fn read(path: &Path) -> Result<Grid> {
    let stem = path.with_extension("");
    let ele_path = sibling(&stem, "ele");
    let node = load(&sibling(&stem, "node"))?;
    let optional = |ext: &str| -> Result<Option<Vec<u8>>> {
        let p = sibling(&stem, ext);
        if p.exists() {
            load(&p).map(Some)
        } else {
            Ok(None)
        }
    };
    let ele = optional("ele")?;
    if ele.is_none() && path.extension().is_some_and(|e| e != "node") {
        return Err(FormatError::whole("the .ele file is missing").with_file(&ele_path));
    }
    let face = optional("face")?;
    let neigh = optional("neigh")?;
    read_parts(
        &stem,
        &node,
        ele.as_deref(),
        face.as_deref(),
        neigh.as_deref(),
    )
}

/// Reads a mesh from the contents of its files; `stem` (`dir/mesh.1`) only names them in
/// errors. `.face` and `.neigh` are used only with an `.ele`.
pub fn read_parts(
    stem: &Path,
    node: &[u8],
    ele: Option<&[u8]>,
    face: Option<&[u8]>,
    neigh: Option<&[u8]>,
) -> Result<Grid> {
    let mut grid = Grid::default();
    let nodes = read_node(node, &sibling(stem, "node"), &mut grid)?;
    let Some(ele) = ele else {
        return Ok(grid);
    };
    let eles = read_ele(ele, &sibling(stem, "ele"), nodes, &mut grid)?;
    if let Some(face) = face {
        read_face(face, &sibling(stem, "face"), nodes, eles, &mut grid)?;
    }
    if let Some(neigh) = neigh {
        read_neigh(neigh, &sibling(stem, "neigh"), eles, &mut grid)?;
    }
    Ok(grid)
}

/// Point count and the number of the first point (0 or 1; ids in other files are relative to it).
#[derive(Clone, Copy)]
struct Nodes {
    count: usize,
    first: i64,
}

/// Tet count, nodes per tet and the number of the first tet (for `.neigh`).
#[derive(Clone, Copy)]
struct Eles {
    count: usize,
    order: usize,
    first: i64,
}

/// Room for `n` records of `per_record` values, bounded by what the file can hold (a value takes
/// at least 2 bytes).
fn capacity(n: usize, r: &Records<'_>, per_record: usize) -> usize {
    n.saturating_mul(per_record).min(r.remaining() / 2 + 1)
}

/// Checks a record's leading number: consecutive from the first record's number, which must
/// be 0 or 1.
fn check_index(
    r: &Records<'_>,
    toks: &[&[u8]],
    line: usize,
    i: usize,
    first: &mut i64,
    what: &str,
) -> Result<()> {
    let idx = r.int(toks, 0, line, &format!("the {what} number"))?;
    if i == 0 {
        if idx != 0 && idx != 1 {
            return Err(r.err(
                line,
                format!("the first {what} is numbered {idx}; TetGen numbers from 0 or 1"),
            ));
        }
        *first = idx;
    } else if Some(idx) != (i as i64).checked_add(*first) {
        return Err(r.err(
            line,
            format!(
                "{what} {} is numbered {idx}; numbers must be consecutive",
                i as i64 + *first
            ),
        ));
    }
    Ok(())
}

fn read_node(bytes: &[u8], path: &Path, grid: &mut Grid) -> Result<Nodes> {
    let mut r = Records::new(bytes, path);
    let mut t = Vec::new();
    let line = r.require(&mut t, "the .node header")?;
    let n = r.count(&t, 0, line, "the number of points")?;
    let dim = if t.len() > 1 {
        r.count(&t, 1, line, "the dimension")?
    } else {
        3
    };
    if dim != 3 {
        return Err(r.err(line, format!("dimension {dim}: only 3-D meshes are read")));
    }
    let nattr = if t.len() > 2 {
        r.count(&t, 2, line, "the number of attributes")?
    } else {
        0
    };
    let nmark = if t.len() > 3 {
        r.count(&t, 3, line, "the boundary marker flag")?
    } else {
        0
    };
    if nmark > 1 {
        return Err(r.err(
            line,
            format!("boundary marker flag {nmark}: must be 0 or 1"),
        ));
    }
    if t.len() > 4 {
        return Err(r.err(line, "the .node header has more than 4 fields"));
    }
    if nattr > r.remaining() {
        return Err(r.err(
            line,
            format!("{nattr} attributes per point cannot fit in the file"),
        ));
    }
    let fields = 4 + nattr + nmark;
    let mut xyz = Vec::with_capacity(capacity(n, &r, 3));
    let mut attrs = Vec::with_capacity(capacity(n, &r, nattr));
    let mut marks = Vec::with_capacity(capacity(n, &r, nmark));
    let mut first = 0;
    for i in 0..n {
        let line = r.require(&mut t, &format!("point {i} of {n}"))?;
        check_index(&r, &t, line, i, &mut first, "point")?;
        if t.len() != fields {
            return Err(r.err(line, format!("a point line has {} fields, expected {fields} (number, x, y, z, {nattr} attributes, {nmark} markers)", t.len())));
        }
        for k in 1..4 {
            let v = r.real(&t, k, line, "a coordinate")?;
            if !v.is_finite() {
                return Err(r.err(line, format!("coordinate {v} is not finite")));
            }
            xyz.push(v);
        }
        for k in 0..nattr {
            attrs.push(r.real(&t, 4 + k, line, "an attribute")?);
        }
        if nmark == 1 {
            let m = r.marker(&t, 4 + nattr, line, "the boundary marker")?;
            marks.push(
                i32::try_from(m).map_err(|_| {
                    r.err(line, format!("boundary marker {m} does not fit 32 bits"))
                })?,
            );
        }
    }
    if let Some(line) = r.next_into(&mut t) {
        return Err(r.err(
            line,
            format!("more lines after the {n} points the header declares"),
        ));
    }
    grid.points = DataArray::new("Points", 3, ArrayData::Float64(xyz));
    for k in 0..nattr {
        let col: Vec<f64> = (0..n).map(|i| attrs[i * nattr + k]).collect();
        grid.point_data.arrays.push(DataArray::new(
            names::node_attribute(k),
            1,
            ArrayData::Float64(col),
        ));
    }
    if nmark == 1 {
        grid.point_data.arrays.push(DataArray::new(
            names::BOUNDARY_MARKER,
            1,
            ArrayData::Int32(marks),
        ));
    }
    Ok(Nodes { count: n, first })
}

/// A point reference, shifted to 0-based and checked.
fn node_ref(r: &Records<'_>, t: &[&[u8]], k: usize, line: usize, nodes: Nodes) -> Result<i64> {
    let v = r.int(t, k, line, "a node number")?;
    let id = v
        .checked_sub(nodes.first)
        .filter(|&id| id >= 0 && (id as u64) < nodes.count as u64);
    id.ok_or_else(|| {
        r.err(
            line,
            format!(
                "node number {v} is out of range ({})",
                numbered(nodes.count as u64, "node", nodes.first)
            ),
        )
    })
}

fn read_ele(bytes: &[u8], path: &Path, nodes: Nodes, grid: &mut Grid) -> Result<Eles> {
    let mut r = Records::new(bytes, path);
    let mut t = Vec::new();
    let line = r.require(&mut t, "the .ele header")?;
    let n = r.count(&t, 0, line, "the number of tetrahedra")?;
    let order = if t.len() > 1 {
        r.count(&t, 1, line, "the nodes per tetrahedron")?
    } else {
        4
    };
    if order != 4 && order != 10 {
        return Err(r.err(
            line,
            format!("{order} nodes per tetrahedron: must be 4 or 10"),
        ));
    }
    let nattr = if t.len() > 2 {
        r.count(&t, 2, line, "the number of attributes")?
    } else {
        0
    };
    if t.len() > 3 {
        return Err(r.err(line, "the .ele header has more than 3 fields"));
    }
    if nattr > r.remaining() {
        return Err(r.err(
            line,
            format!("{nattr} attributes per tetrahedron cannot fit in the file"),
        ));
    }
    let fields = 1 + order + nattr;
    let mut conn = Vec::with_capacity(capacity(n, &r, order));
    let mut attrs = Vec::with_capacity(capacity(n, &r, nattr));
    let mut first = 0;
    let mut ids = [0i64; 10];
    for i in 0..n {
        let line = r.require(&mut t, &format!("tetrahedron {i} of {n}"))?;
        check_index(&r, &t, line, i, &mut first, "tetrahedron")?;
        if t.len() != fields {
            return Err(r.err(line, format!("a tetrahedron line has {} fields, expected {fields} (number, {order} nodes, {nattr} attributes)", t.len())));
        }
        for (k, id) in ids.iter_mut().take(order).enumerate() {
            *id = node_ref(&r, &t, 1 + k, line, nodes)?;
        }
        if order == 4 {
            conn.extend_from_slice(&ids[..4]);
        } else {
            conn.extend(TG_FROM_VTK_QUADRATIC_TETRA.iter().map(|&k| ids[k]));
        }
        for k in 0..nattr {
            attrs.push(r.real(&t, 1 + order + k, line, "a region attribute")?);
        }
    }
    if let Some(line) = r.next_into(&mut t) {
        return Err(r.err(
            line,
            format!("more lines after the {n} tetrahedra the header declares"),
        ));
    }
    let ty = if order == 4 {
        cell_type::TETRA
    } else {
        cell_type::QUADRATIC_TETRA
    };
    grid.cells = Cells {
        types: vec![ty; n],
        offsets: (0..=n as i64).map(|i| i * order as i64).collect(),
        connectivity: conn,
        polyhedron_faces: None,
    };
    for k in 0..nattr {
        let col: Vec<f64> = (0..n).map(|i| attrs[i * nattr + k]).collect();
        grid.cell_data.arrays.push(DataArray::new(
            names::ele_attribute(k),
            1,
            ArrayData::Float64(col),
        ));
    }
    Ok(Eles {
        count: n,
        order,
        first,
    })
}

/// Boundary faces become triangle cells (quadratic triangles for 10-node meshes) after the tets;
/// their markers go to the `boundary_marker` cell array (0 on tets), and every tet-only cell
/// array gets NaN (reals) or 0 (integers) on them. TetGen's `-nn` adjacent-tet columns are read
/// and dropped (`neighbors` carries adjacency).
fn read_face(bytes: &[u8], path: &Path, nodes: Nodes, ele: Eles, grid: &mut Grid) -> Result<()> {
    let mut r = Records::new(bytes, path);
    let mut t = Vec::new();
    let line = r.require(&mut t, "the .face header")?;
    let n = r.count(&t, 0, line, "the number of faces")?;
    let nmark = if t.len() > 1 {
        r.count(&t, 1, line, "the boundary marker flag")?
    } else {
        0
    };
    if nmark > 1 {
        return Err(r.err(
            line,
            format!("boundary marker flag {nmark}: must be 0 or 1"),
        ));
    }
    let mut corners = if ele.order == 10 { 6 } else { 3 };
    let mut base = 1 + corners + nmark;
    let mut conn = Vec::with_capacity(capacity(n, &r, corners));
    let mut marks = Vec::with_capacity(capacity(n, &r, 1));
    let mut first = 0;
    for i in 0..n {
        let line = r.require(&mut t, &format!("face {i} of {n}"))?;
        check_index(&r, &t, line, i, &mut first, "face")?;
        // `tetgen -o2` writes 10-node tets but 3-node faces: the first line's field count says
        // which (3 nodes give 4 + markers or 6 + markers fields, 6 nodes 7 + markers or 9 +).
        if i == 0 && corners == 6 && (t.len() == 4 + nmark || t.len() == 6 + nmark) {
            corners = 3;
            base = 1 + corners + nmark;
        }
        if t.len() != base && t.len() != base + 2 {
            return Err(r.err(line, format!("a face line has {} fields, expected {base} (number, {corners} nodes, {nmark} markers) or {} with adjacent tetrahedra", t.len(), base + 2)));
        }
        for k in 0..corners {
            conn.push(node_ref(&r, &t, 1 + k, line, nodes)?);
        }
        let m = if nmark == 1 {
            r.marker(&t, 1 + corners, line, "the boundary marker")?
        } else {
            0
        };
        marks.push(
            i32::try_from(m)
                .map_err(|_| r.err(line, format!("boundary marker {m} does not fit 32 bits")))?,
        );
        for k in base..t.len() {
            r.int(&t, k, line, "an adjacent tetrahedron")?;
        }
    }
    if let Some(line) = r.next_into(&mut t) {
        return Err(r.err(
            line,
            format!("more lines after the {n} faces the header declares"),
        ));
    }
    let ty = if corners == 3 {
        cell_type::TRIANGLE
    } else {
        cell_type::QUADRATIC_TRIANGLE
    };
    let ntets = grid.num_cells();
    for f in conn.chunks_exact(corners) {
        grid.cells.push(ty, f);
    }
    for a in &mut grid.cell_data.arrays {
        if let ArrayData::Float64(v) = &mut a.data {
            v.resize(v.len() + n * a.components, f64::NAN);
        }
    }
    if nmark == 1 {
        let mut all = vec![0i32; ntets];
        all.extend_from_slice(&marks);
        grid.cell_data.arrays.push(DataArray::new(
            names::BOUNDARY_MARKER,
            1,
            ArrayData::Int32(all),
        ));
    }
    let _ = ele.count;
    Ok(())
}

/// `.neigh`: four neighbouring tets per tet (-1 on the boundary), kept as the Int64 cell array
/// `neighbors` with 0-based tet indices (-1 on boundary triangles too).
fn read_neigh(bytes: &[u8], path: &Path, ele: Eles, grid: &mut Grid) -> Result<()> {
    let mut r = Records::new(bytes, path);
    let mut t = Vec::new();
    let line = r.require(&mut t, "the .neigh header")?;
    let n = r.count(&t, 0, line, "the number of tetrahedra")?;
    if n != ele.count {
        return Err(r.err(
            line,
            format!("{n} tetrahedra, but the .ele file has {}", ele.count),
        ));
    }
    if t.len() > 1 && r.count(&t, 1, line, "the neighbours per tetrahedron")? != 4 {
        return Err(r.err(line, "neighbours per tetrahedron must be 4"));
    }
    let mut v = Vec::with_capacity(capacity(n, &r, 4));
    let mut first = 0;
    for i in 0..n {
        let line = r.require(&mut t, &format!("tetrahedron {i} of {n}"))?;
        check_index(&r, &t, line, i, &mut first, "tetrahedron")?;
        if t.len() != 5 {
            return Err(r.err(
                line,
                format!("a .neigh line has {} fields, expected 5", t.len()),
            ));
        }
        for k in 1..5 {
            let x = r.int(&t, k, line, "a neighbour")?;
            let id = if x == -1 {
                -1
            } else {
                x.checked_sub(ele.first)
                    .filter(|&id| id >= 0 && (id as u64) < n as u64)
                    .ok_or_else(|| {
                        r.err(
                            line,
                            format!("neighbour {x} is neither -1 nor a tetrahedron number"),
                        )
                    })?
            };
            v.push(id);
        }
    }
    if let Some(line) = r.next_into(&mut t) {
        return Err(r.err(
            line,
            format!("more lines after the {n} tetrahedra the header declares"),
        ));
    }
    v.resize(grid.num_cells() * 4, -1);
    grid.cell_data
        .arrays
        .push(DataArray::new(names::NEIGHBORS, 4, ArrayData::Int64(v)));
    Ok(())
}
