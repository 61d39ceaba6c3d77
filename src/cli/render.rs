//! `tetkit render`: projected tetrahedra or ray-cast reference image of a tet mesh.

use anyhow::{bail, Context, Result};
use clap::Args;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::camera_args::CameraArgs;
use super::render_device::{gpu_frames, open_gpu, DeviceChoice, GpuFrames};
use crate::camera::Camera;
use crate::locate::{GridParams, Topology};
use crate::mesh::TetMesh;
use crate::render::cut::BaseLook;
use crate::render::field::Field;
use crate::render::image::{parse_color, parse_size, Image};
use crate::render::integrate::{Integration, PreintTable};
use crate::render::prepare::{self, TableSize};
use crate::render::pt::{self, Shader, View};
use crate::render::raycast::RayCaster;
use crate::render::transfer::{named_colormap, read_preset, OpacitySpec, TransferFunction};
use crate::scene::TransferSpec;
use crate::sort::{Direction, Sorter};

/// Which visibility order PT composites in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SortChoice {
    /// The mesh's own cell order (no sort).
    None,
    /// Centroid depth (VTK's approximate sort).
    Centroid,
    /// Face adjacency over the whole mesh (MPVO).
    Mpvo,
    /// The K-D tree exact sort (leaves from the input's tree, else one leaf).
    Kd,
}

impl SortChoice {
    pub const ALL: [SortChoice; 4] = [
        SortChoice::None,
        SortChoice::Centroid,
        SortChoice::Mpvo,
        SortChoice::Kd,
    ];
    pub fn name(self) -> &'static str {
        match self {
            SortChoice::None => "none",
            SortChoice::Centroid => "centroid",
            SortChoice::Mpvo => "mpvo",
            SortChoice::Kd => "kd",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum MethodChoice {
    /// Projected tetrahedra in visibility order.
    Pt,
    /// The exact reference: per-pixel ray integration through the mesh.
    Raycast,
}

/// Segment integration of `--method raycast`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum RayIntegration {
    /// Exact through every transfer-function node (the reference).
    Exact,
    /// Trilinear lookup in the (Sf, Sb, l) table of `--table`.
    Preintegrated,
}

/// Transfer-function and image options shared by `render` and `tradeoff`.
#[derive(Args, Debug, Clone)]
pub struct LookArgs {
    /// Image size WIDTHxHEIGHT.
    #[arg(long, default_value = "512x512", value_parser = parse_size_arg)]
    pub size: (u32, u32),
    /// Array to render (point data, else cell data; `cell:NAME` for a cell array that shares
    /// its name with a point array; vectors by magnitude, or one component: `v:X`, `v:0`,
    /// `v:Magnitude`, a component's name). Default: active point scalars, else
    /// the first numeric array.
    #[arg(long, value_name = "NAME")]
    pub scalar: Option<String>,
    /// Colormap name (cool-to-warm, viridis, inferno, ...) or a ParaView preset .json
    /// (default: the scene's [transfer], else cool-to-warm).
    #[arg(long, value_name = "NAME|preset.json")]
    pub colormap: Option<String>,
    /// Opacity: a constant (0.3), `ramp`, `ramp:A:B`, or points `t:a,t:a,...` with t in [0, 1]
    /// across the scalar range. Default: the preset's opacity, else `ramp`.
    #[arg(long, value_name = "SPEC")]
    pub opacity: Option<String>,
    /// Scalar range MIN,MAX the colormap spans (default: the array's range).
    #[arg(long, value_name = "MIN,MAX", allow_hyphen_values = true)]
    pub range: Option<String>,
    /// ParaView's scalar opacity unit distance: the thickness at which a constant scalar reaches
    /// its opacity (default: a fifth of the bounding-box diagonal).
    #[arg(long, value_name = "D")]
    pub unit_distance: Option<f64>,
    /// Transfer-function nodes (piecewise linear between them).
    #[arg(long, default_value_t = 64, value_name = "K", value_parser = parse_tf_nodes_arg)]
    pub tf_nodes: usize,
    /// Pre-integration table size SCALARxLENGTH [default: 128x32, with more length steps (up
    /// to 256) where a step of 32 would be optically thick].
    #[arg(long, value_name = "SxL")]
    pub table: Option<TableSize>,
    /// How PT shares a frame among threads: screen tiles honouring the global order, or runs of
    /// the order in separate buffers composited in order.
    #[arg(long, value_enum, default_value = "tiles")]
    pub pt_schedule: pt::Schedule,
    /// Background: black, white, #rrggbb or r,g,b in [0, 1].
    #[arg(long, default_value = "black", value_parser = parse_color_arg)]
    pub background: [f32; 3],
    /// No progress bar or summary on stderr.
    #[arg(long, short)]
    pub quiet: bool,
}

fn parse_range(s: &str) -> Result<[f64; 2]> {
    let parts: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| anyhow::anyhow!("--range '{s}': expected MIN,MAX"))?;
    if parts.len() != 2 || parts.iter().any(|v| !v.is_finite()) {
        bail!("--range '{s}': expected two finite numbers MIN,MAX");
    }
    Ok([parts[0], parts[1]])
}

