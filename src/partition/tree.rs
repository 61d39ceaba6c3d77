//! The K-D tree of axis-aligned split planes, its visibility order of leaves for any viewpoint,
//! and its encoding as VTK field data (so a split .vtu carries its own tree).

use anyhow::{bail, Context, Result};
use formats::{ArrayData, DataArray};

use crate::camera::Viewpoint;
use crate::geom::Aabb;

/// An inner node's plane: `axis` (0 = x, 1 = y, 2 = z) at `position`. Tets with every vertex at
/// `coordinate <= position` belong to `left`, those with every vertex at `>= position` to `right`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Split {
    pub axis: u8,
    pub position: f64,
    pub left: u32,
    pub right: u32,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KdNode {
    pub bounds: Aabb,
    pub depth: u32,
    pub parent: Option<u32>,
    /// `Some` for inner nodes.
    pub split: Option<Split>,
    /// `Some` for leaves: leaf ids are 0..num_leaves, in depth-first left-to-right order.
    pub leaf_id: Option<u32>,
    /// Tets in this node's subtree (after splitting).
    pub tet_count: u64,
}

/// Node 0 is the root.
#[derive(Clone, Debug, PartialEq)]
pub struct KdTree {
    pub nodes: Vec<KdNode>,
}

/// Field data array names that hold the tree in a split .vtu, one tuple per node.
pub const FIELD_BOUNDS: &str = "kd_node_bounds";
pub const FIELD_DEPTH: &str = "kd_node_depth";
pub const FIELD_PARENT: &str = "kd_node_parent";
pub const FIELD_AXIS: &str = "kd_node_axis";
pub const FIELD_POSITION: &str = "kd_node_position";
pub const FIELD_CHILDREN: &str = "kd_node_children";
pub const FIELD_LEAF_ID: &str = "kd_node_leaf_id";
pub const FIELD_TET_COUNT: &str = "kd_node_tet_count";

impl KdTree {
    /// A tree with one leaf (leaf id 0) covering `bounds`.
    pub fn single_leaf(bounds: Aabb, tet_count: u64) -> KdTree {
        KdTree {
            nodes: vec![KdNode {
                bounds,
                depth: 0,
                parent: None,
                split: None,
                leaf_id: Some(0),
                tet_count,
            }],
        }
    }

    pub fn num_leaves(&self) -> usize {
        self.nodes.iter().filter(|n| n.leaf_id.is_some()).count()
    }

    pub fn depth(&self) -> u32 {
        self.nodes.iter().map(|n| n.depth).max().unwrap_or(0)
    }

    /// Node index of each leaf, indexed by leaf id.
    pub fn leaf_nodes(&self) -> Vec<u32> {
        let mut out = vec![0u32; self.num_leaves()];
        for (i, n) in self.nodes.iter().enumerate() {
            if let Some(l) = n.leaf_id {
                out[l as usize] = i as u32;
            }
        }
        out
    }

    /// Leaf ids front to back for the viewpoint: at each inner node the child on the eye's side
    /// of the plane comes first (for a direction, the child the direction enters first). Where the
    /// eye lies exactly on the plane (or the direction is parallel to it) no ray crosses from one
    /// child into the other, so either order is correct; the left child is taken first.
    pub fn leaf_order_front_to_back(&self, view: &Viewpoint) -> Vec<u32> {
        let mut out = Vec::with_capacity(self.num_leaves());
        let mut stack = vec![0u32];
        while let Some(i) = stack.pop() {
            let node = &self.nodes[i as usize];
            match (node.split, node.leaf_id) {
                (Some(s), _) => {
                    let a = s.axis as usize;
                    let right_first = match view {
                        Viewpoint::Eye(e) => e[a] > s.position,
                        Viewpoint::Direction(d) => d[a] < 0.0,
                    };
                    let (first, second) = if right_first {
                        (s.right, s.left)
                    } else {
                        (s.left, s.right)
                    };
                    stack.push(second);
                    stack.push(first);
                }
                (None, Some(l)) => out.push(l),
                (None, None) => {}
            }
        }
        out
    }

