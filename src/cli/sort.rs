//! `tetkit sort`: visibility order of the tets for a camera, written as cell data.

use clap::Args;

#[derive(Args, Debug)]
pub struct SortArgs {}

pub fn run(_args: &SortArgs) -> anyhow::Result<()> {
    anyhow::bail!("not implemented yet")
}
