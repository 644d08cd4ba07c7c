//! `m2rc bench run | merge | import | report`: run a method over a suite (parallel, resumable,
//! shardable), merge shard directories, score another program's routes (`bench_import`), and
//! report the paper's tables and plots.

use crate::io::{unusable, write_atomic};
use anyhow::{Context, Result, bail};
use clap::{Args, Subcommand, ValueEnum};
use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::methods::grounding2route::Grounding2Route;
use m2rc_benchmark::methods::{
    METHOD_NAMES, MODEL_METHOD_NAMES, Method, MethodError, Prediction, PreparedMap, method_by_name,
};
use m2rc_benchmark::report::{self, LoadOptions, episode_png::episode_png, load_runs_with, table};
use m2rc_benchmark::runner::{self, RunOptions, Shard};
use m2rc_benchmark::suite::SuiteManifest;
use serde_json::Value;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Subcommand)]
pub enum BenchCommand {
    /// Run a method on every episode of a suite; one prediction record per episode.
    Run(Box<RunArgs>),
    /// Combine the run directories of `--shard` jobs into one.
    Merge(MergeArgs),
    /// Score another program's routes (a folder of prediction files) into a run directory.
    Import(super::bench_import::ImportArgs),
    /// Table I, the difficulty analysis, plots, and per-episode pictures.
    Report(ReportArgs),
    /// Table I in one command: every method of the table, then the table and Figure 4.
    Table1(Box<super::bench_table1::Table1Args>),
}

#[derive(Args)]
pub struct RunArgs {
    /// Suite directory (holds suite.json).
    #[arg(long)]
    pub suite: PathBuf,
    /// oracle, shortest, hard-only, grounding2route (an LLM; see the model flags below), or a
    /// baseline of Table I (lang2ltl, ...; `--llm gold` answers its calls from the annotations).
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
    /// Worker threads (default: all cores; more than the machine's cores is capped to them).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Print the report of this run directory (Markdown) when the run is done.
    #[arg(long)]
    pub report: bool,
    /// Model price per million prompt tokens, for the cost column of --report.
    #[arg(long)]
    pub llm_price_in: Option<f64>,
    /// Model price per million completion tokens, for the cost column of --report.
    #[arg(long)]
    pub llm_price_out: Option<f64>,
    #[command(flatten)]
    pub llm: m2rc_llm::LlmArgs,
    #[command(flatten)]
    pub lower: m2rc_llm::LowerArgs,
    #[command(flatten)]
    pub baseline: m2rc_baselines::BaselineArgs,
}

#[derive(Args)]
pub struct MergeArgs {
    /// Shard run directories: every shard k/N of one run (each complete, same fingerprint).
    #[arg(required = true)]
    pub shards: Vec<PathBuf>,
    /// The merged run directory.
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
    /// Run directories, one or more per method (a directory named twice is read once).
    #[arg(required = true)]
    pub runs: Vec<PathBuf>,
    /// Report format: Markdown tables (md), CSV rows (csv) or JSON (json).
    #[arg(long, value_enum, default_value_t = ReportFormat::Md)]
    pub format: ReportFormat,
    /// Write the report here instead of standard output (`-`: standard output).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Report methods whose runs lack episodes (the table says so) instead of refusing.
    #[arg(long)]
    pub allow_incomplete: bool,
    /// Report methods with routes that are not drivable (jumps, blocked cells, cut corners; the
    /// table says so) instead of refusing.
    #[arg(long)]
    pub allow_invalid_routes: bool,
    /// Write the difficulty-analysis bar charts (PNG) into this directory.
    #[arg(long)]
    pub plots: Option<PathBuf>,
    /// Table I in the paper's layout (its row order, the delta vs best baseline, the paper's
    /// published rows beside ours; the ceilings table when every baseline had gold replies).
    #[arg(long)]
    pub paper: bool,
    /// Draw these episodes (`<map_id>/instruction_<id>`), one PNG per run, into --png-dir.
    #[arg(long)]
    pub episode: Vec<String>,
    /// Suite directory, needed with --episode.
    #[arg(long)]
    pub suite: Option<PathBuf>,
    /// Directory for the --episode pictures.
    #[arg(long, default_value = ".")]
    pub png_dir: PathBuf,
    /// Model price per million prompt tokens (adds a cost column for model methods).
    #[arg(long)]
    pub llm_price_in: Option<f64>,
    /// Model price per million completion tokens.
    #[arg(long)]
    pub llm_price_out: Option<f64>,
}

