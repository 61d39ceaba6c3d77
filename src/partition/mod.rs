//! K-D partition of a tet mesh: the tree of split planes and the split mesh whose tets each lie in
//! exactly one leaf.

pub mod build;
pub mod input;
pub mod output;
pub mod search;
pub mod split;
pub mod tree;

pub use build::{
    partition, LevelReport, PartitionOptions, PartitionReport, Partitioned, Stop, LEAF_ID,
    ORIGINAL_CELL_ID,
};
pub use search::{SearchParams, Strategy};
pub use tree::{KdNode, KdTree, Split};
