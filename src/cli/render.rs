//! `tetkit render`: projected tetrahedra or ray-cast reference image of a tet mesh.

use clap::Args;

#[derive(Args, Debug)]
pub struct RenderArgs {}

pub fn run(_args: &RenderArgs) -> anyhow::Result<()> {
    anyhow::bail!("not implemented yet")
}
