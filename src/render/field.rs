//! The scalar field a render shows: a point array (linear in each tet) or a cell array (constant
//! in each tet), with multi-component arrays reduced to their magnitude as ParaView does.

// Negated comparisons are deliberate: they also catch NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::mesh::TetMesh;
use anyhow::{bail, Result};
use formats::{Attribute, DataArray};

#[derive(Clone, Debug, PartialEq)]
pub enum Field {
    Point(Vec<f64>),
    Cell(Vec<f64>),
}

/// One component of `a`, named as ParaView names it: `Magnitude`, `X`/`Y`/`Z` (vectors of up
/// to 3 components), the component's name in the file, or its index (`v:0`, as ParaView's
/// CSV export heads the columns). `None` when `comp` names none of them.
fn component(a: &DataArray, comp: &str) -> Result<Option<Vec<f64>>> {
    if a.data.scalar_type().is_none() {
        bail!("array '{}' holds strings, not numbers", a.name);
    }
    let c = a.components.max(1);
    if comp.eq_ignore_ascii_case("magnitude") {
        return values(a).map(Some);
    }
    let k = if let Some(k) = a.component_names.iter().position(|n| n == comp) {
        k
    } else if let Ok(k) = comp.parse::<usize>() {
        if k >= c {
            bail!(
                "--scalar {}:{comp}: '{}' has {c} component(s), numbered from 0",
                a.name,
                a.name
            );
        }
        k
    } else {
        match (comp, c) {
            ("X" | "x", _) => 0,
            ("Y" | "y", 2..=3) => 1,
            ("Z" | "z", 3) => 2,
            _ => return Ok(None),
        }
    };
    Ok(Some(a.data.to_f64_vec().chunks(c).map(|t| t[k]).collect()))
}

fn values(a: &DataArray) -> Result<Vec<f64>> {
    if a.data.scalar_type().is_none() {
        bail!("array '{}' holds strings, not numbers", a.name);
    }
    let c = a.components.max(1);
    let raw = a.data.to_f64_vec();
    Ok(if c == 1 {
        raw
    } else {
        raw.chunks(c)
            .map(|t| t.iter().map(|v| v * v).sum::<f64>().sqrt())
            .collect()
    })
}

/// Arrays the default `--scalar` passes over (they can still be named): ids and flags that
/// tetkit, VTK's filters and the readers add, which colour a mesh as noise. Region labels
/// (Gmsh physical groups, Exodus block ids, Medit refs, TetGen regions) are kept: they are
/// what the mesh's author chose to mark.
const BOOKKEEPING: [&str; 16] = [
    "original_cell_id",
    "leaf_id",
    "vtkGhostType",
    "vtkOriginalCellIds",
    "vtkOriginalPointIds",
    "BlockIdScalars",
    formats::msh::names::NODE_TAG,
    formats::msh::names::ELEMENT_TAG,
    formats::msh::names::GEOMETRICAL,
    formats::exodus::names::NODE_ID,
    formats::exodus::names::ELEMENT_ID,
    formats::tetgen::names::BOUNDARY_MARKER,
    formats::tetgen::names::NEIGHBORS,
    formats::medit::names::CORNER,
    formats::medit::names::RIDGE,
    formats::medit::names::REQUIRED,
];