    /// The tree as field data arrays (see the `FIELD_*` names), one tuple per node.
    pub fn to_field_data(&self) -> Vec<DataArray> {
        let n = &self.nodes;
        let i32s = |f: &dyn Fn(&KdNode) -> i32| ArrayData::Int32(n.iter().map(f).collect());
        vec![
            DataArray::new(
                FIELD_BOUNDS,
                6,
                ArrayData::Float64(n.iter().flat_map(|x| x.bounds.to_vtk()).collect()),
            ),
            DataArray::new(FIELD_DEPTH, 1, i32s(&|x| x.depth as i32)),
            DataArray::new(
                FIELD_PARENT,
                1,
                i32s(&|x| x.parent.map_or(-1, |p| p as i32)),
            ),
            DataArray::new(
                FIELD_AXIS,
                1,
                ArrayData::Int8(
                    n.iter()
                        .map(|x| x.split.map_or(-1, |s| s.axis as i8))
                        .collect(),
                ),
            ),
            DataArray::new(
                FIELD_POSITION,
                1,
                ArrayData::Float64(
                    n.iter()
                        .map(|x| x.split.map_or(f64::NAN, |s| s.position))
                        .collect(),
                ),
            ),
            DataArray::new(
                FIELD_CHILDREN,
                2,
                ArrayData::Int32(
                    n.iter()
                        .flat_map(|x| {
                            x.split
                                .map_or([-1, -1], |s| [s.left as i32, s.right as i32])
                        })
                        .collect(),
                ),
            ),
            DataArray::new(
                FIELD_LEAF_ID,
                1,
                i32s(&|x| x.leaf_id.map_or(-1, |l| l as i32)),
            ),
            DataArray::new(
                FIELD_TET_COUNT,
                1,
                ArrayData::Int64(n.iter().map(|x| x.tet_count as i64).collect()),
            ),
        ]
    }