pub fn run(command: BenchCommand) -> Result<ExitCode> {
    match command {
        BenchCommand::Run(a) => run_method(*a),
        BenchCommand::Merge(a) => merge(a),
        BenchCommand::Import(a) => super::bench_import::run(a),
        BenchCommand::Report(a) => report_cmd(a),
        BenchCommand::Table1(a) => super::bench_table1::run(*a),
    }
}

pub(crate) fn show_progress() -> bool {
    let ci = std::env::var("CI")
        .map(|v| !v.is_empty() && v != "0" && v != "false")
        .unwrap_or(false);
    std::io::stderr().is_terminal() && !ci
}

pub(crate) fn run_method(a: RunArgs) -> Result<ExitCode> {
    crate::outputs::refuse_run_into_suite(&a.out, &a.suite)?;
    let mut model_method = None;
    let mut baseline_setup = None;
    let method: Box<dyn m2rc_benchmark::methods::Method> = if m2rc_baselines::is_baseline(&a.method)
    {
        let built = m2rc_baselines::build(&a.method, &a.llm, &a.baseline, &a.out.join("llm-cache"))
            .map_err(|e| unusable(anyhow::Error::msg(e)))?
            .context("baseline registry")?;
        if let Some(n) = &built.note {
            eprintln!("{n}");
        }
        let label = if m2rc_baselines::uses_embeddings(&a.method) {
            built.setup.label()
        } else {
            built.setup.chat_label()
        };
        eprintln!("note: {}: {label}", a.method);
        baseline_setup = Some(built.setup);
        built.method
    } else if a.method == "grounding2route" {
        let (m, note) = Grounding2Route::from_args(&a.llm, &a.lower, &a.out.join("llm-cache"))
            .map_err(|e| unusable(anyhow::Error::msg(e)))?;
        if let Some(n) = note {
            eprintln!("{n}");
        }
        if m.config.is_simulated() {
            eprintln!("note: {}", m.config.label());
        }
        let m = std::sync::Arc::new(m);
        model_method = Some(m.clone());
        Box::new(SharedMethod(m))
    } else {
        match method_by_name(&a.method) {
            Some(m) => m,
            None => {
                return Err(unusable(anyhow::anyhow!(
                    "--method: unknown method `{}` (known: {}, {}, {})",
                    a.method,
                    METHOD_NAMES.join(", "),
                    MODEL_METHOD_NAMES.join(", "),
                    m2rc_baselines::baseline_names().join(", ")
                )));
            }
        }
    };
    // Each map of the run is loaded through the prepared-map cache, as `compile` and `eval` do.
    if let Some(dir) = m2rc_benchmark::map_cache::dir_from_env() {
        m2rc_benchmark::map_cache::enable_for_runs(dir);
    }
    let opts = RunOptions {
        suite: a.suite,
        out: a.out.clone(),
        shard: a.shard,
        split: a.split,
        progress: show_progress(),
    };
    let summary = match a.threads {
        Some(t) => {
            let pool = rayon_pool(capped_threads(t))?;
            pool.install(|| runner::run(method.as_ref(), &opts))?
        }
        None => runner::run(method.as_ref(), &opts)?,
    };
    if summary.temps_removed > 0 {
        eprintln!(
            "note: removed {} temporary file(s) left by an interrupted run",
            summary.temps_removed
        );
    }
    for r in &summary.recomputed {
        eprintln!("warning: recomputed {r}");
    }
    if let Some(setup) = &baseline_setup {
        report_store(
            &setup.store,
            if setup.is_gold() {
                " [GOLD replies]"
            } else {
                ""
            },
        )?;
    }
    if let Some(m) = &model_method {
        if let Some(b) = &m.store.batch {
            let n = b.finish()?;
            eprintln!(
                "wrote {n} batch request(s) to {}; answer them, then run again with --llm-batch-in <output file>",
                b.path().display()
            );
        }
        for w in m.store.warnings() {
            eprintln!("warning: {w}");
        }
        let s = m.store.stats();
        eprintln!(
            "model requests: {} answered from the cache, {} fetched, {} pending, {} failed{}",
            s.cache_hits,
            s.fetched,
            s.pending,
            s.failed,
            if m.config.is_simulated() {
                " (SIMULATED model)"
            } else {
                ""
            }
        );
    }
    crate::io::stdout(&format!(
        "{}: {} episodes ({} written, {} already done, {} recomputed), {} without a route from the method; records in {}\n",
        method.name(),
        summary.episodes,
        summary.written,
        summary.skipped,
        summary.recomputed.len(),
        summary.method_failures,
        a.out.display()
    ))?;
    if summary.pending > 0 {
        crate::io::stdout(&format!(
            "{}: {} episode(s) pending a model reply (no record yet; import the batch replies and run again)\n",
            method.name(),
            summary.pending
        ))?;
    }
    if a.report {
        let runs = load_runs_with(
            std::slice::from_ref(&a.out),
            LoadOptions {
                allow_incomplete: summary.pending > 0,
                allow_invalid_routes: false,
            },
        )?;
        let prices = report::model::Prices {
            input: a.llm_price_in,
            output: a.llm_price_out,
        };
        crate::io::stdout(&report::markdown_report_with(&runs, &prices))?;
    }
    Ok(ExitCode::SUCCESS)
}

