//! The Exodus II data model read from a NetCDF file, classic or NetCDF-4, into a [`Grid`].

use super::glom::glom;
use super::nc4::{is_hdf5, Nc4};
use super::netcdf::{File, NcType, Source};
use super::types::cell_kind;
use super::{names, warn};
use crate::error::numbered;
use crate::pvd::Selector;
use crate::{ArrayData, Cells, DataArray, FormatError, Grid, Result};
use std::path::Path;

/// Reads the Exodus file in `bytes` at the time step `sel` (see [`super::read_from`]).
pub(crate) fn read(bytes: &[u8], path: &Path, sel: Selector) -> Result<Grid> {
    if is_hdf5(bytes) {
        read_source(&Nc4::open(bytes, path)?, sel)
    } else {
        read_source(&File::parse(bytes, path)?, sel)
    }
}

/// The times of the file's steps in `bytes` (see [`times`]).
pub(crate) fn times_of(bytes: &[u8], path: &Path) -> Result<Vec<f64>> {
    if is_hdf5(bytes) {
        times(&Nc4::open(bytes, path)?)
    } else {
        times(&File::parse(bytes, path)?)
    }
}

fn read_source<S: Source>(f: &S, sel: Selector) -> Result<Grid> {
    let path = f.path();
    let whole = |msg: String| FormatError::whole(msg).with_file(path);
    exodus_or_refuse(f)?;
    let steps = f.numrecs();
    let step = match sel {
        Selector::Index(k) => k as u64,
        Selector::Last => steps.saturating_sub(1),
    };
    if step > 0 && step >= steps {
        return Err(whole(format!(
            "there is no time step {step}: the file has {steps}{}",
            if steps > 0 {
                format!(" (0 to {})", steps - 1)
            } else {
                String::new()
            }
        )));
    }
    let mut g = Grid {
        points: points(f)?,
        ..Grid::default()
    };
    let n_points = g.num_points();
    let blocks = blocks(f, n_points, &mut g.cells)?;
    let n_cells = g.cells.len();

    let ids: Vec<i32> = blocks
        .iter()
        .flat_map(|b| std::iter::repeat(b.id).take(b.cells))
        .collect();
    g.cell_data
        .insert(DataArray::new(names::OBJECT_ID, 1, ArrayData::Int32(ids)));
    if let Some(v) = f.var("eb_names") {
        let mut names = f.strings(v)?;
        names.truncate(blocks.len());
        g.field_data.push(DataArray::new(
            names::BLOCK_NAMES,
            1,
            ArrayData::String(names),
        ));
    }
    node_sets(f, n_points, &mut g)?;
    if f.dim("num_side_sets").is_some_and(|n| n > 0) {
        let names = set_names(f, "ss_names", "ss_prop1", "num_side_sets")?;
        warn(&format!(
            "{}: side sets skipped: {}",
            path.display(),
            names.join(", ")
        ));
    }
    skipped_data(f);
    if steps > 0 {
        // NaN for steps without a time (no `time_whole`): the array is there exactly when the
        // file has steps, so `tetkit info` lists them without reading the file again.
        g.field_data.push(DataArray::new(
            names::TIME,
            1,
            ArrayData::Float64(times(f)?),
        ));
        nodal_vars(f, step, n_points, &mut g)?;
        element_vars(f, step, &blocks, &mut g)?;
        global_vars(f, &mut g)?;
    }
    attributes(f, &blocks, &mut g)?;
    // After the variables: VTK's writer also stores the id arrays as variables of the same
    // name, and the maps win, as in VTK's reader.
    let map = id_map(f, "elem_num_map", n_cells)?;
    g.cell_data
        .insert(DataArray::new(names::ELEMENT_ID, 1, ArrayData::Int64(map)));
    let map = id_map(f, "node_num_map", n_points)?;
    g.point_data
        .insert(DataArray::new(names::NODE_ID, 1, ArrayData::Int64(map)));
    Ok(g)
}

/// Warns of the data the reader leaves out that a user would miss: node set and side set
/// variables, which become no array and went unmentioned.
fn skipped_data<S: Source>(f: &S) {
    for (count, what) in [
        ("num_nset_var", "node set variables"),
        ("num_sset_var", "side set variables"),
    ] {
        if let Some(n) = f.dim(count).filter(|&n| n > 0) {
            warn(&format!(
                "{}: {n} {what} skipped ({count})",
                f.path().display()
            ));
        }
    }
}

