//! `m2rc`: a thin shell over the m2rc crates. Every subcommand parses its flags, does the file and
//! terminal I/O, and calls into a library crate; no compiler or planner logic lives here.

mod cmd;
mod io;
mod lsp_stdio;
mod outputs;
mod suite_layout;
mod timings;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "m2rc",
    version,
    about = "Compile route instructions, written in the .m2r route language, into routes over semantic maps; score routes on the Map2Route benchmark.",
    after_help = "Exit status: 0 success; 1 the input was read and found wrong (program errors, a refused or failed check, a mismatch); 2 an input cannot be used at all (unreadable file, not JSON, not a map, bad flag). Wherever a file is read, `-` reads standard input; `-o -` writes standard output.",
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
    /// Natural language in, route out: an LLM writes the program, the compiler repairs it.
    Run(cmd::run::RunArgs),
    /// Print the exact messages the LLM sees for an instruction (or a repair).
    Prompt(cmd::prompt::PromptArgs),
    /// Run the paper's ablations over a suite, each into one table (docs/ablations.md).
    Ablate(cmd::ablate::AblateArgs),
    /// Serve routes over HTTP: POST /route with a .m2r program, GET /map (docs/serve.md).
    Serve(cmd::serve::ServeArgs),
    /// Serve m2rc's semantic queries as MCP tools over stdio, for an external agent (docs/tools.md).
    Tools(cmd::tools::ToolsArgs),
    /// Turn an LTLf formula into its minimal automaton (JSON, HOA, DOT).
    Ltl(cmd::ltl::LtlArgs),
    /// Inspect the Table I baselines (`explain`: every step of one instruction).
    #[command(subcommand)]
    Baseline(cmd::baseline::BaselineCommand),
}

fn main() -> ExitCode {
    timings::start();
    io::quiet_broken_pipe();
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
        Command::Run(a) => cmd::run::run(a),
        Command::Prompt(a) => cmd::prompt::run(a),
        Command::Ablate(a) => cmd::ablate::run(a),
        Command::Ltl(a) => cmd::ltl::run(a),
        Command::Baseline(c) => cmd::baseline::run(c),
        Command::Serve(a) => cmd::serve::run(a),
        Command::Tools(a) => cmd::tools::run(a),
    };
    match result {
        Ok(code) => code,
        Err(err) if io::is_broken_pipe(&err) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {}", error_chain(&err));
            io::exit_code(&err)
        }
    }
}

/// The error and its causes joined by `: `, leaving out a cause whose text the message before it
/// already quotes (many library errors repeat their source in their own message).
fn error_chain(err: &anyhow::Error) -> String {
    let mut out = String::new();
    for cause in err.chain() {
        let text = cause.to_string();
        if text.is_empty() || out.contains(&text) {
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
    use clap::CommandFactory;

    /// Every subcommand path (`bench merge`), and each argument without a description.
    fn walk(
        cmd: &clap::Command,
        path: &str,
        subs: &mut Vec<String>,
        undocumented: &mut Vec<String>,
    ) {
        for arg in cmd.get_arguments() {
            let id = arg.get_id().as_str();
            if id == "help" || id == "version" {
                continue;
            }
            if arg.get_help().is_none() && arg.get_long_help().is_none() {
                undocumented.push(format!("{path} {id}"));
            }
        }
        for sub in cmd.get_subcommands() {
            let p = format!("{path} {}", sub.get_name());
            if sub.get_subcommands().next().is_none() {
                subs.push(p.clone());
            }
            walk(sub, &p, subs, undocumented);
        }
    }

    #[test]
    fn every_flag_has_a_description_and_readme_lists_every_subcommand() {
        let (mut subs, mut undocumented) = (Vec::new(), Vec::new());
        walk(&super::Cli::command(), "m2rc", &mut subs, &mut undocumented);
        assert!(
            undocumented.is_empty(),
            "arguments without --help text: {undocumented:?}"
        );
        let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../README.md"))
            .expect("README.md");
        let table: String = readme
            .lines()
            .filter(|l| l.starts_with("| `m2rc"))
            .collect::<Vec<_>>()
            .join("\n");
        let missing: Vec<&String> = subs
            .iter()
            .filter(|s| !table.contains(s.as_str()))
            .collect();
        assert!(
            missing.is_empty(),
            "README's command table lacks {missing:?}"
        );
    }

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
