//! Rendering: transfer functions, ray integration, projected tetrahedra and the ray-cast reference.
