//! `tetkit bench io`: times reading and writing a .vtu as appended raw and as zlib, with the peak
//! memory of each step against the size of the mesh in memory. scripts/bench_io.py makes the
//! 4.85M-tet mesh and runs VTK 9.1 on the same files in the same run.

use super::common::{time, FileArgs};
use clap::Args;
use formats::{Compression, Encoding, Grid, WriteOptions};
use serde_json::json;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct IoArgs {
    /// A .vtu (any encoding), also written raw and zlib into --dir and read back.
    #[command(flatten)]
    pub files: FileArgs,
}

/// Bytes the mesh takes in memory (points, cells, every array).
fn mesh_bytes(g: &Grid) -> usize {
    let arrays = g
        .point_data
        .arrays
        .iter()
        .chain(&g.cell_data.arrays)
        .chain(&g.field_data)
        .chain(std::iter::once(&g.points));
    let data: usize = arrays
        .map(|a| match a.data.scalar_type() {
            Some(t) => t.size() * a.data.len(),
            None => a.data.native_bytes().len(),
        })
        .sum();
    data + g.cells.types.len() + 8 * (g.cells.offsets.len() + g.cells.connectivity.len())
}

pub fn run(args: &IoArgs) -> anyhow::Result<()> {
    let args = &args.files;
    let dir = args.out_dir()?;
    let raw = dir.join("tetkit_bench_raw.vtu");
    let zlib = dir.join("tetkit_bench_zlib.vtu");
    let mut steps = Vec::new();

    let (s, grid) = time("read input", args.repeat, || {
        Ok(formats::read(&args.input)?)
    })?;
    steps.push(s);
    let mesh = mesh_bytes(&grid);
    let raw_opts = WriteOptions::default();
    let zlib_opts = WriteOptions {
        encoding: Encoding::Appended,
        compression: Compression::Zlib,
        ..WriteOptions::default()
    };
    let (s, ()) = time("write appended raw", args.repeat, || {
        Ok(formats::write(&raw, &grid, &raw_opts)?)
    })?;
    steps.push(s);
    let (s, ()) = time("write appended zlib", args.repeat, || {
        Ok(formats::write(&zlib, &grid, &zlib_opts)?)
    })?;
    steps.push(s);
    let counts = (grid.num_points(), grid.num_cells());
    drop(grid);
    let (s, g) = time("read appended raw", args.repeat, || {
        Ok(formats::read(&raw)?)
    })?;
    steps.push(s);
    drop(g);
    let (s, g) = time("read appended zlib", args.repeat, || {
        Ok(formats::read(&zlib)?)
    })?;
    steps.push(s);
    drop(g);

    let size = |p: &PathBuf| std::fs::metadata(p).map(|m| m.len()).unwrap_or(0);
    if args.json {
        let v = json!({
            "points": counts.0,
            "cells": counts.1,
            "mesh_bytes": mesh,
            "threads": rayon::current_num_threads(),
            "raw_file_bytes": size(&raw),
            "zlib_file_bytes": size(&zlib),
            "steps": steps.iter().map(|s| json!({
                "name": s.name,
                "seconds": s.best_s,
                "peak_rss_bytes": s.peak,
            })).collect::<Vec<_>>(),
        });
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    println!(
        "mesh: {} points, {} cells, {:.1} MB in memory; {} threads",
        counts.0,
        counts.1,
        mesh as f64 / 1e6,
        rayon::current_num_threads()
    );
    println!(
        "files: raw {:.1} MB, zlib {:.1} MB (in {})",
        size(&raw) as f64 / 1e6,
        size(&zlib) as f64 / 1e6,
        dir.display()
    );
    println!(
        "{:<22} {:>9} {:>14} {:>10}",
        "step", "best s", "peak RSS MB", "x mesh"
    );
    for s in &steps {
        let (mb, ratio) = match s.peak {
            Some(p) => (
                format!("{:.1}", p as f64 / 1e6),
                format!("{:.2}", p as f64 / mesh as f64),
            ),
            None => ("-".into(), "-".into()),
        };
        println!("{:<22} {:>9.3} {:>12} {:>10}", s.name, s.best_s, mb, ratio);
    }
    Ok(())
}
