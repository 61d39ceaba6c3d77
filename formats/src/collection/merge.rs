//! Blocks of a collection merged into one grid as ParaView's Merge Blocks does: points and cells
//! in block order, the arrays every block has, and the block each cell came from.

use super::warn;
use crate::{ArrayData, Attributes, DataArray, FormatError, Grid, Place, Result, ScalarType};
use std::path::Path;

/// Name of the Int32 cell array holding each cell's block: VTK's vtkBlockIdScalars (ParaView's
/// "Block Id Scalars" filter) names its array so, though it stores UInt8 and so wraps past 255.
pub const BLOCK_ID_ARRAY: &str = "BlockIdScalars";

/// Name of the String field array listing the blocks, indexed by [`BLOCK_ID_ARRAY`].
pub const BLOCK_NAMES_ARRAY: &str = "BlockNames";

/// One leaf of a collection: its name (for `BlockNames`), how messages name it, and its mesh
/// (`None` for an empty or skipped block, which keeps its index but adds no cells).
pub(crate) struct Block {
    pub name: String,
    pub label: String,
    pub grid: Option<Grid>,
}

/// Which arrays of `parts` (one per non-empty block) survive: those every block has with the same
/// type and component count, in the first block's order. Each dropped one is warned about.
fn kept_names(file: &Path, parts: &[(&str, &Attributes)], what: &str) -> Vec<String> {
    let Some((_, first)) = parts.first() else {
        return Vec::new();
    };
    let mut kept = Vec::new();
    let mut seen: Vec<&str> = Vec::new();
    for (label, attrs) in parts {
        for a in &attrs.arrays {
            if seen.contains(&a.name.as_str()) {
                continue;
            }
            seen.push(&a.name);
            let lacking: Vec<&str> = parts
                .iter()
                .filter(|(_, o)| o.get(&a.name).is_none())
                .map(|(l, _)| *l)
                .collect();
            let differing: Vec<&str> = parts
                .iter()
                .filter(|(_, o)| {
                    o.get(&a.name).is_some_and(|b| {
                        b.components != a.components || b.data.type_name() != a.data.type_name()
                    })
                })
                .map(|(l, _)| *l)
                .collect();
            if !lacking.is_empty() {
                warn(&format!(
                    "{}: {what} array '{}' ({label} has it) is missing from {}; dropped, as VTK's merge drops it",
                    file.display(),
                    a.name,
                    lacking.join(", ")
                ));
            } else if !differing.is_empty() {
                warn(&format!(
                    "{}: {what} array '{}' is {} x{} in {label} but differs in {}; dropped, as VTK's merge drops it",
                    file.display(),
                    a.name,
                    a.data.type_name(),
                    a.components,
                    differing.join(", ")
                ));
            } else if first.get(&a.name).is_some() {
                kept.push(a.name.clone());
            }
        }
    }
    kept
}

/// `attrs` with only the arrays named in `kept`, in that order, and the active roles they keep.
fn only(mut attrs: Attributes, kept: &[String]) -> Attributes {
    let mut arrays = Vec::with_capacity(kept.len());
    for k in kept {
        if let Some(i) = attrs.arrays.iter().position(|a| &a.name == k) {
            arrays.push(attrs.arrays.swap_remove(i));
        }
    }
    attrs.arrays = arrays;
    attrs.active.retain(|(_, n)| kept.contains(n));
    attrs.lookup_tables.retain(|(n, _)| kept.contains(n));
    attrs
}

