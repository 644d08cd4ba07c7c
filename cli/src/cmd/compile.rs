//! `m2rc compile`: not built yet (see the open issues).

use anyhow::{Result, bail};
use clap::Args;
use std::process::ExitCode;

#[derive(Args)]
pub struct CompileArgs {}

pub fn run(_args: CompileArgs) -> Result<ExitCode> {
    bail!("`m2rc compile` is not available yet in this build")
}
