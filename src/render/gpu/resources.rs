//! What stays on the GPU between frames: the mesh (points, tets, scalars), the per-tet fan
//! vertices and indices, the order buffer, and the shading inputs (pre-integration table as a 3-D
//! texture, transfer-function nodes).

use anyhow::{bail, Result};
use wgpu::util::DeviceExt;

use super::context::GpuContext;
use super::pipelines::{INDICES_PER_TET, VERTEX_BYTES, VERTS_PER_TET};
use crate::render::field::Field;
use crate::render::pt::Shader;

/// Buffers sized for one mesh.
pub struct MeshBuffers {
    pub ntets: u32,
    /// Points are uploaded relative to this (f64) centre, so large offsets cost no precision.
    pub centre: [f64; 3],
    /// The points' bounding box (scenes bound their work with it).
    pub bounds: crate::geom::Aabb,
    pub cell_field: bool,
    pub points: wgpu::Buffer,
    pub tets: wgpu::Buffer,
    pub scalars: wgpu::Buffer,
    pub verts: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub order: wgpu::Buffer,
    pub counts: wgpu::Buffer,
}

/// A texture the shaders sample, filled with `data` (`bytes_per_row` bytes a row, rows of
/// `size.height` per layer or slice).
pub(crate) fn sampled_texture(
    ctx: &GpuContext,
    label: &str,
    size: wgpu::Extent3d,
    dimension: wgpu::TextureDimension,
    format: wgpu::TextureFormat,
    data: &[u8],
    bytes_per_row: u32,
) -> wgpu::Texture {
    let tex = ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size,
        mip_level_count: 1,
        sample_count: 1,
        dimension,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    ctx.queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture: &tex,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        data,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(bytes_per_row),
            rows_per_image: Some(size.height),
        },
        size,
    );
    tex
}

/// Checks one buffer against the device's limits, naming it.
fn check_size(ctx: &GpuContext, what: &str, bytes: u64, storage: bool) -> Result<()> {
    let lim = &ctx.limits;
    if bytes > lim.max_buffer_size {
        bail!(
            "GPU '{}': the {what} need {bytes} bytes, over the adapter's buffer limit of {} bytes",
            ctx.info.name,
            lim.max_buffer_size
        );
    }
    if storage && bytes > lim.max_storage_buffer_binding_size {
        bail!(
            "GPU '{}': the {what} need {bytes} bytes, over the adapter's storage-binding limit of {} bytes",
            ctx.info.name,
            lim.max_storage_buffer_binding_size
        );
    }
    Ok(())
}

impl MeshBuffers {
    pub fn new(
        ctx: &GpuContext,
        points: &[[f64; 3]],
        tets: &[[u32; 4]],
        field: &Field,
    ) -> Result<MeshBuffers> {
        if tets.is_empty() {
            bail!("no tets to render");
        }
        let Ok(ntets) = u32::try_from(tets.len()) else {
            bail!("{} tets: the GPU path takes at most 2^32 - 1", tets.len());
        };
        if tets.len() as u64 * INDICES_PER_TET > u32::MAX as u64 {
            bail!(
                "{} tets: the GPU index buffer addresses at most {} tets",
                tets.len(),
                u32::MAX as u64 / INDICES_PER_TET
            );
        }
        let n = tets.len() as u64;
        check_size(ctx, "points", points.len().max(1) as u64 * 16, true)?;
        check_size(ctx, "tets", n * 16, true)?;
        check_size(ctx, "fan vertices", n * VERTS_PER_TET * VERTEX_BYTES, true)?;
        check_size(ctx, "fan indices", n * INDICES_PER_TET * 4, true)?;

        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for p in points {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let centre = if lo[0].is_finite() {
            [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]))
        } else {
            [0.0; 3]
        };
        let mut pts: Vec<[f32; 4]> = points
            .iter()
            .map(|p| {
                [
                    (p[0] - centre[0]) as f32,
                    (p[1] - centre[1]) as f32,
                    (p[2] - centre[2]) as f32,
                    0.0,
                ]
            })
            .collect();
        if pts.is_empty() {
            pts.push([0.0; 4]);
        }
        let (scal, cell_field): (Vec<f32>, bool) = match field {
            Field::Point(v) => (v.iter().map(|&x| x as f32).collect(), false),
            Field::Cell(v) => (v.iter().map(|&x| x as f32).collect(), true),
        };
        let scal = if scal.is_empty() { vec![0.0] } else { scal };
        check_size(ctx, "scalars", scal.len() as u64 * 4, true)?;
        let dev = &ctx.device;
        let init = |label: &str, contents: &[u8], usage: wgpu::BufferUsages| {
            dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        let st = wgpu::BufferUsages::STORAGE;
        let blank = |label: &str, size: u64, usage: wgpu::BufferUsages| {
            dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        Ok(MeshBuffers {
            ntets,
            centre,
            bounds: crate::geom::Aabb::of_points(points.iter()),
            cell_field,
            points: init("points", bytemuck::cast_slice(&pts), st),
            tets: init("tets", bytemuck::cast_slice(tets), st),
            scalars: init("scalars", bytemuck::cast_slice(&scal), st),
            verts: blank(
                "fan vertices",
                n * VERTS_PER_TET * VERTEX_BYTES,
                st | wgpu::BufferUsages::VERTEX,
            ),
            indices: blank(
                "fan indices",
                n * INDICES_PER_TET * 4,
                st | wgpu::BufferUsages::INDEX,
            ),
            order: blank("order", n * 4, st | wgpu::BufferUsages::COPY_DST),
            counts: blank(
                "class counts",
                32,
                st | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            ),
        })
    }
}

/// Shading inputs for one integration mode.
pub struct ShadeResources {
    pub uniform: wgpu::Buffer,
    pub table: wgpu::Texture,
    pub nodes: wgpu::Buffer,
    /// Per stacked function: scalar origin, 1 / scalar step, 1 / length step, last node index.
    pub luts: wgpu::Buffer,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ShadeUniform {
    mode: [u32; 4],
}

impl ShadeResources {
    pub fn new(ctx: &GpuContext, shader: &Shader) -> Result<ShadeResources> {
        ShadeResources::stack(ctx, &[shader])
    }