/// A NetCDF file that is not Exodus II (no `num_dim`, say: any NetCDF-4 file is HDF5, and
/// HDF5 files are many things) is refused naming what it lacks.
fn exodus_or_refuse<S: Source>(f: &S) -> Result<()> {
    if f.dim("num_dim").is_some() {
        return Ok(());
    }
    let mut missing = vec!["the dimension num_dim"];
    if f.dim("num_nodes").is_none() {
        missing.push("the dimension num_nodes");
    }
    if ["coordx", "coord"].iter().all(|v| f.var(v).is_none()) {
        missing.push("coordinates (coordx/coordy/coordz or coord)");
    }
    if f.var("connect1").is_none() {
        missing.push("connectivity (connect1)");
    }
    Err(FormatError::whole(format!(
        "a NetCDF file with {} dimensions and {} variables but not Exodus II: it lacks {}",
        f.num_dims(),
        f.num_vars(),
        missing.join(", ")
    ))
    .with_file(f.path()))
}

/// The time of each step (`time_whole`; NaN for a step without one).
pub(crate) fn times<S: Source>(f: &S) -> Result<Vec<f64>> {
    let Some(v) = f.var("time_whole") else {
        return Ok(vec![f64::NAN; f.numrecs() as usize]);
    };
    (0..f.numrecs())
        .map(|k| Ok(f.values::<f64>(v, k)?.first().copied().unwrap_or(f64::NAN)))
        .collect()
}

/// The dimension's length, 0 when the file lacks it.
fn dim<S: Source>(f: &S, name: &str) -> u64 {
    f.dim(name).unwrap_or(0)
}

fn points<S: Source>(f: &S) -> Result<DataArray> {
    let whole = |msg: String| FormatError::whole(msg).with_file(f.path());
    let n = dim(f, "num_nodes");
    let nd = dim(f, "num_dim");
    if !(1..=3).contains(&nd) {
        return Err(whole(format!("num_dim is {nd}; Exodus meshes have 1 to 3")));
    }
    let nd = nd as usize;
    // coordx, coordy, coordz; older files hold one `coord` of shape [num_dim][num_nodes].
    let axes: Vec<Option<usize>> = ["coordx", "coordy", "coordz"][..nd]
        .iter()
        .map(|a| f.var(a))
        .collect();
    let mut columns: Vec<Vec<f64>> = Vec::new();
    let mut float32 = true;
    if axes.iter().all(Option::is_some) {
        for v in axes.into_iter().flatten() {
            float32 &= f.ty(v) == Some(NcType::Float);
            columns.push(f.values(v, 0)?);
        }
    } else if let Some(v) = f.var("coord") {
        float32 = f.ty(v) == Some(NcType::Float);
        let all: Vec<f64> = f.values(v, 0)?;
        if all.len() as u64 != n * nd as u64 {
            return Err(f.err_var(
                v,
                format!("holds {} values, not num_dim x num_nodes", all.len()),
            ));
        }
        columns = all.chunks(n.max(1) as usize).map(<[f64]>::to_vec).collect();
        columns.truncate(nd);
    } else if n > 0 {
        return Err(whole(format!(
            "{n} nodes but no coordinates (coordx/coordy/coordz or coord)"
        )));
    } else {
        columns = vec![Vec::new(); nd];
    }
    for (k, c) in columns.iter().enumerate() {
        if c.len() as u64 != n {
            let name = ["coordx", "coordy", "coordz"][k];
            let v = f.var(name).or_else(|| f.var("coord")).unwrap_or(0);
            return Err(f.err_var(v, format!("{} coordinates for num_nodes {n}", c.len())));
        }
    }
    let n = n as usize;
    let coord = |i: usize, k: usize| columns.get(k).map_or(0.0, |c| c[i]);
    // Kept in the stored precision: single-precision files stay Float32.
    let data = if float32 {
        ArrayData::Float32(
            (0..n)
                .flat_map(|i| (0..3).map(move |k| (i, k)))
                .map(|(i, k)| coord(i, k) as f32)
                .collect(),
        )
    } else {
        ArrayData::Float64(
            (0..n)
                .flat_map(|i| (0..3).map(move |k| (i, k)))
                .map(|(i, k)| coord(i, k))
                .collect(),
        )
    };
    Ok(DataArray::new("Points", 3, data))
}

