//! Splitting non-tet cells into conforming, positively oriented linear tets, carrying the data.
//!
//! Supported 3-D cells: tetra (kept; flipped if inverted), voxel, hexahedron, wedge, pyramid,
//! pentagonal and hexagonal prism, polyhedron (any closed polyhedron star-shaped from its smallest
//! vertex or from its centre), quadratic tetra (10 nodes -> 8 tets), and second-order
//! hexahedra, wedges and pyramids, cut into linear pieces over their nodes first: triquadratic
//! (27-node) and quadratic (20-node) hexahedra into 8 hexahedra, biquadratic-quadratic (18-node)
//! and quadratic (15-node) wedges into 8 wedges, quadratic-linear (12-node) wedges into 4, and
//! quadratic (13-node) pyramids into 6 pyramids and 4 tets (see [`cells::sub_cells`]). The
//! 20-node hexahedron, 15-node wedge and 13-node pyramid lack nodes those pieces need (face
//! centres, the body centre) and get them first as new points placed by the cell's own shape
//! functions, one point per face for all the cells on it, with float point data by the same
//! weights and integer and string data from the smallest-id corner (see [`quadratic`]). Other
//! quadratic 3-D cells are refused with an error naming the cell. See [`cells`] for the split
//! rule and why it is conforming.
//!
//! Data: every point is kept, in order, with its point data; cell data is copied to each child and
//! an Int64 `original_cell_id` cell array gives each output cell's input cell (when the input
//! already has an integer `original_cell_id`, its values are carried instead, so ids keep pointing
//! at the first mesh). A cell that needs a centre point adds one point at the mean of its
//! vertices; that point's float arrays are the mean of the vertices' tuples, and its integer and
//! string arrays (labels, markers, ids) take the tuple of the cell's smallest-id vertex, since a
//! mean label means nothing. 2-D, 1-D and 0-D cells are kept as they are (`keep_lower`) or
//! dropped and counted.

pub mod cells;
mod quadratic;

use anyhow::{bail, Result};
use formats::grid::Element;
use formats::{cell_type as ct, ArrayData, Attribute, Attributes, Cells, DataArray, Grid};
use rayon::prelude::*;

use cells::{Split, CENTRE};

/// What tetrahedralization did, for the user.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TetrahedralizeReport {
    /// `(cell type, cells of that type that were split)`, by type id.
    pub split: Vec<(u8, usize)>,
    /// Linear tets passed through.
    pub kept_tets: usize,
    /// Input cells that were inverted (negative volume) and whose tets were flipped.
    pub inverted: usize,
    /// Input linear tets with exactly zero volume (kept as they are: nothing to split).
    pub flat_tets: usize,
    /// Cells filled from a new centre point because pulling from a vertex was invalid.
    pub centre_points: usize,
    /// `(cell type, count)` of 2-D and lower cells kept (`keep_lower`).
    pub kept_lower: Vec<(u8, usize)>,
    /// 2-D and lower cells dropped (only when `keep_lower` is false), in all.
    pub dropped: usize,
    /// `(cell type, count)` of the dropped cells.
    pub dropped_by_type: Vec<(u8, usize)>,
    /// Tets in the output.
    pub tets_out: usize,
}

impl TetrahedralizeReport {
    /// What splitting `n` cells of type `t` did, for stderr.
    pub fn split_line(t: u8, n: usize) -> String {
        if t == ct::LAGRANGE_TETRAHEDRON {
            format!(
                "split {n} {} cells into tets (second-order ones over their 10 nodes, as a quadratic tetra; higher orders by their corners, their other nodes and curvature not used, the nodes staying in the mesh)",
                ct::name(t)
            )
        } else if ct::is_higher_order(t) {
            format!(
                "split {n} {} cells into tets by their corners (their higher-order nodes and curvature are not used; the nodes stay in the mesh)",
                ct::name(t)
            )
        } else {
            format!("split {n} {} cells into tets", ct::name(t))
        }
    }

