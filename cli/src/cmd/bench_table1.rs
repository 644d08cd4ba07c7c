//! `m2rc bench table1 --suite S --out DIR [model flags]`: the paper's Table I in one command.
//! Runs shortest, oracle, grounding2route and every baseline of the registry, each in its own
//! resumable run directory `DIR/<method>` with one reply cache `DIR/llm-cache` shared by all, then
//! writes the table in the paper's layout (`DIR/table1.md`) and Figure 4, the difficulty analysis
//! (`DIR/figure4/*.png` and `DIR/figure4.md`). With `--llm gold` the baselines' calls are
//! answered from the annotations and grounding2route is given the gold program
//! (`--llm simulated:0`): the table of ceilings.

use super::bench::{RunArgs, run_method};
use crate::io::{unusable, write_atomic};
use anyhow::Result;
use clap::Args;
use m2rc_benchmark::report::{self, LoadOptions, MethodRun, difficulty, load_runs_with, table1};
use m2rc_llm::{Backend, SimulatedSpec};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The rows that are not baselines, run first.
const REFERENCE_METHODS: [&str; 3] = ["shortest", "oracle", "grounding2route"];

/// Figure 4's methods when they are present (the paper's pair); otherwise every method.
const FIGURE4_DEFAULT: [&str; 2] = ["grounding2route", "osgllm"];

#[derive(Args)]
pub struct Table1Args {
    /// Suite directory (holds suite.json).
    #[arg(long)]
    pub suite: PathBuf,
    /// Directory of the run directories (one per method), the shared reply cache and the table.
    #[arg(long)]
    pub out: PathBuf,
    /// Only these methods (comma-separated; default: every one).
    #[arg(long, value_delimiter = ',')]
    pub methods: Vec<String>,
    /// Run directories made elsewhere (`bench import`, shards merged) to rank beside.
    #[arg(long = "with")]
    pub with: Vec<PathBuf>,
    /// Figure 4's methods (comma-separated; default: grounding2route and OSG-LLM when present).
    #[arg(long, value_delimiter = ',')]
    pub figure4: Vec<String>,
    /// Which scenes: eval (the paper's evaluation scenes), dev or all.
    #[arg(long, default_value = "eval")]
    pub split: String,
    /// Worker threads per run (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    #[command(flatten)]
    pub llm: m2rc_llm::LlmArgs,
    #[command(flatten)]
    pub lower: m2rc_llm::LowerArgs,
    #[command(flatten)]
    pub baseline: m2rc_baselines::BaselineArgs,
}

/// Every method of the table, in the order they are run.
pub fn table1_methods() -> Vec<String> {
    REFERENCE_METHODS
        .iter()
        .map(|s| s.to_string())
        .chain(
            m2rc_baselines::baseline_names()
                .into_iter()
                .map(String::from),
        )
        .collect()
}

/// `<file>.<method>.<ext>`: each method's own batch file beside the one named.
fn per_method(path: &Path, method: &str) -> PathBuf {
    let stem = path.file_stem().map(|s| s.to_string_lossy().to_string());
    let name = match (stem, path.extension()) {
        (Some(s), Some(e)) => format!("{s}.{method}.{}", e.to_string_lossy()),
        (Some(s), None) => format!("{s}.{method}"),
        _ => method.to_string(),
    };
    path.with_file_name(name)
}