impl Field {
    /// The array named `name` (point data first, then cell data; `point:NAME` or `cell:NAME`
    /// for one of two arrays of that name; `NAME:X`, `NAME:0`, `NAME:Magnitude` for one
    /// component; `coord:x|y|z|r` for a field of the point coordinates), or without a name the active point scalars, else the first numeric
    /// point array, else the first numeric cell array (ids in [`BOOKKEEPING`] passed over), else
    /// a constant (solid colour).
    pub fn select(mesh: &TetMesh, name: Option<&str>) -> Result<(String, Field)> {
        let numeric = |a: &&DataArray| a.data.scalar_type().is_some();
        if let Some(axis) = name.and_then(|n| n.strip_prefix("coord:")) {
            // A field made from the points: x, y, z, or r (distance from the bounds' centre).
            let c = mesh.bounds().center();
            let f = |p: &[f64; 3]| match axis {
                "x" => Some(p[0]),
                "y" => Some(p[1]),
                "z" => Some(p[2]),
                "r" => Some(
                    ((p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2) + (p[2] - c[2]).powi(2)).sqrt(),
                ),
                _ => None,
            };
            let v: Option<Vec<f64>> = mesh.points.iter().map(f).collect();
            return match v {
                Some(v) => Ok((format!("coord:{axis}"), Field::Point(v))),
                None => {
                    bail!("--scalar coord:{axis}: expected coord:x, coord:y, coord:z or coord:r")
                }
            };
        }
        if let Some(n) = name {
            if let Some(a) = mesh.point_data.get(n) {
                return Ok((n.to_string(), Field::Point(values(a)?)));
            }
            if let Some(a) = mesh.cell_data.get(n) {
                return Ok((n.to_string(), Field::Cell(values(a)?)));
            }
            // A point and a cell array of one name (ParaView files often have both): the plain
            // name finds the point one, `cell:NAME` the other (`probe` labels them so too).
            if let Some(a) = n
                .strip_prefix("point:")
                .and_then(|m| mesh.point_data.get(m))
            {
                return Ok((n.to_string(), Field::Point(values(a)?)));
            }
            if let Some(a) = n.strip_prefix("cell:").and_then(|m| mesh.cell_data.get(m)) {
                return Ok((n.to_string(), Field::Cell(values(a)?)));
            }
            // One component: `v:X`, `v:0`, `v:Magnitude`, `cell:v:Y` (ParaView's "Color By"
            // component menu); the whole name was looked up first, so `gmsh:physical` stays.
            if let Some((base, comp)) = n.rsplit_once(':') {
                let (p, c) = match base.split_once(':') {
                    Some(("point", m)) => (mesh.point_data.get(m), None),
                    Some(("cell", m)) => (None, mesh.cell_data.get(m)),
                    _ => (mesh.point_data.get(base), mesh.cell_data.get(base)),
                };
                if let Some(a) = p {
                    if let Some(v) = component(a, comp)? {
                        return Ok((n.to_string(), Field::Point(v)));
                    }
                } else if let Some(a) = c {
                    if let Some(v) = component(a, comp)? {
                        return Ok((n.to_string(), Field::Cell(v)));
                    }
                }
                if let Some(a) = p.or(c) {
                    bail!(
                        "--scalar {n}: '{comp}' is not a component of '{}' ({} components): give Magnitude, X, Y or Z (up to 3 components), a component name, or an index from 0",
                        a.name,
                        a.components.max(1)
                    );
                }
            }
            let names: Vec<String> = mesh
                .point_data
                .arrays
                .iter()
                .map(|a| format!("{} (point)", a.name))
                .chain(
                    mesh.cell_data
                        .arrays
                        .iter()
                        .map(|a| format!("{} (cell)", a.name)),
                )
                .collect();
            bail!(
                "--scalar {n}: no such array; the mesh has: {}",
                if names.is_empty() {
                    "no arrays".to_string()
                } else {
                    names.join(", ")
                }
            );
        }
        if let Some(a) = mesh.point_data.active(Attribute::Scalars).filter(numeric) {
            return Ok((a.name.clone(), Field::Point(values(a)?)));
        }
        // Ids that tetrahedralizing, partitioning or VTK's filters add are bookkeeping, not a
        // field to look at: a mesh with nothing else is drawn in a solid colour, as ParaView does.
        let shown = |a: &&DataArray| numeric(a) && !BOOKKEEPING.contains(&a.name.as_str());
        if let Some(a) = mesh.point_data.arrays.iter().find(shown) {
            return Ok((a.name.clone(), Field::Point(values(a)?)));
        }
        if let Some(a) = mesh.cell_data.arrays.iter().find(shown) {
            return Ok((a.name.clone(), Field::Cell(values(a)?)));
        }
        // Nothing to map: ParaView's "Solid Color", a constant field.
        Ok((
            "(solid colour)".to_string(),
            Field::Point(vec![0.0; mesh.points.len()]),
        ))
    }

    /// Values at the four vertices of tet `t`.
    #[inline]
    pub fn at(&self, t: usize, tet: &[u32; 4]) -> [f64; 4] {
        match self {
            // Explicit, not `tet.map`: a map whose closure may panic compiles to slower code.
            Field::Point(v) => [
                v[tet[0] as usize],
                v[tet[1] as usize],
                v[tet[2] as usize],
                v[tet[3] as usize],
            ],
            Field::Cell(v) => [v[t]; 4],
        }
    }