    /// One line per fact worth telling a user (for stderr).
    pub fn lines(&self) -> Vec<String> {
        let mut out = Vec::new();
        for &(t, n) in &self.split {
            out.push(Self::split_line(t, n));
        }
        if self.centre_points > 0 {
            out.push(format!(
                "{} warped or concave cells were split around a new centre point",
                self.centre_points
            ));
        }
        if self.inverted > 0 {
            out.push(format!(
                "{} inverted cells (negative volume) were flipped",
                self.inverted
            ));
        }
        if self.flat_tets > 0 {
            out.push(format!(
                "warning: {} input tets have zero volume (kept)",
                self.flat_tets
            ));
        }
        for (t, n) in &self.kept_lower {
            out.push(format!("kept {n} {} cells as they are", ct::name(*t)));
        }
        for (t, n) in &self.dropped_by_type {
            out.push(format!(
                "dropped {n} {} cells (only tets are kept)",
                ct::name(*t)
            ));
        }
        out.push(format!("{} tets out", self.tets_out));
        out
    }
}

/// One chunk's output; new points are numbered locally as `-(k + 2)` in `conn` until merged
/// (`-1` is [`CENTRE`] inside a split).
#[derive(Default)]
struct Chunk {
    types: Vec<u8>,
    conn: Vec<i64>,
    sizes: Vec<u32>,
    parents: Vec<usize>,
    /// New points: coordinates (rounded to the stored type) and the vertices they come from.
    centres: Vec<([f64; 3], Vec<i64>)>,
    split: Vec<usize>,
    dropped: Vec<usize>,
    kept_lower: Vec<usize>,
    kept_tets: usize,
    inverted: usize,
    flat_tets: usize,
}

impl Chunk {
    fn new() -> Chunk {
        Chunk {
            split: vec![0; 256],
            dropped: vec![0; 256],
            kept_lower: vec![0; 256],
            ..Chunk::default()
        }
    }

    fn push_cell(&mut self, ty: u8, ids: &[i64], parent: usize) {
        self.types.push(ty);
        self.conn.extend_from_slice(ids);
        self.sizes.push(ids.len() as u32);
        self.parents.push(parent);
    }

    /// Pushes a split's tets (the caller counts an inverted cell once, however many pieces).
    fn push_split(&mut self, s: Split, parent: usize, verts: impl FnOnce() -> Vec<i64>) {
        let local = s.centre.map(|c| {
            self.centres.push((c, verts()));
            -(self.centres.len() as i64 + 1)
        });
        for t in s.tets {
            let t = t.map(|v| if v == CENTRE { local.unwrap_or(v) } else { v });
            self.push_cell(ct::TETRA, &t, parent);
        }
    }
}

/// Start of each cell's face stream in `polyhedron_faces` (only meaningful for polyhedra).
fn face_stream_starts(grid: &Grid) -> Option<Vec<usize>> {
    let (_, ends) = grid.cells.polyhedron_faces.as_ref()?;
    let mut starts = Vec::with_capacity(ends.len());
    let mut next = 0usize;
    for &e in ends {
        starts.push(next);
        if e >= 0 {
            next = e as usize;
        }
    }
    Some(starts)
}

/// The faces of polyhedron `i`, from the face stream (`nfaces, (npts, ids...)*`).
fn polyhedron_faces(
    grid: &Grid,
    starts: Option<&[usize]>,
    i: usize,
) -> Result<Vec<Vec<i64>>, String> {
    let (Some((faces, ends)), Some(starts)) = (grid.cells.polyhedron_faces.as_ref(), starts) else {
        return Err("polyhedron without a face stream".into());
    };
    let end = ends.get(i).copied().unwrap_or(-1);
    if end < 0 {
        return Err("polyhedron without a face stream".into());
    }
    let stream = faces
        .get(starts[i]..end as usize)
        .ok_or("face stream out of range")?;
    let bad = || "malformed face stream".to_string();
    let (&nf, mut rest) = stream.split_first().ok_or_else(bad)?;
    let mut out = Vec::new();
    for _ in 0..nf.max(0) {
        let (&np, r) = rest.split_first().ok_or_else(bad)?;
        let np = usize::try_from(np).map_err(|_| bad())?;
        if r.len() < np {
            return Err(bad());
        }
        out.push(r[..np].to_vec());
        rest = &r[np..];
    }
    let np = grid.num_points() as i64;
    if out.iter().flatten().any(|&v| v < 0 || v >= np) {
        return Err("face stream names a point out of range".into());
    }
    Ok(out)
}

