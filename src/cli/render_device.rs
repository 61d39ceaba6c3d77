//! `tetkit render --device cpu|gpu|auto`: picks the device and runs the GPU frame loop.

use anyhow::{bail, Result};
use std::path::Path;
use std::time::Instant;

use super::render::{frame_path, order_for, MethodChoice, RenderArgs, Session, SortChoice};
use crate::camera::Camera;
use crate::render::cut::SceneLook;
use crate::render::gpu::{GpuContext, GpuRenderer, SceneTables, TargetFormat};
use crate::render::prepare;
use crate::render::pt::{Shader, View};
use crate::scene::{code_string, Scene};
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
    session: &Session,
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
        let m = &session.mesh;
        GpuRenderer::new(ctx, &m.points, &m.tets, &session.field, shader)
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
    pub step: super::render::Orbit,
    pub frames: usize,
    pub size: (u32, u32),
    pub background: [f32; 3],
}

/// A scene with bodies on the GPU (`--device gpu`, or `auto` with an adapter): per-pixel body
/// crossings from the CPU as a texture, fragments split in the fragment shader. Returns false
/// when the CPU should render it (`cpu`, or `auto` without an adapter).
pub fn scene_gpu(
    args: &RenderArgs,
    session: &Session,
    scene: &Scene,
    cam0: Camera,
    step: super::render::Orbit,
) -> Result<bool> {
    let look = &args.look;
    match (args.device, args.method) {
        (DeviceChoice::Cpu, _) => return Ok(false),
        (DeviceChoice::Gpu, MethodChoice::Raycast) => {
            bail!("--method raycast runs on the CPU only (--device gpu draws projected tetrahedra)")
        }
        (DeviceChoice::Auto, MethodChoice::Raycast) => return Ok(false),
        _ => {}
    }
    let shader = prepare::shader(&session.tf, args.integration, session.table, session.lmax);
    let Some(mut gpu) = open_gpu(args.device, session, &shader, look.quiet)? else {
        return Ok(false);
    };
    let m = &session.mesh;
    let mut sl = SceneLook::new(scene, &session.tf, &session.base)?;
    sl.culling = !args.no_culling;
    let sorter = match args.sort {
        SortChoice::None => None,
        _ => Some(session.sorter()?),
    };
    let mut tables = SceneTables::new(args.integration, session.table, session.lmax);
    let frames = args.orbit.unwrap_or(1);
    let (w, h) = look.size;
    let bits = scene.bodies.len();
    let mut lines = vec![
        format!(
            "{} tets, array '{}', read {:.3} s; scene {}: {} bodies, culling {}",
            m.tets.len(),
            session.field_name,
            session.read_s,
            scene.file.display(),
            bits,
            if sl.culling { "on" } else { "off" }
        ),
        format!("GPU: {}", gpu.context().describe()),
    ];
    let mut reports = Vec::new();
    for i in 0..frames {
        let cam = super::render::orbit_camera(&cam0, &step, i);
        let t = Instant::now();
        let (order, sort_s) = order_for(sorter.as_ref(), m.tets.len(), &cam, args.sort);
        let view = View::new(&cam, w, h);
        let (img, _, times, st) = gpu.render_scene(&view, &cam, &order, &sl, &mut tables)?;
        let frame_s = t.elapsed().as_secs_f64();
        write_png(&img, &frame_path(&args.output, i, frames), look.background)?;
        let codes: Vec<String> = st.codes.iter().map(|&c| code_string(c, bits)).collect();
        lines.push(format!(
            "frame {i}: {frame_s:.3} s (sort {sort_s:.3}, crossings {:.3}, upload {:.3}, draw {:.3}, readback {:.3}); codes {codes:?}, {} tables; pixels with crossings {}, at most {} per pixel",
            st.crossings_s, times.upload, times.draw, times.readback, st.tables, st.pixels_with_crossings, st.layers
        ));
        reports.push(serde_json::json!({
            "frame": i,
            "seconds": frame_s,
            "codes": codes,
            "tables": st.tables,
            "pixels_with_crossings": st.pixels_with_crossings,
        }));
    }
    if !look.quiet {
        for l in lines {
            eprintln!("{l}");
        }
    }
    if args.json {
        let report = serde_json::json!({
            "tets": m.tets.len(),
            "bodies": bits,
            "device": "gpu",
            "culling": sl.culling,
            "frames": reports,
        });
        println!("{}", serde_json::to_string_pretty(&report)?);
    }
    Ok(true)
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
        let cam = super::render::orbit_camera(&job.cam0, &job.step, i);
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
