//! `m2rc lsp`: not built yet (see the open issues).

use anyhow::{Result, bail};
use clap::Args;
use std::process::ExitCode;

#[derive(Args)]
pub struct LspArgs {}

pub fn run(_args: LspArgs) -> Result<ExitCode> {
    bail!("`m2rc lsp` is not available yet in this build")
}
