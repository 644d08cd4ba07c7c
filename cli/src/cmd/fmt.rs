//! `m2rc fmt`: rewrite `.m2r` files in the canonical style, keeping their comments.
//!
//! A file with parse errors is never rewritten: formatting a tree with error nodes would change
//! what the author wrote, so the errors are printed instead and the exit code is 1.

use crate::io::{read_to_string, write_atomic};
use anyhow::{Context, Result};
use clap::Args;
use m2rc_grammar::{ParseError, parse, print_with_comments};
use std::io::{Read, Write};
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
                    failed = true;
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
                for e in &errors {
                    eprintln!("{}", render_error(shown, &source, e));
                }
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
            std::io::stdout()
                .write_all(formatted.as_bytes())
                .context("cannot write standard output")?;
        } else if formatted != source {
            write_atomic(path, formatted.as_bytes())?;
        }
    }
    if failed || !unformatted.is_empty() {
        Ok(ExitCode::FAILURE)
    } else {
        Ok(ExitCode::SUCCESS)
    }
}

/// `path:line:col: error[E0002]: message`, then the help, if any (1-based line and column,
/// columns in characters).
fn render_error(path: &Path, source: &str, e: &ParseError) -> String {
    let (line, col) = line_col(source, e.span.start);
    let mut s = format!(
        "{}:{line}:{col}: error[{}]: {}",
        path.display(),
        e.code(),
        e.message
    );
    for (span, label) in &e.labels {
        let (l, c) = line_col(source, span.start);
        s.push_str(&format!("\n  {l}:{c}: {label}"));
    }
    if let Some(help) = &e.help {
        s.push_str(&format!("\n  help: {help}"));
    }
    s
}

fn line_col(source: &str, offset: usize) -> (usize, usize) {
    let before = source.get(..offset.min(source.len())).unwrap_or(source);
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
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
        let errors = format_source("let a = \nroute { go a }").expect_err("has an error");
        assert_eq!(errors.len(), 1);
        let rendered = render_error(Path::new("x.m2r"), "let a = \nroute { go a }", &errors[0]);
        assert_eq!(
            rendered,
            "x.m2r:2:1: error[E0002]: expected an expression, found `route`"
        );
    }

    #[test]
    fn line_and_column_are_one_based() {
        assert_eq!(line_col("ab\ncd", 0), (1, 1));
        assert_eq!(line_col("ab\ncd", 4), (2, 2));
        assert_eq!(line_col("ab", 99), (1, 3));
    }
}
