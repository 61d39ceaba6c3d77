//! `.vtm` (vtkMultiBlockDataSet): nested `<Block>`s and `<Piece>`s whose `<DataSet file=...>`
//! leaves are read in document order; a `<DataSet>` without `file` is an empty block.

use super::merge::Block;
use super::tags::{self, Kind};
use super::{read_index, read_into, Chain};
use crate::{FormatError, Result};
use std::path::Path;

/// VTK writes the leaves of a vtkMultiBlockDataSet and of a vtkMultiPieceDataSet the same way;
/// `vtkMultiGroupDataSet` is what files from before VTK 5.2 say.
const ROOT_TYPES: [&str; 3] = [
    "vtkMultiBlockDataSet",
    "vtkMultiPieceDataSet",
    "vtkMultiGroupDataSet",
];

/// A block's name: its `name` attribute, else `Block N` after its `index` (or its position),
/// as ParaView lists unnamed blocks.
fn block_name(tag: &tags::Tag, position: usize) -> String {
    match (tag.get("name"), tag.get("index")) {
        (Some(n), _) if !n.is_empty() => n.to_string(),
        (_, Some(i)) => format!("Block {i}"),
        _ => format!("Block {position}"),
    }
}

/// Appends the leaves of the .vtm at `path` (already entered in `chain`) to `out`, named by
/// their path of block names (`fluid/inlet`).
pub(crate) fn leaves(path: &Path, chain: &Chain, out: &mut Vec<Block>) -> Result<()> {
    let bytes = read_index(path)?;
    let tags = tags::tags(&bytes).map_err(|e| e.with_file(path))?;
    tags::check_root(&tags, &ROOT_TYPES).map_err(|e| e.with_file(path))?;
    // Names of the open <Block>/<Piece> elements, and how many children each has seen so far
    // (the position of an unnamed, unindexed child).
    let mut stack: Vec<(String, usize)> = vec![(String::new(), 0)];
    for t in &tags[1..] {
        match (t.name.as_str(), t.kind) {
            ("Block" | "Piece", Kind::Open) => {
                let name = block_name(t, next_position(&mut stack));
                stack.push((name, 0));
            }
            ("Block" | "Piece", Kind::Close) if stack.len() > 1 => {
                stack.pop();
            }
            ("DataSet", Kind::Open | Kind::Empty) => {
                let own = block_name(t, next_position(&mut stack));
                let mut full: Vec<&str> = stack[1..].iter().map(|(n, _)| n.as_str()).collect();
                full.push(&own);
                let full = full.join("/");
                let place = format!("block '{full}'");
                match t.get("file") {
                    Some(f) if !f.is_empty() => read_into(path, &place, &full, f, chain, out)?,
                    _ => out.push(Block {
                        name: full,
                        label: place,
                        grid: None,
                    }),
                }
            }
            // An empty <Block/> or <Piece/> holds no leaves.
            _ => {}
        }
    }
    if tags.iter().all(|t| t.name != "DataSet")
        && tags.iter().all(|t| !ROOT_TYPES.contains(&t.name.as_str()))
    {
        return Err(FormatError::whole("no <vtkMultiBlockDataSet> element").with_file(path));
    }
    Ok(())
}

fn next_position(stack: &mut [(String, usize)]) -> usize {
    let Some(top) = stack.last_mut() else {
        return 0;
    };
    top.1 += 1;
    top.1 - 1
}
