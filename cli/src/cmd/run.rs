//! `m2rc run`: natural language in, route out. The instruction is lowered into `.m2r` by the
//! configured model (prompt generated from the built-in table, the map's catalog and worked
//! examples), checked, repaired from the compiler's diagnostics (local fixes first), grounded and
//! planned. Prints each round's reply, local fixes and diagnostics, the final program and the
//! route summary; writes outputs only when a route was found, each atomically.

use crate::cmd::compile::{render_options, route_document, summary_text};
use crate::io::unusable;
use crate::io::write_atomic;
use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use m2rc_benchmark::methods::grounding2route::lower_and_plan;
use m2rc_benchmark::pipeline::PipelineOptions;
use m2rc_compiler::lower::EpisodeOutcome;
use m2rc_llm::{Backend, Exchange};
use m2rc_stdlib::render::render_map;
use std::path::PathBuf;
use std::process::ExitCode;

/// `--llm` is not offered here: the simulated model answers from an episode's gold program, and
/// `m2rc run` has no episode (a `--llm simulated` typed anyway is refused, naming `bench run`).
#[derive(Args)]
#[command(mut_arg("backend", |a| a.hide(true)))]
pub struct RunArgs {
    /// The route instruction, in natural language.
    pub instruction: String,
    /// Map file (Map2Route JSON, ProcTHOR house JSON) or `demo`.
    #[arg(long)]
    pub map: String,
    /// Where to write the route (or the program with `--emit m2r`, the RouteIR with `--emit ir`).
    #[arg(short = 'o', long)]
    pub output: Option<PathBuf>,
    /// What `-o` receives: the route, the program the model wrote (`m2r`), the RouteIR (`ir`),
    /// or the route in the map frame (`nav-path`, `waypoints`, `geojson`, `mcap`, as in
    /// `m2rc compile`).
    #[arg(long, value_enum, default_value_t = RunEmit::Route)]
    pub emit: RunEmit,
    /// Draw the route over the map into this PNG.
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Start `x,y` in metres in the map's frame (default: the map's start).
    #[arg(long, value_parser = crate::cmd::route_out::parse_xy, allow_hyphen_values = true, conflicts_with = "start_cell")]
    pub start: Option<[f64; 2]>,
    /// Start cell `row,col`.
    #[arg(long, value_parser = crate::cmd::route_out::parse_cell)]
    pub start_cell: Option<m2rc_stdlib::grid::Cell>,
    #[command(flatten)]
    pub llm: m2rc_llm::LlmArgs,
    #[command(flatten)]
    pub lower: m2rc_llm::LowerArgs,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum RunEmit {
    Route,
    M2r,
    Ir,
    NavPath,
    Waypoints,
    Geojson,
    Mcap,
}

impl RunEmit {
    fn robot(self) -> Option<crate::cmd::route_out::RobotEmit> {
        use crate::cmd::route_out::RobotEmit;
        match self {
            RunEmit::NavPath => Some(RobotEmit::NavPath),
            RunEmit::Waypoints => Some(RobotEmit::Waypoints),
            RunEmit::Geojson => Some(RobotEmit::Geojson),
            RunEmit::Mcap => Some(RobotEmit::Mcap),
            _ => None,
        }
    }
}

