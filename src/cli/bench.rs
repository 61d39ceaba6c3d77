//! `tetkit bench`: benchmarks, one subcommand each (`bench io`, ...), each in its own file under
//! `bench/`. Speed is measured here, never asserted in tests.

mod common;
mod gpu;
mod io;
mod legacy;

use clap::{Args, Subcommand};

#[derive(Args, Debug)]
pub struct BenchArgs {
    #[command(subcommand)]
    pub which: BenchCommand,
}

#[derive(Subcommand, Debug)]
pub enum BenchCommand {
    /// Read and write a .vtu (appended raw and zlib): time, throughput and peak memory.
    Io(io::IoArgs),
    /// Read a legacy .vtk and write it back as binary 5.1 and 4.2: best times (VTK beside it:
    /// scripts/bench_legacy.py).
    Legacy(legacy::LegacyArgs),
    /// Frame time of GPU projected tetrahedra (sort + upload + draw + readback) against the CPU
    /// path on generated jittered grids.
    Gpu(gpu::GpuBenchArgs),
}

pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    match &args.which {
        BenchCommand::Io(a) => io::run(a),
        BenchCommand::Legacy(a) => legacy::run(a),
        BenchCommand::Gpu(a) => gpu::run(a),
    }
}
