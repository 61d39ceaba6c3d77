//! `tetkit info`: what a mesh file holds.

use clap::Args;
use formats::{cell_type, DataArray, Grid};
use serde_json::{json, Value};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct InfoArgs {
    /// Mesh file (.vtu, .pvtu, .vtk, .node/.ele), or - for stdin.
    pub input: PathBuf,
    /// Print JSON for scripts.
    #[arg(long)]
    pub json: bool,
}

fn array_json(a: &DataArray) -> Value {
    let range = a.magnitude_range();
    json!({
        "name": a.name,
        "type": a.data.type_name(),
        "components": a.components,
        "component_names": a.component_names,
        "tuples": a.tuples(),
        "range": range.map(|(lo, hi)| vec![lo, hi]),
    })
}

/// The summary `info` prints, as JSON.
pub fn summary(grid: &Grid) -> Value {
    let types: Vec<Value> = grid
        .cell_type_counts()
        .into_iter()
        .map(|(t, n)| json!({"type": t, "name": cell_type::name(t), "count": n}))
        .collect();
    json!({
        "points": grid.num_points(),
        "cells": grid.num_cells(),
        "points_type": grid.points.data.type_name(),
        "cell_types": types,
        "bounds": grid.bounds().map(|b| b.to_vec()),
        "point_data": grid.point_data.arrays.iter().map(array_json).collect::<Vec<_>>(),
        "cell_data": grid.cell_data.arrays.iter().map(array_json).collect::<Vec<_>>(),
        "field_data": grid.field_data.iter().map(array_json).collect::<Vec<_>>(),
    })
}

fn print_arrays(title: &str, arrays: &[DataArray]) {
    if arrays.is_empty() {
        return;
    }
    println!("{title}:");
    for a in arrays {
        let range = match a.magnitude_range() {
            Some((lo, hi)) => format!("[{lo:.6e}, {hi:.6e}]"),
            None => "-".to_string(),
        };
        let mag = if a.components > 1 { " (magnitude)" } else { "" };
        let names = if a.component_names.is_empty() {
            String::new()
        } else {
            format!("  components ({})", a.component_names.join(", "))
        };
        println!(
            "  {:<24} {:<8} {:>2} comp  {:>10} tuples  range {range}{mag}{names}",
            a.name,
            a.data.type_name(),
            a.components,
            a.tuples()
        );
    }
}

pub fn run(args: &InfoArgs) -> anyhow::Result<()> {
    let grid = super::read_input(&args.input)?;
    if args.json {
        let mut v = summary(&grid);
        v["file"] = json!(args.input.display().to_string());
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    println!("file:    {}", args.input.display());
    println!(
        "points:  {} ({})",
        grid.num_points(),
        grid.points.data.type_name()
    );
    println!("cells:   {}", grid.num_cells());
    for (t, n) in grid.cell_type_counts() {
        println!("  {:<24} {n}", cell_type::name(t));
    }
    if let Some(b) = grid.bounds() {
        println!(
            "bounds:  x [{:.9e}, {:.9e}]  y [{:.9e}, {:.9e}]  z [{:.9e}, {:.9e}]",
            b[0], b[1], b[2], b[3], b[4], b[5]
        );
    }
    print_arrays("point data", &grid.point_data.arrays);
    print_arrays("cell data", &grid.cell_data.arrays);
    print_arrays("field data", &grid.field_data);
    Ok(())
}
