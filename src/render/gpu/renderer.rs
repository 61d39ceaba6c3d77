//! One GPU frame: upload camera and order, classify and expand in compute passes, draw, read back.

use anyhow::{anyhow, bail, Result};
use std::time::Instant;
use wgpu::util::DeviceExt;

use super::context::GpuContext;
use super::pipelines::{Pipelines, INDICES_PER_TET, WORKGROUP};
use super::readback::{map_read, Target};
use super::resources::{sampled_texture, MeshBuffers, ShadeResources};
use super::scene::{crossings, SceneTables};
use crate::camera::Camera;
use crate::render::cut::SceneLook;
use crate::render::field::Field;
use crate::render::image::Image;
use crate::render::pt::{PtStats, Shader, View};

/// Per-frame timings in seconds; each stage waits for the device before the next starts.
#[derive(Clone, Copy, Debug, Default)]
pub struct GpuTimes {
    /// Camera uniform and order written and flushed to the device.
    pub upload: f64,
    /// Classification, index expansion and the draw.
    pub draw: f64,
    /// Copy of the target into host memory and unpacking into an image.
    pub readback: f64,
}

/// What a scene frame computed besides the image.
#[derive(Clone, Debug, Default)]
pub struct SceneFrameStats {
    /// Seconds for the per-pixel crossings and their upload set-up (on the CPU).
    pub crossings_s: f64,
    pub pixels_with_crossings: u64,
    /// Region codes present where the mesh is.
    pub codes: Vec<u8>,
    /// Transfer-function tables stacked for the frame.
    pub tables: usize,
    /// Most crossings on one pixel's ray.
    pub layers: u32,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct FrameUniform {
    eye: [f32; 4],
    r: [f32; 4],
    u: [f32; 4],
    f: [f32; 4],
    size: [f32; 4],
    flags: [u32; 4],
}

/// A mesh, field and shading mode resident on the GPU, rendering frames of any camera and order.
pub struct GpuRenderer {
    ctx: GpuContext,
    pipes: Pipelines,
    mesh: MeshBuffers,
    shade: ShadeResources,
    /// Stacked tables of the scene functions last used, by their slots.
    scene_shade: Option<(Vec<u16>, ShadeResources)>,
    frame: wgpu::Buffer,
    count: wgpu::Buffer,
    counts_read: wgpu::Buffer,
    classify_bg: wgpu::BindGroup,
    expand_bg: wgpu::BindGroup,
    draw_bg: wgpu::BindGroup,
    target: Option<Target>,
}

/// Workgroup grid covering `n` invocations (x at most 65535 groups).
fn groups(n: u32) -> (u32, u32) {
    let g = n.div_ceil(WORKGROUP).max(1);
    let x = g.min(65535);
    (x, g.div_ceil(x))
}

impl GpuRenderer {
    /// Uploads the mesh, field and shading tables once.
    pub fn new(
        ctx: GpuContext,
        points: &[[f64; 3]],
        tets: &[[u32; 4]],
        field: &Field,
        shader: &Shader,
    ) -> Result<GpuRenderer> {
        let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let oom = ctx.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let pipes = Pipelines::new(&ctx);
        let mesh = MeshBuffers::new(&ctx, points, tets, field)?;
        let shade = ShadeResources::new(&ctx, shader)?;
        let dev = &ctx.device;
        let frame = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame"),
            size: std::mem::size_of::<FrameUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let count = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("order length"),
            contents: bytemuck::cast_slice(&[0u32; 4]),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let counts_read = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("class counts readback"),
            size: 32,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind =
            |layout, label, res: &[wgpu::BindingResource]| bind_group(dev, layout, label, res);
        let classify_bg = bind(
            &pipes.classify_layout,
            "classify",
            &[
                frame.as_entire_binding(),
                mesh.points.as_entire_binding(),
                mesh.tets.as_entire_binding(),
                mesh.scalars.as_entire_binding(),
                mesh.verts.as_entire_binding(),
                mesh.counts.as_entire_binding(),
            ],
        );
        let expand_bg = bind(
            &pipes.expand_layout,
            "expand",
            &[
                count.as_entire_binding(),
                mesh.order.as_entire_binding(),
                mesh.indices.as_entire_binding(),
            ],
        );
        let table_view = shade.table.create_view(&Default::default());
        let draw_bg = bind(
            &pipes.draw_layout,
            "draw",
            &[
                frame.as_entire_binding(),
                shade.uniform.as_entire_binding(),
                wgpu::BindingResource::TextureView(&table_view),
                shade.nodes.as_entire_binding(),
                shade.luts.as_entire_binding(),
            ],
        );
        if let Some(e) = pollster::block_on(oom.pop()) {
            bail!(
                "GPU '{}': out of memory uploading the mesh: {e}",
                ctx.info.name
            );
        }
        if let Some(e) = pollster::block_on(scope.pop()) {
            bail!("GPU '{}': setting up: {e}", ctx.info.name);
        }
        Ok(GpuRenderer {
            ctx,
            pipes,
            mesh,
            shade,
            scene_shade: None,
            frame,
            count,
            counts_read,
            classify_bg,
            expand_bg,
            draw_bg,
            target: None,
        })
    }

    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    /// Renders the tets in `order` (front to back) as seen by `view`. Returns the image, the
    /// projection-class counts (as the CPU path counts them) and the stage times.
    pub fn render(&mut self, view: &View, order: &[u32]) -> Result<(Image, PtStats, GpuTimes)> {
        self.frame(view, order, None)
    }

