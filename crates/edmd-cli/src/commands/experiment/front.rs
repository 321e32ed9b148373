//! `edmd experiment front` (being written).

use anyhow::Result;
use clap::Args;

use super::common::CommonArgs;

/// Options of `edmd experiment front`.
#[derive(Debug, Args)]
pub struct FrontArgs {
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// Runs the experiment.
pub fn run(_args: &FrontArgs) -> Result<()> {
    anyhow::bail!("experiment front: not written yet")
}
