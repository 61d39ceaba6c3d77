//! `tetkit tradeoff`: every sort x integration mode against the ray-cast reference.

use anyhow::{bail, Context, Result};
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;

use super::camera_args::CameraArgs;
use super::render::{order_for, pt_frame, LookArgs, Progress, Session, SortChoice};
use crate::render::integrate::Integration;
use crate::render::plot::{tradeoff_plot, PlotPoint};
use crate::render::prepare;

#[derive(Args, Debug)]
pub struct TradeoffArgs {
    /// Tet mesh (.vtu, .pvtu, .vtk, .node/.ele, .mesh, .msh, .exo, .vtkhdf, .vtm, .pvd, .vti/.vtr/.vts), or - for stdin.
    pub input: PathBuf,
    /// Folder for the images, the table (tradeoff.csv, tradeoff.json) and the plot (tradeoff.png).
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub camera: CameraArgs,
    #[command(flatten)]
    pub look: LookArgs,
    /// Frames timed per combination (the median is reported).
    #[arg(long, default_value_t = 1, value_name = "N")]
    pub repeat: usize,
}

#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub sort: String,
    pub integration: String,
    /// Sort plus render, seconds per frame (median).
    pub seconds: f64,
    pub sort_seconds: f64,
    pub rmse: f64,
    pub max_error: f64,
    /// Share of pixels with a channel off by more than 1/255.
    pub share_off: f64,
    /// Pairs of tets one pixel ray crosses in the wrong order (summed over rays).
    pub order_violations: Option<usize>,
    pub image: String,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// The image of one sort and integration mode.
fn image_name(sort: SortChoice, mode: Integration) -> String {
    format!("pt_{}_{}.png", sort.name(), mode.name())
}

/// Every file a run writes into its folder.
fn outputs() -> Vec<String> {
    let mut v = vec!["reference.png".to_string()];
    for sort in SortChoice::ALL {
        for mode in Integration::ALL {
            v.push(image_name(sort, mode));
        }
    }
    v.extend(["tradeoff.csv", "tradeoff.json", "tradeoff.png"].map(String::from));
    v
}

pub fn run(args: &TradeoffArgs) -> Result<()> {
    // Something in the way of a file written late (a folder named tradeoff.csv) would fail the
    // run after the images were written: found before any work instead.
    for name in outputs() {
        let p = args.output.join(&name);
        if std::fs::metadata(&p).is_ok_and(|m| m.is_dir()) {
            anyhow::bail!(
                "{}: a folder is in the way of tradeoff's output file",
                p.display()
            );
        }
    }
    let look = &args.look;
    let combos = SortChoice::ALL.len() * Integration::ALL.len();
    let mut progress = Progress::new(look.quiet, 3 + combos as u64, "tradeoff");
    let session = Session::open(&args.input, look)?;
    let cam = session
        .bounds_camera(&args.camera)
        .with_context(|| format!("{}", args.input.display()))?;
    progress.step("read");
    // The folder is made once the input is read, and taken back if anything fails after: a
    // failed run leaves no folder of partial results.
    let created = !args.output.exists();
    if args.output.exists() && !args.output.is_dir() {
        // create_dir_all's own message ("File exists") does not say that -o names a folder.
        bail!(
            "{}: is a file; -o names the folder tradeoff writes its table, plot and images into",
            args.output.display()
        );
    }
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("{}: creating folder", args.output.display()))?;
    let result = measure(args, &session, &cam, &mut progress);
    if result.is_err() && created {
        let _ = std::fs::remove_dir_all(&args.output);
    }
    result
}

