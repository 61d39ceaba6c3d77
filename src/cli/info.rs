//! `tetkit info`: what a mesh file holds.

use clap::Args;
use formats::{cell_type, Attributes, DataArray, Grid};
use formats::{exodus, pvd};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

#[derive(Args, Debug)]
pub struct InfoArgs {
    /// Mesh file (.vtu, .pvtu, .vtk, .node/.ele, .mesh, .msh, .exo, .vtkhdf, .vtm, .pvd, .vti/.vtr/.vts,
    /// FILE.pvd@STEP, FILE.exo@STEP), or - for stdin.
    pub input: PathBuf,
    /// Print JSON for scripts.
    #[arg(long)]
    pub json: bool,
}

/// NaN and infinite values of a float array (the range leaves them out, as VTK's finite range
/// does, so they are counted apart rather than hidden).
fn non_finite(a: &DataArray) -> (usize, usize) {
    if !a.data.scalar_type().is_some_and(|t| t.is_float()) {
        return (0, 0);
    }
    (0..a.data.len()).fold((0, 0), |(nan, inf), i| {
        let v = a.data.get_f64(i);
        (nan + v.is_nan() as usize, inf + v.is_infinite() as usize)
    })
}

/// The roles (Scalars, Vectors, ...) `a` is the active array of.
fn roles(attrs: &Attributes, a: &DataArray) -> Vec<&'static str> {
    attrs
        .active
        .iter()
        .filter(|(_, n)| *n == a.name)
        .map(|(r, _)| r.xml_name())
        .collect()
}

fn array_json(a: &DataArray, attrs: Option<&Attributes>) -> Value {
    let range = a.magnitude_range();
    let (nan, inf) = non_finite(a);
    json!({
        "name": a.name,
        "type": a.data.type_name(),
        "components": a.components,
        "component_names": a.component_names,
        "tuples": a.tuples(),
        "range": range.map(|(lo, hi)| vec![lo, hi]),
        "nan": nan,
        "inf": inf,
        "active": attrs.map(|t| roles(t, a)).unwrap_or_default(),
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
        "point_data": grid.point_data.arrays.iter().map(|a| array_json(a, Some(&grid.point_data))).collect::<Vec<_>>(),
        "cell_data": grid.cell_data.arrays.iter().map(|a| array_json(a, Some(&grid.cell_data))).collect::<Vec<_>>(),
        "field_data": grid.field_data.iter().map(|a| array_json(a, None)).collect::<Vec<_>>(),
    })
}

fn print_arrays(title: &str, arrays: &[DataArray], attrs: Option<&Attributes>) {
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
        let mut names = if a.component_names.is_empty() {
            String::new()
        } else {
            format!("  components ({})", a.component_names.join(", "))
        };
        let (nan, inf) = non_finite(a);
        if nan + inf > 0 {
            names.push_str(&format!("  ({nan} NaN, {inf} infinite)"));
        }
        let active = attrs.map(|t| roles(t, a)).unwrap_or_default();
        if !active.is_empty() {
            names.push_str(&format!("  active {}", active.join(", ")));
        }
        println!(
            "  {:<24} {:<8} {:>2} comp  {:>10} tuples  range {range}{mag}{names}",
            a.name,
            a.data.type_name(),
            a.components,
            a.tuples()
        );
    }
}

