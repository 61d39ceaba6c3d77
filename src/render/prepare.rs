//! What a render reuses between frames: the field, the transfer function and its tables, and
//! the longest tet edge that bounds every ray segment.

// Negated comparisons are deliberate: they also catch NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::field::Field;
use super::integrate::{FastTf, Integration, PreintTable};
use super::pt::Shader;
use super::transfer::TransferFunction;
use crate::mesh::TetMesh;
use rayon::prelude::*;

/// Pre-integration table size: `scalar x scalar x length` samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TableSize {
    pub scalar: usize,
    pub length: usize,
}

impl Default for TableSize {
    fn default() -> Self {
        TableSize {
            scalar: 128,
            length: 32,
        }
    }
}

impl std::str::FromStr for TableSize {
    type Err = String;
    /// `SxL`, e.g. `128x64`.
    fn from_str(s: &str) -> Result<TableSize, String> {
        let (a, b) = s
            .split_once(['x', 'X'])
            .ok_or_else(|| format!("'{s}': expected SCALARxLENGTH, e.g. 128x64"))?;
        let p = |t: &str| {
            t.trim()
                .parse::<usize>()
                .ok()
                .filter(|v| (2..=4096).contains(v))
                .ok_or_else(|| format!("'{s}': '{t}' is not a size between 2 and 4096"))
        };
        let (scalar, length) = (p(a)?, p(b)?);
        // The table holds scalar x scalar x length RGBA entries: 4096x4096 passed the checks
        // above and then aborted on a 1 TiB allocation. 2^25 entries is 512 MiB.
        const MAX_ENTRIES: usize = 1 << 25;
        let entries = scalar * scalar * length;
        if entries > MAX_ENTRIES {
            return Err(format!(
                "'{s}': {scalar} x {scalar} x {length} = {entries} table entries, at most {MAX_ENTRIES} (e.g. 1024x32 or 512x128)"
            ));
        }
        Ok(TableSize { scalar, length })
    }
}

/// Longest tet edge: no chord through a tet is longer, so it bounds the table's length axis.
pub fn longest_edge(mesh: &TetMesh) -> f64 {
    mesh.tets
        .par_iter()
        .map(|t| {
            let p = t.map(|v| mesh.points[v as usize]);
            let mut m = 0.0f64;
            for i in 0..4 {
                for j in i + 1..4 {
                    let d = [0, 1, 2].map(|k| p[i][k] - p[j][k]);
                    m = m.max(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                }
            }
            m.sqrt()
        })
        .reduce(|| 0.0, f64::max)
}

/// Builds the shader for an integration mode (the 3-D table for `preintegrated`).
pub fn shader(tf: &TransferFunction, mode: Integration, size: TableSize, lmax: f64) -> Shader {
    match mode {
        Integration::Average => Shader::Average(FastTf::new(tf)),
        Integration::Linear => Shader::Linear(FastTf::new(tf)),
        Integration::Preintegrated => {
            // A hair longer than the longest edge so rounding never clamps a real chord.
            Shader::Pre(PreintTable::build(
                tf,
                size.scalar,
                size.length,
                lmax * 1.0001,
            ))
        }
    }
}

/// The default opacity unit distance: a fifth of the bounding-box diagonal, so the default ramp
/// lets a viewer see into the mesh rather than only its skin.
pub fn default_unit_distance(mesh: &TetMesh) -> f64 {
    let e = mesh.bounds().extent();
    let d = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt() / 5.0;
    if d > 0.0 && d.is_finite() {
        d
    } else {
        1.0
    }
}

/// Field range, widened to a unit interval around a constant field.
pub fn auto_range(field: &Field) -> [f64; 2] {
    match field.range() {
        Some([a, b]) if b > a => [a, b],
        Some([a, _]) => [a - 0.5, a + 0.5],
        None => [0.0, 1.0],
    }
}
