//! Shader modules, bind-group layouts and the three pipelines (classify, expand, draw).

use super::context::GpuContext;

// The frame uniform is declared once, in frame.wgsl, and prepended to the stages that read it.
const CLASSIFY: &str = concat!(
    include_str!("../../../shaders/frame.wgsl"),
    include_str!("../../../shaders/classify.wgsl")
);
const EXPAND: &str = include_str!("../../../shaders/expand.wgsl");
const DRAW: &str = concat!(
    include_str!("../../../shaders/frame.wgsl"),
    include_str!("../../../shaders/draw.wgsl")
);

/// Bytes per fan vertex: clip x, y and the homogeneous (pf, qf, pb, qb).
pub const VERTEX_BYTES: u64 = 24;
/// Fan vertices per tet.
pub const VERTS_PER_TET: u64 = 5;
/// Fan indices per tet (4 triangles).
pub const INDICES_PER_TET: u64 = 12;
/// Compute workgroup size of both compute shaders.
pub const WORKGROUP: u32 = 64;

pub struct Pipelines {
    pub classify: wgpu::ComputePipeline,
    pub classify_layout: wgpu::BindGroupLayout,
    pub expand: wgpu::ComputePipeline,
    pub expand_layout: wgpu::BindGroupLayout,
    pub draw: wgpu::RenderPipeline,
    pub draw_layout: wgpu::BindGroupLayout,
    /// The draw with per-pixel body crossings (scenes).
    pub draw_scene: wgpu::RenderPipeline,
    pub draw_scene_layout: wgpu::BindGroupLayout,
}

fn entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    ty: wgpu::BindingType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty,
        count: None,
    }
}

fn uniform() -> wgpu::BindingType {
    wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Uniform,
        has_dynamic_offset: false,
        min_binding_size: None,
    }
}

fn storage(read_only: bool) -> wgpu::BindingType {
    wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Storage { read_only },
        has_dynamic_offset: false,
        min_binding_size: None,
    }
}

impl Pipelines {
    pub fn new(ctx: &GpuContext) -> Pipelines {
        let dev = &ctx.device;
        let module = |label: &str, src: &str| {
            dev.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(src.into()),
            })
        };
        let cs = wgpu::ShaderStages::COMPUTE;
        let classify_layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("classify"),
            entries: &[
                entry(0, cs, uniform()),
                entry(1, cs, storage(true)),
                entry(2, cs, storage(true)),
                entry(3, cs, storage(true)),
                entry(4, cs, storage(false)),
                entry(5, cs, storage(false)),
            ],
        });
        let expand_layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("expand"),
            entries: &[
                entry(0, cs, uniform()),
                entry(1, cs, storage(true)),
                entry(2, cs, storage(false)),
            ],
        });
        let fs = wgpu::ShaderStages::FRAGMENT;
        let draw_entries = [
            entry(0, fs, uniform()),
            entry(1, fs, uniform()),
            entry(
                2,
                fs,
                wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D3,
                    multisampled: false,
                },
            ),
            entry(3, fs, storage(true)),
            entry(4, fs, storage(true)),
        ];
        let draw_layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("draw"),
            entries: &draw_entries,
        });
        let mut scene_entries = draw_entries.to_vec();
        scene_entries.push(entry(
            5,
            fs,
            wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2Array,
                multisampled: false,
            },
        ));
        scene_entries.push(entry(6, fs, storage(true)));
        let draw_scene_layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("draw scene"),
            entries: &scene_entries,
        });
        let compute =
            |label: &str, src: &str, layout: &wgpu::BindGroupLayout, entry_point: &str| {
                let m = module(label, src);
                let pl = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some(label),
                    bind_group_layouts: &[Some(layout)],
                    immediate_size: 0,
                });
                dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(label),
                    layout: Some(&pl),
                    module: &m,
                    entry_point: Some(entry_point),
                    compilation_options: Default::default(),
                    cache: None,
                })
            };
        let classify = compute("classify", CLASSIFY, &classify_layout, "classify");
        let expand = compute("expand", EXPAND, &expand_layout, "expand");

        let dm = module("draw", DRAW);
        // Front to back: dst = dst + (1 - dst.a) src, for colour and alpha alike.
        let under = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::OneMinusDstAlpha,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Add,
        };
        let render = |label: &str, layout: &wgpu::BindGroupLayout, fs_entry: &str| {
            let pl = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: &[Some(layout)],
                immediate_size: 0,
            });
            dev.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&pl),
                vertex: wgpu::VertexState {
                    module: &dm,
                    entry_point: Some("vs"),
                    compilation_options: Default::default(),
                    buffers: &[Some(wgpu::VertexBufferLayout {
                        array_stride: VERTEX_BYTES,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &wgpu::vertex_attr_array![0 => Float32x2, 1 => Float32x4],
                    })],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: None,
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &dm,
                    entry_point: Some(fs_entry),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: ctx.format.wgpu(),
                        blend: Some(wgpu::BlendState {
                            color: under,
                            alpha: under,
                        }),
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let draw = render("draw", &draw_layout, "fs");
        let draw_scene = render("draw scene", &draw_scene_layout, "fs_scene");
        Pipelines {
            classify,
            classify_layout,
            expand,
            expand_layout,
            draw,
            draw_layout,
            draw_scene,
            draw_scene_layout,
        }
    }
}