fn parse_size_arg(s: &str) -> std::result::Result<(u32, u32), String> {
    parse_size(s).map_err(|e| e.to_string())
}

/// Every node costs memory in each transfer function's tables (24 GB for 1e9 nodes, which used
/// to abort the process), and past a few thousand no 8-bit image changes.
fn parse_tf_nodes_arg(s: &str) -> std::result::Result<usize, String> {
    s.trim()
        .parse::<usize>()
        .ok()
        .filter(|k| (2..=4096).contains(k))
        .ok_or_else(|| format!("--tf-nodes '{s}': expected a count between 2 and 4096"))
}

fn parse_color_arg(s: &str) -> std::result::Result<[f32; 3], String> {
    parse_color(s).map_err(|e| e.to_string())
}

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Tet mesh (.vtu, .pvtu, .vtk, .node/.ele, .mesh, .msh, .exo, .vtkhdf, .vtm, .pvd, .vti/.vtr/.vts), or - for stdin.
    pub input: PathBuf,
    /// Output PNG (with --orbit N: OUT_0000.png ... numbered frames).
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub camera: CameraArgs,
    #[command(flatten)]
    pub look: LookArgs,
    /// Visibility order for PT.
    #[arg(long, value_enum, default_value = "kd")]
    pub sort: SortChoice,
    /// Ray integration per PT fragment.
    #[arg(long, value_enum, default_value = "preintegrated")]
    pub integration: Integration,
    /// Projected tetrahedra, or the exact ray-cast reference.
    #[arg(long, value_enum, default_value = "pt")]
    pub method: MethodChoice,
    /// How the ray caster integrates each segment: exactly (the reference), or by the
    /// pre-integration table's lookup as VTK's ray caster does (faster, approximate).
    #[arg(long, value_enum, default_value = "exact")]
    pub ray_integration: RayIntegration,
    /// Render N frames turning about the focal point like a turntable (azimuth 360/N each,
    /// about the view-up before --elevation and --roll, so frame i is the single render at
    /// --azimuth plus i steps), reusing adjacency, grid and tables.
    #[arg(long, value_name = "N")]
    pub orbit: Option<usize>,
    /// Degrees between orbit frames (default 360/N; needs --orbit).
    #[arg(
        long,
        value_name = "DEG",
        allow_hyphen_values = true,
        requires = "orbit"
    )]
    pub orbit_step: Option<f64>,
    /// Where PT runs: cpu, gpu (wgpu; an error without an adapter) or auto (the GPU when an
    /// adapter is found, else the CPU).
    #[arg(long, value_enum, default_value = "cpu")]
    pub device: DeviceChoice,
    /// Scene file (TOML): cutting bodies and per-region transfer functions, and optionally the
    /// camera and default transfer function (command-line options override the scene's).
    #[arg(long, value_name = "SCENE.toml")]
    pub scene: Option<PathBuf>,
    /// Test every body at every pixel (no bounding-box culling), to measure what culling saves.
    #[arg(long)]
    pub no_culling: bool,
    /// Print a JSON report on stdout: timings and, with a scene, the region codes before and
    /// after merging.
    #[arg(long)]
    pub json: bool,
}

