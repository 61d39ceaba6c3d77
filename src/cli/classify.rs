//! `tetkit classify`: each tet's region code for a scene, written as cell data for ParaView.

use clap::Args;
use formats::{ArrayData, DataArray};
use std::collections::BTreeMap;
use std::path::PathBuf;

use crate::camera::Camera;
use crate::mesh::TetMesh;
use crate::scene::{self, code_string, merge, ray};

#[derive(Args, Debug)]
pub struct ClassifyArgs {
    /// Input tet mesh (.vtu, .pvtu, .vtk, .node/.ele, .mesh, .msh, .exo, .vtkhdf, .vtm, .pvd, .vti/.vtr/.vts).
    pub input: PathBuf,
    /// Scene file (TOML) with the bodies.
    #[arg(long)]
    pub scene: PathBuf,
    /// Output mesh with cell data `region_code` (UInt8: bit i set when the tet's interior
    /// overlaps body i's interior) added to every input array.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Print a JSON report on stdout: bodies, tet counts per code, and the region codes seen
    /// along the camera's pixel rays inside the mesh's bounds, before and after merging.
    #[arg(long)]
    pub json: bool,
    /// Image size for the pixel-ray codes of the report.
    #[arg(long, default_value_t = 256)]
    pub size: u32,
}

pub fn run(args: &ClassifyArgs) -> anyhow::Result<()> {
    super::require_named_arrays(
        &args.output,
        "classify's result is the cell array region_code",
    )?;
    let scene = scene::load(&args.scene)?;
    let grid = super::read_input(&args.input)?;
    // Meshes with other cells (TetGen's .face triangles, Gmsh's boundary elements, quadratic
    // cells) are classified through their tets; each input cell gets the union of its tets'
    // codes (0 for cells below 3-D), so the output keeps every input cell and array.
    let (mesh, input_cell) =
        super::tets_with_input_cells(&grid, &args.input.display().to_string())?;
    let t0 = std::time::Instant::now();
    let fallbacks0 = scene::frustum::exact_fallbacks();
    let codes = scene::classify::classify(&scene, &mesh);
    let classify_s = t0.elapsed().as_secs_f64();
    let fallbacks = scene::frustum::exact_fallbacks() - fallbacks0;
    if grid.cell_data.get("region_code").is_some() {
        eprintln!("tetkit: replacing the input's cell array 'region_code'");
    }
    let mut per_cell = vec![0u8; grid.num_cells()];
    for (&c, &code) in input_cell.iter().zip(&codes) {
        per_cell[c] |= code;
    }
    let lower = grid
        .cells
        .types
        .iter()
        .filter(|&&t| formats::cell_type::dimension(t) < 3)
        .count();
    if lower > 0 {
        // The tets' note above says those cells were dropped from the tets; the output keeps
        // them, and their 0 must not read as "outside every body".
        eprintln!(
            "tetkit: note: {} keeps the {lower} cells of dimension 0-2 with region_code 0: classify labels 3-D cells only",
            args.output.display()
        );
    }
    let mut out_grid = grid;
    out_grid
        .cell_data
        .insert(DataArray::new("region_code", 1, ArrayData::UInt8(per_cell)));
    formats::write(&args.output, &out_grid, &formats::WriteOptions::default())?;
    if args.json {
        let report = report(&scene, &mesh, &codes, args.size, (classify_s, fallbacks));
        println!("{}", serde_json::to_string_pretty(&report)?);
    }
    Ok(())
}

fn report(
    scene: &scene::Scene,
    mesh: &TetMesh,
    codes: &[u8],
    size: u32,
    (classify_s, fallbacks): (f64, u64),
) -> serde_json::Value {
    let bits = scene.bodies.len();
    let mut hist: BTreeMap<u8, usize> = BTreeMap::new();
    for &c in codes {
        *hist.entry(c).or_default() += 1;
    }
    let bounds = mesh.bounds();
    let mut cam = Camera::default();
    cam.reset_to(&bounds);
    scene.camera.apply(&mut cam);
    let view = ray::View::new(scene, cam, size, size);
    // Codes of the ray pieces that lie in the mesh's bounding box.
    let box_body = scene::Primitive::Box {
        min: bounds.min,
        max: bounds.max,
    };
    let mut seen = [false; 256];
    let mut r = ray::RayRegions::default();
    let t0 = std::time::Instant::now();
    for py in 0..size {
        for px in 0..size {
            let (x, y) = (px as f64 + 0.5, py as f64 + 0.5);
            view.pixel(x, y, &mut r);
            let (o, d) = view.camera.pixel_ray(x, y, size, size);
            if let Some((a, b)) = box_body.line_span(&o, &d) {
                let (a, b) = (a.max(0.0), b);
                if a < b {
                    r.pieces(a, b, |_, _, c| seen[c as usize] = true);
                }
            }
        }
    }
    let rays_s = t0.elapsed().as_secs_f64();
    let present: Vec<u8> = (0..=255u8).filter(|&c| seen[c as usize]).collect();
    let merged = merge::merge_scene(scene, &present);
    serde_json::json!({
        "scene": scene.file.display().to_string(),
        "rule": format!("{:?}", scene.rule).to_lowercase(),
        "bodies": scene.bodies.iter().enumerate().map(|(i, b)| serde_json::json!({
            "bit": i,
            "name": b.name,
            "line": b.line,
            "action": match b.action { scene::Action::Cut => "cut", scene::Action::Transfer(_) => "transfer" },
            "tets": codes.iter().filter(|&&c| c >> i & 1 == 1).count(),
            "screen_pixels": view.footprints[i].pixel_count(size, size),
        })).collect::<Vec<_>>(),
        "tets": codes.len(),
        // Cylinder and cone tests the interval filter could not settle (exact arithmetic).
        "frustum_exact_fallbacks": fallbacks,
        "tet_codes": hist.iter().map(|(c, n)| serde_json::json!({"code": code_string(*c, bits), "tets": n})).collect::<Vec<_>>(),
        "pixel_codes_before_merging": present.iter().map(|&c| code_string(c, bits)).collect::<Vec<_>>(),
        "classes_after_merging": merged.groups.iter().map(|(e, cl)| serde_json::json!({
            "effect": match e {
                scene::Effect::Default => "default".to_string(),
                scene::Effect::Cut => "cut".to_string(),
                scene::Effect::Transfer(i) => format!("transfer of body {i}"),
            },
            "classes": cl.iter().map(|c| c.pattern(bits)).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
        "drawn_classes": merged.drawn_classes(),
        "image": [size, size],
        "seconds": {"classify": classify_s, "pixel_rays": rays_s},
    })
}
