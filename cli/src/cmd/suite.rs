//! `m2rc suite build | stats`: generate a benchmark suite from real ProcTHOR houses, and print
//! its statistics (the paper's Fig. 2).

use anyhow::{Context, Result, bail};
use clap::{Args, Subcommand, ValueEnum};
use m2rc_benchmark::methods::{METHOD_NAMES, method_by_name};
use m2rc_benchmark::suite::stats::{stats_markdown, suite_stats};
use m2rc_benchmark::suite::{ProcthorTools, SuiteConfig, build_suite};
use m2rc_stdlib::import::{AssetDb, ImportOptions};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Subcommand)]
pub enum SuiteCommand {
    /// Generate a suite: scenes from the largest multi-room houses, episodes with instructions,
    /// ground-truth annotations and gold programs, each validated by compiling and planning it.
    Build(BuildArgs),
    /// Print suite statistics: words, rooms traversed, candidates, depth, constraint counts.
    Stats(StatsArgs),
}

#[derive(Args)]
pub struct BuildArgs {
    /// ProcTHOR houses: a .jsonl.gz / .jsonl / .json file, a directory of them, or `-` for
    /// standard input (gzip or plain; give `--assets` then).
    #[arg(long)]
    pub houses: PathBuf,
    /// Evaluation scenes.
    #[arg(long, default_value_t = 40)]
    pub scenes: usize,
    /// Development scenes (the next largest houses after the evaluation scenes).
    #[arg(long, default_value_t = 4)]
    pub dev_scenes: usize,
    /// Episodes generated per scene.
    #[arg(long, default_value_t = 25)]
    pub episodes_per_scene: usize,
    /// Share of Hard episodes (5-8 constraints); the rest are Easy (2-4).
    #[arg(long, default_value_t = 0.3)]
    pub hard_fraction: f64,
    /// Random seed; the same houses and seed always give the same suite, byte for byte.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Suite name recorded in the manifest and in run directories.
    #[arg(long, default_value = "map2route-procthor")]
    pub name: String,
    /// ProcTHOR asset database; by default `assets/asset-database.json` beside the houses folder
    /// when it exists, else the importer's built-in size table.
    #[arg(long)]
    pub assets: Option<PathBuf>,
    /// Methods that must score HCS = 1 on an episode for it to be kept (comma-separated).
    #[arg(long, default_value = "oracle,shortest", value_delimiter = ',')]
    pub validate: Vec<String>,
    /// Suite directory to write.
    #[arg(long)]
    pub out: PathBuf,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum StatsFormat {
    Md,
    Json,
}

#[derive(Args)]
pub struct StatsArgs {
    /// Suite directory (holds suite.json).
    pub dir: PathBuf,
    /// Which scenes: eval, dev or all.
    #[arg(long, default_value = "eval")]
    pub split: String,
    /// Print Markdown tables (md) or the numbers as JSON (json).
    #[arg(long, value_enum, default_value_t = StatsFormat::Md)]
    pub format: StatsFormat,
}

pub fn run(command: SuiteCommand) -> Result<ExitCode> {
    match command {
        SuiteCommand::Build(a) => build(a),
        SuiteCommand::Stats(a) => stats(a),
    }
}

/// The asset database beside the houses folder; none for houses read from standard input (give
/// `--assets`).
fn default_assets(houses: &Path) -> Option<PathBuf> {
    if houses == Path::new("-") {
        return None;
    }
    crate::io::asset_path_beside(houses)
}

fn build(a: BuildArgs) -> Result<ExitCode> {
    let mut validators = Vec::new();
    for name in &a.validate {
        match method_by_name(name) {
            Some(m) => validators.push(m),
            None => bail!(
                "--validate: unknown method `{name}` (known: {})",
                METHOD_NAMES.join(", ")
            ),
        }
    }
    let assets_path = a.assets.clone().or_else(|| default_assets(&a.houses));
    let assets = match &assets_path {
        Some(p) => Some(
            AssetDb::load(p)
                .with_context(|| format!("cannot load the asset database {}", p.display()))?,
        ),
        None => None,
    };
    let config = SuiteConfig {
        name: a.name,
        scenes: a.scenes,
        dev_scenes: a.dev_scenes,
        episodes_per_scene: a.episodes_per_scene,
        hard_fraction: a.hard_fraction,
        seed: a.seed,
    };
    let tools = ProcthorTools {
        assets,
        import: ImportOptions::default(),
        validators,
    };
    let progress = |map_id: &str, kept: usize| eprintln!("  {map_id}: {kept} episodes");
    eprintln!(
        "building {} scenes + {} dev scenes × {} episodes from {}{}",
        config.scenes,
        config.dev_scenes,
        config.episodes_per_scene,
        if a.houses == Path::new("-") {
            "standard input".to_string()
        } else {
            a.houses.display().to_string()
        },
        assets_path
            .map(|p| format!(" (assets: {})", p.display()))
            .unwrap_or_default()
    );
    let manifest = build_suite(&a.houses, &config, &tools, &a.out, &progress)?;
    let short: usize = manifest.scenes.iter().map(|s| s.shortfall).sum();
    println!(
        "wrote {} scenes and {} episodes to {}{}",
        manifest.scenes.len(),
        manifest.episodes.len(),
        a.out.display(),
        if short > 0 {
            format!(" ({short} requested episodes could not be generated and validated)")
        } else {
            String::new()
        }
    );
    Ok(ExitCode::SUCCESS)
}

fn stats(a: StatsArgs) -> Result<ExitCode> {
    if !["eval", "dev", "all"].contains(&a.split.as_str()) {
        bail!("--split must be eval, dev or all, got `{}`", a.split);
    }
    let s = suite_stats(&a.dir, &a.split)?;
    match a.format {
        StatsFormat::Md => print!("{}", stats_markdown(&s)),
        StatsFormat::Json => println!("{}", serde_json::to_string_pretty(&s)?),
    }
    Ok(ExitCode::SUCCESS)
}