/// A progress bar on stderr that appears only once work has run for a second, and never with
/// --quiet or when stderr is not a terminal.
pub struct Progress {
    bar: Option<indicatif::ProgressBar>,
    start: Instant,
    shown: bool,
}

impl Progress {
    pub fn new(quiet: bool, len: u64, what: &str) -> Progress {
        let bar = (!quiet && std::io::stderr().is_terminal()).then(|| {
            let b = indicatif::ProgressBar::with_draw_target(
                Some(len),
                indicatif::ProgressDrawTarget::hidden(),
            );
            if let Ok(style) = indicatif::ProgressStyle::with_template(
                "{prefix} [{bar:30}] {pos}/{len} {msg} ({elapsed})",
            ) {
                b.set_style(style.progress_chars("=> "));
            }
            b.set_prefix(what.to_string());
            b
        });
        Progress {
            bar,
            start: Instant::now(),
            shown: false,
        }
    }

    pub fn step(&mut self, msg: &str) {
        if let Some(b) = &self.bar {
            if !self.shown && self.start.elapsed().as_secs_f64() > 1.0 {
                b.set_draw_target(indicatif::ProgressDrawTarget::stderr());
                self.shown = true;
            }
            b.set_message(msg.to_string());
            b.inc(1);
        }
    }

    /// Clears the bar, then prints the summary lines on stderr unless `quiet`.
    pub fn finish_with(&self, quiet: bool, summary: Vec<String>) {
        self.finish();
        if !quiet {
            for line in summary {
                eprintln!("{line}");
            }
        }
    }

    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

/// Everything a render of one mesh reuses between frames.
pub struct Session {
    pub mesh: TetMesh,
    pub field_name: String,
    pub field: Field,
    pub tf: TransferFunction,
    /// What `tf` was built from, for bodies' transfer functions to inherit.
    pub base: BaseLook,
    /// Size of the pre-integration tables: `--table`, or the default fitted to the mesh and
    /// transfer function ([`prepare::table_size`]).
    pub table: TableSize,
    /// Length axis of the pre-integration tables ([`prepare::table_length`]).
    pub lmax: f64,
    /// What the table's scalar axis smooths, where the transfer function is steep (printed
    /// when the table is used).
    pub table_note: Option<String>,
    /// Subtracted from `field` and from every transfer function's scalars
    /// ([`crate::render::field::scalar_offset`]); 0 for most fields.
    pub scalar_offset: f64,
    /// Then multiplied with the field and the transfer functions' scalars
    /// ([`crate::render::field::scalar_scale`]); 1 for most fields.
    pub scalar_scale: f64,
    pub read_s: f64,
    pub schedule: pt::Schedule,
    /// The tets with coincident points welded ([`TetMesh::welded_tets`]; `None` when no points
    /// coincide), computed once for both the sorter and the ray caster's topology.
    welded: std::sync::OnceLock<Option<Vec<[u32; 4]>>>,
}

impl Session {
    pub fn open(input: &Path, look: &LookArgs) -> Result<Session> {
        Session::open_with(input, look, None)
    }

