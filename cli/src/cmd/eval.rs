//! `m2rc eval`: score one route against one Map2Route episode with the exact reference
//! evaluator (HCS, PL, segment-wise SPL, raw soft-constraint values), and say whether the route
//! could be driven (the reference scores jumps through walls as straight segments; so does
//! `eval`, with a warning and `route_valid: false`).

use crate::io::{display_name, read_to_string, unusable};
use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::metrics::{EpisodeMetrics, EvalMap, EvalOptions, evaluate};
use m2rc_benchmark::route::parse_route_text;
use m2rc_benchmark::route::validity::{RouteValidity, route_validity};
use m2rc_stdlib::load::SourceKind;
use serde_json::{Value, json};
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum EvalFormat {
    /// A readable table.
    #[default]
    Text,
    /// One JSON object: {"HCS", "PL", "SPL", "soft": [...], "route_valid", "route_validity"}.
    Json,
}

#[derive(Args)]
pub struct EvalArgs {
    /// The map: a Map2Route map, a ProcTHOR house, `demo`, a minimal map JSON with grid_size and
    /// layers, or `-` for standard input.
    #[arg(long, value_name = "MAP")]
    pub map: String,
    /// The episode (Map2Route instruction JSON); `-` reads standard input.
    #[arg(long, value_name = "INSTRUCTION.json")]
    pub episode: PathBuf,
    /// The route, in any of these forms: a bare [[row, col], ...] list; or an object holding
    /// that list under `trajectory` (`m2rc compile -o` output, a `bench run` or `bench import`
    /// record, the reference's method output), `predicted_trajectory`, or
    /// `human_expert_trajectory` (an episode file: its expert route), the first of the three
    /// that is a list. Points are two integers inside the map; `-` reads standard input.
    #[arg(long, value_name = "ROUTE.json")]
    pub route: PathBuf,
    /// Print a readable table (text) or one JSON object {"HCS", "PL", "SPL", "soft",
    /// "route_valid", "route_validity"} (json).
    #[arg(long, value_enum, default_value_t = EvalFormat::Text)]
    pub format: EvalFormat,
    /// Print the full reference-style metrics object (details of every segment and soft
    /// constraint) instead of the summary; implies JSON.
    #[arg(long)]
    pub full: bool,
    /// Paper variant: count each region waypoint once (the reference code counts repeats).
    #[arg(long)]
    pub dedup_region_waypoints: bool,
    /// Score even when the episode names another map than the one given (by default a mismatch
    /// of the episode's `map_id` and the map's id is refused).
    #[arg(long)]
    pub any_map: bool,
    /// Refuse (exit 2) an episode with cells outside the map, orders below 1 or an unknown
    /// preference type, as planning and `suite build` do. By default these are warnings and the
    /// episode is scored as the reference evaluator scores it.
    #[arg(long)]
    pub strict: bool,
    /// Not taken (refused with the way to do it): `eval` scores a route from its own first cell,
    /// so plan it from the robot's start (`m2rc compile --start X,Y --episode EP`) and score that.
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    pub start: Option<String>,
    /// Not taken, as `--start`.
    #[arg(long, value_name = "ROW,COL")]
    pub start_cell: Option<String>,
}

/// The evaluator's view of a map argument, and the map's id when it is a Map2Route map (a
/// house's or the demo's id is made up by the importer, so it cannot be checked).
fn eval_map(arg: &str) -> Result<(EvalMap, Option<String>)> {
    let staged = crate::io::MapArg::new(arg)?;
    match crate::io::load_map_prepared(&staged.arg) {
        Ok(loaded) => {
            let map = &loaded.doc.map;
            let id = (loaded.kind == SourceKind::Map2RouteMap && !map.map_id.is_empty())
                .then(|| map.map_id.clone());
            let eval_map = EvalMap::from_semantic_map(map);
            if let Some(sq) = &loaded.obstacle_sq {
                eval_map.seed_clearance_sq(sq);
            }
            crate::timings::mark("eval: evaluator's map built");
            Ok((eval_map, id))
        }
        Err(load_err) => {
            // A minimal map (grid_size and layers only) is not a full Map2Route map.
            let Ok(text) = std::fs::read_to_string(&staged.arg) else {
                return Err(load_err);
            };
            let Ok(value) = serde_json::from_str::<Value>(&text) else {
                return Err(load_err);
            };
            let map = EvalMap::from_json(&value).map_err(|_| load_err)?;
            let id = value
                .get("map_id")
                .and_then(Value::as_str)
                .map(str::to_string);
            Ok((map, id))
        }
    }
}

