//! `tetkit sort`: visibility order of the tets for a camera, written as cell data.

use anyhow::Context;
use clap::Args;
use formats::{ArrayData, DataArray, WriteOptions};
use std::path::PathBuf;

use super::camera_args::CameraArgs;
use crate::camera::Camera;
use crate::mesh::TetMesh;
use crate::partition::KdTree;
use crate::sort::{Direction, Method, Order, Sorter};

/// Field data array saying which way `visibility_order` runs (1: front to back).
pub const FIELD_FRONT_TO_BACK: &str = "visibility_front_to_back";

/// Field data array holding the camera `visibility_order` was sorted for: one tuple of 12
/// components, position (3), focal point (3), view-up (3), view angle, parallel (0 or 1) and
/// parallel scale, so `check-order` checks the view the order is for.
pub const FIELD_CAMERA: &str = "visibility_camera";

/// The camera of [`FIELD_CAMERA`] as field data.
fn camera_array(cam: &Camera) -> DataArray {
    let mut v = Vec::with_capacity(12);
    v.extend_from_slice(&cam.position);
    v.extend_from_slice(&cam.focal);
    v.extend_from_slice(&cam.up);
    v.extend([
        cam.view_angle,
        cam.parallel as i32 as f64,
        cam.parallel_scale,
    ]);
    DataArray::new(FIELD_CAMERA, 12, ArrayData::Float64(v))
}

/// The camera a sorted file stores in [`FIELD_CAMERA`]: `None` when it has none, an error
/// naming what is wrong when the array is not one.
pub fn stored_camera(grid: &formats::Grid) -> anyhow::Result<Option<Camera>> {
    let Some(a) = grid.field_data.iter().find(|f| f.name == FIELD_CAMERA) else {
        return Ok(None);
    };
    if a.data.len() != 12 {
        anyhow::bail!(
            "field array {FIELD_CAMERA} has {} values, expected 12 (position, focal point, view-up, view angle, parallel, parallel scale)",
            a.data.len()
        );
    }
    let v: Vec<f64> = (0..12).map(|i| a.data.get_f64(i)).collect();
    if v.iter().any(|x| !x.is_finite()) {
        anyhow::bail!("field array {FIELD_CAMERA} holds a value that is not finite: {v:?}");
    }
    if !(v[9] > 0.0 && v[9] < 180.0) || v[11] <= 0.0 {
        anyhow::bail!(
            "field array {FIELD_CAMERA}: view angle {} must be in (0, 180) and parallel scale {} positive",
            v[9],
            v[11]
        );
    }
    Ok(Some(Camera {
        position: [v[0], v[1], v[2]],
        focal: [v[3], v[4], v[5]],
        up: [v[6], v[7], v[8]],
        view_angle: v[9],
        parallel: v[10] != 0.0,
        parallel_scale: v[11],
    }))
}

