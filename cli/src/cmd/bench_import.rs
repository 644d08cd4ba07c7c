//! `m2rc bench import`: score another program's routes (a folder of prediction files) into a
//! run directory that `bench report` reads beside m2rc's own runs.

use anyhow::Result;
use clap::Args;
use m2rc_benchmark::import::{ImportOptions, import};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub struct ImportArgs {
    /// Suite directory (holds suite.json).
    #[arg(long)]
    pub suite: PathBuf,
    /// Folder of prediction files, one per episode: `<map_id>/instruction_<id:06>.json` holding
    /// a bare `[[row, col], ...]` list, or any `*.json` holding the reference's method output
    /// `{"method", "map_id", "instruction_id", "trajectory"}` (see docs/formats.md).
    #[arg(long)]
    pub predictions: PathBuf,
    /// The name of the method (its records and its report row carry it); not one of m2rc's own
    /// method names.
    #[arg(long)]
    pub method: String,
    /// Run directory to write (never the suite or the predictions folder, nor inside them).
    #[arg(long)]
    pub out: PathBuf,
    /// Which scenes: eval (the paper's evaluation scenes), dev or all.
    #[arg(long, default_value = "eval")]
    pub split: String,
}

/// How many episodes a warning lists by name before it only counts.
const LISTED: usize = 10;

pub fn run(a: ImportArgs) -> Result<ExitCode> {
    // Records among the predictions would be read as predictions by the next import; among
    // the suite's files they would change its fingerprint.
    crate::outputs::refuse_output_among_inputs(
        &a.out,
        std::slice::from_ref(&a.predictions),
        "--predictions folder",
    )?;
    crate::outputs::refuse_output_among_inputs(
        &a.out,
        std::slice::from_ref(&a.suite),
        "--suite folder",
    )?;
    if m2rc_baselines::is_baseline(&a.method) {
        // Read as a refused run (status 1), like the names of m2rc's own methods.
        anyhow::bail!(m2rc_benchmark::runner::RunError::Invalid(format!(
            "--method `{}` is one of m2rc's own methods (a baseline of Table I); give the \
             imported routes a name of their own",
            a.method
        )));
    }
    let s = import(&ImportOptions {
        suite: a.suite,
        predictions: a.predictions,
        method: a.method.clone(),
        out: a.out.clone(),
        split: a.split,
        progress: super::bench::show_progress(),
    })?;
    let list = |what: &str, items: Vec<String>| {
        for item in items.iter().take(LISTED) {
            eprintln!("warning: {what}: {item}");
        }
        if items.len() > LISTED {
            eprintln!("warning: ... and {} more {what}", items.len() - LISTED);
        }
    };
    list("no prediction, scored on the start cell", s.missing.clone());
    list(
        "malformed prediction, scored on the start cell",
        s.malformed
            .iter()
            .map(|(k, why)| format!("{k}: {why}"))
            .collect(),
    );
    list(
        "route not drivable",
        s.invalid_routes
            .iter()
            .map(|(k, why)| format!("{k}: {why}"))
            .collect(),
    );
    if s.ignored_files > 0 {
        eprintln!(
            "note: {} file(s) of the predictions folder are not predictions (not *.json, or hidden) and were not read",
            s.ignored_files
        );
    }
    crate::io::stdout(&format!(
        "{}: {} episodes ({} written, {} already done): {} scored from their prediction, {} without a prediction, {} with a malformed one (both scored on the start cell alone), {} with a route that is not drivable; records in {}\n",
        a.method,
        s.run.episodes,
        s.run.written,
        s.run.skipped,
        s.ok,
        s.missing.len(),
        s.malformed.len(),
        s.invalid_routes.len(),
        a.out.display()
    ))?;
    Ok(ExitCode::SUCCESS)
}