pub fn run(args: RunArgs) -> Result<ExitCode> {
    crate::cmd::prompt::check_instruction(&args.instruction)?;
    if args.llm.backend == Backend::Gold {
        return Err(unusable(anyhow::anyhow!(
            "--llm gold answers a baseline's calls from an episode's gold annotations, so `m2rc \
             run` (which has no episode) does not take it; use `m2rc bench run --method <baseline> \
             --llm gold` on a suite"
        )));
    }
    if let Backend::Simulated(_) = args.llm.backend {
        return Err(unusable(anyhow::anyhow!(
            "--llm simulated answers from an episode's gold program, so `m2rc run` (which has no \
             episode) does not take it; try it on a suite with `m2rc bench run --method \
             grounding2route --llm simulated`, or point `m2rc run` at a server with --llm-base-url"
        )));
    }
    let loaded = crate::io::load_map_prepared(&args.map)?;
    let frame = m2rc_stdlib::map::frame::MapFrame::of(&loaded.doc.map, Some(&loaded.doc.extra))
        .map_err(|e| unusable(anyhow::Error::new(e)))?;
    let map = &loaded.doc.map;
    let start = crate::cmd::route_out::start_from(args.start, args.start_cell, &frame, map.n())?;
    if let Some(s) = start.filter(|s| s.row as usize >= map.n() || s.col as usize >= map.n()) {
        return Err(unusable(anyhow::anyhow!(
            "--start-cell {},{} is outside the map: the grid is {n}x{n} cells",
            s.row,
            s.col,
            n = map.n()
        )));
    }
    if args.emit.robot().is_some_and(|r| r.is_binary()) && args.output.is_none() {
        return Err(unusable(anyhow::anyhow!(
            "--emit mcap writes a binary recording: pass `-o route.mcap`"
        )));
    }
    let ctx = loaded.planning()?;
    let client = match args.llm.http_client() {
        Ok(Some(c)) => c,
        Ok(None) => bail!("no HTTP client"),
        Err(e) => {
            return Err(unusable(anyhow::anyhow!("{e}\n{}", without_server(&args))));
        }
    };
    let default_cache = m2rc_llm::config::default_run_cache();
    let (store, note) = args.llm.store(&default_cache).map_err(anyhow::Error::msg)?;
    if let Some(n) = note {
        eprintln!("{n}");
    }
    if let Some(c) = &store.cache {
        eprintln!("replies cached in {}", c.dir().display());
    }
    let model = Exchange {
        store: &store,
        fetch: &client,
    };
    let budget = m2rc_benchmark::budget::EpisodeBudget::from_args(&args.lower.budget)
        .map_err(|e| crate::io::unusable(anyhow::Error::msg(e)))?;
    let meter = std::sync::Arc::new(m2rc_benchmark::budget::Meter::new(budget));
    let key = format!("{}/run", map.map_id);
    let (prompt, trace) = lower_and_plan(
        &model,
        map,
        &ctx,
        &args.instruction,
        &key,
        &args.lower.prompt_options(),
        &args.lower.repair_options(),
        &PipelineOptions {
            meter: Some(meter.clone()),
            start,
            ..PipelineOptions::default()
        },
    );
    eprintln!(
        "prompt: about {} tokens; model {}",
        prompt.estimated_tokens(),
        client.config().model
    );
    let count = |n: Option<u64>| n.map_or("unknown".to_string(), |n| n.to_string());
    for a in &trace.attempts {
        eprintln!(
            "round {}: reply {} ({} prompt + {} completion tokens, {:.0} ms) -> {}",
            a.round,
            a.reply,
            count(a.prompt_tokens),
            count(a.completion_tokens),
            a.latency_ms,
            a.outcome
        );
        if let Some(p) = &a.program {
            for line in p.lines() {
                eprintln!("    | {line}");
            }
        }
        for f in &a.local_fixes {
            eprintln!(
                "    local fix [{}]: `{}` -> `{}` ({})",
                f.code, f.replaced, f.replacement, f.message
            );
        }
        for d in &a.diagnostics {
            eprintln!("    {}[{}]: {}", d.severity, d.code, d.message);
        }
        if let Some(e) = &a.error {
            eprintln!("    error: {e}");
        }
    }
    for w in store.warnings() {
        eprintln!("warning: {w}");
    }
    if let Some(b) = &store.batch {
        let n = b.finish()?;
        eprintln!("wrote {n} batch request(s) to {}", b.path().display());
    }
    let compiled = match (&trace.outcome, trace.output) {
        (EpisodeOutcome::Success { round }, Some(c)) => {
            eprintln!("accepted in round {round}");
            c
        }
        (outcome, _) => {
            let status = match meter.exceeded() {
                Some(why) => format!("budget_exceeded ({why})"),
                None => outcome.status().to_string(),
            };
            eprintln!("no route: {status} after {} round(s)", trace.attempts.len());
            match outcome {
                EpisodeOutcome::ModelFailed { .. } => eprintln!("{}", without_server(&args)),
                EpisodeOutcome::Pending { .. } => eprintln!(
                    "answer the batch request, then run the same command with --llm-batch-in \
                     <replies.jsonl> --llm-cache-only instead of --llm-batch-out"
                ),
                _ => {}
            }
            return Ok(ExitCode::FAILURE);
        }
    };
    let program = trace.final_program.unwrap_or_default();
    let ir_json = compiled.ir.to_json();
    let route_json = serde_json::to_string_pretty(&route_document(&compiled, map))?;
    let robot = match args.emit.robot() {
        Some(kind) => Some(crate::cmd::route_out::emit(kind, map, &frame, &compiled)?),
        None => None,
    };
    let png = match &args.png {
        Some(_) => Some(
            render_map(map, &render_options(&compiled))
                .context("cannot render the route")?
                .png,
        ),
        None => None,
    };
    match (&args.output, args.emit) {
        (Some(out), RunEmit::Route) => write_atomic(out, route_json.as_bytes())?,
        (Some(out), RunEmit::M2r) => write_atomic(out, program.as_bytes())?,
        (Some(out), RunEmit::Ir) => write_atomic(out, ir_json.as_bytes())?,
        (Some(out), _) => write_atomic(out, robot.as_deref().unwrap_or(&[]))?,
        (None, _) => {}
    }
    if let (Some(path), Some(png)) = (&args.png, png) {
        write_atomic(path, &png)?;
    }
    match (args.emit, &args.output) {
        (RunEmit::M2r, None) => print!("{program}"),
        (RunEmit::Ir, None) => println!("{ir_json}"),
        (_, None) if robot.is_some() => crate::io::stdout_bytes(robot.as_deref().unwrap_or(&[]))?,
        _ => {
            println!("// program");
            print!("{program}");
            print!("{}", summary_text(&compiled));
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// What a user without a reachable model server can do instead, with this command's own map and
/// instruction filled in.
fn without_server(args: &RunArgs) -> String {
    let instruction = args.instruction.replace('\\', "\\\\").replace('"', "\\\"");
    let map = &args.map;
    format!(
        "without a model server:\n  \
         m2rc prompt --map {map} \"{instruction}\"   prints the exact messages the model would get\n  \
         m2rc run \"{instruction}\" --map {map} --llm-batch-out requests.jsonl   writes the \
         request for a batch API; answer it, then run again with --llm-batch-in <replies.jsonl> \
         --llm-cache-only to plan from the reply\n  \
         m2rc bench run --suite <suite> --method grounding2route --llm simulated --out <run>   \
         tries the pipeline without a model (the gold program with injected faults)\n\
         docs/llm.md lists servers that work (llama.cpp, vLLM, Ollama, hosted APIs)"
    )
}
