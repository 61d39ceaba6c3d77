//! K-D partition of a tet mesh: the tree of split planes and the split mesh whose tets each lie in
//! exactly one leaf.

pub mod tree;

pub use tree::{KdNode, KdTree, Split};
