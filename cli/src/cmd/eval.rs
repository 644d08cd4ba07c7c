//! `m2rc eval`: score one route against one Map2Route episode with the exact reference
//! evaluator (HCS, PL, segment-wise SPL, raw soft-constraint values).

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::metrics::{EpisodeMetrics, EvalMap, EvalOptions, evaluate};
use m2rc_benchmark::route::read_route;
use serde_json::{Value, json};
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum EvalFormat {
    /// A readable table.
    #[default]
    Text,
    /// One JSON object: {"HCS", "PL", "SPL", "soft": [...]}.
    Json,
}

#[derive(Args)]
pub struct EvalArgs {
    /// The map JSON (a full Map2Route map, or a minimal one with grid_size and layers).
    #[arg(long, value_name = "MAP.json")]
    pub map: PathBuf,
    /// The episode (Map2Route instruction JSON).
    #[arg(long, value_name = "INSTRUCTION.json")]
    pub episode: PathBuf,
    /// The route: a [[row, col], ...] list, or an object with `trajectory`.
    #[arg(long, value_name = "ROUTE.json")]
    pub route: PathBuf,
    #[arg(long, value_enum, default_value_t = EvalFormat::Text)]
    pub format: EvalFormat,
    /// Print the full reference-style metrics object (details of every segment and soft
    /// constraint) instead of the summary; implies JSON.
    #[arg(long)]
    pub full: bool,
    /// Paper variant: count each region waypoint once (the reference code counts repeats).
    #[arg(long)]
    pub dedup_region_waypoints: bool,
}

pub fn run(args: EvalArgs) -> Result<ExitCode> {
    let map_file = args.map.display().to_string();
    let text =
        std::fs::read_to_string(&args.map).with_context(|| format!("{map_file}: cannot read"))?;
    let map_json: Value =
        serde_json::from_str(&text).with_context(|| format!("{map_file}: not valid JSON"))?;
    drop(text);
    let map = EvalMap::from_json(&map_json).with_context(|| map_file.clone())?;
    drop(map_json);
    let episode = Episode::read(&args.episode)?;
    let route = read_route(&args.route, map.n())?;
    let opts = EvalOptions {
        dedup_region_waypoints: args.dedup_region_waypoints,
    };
    let metrics = evaluate(&route, &episode, &map, &opts)
        .with_context(|| format!("{}: cannot evaluate", args.episode.display()))?;

    let out = if args.full {
        serde_json::to_string_pretty(&metrics)? + "\n"
    } else {
        match args.format {
            EvalFormat::Json => serde_json::to_string(&summary_json(&metrics))? + "\n",
            EvalFormat::Text => text_table(&metrics),
        }
    };
    let mut stdout = std::io::stdout().lock();
    stdout.write_all(out.as_bytes())?;
    stdout.flush()?;
    Ok(ExitCode::SUCCESS)
}

/// The summary schema: `{"HCS", "PL", "SPL", "soft": [{constraint_id, preference_type,
/// raw_value, status}]}`.
pub fn summary_json(m: &EpisodeMetrics) -> Value {
    let soft: Vec<Value> = m
        .details
        .soft_constraints
        .iter()
        .map(|d| {
            json!({
                "constraint_id": d.constraint_id,
                "preference_type": d.preference_type,
                "raw_value": d.raw_value.filter(|x| x.is_finite()),
                "status": d.status,
            })
        })
        .collect();
    json!({"HCS": m.hcs, "PL": m.pl, "SPL": m.segment_wise_spl, "soft": soft})
}

fn num(x: Option<f64>) -> String {
    match x {
        Some(v) if v.is_finite() => format!("{v:.6}"),
        Some(v) => format!("{v}"),
        None => "-".into(),
    }
}

