//! `m2rc map ...`: not built yet (see the open issues).

use anyhow::{Result, bail};
use clap::Subcommand;
use std::process::ExitCode;

#[derive(Subcommand)]
pub enum MapCommand {
    /// Placeholder until the subcommands land.
    Todo,
}

pub fn run(_command: MapCommand) -> Result<ExitCode> {
    bail!("`m2rc map` is not available yet in this build")
}
