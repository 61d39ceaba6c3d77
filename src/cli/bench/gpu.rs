//! `tetkit bench gpu`: frame time of projected tetrahedra on the GPU (sort + upload + draw +
//! readback) against the CPU path (sort + project + bin + raster) on generated jittered grids.

use anyhow::Result;
use clap::Args;
use std::time::Instant;

use crate::camera::Camera;
use crate::mesh::generate::{jitter, structured_grid};
use crate::render::field::Field;
use crate::render::gpu::{GpuContext, GpuRenderer};
use crate::render::image::parse_size;
use crate::render::integrate::Integration;
use crate::render::prepare::{self, TableSize};
use crate::render::pt::{self, View};
use crate::render::transfer::{named_colormap, OpacitySpec, TransferFunction};
use crate::sort::{Direction, Method, Sorter};

#[derive(Args, Debug)]
pub struct GpuBenchArgs {
    /// Approximate tet counts, comma-separated (a jittered grid of 6-tet cubes each).
    #[arg(long, default_value = "200000,1000000", value_delimiter = ',')]
    pub tets: Vec<usize>,
    /// Image size WIDTHxHEIGHT.
    #[arg(long, default_value = "512x512")]
    pub size: String,
    /// Frames per device, each turned 360/N degrees about the mesh; the median is reported.
    #[arg(long, default_value_t = 5)]
    pub frames: usize,
    /// Integration mode.
    #[arg(long, value_enum, default_value = "preintegrated")]
    pub integration: Integration,
    /// Skip the CPU path.
    #[arg(long)]
    pub gpu_only: bool,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        f64::NAN
    } else {
        v[v.len() / 2]
    }
}

pub fn run(args: &GpuBenchArgs) -> Result<()> {
    let (w, h) = parse_size(&args.size)?;
    let frames = args.frames.max(1);
    let ctx = GpuContext::new()?;
    println!("GPU: {}", ctx.describe());
    let mut ctx = Some(ctx);
    println!(
        "{:>9} {:>6} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}",
        "tets", "device", "sort", "upload", "draw", "readback", "frame", "fps"
    );
    println!(
        "{:>9} {:>6} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}",
        "", "", "", "(project)", "(raster)", "", "", ""
    );
    for &target in &args.tets {
        let side = ((target as f64 / 6.0).cbrt().round() as usize).max(1);
        let n = [side; 3];
        let mut m = structured_grid(n, [0.0; 3], [1.0; 3]);
        jitter(&mut m, n, 0.25, 7);
        let field = match m.point_data.get("scalar") {
            Some(a) => Field::Point(a.data.to_f64_vec()),
            None => Field::Point(vec![0.0; m.points.len()]),
        };
        let tf = TransferFunction::build(
            &named_colormap("viridis")?,
            Some(&OpacitySpec::parse("0:0.05,0.5:0.6,1:0.2")?),
            [0.0, 1.0],
            prepare::default_unit_distance(&m),
            64,
        )?;
        let shader = prepare::shader(
            &tf,
            args.integration,
            TableSize::default(),
            prepare::table_length(&m, &tf, TableSize::default().length),
        );
        let sorter = Sorter::new(&m, None)?;
        let cam_at = |i: usize| {
            let mut c = Camera {
                position: [0.5, -1.6, 1.3],
                focal: [0.5, 0.5, 0.5],
                up: [0.0, 0.0, 1.0],
                view_angle: 35.0,
                ..Camera::default()
            };
            c.azimuth(360.0 * i as f64 / frames as f64);
            c
        };
        let sort = |cam: &Camera| {
            let t = Instant::now();
            let o = sorter.order(cam, Method::Kd, Direction::FrontToBack).order;
            (o, t.elapsed().as_secs_f64())
        };

        let c = ctx.take().map_or_else(GpuContext::new, Ok)?;
        let t = Instant::now();
        let mut gpu = GpuRenderer::new(c, &m.points, &m.tets, &field, &shader)?;
        let setup = t.elapsed().as_secs_f64();
        let mut cols = [vec![], vec![], vec![], vec![], vec![]];
        for i in 0..frames {
            let cam = cam_at(i);
            let t = Instant::now();
            let (order, s) = sort(&cam);
            let (_, _, g) = gpu.render(&View::new(&cam, w, h), &order)?;
            for (c, v) in cols.iter_mut().zip([s, g.upload, g.draw, g.readback]) {
                c.push(v);
            }
            cols[4].push(t.elapsed().as_secs_f64());
        }
        let [s, u, d, r, f] = cols.map(median);
        println!(
            "{:>9} {:>6} {s:>9.4} {u:>9.4} {d:>9.4} {r:>9.4} {f:>9.4} {:>9.2}   (mesh upload {setup:.3} s)",
            m.tets.len(),
            "gpu",
            1.0 / f
        );
        if args.gpu_only {
            continue;
        }
        let mut cols = [vec![], vec![], vec![], vec![]];
        for i in 0..frames {
            let cam = cam_at(i);
            let t = Instant::now();
            let (order, s) = sort(&cam);
            let (_, _, p) = pt::render(
                &View::new(&cam, w, h),
                &m.points,
                &m.tets,
                &field,
                &order,
                &shader,
            );
            for (c, v) in cols.iter_mut().zip([s, p.project, p.bin + p.raster]) {
                c.push(v);
            }
            cols[3].push(t.elapsed().as_secs_f64());
        }
        let [s, p, r, f] = cols.map(median);
        println!(
            "{:>9} {:>6} {s:>9.4} {p:>9.4} {r:>9.4} {:>9} {f:>9.4} {:>9.2}",
            m.tets.len(),
            "cpu",
            "-",
            1.0 / f
        );
    }
    Ok(())
}
