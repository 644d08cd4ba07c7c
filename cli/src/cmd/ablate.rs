//! `m2rc ablate <which> --suite S [--out DIR]`: the paper's ablations (`m2rc_benchmark::ablate`).

use anyhow::{Result, bail};
use clap::{Args, ValueEnum};
use m2rc_benchmark::ablate::{self, AblateOptions, Ablation};
use m2rc_benchmark::methods::grounding2route::Grounding2Route;
use m2rc_benchmark::runner::Shard;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Which {
    /// Gold programs planned through RouteIR and through the LTL backend.
    LtlVsRouteir,
    /// The LLM method with R = 0..3 repair rounds.
    RepairRounds,
    /// Global-T, Global-S, Global-TS and Hard-only on the frozen RouteIR.
    Scopes,
    /// Shortest-feasible, sequential and global planners on gold programs.
    OraclePlanner,
    /// Every ablation, one report (`<out>/ablations.md`).
    All,
    /// The grounding representations (CaG, Schema) with one model and one reply cache, one-shot
    /// and with `--repair-rounds` R (issue 31).
    Grounding,
}

#[derive(Args)]
pub struct AblateArgs {
    /// Which ablation to run (`all` runs every one into one report).
    #[arg(value_enum)]
    pub which: Which,
    /// Suite directory (holds suite.json).
    #[arg(long)]
    pub suite: PathBuf,
    /// Output directory: `<out>/<ablation>/<variant>/` run directories and
    /// `<out>/<ablation>/table.{md,csv,json}`.
    #[arg(long, default_value = "ablations")]
    pub out: PathBuf,
    /// Run only shard k of N (1-based) of every variant.
    #[arg(long)]
    pub shard: Option<Shard>,
    /// Which scenes: eval (the paper's evaluation scenes), dev or all.
    #[arg(long, default_value = "eval")]
    pub split: String,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// The model for `repair-rounds` (the same flags as `bench run --method grounding2route`).
    #[command(flatten)]
    pub llm: m2rc_llm::LlmArgs,
    /// `repair-rounds` runs R = 0 up to `--repair-rounds` (default 3).
    #[command(flatten)]
    pub lower: m2rc_llm::LowerArgs,
    /// Embedding flags of the baselines (unused by the grounding variants; kept so the model
    /// setup is the one `bench run` builds).
    #[command(flatten)]
    pub baseline: m2rc_baselines::BaselineArgs,
}

/// The model for `repair-rounds`, when one is configured: a server's base URL, or the simulated
/// model. One reply cache for all R, so that every variant's first answer is the same reply.
fn model_spec(a: &AblateArgs) -> Option<ablate::ModelSpec> {
    let configured = match a.llm.backend {
        m2rc_llm::Backend::Http => a.llm.llm_base_url.is_some(),
        m2rc_llm::Backend::Simulated(_) => true,
        // Refused when the method is built (grounding2route has no gold oracle).
        m2rc_llm::Backend::Gold => true,
    };
    if !configured {
        return None;
    }
    let (llm, lower) = (a.llm.clone(), a.lower.clone());
    let cache = a.out.join("repair-rounds").join("llm-cache");
    Some(ablate::ModelSpec {
        max_rounds: a.lower.repair_rounds,
        make: Box::new(move |r, planner| {
            let mut lower = lower.clone();
            lower.repair_rounds = r;
            let (mut m, note) = Grounding2Route::from_args(&llm, &lower, &cache)?;
            m.config.planner = planner;
            if let (0, Some(n)) = (r, note) {
                eprintln!("{n}");
            }
            Ok(Box::new(m) as Box<dyn m2rc_benchmark::methods::Method>)
        }),
    })
}

pub fn run(a: AblateArgs) -> Result<ExitCode> {
    let model = model_spec(&a);
    let opts = AblateOptions {
        suite: a.suite.clone(),
        out: a.out.clone(),
        shard: a.shard,
        split: a.split.clone(),
        progress: super::bench::show_progress(),
        model,
    };
    let go = || -> Result<String> {
        Ok(match a.which {
            Which::Grounding => super::ablate_grounding::run(&a, &opts)?,
            Which::All => {
                ablate::run_all(&opts)?;
                std::fs::read_to_string(opts.out.join("ablations.md"))?
            }
            w => {
                let ab = match w {
                    Which::LtlVsRouteir => Ablation::LtlVsRouteir,
                    Which::RepairRounds => Ablation::RepairRounds,
                    Which::Scopes => Ablation::Scopes,
                    Which::OraclePlanner | Which::All | Which::Grounding => Ablation::OraclePlanner,
                };
                if let Err(why) = ab.variants(opts.model.as_ref()) {
                    bail!("{why}");
                }
                ablate::run_ablation(ab, &opts)?.markdown
            }
        })
    };
    let text = match a.threads {
        Some(t) => super::bench::rayon_pool(t)?.install(go)?,
        None => go()?,
    };
    print!("{text}");
    println!("\ntables written under {}", a.out.display());
    Ok(ExitCode::SUCCESS)
}
