//! SayPlan (CoRL'23), adapted to Map2Route as the paper did: the model explores a collapsed 2D
//! scene graph with `expand_node` / `contract_node` (semantic search, up to 20 steps), then writes
//! a `goto(node)` plan that grid A* realises and a verifier checks; a rejected plan's feedback
//! drives the next planning round (up to 5). Each call may be re-asked twice when its reply is not
//! the asked JSON. Preferences and avoids are not represented (ignored).
//!
//! Statuses: `ok`; `planning_failed` (every plan rejected: the longest attempted route is kept);
//! `llm_output_invalid` (the re-asks ran out); `model_failed` (a request failed).

pub mod graph;
pub mod method;
pub mod prompts;
pub mod verify;

use crate::common::failure::{Failure, PENDING};
use crate::common::grid::GridSearch;
use crate::iln::Ask;
use graph::{NodeKind, SceneGraph};
use m2rc_compiler::lower::{Message, Role};
use m2rc_stdlib::grid::Cell;
use prompts::{Memory, SearchCommand};
use serde_json::{Value, json};
use std::collections::BTreeSet;

pub const MAX_SEARCH_STEPS: usize = 20;
pub const MAX_PLANS: usize = 5;
pub const MAX_JSON_REASKS: usize = 2;

/// What the gold oracle answers: the rooms to expand, in order, then the plan's target nodes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GoldScript {
    pub expand: Vec<String>,
    pub targets: Vec<String>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct SayPlanOutcome {
    pub trajectory: Vec<Cell>,
    pub status: String,
    /// The record's `sayplan` block.
    pub info: Value,
    pub pending: bool,
}

enum Stop {
    Chat(Failure),
    /// The reply stayed unusable after the re-asks; the last reason.
    Invalid(String),
}

/// One call with its JSON re-asks: the typed answer, or why there is none.
fn ask_json<T>(
    ask: &mut Ask<'_>,
    calls: &mut usize,
    step: &str,
    messages: Vec<Message>,
    gold: &dyn Fn() -> Result<String, String>,
    read: impl Fn(&str) -> Result<T, String>,
) -> Result<T, Stop> {
    let mut messages = messages;
    let mut last = String::new();
    for attempt in 0..=MAX_JSON_REASKS {
        let id = match attempt {
            0 => step.to_string(),
            k => format!("{step}-reask{k}"),
        };
        let reply = ask(&id, messages.clone(), gold).map_err(Stop::Chat)?;
        *calls += 1;
        match read(&reply) {
            Ok(t) => return Ok(t),
            Err(e) => {
                messages.push(Message {
                    role: Role::Assistant,
                    content: reply,
                });
                messages.push(Message::user(prompts::reask(&e)));
                last = e;
            }
        }
    }
    Err(Stop::Invalid(last))
}

/// Applies a search command to the visible set; the feedback for the next step.
fn apply(
    g: &SceneGraph,
    visible: &mut BTreeSet<usize>,
    memory: &mut Memory,
    cmd: &SearchCommand,
) -> String {
    let (expand, id) = match cmd {
        SearchCommand::Expand(id) => (true, id),
        SearchCommand::Contract(id) => (false, id),
        SearchCommand::Plan => return String::new(),
    };
    let verb = if expand {
        "expand_node"
    } else {
        "contract_node"
    };
    memory.history.push(format!("{verb}({id})"));
    let Some(i) = g.index(id) else {
        return format!("{verb}: `{id}` is not a node of the scene graph; use a visible node id");
    };
    if !visible.contains(&i) {
        return format!("{verb}: `{id}` is hidden; only visible nodes can be used");
    }
    if !matches!(g.nodes[i].kind, NodeKind::Room { .. }) {
        return format!("{verb}: `{id}` is not a room; only rooms can be expanded or contracted");
    }
    if expand {
        visible.extend(g.nodes[i].children.iter().copied());
        memory.contracted.retain(|x| x != id);
        if !memory.expanded.contains(id) {
            memory.expanded.push(id.clone());
        }
        format!(
            "expanded `{id}`: {} object(s) now visible",
            g.nodes[i].children.len()
        )
    } else {
        for c in &g.nodes[i].children {
            visible.remove(c);
        }
        memory.expanded.retain(|x| x != id);
        if !memory.contracted.contains(id) {
            memory.contracted.push(id.clone());
        }
        format!("contracted `{id}`")
    }
}