    /// Renders with a scene's bodies: per-pixel crossings (on the CPU, as the CPU path computes
    /// them) as a texture, each fragment split at its pixel's crossings and each piece shaded
    /// with its region's transfer function. The bodies' tables are built on first use.
    pub fn render_scene(
        &mut self,
        view: &View,
        cam: &Camera,
        order: &[u32],
        look: &SceneLook,
        tables: &mut SceneTables,
    ) -> Result<(Image, PtStats, GpuTimes, SceneFrameStats)> {
        let t0 = Instant::now();
        let cr = crossings(view, cam, look, &self.mesh.bounds);
        let (need, slots, shaders) = tables.resolve(look, &cr.seen)?;
        let ctx = &self.ctx;
        if !shaders.is_empty() && self.scene_shade.as_ref().is_none_or(|(k, _)| *k != need) {
            self.scene_shade = Some((need.clone(), ShadeResources::stack(ctx, &shaders)?));
        }
        let shade = match &self.scene_shade {
            Some((k, s)) if *k == need => s,
            // Everything present is cut: no lookup happens.
            _ => &self.shade,
        };
        let max_layers = ctx.limits.max_texture_array_layers;
        if cr.layers > max_layers {
            bail!(
                "GPU '{}': {} body crossings on one pixel ray, over the adapter's {max_layers} texture layers",
                ctx.info.name,
                cr.layers - 1
            );
        }
        let size = wgpu::Extent3d {
            width: view.width,
            height: view.height,
            depth_or_array_layers: cr.layers,
        };
        let tex = sampled_texture(
            ctx,
            "body crossings",
            size,
            wgpu::TextureDimension::D2,
            wgpu::TextureFormat::Rg32Float,
            bytemuck::cast_slice(&cr.texels),
            view.width * 8,
        );
        let tex_view = tex.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let slot_buf = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("region slots"),
                contents: bytemuck::cast_slice(&slots),
                usage: wgpu::BufferUsages::STORAGE,
            });
        let table_view = shade.table.create_view(&Default::default());
        let res = [
            self.frame.as_entire_binding(),
            shade.uniform.as_entire_binding(),
            wgpu::BindingResource::TextureView(&table_view),
            shade.nodes.as_entire_binding(),
            shade.luts.as_entire_binding(),
            wgpu::BindingResource::TextureView(&tex_view),
            slot_buf.as_entire_binding(),
        ];
        let bg = bind_group(
            &ctx.device,
            &self.pipes.draw_scene_layout,
            "draw scene",
            &res,
        );
        let crossings_s = t0.elapsed().as_secs_f64();
        let (img, stats, times) = self.frame(view, order, Some(&bg))?;
        Ok((
            img,
            stats,
            times,
            SceneFrameStats {
                crossings_s,
                pixels_with_crossings: cr.traced,
                codes: (0..256).filter(|&c| cr.seen[c]).map(|c| c as u8).collect(),
                tables: need.len(),
                layers: cr.layers - 1,
            },
        ))
    }

    fn frame(
        &mut self,
        view: &View,
        order: &[u32],
        scene: Option<&wgpu::BindGroup>,
    ) -> Result<(Image, PtStats, GpuTimes)> {
        let n = self.mesh.ntets;
        if order.len() > n as usize {
            bail!("order of {} tets for a mesh of {n}", order.len());
        }
        if let Some(&bad) = order.iter().find(|&&t| t >= n) {
            bail!("order names tet {bad} of a mesh of {n}");
        }
        if self
            .target
            .as_ref()
            .is_none_or(|t| t.width != view.width || t.height != view.height)
        {
            self.target = Some(Target::new(&self.ctx, view.width, view.height)?);
        }
        let Some(target) = self.target.as_ref() else {
            bail!("no render target");
        };
        let ctx = &self.ctx;
        let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let wait = |what: &str| {
            ctx.device
                .poll(wgpu::PollType::wait_indefinitely())
                .map(|_| ())
                .map_err(|e| anyhow!("GPU '{}': {what}: {e}", ctx.info.name))
        };

        let t0 = Instant::now();
        let c = self.mesh.centre;
        let rel = |p: [f64; 3]| {
            [
                (p[0] - c[0]) as f32,
                (p[1] - c[1]) as f32,
                (p[2] - c[2]) as f32,
                0.0,
            ]
        };
        let dir = |d: [f64; 3]| [d[0] as f32, d[1] as f32, d[2] as f32, 0.0];
        let mut eye = rel(view.eye);
        // The near depth rides in the eye's unused w (classify.wgsl).
        eye[3] = view.near as f32;
        let uni = FrameUniform {
            eye,
            r: dir(view.r),
            u: dir(view.u),
            f: dir(view.f),
            size: [
                view.width as f32,
                view.height as f32,
                view.scale as f32,
                view.aspect as f32,
            ],
            flags: [n, view.parallel as u32, self.mesh.cell_field as u32, 0],
        };
        let q = &ctx.queue;
        q.write_buffer(&self.frame, 0, bytemuck::bytes_of(&uni));
        q.write_buffer(
            &self.count,
            0,
            bytemuck::cast_slice(&[order.len() as u32, 0, 0, 0]),
        );
        q.write_buffer(&self.mesh.counts, 0, &[0u8; 32]);
        if !order.is_empty() {
            q.write_buffer(&self.mesh.order, 0, bytemuck::cast_slice(order));
        }
        q.submit([]);
        wait("uploading the order")?;
        let t1 = Instant::now();

        let mut enc = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        {
            let mut cp = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("classify"),
                timestamp_writes: None,
            });
            cp.set_pipeline(&self.pipes.classify);
            cp.set_bind_group(0, &self.classify_bg, &[]);
            let (gx, gy) = groups(n);
            cp.dispatch_workgroups(gx, gy, 1);
            if !order.is_empty() {
                cp.set_pipeline(&self.pipes.expand);
                cp.set_bind_group(0, &self.expand_bg, &[]);
                let (gx, gy) = groups(order.len() as u32);
                cp.dispatch_workgroups(gx, gy, 1);
            }
        }
        {
            let mut rp = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("draw"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target.view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            if !order.is_empty() {
                match scene {
                    Some(bg) => {
                        rp.set_pipeline(&self.pipes.draw_scene);
                        rp.set_bind_group(0, bg, &[]);
                    }
                    None => {
                        rp.set_pipeline(&self.pipes.draw);
                        rp.set_bind_group(0, &self.draw_bg, &[]);
                    }
                }
                rp.set_vertex_buffer(0, self.mesh.verts.slice(..));
                rp.set_index_buffer(self.mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                rp.draw_indexed(0..(order.len() as u64 * INDICES_PER_TET) as u32, 0, 0..1);
            }
        }
        enc.copy_buffer_to_buffer(&self.mesh.counts, 0, &self.counts_read, 0, 32);
        q.submit([enc.finish()]);
        wait("drawing")?;
        let t2 = Instant::now();

        let mut enc = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("readback"),
            });
        target.copy(&mut enc);
        q.submit([enc.finish()]);
        let img = target.read(ctx)?;
        let counts = map_read(ctx, &self.counts_read)?;
        self.counts_read.unmap();
        let t3 = Instant::now();
        if let Some(e) = pollster::block_on(scope.pop()) {
            bail!("GPU '{}': rendering: {e}", ctx.info.name);
        }
        let c: Vec<u32> = counts
            .chunks_exact(4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        let stats = PtStats {
            class: [c[0], c[1], c[2], c[3], c[4]].map(u64::from),
            clipped: c[5] as u64,
            per_pixel: 0,
            fragments: 0,
            hidden: 0,
            clear: 0,
        };
        Ok((
            img,
            stats,
            GpuTimes {
                upload: (t1 - t0).as_secs_f64(),
                draw: (t2 - t1).as_secs_f64(),
                readback: (t3 - t2).as_secs_f64(),
            },
        ))
    }
}

/// A bind group whose entries are `res` at bindings 0, 1, 2, ... in order.
fn bind_group(
    dev: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    label: &str,
    res: &[wgpu::BindingResource],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = res
        .iter()
        .enumerate()
        .map(|(i, r)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: r.clone(),
        })
        .collect();
    dev.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}
