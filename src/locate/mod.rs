//! The hierarchical uniform grid of seed 002: O(N) cell location and ray entry faces.
