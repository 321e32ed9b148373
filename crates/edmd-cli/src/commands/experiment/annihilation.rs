//! `edmd experiment annihilation` (being written).

use anyhow::Result;
use clap::Args;

use super::common::CommonArgs;

/// Options of `edmd experiment annihilation`.
#[derive(Debug, Args)]
pub struct AnnihilationArgs {
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// Runs the experiment.
pub fn run(_args: &AnnihilationArgs) -> Result<()> {
    anyhow::bail!("experiment annihilation: not written yet")
}