/// One element block as read: its id and how many cells it gave.
pub(crate) struct Block {
    pub id: i32,
    pub cells: usize,
}

fn blocks<S: Source>(f: &S, n_points: usize, cells: &mut Cells) -> Result<Vec<Block>> {
    let n = dim(f, "num_el_blk");
    let ids = match f.var("eb_prop1") {
        Some(v) => {
            let ids: Vec<i64> = f.values(v, 0)?;
            if ids.len() as u64 != n {
                return Err(f.err_var(v, format!("{} ids for num_el_blk {n}", ids.len())));
            }
            ids.into_iter()
                .map(|id| {
                    i32::try_from(id)
                        .map_err(|_| f.err_var(v, format!("block id {id} does not fit Int32")))
                })
                .collect::<Result<Vec<i32>>>()?
        }
        // No ids: number the blocks from 1, as they are named connect1, connect2, ...
        None => {
            // Each block has a dimension or variable of its own: a larger count is corrupt.
            if n > (f.num_dims() + f.num_vars()) as u64 {
                return Err(FormatError::whole(format!(
                    "num_el_blk is {n}, more blocks than the file describes"
                ))
                .with_file(f.path()));
            }
            (1..=n as i32).collect()
        }
    };
    let mut out = Vec::with_capacity(ids.len());
    for (b, &id) in ids.iter().enumerate() {
        let k = b + 1;
        let n_el = dim(f, &format!("num_el_in_blk{k}"));
        let conn = f.var(&format!("connect{k}"));
        if n_el == 0 {
            // An empty (null) block gives no cells but keeps its place for element variables.
            out.push(Block { id, cells: 0 });
            continue;
        }
        // Elements without connectivity cannot be read; dropping them would lose the block (VTK
        // refuses the file too: "Could not read block params").
        let Some(v) = conn else {
            return Err(FormatError::whole(format!(
                "element block {k} (id {id}) has {n_el} elements (num_el_in_blk{k}) but no \
                 connectivity variable connect{k}"
            ))
            .with_file(f.path()));
        };
        if f.is_record(v) {
            return Err(f.err_var(v, "is a record variable; connectivity is fixed"));
        }
        let elem_type = f
            .attr_text(v, "elem_type")
            .ok_or_else(|| f.err_var(v, "has no elem_type attribute"))?;
        let shape = f.shape(v);
        let npe = match shape.as_slice() {
            [rows, npe] if *rows == n_el => *npe as usize,
            _ => {
                return Err(f.err_var(
                    v,
                    format!("has shape {shape:?}, not [num_el_in_blk{k} = {n_el}, nodes]"),
                ))
            }
        };
        let kind = cell_kind(&elem_type, npe).map_err(|m| f.err_var(v, m))?;
        let ids: Vec<i64> = f.values(v, 0)?;
        let mut vtk = vec![0i64; npe];
        for (e, el) in ids.chunks_exact(npe.max(1)).enumerate() {
            for (j, slot) in vtk.iter_mut().enumerate() {
                let node = el[kind.perm.map_or(j, |p| p[j])];
                if node < 1 || node > n_points as i64 {
                    return Err(f.err_var(
                        v,
                        format!(
                            "element {} names node {node}, out of range ({})",
                            e + 1,
                            numbered(n_points as u64, "node", 1)
                        ),
                    ));
                }
                *slot = node - 1;
            }
            cells.push(kind.vtk, &vtk);
        }
        out.push(Block {
            id,
            cells: n_el as usize,
        });
    }
    Ok(out)
}

/// A node or element number map; a file without one numbers its objects 1, 2, ... (Exodus's
/// default map, which VTK's reader gives too).
fn id_map<S: Source>(f: &S, name: &str, expect: usize) -> Result<Vec<i64>> {
    let Some(v) = f.var(name) else {
        return Ok((1..=expect as i64).collect());
    };
    let map: Vec<i64> = f.values(v, 0)?;
    if map.len() != expect {
        return Err(f.err_var(v, format!("{} entries for {expect} objects", map.len())));
    }
    Ok(map)
}

