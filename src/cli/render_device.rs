//! `tetkit render --device cpu|gpu|auto`: picks the device and runs the GPU frame loop.

use anyhow::{bail, Result};
use std::path::Path;
use std::time::Instant;

use super::render::{order_for, SortChoice};
use crate::camera::Camera;
use crate::render::gpu::{GpuContext, GpuRenderer, TargetFormat};
use crate::render::pt::{Shader, View};
use crate::sort::Sorter;

/// Where projected tetrahedra run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum DeviceChoice {
    /// The CPU rasterizer (exact fixed-point coverage, parallel tiles).
    Cpu,
    /// wgpu compute + draw (fails when no adapter is found).
    Gpu,
    /// The GPU when an adapter is found, else the CPU (said on stderr).
    Auto,
}

/// The GPU renderer for `--device gpu|auto`, or None for the CPU. `auto` falls back to the CPU
/// with one line on stderr when no adapter is found or the mesh does not fit the device.
pub fn open_gpu(
    device: DeviceChoice,
    points: &[[f64; 3]],
    tets: &[[u32; 4]],
    field: &crate::render::field::Field,
    shader: &Shader,
    quiet: bool,
) -> Result<Option<GpuRenderer>> {
    if device == DeviceChoice::Cpu {
        return Ok(None);
    }
    let made = GpuContext::new().and_then(|ctx| {
        if ctx.format == TargetFormat::Rgba16Float && !quiet {
            eprintln!(
                "tetkit: GPU '{}' cannot blend Rgba32Float targets; compositing in Rgba16Float",
                ctx.info.name
            );
        }
        GpuRenderer::new(ctx, points, tets, field, shader)
    });
    match (made, device) {
        (Ok(r), _) => Ok(Some(r)),
        (Err(e), DeviceChoice::Auto) => {
            eprintln!("tetkit: --device auto: {e:#}; rendering on the CPU");
            Ok(None)
        }
        (Err(e), _) => Err(e),
    }
}

/// What the GPU frame loop needs from `render`.
pub struct GpuFrames<'a> {
    pub sorter: Option<&'a Sorter<'a>>,
    pub ntets: usize,
    pub sort: SortChoice,
    pub cam0: Camera,
    pub step: f64,
    pub frames: usize,
    pub size: (u32, u32),
    pub background: [f32; 3],
}

/// Scene bodies render on the CPU: `--device gpu` refuses them, `auto` says so.
pub fn scene_on_cpu(device: DeviceChoice, bodies: usize) -> Result<()> {
    match device {
        DeviceChoice::Cpu => Ok(()),
        DeviceChoice::Gpu => {
            bail!("--device gpu: a scene with {bodies} bodies renders on the CPU only (--device cpu or auto)")
        }
        DeviceChoice::Auto => {
            eprintln!("tetkit: --device auto: scene bodies render on the CPU");
            Ok(())
        }
    }
}

/// Renders every frame on the GPU (the mesh stays resident; each frame uploads the camera and the
/// order) and writes the PNGs; returns one summary line per frame and the frame times.
pub fn gpu_frames(
    gpu: &mut GpuRenderer,
    job: &GpuFrames,
    path: impl Fn(usize) -> std::path::PathBuf,
    mut each: impl FnMut(),
) -> Result<(Vec<String>, Vec<f64>)> {
    let mut lines = vec![format!("GPU: {}", gpu.context().describe())];
    let mut frame_times = Vec::new();
    for i in 0..job.frames {
        let mut cam = job.cam0;
        cam.azimuth(job.step * i as f64);
        let t = Instant::now();
        let (order, sort_s) = order_for(job.sorter, job.ntets, &cam, job.sort);
        let view = View::new(&cam, job.size.0, job.size.1);
        let (img, stats, times) = gpu.render(&view, &order)?;
        let frame_s = t.elapsed().as_secs_f64();
        frame_times.push(frame_s);
        let out = path(i);
        write_png(&img, &out, job.background)?;
        lines.push(format!(
            "frame {i}: {frame_s:.3} s (sort {sort_s:.3}, upload {:.3}, draw {:.3}, readback {:.3}); classes 1/2/3/4/flat {:?}, clipped {}",
            times.upload, times.draw, times.readback, stats.class, stats.clipped
        ));
        each();
    }
    Ok((lines, frame_times))
}

fn write_png(img: &crate::render::Image, out: &Path, bg: [f32; 3]) -> Result<()> {
    if img.has_nan() {
        bail!("{}: the GPU image has NaN pixels", out.display());
    }
    img.write_png(out, bg)
}
