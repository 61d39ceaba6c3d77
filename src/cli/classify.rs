//! `tetkit classify`: each tet's region code for a scene, written as cell data for ParaView.

use clap::Args;

#[derive(Args, Debug)]
pub struct ClassifyArgs {}

pub fn run(_args: &ClassifyArgs) -> anyhow::Result<()> {
    anyhow::bail!("not implemented yet")
}
