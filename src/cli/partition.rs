//! `tetkit partition`: K-D tree split of a tet mesh, tree and pieces written for ParaView.

use clap::Args;

#[derive(Args, Debug)]
pub struct PartitionArgs {}

pub fn run(_args: &PartitionArgs) -> anyhow::Result<()> {
    anyhow::bail!("not implemented yet")
}