const UNSUPPORTED: &str = "this cell type is not supported by tetrahedralization (supported: tetra, voxel, hexahedron, wedge, pyramid, pentagonal/hexagonal prism, polyhedron, quadratic tetra, quadratic and triquadratic hexahedron, quadratic, quadratic-linear and biquadratic-quadratic wedge, quadratic pyramid, Lagrange and Bezier tetra, hexahedron, wedge and pyramid by their corners)";

/// The 3-D cell types [`tetrahedralize`] splits.
const SPLITTABLE: [u8; 15] = [
    ct::TETRA,
    ct::VOXEL,
    ct::HEXAHEDRON,
    ct::WEDGE,
    ct::PYRAMID,
    ct::PENTAGONAL_PRISM,
    ct::HEXAGONAL_PRISM,
    ct::POLYHEDRON,
    ct::QUADRATIC_TETRA,
    ct::QUADRATIC_HEXAHEDRON,
    ct::TRIQUADRATIC_HEXAHEDRON,
    ct::QUADRATIC_WEDGE,
    ct::QUADRATIC_LINEAR_WEDGE,
    ct::BIQUADRATIC_QUADRATIC_WEDGE,
    ct::QUADRATIC_PYRAMID,
];

/// Splits every 3-D cell into linear tets. `keep_lower`: keep 0-, 1- and 2-D cells as they are
/// (convert) instead of dropping them (stages that need only tets). Errors name the first cell
/// that cannot be split.
pub fn tetrahedralize(grid: &Grid, keep_lower: bool) -> Result<(Grid, TetrahedralizeReport)> {
    if let Err(m) = grid.validate() {
        bail!("invalid mesh: {m}");
    }
    // Refuse a cell type that cannot be split before anything is made, naming the first such
    // cell (a file mixing them with splittable cells gets the same message wherever they are).
    if let Some(i) =
        grid.cells.types.iter().position(|&t| {
            ct::dimension(t) == 3 && !SPLITTABLE.contains(&t) && !ct::is_higher_order(t)
        })
    {
        let t = grid.cells.types[i];
        bail!("cell {i} ({}, type {t}): {UNSUPPORTED}", ct::name(t));
    }
    // Quadratic cells lacking face nodes get them (same type, more nodes: only for the split).
    let completed = quadratic::complete(grid);
    let grid = completed.as_ref().unwrap_or(grid);
    let pts = grid.points_f64();
    let pos = |i: i64| pts[i as usize];
    let float32 = matches!(grid.points.data, ArrayData::Float32(_));
    let float64 = matches!(grid.points.data, ArrayData::Float64(_));
    let round = move |p: [f64; 3]| {
        if float64 {
            p
        } else if float32 {
            p.map(|x| x as f32 as f64)
        } else {
            p.map(|x| x.round())
        }
    };
    let starts = face_stream_starts(grid);
    let sub_cells: Vec<Vec<cells::SubCell>> = (0..=255u8).map(cells::sub_cells).collect();
    let prism5 = cells::prism_faces(5);
    let prism6 = cells::prism_faces(6);
    let prism5: Vec<&[usize]> = prism5.iter().map(|f| f.as_slice()).collect();
    let prism6: Vec<&[usize]> = prism6.iter().map(|f| f.as_slice()).collect();
    let n = grid.num_cells();
    const CHUNK: usize = 8192;

    let process = |range: std::ops::Range<usize>| -> Result<Chunk, String> {
        let mut out = Chunk::new();
        for i in range {
            let t = grid.cells.types[i];
            let ids = grid.cells.cell(i);
            let fail = |what: &str| format!("cell {i} ({}, type {t}): {what}", ct::name(t));
            let invalid = || {
                fail("cannot be split into positively oriented tets (flat, or so warped or concave that no point inside it sees all its faces)")
            };
            if ct::dimension(t) < 3 {
                if keep_lower {
                    out.push_cell(t, ids, i);
                    out.kept_lower[t as usize] += 1;
                } else {
                    out.dropped[t as usize] += 1;
                }
                continue;
            }
            // Lagrange and Bezier cells by the linear cell of their corners (VTK lists the
            // corners first, in the linear cell's order; both kinds interpolate at them).
            let lin = ct::linear_counterpart(t).filter(|_| ct::is_higher_order(t));
            let (t, ids) = match lin {
                Some(l) => {
                    let n = ct::fixed_size(l).unwrap_or(0);
                    if ids.len() < n {
                        return Err(fail(&format!(
                            "has {} nodes, fewer than its {n} corners",
                            ids.len()
                        )));
                    }
                    (l, &ids[..n])
                }
                None => (t, ids),
            };
            if let (Some(_), ct::TETRA) = (lin, t) {
                let nodes = grid.cells.cell(i);
                if grid.cells.types[i] == ct::LAGRANGE_TETRAHEDRON && nodes.len() == 10 {
                    // A second-order Lagrange tet lists its nodes as the quadratic tetra does
                    // (corners, then mid-edges 01 12 20 03 13 23), and interpolates at all of
                    // them: split over them as that cell is.
                    let s = cells::split_quadratic_tet(nodes, &pos).map_err(|_| invalid())?;
                    out.inverted += s.inverted as usize;
                    out.push_split(s, i, Vec::new);
                    out.split[ct::LAGRANGE_TETRAHEDRON as usize] += 1;
                    continue;
                }
                let q = [ids[0], ids[1], ids[2], ids[3]];
                let (q, inv) = cells::orient_tet(q, &pos).ok_or_else(invalid)?;
                out.push_cell(t, &q, i);
                out.inverted += inv as usize;
                out.split[grid.cells.types[i] as usize] += 1;
                continue;
            }
            match t {
                ct::TETRA => {
                    let q = [ids[0], ids[1], ids[2], ids[3]];
                    match cells::orient_tet(q, &pos) {
                        Some((q, inv)) => {
                            out.push_cell(t, &q, i);
                            out.inverted += inv as usize;
                        }
                        None => {
                            out.push_cell(t, &q, i);
                            out.flat_tets += 1;
                        }
                    }
                    out.kept_tets += 1;
                    continue;
                }
                ct::VOXEL
                | ct::HEXAHEDRON
                | ct::WEDGE
                | ct::PYRAMID
                | ct::PENTAGONAL_PRISM
                | ct::HEXAGONAL_PRISM => {
                    let voxel;
                    let (ids, faces): (&[i64], &[&[usize]]) = match t {
                        ct::VOXEL => {
                            voxel = cells::VOXEL_TO_HEX.map(|l| ids[l]);
                            (&voxel, &cells::HEX_FACES)
                        }
                        ct::HEXAHEDRON => (ids, &cells::HEX_FACES),
                        ct::WEDGE => (ids, &cells::WEDGE_FACES),
                        ct::PYRAMID => (ids, &cells::PYRAMID_FACES),
                        ct::PENTAGONAL_PRISM => (ids, &prism5),
                        _ => (ids, &prism6),
                    };
                    let s = cells::split_table(ids, faces, &pos, &round).map_err(|_| invalid())?;
                    out.inverted += s.inverted as usize;
                    out.push_split(s, i, || ids.to_vec());
                }
                ct::QUADRATIC_TETRA => {
                    let s = cells::split_quadratic_tet(ids, &pos).map_err(|_| invalid())?;
                    out.inverted += s.inverted as usize;
                    out.push_split(s, i, Vec::new);
                }
                _ if !sub_cells[t as usize].is_empty() => {
                    // Linear pieces over the nodes. They must all turn the same way: a piece
                    // turned over means a tangled cell, whose tets would overlap.
                    let mut inverted = None;
                    for (local, faces) in &sub_cells[t as usize] {
                        let mut buf = [0i64; 8];
                        let piece = &mut buf[..local.len()];
                        for (v, &l) in piece.iter_mut().zip(local) {
                            *v = ids[l];
                        }
                        let s = cells::split_table(piece, faces, &pos, &round)
                            .map_err(|_| invalid())?;
                        if *inverted.get_or_insert(s.inverted) != s.inverted {
                            return Err(fail(
                                "is tangled: some of its linear pieces are inverted and others not",
                            ));
                        }
                        out.push_split(s, i, || piece.to_vec());
                    }
                    out.inverted += (inverted == Some(true)) as usize;
                }
                ct::POLYHEDRON => {
                    let mut faces =
                        polyhedron_faces(grid, starts.as_deref(), i).map_err(|m| fail(&m))?;
                    cells::orient_polyhedron_faces(&mut faces).map_err(|m| fail(&m))?;
                    let s = cells::split_polytope(&faces, &pos, &round).map_err(|_| invalid())?;
                    out.push_split(s, i, || {
                        let mut v: Vec<i64> = faces.iter().flatten().copied().collect();
                        v.sort_unstable();
                        v.dedup();
                        v
                    });
                }
                _ => return Err(fail(UNSUPPORTED)),
            }
            // Counted by the input's type (a Lagrange hexahedron, not the hexahedron it became).
            out.split[grid.cells.types[i] as usize] += 1;
        }
        Ok(out)
    };

    let ranges: Vec<_> = (0..n.div_ceil(CHUNK))
        .map(|c| c * CHUNK..((c + 1) * CHUNK).min(n))
        .collect();
    let chunks: Vec<Result<Chunk, String>> = ranges.into_par_iter().map(process).collect();

    // Merge, numbering new points after the existing ones, in cell order.
    let np = grid.num_points() as i64;
    let mut report = TetrahedralizeReport::default();
    let mut cells_out = Cells::new();
    let mut parents = Vec::new();
    let mut centres: Vec<([f64; 3], Vec<i64>)> = Vec::new();
    let (mut split, mut dropped, mut kept) =
        (vec![0usize; 256], vec![0usize; 256], vec![0usize; 256]);
    let total: usize = chunks
        .iter()
        .map(|c| c.as_ref().map_or(0, |c| c.types.len()))
        .sum();
    cells_out.types.reserve(total);
    cells_out.offsets.reserve(total);
    parents.reserve(total);
    for c in chunks {
        let c = c.map_err(anyhow::Error::msg)?;
        let base = np + centres.len() as i64;
        cells_out.types.extend_from_slice(&c.types);
        cells_out.connectivity.extend(
            c.conn
                .iter()
                .map(|&v| if v < 0 { base + (-v - 2) } else { v }),
        );
        let mut off = *cells_out.offsets.last().unwrap_or(&0);
        for s in &c.sizes {
            off += *s as i64;
            cells_out.offsets.push(off);
        }
        parents.extend_from_slice(&c.parents);
        centres.extend(c.centres);
        for t in 0..256 {
            split[t] += c.split[t];
            dropped[t] += c.dropped[t];
            kept[t] += c.kept_lower[t];
        }
        report.kept_tets += c.kept_tets;
        report.inverted += c.inverted;
        report.flat_tets += c.flat_tets;
    }
    let by_type = |v: &[usize]| -> Vec<(u8, usize)> {
        (0..256)
            .filter(|&t| v[t] > 0)
            .map(|t| (t as u8, v[t]))
            .collect()
    };
    report.split = by_type(&split);
    report.dropped_by_type = by_type(&dropped);
    report.dropped = dropped.iter().sum();
    report.kept_lower = by_type(&kept);
    report.centre_points = centres.len();
    report.tets_out = cells_out.types.iter().filter(|&&t| t == ct::TETRA).count();

    let mut points = grid.points.clone();
    let mut point_data = grid.point_data.clone();
    if !centres.is_empty() {
        let coords: Vec<f64> = centres.iter().flat_map(|(c, _)| *c).collect();
        append_values(&mut points.data, &coords);
        append_centre_data(&mut point_data, &centres);
    }
    let mut cell_data = grid.cell_data.gather(&parents);
    // Children share their parent's tuple, so ids declared globally unique no longer are.
    cell_data.active.retain(|(r, _)| *r != Attribute::GlobalIds);
    let carried = grid
        .cell_data
        .get("original_cell_id")
        .filter(|a| a.components == 1 && a.data.scalar_type().is_some_and(|t| !t.is_float()));
    if carried.is_none() {
        cell_data.insert(DataArray::new(
            "original_cell_id",
            1,
            ArrayData::Int64(parents.iter().map(|&p| p as i64).collect()),
        ));
    }
    let out = Grid {
        points,
        cells: cells_out,
        point_data,
        cell_data,
        field_data: grid.field_data.clone(),
    };
    Ok((out, report))
}

