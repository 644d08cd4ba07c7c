//! `m2rc bench ...`: not built yet (see the open issues).

use anyhow::{Result, bail};
use clap::Subcommand;
use std::process::ExitCode;

#[derive(Subcommand)]
pub enum BenchCommand {
    /// Placeholder until the subcommands land.
    Todo,
}

pub fn run(_command: BenchCommand) -> Result<ExitCode> {
    bail!("`m2rc bench` is not available yet in this build")
}
