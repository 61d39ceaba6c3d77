//! MSH 4.1 `$Entities`, `$Nodes` and `$Elements` (ASCII or binary).

use super::build::{tag_i64, to_i32, Builder};
use super::cursor::Cursor;
use super::types::element_type;
use super::warn;
use crate::Result;
use std::collections::HashMap;

/// First physical tag of each entity, by (dimension, tag).
pub(crate) type Physicals = HashMap<(i64, i64), i32>;

pub(crate) fn entities(c: &mut Cursor<'_>, phys: &mut Physicals) -> Result<()> {
    let mut counts = [0u64; 4];
    for (d, n) in counts.iter_mut().enumerate() {
        *n = c.size(&format!("the number of entities of dimension {d}"))?;
    }
    let mut several = 0usize;
    for (dim, &n) in counts.iter().enumerate() {
        for _ in 0..n {
            let tag = c.int("an entity tag")?;
            // A point has its coordinates, the others their bounding box.
            let reals = if dim == 0 { 3 } else { 6 };
            for _ in 0..reals {
                c.real("an entity's coordinates")?;
            }
            let at = c.pos;
            let np = c.size("the number of physical tags of an entity")?;
            if np > c.remaining() as u64 {
                return Err(c.err_at(at, format!("{np} physical tags cannot fit in the file")));
            }
            for k in 0..np {
                let at = c.pos;
                let p = c.int("a physical tag")?;
                let p = to_i32(c, at, p, "physical tag")?;
                if k == 0 {
                    phys.insert((dim as i64, tag), p);
                } else if k == 1 {
                    several += 1;
                }
            }
            if dim > 0 {
                let at = c.pos;
                let nb = c.size("the number of bounding entities")?;
                if nb > c.remaining() as u64 {
                    return Err(
                        c.err_at(at, format!("{nb} bounding entities cannot fit in the file"))
                    );
                }
                for _ in 0..nb {
                    c.int("a bounding entity tag")?;
                }
            }
        }
    }
    if several > 0 {
        warn(&format!(
            "{}: {several} entities belong to several physical groups; gmsh:physical keeps the first group of each",
            c.file_name()
        ));
    }
    c.expect_end("Entities")
}

pub(crate) fn nodes(c: &mut Cursor<'_>, b: &mut Builder) -> Result<()> {
    let blocks = c.size("the number of node blocks")?;
    let at = c.pos;
    let total = c.size("the number of nodes")?;
    c.size("the smallest node tag")?;
    c.size("the largest node tag")?;
    b.node_tags.reserve(c.cap(total, 8));
    b.coords.reserve(c.cap(total.saturating_mul(3), 8));
    let mut read = 0u64;
    let mut tags = Vec::new();
    for _ in 0..blocks {
        let at_block = c.pos;
        let dim = c.int("the dimension of a node block")?;
        c.int("the entity tag of a node block")?;
        let parametric = c.int("the parametric flag of a node block")?;
        let n = c.size("the number of nodes in a block")?;
        if !(0..=3).contains(&dim) || !(0..=1).contains(&parametric) {
            return Err(c.err_at(
                at_block,
                format!("node block of dimension {dim} with parametric flag {parametric}"),
            ));
        }
        let params = if parametric == 1 { dim as usize } else { 0 };
        tags.clear();
        tags.reserve(c.cap(n, 8));
        for _ in 0..n {
            let at = c.pos;
            let t = c.size("a node tag")?;
            tags.push((at, tag_i64(c, at, t, "node tag")?));
        }
        for &(_, tag) in &tags {
            let at = c.pos;
            let mut xyz = [0.0; 3];
            for v in &mut xyz {
                *v = c.real("a node coordinate")?;
            }
            let uvw = if parametric == 1 {
                let mut uvw = [f64::NAN; 3];
                for v in uvw.iter_mut().take(params) {
                    *v = c.real("a parametric coordinate")?;
                }
                Some(uvw)
            } else {
                None
            };
            b.add_node(c, at, tag, xyz, uvw)?;
        }
        read += n;
    }
    if read != total {
        return Err(c.err_at(
            at,
            format!("the $Nodes header counts {total} nodes, its blocks hold {read}"),
        ));
    }
    b.nodes_read = true;
    c.expect_end("Nodes")
}

pub(crate) fn elements(c: &mut Cursor<'_>, b: &mut Builder, phys: &Physicals) -> Result<()> {
    let blocks = c.size("the number of element blocks")?;
    let at = c.pos;
    let total = c.size("the number of elements")?;
    c.size("the smallest element tag")?;
    c.size("the largest element tag")?;
    let room = c.cap(total, 16);
    b.cells.types.reserve(room);
    b.cells.offsets.reserve(room);
    b.element_tags.reserve(room);
    b.physical.reserve(room);
    b.geometrical.reserve(room);
    let mut read = 0u64;
    let mut node_tags = [0i64; 27];
    for _ in 0..blocks {
        let dim = c.int("the dimension of an element block")?;
        let at_entity = c.pos;
        let entity = c.int("the entity tag of an element block")?;
        let at_type = c.pos;
        let ty = c.int("the element type of a block")?;
        let ty = element_type(ty).map_err(|m| c.err_at(at_type, m))?;
        let n = c.size("the number of elements in a block")?;
        let physical = phys.get(&(dim, entity)).copied().unwrap_or(0);
        let geometrical = to_i32(c, at_entity, entity, "entity tag")?;
        for _ in 0..n {
            let at = c.pos;
            let t = c.size("an element tag")?;
            let tag = tag_i64(c, at, t, "element tag")?;
            for slot in node_tags.iter_mut().take(ty.nodes) {
                let at_node = c.pos;
                let v = c.size("a node tag of an element")?;
                *slot = tag_i64(c, at_node, v, "node tag")?;
            }
            b.add_element(
                c,
                at,
                &ty,
                tag,
                &node_tags[..ty.nodes],
                physical,
                geometrical,
            )?;
        }
        read += n;
    }
    if read != total {
        return Err(c.err_at(
            at,
            format!("the $Elements header counts {total} elements, its blocks hold {read}"),
        ));
    }
    b.elements_read = true;
    c.expect_end("Elements")
}
