//! The ToolCall conversation: turns of tool calls answered by the session until `task`, with
//! the reference's budgets and termination rules. The model side is a [`Turns`] source: the
//! server (every turn through the cache and the batch exchange: a turn is a batch round, and a
//! re-run conversation is answered from the cache up to its first new turn) or the gold sequence.

use m2rc_compiler::tools::{GoldCall, TASK_TOOL, ToolSession};
use m2rc_llm::{Exchange, ToolCall};
use serde_json::{Value, json};

/// The reference's budgets (`MAX_TOOL_CALLS`, `MAX_TOOL_LLM_TURNS`, `MAX_TOOL_QUERY_RETRIES`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Budgets {
    pub tool_calls: usize,
    pub turns: usize,
    pub retries: usize,
}

impl Default for Budgets {
    fn default() -> Self {
        Budgets {
            tool_calls: 32,
            turns: 40,
            retries: 3,
        }
    }
}

/// One turn of the model: its calls (and the text it wrote beside them).
pub struct Turn {
    pub calls: Vec<ToolCall>,
    pub assistant: Value,
    pub text: Option<String>,
    pub prompt_tokens: Option<u64>,
    pub completion_tokens: Option<u64>,
}

/// Why a turn could not be had.
pub struct TurnError {
    pub status: &'static str,
    pub message: String,
}

/// Where turns come from.
pub trait Turns {
    fn next(&mut self, turn: usize, messages: &[Value]) -> Result<Turn, TurnError>;
    /// What the call `id` produced (a handle, or none when it failed).
    fn observe(&mut self, _id: &str, _handle: Option<&str>) {}
}

/// The server, through the run's cache and batch exchange.
pub struct ModelTurns<'a> {
    pub exchange: Exchange<'a>,
    pub key: String,
    pub tools: &'a [Value],
}

impl Turns for ModelTurns<'_> {
    fn next(&mut self, turn: usize, messages: &[Value]) -> Result<Turn, TurnError> {
        let id = format!("{}/turn{turn}", self.key);
        match self.exchange.complete_tools(&id, messages, self.tools) {
            Ok(r) => {
                if let Some(refusal) = r.reply.refusal.as_deref().filter(|s| !s.trim().is_empty()) {
                    return Err(TurnError {
                        status: "llm_refused",
                        message: format!("turn {turn}: the model refused: {refusal}"),
                    });
                }
                Ok(Turn {
                    assistant: r.assistant_message(),
                    text: r.reply.content.clone(),
                    prompt_tokens: r.reply.usage.prompt_tokens,
                    completion_tokens: r.reply.usage.completion_tokens,
                    calls: r.tool_calls,
                })
            }
            Err(m2rc_compiler::lower::ChatError::Pending(_)) => Err(TurnError {
                status: crate::common::failure::PENDING,
                message: format!("turn {turn}: waiting for the batch reply"),
            }),
            Err(m2rc_compiler::lower::ChatError::Failed(e)) => Err(TurnError {
                status: "llm_failed",
                message: e,
            }),
        }
    }
}

/// The gold sequence: each turn sends every call whose earlier results are all known.
pub struct GoldTurns {
    pub calls: Vec<GoldCall>,
    pub handles: Vec<Option<String>>,
    pub sent: usize,
}

impl GoldTurns {
    pub fn new(calls: Vec<GoldCall>) -> Self {
        let n = calls.len();
        GoldTurns {
            calls,
            handles: vec![None; n],
            sent: 0,
        }
    }
}

impl Turns for GoldTurns {
    fn next(&mut self, turn: usize, _messages: &[Value]) -> Result<Turn, TurnError> {
        let first = self.sent;
        let mut calls = Vec::new();
        while let Some(c) = self.calls.get(self.sent) {
            // The calls are in dependency order; a turn holds those whose inputs are all known.
            if c.deps.iter().any(|&d| d >= first) {
                break;
            }
            let Some(args) = c.bind(&self.handles) else {
                return Err(TurnError {
                    status: "gold_unavailable",
                    message: format!(
                        "turn {turn}: the gold call `{}` needs a result that failed",
                        c.name
                    ),
                });
            };
            calls.push(ToolCall {
                id: format!("gold_{}", self.sent),
                name: c.name.clone(),
                raw_arguments: args.to_string(),
                arguments: Ok(args),
            });
            self.sent += 1;
        }
        let assistant = json!({"role": "assistant", "content": null, "tool_calls": calls.iter().map(|c| json!({
            "id": c.id, "type": "function", "function": {"name": c.name, "arguments": c.raw_arguments}
        })).collect::<Vec<_>>()});
        Ok(Turn {
            calls,
            assistant,
            text: None,
            prompt_tokens: Some(0),
            completion_tokens: Some(0),
        })
    }