    /// [`Session::open`] with a scene's default transfer function filling what the command line
    /// leaves unset.
    pub fn open_with(
        input: &Path,
        look: &LookArgs,
        scene_tf: Option<&TransferSpec>,
    ) -> Result<Session> {
        let t0 = Instant::now();
        let grid = super::read_input(input)?;
        // Tets kept, other 3-D cells tetrahedralized, lower cells dropped (said on stderr).
        let (mut mesh, _, notes) =
            crate::partition::input::tets_of(&grid, &input.display().to_string())?;
        if !look.quiet {
            for n in notes {
                eprintln!("tetkit: {n}");
            }
        }
        if mesh.tets.is_empty() {
            bail!("{}: no tets to render", input.display());
        }
        let (field_name, mut field) = Field::select(&mesh, look.scalar.as_deref())
            .with_context(|| format!("{}", input.display()))?;
        field
            .check(&mesh, &field_name)
            .with_context(|| format!("{}", input.display()))?;
        let left_out = field.drop_non_finite(&mut mesh);
        if left_out > 0 {
            if mesh.tets.is_empty() {
                bail!(
                    "{}: every tet reads a NaN or infinite value of '{field_name}': nothing to draw",
                    input.display()
                );
            }
            if !look.quiet {
                eprintln!(
                    "tetkit: {}: {left_out} tets read a NaN or infinite value of '{field_name}' and are left out",
                    input.display()
                );
            }
        }
        let range = match &look.range {
            Some(r) => {
                let v = parse_range(r)?;
                if v[0].partial_cmp(&v[1]) != Some(std::cmp::Ordering::Less) {
                    bail!("--range {r}: MIN must be below MAX");
                }
                v
            }
            None => match scene_tf.and_then(|t| t.range) {
                Some(r) => r,
                None => prepare::auto_range(&field),
            },
        };
        let colors = match (&look.colormap, scene_tf) {
            (Some(c), _) if c.to_ascii_lowercase().ends_with(".json") => read_preset(Path::new(c))?,
            (Some(c), _) => named_colormap(c)?,
            (
                None,
                Some(TransferSpec {
                    colormap: Some(c), ..
                }),
            ) => named_colormap(c)?,
            (
                None,
                Some(TransferSpec {
                    preset: Some(p), ..
                }),
            ) => read_preset(p)?,
            (None, _) => named_colormap("cool-to-warm")?,
        };
        let opacity = match (&look.opacity, scene_tf) {
            (Some(o), _) => Some(OpacitySpec::parse(o)?),
            (None, Some(t)) if !t.opacity.is_empty() => {
                let span = range[1] - range[0];
                Some(OpacitySpec::Points(
                    t.opacity
                        .iter()
                        .map(|p| ((p[0] - range[0]) / span, p[1]))
                        .collect(),
                ))
            }
            (None, _) => None,
        };
        let unit = match look.unit_distance {
            Some(d) if d > 0.0 && d.is_finite() => d,
            Some(d) => bail!("--unit-distance {d}: must be positive and finite"),
            None => match scene_tf.and_then(|t| t.unit_distance) {
                Some(d) => d,
                None => prepare::default_unit_distance(&mesh),
            },
        };
        // Far from zero compared with its range, or beyond f32's reach, the field is drawn
        // shifted towards zero and scaled by a power of two (PT keeps scalars in f32); the
        // scene's transfer functions move with it (`run`).
        let scalar_offset = crate::render::field::scalar_offset(range);
        let scalar_scale = crate::render::field::scalar_scale(range.map(|x| x - scalar_offset));
        let range = if scalar_offset != 0.0 || scalar_scale != 1.0 {
            field.rescale(scalar_offset, scalar_scale);
            range.map(|x| (x - scalar_offset) * scalar_scale)
        } else {
            range
        };
        let tf = TransferFunction::build(&colors, opacity.as_ref(), range, unit, look.tf_nodes)?;
        let base = BaseLook {
            colors,
            range,
            unit_distance: unit,
            nodes: look.tf_nodes,
        };
        let (table, lmax, table_note) = prepare::table_plan(&mesh, &tf, look.table);
        Ok(Session {
            mesh,
            field_name,
            field,
            tf,
            base,
            table,
            lmax,
            table_note,
            scalar_offset,
            scalar_scale,
            read_s: t0.elapsed().as_secs_f64(),
            schedule: look.pt_schedule,
            welded: std::sync::OnceLock::new(),
        })
    }

    /// The ray caster's face adjacency, which the caster borrows (so the caller keeps it); with
    /// coincident points welded ([`TetMesh::welded_tets`]), so the walk crosses the doubled
    /// faces of an unwelded mesh instead of re-entering through the grid at each (5x slower on
    /// a per-element mesh of 8,640 tets, same image).
    pub fn topology(&self) -> Topology {
        let topo = Topology::build(self.welded().unwrap_or(&self.mesh.tets));
        super::sort::warn_nonmanifold(
            topo.nonmanifold,
            "the ray caster takes them as boundary faces and its walks there are not exact",
        );
        topo
    }

    /// [`TetMesh::welded_tets`] of this session's mesh, computed on first use.
    fn welded(&self) -> Option<&[[u32; 4]]> {
        self.welded
            .get_or_init(|| self.mesh.welded_tets())
            .as_deref()
    }

