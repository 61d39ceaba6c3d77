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

impl Field {
    /// The array named `name` (point data first, then cell data), or without a name the active
    /// point scalars, else the first numeric point array, else the first numeric cell array.
    pub fn select(mesh: &TetMesh, name: Option<&str>) -> Result<(String, Field)> {
        let numeric = |a: &&DataArray| a.data.scalar_type().is_some();
        if let Some(n) = name {
            if let Some(a) = mesh.point_data.get(n) {
                return Ok((n.to_string(), Field::Point(values(a)?)));
            }
            if let Some(a) = mesh.cell_data.get(n) {
                return Ok((n.to_string(), Field::Cell(values(a)?)));
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
        if let Some(a) = mesh.point_data.arrays.iter().find(numeric) {
            return Ok((a.name.clone(), Field::Point(values(a)?)));
        }
        if let Some(a) = mesh.cell_data.arrays.iter().find(numeric) {
            return Ok((a.name.clone(), Field::Cell(values(a)?)));
        }
        bail!("the mesh has no numeric point or cell array to render")
    }

    /// Values at the four vertices of tet `t`.
    #[inline]
    pub fn at(&self, t: usize, tet: &[u32; 4]) -> [f64; 4] {
        match self {
            Field::Point(v) => tet.map(|i| v[i as usize]),
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

    /// Checks lengths against the mesh and that every value is finite.
    pub fn check(&self, mesh: &TetMesh, name: &str) -> Result<()> {
        let (v, n, what) = match self {
            Field::Point(v) => (v, mesh.points.len(), "points"),
            Field::Cell(v) => (v, mesh.tets.len(), "cells"),
        };
        if v.len() != n {
            bail!("array '{name}' has {} tuples for {n} {what}", v.len());
        }
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            bail!("array '{name}' tuple {i}: value {} is not finite", v[i]);
        }
        Ok(())
    }
}
