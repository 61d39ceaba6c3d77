//! Command-line interface: argument parsing and one thin function per subcommand.

mod convert;
mod info;

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
    /// Convert between VTU, PVTU, legacy VTK and TetGen, optionally tetrahedralizing.
    Convert(convert::ConvertArgs),
}

/// Runs the command line; errors go to stderr with a non-zero exit code.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Info(a) => info::run(&a),
        Command::Convert(a) => convert::run(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tetkit: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

/// Reads a mesh from a path, or from stdin for `-` (VTU or legacy VTK, sniffed from the content).
pub fn read_input(path: &std::path::Path) -> anyhow::Result<formats::Grid> {
    use anyhow::Context;
    if path.as_os_str() == "-" {
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(&mut std::io::stdin().lock(), &mut bytes)
            .context("reading stdin")?;
        let format = formats::sniff(&bytes)
            .ok_or_else(|| anyhow::anyhow!("<stdin>: byte 0: not a VTU or legacy VTK stream"))?;
        return formats::read_bytes(&bytes, format).map_err(|mut e| {
            e.file = Some("<stdin>".into());
            e.into()
        });
    }
    Ok(formats::read(path)?)
}
