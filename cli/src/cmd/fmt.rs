//! `m2rc fmt`: rewrite `.m2r` files in the canonical style, keeping their comments.
//!
//! A file with parse errors is never rewritten: formatting a tree with error nodes would change
//! what the author wrote, so the errors are printed instead and the exit code is 1.

use crate::io::{read_to_string, write_atomic};
use anyhow::{Context, Result};
use clap::Args;
use m2rc_compiler::diagnostic::{Diagnostic, render_text};
use m2rc_grammar::{ParseError, parse, print_with_comments};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Args)]
pub struct FmtArgs {
    /// Files to format in place; `-` reads standard input and writes standard output.
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,
    /// Change nothing; list the files that are not formatted and exit with 1 if there are any.
    #[arg(long)]
    pub check: bool,
}

/// The canonical form of `source`, or its parse errors.
pub fn format_source(source: &str) -> Result<String, Vec<ParseError>> {
    let parsed = parse(source);
    if !parsed.errors.is_empty() {
        return Err(parsed.errors);
    }
    Ok(print_with_comments(
        &parsed.program,
        &parsed.comments,
        source,
    ))
}

pub fn run(args: FmtArgs) -> Result<ExitCode> {
    let mut failed = false;
    let mut unreadable = false;
    let mut unformatted = Vec::new();
    for path in &args.files {
        let stdin = path.as_os_str() == "-";
        let source = if stdin {
            let mut s = String::new();
            std::io::stdin()
                .read_to_string(&mut s)
                .context("cannot read standard input")?;
            s
        } else {
            match read_to_string(path) {
                Ok(s) => s,
                Err(err) => {
                    // Keep going: one unreadable file should not stop the others.
                    eprintln!("error: {err:#}");
                    unreadable = true;
                    continue;
                }
            }
        };
        let shown = if stdin {
            Path::new("<stdin>")
        } else {
            path.as_path()
        };
        let formatted = match format_source(&source) {
            Ok(f) => f,
            Err(errors) => {
                let diags: Vec<Diagnostic> = errors.iter().map(Diagnostic::from_parse).collect();
                eprint!(
                    "{}",
                    render_text(&diags, &shown.display().to_string(), &source)
                );
                eprintln!(
                    "{}: not formatted: {} parse error(s)",
                    shown.display(),
                    errors.len()
                );
                failed = true;
                continue;
            }
        };
        if args.check {
            if formatted != source {
                println!("{}", shown.display());
                unformatted.push(shown.to_path_buf());
            }
        } else if stdin {
            crate::io::stdout(&formatted)?;
        } else if formatted != source {
            write_atomic(path, formatted.as_bytes())?;
        }
    }
    if unreadable {
        Ok(ExitCode::from(crate::io::EXIT_UNUSABLE))
    } else if failed || !unformatted.is_empty() {
        Ok(ExitCode::FAILURE)
    } else {
        Ok(ExitCode::SUCCESS)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_and_is_idempotent_and_keeps_comments() {
        let src =
            "// map: demo\nlet a=rooms(kitchen)   // the kitchen\nroute{go a{prefer near(a)}}\n";
        let once = format_source(src).expect("parses");
        assert_eq!(
            once,
            "// map: demo\nlet a = rooms(kitchen) // the kitchen\nroute {\n  go a {\n    prefer near(a)\n  }\n}\n"
        );
        assert_eq!(format_source(&once).expect("parses"), once);
    }

    #[test]
    fn refuses_a_file_with_errors() {
        let src = "let a = \nroute { go a }";
        let errors = format_source(src).expect_err("has an error");
        assert_eq!(errors.len(), 1);
        let diags: Vec<Diagnostic> = errors.iter().map(Diagnostic::from_parse).collect();
        let rendered = render_text(&diags, "x.m2r", src);
        assert!(
            rendered.contains("error[E0002]: expected an expression, found `route`")
                && rendered.contains("x.m2r:2:1"),
            "{rendered}"
        );
    }
}
