//! `m2rc bench run | merge | report`: run a method over a suite (parallel, resumable, shardable),
//! merge shard directories, and report the paper's tables and plots.

use crate::io::write_atomic;
use anyhow::{Context, Result, bail};
use clap::{Args, Subcommand, ValueEnum};
use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::methods::{METHOD_NAMES, method_by_name};
use m2rc_benchmark::report::{self, episode_png::episode_png, load_runs, table};
use m2rc_benchmark::runner::{self, RunOptions, Shard};
use m2rc_benchmark::suite::SuiteManifest;
use serde_json::Value;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Subcommand)]
pub enum BenchCommand {
    /// Run a method on every episode of a suite; one prediction record per episode.
    Run(RunArgs),
    /// Combine the run directories of `--shard` jobs into one.
    Merge(MergeArgs),
    /// Table I, the difficulty analysis, plots, and per-episode pictures.
    Report(ReportArgs),
}

#[derive(Args)]
pub struct RunArgs {
    /// Suite directory (holds suite.json).
    #[arg(long)]
    pub suite: PathBuf,
    /// oracle, shortest or hard-only.
    #[arg(long)]
    pub method: String,
    /// Run directory; records go to <out>/<map_id>/instruction_<id>.json.
    #[arg(long)]
    pub out: PathBuf,
    /// Run only shard k of N (1-based), e.g. `--shard $SLURM_ARRAY_TASK_ID/8`.
    #[arg(long)]
    pub shard: Option<Shard>,
    /// Which scenes: eval (the paper's evaluation scenes), dev or all.
    #[arg(long, default_value = "eval")]
    pub split: String,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
}

#[derive(Args)]
pub struct MergeArgs {
    /// Shard run directories.
    #[arg(required = true)]
    pub shards: Vec<PathBuf>,
    #[arg(long)]
    pub out: PathBuf,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ReportFormat {
    Md,
    Csv,
    Json,
}

#[derive(Args)]
pub struct ReportArgs {
    /// Run directories, one or more per method.
    #[arg(required = true)]
    pub runs: Vec<PathBuf>,
    #[arg(long, value_enum, default_value_t = ReportFormat::Md)]
    pub format: ReportFormat,
    /// Write the report here instead of standard output.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write the difficulty-analysis bar charts (PNG) into this directory.
    #[arg(long)]
    pub plots: Option<PathBuf>,
    /// Draw these episodes (`<map_id>/instruction_<id>`), one PNG per run, into --png-dir.
    #[arg(long)]
    pub episode: Vec<String>,
    /// Suite directory, needed with --episode.
    #[arg(long)]
    pub suite: Option<PathBuf>,
    #[arg(long, default_value = ".")]
    pub png_dir: PathBuf,
}

pub fn run(command: BenchCommand) -> Result<ExitCode> {
    match command {
        BenchCommand::Run(a) => run_method(a),
        BenchCommand::Merge(a) => merge(a),
        BenchCommand::Report(a) => report_cmd(a),
    }
}

pub(crate) fn show_progress() -> bool {
    let ci = std::env::var("CI")
        .map(|v| !v.is_empty() && v != "0" && v != "false")
        .unwrap_or(false);
    std::io::stderr().is_terminal() && !ci
}

fn run_method(a: RunArgs) -> Result<ExitCode> {
    let Some(method) = method_by_name(&a.method) else {
        bail!(
            "--method: unknown method `{}` (known: {})",
            a.method,
            METHOD_NAMES.join(", ")
        );
    };
    let opts = RunOptions {
        suite: a.suite,
        out: a.out.clone(),
        shard: a.shard,
        split: a.split,
        progress: show_progress(),
    };
    let summary = match a.threads {
        Some(t) => {
            let pool = rayon_pool(t)?;
            pool.install(|| runner::run(method.as_ref(), &opts))?
        }
        None => runner::run(method.as_ref(), &opts)?,
    };
    println!(
        "{}: {} episodes ({} written, {} already done), {} without a route from the method; records in {}",
        method.name(),
        summary.episodes,
        summary.written,
        summary.skipped,
        summary.method_failures,
        a.out.display()
    );
    Ok(ExitCode::SUCCESS)
}

pub(crate) fn rayon_pool(threads: usize) -> Result<rayon::ThreadPool> {
    if threads == 0 {
        bail!("--threads must be at least 1");
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("cannot start worker threads")
}

fn merge(a: MergeArgs) -> Result<ExitCode> {
    let s = runner::merge(&a.shards, &a.out)?;
    println!(
        "merged {} shards: {} records ({} duplicates identical) into {}",
        s.shards,
        s.records,
        s.duplicates,
        a.out.display()
    );
    Ok(ExitCode::SUCCESS)
}

fn report_cmd(a: ReportArgs) -> Result<ExitCode> {
    let runs = load_runs(&a.runs)?;
    let text = match a.format {
        ReportFormat::Md => report::markdown_report(&runs),
        ReportFormat::Csv => table::csv(&table::table(&runs)),
        ReportFormat::Json => table::json(&table::table(&runs)) + "\n",
    };
    match &a.out {
        Some(path) => write_atomic(path, text.as_bytes())?,
        None => print!("{text}"),
    }
    if let Some(dir) = &a.plots {
        for p in report::write_plots(&runs, dir)? {
            eprintln!("wrote {}", p.display());
        }
    }
    if !a.episode.is_empty() {
        let Some(suite) = &a.suite else {
            bail!("--episode needs --suite <dir>")
        };
        let manifest = SuiteManifest::read(suite)?;
        for key in &a.episode {
            let Some((map_id, instruction_id)) = key.split_once('/') else {
                bail!("--episode `{key}` is not of the form <map_id>/instruction_<id>");
            };
            let entry = manifest
                .episodes
                .iter()
                .find(|e| e.map_id == map_id && e.instruction_id == instruction_id)
                .with_context(|| {
                    format!("--episode `{key}`: not in the suite {}", suite.display())
                })?;
            let map_path = manifest
                .map_path(suite, map_id)
                .with_context(|| format!("suite has no map {map_id}"))?;
            let map = m2rc_stdlib::map::read_map_json(
                &std::fs::read(&map_path)?,
                &map_path.display().to_string(),
            )?;
            let episode = Episode::read(&suite.join(&entry.file))?;
            for dir in &a.runs {
                let method = runner::read_run_manifest(dir)?.method;
                let record_path = runner::record_path(dir, map_id, instruction_id);
                if !record_path.exists() {
                    // Another shard of the same method holds it.
                    continue;
                }
                let record: Value = serde_json::from_slice(
                    &std::fs::read(&record_path)
                        .with_context(|| format!("cannot read {}", record_path.display()))?,
                )
                .with_context(|| format!("{} is not a prediction record", record_path.display()))?;
                let route: Vec<[i64; 2]> = serde_json::from_value(
                    record.get("trajectory").cloned().unwrap_or(Value::Null),
                )
                .with_context(|| {
                    format!(
                        "{}: field `trajectory` is not a list of [row, col]",
                        record_path.display()
                    )
                })?;
                let png = episode_png(&map, &episode, &route, &format!("{method} — {key}"))
                    .map_err(anyhow::Error::msg)?;
                let out = a
                    .png_dir
                    .join(format!("{map_id}_{instruction_id}_{method}.png"));
                write_atomic(&out, &png)?;
                eprintln!("wrote {}", out.display());
            }
        }
    }
    Ok(ExitCode::SUCCESS)
}
