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

pub(crate) fn nodes(c: &mut Cursor<'_>, b: &mut Builder) -> Result<()> {
    let n = count_line(c, "the number of nodes")?;
    b.node_tags.reserve(c.cap(n, 8));
    b.coords.reserve(c.cap(n.saturating_mul(3), 8));
    for _ in 0..n {
        let at = c.pos;
        let tag = c.int("a node number")?;
        let mut xyz = [0.0; 3];
        for v in &mut xyz {
            *v = c.real("a node coordinate")?;
        }
        b.add_node(c, at, tag, xyz, None)?;
    }
    b.nodes_read = true;
    c.expect_end("Nodes")
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
    c.expect_end("Elements")
}
