//! Command-line interface: argument parsing and one thin function per subcommand.

mod bench;
pub mod camera_args;
mod check_order;
mod classify;
mod convert;
mod info;
mod partition;
mod probe;
mod render;
mod render_device;
mod render_scene;
mod sort;
mod tradeoff;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    name = "tetkit",
    version,
    about = "Tetrahedral volume meshes: convert, partition, sort, render"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Print counts, cell types, bounds and every data array of a mesh.
    Info(info::InfoArgs),
    /// Convert between VTU, PVTU, legacy VTK, TetGen and Medit (and read Gmsh MSH, VTK collections
    /// and structured data), optionally tetrahedralizing.
    Convert(convert::ConvertArgs),
    /// Split a tet mesh with a K-D tree (exact, conforming) and write the split mesh and the tree.
    Partition(partition::PartitionArgs),
    /// Order the tets of a mesh for a camera (centroid, mpvo or the exact kd sort).
    Sort(sort::SortArgs),
    /// Count ray-order violations of a visibility order by casting rays through pixel centres.
    CheckOrder(check_order::CheckOrderArgs),
    /// Render a tet mesh with projected tetrahedra or the ray-cast reference.
    Render(render::RenderArgs),
    /// Values of every array at given points (cell location with the O(N) grid).
    Probe(probe::ProbeArgs),
    /// Render one view with every sort x integration mode and compare time against error.
    Tradeoff(tradeoff::TradeoffArgs),
    /// Write each tet's region code (which scene bodies it touches) as cell data.
    Classify(classify::ClassifyArgs),
    /// Benchmarks on generated meshes (I/O, partition, sort, render).
    Bench(bench::BenchArgs),
}

/// Runs the command line; errors go to stderr with a non-zero exit code.
pub fn main() -> ExitCode {
    default_sigpipe();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Info(a) => info::run(&a),
        Command::Convert(a) => convert::run(&a),
        Command::Partition(a) => partition::run(&a),
        Command::Sort(a) => sort::run(&a),
        Command::CheckOrder(a) => check_order::run(&a),
        Command::Render(a) => render::run(&a),
        Command::Probe(a) => probe::run(&a),
        Command::Tradeoff(a) => tradeoff::run(&a),
        Command::Classify(a) => classify::run(&a),
        Command::Bench(a) => bench::run(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tetkit: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

/// Rust starts programs with SIGPIPE ignored, so once a reader such as `head` closes the pipe,
/// every `println!` panics ("failed printing to stdout: Broken pipe") and `convert -` fails
/// with an error. Restoring the default makes `tetkit info mesh.vtu | head` end quietly, as
/// `cat` and `grep` do.
fn default_sigpipe() {
    #[cfg(unix)]
    // SAFETY: called first in `main`, before any thread is started; SIG_DFL is a valid
    // disposition for SIGPIPE and no handler of ours is replaced.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// Refuses an output whose format cannot hold named cell arrays (TetGen's `.ele` keeps
/// attributes without names, Medit keeps only its refs): a command whose result is the arrays
/// `what` names must not write a file that silently drops or renames them.
pub fn require_named_arrays(path: &std::path::Path, what: &str) -> anyhow::Result<()> {
    use formats::Format;
    let format = Format::for_output(path)?;
    if !matches!(format, Format::Vtu | Format::Pvtu | Format::Legacy) {
        anyhow::bail!(
            "{}: {what}, which a {} file cannot hold by name; write .vtu, .pvtu or .vtk",
            path.display(),
            format.name()
        );
    }
    Ok(())
}

/// Reads a mesh from a path, or from stdin for `-` (VTU, legacy VTK, Medit, Gmsh MSH or Exodus
/// II, sniffed from the content).
pub fn read_input(path: &std::path::Path) -> anyhow::Result<formats::Grid> {
    use anyhow::Context;
    if path.as_os_str() == "-" {
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(&mut std::io::stdin().lock(), &mut bytes)
            .context("reading stdin")?;
        let format = formats::sniff(&bytes).ok_or_else(|| {
            anyhow::anyhow!(
                "<stdin>: byte 0: not a VTU, legacy VTK, Medit, Gmsh MSH or Exodus II stream"
            )
        })?;
        return formats::read_bytes(&bytes, format).map_err(|mut e| {
            e.file = Some("<stdin>".into());
            e.into()
        });
    }
    Ok(formats::read(path)?)
}

/// The tets of any mesh for the commands that answer per input cell (probe, classify): tets
/// kept, other 3-D cells tetrahedralized, lower cells (TetGen's `.face` triangles, Gmsh's
/// boundary elements) dropped, as every view command does, with notes on stderr. Returns the
/// mesh and, for each of its tets, the index of the input cell it belongs to.
pub fn tets_with_input_cells(
    grid: &formats::Grid,
    name: &str,
) -> anyhow::Result<(crate::mesh::TetMesh, Vec<usize>)> {
    use anyhow::Context;
    use formats::{cell_type, ArrayData, DataArray};
    if grid.cells.types.iter().all(|&t| t == cell_type::TETRA)
        && crate::partition::input::without_ghost_cells(grid).is_none()
    {
        let mesh = crate::mesh::TetMesh::from_grid(grid).with_context(|| name.to_string())?;
        let cells = (0..mesh.tets.len()).collect();
        return Ok((mesh, cells));
    }
    // A private cell array rides through dropping and tetrahedralization (both gather cell
    // data by parent), so each tet names its input cell whatever the input already carries.
    const TAG: &str = "tetkit:input_cell";
    let mut tagged = grid.clone();
    tagged.cell_data.insert(DataArray::new(
        TAG,
        1,
        ArrayData::Int64((0..grid.num_cells() as i64).collect()),
    ));
    let (mut mesh, _, notes) = crate::partition::input::tets_of(&tagged, name)?;
    for n in notes {
        eprintln!("tetkit: {n}");
    }
    let cells = match mesh.cell_data.get(TAG) {
        Some(a) => a
            .data
            .to_f64_vec()
            .into_iter()
            .map(|v| v as usize)
            .collect(),
        None => anyhow::bail!("{name}: the input cell of each tet was lost"),
    };
    mesh.cell_data.arrays.retain(|a| a.name != TAG);
    Ok((mesh, cells))
}
