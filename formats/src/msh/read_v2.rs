//! MSH 2.2 `$Nodes` and `$Elements` (ASCII or binary): tags on every element (physical, elementary, then partitions), no entities.

use super::build::Builder;
use super::cursor::Cursor;
use super::types::element_type;
use crate::Result;

/// The count line that opens both sections: text even in binary files.
fn count_line(c: &mut Cursor<'_>, what: &str) -> Result<u64> {
    let n = c.ascii_count(what)?;
    if c.binary {
        c.end_line()?;
    }
    Ok(n)
}

/// A node line's start: its position, number and coordinates.
fn node_start(c: &mut Cursor<'_>) -> Result<(usize, i64, [f64; 3])> {
    let at = c.pos;
    let tag = c.int("a node number")?;
    let mut xyz = [0.0; 3];
    for v in &mut xyz {
        *v = c.real("a node coordinate")?;
    }
    Ok((at, tag, xyz))
}

pub(crate) fn nodes(c: &mut Cursor<'_>, b: &mut Builder) -> Result<()> {
    let n = count_line(c, "the number of nodes")?;
    b.node_tags.reserve(c.cap(n, 8));
    b.coords.reserve(c.cap(n.saturating_mul(3), 8));
    for _ in 0..n {
        let (at, tag, xyz) = node_start(c)?;
        b.add_node(c, at, tag, xyz, None)?;
    }
    b.nodes_read = true;
    c.expect_end("Nodes")
}

/// `$ParametricNodes` (`gmsh -save_parametric`, ASCII): per node `tag x y z dim entity` and
/// then its parametric coordinates on its entity (`u` on a curve, `u v` on a surface), which go
/// to `gmsh:parametric` as the MSH 4.1 reader puts them.
pub(crate) fn parametric_nodes(c: &mut Cursor<'_>, b: &mut Builder) -> Result<()> {
    if c.binary {
        return Err(c.err("a binary $ParametricNodes section is not supported (save it as ASCII)"));
    }
    let n = count_line(c, "the number of nodes")?;
    b.node_tags.reserve(c.cap(n, 8));
    b.coords.reserve(c.cap(n.saturating_mul(3), 8));
    for _ in 0..n {
        let (at, tag, xyz) = node_start(c)?;
        c.int("the node's entity dimension")?;
        c.int("the node's entity tag")?;
        let rest = c.rest_of_line();
        let mut uvw = [f64::NAN; 3];
        let tokens = rest
            .split(|b| b.is_ascii_whitespace())
            .filter(|t| !t.is_empty());
        for (k, t) in tokens.enumerate() {
            let v = std::str::from_utf8(t)
                .ok()
                .and_then(|t| t.parse::<f64>().ok())
                .filter(|_| k < 3)
                .ok_or_else(|| {
                    c.err_at(
                        at,
                        format!(
                            "node {tag}: '{}' is not a parametric coordinate (at most three numbers follow the entity)",
                            String::from_utf8_lossy(t)
                        ),
                    )
                })?;
            uvw[k] = v;
        }
        b.add_node(c, at, tag, xyz, Some(uvw))?;
    }
    b.nodes_read = true;
    c.expect_end("ParametricNodes")
}

/// Physical and elementary tags from an element's tag list (0 when absent).
fn tags(list: &[i64]) -> (i64, i64) {
    (
        list.first().copied().unwrap_or(0),
        list.get(1).copied().unwrap_or(0),
    )
}