    /// Finite min and max.
    pub fn range(&self) -> Option<[f64; 2]> {
        let v = match self {
            Field::Point(v) | Field::Cell(v) => v,
        };
        let mut r: Option<[f64; 2]> = None;
        for &x in v.iter().filter(|x| x.is_finite()) {
            r = Some(match r {
                None => [x, x],
                Some([a, b]) => [a.min(x), b.max(x)],
            });
        }
        r
    }

    /// Maps every value to `(v - offset) * scale` (see [`scalar_offset`] and [`scalar_scale`]:
    /// a power of two, so the scaling is exact).
    pub fn rescale(&mut self, offset: f64, scale: f64) {
        match self {
            Field::Point(v) | Field::Cell(v) => {
                v.iter_mut().for_each(|x| *x = (*x - offset) * scale)
            }
        }
    }

    /// Leaves out the tets that read a NaN or infinite value (any vertex's, or the cell's own):
    /// the mesh and a cell field keep the rest in order, with their cell data; point values no
    /// kept tet reads become 0. Returns how many tets were left out. A solver's result with NaN
    /// where it is undefined is drawn where it is defined, rather than refused.
    pub fn drop_non_finite(&mut self, mesh: &mut TetMesh) -> usize {
        let n = mesh.tets.len();
        let keep: Vec<usize> = match &*self {
            Field::Point(v) if v.len() == mesh.points.len() => (0..n)
                .filter(|&t| mesh.tets[t].iter().all(|&p| v[p as usize].is_finite()))
                .collect(),
            Field::Cell(v) if v.len() == n => (0..n).filter(|&t| v[t].is_finite()).collect(),
            // Lengths that disagree: `check`, called first, has refused them.
            _ => return 0,
        };
        if keep.len() == n {
            return 0;
        }
        mesh.tets = keep.iter().map(|&t| mesh.tets[t]).collect();
        mesh.cell_data = mesh.cell_data.gather(&keep);
        match self {
            Field::Point(v) => v
                .iter_mut()
                .filter(|x| !x.is_finite())
                .for_each(|x| *x = 0.0),
            Field::Cell(v) => *v = keep.iter().map(|&t| v[t]).collect(),
        }
        n - keep.len()
    }

    /// Checks lengths against the mesh (non-finite values are [`Field::drop_non_finite`]'s).
    pub fn check(&self, mesh: &TetMesh, name: &str) -> Result<()> {
        let (v, n, what) = match self {
            Field::Point(v) => (v, mesh.points.len(), "points"),
            Field::Cell(v) => (v, mesh.tets.len(), "cells"),
        };
        if v.len() != n {
            bail!("array '{name}' has {} tuples for {n} {what}", v.len());
        }
        Ok(())
    }
}

/// What a render subtracts from the field, its transfer functions' ranges and opacity points
/// before drawing: the range start when the values are far from zero compared with the range
/// (temperatures in kelvin with small variations, `coord:x` of a mesh at UTM coordinates), else
/// 0 (nothing changes). Projected tetrahedra keep scalars in f32: `1e7 + [0, 3]` would keep
/// only whole numbers, `1e8 + [0, 3]` a single value. Shifted, both the f32 rasterizer and the
/// f64 ray caster see values within the range's own width of zero; the colours are the same up
/// to rounding because every transfer function moves with the field.
pub fn scalar_offset(range: [f64; 2]) -> f64 {
    let span = range[1] - range[0];
    if range[0].abs().max(range[1].abs()) > 16.0 * span.abs() {
        range[0]
    } else {
        0.0
    }
}

/// What a render multiplies the (shifted) field by: 1 for ordinary ranges, else the power of
/// two bringing the range's larger end into [1, 2). Projected tetrahedra keep scalars in f32,
/// which ends at 3.4e38 and loses precision below 1.2e-38: a `--range -1e100,1e100` drew a
/// blank image (the table's start was -inf) while the f64 ray caster drew it right. A power of
/// two scales exactly, and the transfer functions scale with the field, so colours keep.
pub fn scalar_scale(range: [f64; 2]) -> f64 {
    let m = range[0].abs().max(range[1].abs());
    let (lo, hi) = (2f64.powi(-100), 2f64.powi(100));
    if !m.is_finite() || m == 0.0 || (lo..=hi).contains(&m) {
        return 1.0;
    }
    // m lies in [2^e, 2^(e+1)); the exponent field of an f64 gives e without rounding.
    let e = ((m.to_bits() >> 52) & 0x7ff) as i32 - 1023;
    2f64.powi(-e.clamp(-1000, 1023))
}