    /// Reads the tree back from field data; `Ok(None)` when the arrays are absent (a mesh that was
    /// never partitioned). Checks every index so a hand-edited file cannot make it loop.
    pub fn from_field_data(field: &[DataArray]) -> Result<Option<KdTree>> {
        let get = |name: &str| field.iter().find(|a| a.name == name);
        let Some(axis) = get(FIELD_AXIS) else {
            return Ok(None);
        };
        let need = |name: &str| {
            get(name).with_context(|| format!("field data has {FIELD_AXIS} but not {name}"))
        };
        let bounds = need(FIELD_BOUNDS)?;
        let depth = need(FIELD_DEPTH)?;
        let parent = need(FIELD_PARENT)?;
        let position = need(FIELD_POSITION)?;
        let children = need(FIELD_CHILDREN)?;
        let leaf = need(FIELD_LEAF_ID)?;
        let count = need(FIELD_TET_COUNT)?;
        let n = axis.data.len();
        for (a, c) in [
            (bounds, 6),
            (depth, 1),
            (parent, 1),
            (position, 1),
            (children, 2),
            (leaf, 1),
            (count, 1),
        ] {
            if a.data.len() != n * c {
                bail!(
                    "field data array '{}' has {} values, expected {} for {n} tree nodes",
                    a.name,
                    a.data.len(),
                    n * c
                );
            }
        }
        if n == 0 {
            bail!("field data array '{FIELD_AXIS}' is empty: a K-D tree has at least a root");
        }
        let idx = |v: f64, what: &str, i: usize| -> Result<Option<u32>> {
            if v == -1.0 {
                return Ok(None);
            }
            if v < 0.0 || v >= n as f64 || v.fract() != 0.0 {
                bail!("tree node {i}: {what} {v} is not a node index below {n}");
            }
            Ok(Some(v as u32))
        };
        let mut nodes = Vec::with_capacity(n);
        let mut leaves = 0usize;
        for i in 0..n {
            let b = [0, 1, 2, 3, 4, 5].map(|k| bounds.data.get_f64(6 * i + k));
            let ax = axis.data.get_f64(i);
            let split = if ax >= 0.0 {
                if ax > 2.0 {
                    bail!("tree node {i}: split axis {ax} is not 0, 1 or 2");
                }
                let l = idx(children.data.get_f64(2 * i), "left child", i)?;
                let r = idx(children.data.get_f64(2 * i + 1), "right child", i)?;
                match (l, r) {
                    (Some(l), Some(r)) if l as usize > i && r as usize > i && l != r => {
                        Some(Split {
                            axis: ax as u8,
                            position: position.data.get_f64(i),
                            left: l,
                            right: r,
                        })
                    }
                    _ => bail!("tree node {i}: children must be two distinct later nodes"),
                }
            } else {
                None
            };
            let leaf_id = idx(leaf.data.get_f64(i), "leaf id", i)?;
            if split.is_none() == leaf_id.is_none() {
                bail!("tree node {i}: a node is a leaf (leaf id, no split) or inner (split, leaf id -1)");
            }
            leaves += leaf_id.is_some() as usize;
            nodes.push(KdNode {
                bounds: Aabb {
                    min: [b[0], b[2], b[4]],
                    max: [b[1], b[3], b[5]],
                },
                depth: depth.data.get_f64(i).max(0.0) as u32,
                parent: idx(parent.data.get_f64(i), "parent", i)?,
                split,
                leaf_id,
                tet_count: count.data.get_f64(i).max(0.0) as u64,
            });
        }
        let mut seen = vec![false; leaves];
        for (i, node) in nodes.iter().enumerate() {
            if let Some(l) = node.leaf_id {
                match seen.get_mut(l as usize) {
                    Some(s) if !*s => *s = true,
                    _ => bail!("tree node {i}: leaf id {l} is repeated or not below {leaves}"),
                }
            }
        }
        Ok(Some(KdTree { nodes }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_leaves() -> KdTree {
        let b = Aabb {
            min: [0.0; 3],
            max: [2.0, 1.0, 1.0],
        };
        let mut lb = b;
        lb.max[0] = 1.0;
        let mut rb = b;
        rb.min[0] = 1.0;
        let leaf = |bounds, id| KdNode {
            bounds,
            depth: 1,
            parent: Some(0),
            split: None,
            leaf_id: Some(id),
            tet_count: 5,
        };
        KdTree {
            nodes: vec![
                KdNode {
                    bounds: b,
                    depth: 0,
                    parent: None,
                    split: Some(Split {
                        axis: 0,
                        position: 1.0,
                        left: 1,
                        right: 2,
                    }),
                    leaf_id: None,
                    tet_count: 10,
                },
                leaf(lb, 0),
                leaf(rb, 1),
            ],
        }
    }

    #[test]
    fn field_data_round_trip() {
        let t = two_leaves();
        let back = KdTree::from_field_data(&t.to_field_data())
            .unwrap()
            .unwrap();
        assert_eq!(back, t);
    }

    #[test]
    fn leaf_order_follows_eye() {
        let t = two_leaves();
        assert_eq!(
            t.leaf_order_front_to_back(&Viewpoint::Eye([5.0, 0.5, 0.5])),
            vec![1, 0]
        );
        assert_eq!(
            t.leaf_order_front_to_back(&Viewpoint::Eye([-5.0, 0.5, 0.5])),
            vec![0, 1]
        );
        assert_eq!(
            t.leaf_order_front_to_back(&Viewpoint::Direction([1.0, 0.0, 0.0])),
            vec![0, 1]
        );
        assert_eq!(
            t.leaf_order_front_to_back(&Viewpoint::Direction([-1.0, 0.0, 0.0])),
            vec![1, 0]
        );
    }

    #[test]
    fn rejects_cyclic_children() {
        let mut f = two_leaves().to_field_data();
        if let ArrayData::Int32(v) = &mut f[5].data {
            v[0] = 0;
        }
        assert!(KdTree::from_field_data(&f).is_err());
    }
}
