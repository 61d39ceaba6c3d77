//! `tetkit bench io`: times reading and writing a .vtu as appended raw and as zlib, with the peak
//! memory of each step against the size of the mesh in memory. scripts/bench_io.py makes the
//! 4.85M-tet mesh and runs VTK 9.1 on the same files in the same run.

use anyhow::Context;
use clap::Args;
use formats::{Compression, Encoding, Grid, WriteOptions};
use serde_json::json;
use std::path::PathBuf;
use std::time::Instant;

#[derive(Args, Debug)]
pub struct IoArgs {
    /// A .vtu to read (any encoding); it is also written raw and zlib into --dir and read back.
    pub input: PathBuf,
    /// Folder for the files written (default: beside the input).
    #[arg(long)]
    pub dir: Option<PathBuf>,
    /// Runs per step; the best time is reported.
    #[arg(long, default_value_t = 3)]
    pub repeat: usize,
    /// Print JSON (for scripts/bench_io.py) instead of a table.
    #[arg(long)]
    pub json: bool,
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

/// Returns freed heap to the system and resets the kernel's peak-RSS mark (Linux: `5` into
/// /proc/self/clear_refs), so each step's peak is its own and not the last step's leftovers.
fn reset_peak() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim only releases free memory held by the allocator.
    unsafe {
        libc::malloc_trim(0);
    }
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// Peak resident memory since the last reset, in bytes (Linux VmHWM).
fn peak_rss() -> Option<usize> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: usize = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

struct Step {
    name: String,
    best_s: f64,
    /// Peak resident memory of the process during the step (the largest over the runs).
    peak: Option<usize>,
}

fn time<T>(
    name: &str,
    repeat: usize,
    mut f: impl FnMut() -> anyhow::Result<T>,
) -> anyhow::Result<(Step, T)> {
    let mut best = f64::INFINITY;
    let mut peak = None;
    let mut last = None;
    for _ in 0..repeat.max(1) {
        drop(last.take());
        reset_peak();
        let t = Instant::now();
        let v = f()?;
        best = best.min(t.elapsed().as_secs_f64());
        if let Some(p) = peak_rss() {
            peak = Some(peak.map_or(p, |e: usize| e.max(p)));
        }
        last = Some(v);
    }
    let v = last.context("no run")?;
    Ok((
        Step {
            name: name.to_string(),
            best_s: best,
            peak,
        },
        v,
    ))
}

pub fn run(args: &IoArgs) -> anyhow::Result<()> {
    let dir = match &args.dir {
        Some(d) => d.clone(),
        None => args
            .input
            .parent()
            .map(|p| p.to_path_buf())
            .unwrap_or_default(),
    };
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
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
