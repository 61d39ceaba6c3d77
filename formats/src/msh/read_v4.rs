//! MSH 4.1 `$Entities`, `$PartitionedEntities`, `$Nodes` and `$Elements` (ASCII or binary).

use super::build::{tag_i64, to_i32, Builder};
use super::cursor::Cursor;
use super::types::element_type;
use super::warn;
use crate::Result;
use std::collections::HashMap;

/// An entity of a partitioned mesh (`$PartitionedEntities`): elements of a partitioned file name
/// these, not the model's entities.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Partitioned {
    /// The model entity it was cut from, (dimension, tag).
    pub parent: (i64, i64),
    /// Its own first physical tag, when it has one.
    pub physical: Option<i32>,
    /// The first partition it belongs to (interfaces belong to several).
    pub partition: i32,
    /// Whether it belongs to more than one partition.
    pub shared: bool,
}

/// What `$Entities` and `$PartitionedEntities` say about each entity, by (dimension, tag).
#[derive(Default)]
pub(crate) struct Physicals {
    /// First physical tag of each model entity.
    pub model: HashMap<(i64, i64), i32>,
    pub partitioned: HashMap<(i64, i64), Partitioned>,
    /// Whether the file has a `$PartitionedEntities` section.
    pub is_partitioned: bool,
}

impl Physicals {
    pub fn new() -> Physicals {
        Physicals::default()
    }

    /// The physical group and the partition (0 unpartitioned) of elements of entity
    /// (`dim`, `tag`): a partitioned entity's own physical tag, else its parent's.
    fn of(&self, dim: i64, tag: i64) -> (i32, i32, bool) {
        if self.is_partitioned {
            if let Some(p) = self.partitioned.get(&(dim, tag)) {
                let physical = p
                    .physical
                    .or_else(|| self.model.get(&p.parent).copied())
                    .unwrap_or(0);
                return (physical, p.partition, p.shared);
            }
        }
        (self.model.get(&(dim, tag)).copied().unwrap_or(0), 0, false)
    }
}

/// Reads the physical tags of an entity (after its coordinates): the first, and whether there
/// were more.
fn physical_tags(c: &mut Cursor<'_>) -> Result<(Option<i32>, bool)> {
    let at = c.pos;
    let np = c.size("the number of physical tags of an entity")?;
    if np > c.remaining() as u64 {
        return Err(c.err_at(at, format!("{np} physical tags cannot fit in the file")));
    }
    let mut first = None;
    for k in 0..np {
        let at = c.pos;
        let p = c.int("a physical tag")?;
        let p = to_i32(c, at, p, "physical tag")?;
        if k == 0 {
            first = Some(p);
        }
    }
    Ok((first, np > 1))
}

/// Skips an entity's coordinates: a point's position, or the others' bounding box.
fn skip_coordinates(c: &mut Cursor<'_>, dim: usize) -> Result<()> {
    let reals = if dim == 0 { 3 } else { 6 };
    for _ in 0..reals {
        c.real("an entity's coordinates")?;
    }
    Ok(())
}

/// Skips the bounding entities that follow a curve's, surface's or volume's physical tags.
fn skip_bounding(c: &mut Cursor<'_>, dim: usize) -> Result<()> {
    if dim == 0 {
        return Ok(());
    }
    let at = c.pos;
    let nb = c.size("the number of bounding entities")?;
    if nb > c.remaining() as u64 {
        return Err(c.err_at(at, format!("{nb} bounding entities cannot fit in the file")));
    }
    for _ in 0..nb {
        c.int("a bounding entity tag")?;
    }
    Ok(())
}

fn warn_several(c: &Cursor<'_>, several: usize, what: &str) {
    if several > 0 {
        warn(&format!(
            "{}: {several} {what} belong to several physical groups; gmsh:physical keeps the first group of each",
            c.file_name()
        ));
    }
}

pub(crate) fn entities(c: &mut Cursor<'_>, phys: &mut Physicals) -> Result<()> {
    let mut counts = [0u64; 4];
    for (d, n) in counts.iter_mut().enumerate() {
        *n = c.size(&format!("the number of entities of dimension {d}"))?;
    }
    let mut several = 0usize;
    for (dim, &n) in counts.iter().enumerate() {
        for _ in 0..n {
            let tag = c.int("an entity tag")?;
            skip_coordinates(c, dim)?;
            let (first, more) = physical_tags(c)?;
            if let Some(p) = first {
                phys.model.insert((dim as i64, tag), p);
            }
            several += usize::from(more);
            skip_bounding(c, dim)?;
        }
    }
    warn_several(c, several, "entities");
    c.expect_end("Entities")
}

/// Reads `$PartitionedEntities` (what `gmsh -part N` writes): the partition count, the ghost
/// entities (tag and partition; their elements come in `$GhostElements`, which is skipped), then
/// each partitioned point, curve, surface and volume with its parent model entity, its
/// partitions, its coordinates, its physical tags and (but points) its bounding entities.
pub(crate) fn partitioned_entities(c: &mut Cursor<'_>, phys: &mut Physicals) -> Result<()> {
    c.size("the number of partitions")?;
    let at = c.pos;
    let ghosts = c.size("the number of ghost entities")?;
    if ghosts > c.remaining() as u64 {
        return Err(c.err_at(
            at,
            format!("{ghosts} ghost entities cannot fit in the file"),
        ));
    }
    for _ in 0..ghosts {
        c.int("a ghost entity tag")?;
        c.int("the partition of a ghost entity")?;
    }
    let mut counts = [0u64; 4];
    for (d, n) in counts.iter_mut().enumerate() {
        *n = c.size(&format!(
            "the number of partitioned entities of dimension {d}"
        ))?;
    }
    let mut several = 0usize;
    for (dim, &n) in counts.iter().enumerate() {
        for _ in 0..n {
            let at_entity = c.pos;
            let tag = c.int("a partitioned entity tag")?;
            let parent_dim = c.int("the parent dimension of a partitioned entity")?;
            let parent_tag = c.int("the parent tag of a partitioned entity")?;
            let at = c.pos;
            let np = c.size("the number of partitions of an entity")?;
            if np > c.remaining() as u64 {
                return Err(c.err_at(at, format!("{np} partitions cannot fit in the file")));
            }
            if np == 0 {
                return Err(c.err_at(
                    at,
                    format!("partitioned entity {tag} of dimension {dim} is in no partition"),
                ));
            }
            let mut partition = 0;
            for k in 0..np {
                let at = c.pos;
                let p = c.int("a partition tag")?;
                if k == 0 {
                    partition = to_i32(c, at, p, "partition tag")?;
                }
            }
            skip_coordinates(c, dim)?;
            let (physical, more) = physical_tags(c)?;
            several += usize::from(more);
            skip_bounding(c, dim)?;
            let entity = Partitioned {
                parent: (parent_dim, parent_tag),
                physical,
                partition,
                shared: np > 1,
            };
            if phys.partitioned.insert((dim as i64, tag), entity).is_some() {
                return Err(c.err_at(
                    at_entity,
                    format!("partitioned entity {tag} of dimension {dim} appears twice"),
                ));
            }
        }
    }
    phys.is_partitioned = true;
    warn_several(c, several, "partitioned entities");
    c.expect_end("PartitionedEntities")
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
        let (physical, partition, shared) = phys.of(dim, entity);
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
        if phys.is_partitioned {
            b.partition
                .extend(std::iter::repeat(partition).take(n as usize));
            if shared {
                b.shared_partition_cells += n as usize;
            }
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