    /// The ray caster (entry and locator grids) over this session's mesh and field.
    pub fn raycaster<'a>(&'a self, topo: &'a Topology) -> RayCaster<'a> {
        RayCaster::new(
            &self.mesh.points,
            &self.mesh.tets,
            &self.field,
            topo,
            GridParams::default(),
        )
    }

    pub fn bounds_camera(&self, args: &CameraArgs) -> Result<Camera> {
        args.camera(&self.mesh.bounds())
    }

    /// The sorter (adjacency, leaves from the input's K-D tree when it carries one).
    pub fn sorter(&self) -> Result<Sorter<'_>> {
        let tree = crate::partition::KdTree::from_field_data(&self.mesh.field_data)?;
        let sorter = Sorter::with_welded(&self.mesh, tree.as_ref(), self.welded())?;
        super::sort::note_nonmanifold(&sorter);
        Ok(sorter)
    }
}

/// A front-to-back order for PT.
pub fn order_for(
    sorter: Option<&Sorter>,
    n: usize,
    cam: &Camera,
    sort: SortChoice,
) -> (Vec<u32>, f64) {
    let t0 = Instant::now();
    let method = match sort {
        SortChoice::None => return ((0..n as u32).collect(), 0.0),
        SortChoice::Centroid => crate::sort::Method::Centroid,
        SortChoice::Mpvo => crate::sort::Method::Mpvo,
        SortChoice::Kd => crate::sort::Method::Kd,
    };
    let Some(s) = sorter else {
        return ((0..n as u32).collect(), 0.0);
    };
    let o = s.order(cam, method, Direction::FrontToBack);
    (o.order, t0.elapsed().as_secs_f64())
}

pub fn frame_path(out: &Path, i: usize, n: usize) -> PathBuf {
    if n <= 1 {
        return out.to_path_buf();
    }
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "frame".into());
    let ext = out
        .extension()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "png".into());
    out.with_file_name(format!("{stem}_{i:04}.{ext}"))
}

