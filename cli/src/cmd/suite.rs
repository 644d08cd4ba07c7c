//! `m2rc suite ...`: not built yet (see the open issues).

use anyhow::{Result, bail};
use clap::Subcommand;
use std::process::ExitCode;

#[derive(Subcommand)]
pub enum SuiteCommand {
    /// Placeholder until the subcommands land.
    Todo,
}

pub fn run(_command: SuiteCommand) -> Result<ExitCode> {
    bail!("`m2rc suite` is not available yet in this build")
}