/// The time steps of a .pvd, Exodus or VTKHDF input (`FILE.pvd`, `FILE.pvd@K`, `FILE.exo`,
/// `FILE.exo@K`, `FILE.vtkhdf@K`) and the one read, else `None` (also for an Exodus or VTKHDF
/// file without steps). Exodus and VTKHDF steps name no files.
///
/// `grid` is what was read from `input`: an Exodus file's times are its `exodus:time` field
/// array (which the reader adds exactly when the file has steps) rather than a second read.
fn time_steps(input: &Path, grid: &Grid) -> anyhow::Result<Option<(Vec<pvd::Step>, usize)>> {
    use formats::{vtkhdf, Format};
    if let Some((file, sel)) = selected(input, vtkhdf::split_selector, Format::VtkHdf) {
        return Ok(timed_steps(vtkhdf::times(&file)?, sel));
    }
    if let Some((_, sel)) = selected(input, exodus::split_selector, Format::Exodus) {
        let times = grid
            .field_data
            .iter()
            .find(|a| a.name == exodus::names::TIME)
            .map_or_else(Vec::new, |a| {
                (0..a.data.len()).map(|i| a.data.get_f64(i)).collect()
            });
        return Ok(timed_steps(times, sel));
    }
    let Some((file, sel)) = selected(input, pvd::split_selector, Format::Pvd) else {
        return Ok(None);
    };
    let steps = pvd::steps(&file)?;
    let k = sel.index_of(steps.len());
    Ok(Some((steps, k)))
}

/// `FILE@K` split by `split`, or a plain `FILE` of `format` as its step 0; `None` for other
/// inputs.
fn selected(
    input: &Path,
    split: fn(&Path) -> Option<(PathBuf, pvd::Selector)>,
    format: formats::Format,
) -> Option<(PathBuf, pvd::Selector)> {
    split(input).or_else(|| {
        (formats::Format::from_path(input).ok() == Some(format))
            .then(|| (input.to_path_buf(), pvd::Selector::Index(0)))
    })
}

/// Steps that name no files (Exodus, VTKHDF) from their times, and the one `sel` reads; `None`
/// when there are none (a file without time steps).
fn timed_steps(times: Vec<f64>, sel: pvd::Selector) -> Option<(Vec<pvd::Step>, usize)> {
    if times.is_empty() {
        return None;
    }
    let k = sel.index_of(times.len());
    let steps = times
        .into_iter()
        .map(|t| pvd::Step {
            time: Some(t),
            entries: Vec::new(),
        })
        .collect();
    Some((steps, k))
}

fn steps_json(steps: &[pvd::Step], read: usize) -> Value {
    json!({
        "read": read,
        "steps": steps.iter().enumerate().map(|(i, s)| json!({
            "index": i,
            "time": s.time,
            "files": s.entries.iter().map(|e| e.file.clone()).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
    })
}

fn print_steps(input: &Path, steps: &[pvd::Step], read: usize) {
    let base = pvd::split_selector(input)
        .or_else(|| exodus::split_selector(input))
        .or_else(|| formats::vtkhdf::split_selector(input))
        .map_or_else(|| input.to_path_buf(), |(f, _)| f);
    println!(
        "time steps: {} (read one with {}@K; this is step {read})",
        steps.len(),
        base.display()
    );
    for (i, s) in steps.iter().enumerate() {
        let mark = if i == read { '*' } else { ' ' };
        let time = s.time.map_or_else(|| "-".to_string(), |t| format!("{t}"));
        let files: Vec<&str> = s.entries.iter().map(|e| e.file.as_str()).collect();
        println!("  {mark}{i:>4}  t = {time:<14} {}", files.join(", "));
    }
}

pub fn run(args: &InfoArgs) -> anyhow::Result<()> {
    // The grid first: its reader names what is wrong with a file best.
    let grid = super::read_input(&args.input)?;
    let steps = time_steps(&args.input, &grid)?;
    if args.json {
        let mut v = summary(&grid);
        v["file"] = json!(args.input.display().to_string());
        if let Some((s, k)) = &steps {
            v["time_steps"] = steps_json(s, *k);
        }
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    println!("file:    {}", args.input.display());
    if let Some((s, k)) = &steps {
        print_steps(&args.input, s, *k);
    }
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
    print_arrays(
        "point data",
        &grid.point_data.arrays,
        Some(&grid.point_data),
    );
    print_arrays("cell data", &grid.cell_data.arrays, Some(&grid.cell_data));
    print_arrays("field data", &grid.field_data, None);
    Ok(())
}
