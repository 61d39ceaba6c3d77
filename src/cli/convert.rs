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
    let mut grid = super::read_input(&args.input)?;
    if args.tetrahedralize {
        let (tets, report) = tetrahedralize(&grid, true)
            .with_context(|| format!("tetrahedralizing {}", args.input.display()))?;
        for (t, n) in &report.split {
            eprintln!(
                "tetkit: split {n} {} cells into tets",
                formats::cell_type::name(*t)
            );
        }
        grid = tets;
    }
    let opts = args.write_options();
    if args.output.as_os_str() == "-" {
        let format = Format::from_name(&args.to)
            .filter(|f| matches!(f, Format::Vtu | Format::Legacy))
            .with_context(|| format!("--to {}: stdout takes vtu or vtk", args.to))?;
        let mut out = std::io::BufWriter::new(std::io::stdout().lock());
        formats::write_to(&mut out, format, &grid, &opts)?;
        std::io::Write::flush(&mut out).context("writing stdout")?;
        return Ok(());
    }
    if Format::from_path(&args.output)? == Format::TetGen
        && grid
            .cells
            .types
            .iter()
            .any(|&t| t != formats::cell_type::TETRA)
    {
        bail!(
            "{}: TetGen files hold only tetrahedra; add --tetrahedralize",
            args.output.display()
        );
    }
    formats::write(&args.output, &grid, &opts)?;
    Ok(())
}