/// The last `/`-separated part of a map id (`procthor/001_valunseen` -> `001_valunseen`).
pub fn map_id_tail(id: &str) -> &str {
    id.rsplit('/').next().unwrap_or(id)
}

/// Refuses an episode made for another map than `map_id`.
pub fn check_same_map(
    episode: &Episode,
    episode_name: &str,
    map_id: Option<&str>,
    map_name: &str,
) -> Result<()> {
    if let (Some(ep), Some(map)) = (episode.map_id.as_deref(), map_id)
        && map_id_tail(ep) != map_id_tail(map)
    {
        anyhow::bail!(
            "{episode_name} is an episode of map `{ep}`, but {map_name} is map `{map}`; give the episode's own map (or --any-map to score anyway)"
        );
    }
    Ok(())
}

pub fn run(args: EvalArgs) -> Result<ExitCode> {
    if let Some(flag) = [("--start", &args.start), ("--start-cell", &args.start_cell)]
        .iter()
        .find_map(|(f, v)| v.is_some().then_some(*f))
    {
        return Err(unusable(anyhow::anyhow!(
            "{flag}: `m2rc eval` takes no start: it scores a route against an episode from the \
             route's own first cell, as the reference evaluator does (every segment is measured \
             from where the route actually is)\nhelp: plan the route from the robot's start with \
             `m2rc compile PROGRAM.m2r --map MAP --episode EPISODE.json {flag} ... -o route.json`, \
             then score it with `m2rc eval --map MAP --episode EPISODE.json --route route.json`"
        )));
    }
    let (map, map_id) = eval_map(&args.map)?;
    let ep_name = display_name(&args.episode);
    let episode = Episode::from_json_str(&read_to_string(&args.episode)?, &ep_name)?;
    check_episode_for_eval(&episode, map.n(), &ep_name, args.strict)?;
    if !args.any_map {
        check_same_map(&episode, &ep_name, map_id.as_deref(), &args.map)?;
    }
    let route_name = display_name(&args.route);
    let route_text = crate::io::read_to_string_capped(
        &args.route,
        m2rc_benchmark::route_read::MAX_ROUTE_FILE_BYTES,
        "a route file",
    )
    .map_err(unusable)?;
    let route = parse_route_text(&route_text, map.n(), &route_name)?;
    let opts = EvalOptions {
        dedup_region_waypoints: args.dedup_region_waypoints,
    };
    crate::timings::mark("eval: episode and route read");
    let metrics = evaluate(&route, &episode, &map, &opts)
        .with_context(|| format!("{ep_name}: cannot evaluate"))?;
    crate::timings::mark("eval: scored");
    let validity = route_validity(&route, &map);
    if !validity.valid {
        eprintln!(
            "warning: {route_name}: the route is not drivable: {}; scored anyway, as the reference evaluator scores it (straight segments between points)",
            validity.summary()
        );
    }

    let out = if args.full {
        let mut full = serde_json::to_value(&metrics)?;
        add_validity(&mut full, &validity);
        serde_json::to_string_pretty(&full)? + "\n"
    } else {
        match args.format {
            EvalFormat::Json => serde_json::to_string(&summary_json(&metrics, &validity))? + "\n",
            EvalFormat::Text => text_table(&metrics, &validity),
        }
    };
    crate::io::stdout(&out)?;
    crate::timings::mark("eval: written");
    Ok(ExitCode::SUCCESS)
}

/// Refuses what the reference evaluator refuses too (and, with `strict`, everything the
/// episode check finds); warns about the rest, which is scored as the reference scores it.
fn check_episode_for_eval(episode: &Episode, n: usize, name: &str, strict: bool) -> Result<()> {
    use m2rc_benchmark::episode_check::{check_episode, episode_problems};
    if strict {
        return check_episode(episode, Some(n), name).map_err(unusable);
    }
    let problems = episode_problems(episode, Some(n));
    if let Some(p) = problems.iter().find(|p| p.reference.is_none()) {
        return Err(unusable(p.clone().into_error(name)));
    }
    for p in &problems {
        if let Some(w) = p.warning(name) {
            eprintln!("{w}");
        }
    }
    Ok(())
}

/// Adds `route_valid` and `route_validity` (counts and the first problem) to a JSON object.
fn add_validity(out: &mut Value, validity: &RouteValidity) {
    if let Value::Object(o) = out {
        o.insert("route_valid".into(), Value::Bool(validity.valid));
        o.insert(
            "route_validity".into(),
            serde_json::to_value(validity).unwrap_or(Value::Null),
        );
    }
}

