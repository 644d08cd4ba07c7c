//! `m2rc check`: not built yet (see the open issues).

use anyhow::{Result, bail};
use clap::Args;
use std::process::ExitCode;

#[derive(Args)]
pub struct CheckArgs {}

pub fn run(_args: CheckArgs) -> Result<ExitCode> {
    bail!("`m2rc check` is not available yet in this build")
}