pub(crate) fn elements(c: &mut Cursor<'_>, b: &mut Builder) -> Result<()> {
    let total = count_line(c, "the number of elements")?;
    let room = c.cap(total, 16);
    b.cells.types.reserve(room);
    b.cells.offsets.reserve(room);
    b.element_tags.reserve(room);
    b.physical.reserve(room);
    b.geometrical.reserve(room);
    let mut node_tags = [0i64; 27];
    let mut tag_list = Vec::new();
    let mut read = 0u64;
    while read < total {
        // Binary files group elements under a header (type, count, tags per element); ASCII ones
        // give type and tag count on every line.
        let (ty, in_group, ntags, at_head) = if c.binary {
            let at = c.pos;
            let ty = c.bin_i32("the element type of a group")?;
            let n = c.bin_i32("the number of elements in a group")?;
            let nt = c.bin_i32("the number of tags in a group")?;
            let n = u64::try_from(n)
                .ok()
                .filter(|&n| n <= total - read)
                .ok_or_else(|| {
                    c.err_at(
                        at,
                        format!("a group of {n} elements, {} left to read", total - read),
                    )
                })?;
            (Some(i64::from(ty)), n, Some(nt), at)
        } else {
            (None, 1, None, c.pos)
        };
        let group_type = match ty {
            Some(t) => Some(element_type(t).map_err(|m| c.err_at(at_head, m))?),
            None => None,
        };
        for _ in 0..in_group {
            let at = c.pos;
            let tag = c.int("an element number")?;
            let owned;
            let ty = match &group_type {
                Some(t) => t,
                None => {
                    let at_type = c.pos;
                    let t = c.int("an element type")?;
                    owned = element_type(t).map_err(|m| c.err_at(at_type, m))?;
                    &owned
                }
            };
            let nt = match ntags {
                Some(nt) => i64::from(nt),
                None => c.int("the number of tags")?,
            };
            let nt = usize::try_from(nt)
                .ok()
                .filter(|&n| n <= 1024)
                .ok_or_else(|| c.err_at(at, format!("element {tag} has {nt} tags")))?;
            tag_list.clear();
            for _ in 0..nt {
                tag_list.push(c.int("an element tag")?);
            }
            for slot in node_tags.iter_mut().take(ty.nodes) {
                *slot = c.int("a node number of an element")?;
            }
            let (p, g) = tags(&tag_list);
            // c.int gives values that fit 32 bits.
            b.add_element(c, at, ty, tag, &node_tags[..ty.nodes], p as i32, g as i32)?;
            // A partitioned file's tags go on with the partition count and the partitions,
            // the owner first (ghosts negative after it).
            let parts = tag_list.get(2).copied().unwrap_or(0);
            b.partition.push(if parts >= 1 {
                if parts > 1 {
                    b.shared_partition_cells += 1;
                }
                tag_list.get(3).map_or(0, |&q| q.unsigned_abs() as i32)
            } else {
                0
            });
        }
        read += in_group;
    }
    // Unpartitioned files (no element with a partition) get no partition array.
    if b.partition.iter().all(|&q| q == 0) {
        b.partition.clear();
        b.shared_partition_cells = 0;
    }
    b.elements_read = true;
    warn_copies(c, b);
    c.expect_end("Elements")
}

/// Warns when elements repeat (same type and nodes): Gmsh 2.2 writes an element once per
/// physical group it belongs to, and the copies stay separate cells, as Gmsh reads them back,
/// so the mesh overlaps itself (volumes count twice, and no visibility order is exact).
fn warn_copies(c: &Cursor<'_>, b: &Builder) {
    use std::hash::{Hash, Hasher};
    let cells = &b.cells;
    let mut seen = std::collections::HashSet::with_capacity(cells.len());
    let mut copies = 0usize;
    let mut nodes = Vec::new();
    for i in 0..cells.len() {
        nodes.clear();
        nodes.extend_from_slice(cells.cell(i));
        nodes.sort_unstable();
        let mut h = std::collections::hash_map::DefaultHasher::new();
        (cells.types[i], &nodes).hash(&mut h);
        if !seen.insert(h.finish()) {
            copies += 1;
        }
    }
    if copies > 0 {
        crate::warn(&format!(
            "{}: {copies} elements repeat an earlier one's type and nodes (MSH 2.2 writes an element once per physical group it is in); the copies are kept as separate cells, as Gmsh reads them, so they overlap",
            c.file_name()
        ));
    }
}