/// The summary schema: `{"HCS", "PL", "SPL", "soft": [{constraint_id, preference_type,
/// raw_value, status}], "route_valid", "route_validity"}`.
pub fn summary_json(m: &EpisodeMetrics, validity: &RouteValidity) -> Value {
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
    let mut out = json!({"HCS": m.hcs, "PL": m.pl, "SPL": m.segment_wise_spl, "soft": soft});
    add_validity(&mut out, validity);
    out
}

fn num(x: Option<f64>) -> String {
    match x {
        Some(v) if v.is_finite() => format!("{v:.6}"),
        Some(v) => format!("{v}"),
        None => "-".into(),
    }
}

fn text_table(m: &EpisodeMetrics, validity: &RouteValidity) -> String {
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
    let _ = writeln!(
        s,
        "route {}",
        if validity.valid && !validity.occupancy_checked {
            "valid by adjacency only (the map has no occupancy layer: free cells and corners not checked)".to_string()
        } else if validity.valid {
            "valid (every step to a neighbouring free cell, no corner cut)".to_string()
        } else {
            format!("INVALID (not drivable): {}", validity.summary())
        }
    );
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

    fn map() -> EvalMap {
        EvalMap::from_json(&json!({
            "grid_size": 4,
            "layers": {"occupancy": [[1, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0]],
                       "object_instance": [[0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0]]}
        }))
        .unwrap()
    }

    /// The metrics and the validity of `route` from the start (1,1) to the goal (3,3).
    fn scored(route: &[[i64; 2]]) -> (EpisodeMetrics, RouteValidity) {
        let pass = |id: &str, r: i64, c: i64, o: i64| json!({"constraint_id": id, "kind": "must_pass", "shape": "freeform", "order": o, "cells": [[r, c]]});
        let ep = Episode::from_value(
            json!({"hard_constraints": [pass("start", 1, 1, 1), pass("goal", 3, 3, 2)],
                   "soft_constraints": [{"constraint_id": "c", "preference_type": "clearance"}]}),
            "ep.json",
        )
        .unwrap();
        let map = map();
        let m = evaluate(route, &ep, &map, &EvalOptions::default()).unwrap();
        (m, route_validity(route, &map))
    }

    fn metrics() -> (EpisodeMetrics, RouteValidity) {
        scored(&[[1, 1], [2, 2], [3, 3]])
    }

    #[test]
    fn json_summary_has_exactly_the_documented_keys() {
        let (m, v) = metrics();
        let v = summary_json(&m, &v);
        let keys: Vec<&str> = v.as_object().unwrap().keys().map(String::as_str).collect();
        assert_eq!(
            keys,
            ["HCS", "PL", "SPL", "soft", "route_valid", "route_validity"]
        );
        assert_eq!(v["HCS"], 1.0);
        assert_eq!(v["SPL"], 1.0);
        assert_eq!(v["route_valid"], true);
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
    fn a_jump_keeps_the_reference_score_and_is_reported_invalid() {
        let (m, v) = scored(&[[1, 1], [3, 3]]);
        let j = summary_json(&m, &v);
        assert_eq!(j["HCS"], 1.0);
        assert_eq!(j["SPL"], 1.0);
        assert_eq!(j["route_valid"], false);
        assert_eq!(j["route_validity"]["non_adjacent_steps"], 1);
        assert_eq!(
            j["route_validity"]["first_problem"],
            json!({"kind": "non_adjacent_step", "step": 0, "from": [1, 1], "to": [3, 3]})
        );
        let t = text_table(&m, &v);
        assert!(
            t.contains("route INVALID (not drivable): 1 step that is not to a neighbouring cell"),
            "{t}"
        );
    }

    #[test]
    fn without_occupancy_the_table_does_not_claim_free_cells_were_checked() {
        let (m, _) = metrics();
        let bare = EvalMap::from_json(&json!({"grid_size": 4})).unwrap();
        let v = route_validity(&[[1, 1], [2, 2]], &bare);
        let t = text_table(&m, &v);
        assert!(t.contains("route valid by adjacency only"), "{t}");
    }

    #[test]
    fn text_table_lists_segments_and_soft_constraints() {
        let (m, v) = metrics();
        let t = text_table(&m, &v);
        assert!(t.starts_with("HCS  1.000000  (1/1 targets)"), "{t}");
        assert!(t.contains("route valid"), "{t}");
        assert!(t.contains("goal"), "{t}");
        assert!(t.contains("completed"), "{t}");
        assert!(t.contains("clearance"), "{t}");
    }
}
