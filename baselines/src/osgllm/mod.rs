//! OSG-LLM ("Optimal Scene Graph Planning with LLM Guidance", ICRA'24) as Map2Route adapted it:
//! three model calls (ground the instruction to a scene graph, translate the grounded goals to
//! prefix LTL, name the rooms a search should prefer), a product-state A* over (cell, residual
//! formula) with an expansion limit, and, when that finds nothing and nothing is avoided, the
//! room-skeleton and sequential fallbacks. See `docs/baselines.md`, "OSG-LLM".

pub mod fallback;
pub mod gold;
pub mod graph;
pub mod method;
pub mod prefix;
pub mod product;
pub mod prompts;
pub mod reply;

use graph::SceneGraph;
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use serde_json::{Value, json};

/// The method's name on the command line and in records.
pub const NAME: &str = "osg-llm";

/// The calls of one episode, in order.
pub const CALLS: [&str; 3] = ["grounding", "ltl", "heuristic"];

/// A model call that did not give a reply.
#[derive(Clone, Debug, PartialEq)]
pub enum CallError {
    /// The request went into a batch file; the episode waits for the next round.
    Pending(String),
    /// The call failed (transport, refusal, cache-only miss).
    Failed(String),
}

/// Whatever answers the method's calls: a model through the harness, or the gold oracle.
pub trait Ask {
    /// The reply text to call `call` (one of [`CALLS`]).
    fn ask(&mut self, call: &str, system: &str, user: &str) -> Result<String, CallError>;
}

/// The APs the translation may use: the goals', then the avoids' (each once).
pub fn allowed_aps(goals: &[String], avoids: &[String]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for a in goals.iter().chain(avoids) {
        if !out.contains(a) {
            out.push(a.clone());
        }
    }
    out
}

/// How an episode ended, with the `osgllm` record block.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// Starts at the start cell; just the start cell when the method failed.
    pub trajectory: Vec<Cell>,
    /// `ok`, `ltl_translation_failed`, `planning_failed`, or `pending` (batch).
    pub status: String,
    pub record: Value,
}

/// Runs one episode: the three calls, then the planners, in the adaptation's fallback order.
pub fn run_episode(
    map: &SemanticMap,
    graph: &SceneGraph,
    instruction: &str,
    start: Cell,
    ask: &mut dyn Ask,
) -> Outcome {
    let mut rec = serde_json::Map::new();
    rec.insert("scene_graph_summary".into(), graph.summary());
    let failed = |rec: serde_json::Map<String, Value>, status: &str, call: &str, why: String| {
        let mut rec = rec;
        rec.insert("failed_call".into(), json!(call));
        rec.insert("error".into(), json!(why));
        Outcome {
            trajectory: vec![start],
            status: status.into(),
            record: Value::Object(rec),
        }
    };
    macro_rules! call {
        ($name:expr, $sys:expr, $user:expr) => {
            match ask.ask($name, $sys, &$user) {
                Ok(t) => t,
                Err(CallError::Pending(id)) => {
                    return failed(
                        rec,
                        "pending",
                        $name,
                        format!("waiting for batch reply {id}"),
                    );
                }
                Err(CallError::Failed(why)) => {
                    return failed(rec, "ltl_translation_failed", $name, why);
                }
            }
        };
    }
    // 1. Grounding.
    let text = call!(
        CALLS[0],
        prompts::GROUNDING_SYSTEM,
        prompts::grounding_user(instruction, &graph.prompt_json())
    );
    let grounding = match reply::parse_grounding(&text, graph) {
        Ok(g) => g,
        Err(e) => return failed(rec, "ltl_translation_failed", CALLS[0], e),
    };
    let ap = |id: &String| graph.node(id).map(|n| n.ap.clone()).unwrap_or_default();
    let goals: Vec<String> = grounding.goals.iter().map(ap).collect();
    let avoids: Vec<String> = grounding.avoids.iter().map(ap).collect();
    rec.insert(
        "grounding".into(),
        json!({"goal_aps": goals, "avoid_aps": avoids,
               "unsupported_phrases": grounding.unsupported, "entity_bindings": grounding.bindings}),
    );
    // 2. Translation.
    let allowed = allowed_aps(&goals, &avoids);
    let text = call!(
        CALLS[1],
        prompts::LTL_SYSTEM,
        prompts::ltl_user(instruction, &goals, &avoids, &allowed)
    );
    let (formula, source) = match reply::parse_ltl(&text, &allowed, &goals, &avoids) {
        Ok(x) => x,
        Err(e) => return failed(rec, "ltl_translation_failed", CALLS[1], e),
    };
    rec.insert(
        "ltl".into(),
        json!({"prefix": prefix::to_prefix(&formula, &allowed), "source": source.as_str(),
               "allowed_aps": allowed}),
    );
    // 3. Heuristic (only orders the room search of the fallback).
    let text = call!(
        CALLS[2],
        prompts::HEURISTIC_SYSTEM,
        prompts::heuristic_user(instruction, &goals, &graph.heuristic_json())
    );
    let (preferred, unknown) = match reply::parse_heuristic(&text, graph) {
        Ok(x) => x,
        Err(e) => return failed(rec, "ltl_translation_failed", CALLS[2], e),
    };
    rec.insert(
        "heuristic".into(),
        json!({"preferred_rooms": preferred, "ignored_ids": unknown}),
    );
    let limit = product::MAX_EXPANSIONS.min(product::TIME_LIMIT_EXPANSIONS);
    let start_room = graph.room_of_cell(map, start);
    let planned = plan(
        graph, &formula, &allowed, &goals, &avoids, &preferred, start, start_room, limit,
    );
    rec.insert("planner".into(), planned.record);
    rec.insert("method_level_deviations".into(), json!(DEVIATIONS));
    match planned.trajectory {
        Some(t) => Outcome {
            trajectory: t,
            status: "ok".into(),
            record: Value::Object(rec),
        },
        None => Outcome {
            trajectory: vec![start],
            status: "planning_failed".into(),
            record: Value::Object(rec),
        },
    }
}

