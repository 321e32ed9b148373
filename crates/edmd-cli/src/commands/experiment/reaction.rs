//! `edmd experiment reaction` (being written).

use anyhow::Result;
use clap::Args;

use super::common::CommonArgs;

/// Options of `edmd experiment reaction`.
#[derive(Debug, Args)]
pub struct ReactionArgs {
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// Runs the experiment.
pub fn run(_args: &ReactionArgs) -> Result<()> {
    anyhow::bail!("experiment reaction: not written yet")
}