pub fn run(args: &RenderArgs) -> Result<()> {
    // PNG is the only image written: a .jpg or .tif name would get PNG bytes under a wrong name.
    if let Some(ext) = args.output.extension() {
        if !ext.eq_ignore_ascii_case("png") {
            bail!(
                "{}: render writes PNG images; name the output .png",
                args.output.display()
            );
        }
    }
    let look = &args.look;
    let frames = args.orbit.unwrap_or(1);
    if frames == 0 {
        bail!("--orbit 0: need at least one frame");
    }
    let step = args.orbit_step.unwrap_or(360.0 / frames as f64);
    if !step.is_finite() {
        bail!("--orbit-step must be finite");
    }
    let mut progress = Progress::new(look.quiet, 2 + frames as u64, "render");
    let mut scene = match &args.scene {
        Some(p) => Some(crate::scene::load(p)?),
        None => None,
    };
    let session = Session::open_with(
        &args.input,
        look,
        scene.as_ref().and_then(|s| s.transfer.as_ref()),
    )?;
    if let Some(s) = scene.as_mut() {
        s.shift_scalars(session.scalar_offset, session.scalar_scale);
    }
    progress.step("read");
    let uses_table = match args.method {
        MethodChoice::Pt => args.integration == Integration::Preintegrated,
        MethodChoice::Raycast => args.ray_integration == RayIntegration::Preintegrated,
    };
    if uses_table && scene.as_ref().is_none_or(|s| s.bodies.is_empty()) {
        if let Some(n) = &session.table_note {
            eprintln!("tetkit: note: {}: {n}", args.input.display());
        }
    }
    let cam_args = match &scene {
        Some(s) => super::render_scene::camera_args(&args.camera, s),
        None => args.camera.clone(),
    };
    let cam0 = session
        .bounds_camera(&cam_args)
        .with_context(|| match &scene {
            // The scene's [camera] filled some of it: say so, since the message names options.
            Some(s) if s.camera != crate::scene::CameraSpec::default() => format!(
                "{} (camera with the [camera] of {})",
                args.input.display(),
                s.file.display()
            ),
            _ => format!("{}", args.input.display()),
        })?;
    if cam0.parallel {
        // Parallel rays are drawn whole, from behind the mesh's box: what lies behind the
        // camera's position is drawn too, where VTK and ParaView clip at a near plane in front
        // of the camera (a new user put the eye inside a cavity and saw the whole mesh).
        let b = session.mesh.bounds();
        let dir = cam0.direction();
        let behind = (0..8).any(|k| {
            let c = [0, 1, 2].map(|a| if k >> a & 1 == 1 { b.max[a] } else { b.min[a] });
            crate::geom::dot(&crate::geom::sub(&c, &cam0.position), &dir) < 0.0
        });
        if behind && !b.is_empty() {
            eprintln!(
                "tetkit: note: {}: with --parallel every ray is drawn through the whole mesh, also where it lies behind the camera position {:?} (VTK clips at a near plane in front of the camera); use a perspective view to look from inside",
                args.input.display(),
                cam0.position
            );
        }
    }
    // The orbit turns about the view-up as it was before --elevation and --roll tilted it, so
    // frame i is the single render at azimuth + i step (a turntable, not a tumble).
    let level = CameraArgs {
        elevation: None,
        roll: None,
        ..cam_args
    };
    let step = Orbit {
        step,
        axis: session.bounds_camera(&level).map_or(cam0.up, |c| c.up),
    };
    // Bodies take their own path; a scene without bodies renders exactly as no scene.
    if let Some(s) = scene.as_ref().filter(|s| !s.bodies.is_empty()) {
        if super::render_device::scene_gpu(args, &session, s, cam0, step)? {
            return Ok(());
        }
        return super::render_scene::run(args, &session, s, cam0, step, progress);
    }
    let mut frame_times = Vec::new();
    let (w, h) = look.size;
    let t_setup = Instant::now();
    let mut summary = Vec::new();
    match args.method {
        MethodChoice::Pt => {
            let sorter = match args.sort {
                SortChoice::None => None,
                _ => Some(session.sorter()?),
            };
            let t_table = Instant::now();
            let shader =
                prepare::shader(&session.tf, args.integration, session.table, session.lmax);
            let table_s = t_table.elapsed().as_secs_f64();
            let mut gpu = open_gpu(args.device, &session, &shader, look.quiet)?;
            let setup = t_setup.elapsed().as_secs_f64();
            progress.step("setup");
            if let Some(gpu) = gpu.as_mut() {
                let job = GpuFrames {
                    sorter: sorter.as_ref(),
                    ntets: session.mesh.tets.len(),
                    sort: args.sort,
                    cam0,
                    step,
                    frames,
                    size: (w, h),
                    background: look.background,
                };
                let path = |i| frame_path(&args.output, i, frames);
                let (lines, times) = gpu_frames(gpu, &job, path, || progress.step("frame"))?;
                summary.extend(lines);
                frame_times.extend(times);
            }
            let cpu_frames = if gpu.is_some() { 0 } else { frames };
            for i in 0..cpu_frames {
                let cam = orbit_camera(&cam0, &step, i);
                let t = Instant::now();
                // The sort runs while the points are projected (see `pt::render_sorting`).
                let view = View::new(&cam, w, h);
                let (img, stats, times, sort_s) = pt::render_sorting(
                    &view,
                    &session.mesh.points,
                    &session.mesh.tets,
                    &session.field,
                    &shader,
                    session.schedule,
                    || order_for(sorter.as_ref(), session.mesh.tets.len(), &cam, args.sort),
                );
                let frame_s = t.elapsed().as_secs_f64();
                frame_times.push(frame_s);
                img.write_png(&frame_path(&args.output, i, frames), look.background)?;
                summary.push(format!(
                    "frame {i}: {frame_s:.3} s (sort {sort_s:.3}, project {:.3}, bin {:.3}, raster {:.3}); classes 1/2/3/4/flat {:?}, clipped {}, per pixel (a face nearly edge-on on a pixel centre) {}, fragments {}, hidden behind opaque blocks {}, clear (the transfer function draws nothing there) {}",
                    times.project, times.bin, times.raster, stats.class, stats.clipped, stats.per_pixel, stats.fragments, stats.hidden, stats.clear
                ));
                progress.step("frame");
            }
            summary.insert(
                0,
                format!(
                    "{} tets, array '{}', read {:.3} s, setup (adjacency, leaves, table) {setup:.3} s, of which table {table_s:.3} s{}",
                    session.mesh.tets.len(),
                    session.field_name,
                    session.read_s,
                    if args.integration == Integration::Preintegrated {
                        let t = session.table;
                        format!(" ({}x{}x{} entries)", t.scalar, t.scalar, t.length)
                    } else {
                        String::new()
                    }
                ),
            );
        }
        MethodChoice::Raycast => {
            if args.device == DeviceChoice::Gpu {
                bail!("--method raycast runs on the CPU only (--device gpu draws projected tetrahedra)");
            }
            let topo = session.topology();
            let rc = session.raycaster(&topo);
            let table = (args.ray_integration == RayIntegration::Preintegrated).then(|| {
                PreintTable::build(
                    &session.tf,
                    session.table.scalar,
                    session.table.length,
                    session.lmax * 1.0001,
                )
            });
            let setup = t_setup.elapsed().as_secs_f64();
            progress.step("setup");
            let (e, l) = (rc.entry.grid.stats, rc.locator.grid.stats);
            summary.push(format!(
                "{} tets, array '{}', read {:.3} s, setup (adjacency, grids) {setup:.3} s; entry grid over {} boundary faces: {:.2} cells and {:.2} references per face, depth {}; tet grid: {:.2} cells and {:.2} references per tet, depth {}",
                session.mesh.tets.len(),
                session.field_name,
                session.read_s,
                e.primitives,
                e.cells_per_primitive(),
                e.refs_per_primitive(),
                e.depth,
                l.cells_per_primitive(),
                l.refs_per_primitive(),
                l.depth
            ));
            for i in 0..frames {
                let cam = orbit_camera(&cam0, &step, i);
                let t = Instant::now();
                let (img, st) = match &table {
                    None => rc.render(&session.tf, &cam, w, h),
                    Some(tab) => rc.render_with(
                        &|a, b, l| tab.segment(a as f32, b as f32, l as f32).map(f64::from),
                        &cam,
                        w,
                        h,
                    ),
                };
                let frame_s = t.elapsed().as_secs_f64();
                frame_times.push(frame_s);
                img.write_png(&frame_path(&args.output, i, frames), look.background)?;
                summary.push(format!(
                    "frame {i}: {frame_s:.3} s; segments {}, re-entries {}, lost walks {}",
                    st.segments, st.reentries, st.lost
                ));
                progress.step("frame");
            }
        }
    }
    progress.finish_with(look.quiet, summary);
    if args.json {
        // No bodies: one region (code 0), nothing merged, the plain path.
        let report = serde_json::json!({
            "tets": session.mesh.tets.len(),
            "bodies": 0,
            "frame_s": frame_times,
        });
        println!("{}", serde_json::to_string_pretty(&report)?);
    }
    Ok(())
}

/// How `--orbit` turns the camera from frame to frame.
#[derive(Clone, Copy, Debug)]
pub struct Orbit {
    /// Degrees a frame.
    pub step: f64,
    /// The axis through the focal point it turns about: the view-up before elevation and roll.
    pub axis: [f64; 3],
}

/// Frame `i` of an orbit: `cam0` turned `step * i` degrees about the orbit's axis through the
/// focal point, position and view-up together.
pub fn orbit_camera(cam0: &Camera, orbit: &Orbit, i: usize) -> Camera {
    let mut cam = *cam0;
    cam.turn(&orbit.axis, orbit.step * i as f64);
    cam
}

/// One PT frame.
pub fn pt_frame(
    session: &Session,
    cam: &Camera,
    w: u32,
    h: u32,
    order: &[u32],
    shader: &Shader,
) -> (Image, pt::PtStats, pt::PtTimes) {
    let view = View::new(cam, w, h);
    pt::render_with(
        &view,
        &session.mesh.points,
        &session.mesh.tets,
        &session.field,
        order,
        shader,
        session.schedule,
    )
}
