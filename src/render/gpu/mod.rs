//! GPU projected tetrahedra (hardware-assisted PT) with wgpu and the WGSL shaders in `shaders/`.
//!
//! Per frame: the camera and the CPU sort's visibility order are uploaded (nothing else; the mesh,
//! field and shading tables stay resident), a compute pass classifies every projected tet and
//! writes its fan of 3 or 4 triangles with homogeneous (Sf, Sb, l) per vertex, a second one turns
//! the order into the index buffer, and one draw composites the triangles front to back into a
//! float target that is read back into an [`Image`](super::Image).

mod context;
mod pipelines;
mod readback;
mod renderer;
mod resources;
mod scene;

pub use context::{GpuContext, TargetFormat};
pub use renderer::{GpuRenderer, GpuTimes, SceneFrameStats};
pub use scene::SceneTables;
