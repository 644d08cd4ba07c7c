//! ToolCall: the model grounds the instruction by calling m2rc's read-only queries one at a time
//! as function calls (the tools are generated from the built-in table, `m2rc_compiler::tools`),
//! composing earlier results through opaque handles, and submits the route with the RouteIR
//! builders; the route then goes through the same compiler and planner as CaG. Budgets and
//! termination rules are the reference's (32 tool calls, 40 turns, 3 tries per identical failing
//! query; a text reply without `task` fails), and, as its code runs it, there is no repair: a
//! submitted route that does not compile ends the episode.

pub mod conversation;

use super::model_label;
use crate::calls::{GOLD_LABEL, ModelSetup};
use conversation::{Budgets, GoldTurns, ModelTurns, Trace, Turns, converse};
use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::methods::{
    Method, MethodError, Prediction, PreparedMap, instruction_of, start_cell,
};
use m2rc_benchmark::pipeline::compile_and_plan_with;
use m2rc_compiler::lower::{CatalogMode, Phase, SceneCatalog, estimate_tokens};
use m2rc_compiler::tools::{Limits, ToolSession, gold_calls, openai_tools};
use m2rc_llm::{Backend, Exchange};
use serde_json::{Value, json};
use std::sync::{Arc, OnceLock};

pub const NAME: &str = "toolcall";

/// The system prompt, in our words after the reference's rules.
pub const SYSTEM_PROMPT: &str = "You are a route-grounding agent for a robot. Turn the user's \
instruction into a route by calling the read-only map tools over several turns; each result is \
an opaque handle (e.g. `set#3`) with a short preview, and later calls take handles as arguments.
Rules:
1. Resolve every room, object, relation, destination, constraint and scope through the tools.
2. Invent nothing: use only the listed categories and the handles you were given.
3. Write no code; never ask for grids, planner internals or trajectories.
4. The route starts at `start`; each segment starts where the previous one ended. Call \
`set_segment_context` before making a segment's constraints (or list them in `segment`).
5. Build the constraints, then the segments, then call `task` exactly once with the segments in \
order.
6. A singular phrase does not prove there is only one: check with `count` or `only`.
7. A query that failed or came back empty may be tried at most three times; then change it or \
stop.
`task` is the only valid answer; a reply without a tool call ends the conversation.";

/// The tools every request carries (generated once).
pub fn tools() -> &'static [Value] {
    static TOOLS: OnceLock<Vec<Value>> = OnceLock::new();
    TOOLS.get_or_init(openai_tools)
}

/// The estimated prompt tokens of the tool list alone (sent with every turn).
pub fn tools_estimated_tokens() -> usize {
    estimate_tokens(&serde_json::to_string(tools()).unwrap_or_default())
}

/// The user message: instruction, categories, category counts, the initial handle.
pub fn user_message(map: &m2rc_stdlib::map::SemanticMap, instruction: &str) -> String {
    let catalog = SceneCatalog::from_map(map, CatalogMode::Counts);
    format!(
        "Instruction: {instruction}\n\n{}\nInitial handles: `start` (where the robot starts; \
         also the start of the first segment).",
        catalog.render()
    )
}

pub struct ToolCallMethod {
    pub setup: Arc<ModelSetup>,
    pub budgets: Budgets,
    pub name: String,
}

pub fn make(setup: Arc<ModelSetup>) -> Box<dyn Method> {
    Box::new(ToolCallMethod::new(setup))
}

impl ToolCallMethod {
    pub fn new(setup: Arc<ModelSetup>) -> Self {
        ToolCallMethod {
            setup,
            budgets: Budgets::default(),
            name: NAME.into(),
        }
    }
}

impl Method for ToolCallMethod {
    fn name(&self) -> &str {
        &self.name
    }

    fn config(&self) -> Value {
        json!({
            "method": NAME,
            "m2rc": env!("CARGO_PKG_VERSION"),
            "model": self.setup.config(),
            "backend": self.setup.backend,
            "budgets": self.budgets,
            "repair_rounds": 0,
        })
    }