/// Appends coordinates (already representable in the array's type) to a points array.
fn append_values(data: &mut ArrayData, values: &[f64]) {
    fn ext<T: Element>(v: &mut Vec<T>, values: &[f64]) {
        v.extend(values.iter().map(|&x| T::from_f64(x)));
    }
    match data {
        ArrayData::Int8(v) => ext(v, values),
        ArrayData::UInt8(v) => ext(v, values),
        ArrayData::Int16(v) => ext(v, values),
        ArrayData::UInt16(v) => ext(v, values),
        ArrayData::Int32(v) => ext(v, values),
        ArrayData::UInt32(v) => ext(v, values),
        ArrayData::Int64(v) => ext(v, values),
        ArrayData::UInt64(v) => ext(v, values),
        ArrayData::Float32(v) => ext(v, values),
        ArrayData::Float64(v) => ext(v, values),
        ArrayData::String(_) => {}
    }
}

/// Point data of new centre points: float arrays take the mean of the vertices' tuples; integer
/// and string arrays the tuple of the smallest-id vertex.
fn append_centre_data(pd: &mut Attributes, centres: &[([f64; 3], Vec<i64>)]) {
    fn mean<T: Element>(v: &mut Vec<T>, c: usize, centres: &[([f64; 3], Vec<i64>)]) {
        for (_, verts) in centres {
            for k in 0..c {
                let s: f64 = verts.iter().map(|&p| v[p as usize * c + k].to_f64()).sum();
                v.push(T::from_f64(s / verts.len() as f64));
            }
        }
    }
    fn first<T: Clone>(v: &mut Vec<T>, c: usize, centres: &[([f64; 3], Vec<i64>)]) {
        for (_, verts) in centres {
            let p = verts.iter().copied().min().unwrap_or(0) as usize;
            for k in 0..c {
                let x = v[p * c + k].clone();
                v.push(x);
            }
        }
    }
    for a in &mut pd.arrays {
        let c = a.components;
        match &mut a.data {
            ArrayData::Float32(v) => mean(v, c, centres),
            ArrayData::Float64(v) => mean(v, c, centres),
            ArrayData::Int8(v) => first(v, c, centres),
            ArrayData::UInt8(v) => first(v, c, centres),
            ArrayData::Int16(v) => first(v, c, centres),
            ArrayData::UInt16(v) => first(v, c, centres),
            ArrayData::Int32(v) => first(v, c, centres),
            ArrayData::UInt32(v) => first(v, c, centres),
            ArrayData::Int64(v) => first(v, c, centres),
            ArrayData::UInt64(v) => first(v, c, centres),
            ArrayData::String(v) => first(v, c, centres),
        }
    }
}

#[cfg(test)]
mod tests;