#[derive(Args, Debug)]
pub struct SortArgs {
    /// Input tet mesh (.vtu, .pvtu, .vtk, .node/.ele, .mesh, .msh, .exo, .vtkhdf, .vtm, .pvd, .vti/.vtr/.vts); a split mesh from `tetkit partition`
    /// carries its K-D tree in field data and its leaves in the cell array `leaf_id`.
    pub input: PathBuf,
    /// Output .vtu, .pvtu or .vtk: the input with cell data visibility_order, layer and leaf_id
    /// added (formats that cannot hold named arrays are refused).
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub camera: CameraArgs,
    /// centroid: VTK's approximate depth sort; mpvo: adjacency only, one leaf; kd: exact,
    /// per-leaf layers with non-convex dependencies and cycle breaking.
    #[arg(long, value_enum, default_value = "kd")]
    pub method: Method,
    #[arg(long, value_enum, default_value = "back-to-front")]
    pub direction: Direction,
    /// Print the statistics as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Reads a mesh and its tree (if it has one) for the view commands. Meshes with other cells
/// (Gmsh writes its boundary triangles, lines and vertices too; hexes, wedges...) are
/// tetrahedralized first, dropping the cells below 3-D, with a note on stderr.
pub fn load(input: &std::path::Path) -> anyhow::Result<(formats::Grid, TetMesh, Option<KdTree>)> {
    let mut grid = super::read_input(input)?;
    if let Some((drawn, keep)) = crate::partition::input::without_ghost_cells(&grid) {
        eprintln!(
            "tetkit: {}",
            crate::partition::input::ghost_note(
                &input.display().to_string(),
                grid.num_cells() - keep.len()
            )
        );
        grid = drawn;
    }
    if grid
        .cells
        .types
        .iter()
        .any(|&t| t != formats::cell_type::TETRA)
    {
        let (tets, report) = crate::mesh::tetrahedralize::tetrahedralize(&grid, false)
            .with_context(|| format!("tetrahedralizing {}", input.display()))?;
        let dropped =
            grid.num_cells() - report.kept_tets - report.split.iter().map(|s| s.1).sum::<usize>();
        eprintln!(
            "tetkit: {}: using {} tets ({} cells split into tets, {} cells below 3-D dropped)",
            input.display(),
            tets.num_cells(),
            report.split.iter().map(|s| s.1).sum::<usize>(),
            dropped
        );
        grid = tets;
    }
    let mesh = TetMesh::from_grid(&grid).with_context(|| format!("{}", input.display()))?;
    let tree = KdTree::from_field_data(&grid.field_data)
        .with_context(|| format!("{}: field data", input.display()))?;
    Ok((grid, mesh, tree))
}

/// Adds `visibility_order` (rank of each tet in drawing order), `layer` and `leaf_id`, and the
/// direction and camera as field data.
pub fn annotate(grid: &mut formats::Grid, order: &Order, dir: Direction, cam: &Camera) {
    let to_i32 = |v: &[u32]| ArrayData::Int32(v.iter().map(|&x| x as i32).collect());
    grid.cell_data.insert(DataArray::new(
        "visibility_order",
        1,
        to_i32(&order.ranks()),
    ));
    grid.cell_data
        .insert(DataArray::new("layer", 1, to_i32(&order.layer)));
    grid.cell_data
        .insert(DataArray::new("leaf_id", 1, to_i32(&order.leaf)));
    grid.field_data
        .retain(|a| a.name != FIELD_FRONT_TO_BACK && a.name != FIELD_CAMERA);
    grid.field_data.push(DataArray::new(
        FIELD_FRONT_TO_BACK,
        1,
        ArrayData::Int32(vec![(dir == Direction::FrontToBack) as i32]),
    ));
    grid.field_data.push(camera_array(cam));
}

pub fn run(args: &SortArgs) -> anyhow::Result<()> {
    super::require_named_arrays(
        &args.output,
        "sort's result is the cell arrays visibility_order, layer and leaf_id",
    )?;
    let (mut grid, mesh, tree) = load(&args.input)?;
    let cam = args
        .camera
        .camera(&mesh.bounds())
        .with_context(|| format!("{}", args.input.display()))?;
    let t0 = std::time::Instant::now();
    let sorter = Sorter::new(&mesh, tree.as_ref())?;
    note_nonmanifold(&sorter);
    let setup = t0.elapsed().as_secs_f64();
    let order = sorter.order(&cam, args.method, args.direction);
    annotate(&mut grid, &order, args.direction, &cam);
    formats::write(&args.output, &grid, &WriteOptions::default())?;
    let s = &order.stats;
    if s.tets_outside_leaf > 0 {
        eprintln!(
            "tetkit: warning: {} tets cross their leaf's box (the tree does not cut tets; leaves by tet centroid): the leaf order may misplace them; `tetkit partition` cuts them for an exact order",
            s.tets_outside_leaf
        );
    }
    if args.json {
        let j = serde_json::json!({
            "input": args.input.display().to_string(),
            "output": args.output.display().to_string(),
            "direction": args.direction,
            "camera": {
                "position": cam.position, "focal": cam.focal, "up": cam.up,
                "view_angle": cam.view_angle, "parallel": cam.parallel,
                "parallel_scale": cam.parallel_scale,
            },
            "setup_seconds": setup,
            "stats": s,
        });
        println!("{}", serde_json::to_string_pretty(&j)?);
    } else {
        eprintln!(
            "tetkit: {:?} sort of {} tets in {} leaves: {} layers (max per leaf), {} extra constraints, {} cycles broken ({} tets), {:.4} s (+{:.4} s setup)",
            args.method, s.tets, s.leaves, s.layers, s.extra_constraints, s.cycles, s.cycle_tets, s.seconds, setup
        );
    }
    Ok(())
}

/// Warns when the sorter's mesh has faces shared by more than two tets.
pub(crate) fn note_nonmanifold(sorter: &Sorter) {
    warn_nonmanifold(
        sorter.nonmanifold_faces(),
        "the tets on either side of each were paired, but no visibility order is exact between tets that overlap",
    );
}

/// Warns that `n` faces are shared by more than two tets, and what that does (`consequence`).
pub(crate) fn warn_nonmanifold(n: usize, consequence: &str) {
    if n > 0 {
        eprintln!(
            "tetkit: warning: {n} faces are shared by more than two tets (duplicated or overlapping tets, such as a mesh appended to itself): {consequence}"
        );
    }
}
