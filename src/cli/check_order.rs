//! `tetkit check-order`: ray-order violations of a visibility order, independent of the sort code.

use clap::Args;

#[derive(Args, Debug)]
pub struct CheckOrderArgs {}

pub fn run(_args: &CheckOrderArgs) -> anyhow::Result<()> {
    anyhow::bail!("not implemented yet")
}
