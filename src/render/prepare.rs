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

/// Longest edge of tet `t`: no chord through it is longer.
fn tet_longest_edge(mesh: &TetMesh, t: &[u32; 4]) -> f64 {
    let p = t.map(|v| mesh.points[v as usize]);
    let mut m = 0.0f64;
    for i in 0..4 {
        for j in i + 1..4 {
            let d = [0, 1, 2].map(|k| p[i][k] - p[j][k]);
            m = m.max(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        }
    }
    m.sqrt()
}

/// Longest tet edge: no chord through a tet is longer, so it bounds the table's length axis.
pub fn longest_edge(mesh: &TetMesh) -> f64 {
    mesh.tets
        .par_iter()
        .map(|t| tet_longest_edge(mesh, t))
        .reduce(|| 0.0, f64::max)
}

/// Optical depth of one step of the table's length axis above which long fragments are split
/// rather than the steps made that long: interpolating across a step of optical depth `D` errs
/// by up to about `D^2 / 8`.
const STEP_DEPTH: f64 = 0.1;

/// The pre-integration table's length axis for `steps` entries along it and transfer function
/// `tf`: the longest tet edge, unless a step that long would be optically thick (over
/// [`STEP_DEPTH`] at the function's densest) and most fragments are much shorter. Then the axis
/// is shortened to the length where a step has that depth, but not below the 90th percentile
/// of the tets' typical chords (more would split most fragments), and longer fragments are split
/// into pieces ([`crate::render::integrate::PreintTable::segment`]). A tet's typical chord is
/// twice its mean chord `4 V / S` (Cauchy's formula over all lines through it): about half the
/// edge of a regular tet, and the thickness of a flat one, whose fragments are that short
/// wherever it is not seen edge-on. A mesh of slivers or a graded one has a few edges many
/// times the typical one, and a flattened one (a plate, a shell) has edges many times its
/// thickness; an axis spanning its longest edges left most fragments inside its first step,
/// interpolated between nothing and an opaque step (on a TetGen Delaunay cloud of 134k tets,
/// longest edge 1.02: RMSE against the exact ray caster 3.5e-3 before, 4e-5 split; the TetGen
/// torus flattened to 1e-4 of its height with a unit distance of a tenth of that: a nearly
/// black image, RMSE 0.31, before). A near-uniform mesh with thin steps is never split.
pub fn table_length(mesh: &TetMesh, tf: &TransferFunction, steps: usize) -> f64 {
    axis_length(&edge_spread(mesh), densest(tf), steps)
}

/// Twice the mean chord `4 V / S` of tet `t` (0 for a flat one).
fn tet_typical_chord(mesh: &TetMesh, t: &[u32; 4]) -> f64 {
    use crate::geom::{cross, dot, sub};
    let p = t.map(|v| mesh.points[v as usize]);
    let norm = |a: [f64; 3]| dot(&a, &a).sqrt();
    let (e1, e2, e3) = (sub(&p[1], &p[0]), sub(&p[2], &p[0]), sub(&p[3], &p[0]));
    let n = cross(&e1, &e2);
    let six_v = dot(&n, &e3).abs();
    // Twice the surface area: the four faces' cross products.
    let two_s = norm(n)
        + norm(cross(&e2, &e3))
        + norm(cross(&e3, &e1))
        + norm(cross(&sub(&p[2], &p[1]), &sub(&p[3], &p[1])));
    // 2 * 4 V / S = 8 (6V / 6) / (2S / 2) = (8 / 3) 6V / 2S.
    let c = 8.0 / 3.0 * six_v / two_s;
    if c.is_finite() {
        c
    } else {
        0.0
    }
}

/// The longest tet edge and the 90th percentile of the tets' typical chords
/// ([`tet_typical_chord`]), over the tets with finite edges, or `None` without any.
fn edge_spread(mesh: &TetMesh) -> Option<(f64, f64)> {
    let mut pairs: Vec<(f64, f64)> = mesh
        .tets
        .par_iter()
        .map(|t| (tet_longest_edge(mesh, t), tet_typical_chord(mesh, t)))
        .filter(|m| m.0.is_finite())
        .collect();
    let max = pairs.iter().map(|p| p.0).max_by(|a, b| a.total_cmp(b))?;
    let k = (pairs.len() - 1) * 90 / 100;
    let (_, &mut (_, p90), _) = pairs.select_nth_unstable_by(k, |a, b| a.1.total_cmp(&b.1));
    Some((max, p90))
}

/// The transfer function's largest extinction.
fn densest(tf: &TransferFunction) -> f64 {
    tf.tau.iter().copied().fold(0.0, f64::max)
}

/// [`table_length`] from the mesh's [`edge_spread`] and the densest extinction `tau`.
fn axis_length(spread: &Option<(f64, f64)>, tau: f64, steps: usize) -> f64 {
    let Some((max, p90)) = *spread else {
        return 0.0;
    };
    let thin = STEP_DEPTH * steps.saturating_sub(1).max(1) as f64 / tau;
    let cap = if thin.is_nan() {
        max
    } else {
        thin.min(max).max(p90)
    };
    if cap > 0.5 * max || !(cap > 0.0) {
        max
    } else {
        cap
    }
}

/// Most length steps the default table grows to (128 x 128 x 256 entries: 64 MiB).
const MAX_DEFAULT_STEPS: usize = 256;

/// Most entries the default table grows to along its scalar axis (64 MiB of RGBA f32).
const MAX_DEFAULT_ENTRIES: usize = 1 << 22;

/// Optical depth that one step of the default table's scalar axis may add to a typical
/// fragment where the transfer function is steepest; past it the axis is refined.
const SCALAR_STEP_DEPTH: f64 = 0.5;

/// The default table's scalar samples for `length` length steps: a whole number `m` of steps
/// per interval between the transfer function's nodes (about 127 steps in all at least), so every
/// node is a sample and the function is linear between neighbouring samples. A grid that did
/// not meet the nodes interpolated across their kinks: under an opacity step (`0:1,0.4:1,0.41:0,1:0`,
/// unit distance 0.005 on a 292k-tet mesh), fragments whose scalars lay where the function is
/// zero were drawn nearly opaque (max 0.96 off the exact ray caster, 77 pixels drawn that are
/// black). `m` grows until one step changes the extinction over a typical chord `chord` by at
/// most [`SCALAR_STEP_DEPTH`], within [`MAX_DEFAULT_ENTRIES`].
pub fn scalar_samples(tf: &TransferFunction, chord: f64, length: usize) -> usize {
    let intervals = tf.tau.len().saturating_sub(1).max(1);
    let cap = ((MAX_DEFAULT_ENTRIES / length.max(1)) as f64).sqrt() as usize;
    if intervals + 1 > cap {
        // More nodes than the budget has samples (`--tf-nodes 4096`): one sample per node
        // would take gigabytes, so the plain 128 (the render notes that it misses the nodes).
        return 128.min(cap).max(2);
    }
    // About 128 samples, as the table always had.
    let at_least = ((127 + intervals / 2) / intervals).max(1);
    let most = (cap - 1) / intervals;
    let need = (steepest_depth(tf, chord) / SCALAR_STEP_DEPTH).ceil();
    let m = if need.is_finite() && need > at_least as f64 {
        (need as usize).min(most)
    } else {
        at_least.min(most)
    };
    m * intervals + 1
}

/// The largest change of extinction between neighbouring nodes of `tf`, as optical depth over
/// a length `chord`.
fn steepest_depth(tf: &TransferFunction, chord: f64) -> f64 {
    let steepest = tf
        .tau
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .fold(0.0, f64::max);
    steepest * chord
}

/// The pre-integration table's size and length axis: `asked` (`--table`) as given, or the
/// default's scalar axis with enough length steps that one step over the longest tet edge is
/// at most [`STEP_DEPTH`] optical depths at the function's densest (at least the default's
/// 32, at most [`MAX_DEFAULT_STEPS`]). Interpolation along the length errs by about the
/// square of a step's depth: on a coarse block of 24 tets seen at 64x64 with the default ramp
/// (a step of 32 about 1.1 optical depths), 32 steps were 11/255 off the exact ray caster at
/// worst and 8 % of pixels more than 1/255, 256 steps 1/255 and none. A fine mesh's steps are
/// thin already and keep the default (more steps cost lookups their cache).
pub fn table_size(
    mesh: &TetMesh,
    tf: &TransferFunction,
    asked: Option<TableSize>,
) -> (TableSize, f64) {
    let (size, lmax, _) = table_plan(mesh, tf, asked);
    (size, lmax)
}

/// [`table_size`] and the [`table_note`] of that size, from one pass over the tets.
pub fn table_plan(
    mesh: &TetMesh,
    tf: &TransferFunction,
    asked: Option<TableSize>,
) -> (TableSize, f64, Option<String>) {
    // One pass over the tets' edges serves both the step count and the axis.
    let spread = edge_spread(mesh);
    let chord = spread.map_or(0.0, |s| s.1);
    let tau = densest(tf);
    let size = asked.unwrap_or_else(|| {
        let d = TableSize::default();
        let longest = spread.map_or(0.0, |s| s.0);
        let need = (tau * longest / STEP_DEPTH).ceil() + 1.0;
        let length = if need.is_finite() && need > d.length as f64 {
            (need as usize).min(MAX_DEFAULT_STEPS)
        } else {
            d.length
        };
        TableSize {
            length,
            scalar: scalar_samples(tf, chord, length),
        }
    });
    let note = note_for(tf, chord, size.scalar);
    (size, axis_length(&spread, tau, size.length), note)
}

/// A note when the table's scalar axis (`ns` samples) is coarse for the transfer function
/// where it is steepest: one step there adds more than two optical depths to a typical
/// fragment of `mesh` that is not already opaque ([`steepest_visible_depth`]) (saying so too when the samples miss the function's nodes, which then
/// smooths the steep part across them). A gentle function needs no note on any axis.
pub fn table_note(mesh: &TetMesh, tf: &TransferFunction, ns: usize) -> Option<String> {
    note_for(tf, edge_spread(mesh).map_or(0.0, |s| s.1), ns)
}

/// The largest change of extinction between neighbouring nodes of `tf`, as optical depth over
/// a length `chord`, each weighted by the light a fragment that long still lets through at the
/// interval's thinner end: where that end already makes the fragment opaque, smoothing the
/// rest of the interval changes little that can be seen. The ramp the default opacity ends in
/// (its last node clamped just below 1, so its extinction jumps there) made the note fire on
/// every default render of a coarse mesh.
fn steepest_visible_depth(tf: &TransferFunction, chord: f64) -> f64 {
    tf.tau
        .windows(2)
        .map(|w| (w[1] - w[0]).abs() * chord * (-w[0].min(w[1]) * chord).exp())
        .fold(0.0, f64::max)
}

/// [`table_note`] for a mesh whose typical chord is `chord`.
fn note_for(tf: &TransferFunction, chord: f64, ns: usize) -> Option<String> {
    let intervals = tf.tau.len().saturating_sub(1).max(1);
    let steps = ns.saturating_sub(1).max(1);
    let aligned = steps.is_multiple_of(intervals);
    let per_step = steepest_visible_depth(tf, chord) * intervals as f64 / steps as f64;
    if !(per_step > 2.0) {
        return None;
    }
    Some(format!(
        "the pre-integration table's scalar axis ({ns} samples{}) is coarse for this transfer function: where it is steepest one step adds about {per_step:.1} optical depths to a typical fragment that is not already opaque, so fragments there are smoothed; --method raycast integrates it exactly, and --table with more samples (a multiple of {intervals} steps plus one meets its nodes) or a larger --unit-distance narrows the error",
        if aligned { "" } else { ", not on the function's nodes" }
    ))
}

/// Builds the shader for an integration mode (the 3-D table for `preintegrated`).
pub fn shader(tf: &TransferFunction, mode: Integration, size: TableSize, lmax: f64) -> Shader {
    match mode {
        Integration::Average => Shader::Average(FastTf::new(tf)),
        Integration::Linear => Shader::Linear(FastTf::new(tf)),
        Integration::Preintegrated => {
            // A hair longer than `lmax` so rounding never splits a chord of that length.
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::structured_grid;
    use crate::render::transfer::{named_colormap, OpacitySpec};

    fn tf(max_opacity: f64, unit: f64) -> anyhow::Result<TransferFunction> {
        let spec = OpacitySpec::parse(&format!("0:0,1:{max_opacity}"))?;
        TransferFunction::build(
            &named_colormap("viridis")?,
            Some(&spec),
            [0.0, 1.0],
            unit,
            16,
        )
    }

    #[test]
    fn table_length_shortens_the_axis_only_for_long_outliers_and_thick_steps() -> anyhow::Result<()>
    {
        // Near-uniform: the longest edge while its steps are thin; when opaque, down to the
        // typical chord (twice the mean chord, about half the longest edge here).
        let grid = structured_grid([6, 6, 6], [0.0; 3], [1.0; 3]);
        let longest = longest_edge(&grid);
        assert_eq!(table_length(&grid, &tf(0.3, 10.0)?, 32), longest);
        let opaque = table_length(&grid, &tf(1.0, 0.01)?, 32);
        assert!(
            opaque > 0.2 * longest && opaque < 0.5 * longest,
            "{opaque} of {longest}"
        );
        // Flattened to 1e-4 of its height (a plate): its fragments are as short as it is
        let mut plate = structured_grid([6, 6, 6], [0.0; 3], [1.0; 3]);
        for p in plate.points.iter_mut() {
            p[2] *= 1e-4;
        }
        // thick (a layer here: 2e-5) wherever it is not seen edge-on, so an opaque axis comes
        // down to that, or to where a step is 0.1 optical depths if longer. It stayed at the
        // longest edge, 0.35, under the old floor of the edges' percentile.
        let t = tf(1.0, 1e-5)?;
        let tau = t.tau.iter().copied().fold(0.0, f64::max);
        let flat = table_length(&plate, &t, 256);
        assert!(flat >= 0.1 * 255.0 / tau && flat < 1e-4, "{flat}");
        // A graded mesh: 200 thin columns and one 100 times wider (0.4 % of the tets).
        let mut graded = structured_grid([201, 2, 2], [0.0; 3], [1.0, 0.01, 0.01]);
        for p in graded.points.iter_mut() {
            let i = (p[0] * 201.0).round();
            p[0] = if i <= 200.0 { i * 1e-3 } else { 0.3 };
        }
        let longest = longest_edge(&graded);
        assert!(longest > 0.09, "{longest}");
        // Optically thin steps: nothing to gain, the whole axis.
        assert_eq!(table_length(&graded, &tf(0.3, 10.0)?, 32), longest);
        // Opaque: down to where a step is 0.1 optical depths, above the 90th percentile of
        // typical chords (the columns are slabs 1e-3 thick: about 2e-3).
        let t = tf(1.0, 0.01)?;
        let tau = t.tau.iter().copied().fold(0.0, f64::max);
        let thick = table_length(&graded, &t, 32);
        assert!(
            (thick - 0.1 * 31.0 / tau).abs() < 1e-15 && thick > 1e-3,
            "{thick}"
        );
        // Between: where a step is 0.1 optical depths.
        let t = tf(0.5, 0.007)?;
        let tau = t.tau.iter().copied().fold(0.0, f64::max);
        let mid = table_length(&graded, &t, 32);
        assert!(
            (mid - 0.1 * 31.0 / tau).abs() < 1e-12 && mid < 0.5 * longest,
            "{mid}"
        );
        Ok(())
    }
}
