//! `tetkit bench legacy`: times reading a legacy .vtk and writing it back as binary 5.1 and 4.2
//! (and reading those), best of --repeat runs. scripts/bench_legacy.py makes the 4.85M-tet mesh
//! with VTK 9.1 and times VTK on the same files in the same run.

use super::common::{time, FileArgs};
use clap::Args;
use formats::{Encoding, LegacyVersion, WriteOptions};
use serde_json::json;

#[derive(Args, Debug)]
pub struct LegacyArgs {
    /// A legacy .vtk (any version and encoding), written back as binary 5.1 and 4.2.
    #[command(flatten)]
    pub files: FileArgs,
    /// Also write and read ASCII (slow on big meshes).
    #[arg(long)]
    pub ascii: bool,
}

/// Best time of `repeat` runs of `f`, and its last value.
fn best<T>(repeat: usize, f: impl FnMut() -> anyhow::Result<T>) -> anyhow::Result<(f64, T)> {
    let (step, v) = time("", repeat, f)?;
    Ok((step.best_s, v))
}

pub fn run(args: &LegacyArgs) -> anyhow::Result<()> {
    let ascii = args.ascii;
    let args = &args.files;
    let dir = args.out_dir()?;
    let mut steps: Vec<(String, f64)> = Vec::new();
    let (t, grid) = best(args.repeat, || Ok(formats::read(&args.input)?))?;
    steps.push(("read input".into(), t));
    let mut variants = vec![
        ("5.1 binary", LegacyVersion::V51, Encoding::Binary),
        ("4.2 binary", LegacyVersion::V42, Encoding::Binary),
    ];
    if ascii {
        variants.push(("5.1 ascii", LegacyVersion::V51, Encoding::Ascii));
    }
    for (name, legacy_version, encoding) in variants {
        let out = dir.join(format!(
            "tetkit_bench_{}.vtk",
            name.replace([' ', '.'], "_")
        ));
        let opts = WriteOptions {
            encoding,
            legacy_version,
            ..Default::default()
        };
        let (t, ()) = best(args.repeat, || Ok(formats::write(&out, &grid, &opts)?))?;
        steps.push((format!("write {name}"), t));
        let (t, back) = best(args.repeat, || Ok(formats::read(&out)?))?;
        anyhow::ensure!(
            back.num_points() == grid.num_points() && back.cells == grid.cells,
            "{} does not read back as written",
            out.display()
        );
        steps.push((format!("read {name}"), t));
        std::fs::remove_file(&out).ok();
    }
    if args.json {
        let v = json!({
            "input": args.input,
            "points": grid.num_points(),
            "cells": grid.num_cells(),
            "threads": rayon::current_num_threads(),
            "steps": steps.iter().map(|(n, t)| json!({"name": n, "best_s": t})).collect::<Vec<_>>(),
        });
        println!("{v}");
    } else {
        println!(
            "{}: {} points, {} cells, best of {} ({} threads)",
            args.input.display(),
            grid.num_points(),
            grid.num_cells(),
            args.repeat,
            rayon::current_num_threads()
        );
        for (n, t) in &steps {
            println!("  {n:<20} {t:>8.3} s");
        }
    }
    Ok(())
}
