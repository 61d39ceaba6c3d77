//! `tetkit check-order`: ray-order violations of a visibility order, independent of the sort code.

use anyhow::{bail, Context};
use clap::Args;
use std::path::PathBuf;

use super::camera_args::CameraArgs;
use super::sort::{load, stored_camera, FIELD_CAMERA, FIELD_FRONT_TO_BACK};
use crate::sort::check::check_order;
use crate::sort::{Direction, Method, Sorter};

#[derive(Args, Debug)]
pub struct CheckOrderArgs {
    /// Input tet mesh. Without --method, its cell array `visibility_order` (from `tetkit sort`)
    /// is checked; with --method the mesh is sorted first.
    pub input: PathBuf,
    #[command(flatten)]
    pub camera: CameraArgs,
    /// Number of rays, cast through the pixel centres of a square image of about this many pixels.
    #[arg(long, default_value_t = 65536, value_parser = parse_rays)]
    pub rays: u64,
    /// Sort with this method and check the result (default when the file has no visibility_order: kd).
    #[arg(long, value_enum)]
    pub method: Option<Method>,
    /// Drawing direction of the sort (with --method) [default: back-to-front]; a file's order
    /// carries its own.
    #[arg(long, value_enum)]
    pub direction: Option<Direction>,
    /// Print the report as JSON on stdout.
    #[arg(long)]
    pub json: bool,
    /// Exit non-zero when any violation is found.
    #[arg(long)]
    pub fail_on_violation: bool,
}

/// The rays' image side is at most 8192: a larger request was cut down without a word (and
/// 8192^2 rays already take gigabytes), so say so instead.
fn parse_rays(s: &str) -> Result<u64, String> {
    s.trim()
        .parse::<u64>()
        .ok()
        .filter(|n| (1..=8192 * 8192).contains(n))
        .ok_or_else(|| format!("--rays '{s}': expected a count between 1 and 67108864 (8192^2)"))
}

pub fn run(args: &CheckOrderArgs) -> anyhow::Result<()> {
    let (grid, mesh, tree) = load(&args.input)?;
    let mut cam = args
        .camera
        .camera(&mesh.bounds())
        .with_context(|| format!("{}", args.input.display()))?;
    let side = ((args.rays.max(1) as f64).sqrt().round() as u32).clamp(1, 8192);
    let n = mesh.tets.len();
    let from_file = grid.cell_data.get("visibility_order");
    let (rank, ftb, what, stats) = match (args.method, from_file) {
        (None, Some(a)) => {
            if args.direction.is_some() {
                eprintln!(
                    "tetkit: note: --direction is not used: {}'s visibility_order carries its own direction (field visibility_front_to_back); give --method to sort and check in a direction",
                    args.input.display()
                );
            }
            if a.components != 1 || a.data.len() != n {
                bail!(
                    "{}: cell array visibility_order has {} values in {} components, expected {n}",
                    args.input.display(),
                    a.data.len(),
                    a.components
                );
            }
            let mut seen = vec![false; n];
            let mut rank = Vec::with_capacity(n);
            for i in 0..n {
                let v = a.data.get_f64(i);
                if !(v >= 0.0 && v < n as f64 && v.fract() == 0.0) || seen[v as usize] {
                    bail!(
                        "{}: cell array visibility_order: value {v} of cell {i} is not a rank (a permutation of 0 to {})",
                        args.input.display(),
                        n.saturating_sub(1)
                    );
                }
                seen[v as usize] = true;
                rank.push(v as u32);
            }
            // The order is for the camera `sort` stored: check that view unless another is
            // asked for (an order checked in a view it was not sorted for has violations).
            let stored = stored_camera(&grid)
                .with_context(|| format!("{}: field data", args.input.display()))?;
            match stored {
                Some(c) if args.camera == CameraArgs::default() => {
                    eprintln!(
                        "tetkit: note: checking the view {}'s visibility_order was sorted for (field {FIELD_CAMERA}); camera options check another",
                        args.input.display()
                    );
                    cam = c;
                }
                Some(c) if c != cam => eprintln!(
                    "tetkit: note: {}'s visibility_order was sorted for another camera (field {FIELD_CAMERA}: position {:?}, focal point {:?}); checking the view given, where it need not hold",
                    args.input.display(),
                    c.position,
                    c.focal
                ),
                _ => {}
            }
            let ftb = grid
                .field_data
                .iter()
                .find(|f| f.name == FIELD_FRONT_TO_BACK)
                .map(|f| f.data.len() == 1 && f.data.get_f64(0) != 0.0)
                .unwrap_or(false);
            (rank, ftb, "visibility_order array".to_string(), None)
        }
        (m, _) => {
            let method = m.unwrap_or(Method::Kd);
            let what = if m.is_none() {
                // A file written where the order could not be kept (or never sorted) must
                // not pass for a checked order: say whose order this is.
                eprintln!(
                    "tetkit: note: {}: no cell array visibility_order (what `tetkit sort` writes to .vtu, .pvtu or .vtk); checking tetkit's own kd sort of the mesh instead",
                    args.input.display()
                );
                "no visibility_order in the file; tetkit's kd sort".to_string()
            } else {
                format!("{method:?} sort")
            };
            let sorter = Sorter::new(&mesh, tree.as_ref())?;
            let direction = args.direction.unwrap_or(Direction::BackToFront);
            let o = sorter.order(&cam, method, direction);
            (
                o.ranks(),
                direction == Direction::FrontToBack,
                what,
                Some(o.stats),
            )
        }
    };
    let r = check_order(&mesh, &cam, &rank, ftb, side, side);
    if args.json {
        let j = serde_json::json!({
            "input": args.input.display().to_string(),
            "checked": what,
            "front_to_back": ftb,
            "report": r,
            "sort_stats": stats,
        });
        println!("{}", serde_json::to_string_pretty(&j)?);
    } else {
        println!(
            "{}: {what}: {} violations ({} between neighbours on a ray) on {} of {} rays ({}x{}, {} crossings)",
            args.input.display(),
            r.violations,
            r.adjacent_violations,
            r.rays_with_violations,
            r.rays,
            r.width,
            r.height,
            r.crossings
        );
        if r.edge_meetings > 0 {
            println!(
                "  {} pairs of neighbours on a ray meeting only at a shared edge or vertex not counted (the ray does not decide their order)",
                r.edge_meetings
            );
        }
    }
    if args.fail_on_violation && r.violations > 0 {
        bail!("{} ray-order violations", r.violations);
    }
    Ok(())
}
