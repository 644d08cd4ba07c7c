//! `m2rc check`: parse, resolve, type-check and scope-check a `.m2r` program; with `--fix`, first
//! apply the machine-applicable fixes the diagnostics carry.
//!
//! Exit status: 0 when there is no error (warnings allowed), 1 when the program has errors, 2 when
//! the file or the map cannot be read. Text diagnostics and the `ok:` line go to standard error
//! (coloured only on a terminal), as every command's messages do; `--format json` prints one JSON
//! array to standard output (schema in `docs/diagnostics.md`).

use anyhow::Result;
use clap::{Args, ValueEnum};
use m2rc_compiler::diagnostic::{render_text, render_text_colored, to_json};
use m2rc_compiler::lower::repair::{LocalFix, Phase, Verdict, verify_with_fixes};
use m2rc_compiler::{CheckResult, check};
use m2rc_grammar::ast::{Item, Program, RouteItem, StageItem};
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
    /// Apply the unambiguous machine-applicable fixes (an error with exactly one suggestion, as
    /// the repair loop applies before asking the model), rewrite FILE atomically (or write `-o`),
    /// say what changed, then check the result.
    #[arg(long)]
    pub fix: bool,
    /// With `--fix`: write the fixed program here instead of over FILE (`-`: standard output).
    #[arg(short = 'o', long, value_name = "OUT", requires = "fix")]
    pub output: Option<PathBuf>,
}

pub fn run(args: CheckArgs) -> Result<ExitCode> {
    let (name, mut source, vocab) = match inputs(&args) {
        Ok(v) => v,
        Err(err) => return Err(crate::io::unusable(err)),
    };
    let fix_to_stdout = match &args.output {
        Some(o) => crate::io::is_dash(o),
        None => crate::io::is_dash(&args.file),
    };
    if args.fix && fix_to_stdout && args.format == Format::Json {
        return Err(crate::io::unusable(anyhow::anyhow!(
            "--fix would write the program and --format json the diagnostics to standard output: \
             pass -o <file> for the fixed program"
        )));
    }
    if args.fix {
        source = fix(&args, &name, source, &vocab)?;
    }
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
            if errors == 0 {
                eprintln!("{}", ok_line(&result));
            }
        }
    }
    Ok(if result.has_errors() {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

/// `ok: N bindings, M stages`: a silent success looked like nothing had run.
fn ok_line(result: &CheckResult) -> String {
    let b = bindings(&result.program);
    let s = result.stages.len();
    format!(
        "ok: {b} binding{}, {s} stage{}",
        if b == 1 { "" } else { "s" },
        if s == 1 { "" } else { "s" }
    )
}

/// Names the program binds: its `let`s, wherever they stand, and its `for` variables.
fn bindings(program: &Program) -> usize {
    fn route_items(items: &[RouteItem]) -> usize {
        items
            .iter()
            .map(|i| match i {
                RouteItem::Let(_) => 1,
                RouteItem::Stage(s) => s
                    .body
                    .iter()
                    .filter(|i| matches!(i, StageItem::Let(_)))
                    .count(),
                RouteItem::For(f) => 1 + route_items(&f.body),
                _ => 0,
            })
            .sum()
    }
    program
        .items
        .iter()
        .map(|i| match i {
            Item::Let(_) => 1,
            Item::Route(r) => route_items(&r.items),
            Item::Error(_) => 0,
        })
        .sum()
}

/// Applies the fixes, writes the fixed program (only when something changed, or always with an
/// explicit `-o`), reports each fix on standard error, and returns the program to check.
fn fix(args: &CheckArgs, name: &str, source: String, vocab: &Vocabulary) -> Result<String> {
    let mut verifier = |src: &str| -> Verdict<()> {
        let r = check(src, vocab);
        if r.has_errors() {
            Verdict::Rejected {
                phase: Phase::Check,
                diagnostics: r.diagnostics,
            }
        } else {
            Verdict::Accepted(())
        }
    };
    let (_, fixes, fixed) = verify_with_fixes(&mut verifier, &source, true);
    for f in &fixes {
        eprintln!("{}", fix_line(f));
    }
    let target = match &args.output {
        Some(out) => Some(out.clone()),
        None if crate::io::is_dash(&args.file) => Some(PathBuf::from("-")),
        None if fixes.is_empty() => None,
        None => Some(args.file.clone()),
    };
    if let Some(out) = &target {
        crate::io::write_atomic(out, fixed.as_bytes())?;
    }
    match (&target, fixes.len()) {
        (_, 0) => eprintln!("{name}: nothing to fix"),
        (Some(out), n) if !crate::io::is_dash(out) => {
            eprintln!("{name}: applied {n} fix(es); wrote {}", out.display())
        }
        (_, n) => eprintln!("{name}: applied {n} fix(es)"),
    }
    Ok(fixed)
}

fn fix_line(f: &LocalFix) -> String {
    let what = if f.replaced.is_empty() {
        format!("inserted `{}`", f.replacement)
    } else {
        format!("`{}` -> `{}`", f.replaced, f.replacement)
    };
    format!("fixed [{}]: {what} ({})", f.code, f.message)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bindings_count_lets_everywhere_and_for_variables() {
        let src = "let a = rooms(kitchen)\nroute {\n  let b = objects(bed)\n  go a {\n    let c = objects(chair)\n    avoid c\n  }\n  for x in b.sorted_by_distance(start) {\n    go x\n  }\n}\n";
        let r = check(src, &Vocabulary::benchmark());
        assert_eq!(bindings(&r.program), 4);
    }
}
