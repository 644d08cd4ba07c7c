//! ILN (Intelligent LiDAR Navigation with an LLM copilot, IROS'25), adapted to Map2Route as the
//! paper did: the model picks one destination area on an area–passage graph and rates the
//! passages' costs; Dijkstra over passages chooses the area route and grid A* drives it through
//! the passages' anchors to the destination's medoid. Objects, order, avoids and preferences are
//! ignored by design (the method has no place for them).
//!
//! Two calls per episode. Failures keep the route so far (the start cell at least) and say why in
//! the status: `grounding_failed` (an area not in the graph), `llm_output_invalid` (a reply that
//! is not the asked JSON), `no_graph_path`, `grid_realization_failed`, `model_failed`.

pub mod graph;
pub mod method;
pub mod prompts;
pub mod reply;
pub mod route;

use crate::common::failure::{Failure, PENDING};
use crate::common::grid::GridSearch;
use graph::AreaGraph;
use m2rc_compiler::lower::Message;
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use route::Realised;
use serde_json::{Value, json};

/// The gold oracle's reply at one step, or why it has none.
pub type Gold<'a> = &'a dyn Fn() -> Result<String, String>;

/// One model call (`Session::chat` in a run, a script in the tests): a step name (part of the
/// request id), the messages, and the gold oracle's reply; the caller decides which answers.
pub type Ask<'a> = dyn FnMut(&str, Vec<Message>, Gold<'_>) -> Result<String, Failure> + 'a;

/// What an episode produced.
#[derive(Clone, Debug, PartialEq)]
pub struct IlnOutcome {
    pub trajectory: Vec<Cell>,
    /// `ok`, or the failure status.
    pub status: String,
    /// The record's `iln` block.
    pub info: Value,
    /// Set when a call is waiting for a batch reply: the episode is pending.
    pub pending: bool,
}

/// Runs ILN on one episode. `gold_dest` is the oracle's destination area id (for the gold
/// replies; unused by a real model; `None` when the annotations give none).
pub fn run(
    map: &SemanticMap,
    g: &AreaGraph,
    grid: &mut GridSearch<'_>,
    instruction: &str,
    start: Cell,
    gold_dest: Option<&str>,
    ask: &mut Ask<'_>,
) -> IlnOutcome {
    let mut info = json!({
        "area_passage_graph": {"areas": g.areas.len(), "passages": g.passages.len()},
    });
    let done = |info: Value, trajectory: Vec<Cell>, status: &str| {
        let mut info = info;
        info["status"] = json!(status);
        IlnOutcome {
            trajectory,
            status: status.to_string(),
            info,
            pending: false,
        }
    };
    let Some(start_area) = g.start_area(map, start) else {
        info["failure_reason"] = json!("no area within reach of the start cell");
        return done(info, vec![start], "grounding_failed");
    };
    let current = g.areas[start_area].id.clone();
    info["start_area"] = json!(current);
    let failed = |info: Value, f: Failure| {
        let mut info = info;
        info["failure_reason"] = json!(f.message);
        info["status"] = json!(f.status);
        IlnOutcome {
            trajectory: vec![start],
            pending: f.status == PENDING,
            status: f.status,
            info,
        }
    };
    let no_gold = || "the annotations name no room for the final destination".to_string();
    let reply = match ask(
        "destination",
        prompts::destination_messages(g, instruction),
        &|| {
            gold_dest
                .map(prompts::gold_destination_reply)
                .ok_or_else(no_gold)
        },
    ) {
        Ok(r) => r,
        Err(e) => return failed(info, e),
    };
    info["grounding_adapter"] = json!({"reply": reply});
    let dest = match prompts::read_destination(g, &reply) {
        Ok(d) => d,
        Err(r) => {
            info["failure_reason"] = json!(r.reason);
            return done(info, vec![start], r.status);
        }
    };
    let dest_id = g.areas[dest].id.clone();
    info["grounding_adapter"]["destination_area"] = json!(dest_id);
    let reply = match ask(
        "passage_costs",
        prompts::cost_messages(g, instruction, &current, &dest_id),
        &|| Ok(prompts::gold_cost_reply(&current, &dest_id)),
    ) {
        Ok(r) => r,
        Err(e) => return failed(info, e),
    };
    info["passage_cost_evaluator"] = json!({"reply": reply});
    let (costs, notes) = match prompts::read_costs(g, &reply) {
        Ok(c) => c,
        Err(r) => {
            info["failure_reason"] = json!(r.reason);
            return done(info, vec![start], r.status);
        }
    };
    info["passage_cost_evaluator"]["costs"] = json!(
        costs
            .iter()
            .map(|(&k, &c)| (g.passages[k].id.clone(), json!(c)))
            .collect::<serde_json::Map<String, Value>>()
    );
    if !notes.is_empty() {
        info["passage_cost_evaluator"]["notes"] = json!(notes);
    }
    let ids =
        |ps: &[usize]| -> Vec<String> { ps.iter().map(|&k| g.passages[k].id.clone()).collect() };
    match route::plan_and_realise(g, grid, &costs, start, start_area, dest) {
        Realised::Complete {
            route,
            passages,
            replanned,
        } => {
            info["graph_planner"] = json!({"passages": ids(&passages)});
            info["grid_realizer"] = json!({"replanned": replanned});
            done(info, route, "ok")
        }
        Realised::NoGraphPath { route } => {
            info["failure_reason"] = json!(format!("no passage route from {current} to {dest_id}"));
            done(info, route, "no_graph_path")
        }
        Realised::GridFailed {
            route,
            passages,
            unreachable,
        } => {
            info["graph_planner"] = json!({"passages": ids(&passages)});
            info["failure_reason"] = json!(format!("{unreachable} is unreachable on the grid"));
            done(info, route, "grid_realization_failed")
        }
    }
}