/// Runs SayPlan on one episode.
pub fn run(
    g: &SceneGraph,
    grid: &mut GridSearch<'_>,
    instruction: &str,
    gold: Result<&GoldScript, &str>,
    ask: &mut Ask<'_>,
) -> SayPlanOutcome {
    let start = g.start;
    let mut visible = g.collapsed();
    let mut memory = Memory::default();
    let mut feedback = String::new();
    let mut search_trace = Vec::new();
    let mut attempts = Vec::new();
    let mut calls = 0usize;
    let finish = |status: &str,
                  trajectory: Vec<Cell>,
                  extra: Value,
                  visible: &BTreeSet<usize>,
                  search_trace: Vec<Value>,
                  attempts: Vec<Value>,
                  calls: usize| {
        let mut info = json!({
            "planning_failed": status != "ok",
            "semantic_search_trace": search_trace,
            "planning_attempts": attempts,
            "task_subgraph": visible.iter().map(|&i| g.nodes[i].id.clone()).collect::<Vec<_>>(),
            "call_count": calls,
            "status": status,
        });
        if let (Value::Object(m), Value::Object(e)) = (&mut info, extra) {
            m.extend(e);
        }
        SayPlanOutcome {
            pending: status == PENDING,
            trajectory,
            status: status.to_string(),
            info,
        }
    };
    let stopped = |s: Stop| -> (String, Value) {
        match s {
            Stop::Chat(f) => (f.status, json!({"failure_reason": f.message})),
            Stop::Invalid(m) => (
                "llm_output_invalid".to_string(),
                json!({"failure_reason": format!("no usable JSON after {MAX_JSON_REASKS} re-asks: {m}")}),
            ),
        }
    };
    for step in 0..MAX_SEARCH_STEPS {
        let gold_reply = || match gold {
            Ok(g) => Ok(prompts::gold_search_reply(
                g.expand.get(step).map(String::as_str),
            )),
            Err(e) => Err(e.to_string()),
        };
        let messages =
            prompts::search_messages(instruction, &g.view_json(&visible), &memory, &feedback);
        let cmd = match ask_json(
            ask,
            &mut calls,
            &format!("search{}", step + 1),
            messages,
            &gold_reply,
            prompts::read_search,
        ) {
            Ok(c) => c,
            Err(s) => {
                let (status, extra) = stopped(s);
                return finish(
                    &status,
                    vec![start],
                    extra,
                    &visible,
                    search_trace,
                    attempts,
                    calls,
                );
            }
        };
        feedback = apply(g, &mut visible, &mut memory, &cmd);
        search_trace.push(json!({
            "step": step + 1,
            "command": match &cmd {
                SearchCommand::Expand(id) => format!("expand_node({id})"),
                SearchCommand::Contract(id) => format!("contract_node({id})"),
                SearchCommand::Plan => "planning".to_string(),
            },
            "feedback": feedback,
        }));
        if cmd == SearchCommand::Plan {
            break;
        }
    }
    let gold_plan = || match gold {
        Ok(g) => Ok(prompts::gold_plan_reply(&g.targets)),
        Err(e) => Err(e.to_string()),
    };
    let mut previous: Option<Vec<String>> = None;
    let mut feedback = String::new();
    let mut best: Vec<Cell> = vec![start];
    for round in 1..=MAX_PLANS {
        let messages = prompts::plan_messages(
            instruction,
            &g.view_json(&visible),
            &memory,
            previous.as_deref(),
            &feedback,
        );
        let plan = match ask_json(
            ask,
            &mut calls,
            &format!("plan{round}"),
            messages,
            &gold_plan,
            prompts::read_plan,
        ) {
            Ok(p) => p,
            Err(s) => {
                let (status, extra) = stopped(s);
                return finish(
                    &status,
                    best,
                    extra,
                    &visible,
                    search_trace,
                    attempts,
                    calls,
                );
            }
        };
        let verdict = verify::verify(g, &visible, grid, &plan);
        attempts.push(json!({
            "round": round,
            "plan": plan,
            "accepted": verdict.rejection.is_none(),
            "feedback": verdict.rejection,
        }));
        match verdict.rejection {
            None => {
                let extra = json!({"final_high_level_plan": plan});
                return finish(
                    "ok",
                    verdict.route,
                    extra,
                    &visible,
                    search_trace,
                    attempts,
                    calls,
                );
            }
            Some(why) => {
                if verdict.route.len() > best.len() {
                    best = verdict.route;
                }
                feedback = why;
                previous = Some(plan);
            }
        }
    }
    let extra = json!({
        "failure_reason": format!("every one of {MAX_PLANS} plans was rejected; last: {feedback}"),
        "final_high_level_plan": previous,
    });
    finish(
        "planning_failed",
        best,
        extra,
        &visible,
        search_trace,
        attempts,
        calls,
    )
}

/// The gold oracle's script: expand each room holding a target object (in target order), then
/// plan `goto` each target (the object when it can be approached, else its room).
pub fn gold_script(g: &SceneGraph, targets: &[crate::common::gold::GoldPlace]) -> GoldScript {
    let mut script = GoldScript::default();
    for t in targets {
        let object = t.object_id.map(|o| format!("object_{o}")).and_then(|id| {
            let i = g.index(&id)?;
            match &g.nodes[i].kind {
                NodeKind::Object {
                    room: Some(r),
                    approach_cells,
                } if !approach_cells.is_empty() => Some((id, format!("room_{r}"))),
                _ => None,
            }
        });
        match object {
            Some((id, room)) => {
                if !script.expand.contains(&room) {
                    script.expand.push(room);
                }
                script.targets.push(id);
            }
            None => {
                if let Some(r) = t.room_id {
                    script.targets.push(format!("room_{r}"));
                }
            }
        }
    }
    script
}
