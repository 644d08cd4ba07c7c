//! `m2rc check`: parse, resolve, type-check and scope-check a `.m2r` program.
//!
//! Exit status: 0 when there is no error (warnings allowed), 1 when the program has errors, 2 when
//! the file or the map cannot be read. Text diagnostics go to standard error (coloured only on a
//! terminal); `--format json` prints one JSON array to standard output (schema in
//! `docs/diagnostics.md`).

use anyhow::Result;
use clap::{Args, ValueEnum};
use m2rc_compiler::check;
use m2rc_compiler::diagnostic::{render_text, render_text_colored, to_json};
use m2rc_stdlib::vocab::Vocabulary;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Format {
    Text,
    Json,
}

#[derive(Args)]
pub struct CheckArgs {
    /// The program to check; `-` reads standard input.
    #[arg(value_name = "FILE")]
    pub file: PathBuf,
    /// Check category names against this map's vocabulary (a map or house file, `demo`, or `-`)
    /// instead of the benchmark's 97 object and 4 room categories.
    #[arg(long, value_name = "MAP")]
    pub map: Option<String>,
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub format: Format,
}

pub fn run(args: CheckArgs) -> Result<ExitCode> {
    let (name, source, vocab) = match inputs(&args) {
        Ok(v) => v,
        Err(err) => return Err(crate::io::unusable(err)),
    };
    let result = check(&source, &vocab);
    match args.format {
        Format::Json => crate::io::stdout(&format!("{}\n", to_json(&result.diagnostics, &source)))?,
        Format::Text => {
            let text = if std::io::stderr().is_terminal() {
                render_text_colored(&result.diagnostics, &name, &source)
            } else {
                render_text(&result.diagnostics, &name, &source)
            };
            eprint!("{text}");
            let errors = result.errors().count();
            let warnings = result.diagnostics.len() - errors;
            if errors > 0 || warnings > 0 {
                eprintln!("{name}: {errors} error(s), {warnings} warning(s)");
            }
        }
    }
    Ok(if result.has_errors() {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

/// The display name and text of the program, and the vocabulary to check against.
fn inputs(args: &CheckArgs) -> Result<(String, String, Vocabulary)> {
    let name = crate::io::display_name(&args.file);
    let source = crate::io::read_to_string(&args.file)?;
    m2rc_benchmark::limits::check_program_size(&source)
        .map_err(|m| anyhow::anyhow!("{name}: {m}"))?;
    let vocab = match &args.map {
        Some(m) => {
            let map = crate::io::load_map(m)?;
            Vocabulary::from_map(&map)
        }
        None => Vocabulary::benchmark(),
    };
    Ok((name, source, vocab))
}
