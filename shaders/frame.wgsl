// The per-frame uniform shared by classify.wgsl and draw.wgsl; prepended to both when the
// shaders are loaded (WGSL has no include), so the layout is written once, matching the Rust
// `FrameUniform` it is filled from.

struct Frame {
    // xyz: the eye relative to the mesh centre; w: the near depth (View::near)
    eye: vec4<f32>,
    r: vec4<f32>,
    u: vec4<f32>,
    f: vec4<f32>,
    // width, height, scale (tan of half the view angle, or the parallel scale), aspect
    size: vec4<f32>,
    // tet count, parallel (0/1), cell field (0/1), unused
    flags: vec4<u32>,
}
