//! `m2rc`: a thin shell over the m2rc crates. Every subcommand parses its flags, does the file and
//! terminal I/O, and calls into a library crate; no compiler or planner logic lives here.

mod cmd;
mod io;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "m2rc",
    version,
    about = "Compile route instructions, written in the .m2r route language, into routes over semantic maps; score routes on the Map2Route benchmark.",
    propagate_version = true
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Import, inspect and render semantic maps.
    #[command(subcommand)]
    Map(cmd::map::MapCommand),
    /// Check a .m2r program: parse, resolve names, type-check and scope-check it.
    Check(cmd::check::CheckArgs),
    /// Format a .m2r program in the canonical style.
    Fmt(cmd::fmt::FmtArgs),
    /// Compile a .m2r program against a map into a grounded route.
    Compile(cmd::compile::CompileArgs),
    /// Score a route against a Map2Route episode, exactly as the reference evaluator does.
    Eval(cmd::eval::EvalArgs),
    /// Build and inspect benchmark suites of episodes from real houses.
    #[command(subcommand)]
    Suite(cmd::suite::SuiteCommand),
    /// Run methods over a suite, merge shards, and report tables.
    #[command(subcommand)]
    Bench(cmd::bench::BenchCommand),
    /// Run the .m2r language server over stdio.
    Lsp(cmd::lsp::LspArgs),
    /// Run the paper's ablations over a suite, each into one table (docs/ablations.md).
    Ablate(cmd::ablate::AblateArgs),
    /// Turn an LTLf formula into its minimal automaton (JSON, HOA, DOT).
    Ltl(cmd::ltl::LtlArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Map(c) => cmd::map::run(c),
        Command::Check(a) => cmd::check::run(a),
        Command::Fmt(a) => cmd::fmt::run(a),
        Command::Compile(a) => cmd::compile::run(a),
        Command::Eval(a) => cmd::eval::run(a),
        Command::Suite(c) => cmd::suite::run(c),
        Command::Bench(c) => cmd::bench::run(c),
        Command::Lsp(a) => cmd::lsp::run(a),
        Command::Ablate(a) => cmd::ablate::run(a),
        Command::Ltl(a) => cmd::ltl::run(a),
    };
    match result {
        Ok(code) => code,
        Err(err) => {
            eprintln!("error: {}", error_chain(&err));
            ExitCode::FAILURE
        }
    }
}

/// The error and its causes joined by `: `, leaving out a cause whose text the message before it
/// already quotes (many library errors repeat their source in their own message).
fn error_chain(err: &anyhow::Error) -> String {
    let mut out = String::new();
    for cause in err.chain() {
        let text = cause.to_string();
        if out.contains(&text) {
            continue;
        }
        if !out.is_empty() {
            out.push_str(": ");
        }
        out.push_str(&text);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::error_chain;

    #[test]
    fn a_cause_repeated_in_its_context_is_printed_once() {
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "no such file");
        let err = anyhow::Error::new(io).context("suite.json: no such file");
        assert_eq!(error_chain(&err), "suite.json: no such file");
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "no such file");
        let err = anyhow::Error::new(io).context("cannot read suite.json");
        assert_eq!(error_chain(&err), "cannot read suite.json: no such file");
    }
}