/// The end-of-run lines about a model's requests: the batch file written, warnings, counts.
fn report_store(store: &m2rc_llm::Store, label: &str) -> Result<()> {
    if let Some(b) = &store.batch {
        let n = b.finish()?;
        eprintln!(
            "wrote {n} batch request(s) to {}; answer them, then run again with --llm-batch-in <output file>",
            b.path().display()
        );
    }
    for w in store.warnings() {
        eprintln!("warning: {w}");
    }
    let s = store.stats();
    eprintln!(
        "model requests: {} answered from the cache, {} fetched, {} pending, {} failed{label}",
        s.cache_hits, s.fetched, s.pending, s.failed
    );
    Ok(())
}

/// `--threads` capped to the cores the machine has (a huge value would start that many OS
/// threads and stall the machine).
fn capped_threads(requested: usize) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    if requested > cores {
        eprintln!("note: --threads {requested} is more than the {cores} cores here; using {cores}");
        cores
    } else {
        requested
    }
}

pub(crate) fn rayon_pool(threads: usize) -> Result<rayon::ThreadPool> {
    if threads == 0 {
        return Err(unusable(anyhow::anyhow!("--threads must be at least 1")));
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("cannot start worker threads")
}

fn merge(a: MergeArgs) -> Result<ExitCode> {
    crate::outputs::refuse_output_among_inputs(&a.out, &a.shards, "shard")?;
    let s = runner::merge(&a.shards, &a.out)?;
    crate::io::stdout(&format!(
        "merged {} shards: {} records ({} duplicates identical) into {}\n",
        s.shards,
        s.records,
        s.duplicates,
        a.out.display()
    ))?;
    Ok(ExitCode::SUCCESS)
}

fn report_cmd(a: ReportArgs) -> Result<ExitCode> {
    let runs = load_runs_with(
        &a.runs,
        LoadOptions {
            allow_incomplete: a.allow_incomplete,
            allow_invalid_routes: a.allow_invalid_routes,
        },
    )?;
    let text = match a.format {
        ReportFormat::Md if a.paper => {
            let ceilings = runs.iter().any(|r| r.method.ends_with("[GOLD replies]"));
            report::table1::markdown(&runs, ceilings)
        }
        ReportFormat::Md => report::markdown_report_with(
            &runs,
            &report::model::Prices {
                input: a.llm_price_in,
                output: a.llm_price_out,
            },
        ),
        ReportFormat::Csv => table::csv(&table::table(&runs)),
        ReportFormat::Json => table::json(&table::table(&runs)) + "\n",
    };
    match &a.out {
        Some(path) => write_atomic(path, text.as_bytes())?,
        None => crate::io::stdout(&text)?,
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

/// A method shared with the command (which reads its store's statistics after the run).
struct SharedMethod(std::sync::Arc<Grounding2Route>);

impl Method for SharedMethod {
    fn name(&self) -> &str {
        self.0.name()
    }

    fn config(&self) -> Value {
        self.0.config()
    }

    fn predict(&self, map: &PreparedMap, episode: &Episode) -> Result<Prediction, MethodError> {
        self.0.predict(map, episode)
    }
}