/// What this implementation does differently from the adaptation, written into every record.
pub const DEVIATIONS: &[&str] = &[
    "product A* over minimised automaton states (equivalent residuals merged), not syntactic residuals",
    "30 s planning limit read as 300000 expansions; the 250000-expansion limit binds first",
    "room adjacency from the map's passages (includes door patches without a room label)",
    "not the official AMRA* multi-queue planner (as in the adaptation)",
];

/// The planners' result.
pub struct Planned {
    pub trajectory: Option<Vec<Cell>>,
    pub record: Value,
}

/// Product A* within `limit` expansions; then, with no avoids, the skeleton and the plain
/// sequential fallbacks.
#[allow(clippy::too_many_arguments)]
pub fn plan(
    graph: &SceneGraph,
    formula: &m2rc_compiler::ltl::Formula,
    allowed: &[String],
    goals: &[String],
    avoids: &[String],
    preferred: &[u32],
    start: Cell,
    start_room: Option<u32>,
    limit: u64,
) -> Planned {
    let region = |atom: &str| product::alias_region(graph, allowed, atom);
    let result = product::search(&product::ProductQuery::osg(
        graph, formula, &region, start, limit,
    ));
    let mut rec = serde_json::Map::new();
    match &result {
        Ok(r) => {
            rec.insert(
                "product".into(),
                json!({"result": "found", "expansions": r.expansions,
                       "automaton_states": r.automaton_states, "length_cells": r.cost,
                       "expansion_limit": limit}),
            );
            rec.insert("used".into(), json!("product"));
            return Planned {
                trajectory: Some(r.trajectory.clone()),
                record: Value::Object(rec),
            };
        }
        Err(e) => {
            let expansions = match e {
                product::ProductError::NoRoute { expansions }
                | product::ProductError::Limit { expansions } => Some(*expansions),
                _ => None,
            };
            rec.insert(
                "product".into(),
                json!({"result": e.kind(), "message": e.to_string(), "expansions": expansions,
                       "expansion_limit": limit}),
            );
        }
    }
    if !avoids.is_empty() {
        rec.insert("used".into(), json!(null));
        rec.insert(
            "fallback".into(),
            json!("none: the instruction has avoids, and the fallbacks cannot keep them"),
        );
        return Planned {
            trajectory: None,
            record: Value::Object(rec),
        };
    }
    if let Some(augmented) = fallback::skeleton_goals(graph, start_room, goals, preferred) {
        rec.insert("skeleton_goals".into(), json!(augmented));
        match fallback::sequential(graph, start, &augmented) {
            Ok(t) => {
                rec.insert("used".into(), json!("room_skeleton"));
                return Planned {
                    trajectory: Some(t),
                    record: Value::Object(rec),
                };
            }
            Err(f) => {
                rec.insert(
                    "skeleton_failure".into(),
                    json!({"goal": f.goal, "reached": f.reached}),
                );
            }
        }
    } else {
        rec.insert("skeleton_goals".into(), json!(null));
    }
    match fallback::sequential(graph, start, goals) {
        Ok(t) => {
            rec.insert("used".into(), json!("sequential"));
            Planned {
                trajectory: Some(t),
                record: Value::Object(rec),
            }
        }
        Err(f) => {
            rec.insert("used".into(), json!(null));
            rec.insert(
                "sequential_failure".into(),
                json!({"goal": f.goal, "reached": f.reached}),
            );
            Planned {
                trajectory: None,
                record: Value::Object(rec),
            }
        }
    }
}

#[cfg(test)]
mod tests;