    fn observe(&mut self, id: &str, handle: Option<&str>) {
        if let Some(k) = id
            .strip_prefix("gold_")
            .and_then(|n| n.parse::<usize>().ok())
            && k < self.handles.len()
        {
            self.handles[k] = handle.map(str::to_string);
        }
    }
}

/// How a conversation ended, and everything it did.
#[derive(Debug, Default)]
pub struct Trace {
    /// `ok` when `task` submitted a route, else the failure (the reference's name beside it).
    pub status: &'static str,
    pub reference_status: Option<&'static str>,
    pub message: Option<String>,
    pub turns: usize,
    pub tool_calls: usize,
    pub calls: Vec<Value>,
    pub prompt_tokens: u64,
    pub completion_tokens: u64,
    /// Some token count was unknown.
    pub tokens_unknown: bool,
}

impl Trace {
    fn end(
        mut self,
        status: &'static str,
        reference: Option<&'static str>,
        message: String,
    ) -> Trace {
        self.status = status;
        self.reference_status = reference;
        self.message = Some(message);
        self
    }
}

/// Runs the conversation from its start (`messages` = system and user messages).
pub fn converse(
    session: &mut ToolSession,
    turns: &mut dyn Turns,
    mut messages: Vec<Value>,
    budgets: Budgets,
) -> Trace {
    let mut t = Trace::default();
    for turn in 0..budgets.turns {
        let reply = match turns.next(turn, &messages) {
            Ok(r) => r,
            Err(e) => return t.end(e.status, None, e.message),
        };
        t.turns += 1;
        match reply.prompt_tokens {
            Some(n) => t.prompt_tokens += n,
            None => t.tokens_unknown = true,
        }
        match reply.completion_tokens {
            Some(n) => t.completion_tokens += n,
            None => t.tokens_unknown = true,
        }
        if reply.calls.is_empty() {
            let text: String = reply.text.unwrap_or_default().chars().take(300).collect();
            return t.end(
                "text_without_task",
                Some("MODEL_RETURNED_TEXT_WITHOUT_TASK"),
                format!("turn {turn}: the model answered with text and no tool call: {text}"),
            );
        }
        messages.push(reply.assistant);
        for call in &reply.calls {
            if t.tool_calls >= budgets.tool_calls {
                let message = format!("{} tool calls made without a task", t.tool_calls);
                return t.end(
                    "tool_budget_exhausted",
                    Some("TOOL_BUDGET_EXHAUSTED"),
                    message,
                );
            }
            t.tool_calls += 1;
            let outcome = match &call.arguments {
                Ok(args) => session.call(&call.name, args),
                Err(e) => m2rc_compiler::tools::ToolOutcome {
                    ok: false,
                    content: json!({"error": e}),
                    blocked: false,
                },
            };
            let handle = outcome.content["handle"].as_str();
            turns.observe(&call.id, handle);
            t.calls.push(json!({
                "turn": turn,
                "name": call.name,
                "arguments": call.raw_arguments.chars().take(2000).collect::<String>(),
                "ok": outcome.ok,
                "blocked": outcome.blocked,
                "result": outcome.content,
            }));
            messages.push(m2rc_llm::tools::tool_message(&call.id, &outcome.content));
            if call.name == TASK_TOOL {
                if session.finished.is_some() {
                    t.status = "ok";
                    return t;
                }
                // The reference runs ToolCall with repair off: a route that does not verify ends it.
                return t.end(
                    "route_ir_verification_failed",
                    Some("ROUTE_IR_VERIFICATION_FAILED"),
                    outcome.content["error"].as_str().unwrap_or("").to_string(),
                );
            }
        }
    }
    t.end(
        "turn_budget_exhausted",
        Some("LLM_TURN_BUDGET_EXHAUSTED"),
        format!("{} turns without a task", budgets.turns),
    )
}
