//! `tetkit convert`: any supported format to any other, optionally tetrahedralizing.

use anyhow::{bail, Context};
use clap::{Args, ValueEnum};
use formats::{Compression, Encoding, Format, LegacyVersion, WriteOptions};
use std::path::PathBuf;

use crate::mesh::tetrahedralize::tetrahedralize;

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum EncodingArg {
    Appended,
    Binary,
    Ascii,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum CompressArg {
    None,
    Zlib,
    Lz4,
    Lzma,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum LegacyVersionArg {
    #[value(name = "4.2")]
    V42,
    #[value(name = "5.1")]
    V51,
}

#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// Input mesh (.vtu, .pvtu, .vtk, .node/.ele), or - for stdin (VTU or legacy VTK).
    pub input: PathBuf,
    /// Output mesh; the extension picks the format. - writes to stdout (see --to).
    pub output: PathBuf,
    /// VTU: appended raw (ParaView's default), inline base64 binary, or ascii. Legacy: binary or ascii.
    #[arg(long, value_enum, default_value = "appended")]
    pub encoding: EncodingArg,
    /// Compression of VTU binary data.
    #[arg(long = "compress", value_enum, default_value = "none")]
    pub compress: CompressArg,
    /// Legacy VTK file version to write.
    #[arg(long, value_enum, default_value = "5.1")]
    pub legacy_version: LegacyVersionArg,
    /// Split hexahedra, wedges, pyramids, voxels and quadratic tets into conforming linear tets.
    #[arg(long)]
    pub tetrahedralize: bool,
    /// Output format when writing to stdout: vtu or vtk.
    #[arg(long, default_value = "vtu")]
    pub to: String,
}

impl ConvertArgs {
    pub fn write_options(&self) -> WriteOptions {
        WriteOptions {
            encoding: match self.encoding {
                EncodingArg::Appended => Encoding::Appended,
                EncodingArg::Binary => Encoding::Binary,
                EncodingArg::Ascii => Encoding::Ascii,
            },
            compression: match self.compress {
                CompressArg::None => Compression::None,
                CompressArg::Zlib => Compression::Zlib,
                CompressArg::Lz4 => Compression::Lz4,
                CompressArg::Lzma => Compression::Lzma,
            },
            legacy_version: match self.legacy_version {
                LegacyVersionArg::V42 => LegacyVersion::V42,
                LegacyVersionArg::V51 => LegacyVersion::V51,
            },
        }
    }
}

pub fn run(args: &ConvertArgs) -> anyhow::Result<()> {
    let to_stdout = args.output.as_os_str() == "-";
    // Decide the output format before reading, so a bad name fails fast and writes nothing.
    let format = if to_stdout {
        Format::from_name(&args.to)
            .filter(|f| matches!(f, Format::Vtu | Format::Legacy))
            .with_context(|| format!("--to {}: stdout takes vtu or vtk", args.to))?
    } else {
        Format::from_path(&args.output)?
    };
    let mut grid = super::read_input(&args.input)?;
    if args.tetrahedralize {
        // TetGen files hold only tets; every other format keeps the boundary cells too.
        let keep_lower = format != Format::TetGen;
        let (tets, report) = tetrahedralize(&grid, keep_lower)
            .with_context(|| format!("{}: tetrahedralizing", args.input.display()))?;
        for line in report.lines() {
            eprintln!("tetkit: {line}");
        }
        grid = tets;
    }
    let opts = args.write_options();
    if to_stdout {
        // Encode fully before writing anything, so a failure leaves no partial stream.
        let mut buf = Vec::new();
        formats::write_to(&mut buf, format, &grid, &opts)?;
        let mut out = std::io::stdout().lock();
        std::io::Write::write_all(&mut out, &buf)
            .and_then(|_| std::io::Write::flush(&mut out))
            .context("writing stdout")?;
        return Ok(());
    }
    if format == Format::TetGen {
        if let Some(i) = grid
            .cells
            .types
            .iter()
            .position(|&t| t != formats::cell_type::TETRA)
        {
            bail!(
                "{}: TetGen files hold only linear tetrahedra, but cell {i} is a {}; add --tetrahedralize",
                args.output.display(),
                formats::cell_type::name(grid.cells.types[i])
            );
        }
    }
    formats::write(&args.output, &grid, &opts)?;
    Ok(())
}
