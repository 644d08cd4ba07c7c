//! `m2rc lsp`: the .m2r language server over stdio (for editors). The engine lives in
//! `m2rc_compiler::lsp`; this shell opens the transport (`crate::lsp_stdio`, which bounds message
//! sizes and answers malformed JSON-RPC) and picks the vocabulary.
//!
//! Exit status: 0 after `shutdown` then `exit` (or when the client closes the stream between
//! messages), 1 after an `exit` without `shutdown`, as the protocol says, or a protocol error; 2
//! when the stream cannot be framed (a malformed header, a message cut off), said on standard
//! error.

use anyhow::{Context, Result};
use clap::Args;
use m2rc_compiler::lsp::LspError;
use m2rc_stdlib::vocab::Vocabulary;
use std::io::IsTerminal;
use std::process::ExitCode;

#[derive(Args)]
pub struct LspArgs {
    /// Check category names against this map's categories (a Map2Route map, a ProcTHOR house,
    /// `demo`, or `-`) instead of the benchmark's 97 object and 4 room categories.
    #[arg(long)]
    map: Option<String>,
}

pub fn run(args: LspArgs) -> Result<ExitCode> {
    let vocab = match &args.map {
        Some(path) => Vocabulary::from_map(&crate::io::load_map(path)?),
        None => Vocabulary::benchmark(),
    };
    if std::io::stdin().is_terminal() {
        eprintln!(
            "m2rc lsp is a language server: it speaks the Language Server Protocol over stdin and \
             stdout. Configure your editor to start `m2rc lsp` for .m2r files."
        );
    }
    let (connection, transport) = crate::lsp_stdio::stdio();
    let result = m2rc_compiler::lsp::serve(&connection, &vocab);
    drop(connection);
    let broken = transport.broken();
    transport.join();
    if let Some(why) = broken {
        return Err(crate::io::unusable(anyhow::anyhow!(
            "language server: malformed message from the client: {why}; stopped reading"
        )));
    }
    match result {
        Ok(()) => Ok(ExitCode::SUCCESS),
        Err(LspError::ExitWithoutShutdown) => Ok(ExitCode::from(1)),
        Err(e) => Err(e).context("language server protocol error"),
    }
}