    /// Several transfer functions' shading inputs of one mode and size, stacked: table `k` at
    /// depth `k * nl` of the 3-D texture, nodes of function `k` from `k * nodes`.
    pub fn stack(ctx: &GpuContext, shaders: &[&Shader]) -> Result<ShadeResources> {
        let dev = &ctx.device;
        let Some(first) = shaders.first() else {
            bail!("no transfer function to shade with");
        };
        let table_texture = |dims: [u32; 3], data: &[[f32; 4]]| {
            let size = wgpu::Extent3d {
                width: dims[0],
                height: dims[1],
                depth_or_array_layers: dims[2],
            };
            sampled_texture(
                ctx,
                "pre-integration tables",
                size,
                wgpu::TextureDimension::D3,
                wgpu::TextureFormat::Rgba32Float,
                bytemuck::cast_slice(data),
                dims[0] * 16,
            )
        };
        let nodes_buffer = |nodes: &[[f32; 4]]| {
            dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("transfer-function nodes"),
                contents: bytemuck::cast_slice(nodes),
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let (uni, table, nodes, luts) = match first {
            Shader::Pre(t) => {
                let mut data = Vec::with_capacity(t.data.len() * shaders.len());
                let mut luts = Vec::with_capacity(shaders.len());
                for s in shaders {
                    match s {
                        Shader::Pre(u) if u.ns == t.ns && u.nl == t.nl => {
                            data.extend_from_slice(&u.data);
                            luts.push([u.s0, u.inv_ds, u.inv_dl, 0.0]);
                        }
                        _ => bail!("stacked tables differ in mode or size"),
                    }
                }
                let depth = t.nl * shaders.len();
                let max3 = ctx.limits.max_texture_dimension_3d as usize;
                if t.ns > max3 || depth > max3 {
                    bail!(
                        "GPU '{}': {} pre-integration table(s) of {}x{}x{} exceed the adapter's 3-D texture limit of {max3}",
                        ctx.info.name,
                        shaders.len(),
                        t.ns,
                        t.ns,
                        t.nl
                    );
                }
                (
                    ShadeUniform {
                        mode: [2, t.ns as u32, t.nl as u32, 0],
                    },
                    table_texture([t.ns as u32, t.ns as u32, depth as u32], &data),
                    nodes_buffer(&[[0.0; 4]; 2]),
                    luts,
                )
            }
            Shader::Average(tf) | Shader::Linear(tf) => {
                if tf.nodes.len() < 2 {
                    bail!("transfer function with {} nodes: need 2", tf.nodes.len());
                }
                let mut all = Vec::with_capacity(tf.nodes.len() * shaders.len());
                let mut luts = Vec::with_capacity(shaders.len());
                for s in shaders {
                    match s {
                        Shader::Average(u) | Shader::Linear(u)
                            if u.nodes.len() == tf.nodes.len() =>
                        {
                            all.extend_from_slice(&u.nodes);
                            luts.push([u.s0, u.inv_ds, 0.0, u.last]);
                        }
                        _ => bail!("stacked transfer functions differ in mode or node count"),
                    }
                }
                check_size(ctx, "transfer-function nodes", all.len() as u64 * 16, true)?;
                let mode = if matches!(first, Shader::Average(_)) {
                    0
                } else {
                    1
                };
                (
                    ShadeUniform {
                        mode: [mode, tf.nodes.len() as u32, 0, 0],
                    },
                    table_texture([1, 1, 1], &[[0.0; 4]]),
                    nodes_buffer(&all),
                    luts,
                )
            }
        };
        let uniform = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("shade"),
            contents: bytemuck::bytes_of(&uni),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let luts = nodes_buffer(&luts);
        Ok(ShadeResources {
            uniform,
            table,
            nodes,
            luts,
        })
    }
}