#[cfg(test)]
mod tests {
    use super::*;
    use formats::ArrayData;

    #[test]
    fn extreme_ranges_scale_by_a_power_of_two() {
        assert_eq!(scalar_scale([0.0, 1.0]), 1.0);
        assert_eq!(scalar_scale([-1e20, 1e20]), 1.0);
        for r in [
            [-1e100, 1e100],
            [0.0, 1e39],
            [-1.7e308, 1.7e308],
            [1e-45, 3e-45],
        ] {
            let s = scalar_scale(r);
            let m = r[0].abs().max(r[1].abs()) * s;
            assert!((1.0..2.0).contains(&m), "{r:?}: {s} gives {m}");
            assert_eq!(s.log2().fract(), 0.0, "a power of two");
        }
    }

    fn one_tet() -> TetMesh {
        TetMesh {
            points: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            tets: vec![[0, 1, 2, 3]],
            ..TetMesh::default()
        }
    }

    #[test]
    fn one_component_by_paraview_name_or_index() -> Result<()> {
        let mut m = one_tet();
        let v: Vec<f64> = (0..4).flat_map(|i| [i as f64, 3.0, 4.0]).collect();
        m.point_data
            .insert(DataArray::new("v", 3, ArrayData::Float64(v)));
        let mut t = DataArray::new("t", 2, ArrayData::Float64(vec![5.0, 6.0]));
        t.component_names = vec!["lo".into(), "hi".into()];
        m.cell_data.insert(t);
        m.cell_data.insert(DataArray::new(
            "gmsh:physical",
            1,
            ArrayData::Int32(vec![2]),
        ));
        let tet = m.tets[0];
        for (n, want) in [
            ("v:X", [0.0, 1.0, 2.0, 3.0]),
            ("v:0", [0.0, 1.0, 2.0, 3.0]),
            ("v:Z", [4.0; 4]),
            ("point:v:1", [3.0; 4]),
            (
                "v:Magnitude",
                [5.0, 26f64.sqrt(), 29f64.sqrt(), 34f64.sqrt()],
            ),
            ("t:hi", [6.0; 4]),
            ("cell:t:Y", [6.0; 4]),
            ("gmsh:physical", [2.0; 4]),
        ] {
            let (name, f) = Field::select(&m, Some(n))?;
            assert_eq!((name.as_str(), f.at(0, &tet)), (n, want));
        }
        for (n, needle) in [
            ("v:3", "3 component(s)"),
            ("v:W", "'W' is not a component of 'v'"),
            ("t:Z", "'Z' is not a component of 't'"),
            ("w:X", "no such array"),
        ] {
            match Field::select(&m, Some(n)) {
                Ok(_) => bail!("{n} accepted"),
                Err(e) => assert!(e.to_string().contains(needle), "{n}: {e}"),
            }
        }
        Ok(())
    }

    #[test]
    fn the_default_passes_over_bookkeeping_ids() {
        let mut m = one_tet();
        for name in BOOKKEEPING {
            m.cell_data
                .insert(DataArray::new(name, 1, ArrayData::Int64(vec![7])));
        }
        // The readers' point ids too (a Gmsh mesh's node tags, Exodus's node map).
        for name in [
            formats::msh::names::NODE_TAG,
            formats::exodus::names::NODE_ID,
        ] {
            m.point_data
                .insert(DataArray::new(name, 1, ArrayData::Int64(vec![1, 2, 3, 4])));
        }
        let (name, f) = Field::select(&m, None).unwrap();
        assert_eq!(name, "(solid colour)");
        assert_eq!(f.at(0, &m.tets[0]), [0.0; 4]);
        // A region label is what its author marked: drawn.
        let mut labelled = m.clone();
        labelled.cell_data.insert(DataArray::new(
            formats::msh::names::PHYSICAL,
            1,
            ArrayData::Int32(vec![2]),
        ));
        assert!(
            matches!(Field::select(&labelled, None), Ok((n, _)) if n == formats::msh::names::PHYSICAL)
        );
        // A real array after them is the one drawn, and a named id still is.
        m.cell_data
            .insert(DataArray::new("pressure", 1, ArrayData::Float32(vec![2.5])));
        assert_eq!(Field::select(&m, None).unwrap().0, "pressure");
        let (name, f) = Field::select(&m, Some("leaf_id")).unwrap();
        assert_eq!(name, "leaf_id");
        assert_eq!(f.at(0, &m.tets[0]), [7.0; 4]);
    }
}
