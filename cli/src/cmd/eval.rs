//! `m2rc eval`: not built yet (see the open issues).

use anyhow::{Result, bail};
use clap::Args;
use std::process::ExitCode;

#[derive(Args)]
pub struct EvalArgs {}

pub fn run(_args: EvalArgs) -> Result<ExitCode> {
    bail!("`m2rc eval` is not available yet in this build")
}