/// The names of the sets counted by dimension `count`: from `names_var` where given and not
/// empty, else the set's id from `ids_var`, else its number.
fn set_names<S: Source>(f: &S, names_var: &str, ids_var: &str, count: &str) -> Result<Vec<String>> {
    let n = dim(f, count) as usize;
    let given = match f.var(names_var) {
        Some(v) => f.strings(v)?,
        None => Vec::new(),
    };
    let ids: Vec<i64> = match f.var(ids_var) {
        Some(v) => f.values(v, 0)?,
        None => Vec::new(),
    };
    // A name per set, but no more sets than the file has variables for.
    let n = n.min(given.len().max(ids.len()).max(f.num_vars()));
    Ok((0..n)
        .map(|i| match (given.get(i), ids.get(i)) {
            (Some(s), _) if !s.is_empty() => s.clone(),
            (_, Some(id)) => id.to_string(),
            _ => (i + 1).to_string(),
        })
        .collect())
}

/// Node sets as UInt8 point arrays `nodeset:NAME` (1 for the set's nodes).
fn node_sets<S: Source>(f: &S, n_points: usize, g: &mut Grid) -> Result<()> {
    if dim(f, "num_node_sets") == 0 {
        return Ok(());
    }
    let names = set_names(f, "ns_names", "ns_prop1", "num_node_sets")?;
    for (i, name) in names.iter().enumerate() {
        let Some(v) = f.var(&format!("node_ns{}", i + 1)) else {
            continue;
        };
        let mut mark = vec![0u8; n_points];
        for node in f.values::<i64>(v, 0)? {
            if node < 1 || node > n_points as i64 {
                return Err(f.err_var(
                    v,
                    format!(
                        "names node {node}, out of range ({})",
                        numbered(n_points as u64, "node", 1)
                    ),
                ));
            }
            mark[node as usize - 1] = 1;
        }
        g.point_data.insert(DataArray::new(
            format!("{}{name}", names::NODE_SET_PREFIX),
            1,
            ArrayData::UInt8(mark),
        ));
    }
    Ok(())
}

/// Variable names from `var` (`name_nod_var`, ...), `fallback{k}` where missing or empty.
fn var_names<S: Source>(f: &S, var: &str, count: usize, fallback: &str) -> Result<Vec<String>> {
    let given = match f.var(var) {
        Some(v) => f.strings(v)?,
        None => Vec::new(),
    };
    // Each variable has a name row or a variable of its own in the file: a larger count is
    // corrupt, and is refused before anything is allocated for it.
    if count > given.len().max(f.num_vars()) {
        return Err(FormatError::whole(format!(
            "{count} variables counted for {var}, more than the file could hold"
        ))
        .with_file(f.path()));
    }
    Ok((0..count)
        .map(|k| match given.get(k) {
            Some(s) if !s.is_empty() => s.clone(),
            _ => format!("{fallback}{}", k + 1),
        })
        .collect())
}

/// Values as the file stores them: Float32 when it does, else Float64.
fn typed(float32: bool, values: Vec<f64>) -> ArrayData {
    if float32 {
        ArrayData::Float32(values.into_iter().map(|v| v as f32).collect())
    } else {
        ArrayData::Float64(values)
    }
}

/// One variable's values over the mesh's nodes or cells, and whether the file stores it as
/// Float32; `None` where the file has no values for it.
type Column = Option<(Vec<f64>, bool)>;

/// The arrays of the variables `names` (their values in `columns`, `n` each) joined as VTK's
/// reader joins them (see [`glom`]): components in the variables' order, named by the
/// variables they came from; NaN for a component without values. With `pad` (a 2-D mesh's
/// nodal and element variables) a 2-component array gets a third, 0, as VTK gives it.
fn joined(
    names: &[String],
    columns: Vec<Column>,
    n: usize,
    pad: bool,
    joins: impl Fn(usize) -> bool,
) -> Vec<DataArray> {
    let mut out = Vec::new();
    for g in glom(names, joins) {
        let parts: Vec<&Column> = g.members.iter().map(|&k| &columns[k]).collect();
        if parts.iter().all(|c| c.is_none()) {
            continue;
        }
        let float32 = parts.iter().copied().flatten().all(|(_, f)| *f);
        let c = if pad && parts.len() == 2 {
            3
        } else {
            parts.len()
        };
        let mut values = Vec::with_capacity(n * c);
        for i in 0..n {
            for k in 0..c {
                values.push(match parts.get(k) {
                    Some(Some((v, _))) => v[i],
                    Some(None) => f64::NAN,
                    None => 0.0,
                });
            }
        }
        let mut a = DataArray::new(g.name, c, typed(float32, values));
        if c > 1 && c == parts.len() {
            a.component_names = g.members.iter().map(|&k| names[k].clone()).collect();
        }
        out.push(a);
    }
    out
}