/// Everything `run` does once the input is read and the folder exists.
fn measure(
    args: &TradeoffArgs,
    session: &Session,
    cam: &crate::camera::Camera,
    progress: &mut Progress,
) -> Result<()> {
    let look = &args.look;
    let repeat = args.repeat.max(1);
    let cam = *cam;
    let (w, h) = look.size;

    // The reference.
    let t = Instant::now();
    let topo = session.topology();
    let rc = session.raycaster(&topo);
    let rc_setup = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let (reference, _) = rc.render(&session.tf, &cam, w, h);
    let rc_time = t.elapsed().as_secs_f64();
    reference.write_png(&args.output.join("reference.png"), look.background)?;
    progress.step("reference");

    let t = Instant::now();
    let sorter = session.sorter()?;
    let shaders: Vec<_> = Integration::ALL
        .iter()
        .map(|&m| prepare::shader(&session.tf, m, session.table, session.lmax))
        .collect();
    let pt_setup = t.elapsed().as_secs_f64();
    progress.step("setup");

    let mut rows = Vec::new();
    for sort in SortChoice::ALL {
        let (order, _) = order_for(Some(&sorter), session.mesh.tets.len(), &cam, sort);
        let mut rank = vec![0u32; order.len()];
        for (k, &t) in order.iter().enumerate() {
            rank[t as usize] = k as u32;
        }
        let check = crate::sort::check::check_order(&session.mesh, &cam, &rank, true, w, h);
        for (mi, &mode) in Integration::ALL.iter().enumerate() {
            let mut times = Vec::new();
            let mut sort_times = Vec::new();
            let mut img = None;
            for _ in 0..repeat {
                let t = Instant::now();
                let (order, sort_s) = order_for(Some(&sorter), session.mesh.tets.len(), &cam, sort);
                let (im, _, _) = pt_frame(session, &cam, w, h, &order, &shaders[mi]);
                times.push(t.elapsed().as_secs_f64());
                sort_times.push(sort_s);
                img = Some(im);
            }
            let img = img.unwrap_or_else(|| reference.clone());
            let name = image_name(sort, mode);
            img.write_png(&args.output.join(&name), look.background)?;
            let err = img.error_against(&reference, look.background);
            rows.push(Row {
                sort: sort.name().into(),
                integration: mode.name().into(),
                seconds: median(times),
                sort_seconds: median(sort_times),
                rmse: err.rmse,
                max_error: err.max,
                share_off: err.share_off,
                order_violations: Some(check.violations),
                image: name,
            });
            progress.step(&format!("{} {}", sort.name(), mode.name()));
        }
    }
    rows.push(Row {
        sort: "raycast".into(),
        integration: "exact".into(),
        seconds: rc_time,
        sort_seconds: 0.0,
        rmse: 0.0,
        max_error: 0.0,
        share_off: 0.0,
        order_violations: None,
        image: "reference.png".into(),
    });
    progress.finish();

    let mut csv = String::from(
        "sort,integration,seconds_per_frame,sort_seconds,rmse,max_error,share_off_1_255,order_violations,image\n",
    );
    for r in &rows {
        csv.push_str(&format!(
            "{},{},{:.6},{:.6},{:.6},{:.6},{:.6},{},{}\n",
            r.sort,
            r.integration,
            r.seconds,
            r.sort_seconds,
            r.rmse,
            r.max_error,
            r.share_off,
            r.order_violations.map_or(String::new(), |v| v.to_string()),
            r.image
        ));
    }
    crate::render::image::write_atomic(&args.output.join("tradeoff.csv"), csv.as_bytes())?;
    let json = serde_json::json!({
        "input": args.input.display().to_string(),
        "tets": session.mesh.tets.len(),
        "array": session.field_name,
        "size": [w, h],
        "setup_seconds": {"read": session.read_s, "pt": pt_setup, "raycast": rc_setup},
        "rows": rows,
    });
    crate::render::image::write_atomic(
        &args.output.join("tradeoff.json"),
        serde_json::to_string_pretty(&json)?.as_bytes(),
    )?;
    let points: Vec<PlotPoint> = rows
        .iter()
        .filter(|r| r.sort != "raycast")
        .map(|r| PlotPoint {
            series: r.sort.clone(),
            label: r.integration.clone(),
            seconds: r.seconds,
            error: r.rmse,
        })
        .collect();
    let title = format!(
        "{} tets, {}x{}: time vs error (ray-cast reference {:.2} s)",
        session.mesh.tets.len(),
        w,
        h,
        rc_time
    );
    let labelled = tradeoff_plot(
        &args.output.join("tradeoff.png"),
        &points,
        &title,
        "seconds per frame (sort + render)",
        "RMSE against the ray-cast reference",
    )?;

    println!(
        "{} tets, array '{}', {}x{}; setup: read {:.3} s, PT (adjacency, leaves, tables) {:.3} s, ray caster (adjacency, grids) {:.3} s",
        session.mesh.tets.len(),
        session.field_name,
        w,
        h,
        session.read_s,
        pt_setup,
        rc_setup
    );
    println!(
        "| sort | integration | s/frame | sort s | RMSE | max error | px off > 1/255 | ray-order violations |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- |");
    for r in &rows {
        println!(
            "| {} | {} | {:.4} | {:.4} | {:.5} | {:.4} | {:.2}% | {} |",
            r.sort,
            r.integration,
            r.seconds,
            r.sort_seconds,
            r.rmse,
            r.max_error,
            100.0 * r.share_off,
            r.order_violations
                .map_or("-".to_string(), |v| v.to_string())
        );
    }
    if !labelled && !look.quiet {
        eprintln!(
            "tetkit: note: no system font found (e.g. fonts-dejavu-core, or set TETKIT_FONT), so tradeoff.png has no text; the table above has the numbers"
        );
    }
    Ok(())
}
