//! `m2rc baseline explain`: one instruction through one baseline, every step printed (each call
//! and its reply, the grounding, the formula and its automaton's size, the planner's figures, the
//! route), so a user can see where a representation loses the instruction. Generic over the
//! baselines: each method records its trace in its block of the prediction record.

use crate::io::unusable;
use anyhow::Result;
use clap::{Args, Subcommand, ValueEnum};
use m2rc_benchmark::episode::{Episode, StartPose};
use m2rc_benchmark::methods::PreparedMap;
use serde_json::Value;
use std::process::ExitCode;

#[derive(Subcommand)]
pub enum BaselineCommand {
    /// Run one instruction through a baseline and print every step.
    Explain(Box<ExplainArgs>),
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ExplainFormat {
    Text,
    Json,
}

#[derive(Args)]
pub struct ExplainArgs {
    /// The route instruction, in natural language.
    pub instruction: String,
    /// The baseline (lang2ltl, lang2ltl-2, limp, ...).
    #[arg(long)]
    pub method: String,
    /// Map file (Map2Route JSON, ProcTHOR house JSON) or `demo`.
    #[arg(long)]
    pub map: String,
    /// Start `x,y` in metres in the map's frame, as `compile` and `run` take it (default: the
    /// map's start, else its first free cell).
    #[arg(long, value_parser = crate::cmd::route_out::parse_xy, allow_hyphen_values = true, conflicts_with = "start_cell")]
    pub start: Option<[f64; 2]>,
    /// Start cell `row,col`.
    #[arg(long, value_parser = crate::cmd::route_out::parse_cell)]
    pub start_cell: Option<m2rc_stdlib::grid::Cell>,
    /// `text`, or the method's whole record block as JSON.
    #[arg(long, value_enum, default_value_t = ExplainFormat::Text)]
    pub format: ExplainFormat,
    #[command(flatten)]
    pub llm: m2rc_llm::LlmArgs,
    #[command(flatten)]
    pub baseline: m2rc_baselines::BaselineArgs,
}

pub fn run(c: BaselineCommand) -> Result<ExitCode> {
    match c {
        BaselineCommand::Explain(a) => explain(*a),
    }
}

fn explain(a: ExplainArgs) -> Result<ExitCode> {
    crate::cmd::prompt::check_instruction(&a.instruction)?;
    if a.llm.backend != m2rc_llm::Backend::Http {
        return Err(unusable(anyhow::anyhow!(
            "--llm {}: `baseline explain` takes an instruction, not an episode, so there are no \
             gold annotations or gold program to answer from; explain needs a model server \
             (`--llm http`). For gold replies run `m2rc bench run --method {} --llm gold --suite S \
             --shard 1/100` and read the records",
            if a.llm.backend == m2rc_llm::Backend::Gold {
                "gold"
            } else {
                "simulated"
            },
            a.method
        )));
    }
    let (doc, _) = crate::io::load_map_doc_kind(&a.map)?;
    let frame = m2rc_stdlib::map::frame::MapFrame::of(&doc.map, Some(&doc.extra))
        .map_err(|e| unusable(anyhow::Error::new(e).context(format!("map `{}`", a.map))))?;
    let map = doc.map;
    let start = match crate::cmd::route_out::start_from(a.start, a.start_cell, &frame, map.n())? {
        Some(c) => c,
        None => map
            .start
            .or_else(|| {
                map.occupancy
                    .iter_cells()
                    .find(|(c, _)| map.is_free(*c))
                    .map(|(c, _)| c)
            })
            .ok_or_else(|| unusable(anyhow::anyhow!("the map has no free cell to start from")))?,
    };
    if !map.is_free(start) {
        return Err(unusable(anyhow::anyhow!(
            "the start cell {},{} is not a free cell of the map",
            start.row,
            start.col
        )));
    }
    let built = m2rc_baselines::build(
        &a.method,
        &a.llm,
        &a.baseline,
        &m2rc_llm::config::default_run_cache(),
    )
    .map_err(|e| unusable(anyhow::Error::msg(e)))?
    .ok_or_else(|| {
        unusable(anyhow::anyhow!(
            "--method: `{}` is not a baseline (known: {})",
            a.method,
            m2rc_baselines::baseline_names().join(", ")
        ))
    })?;
    let episode = Episode {
        map_id: Some(map.map_id.clone()),
        instruction: Some(a.instruction.clone()),
        start_pose: Some(StartPose {
            row: Some(start.row as i64),
            col: Some(start.col as i64),
            ..StartPose::default()
        }),
        ..Episode::default()
    };
    let prepared = PreparedMap::new(map);
    let p = built
        .method
        .predict(&prepared, &episode)
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    if let Some(b) = &built.setup.store.batch {
        b.finish()?;
    }
    let block = p
        .extra
        .get(built.method.name())
        .cloned()
        .unwrap_or(Value::Null);
    let text = match a.format {
        ExplainFormat::Json => serde_json::to_string_pretty(&block)? + "\n",
        ExplainFormat::Text => render(
            built.method.name(),
            &block,
            &p.trajectory,
            prepared.map.resolution(),
        ),
    };
    crate::io::stdout(&text)?;
    Ok(if p.status.is_none() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

fn render(name: &str, block: &Value, route: &[m2rc_stdlib::grid::Cell], resolution: f64) -> String {
    let mut out = format!(
        "{name} — {}\nstatus: {}\n",
        block["model"].as_str().unwrap_or("?"),
        block["status"].as_str().unwrap_or("?")
    );
    if let Some(f) = block["failure"].as_str() {
        out += &format!("failure: {f}\n");
    }
    for (i, c) in block["calls"].as_array().into_iter().flatten().enumerate() {
        out += &format!("\ncall {} `{}`", i + 1, c["step"].as_str().unwrap_or("?"));
        if c.get("embeddings").is_some() {
            out += &format!(
                " (embeddings: {} input(s), {} dimensions)\n",
                c["inputs"], c["dims"]
            );
        } else {
            out += &format!(
                "\n  asked: {}\n  reply: {}\n",
                indent(c["user"].as_str().unwrap_or("")),
                indent(c["reply"].as_str().unwrap_or("(none)"))
            );
        }
        if let Some(e) = c["error"].as_str() {
            out += &format!("  error: {e}\n");
        }
    }
    out.push('\n');
    if let Value::Object(m) = block {
        for (k, v) in m {
            if ["calls", "model", "status", "failure", "gold_replies"].contains(&k.as_str()) {
                continue;
            }
            let v = match v {
                Value::String(s) => s.clone(),
                other => serde_json::to_string_pretty(other).unwrap_or_default(),
            };
            out += &format!("{k}: {}\n", indent(&v));
        }
    }
    if let Some(f) = block["formula"].as_str()
        && let Ok(formula) = m2rc_baselines::common::prefix_ltl::parse_prefix(f)
    {
        let mut atoms: Vec<String> = formula.atoms().iter().map(|s| s.to_string()).collect();
        atoms.dedup();
        atoms.sort();
        atoms.dedup();
        match m2rc_compiler::ltl::Dfa::build(&formula, &atoms, true) {
            Ok(d) => {
                out += &format!(
                    "automaton: {} states over {} atoms\n",
                    d.states(),
                    atoms.len()
                )
            }
            Err(e) => out += &format!("automaton: not built ({e})\n"),
        }
    }
    // `+ 0.0` prints an empty route as 0.0, not -0.0.
    let len: f64 = route.windows(2).map(|w| w[0].dist(w[1])).sum::<f64>() * resolution + 0.0;
    out += &format!("route: {} cells, {len:.1} m\n", route.len());
    out
}

fn indent(s: &str) -> String {
    s.replace('\n', "\n    ")
}