pub fn run(a: Table1Args) -> Result<ExitCode> {
    crate::outputs::refuse_run_into_suite(&a.out, &a.suite)?;
    let all = table1_methods();
    let methods: Vec<String> = if a.methods.is_empty() {
        all.clone()
    } else {
        for m in &a.methods {
            if !all.contains(m) {
                return Err(unusable(anyhow::anyhow!(
                    "--methods: `{m}` is not a method of Table I (known: {})",
                    all.join(", ")
                )));
            }
        }
        all.iter()
            .filter(|m| a.methods.contains(m))
            .cloned()
            .collect()
    };
    let gold = a.llm.backend == Backend::Gold;
    let cache = a
        .llm
        .llm_cache
        .clone()
        .unwrap_or_else(|| a.out.join("llm-cache"));
    let mut dirs = Vec::new();
    let mut timings = Vec::new();
    for method in &methods {
        let mut llm = a.llm.clone();
        llm.llm_cache = Some(cache.clone());
        llm.llm_batch_out = a
            .llm
            .llm_batch_out
            .as_deref()
            .map(|p| per_method(p, method));
        if gold && method == "grounding2route" {
            llm.backend = Backend::Simulated(SimulatedSpec {
                fault_rate: 0.0,
                seed: 0,
            });
        }
        let out = a.out.join(method);
        eprintln!("== {method} -> {}", out.display());
        let began = std::time::Instant::now();
        run_method(RunArgs {
            suite: a.suite.clone(),
            method: method.clone(),
            out: out.clone(),
            shard: None,
            split: a.split.clone(),
            threads: a.threads,
            report: false,
            llm_price_in: None,
            llm_price_out: None,
            llm,
            lower: a.lower.clone(),
            baseline: a.baseline.clone(),
        })?;
        timings.push((method.clone(), began.elapsed().as_secs_f64()));
        dirs.push(out);
    }
    // Wall times go to the terminal only: records and tables stay the same bytes on every run.
    for (method, secs) in &timings {
        eprintln!(
            "time: {method}: {secs:.1} s in this invocation (episodes already done are not re-run)"
        );
    }
    dirs.extend(a.with.iter().cloned());
    let runs = load_runs_with(
        &dirs,
        LoadOptions {
            allow_incomplete: true,
            allow_invalid_routes: true,
        },
    )?;
    let text = format!(
        "## Table I{}\n\n{}",
        if gold { " (ceilings)" } else { "" },
        table1::markdown(&runs, gold)
    );
    write_atomic(&a.out.join("table1.md"), text.as_bytes())?;
    let fig = figure4_runs(&runs, &a.figure4)?;
    let fig_md = format!(
        "## Figure 4: HCS by difficulty\n\n{}",
        difficulty::markdown(&difficulty::analysis(&fig))
    );
    write_atomic(&a.out.join("figure4.md"), fig_md.as_bytes())?;
    for p in report::write_plots(&fig, &a.out.join("figure4"))? {
        eprintln!("wrote {}", p.display());
    }
    crate::io::stdout(&format!("{text}\n{fig_md}"))?;
    eprintln!(
        "wrote {} and {}",
        a.out.join("table1.md").display(),
        a.out.join("figure4.md").display()
    );
    Ok(ExitCode::SUCCESS)
}

/// The runs Figure 4 draws: those named, else grounding2route and OSG-LLM when either is there,
/// else every run.
pub fn figure4_runs(runs: &[MethodRun], names: &[String]) -> Result<Vec<MethodRun>> {
    if !names.is_empty() {
        let wanted: Vec<String> = names.iter().map(|n| table1::base_name(n)).collect();
        let picked: Vec<MethodRun> = runs
            .iter()
            .filter(|r| wanted.contains(&table1::base_name(&r.method)))
            .cloned()
            .collect();
        if picked.len() < wanted.len() {
            let have: Vec<&str> = runs.iter().map(|r| r.method.as_str()).collect();
            return Err(unusable(anyhow::anyhow!(
                "--figure4 names a method without a run (runs: {})",
                have.join(", ")
            )));
        }
        return Ok(picked);
    }
    let picked: Vec<MethodRun> = runs
        .iter()
        .filter(|r| FIGURE4_DEFAULT.contains(&table1::base_name(&r.method).as_str()))
        .cloned()
        .collect();
    Ok(if picked.is_empty() {
        runs.to_vec()
    } else {
        picked
    })
}
