//! `tetkit partition`: K-D tree split of a tet mesh, tree and pieces written for ParaView.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use formats::{ArrayData, WriteOptions};

use crate::partition::input::tets_of;
use crate::partition::{
    output, partition, PartitionOptions, PartitionReport, SearchParams, Stop, Strategy,
    ORIGINAL_CELL_ID,
};

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum StrategyArg {
    /// Li et al. 2012 as published: N candidates, beta <= PHI, alpha < EPS, best beta of x/y/z.
    Paper,
    /// Fewest tets + W * imbalance over wide-gap and vertex-layer candidates.
    Cost,
}

#[derive(Args, Debug)]
pub struct PartitionArgs {
    /// Input mesh (.vtu, .pvtu, .vtk, .node/.ele, .mesh, .msh, .exo, .vtkhdf, .vtm, .pvd, .vti/.vtr/.vts); non-tet 3-D cells are
    /// tetrahedralized, 2-D and lower cells dropped.
    pub input: PathBuf,
    /// The split mesh (.vtu): cell data leaf_id and original_cell_id, the tree in field data.
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Also the tree as one hexahedron per node (.vtu); the split mesh holds it in field data
    /// either way.
    #[arg(long)]
    pub tree: Option<PathBuf>,
    /// Split the largest nodes until there are N leaves [default: 8].
    #[arg(long, conflicts_with = "depth")]
    pub leaves: Option<usize>,
    /// Split every node down to depth D instead.
    #[arg(long)]
    pub depth: Option<u32>,
    /// Plane search.
    #[arg(long, value_enum, default_value = "paper")]
    pub strategy: StrategyArg,
    /// N: evenly spaced candidate planes per axis and node.
    #[arg(long, default_value_t = 16)]
    pub candidates: usize,
    /// PHI: give up a plane whose beta (tets made by cutting / tets in the node) exceeds this.
    #[arg(long, default_value_t = 1.0)]
    pub phi: f64,
    /// EPS: the paper's balance threshold on alpha = |l - r| / ((l + r) / 2).
    #[arg(long, default_value_t = 0.2)]
    pub eps: f64,
    /// W of the cost strategy: it minimizes tets after the cut + W * |l - r|.
    #[arg(long, default_value_t = 0.5)]
    pub balance_weight: f64,
    /// Also write one .vtu per leaf into DIR/<stem>/, named by DIR/<stem>.pvtu and DIR/<stem>.vtm.
    #[arg(long, value_name = "DIR")]
    pub pieces: Option<PathBuf>,
    /// Print the report as JSON on stdout instead of a table on stderr.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: &PartitionArgs) -> Result<()> {
    // Candidate planes are stored per axis and per node: 1e9 aborted on an 8 GB allocation, and
    // past a few thousand per axis no tet count changes.
    if !(1..=4096).contains(&args.candidates) {
        bail!(
            "--candidates {}: expected a count between 1 and 4096",
            args.candidates
        );
    }
    if [args.phi, args.eps, args.balance_weight]
        .iter()
        .any(|x| x.is_nan() || *x < 0.0)
    {
        bail!("--phi, --eps and --balance-weight must be non-negative numbers");
    }
    if matches!(args.leaves, Some(0)) {
        bail!("--leaves must be at least 1");
    }
    for out in std::iter::once(&args.output).chain(&args.tree) {
        if formats::Format::from_path(out)? != formats::Format::Vtu {
            bail!("{}: partition writes .vtu files", out.display());
        }
    }
    let name = args.input.display().to_string();
    let grid = super::read_input(&args.input)?;
    let (mesh, input_ids, notes) = tets_of(&grid, &name)?;
    for n in notes {
        eprintln!("tetkit: {n}");
    }
    if mesh.tets.is_empty() {
        bail!("{name}: no tetrahedra to partition");
    }
    let opts = PartitionOptions {
        stop: match (args.leaves, args.depth) {
            (_, Some(d)) => Stop::Depth(d),
            (Some(l), None) => Stop::Leaves(l),
            (None, None) => Stop::Leaves(8),
        },
        search: SearchParams {
            strategy: match args.strategy {
                StrategyArg::Paper => Strategy::Paper,
                StrategyArg::Cost => Strategy::Cost,
            },
            candidates: args.candidates,
            phi: args.phi,
            eps: args.eps,
            balance_weight: args.balance_weight,
        },
    };
    let mut result = partition(&mesh, &opts).with_context(|| format!("partitioning {name}"))?;
    if result.report.reoriented > 0 {
        eprintln!(
            "tetkit: {name}: {} tets had negative volume and were reoriented (two vertices swapped)",
            result.report.reoriented
        );
    }
    if result.report.degenerate > 0 {
        eprintln!(
            "tetkit: {name}: warning: {} tets have zero volume (kept as they are)",
            result.report.degenerate
        );
    }
    if let Stop::Leaves(asked) = opts.stop {
        // The table says how many leaves came out, but a user who asked for more reads it as
        // success; say why and what finds more.
        if result.report.leaves < asked {
            let why = match args.strategy {
                StrategyArg::Paper => format!(
                    "no plane within --phi {} and --eps {} splits any leaf further; --strategy cost, or a larger --phi or --eps, accepts more planes",
                    args.phi, args.eps
                ),
                StrategyArg::Cost => format!(
                    "no plane within --phi {} splits any leaf further; a larger --phi accepts more planes",
                    args.phi
                ),
            };
            eprintln!(
                "tetkit: {name}: warning: {} of the {asked} leaves asked for: {why}",
                result.report.leaves
            );
        }
    }
    if let Some(a) = result.mesh.cell_data.get_mut(ORIGINAL_CELL_ID) {
        a.data = ArrayData::Int64(
            result
                .original
                .iter()
                .map(|&o| input_ids.get(o as usize).copied().unwrap_or(o as i64))
                .collect(),
        );
    }
    let wopts = WriteOptions::default();
    let tree_grid = output::tree_grid(&result.tree);
    let split_grid = result.mesh.to_grid();
    // Every file or none: the leaf pieces are written once the split mesh and tree are made
    // (into hidden files) but before those are placed, so pieces that cannot be written leave
    // the previous split mesh and tree as they were, and a split mesh or tree that cannot be
    // placed takes the pieces back.
    let (targets, grids): (Vec<PathBuf>, Vec<&formats::Grid>) = match &args.tree {
        Some(t) => (
            vec![t.clone(), args.output.clone()],
            vec![&tree_grid, &split_grid],
        ),
        None => (vec![args.output.clone()], vec![&split_grid]),
    };
    let stem = args
        .output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "split".into());
    let pieces = match &args.pieces {
        Some(_) => output::leaf_pieces(&result.mesh, &result.tree),
        None => Vec::new(),
    };
    let mut pieces_written: Option<(PathBuf, PathBuf)> = None;
    let mut pieces_error: Option<anyhow::Error> = None;
    let last = targets.len() - 1;
    let placed = formats::atomic::write_all_or_none(&targets, |i, w| -> anyhow::Result<()> {
        grids[i].validate().map_err(|m| {
            anyhow::anyhow!(
                "{}: refusing to write an invalid mesh: {m}",
                targets[i].display()
            )
        })?;
        formats::write_to(w, formats::Format::Vtu, grids[i], &wopts)
            .map_err(|e| e.with_file(&targets[i]))?;
        if let (true, Some(dir)) = (i == last, &args.pieces) {
            match output::write_pieces(dir, &stem, &pieces, &wopts) {
                Ok(p) => pieces_written = Some(p),
                Err(e) => {
                    pieces_error = Some(e);
                    anyhow::bail!("the leaf pieces could not be written");
                }
            }
        }
        Ok(())
    });
    if let Some(e) = pieces_error {
        return Err(e);
    }
    if let Err(e) = placed {
        if let (Some(dir), Some(_)) = (&args.pieces, &pieces_written) {
            output::remove_pieces(dir, &stem, pieces.len(), true);
        }
        let names: Vec<String> = targets.iter().map(|t| t.display().to_string()).collect();
        return Err(e.context(format!("writing {}", names.join(" and "))));
    }
    if let (Some((pvtu, vtm)), false) = (&pieces_written, args.json) {
        eprintln!(
            "tetkit: wrote {} leaf pieces, named by {} and {}",
            pieces.len(),
            pvtu.display(),
            vtm.display()
        );
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&result.report)?);
    } else {
        eprint!("{}", table(&result.report));
    }
    Ok(())
}

/// The report as a small table.
pub fn table(r: &PartitionReport) -> String {
    let mut s = String::new();
    let strategy = match r.strategy {
        Strategy::Paper => "paper",
        Strategy::Cost => "cost",
    };
    s += &format!(
        "partition ({strategy}): {} leaves, depth {}, tets {} -> {} (growth {:.3}x), points {} -> {}\n",
        r.leaves, r.depth, r.tets_before, r.tets_after, r.growth, r.points_before, r.points_after
    );
    s += &format!(
        "balance {:.3} (largest leaf {}, smallest {}), neighbour tets split for conformity {}, {:.3} s\n",
        r.balance, r.largest_leaf, r.smallest_leaf, r.neighbour_splits, r.seconds
    );
    s += "depth  split  no plane  tets after  seconds\n";
    for l in &r.levels {
        s += &format!(
            "{:>5}  {:>5}  {:>8}  {:>10}  {:>7.3}\n",
            l.depth, l.split, l.no_plane, l.tets_after, l.seconds
        );
    }
    s
}
