//! `tetkit probe`: values of every array at given points, located with the O(N) grid.

use clap::Args;

#[derive(Args, Debug)]
pub struct ProbeArgs {}

pub fn run(_args: &ProbeArgs) -> anyhow::Result<()> {
    anyhow::bail!("not implemented yet")
}
