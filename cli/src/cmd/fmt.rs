//! `m2rc fmt`: not built yet (see the open issues).

use anyhow::{Result, bail};
use clap::Args;
use std::process::ExitCode;

#[derive(Args)]
pub struct FmtArgs {}

pub fn run(_args: FmtArgs) -> Result<ExitCode> {
    bail!("`m2rc fmt` is not available yet in this build")
}