fn nodal_vars<S: Source>(f: &S, step: u64, n_points: usize, g: &mut Grid) -> Result<()> {
    let n = dim(f, "num_nod_var") as usize;
    if n == 0 {
        return Ok(());
    }
    // Each name takes at least a byte of the file; a count beyond that is corrupt.
    let names = var_names(f, "name_nod_var", n, "nod_var")?;
    // Old files keep all nodal variables in one `vals_nod_var` [time][num_nod_var][num_nodes].
    let old = f.var("vals_nod_var");
    let old_values: Option<Vec<f64>> = match old {
        Some(v) => Some(f.values(v, step)?),
        None => None,
    };
    let mut columns: Vec<Column> = Vec::with_capacity(n);
    for (k, name) in names.iter().enumerate() {
        columns.push(match (&old_values, old) {
            (Some(all), Some(v)) => {
                let part = all.get(k * n_points..(k + 1) * n_points).ok_or_else(|| {
                    f.err_var(
                        v,
                        format!("holds too few values for nodal variable {}", k + 1),
                    )
                })?;
                Some((part.to_vec(), f.ty(v) == Some(NcType::Float)))
            }
            _ => match f.var(&format!("vals_nod_var{}", k + 1)) {
                Some(v) => {
                    let values: Vec<f64> = f.values(v, step)?;
                    if values.len() != n_points {
                        return Err(
                            f.err_var(v, format!("{} values for {n_points} nodes", values.len()))
                        );
                    }
                    Some((values, f.ty(v) == Some(NcType::Float)))
                }
                None => {
                    warn(&format!(
                        "{}: nodal variable '{name}' has no values (vals_nod_var{}); {}",
                        f.path().display(),
                        k + 1,
                        "skipped, or NaN in the array it joins"
                    ));
                    None
                }
            },
        });
    }
    let pad = dim(f, "num_dim") == 2;
    for a in joined(&names, columns, n_points, pad, |_| true) {
        g.point_data.insert(a);
    }
    Ok(())
}

fn element_vars<S: Source>(f: &S, step: u64, blocks: &[Block], g: &mut Grid) -> Result<()> {
    let n = dim(f, "num_elem_var") as usize;
    if n == 0 {
        return Ok(());
    }
    let names = var_names(f, "name_elem_var", n, "elem_var")?;
    // The truth table says which blocks hold which variable; without one, a block holds those
    // whose values are in the file.
    let table: Option<Vec<i64>> = match f.var("elem_var_tab") {
        Some(v) => {
            let t: Vec<i64> = f.values(v, 0)?;
            if t.len() != blocks.len() * n {
                return Err(f.err_var(
                    v,
                    format!(
                        "{} entries for {} blocks x {n} variables",
                        t.len(),
                        blocks.len()
                    ),
                ));
            }
            Some(t)
        }
        None => None,
    };
    let held = |b: usize, k: usize| table.as_ref().map_or(true, |t| t[b * n + k] != 0);
    let total: usize = blocks.iter().map(|b| b.cells).sum();
    let mut columns: Vec<Column> = Vec::with_capacity(n);
    for k in 0..n {
        let mut values = Vec::with_capacity(total);
        let mut float32 = true;
        for (b, block) in blocks.iter().enumerate() {
            let var = f.var(&format!("vals_elem_var{}eb{}", k + 1, b + 1));
            match var.filter(|_| held(b, k) && block.cells > 0) {
                Some(v) => {
                    let vals: Vec<f64> = f.values(v, step)?;
                    if vals.len() != block.cells {
                        return Err(f.err_var(
                            v,
                            format!("{} values for {} elements", vals.len(), block.cells),
                        ));
                    }
                    float32 &= f.ty(v) == Some(NcType::Float);
                    values.extend(vals);
                }
                // NaN where the block does not hold the variable, as VTK leaves it undefined.
                None => values.extend(std::iter::repeat(f64::NAN).take(block.cells)),
            }
        }
        columns.push(Some((values, float32)));
    }
    // VTK starts an array only at a variable some block holds; the other components follow
    // whatever the truth table says of them, each NaN where its block lacks it (VTK reads the
    // first component's blocks only, and fails on a block that lacks a later one).
    let pad = dim(f, "num_dim") == 2;
    let starts = |k: usize| (0..blocks.len()).any(|b| held(b, k));
    for a in joined(&names, columns, total, pad, starts) {
        g.cell_data.insert(a);
    }
    Ok(())
}