    fn predict(&self, map: &PreparedMap, episode: &Episode) -> Result<Prediction, MethodError> {
        let instruction = instruction_of(episode)?;
        let start = start_cell(&map.map, episode)?;
        let key = format!(
            "{}/{}/{NAME}",
            episode.map_id.as_deref().unwrap_or(&map.map.map_id),
            episode
                .instruction_id()
                .unwrap_or_else(|| "instruction".into())
        );
        let limits = Limits {
            retry_limit: self.budgets.retries,
            ..Limits::default()
        };
        let mut session = ToolSession::new(&map.map, Some(start), limits);
        let messages = vec![
            json!({"role": "system", "content": SYSTEM_PROMPT}),
            json!({"role": "user", "content": user_message(&map.map, instruction)}),
        ];
        let mut gold_len = None;
        let trace: Trace = match &self.setup.backend {
            Backend::Gold => {
                let program = episode.m2rc_gold_program.as_deref().ok_or_else(|| {
                    MethodError("gold replies need the episode's gold program".into())
                })?;
                match gold_calls(program) {
                    Ok(calls) => {
                        gold_len = Some(calls.len());
                        let mut turns = GoldTurns::new(calls);
                        converse(&mut session, &mut turns, messages, self.budgets)
                    }
                    Err(e) => Trace {
                        status: "gold_unavailable",
                        message: Some(format!("the gold program has no tool-call form: {e}")),
                        ..Trace::default()
                    },
                }
            }
            Backend::Http => {
                let http = self
                    .setup
                    .http
                    .as_ref()
                    .ok_or_else(|| MethodError("no LLM client configured".into()))?;
                let mut turns = ModelTurns {
                    exchange: Exchange {
                        store: &self.setup.store,
                        fetch: http,
                    },
                    key: key.clone(),
                    tools: tools(),
                };
                let t: &mut dyn Turns = &mut turns;
                converse(&mut session, t, messages, self.budgets)
            }
            Backend::Simulated(_) => {
                return Err(MethodError(
                    "--llm simulated injects faults into a program and has no tool-call form; \
                     use --llm gold or a server"
                        .into(),
                ));
            }
        };
        let mut info = json!({
            "model": model_label(&self.setup),
            "repair_rounds": 0,
            "outcome": trace.status,
            "reference_status": trace.reference_status,
            "message": trace.message,
            "turns": trace.turns,
            "tool_calls": trace.tool_calls,
            "failed_calls": session.failed,
            "blocked_calls": session.blocked,
            "handles": session.handle_count(),
            "prompt_tokens": (!trace.tokens_unknown).then_some(trace.prompt_tokens),
            "completion_tokens": (!trace.tokens_unknown).then_some(trace.completion_tokens),
            "tools_estimated_tokens": tools_estimated_tokens(),
            "gold_replies": self.setup.is_gold(),
            "calls": trace.calls,
        });
        if let Some(n) = gold_len {
            info["gold_sequence_calls"] = json!(n);
        }
        let mut status = trace.status.to_string();
        let mut trajectory = Vec::new();
        let mut program = None;
        let (meter, pipeline) = super::metered(start);
        if let Some(done) = &session.finished {
            program = Some(done.program.clone());
            info["route_graph"] = done.graph.clone();
            let ctx = map.planning()?;
            match compile_and_plan_with(&done.program, &map.map, ctx, &pipeline) {
                Ok(c) => trajectory = c.route.trajectory,
                Err(diags) => {
                    status = match Phase::of_errors(&diags) {
                        Phase::Plan => "plan_failed",
                        _ => "grounding_failed",
                    }
                    .into();
                    info["diagnostics"] = json!(
                        diags
                            .iter()
                            .filter(|d| d.is_error())
                            .map(|d| format!("{}: {}", d.code.id(), d.message))
                            .collect::<Vec<_>>()
                    );
                }
            }
        }
        if let Some(reason) = meter.exceeded().filter(|_| trajectory.is_empty()) {
            info["budget_exceeded"] = json!(reason);
            status = "budget_exceeded".into();
        }
        let mut extra = serde_json::Map::new();
        extra.insert(NAME.into(), info);
        Ok(Prediction {
            trajectory,
            program,
            notes: self
                .setup
                .is_gold()
                .then(|| {
                    format!(
                        "{GOLD_LABEL}: the gold program as a tool-call sequence (the \
                         representation's ceiling)"
                    )
                })
                .into_iter()
                .collect(),
            status: (status != "ok").then_some(status),
            extra,
        })
    }
}
