//! `tetkit tradeoff`: every sort x integration mode against the ray-cast reference.

use clap::Args;

#[derive(Args, Debug)]
pub struct TradeoffArgs {}

pub fn run(_args: &TradeoffArgs) -> anyhow::Result<()> {
    anyhow::bail!("not implemented yet")
}