/// Merges `blocks` (the leaves of `file`, in order) into one grid with the cell array
/// [`BLOCK_ID_ARRAY`] and the field array [`BLOCK_NAMES_ARRAY`].
pub(crate) fn merge_blocks(file: &Path, blocks: Vec<Block>) -> Result<Grid> {
    let names: Vec<String> = blocks.iter().map(|b| b.name.clone()).collect();
    // Blocks without points add nothing, and VTK's append leaves them out of the array
    // intersection too, so an empty block does not cost the others their arrays.
    let mut full: Vec<(usize, String, Grid)> = blocks
        .into_iter()
        .enumerate()
        .filter_map(|(i, b)| b.grid.map(|g| (i, b.label, g)))
        .filter(|(_, _, g)| g.num_points() > 0)
        .collect();
    if let Some((_, l0, g0)) = full.first() {
        let t0 = g0.points.data.scalar_type();
        let l0 = l0.clone();
        if let Some((_, l, gl)) = full[1..]
            .iter()
            .find(|(_, _, g)| g.points.data.scalar_type() != t0)
        {
            // Image data reads as Float64 points beside Float32 meshes; like VTK's append,
            // mixed types meet in Float64, which holds every Float32 and 32-bit integer exactly.
            let exact = |t: Option<ScalarType>| {
                matches!(
                    t,
                    Some(
                        ScalarType::Float32
                            | ScalarType::Float64
                            | ScalarType::Int8
                            | ScalarType::UInt8
                            | ScalarType::Int16
                            | ScalarType::UInt16
                            | ScalarType::Int32
                            | ScalarType::UInt32
                    )
                )
            };
            if let Some((_, bad, g)) = full
                .iter()
                .find(|(_, _, g)| !exact(g.points.data.scalar_type()))
            {
                return Err(FormatError::new(
                    Place::Other(bad.clone()),
                    format!(
                        "points are {} and other blocks' are not ({l0}: {}, {l}: {}); blocks with 64-bit integer points merge only with blocks of the same type",
                        g.points.data.type_name(),
                        g0.points.data.type_name(),
                        gl.points.data.type_name()
                    ),
                )
                .with_file(file));
            }
            for (_, _, g) in &mut full {
                if !matches!(g.points.data, ArrayData::Float64(_)) {
                    g.points.data = ArrayData::Float64(g.points.data.to_f64_vec());
                }
            }
        }
    }
    let point_keep = {
        let parts: Vec<(&str, &Attributes)> = full
            .iter()
            .map(|(_, l, g)| (l.as_str(), &g.point_data))
            .collect();
        kept_names(file, &parts, "point")
    };
    let cell_keep = {
        let parts: Vec<(&str, &Attributes)> = full
            .iter()
            .map(|(_, l, g)| (l.as_str(), &g.cell_data))
            .collect();
        kept_names(file, &parts, "cell")
    };
    let field = common_field_data(file, &full);
    let mut ids = Vec::new();
    let mut grids = Vec::with_capacity(full.len());
    for (i, _, mut g) in full {
        ids.extend(std::iter::repeat(i as i32).take(g.num_cells()));
        g.point_data = only(std::mem::take(&mut g.point_data), &point_keep);
        g.cell_data = only(std::mem::take(&mut g.cell_data), &cell_keep);
        grids.push(g);
    }
    let mut g = crate::vtu::merge(grids).map_err(|e| e.with_file(file))?;
    if g.cell_data.get(BLOCK_ID_ARRAY).is_some() {
        warn(&format!(
            "{}: the blocks' own cell array '{BLOCK_ID_ARRAY}' is replaced by the merged block index",
            file.display()
        ));
    }
    g.cell_data
        .insert(DataArray::new(BLOCK_ID_ARRAY, 1, ArrayData::Int32(ids)));
    g.field_data = field;
    g.field_data.retain(|a| a.name != BLOCK_NAMES_ARRAY);
    g.field_data.push(DataArray::new(
        BLOCK_NAMES_ARRAY,
        1,
        ArrayData::String(names),
    ));
    Ok(g)
}

/// Field arrays bit-identical in every block (a shared time value, say); the others belong to
/// one block each and have no place in the merged grid, so they are dropped with a warning.
fn common_field_data(file: &Path, full: &[(usize, String, Grid)]) -> Vec<DataArray> {
    let Some((_, _, first)) = full.first() else {
        return Vec::new();
    };
    let mut out = Vec::new();
    let mut dropped = Vec::new();
    for a in &first.field_data {
        if full[1..]
            .iter()
            .all(|(_, _, g)| g.field_data.iter().any(|b| b.name == a.name && b.bit_eq(a)))
        {
            out.push(a.clone());
        } else {
            dropped.push(a.name.as_str());
        }
    }
    for (_, _, g) in &full[1..] {
        for b in &g.field_data {
            if !out.iter().any(|a| a.name == b.name) && !dropped.contains(&b.name.as_str()) {
                dropped.push(&b.name);
            }
        }
    }
    if !dropped.is_empty() {
        warn(&format!(
            "{}: field data {} differs between blocks; dropped",
            file.display(),
            dropped
                .iter()
                .map(|n| format!("'{n}'"))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    out
}
