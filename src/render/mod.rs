//! Rendering: transfer functions, ray integration, projected tetrahedra and the ray-cast reference.

// Negated comparisons are deliberate: they also catch NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod colorspace;
pub mod cut;
pub mod field;
pub mod gpu;
pub mod image;
pub mod integrate;
pub mod plot;
pub mod prepare;
pub mod pt;
pub mod raycast;
pub mod transfer;
pub mod walk;

pub use image::Image;
pub use integrate::Integration;