/// Element attributes (`attrib{k}`: a beam's area, a sphere's radius, a shell's thickness) as
/// cell arrays named from `attrib_name{k}` (`attrib{j}` where unnamed), one per name and not
/// joined, as VTK's reader gives them; NaN in blocks without the attribute. A name that an
/// element variable already has gets `_` appended, so neither is lost.
fn attributes<S: Source>(f: &S, blocks: &[Block], g: &mut Grid) -> Result<()> {
    let total: usize = blocks.iter().map(|b| b.cells).sum();
    let mut arrays: Vec<(String, Vec<f64>, bool)> = Vec::new();
    let mut at = 0;
    for (b, block) in blocks.iter().enumerate() {
        let k = b + 1;
        let var = f.var(&format!("attrib{k}")).filter(|_| block.cells > 0);
        if let Some(v) = var {
            let na = dim(f, &format!("num_att_in_blk{k}")) as usize;
            let values: Vec<f64> = f.values(v, 0)?;
            if values.len() != na * block.cells {
                return Err(f.err_var(
                    v,
                    format!(
                        "holds {} values, not {} elements x num_att_in_blk{k} = {na}",
                        values.len(),
                        block.cells
                    ),
                ));
            }
            // The count is bounded by the values just read, so no name row limit is needed.
            let given = match f.var(&format!("attrib_name{k}")) {
                Some(v) => f.strings(v)?,
                None => Vec::new(),
            };
            let names = (0..na).map(|j| match given.get(j) {
                Some(s) if !s.is_empty() => s.clone(),
                _ => format!("attrib{}", j + 1),
            });
            let float32 = f.ty(v) == Some(NcType::Float);
            for (j, name) in names.enumerate() {
                let slot = match arrays.iter().position(|a| a.0 == name) {
                    Some(s) => s,
                    None => {
                        arrays.push((name, vec![f64::NAN; total], true));
                        arrays.len() - 1
                    }
                };
                let (_, column, f32s) = &mut arrays[slot];
                *f32s &= float32;
                for (e, x) in column[at..at + block.cells].iter_mut().enumerate() {
                    *x = values[e * na + j];
                }
            }
        }
        at += block.cells;
    }
    for (mut name, values, float32) in arrays {
        while g.cell_data.get(&name).is_some() {
            name.push('_');
        }
        g.cell_data
            .insert(DataArray::new(name, 1, typed(float32, values)));
    }
    Ok(())
}

/// Global variables: one field array each (joined as nodal ones are, never padded), its value
/// at every time step.
fn global_vars<S: Source>(f: &S, g: &mut Grid) -> Result<()> {
    let n = dim(f, "num_glo_var") as usize;
    let Some(v) = f.var("vals_glo_var").filter(|_| n > 0) else {
        return Ok(());
    };
    let names = var_names(f, "name_glo_var", n, "glo_var")?;
    let steps = f.numrecs() as usize;
    let mut columns = vec![Vec::with_capacity(steps.min(1 << 16)); n];
    for step in 0..f.numrecs() {
        let row: Vec<f64> = f.values(v, step)?;
        if row.len() != n {
            return Err(f.err_var(v, format!("{} values for {n} global variables", row.len())));
        }
        for (c, x) in columns.iter_mut().zip(row) {
            c.push(x);
        }
    }
    // Float64 whatever the file stores, as before.
    let columns = columns.into_iter().map(|c| Some((c, false))).collect();
    g.field_data
        .extend(joined(&names, columns, steps, false, |_| true));
    Ok(())
}
