//! `m2rc lsp`: the .m2r language server over stdio (for editors). The engine lives in
//! `m2rc_compiler::lsp`; this shell only opens the transport and picks the vocabulary.

use anyhow::{Context, Result};
use clap::Args;
use m2rc_stdlib::vocab::Vocabulary;
use std::io::IsTerminal;
use std::process::ExitCode;

#[derive(Args)]
pub struct LspArgs {
    /// Check category names against this map's categories (a Map2Route map, a ProcTHOR house, or
    /// `demo`) instead of the benchmark's 97 object and 4 room categories.
    #[arg(long)]
    map: Option<String>,
}

pub fn run(args: LspArgs) -> Result<ExitCode> {
    let vocab = match &args.map {
        Some(path) => {
            let map = m2rc_stdlib::load::load_map(path)
                .with_context(|| format!("cannot load map {path}"))?;
            Vocabulary::from_map(&map)
        }
        None => Vocabulary::benchmark(),
    };
    if std::io::stdin().is_terminal() {
        eprintln!(
            "m2rc lsp is a language server: it speaks the Language Server Protocol over stdin and \
             stdout. Configure your editor to start `m2rc lsp` for .m2r files."
        );
    }
    let (connection, io_threads) = lsp_server::Connection::stdio();
    m2rc_compiler::lsp::serve(&connection, &vocab).context("language server protocol error")?;
    drop(connection);
    io_threads.join().context("language server I/O")?;
    Ok(ExitCode::SUCCESS)
}