fn text_table(m: &EpisodeMetrics) -> String {
    let mut s = String::new();
    let h = &m.details.hcs;
    let _ = writeln!(
        s,
        "HCS  {:.6}  ({}/{} targets)",
        m.hcs, h.valid_completed_count, h.must_pass_count
    );
    if let Some(f) = &h.failure_type {
        let who = h.first_must_avoid_violation.as_deref().unwrap_or("-");
        let _ = writeln!(s, "     failed: {f} ({who})");
    }
    let _ = writeln!(s, "PL   {:.6} m", m.pl);
    let _ = writeln!(s, "SPL  {:.6}", m.segment_wise_spl);
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "{:<4} {:<14} {:<24} {:>12} {:>12} {:>9}  status",
        "seg", "orders", "goal", "L* (m)", "L (m)", "SPL"
    );
    for seg in &m.details.segments {
        let orders = format!(
            "{} -> {}",
            seg.from_order.map_or("-".into(), |o| o.to_string()),
            seg.to_order.map_or("-".into(), |o| o.to_string())
        );
        let _ = writeln!(
            s,
            "{:<4} {:<14} {:<24} {:>12} {:>12} {:>9.6}  {}",
            seg.index,
            orders,
            seg.goal_region_constraint_id,
            num(seg.l_star),
            num(seg.l),
            seg.spl,
            seg.status
        );
    }
    if !m.details.soft_constraints.is_empty() {
        let _ = writeln!(s);
        let _ = writeln!(
            s,
            "{:<28} {:<28} {:>12}  status",
            "soft constraint", "type", "raw value"
        );
        for d in &m.details.soft_constraints {
            let _ = writeln!(
                s,
                "{:<28} {:<28} {:>12}  {}",
                d.constraint_id,
                d.preference_type.as_deref().unwrap_or("-"),
                num(d.raw_value),
                d.status
            );
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn metrics() -> EpisodeMetrics {
        let map = EvalMap::from_json(&json!({
            "grid_size": 4,
            "layers": {"occupancy": [[1, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0]],
                       "object_instance": [[0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0]]}
        }))
        .unwrap();
        let pass = |id: &str, r: i64, c: i64, o: i64| json!({"constraint_id": id, "kind": "must_pass", "shape": "freeform", "order": o, "cells": [[r, c]]});
        let ep = Episode::from_value(
            json!({"hard_constraints": [pass("start", 1, 1, 1), pass("goal", 3, 3, 2)],
                   "soft_constraints": [{"constraint_id": "c", "preference_type": "clearance"}]}),
            "ep.json",
        )
        .unwrap();
        evaluate(
            &[[1, 1], [2, 2], [3, 3]],
            &ep,
            &map,
            &EvalOptions::default(),
        )
        .unwrap()
    }

    #[test]
    fn json_summary_has_exactly_the_documented_keys() {
        let v = summary_json(&metrics());
        let keys: Vec<&str> = v.as_object().unwrap().keys().map(String::as_str).collect();
        assert_eq!(keys, ["HCS", "PL", "SPL", "soft"]);
        assert_eq!(v["HCS"], 1.0);
        assert_eq!(v["SPL"], 1.0);
        let soft = &v["soft"][0];
        let keys: Vec<&str> = soft
            .as_object()
            .unwrap()
            .keys()
            .map(String::as_str)
            .collect();
        assert_eq!(
            keys,
            ["constraint_id", "preference_type", "raw_value", "status"]
        );
        assert_eq!(soft["status"], "computed");
        // Mean distance to the obstacle at (0,0) from (1,1), (2,2), (3,3).
        let expected = (2f64.sqrt() + 8f64.sqrt() + 18f64.sqrt()) / 3.0;
        assert!((soft["raw_value"].as_f64().unwrap() - expected).abs() < 1e-12);
    }

    #[test]
    fn text_table_lists_segments_and_soft_constraints() {
        let t = text_table(&metrics());
        assert!(t.starts_with("HCS  1.000000  (1/1 targets)"), "{t}");
        assert!(t.contains("goal"), "{t}");
        assert!(t.contains("completed"), "{t}");
        assert!(t.contains("clearance"), "{t}");
    }
}
