//! The ablation table's grounding variants (issue 31): the same compiler, RouteIR and planner as
//! `grounding2route` (CaG), only the representation the model writes differs.
//!
//! * [`toolcall`]: the built-in queries as function-calling tools with opaque handles and the
//!   RouteIR builders (`m2rc_compiler::tools`), in a conversation with the reference's budgets.
//! * [`schema`]: a JSON intent graph over operators generated from the built-in table
//!   (`m2rc_compiler::intent`), compiled deterministically to `.m2r`; its diagnostics point into
//!   the graph, so the same repair loop runs on it.
//! * [`directid`]: the model picks ids from a compact catalog of the map; m2rc checks them and
//!   builds the RouteIR directly. Its catalog-LTL form (`directid::ltl`) writes the same ids under
//!   a restricted LTL skeleton.
//!
//! Each variant's model is one of: a server through the cache and batch exchange, the labelled
//! simulated model ([`simulated`]: the `.m2r` fault classes, injected into the gold program before
//! it is written as the variant's JSON), or `--llm gold` (the gold program in the variant's own
//! form: the representation's ceiling, labelled `[GOLD replies]`).

pub mod directid;
pub mod schema;
pub mod simulated;
pub mod toolcall;

use crate::calls::{GOLD_LABEL, ModelSetup};
use m2rc_compiler::lower::{ChatError, ChatModel, ChatReply, ChatRequest, Usage, estimate_tokens};
use m2rc_llm::{Backend, Exchange, Fetch};

/// A model that answers every request with one fixed reply: a variant's gold oracle.
pub struct GoldModel {
    pub reply: Result<String, String>,
}

impl ChatModel for GoldModel {
    fn complete(&self, request: &ChatRequest) -> Result<ChatReply, ChatError> {
        let text = self
            .reply
            .clone()
            .map_err(|e| ChatError::Failed(format!("gold reply unavailable: {e}")))?;
        Ok(ChatReply {
            choices: 1,
            usage: Usage {
                prompt_tokens: Some(
                    request
                        .messages
                        .iter()
                        .map(|m| estimate_tokens(&m.content) as u64)
                        .sum(),
                ),
                completion_tokens: Some(estimate_tokens(&text) as u64),
            },
            content: Some(text),
            finish_reason: Some("stop".into()),
            refusal: None,
            latency_ms: 0.0,
        })
    }
}

/// Runs `f` with the episode's model: the gold oracle, the simulated model, or the server, the
/// last two through the run's cache and batch exchange.
pub fn with_model<T>(
    setup: &ModelSetup,
    gold: impl FnOnce() -> Result<String, String>,
    simulated: impl FnOnce(m2rc_llm::SimulatedSpec) -> Box<dyn Fetch>,
    f: impl FnOnce(&dyn ChatModel) -> T,
) -> Result<T, String> {
    match &setup.backend {
        Backend::Gold => Ok(f(&GoldModel { reply: gold() })),
        Backend::Simulated(spec) => {
            let fetch = simulated(*spec);
            Ok(f(&Exchange {
                store: &setup.store,
                fetch: fetch.as_ref(),
            }))
        }
        Backend::Http => match &setup.http {
            Some(h) => Ok(f(&Exchange {
                store: &setup.store,
                fetch: h,
            })),
            None => Err("no LLM client configured".into()),
        },
    }
}

/// The label of what answered (gold, simulated or the server).
pub fn model_label(setup: &ModelSetup) -> String {
    match &setup.backend {
        Backend::Gold => GOLD_LABEL.to_string(),
        Backend::Simulated(s) => s.label(),
        Backend::Http => format!(
            "{} at {}",
            setup.model,
            setup.base_url.as_deref().unwrap_or("?")
        ),
    }
}

/// The model setup of a grounding variant: the baselines' setup, except that the simulated model
/// is accepted (its faults are the `.m2r` model's, written in the variant's form).
pub fn variant_setup(
    llm: &m2rc_llm::LlmArgs,
    args: &crate::registry::BaselineArgs,
    default_cache: &std::path::Path,
) -> Result<(ModelSetup, Option<String>), String> {
    if let Backend::Simulated(spec) = llm.backend {
        let (store, note) = llm.store(default_cache)?;
        return Ok((
            ModelSetup {
                backend: Backend::Simulated(spec),
                store,
                http: None,
                embed_http: None,
                model: spec.model_name(),
                base_url: None,
                temperature: 0.0,
                max_tokens: None,
                embeddings: crate::calls::embed::EmbedMode::Lexical,
            },
            note,
        ));
    }
    crate::registry::model_setup(llm, args, default_cache)
}

/// Whether `name` is a grounding variant (which takes the simulated model too).
pub fn is_variant(name: &str) -> bool {
    [schema::NAME, directid::NAME, directid::ltl::NAME].contains(&name)
}

/// An episode's pipeline options, planned from `start` under the default episode budget, with
/// the meter to read afterwards (whether the budget ran out).
pub fn metered(
    start: m2rc_stdlib::grid::Cell,
) -> (
    std::sync::Arc<m2rc_benchmark::budget::Meter>,
    m2rc_benchmark::pipeline::PipelineOptions,
) {
    use m2rc_benchmark::budget::{EpisodeBudget, Meter};
    let meter = std::sync::Arc::new(Meter::new(EpisodeBudget::default()));
    let pipeline = m2rc_benchmark::pipeline::PipelineOptions {
        start: Some(start),
        meter: Some(meter.clone()),
        ..Default::default()
    };
    (meter, pipeline)
}

/// What a JSON grounding variant (Schema, Direct ID, catalog-LTL) records of one episode, from
/// its repair trace: the outcome, tokens and calls under the variant's key, with `details` (its
/// own fields) after the prompt's size and `after` at the end; the simulated faults and the budget
/// when they apply; and, for gold replies, the note that the row is the representation's ceiling
/// (`ceiling` says in which form).
pub struct JsonRecord<'a> {
    pub key: &'a str,
    pub setup: &'a ModelSetup,
    pub repair: &'a m2rc_compiler::lower::RepairOptions,
    pub prompt: &'a m2rc_compiler::lower::Prompt,
    pub meter: &'a m2rc_benchmark::budget::Meter,
    pub faults: &'a [&'static str],
    pub ceiling: &'a str,
}

impl JsonRecord<'_> {
    pub fn prediction(
        self,
        trace: m2rc_compiler::lower::Trace<m2rc_benchmark::pipeline::CompiledRoute>,
        details: serde_json::Map<String, serde_json::Value>,
        after: serde_json::Map<String, serde_json::Value>,
    ) -> m2rc_benchmark::methods::Prediction {
        use serde_json::json;
        let success_round = match trace.outcome {
            m2rc_compiler::lower::EpisodeOutcome::Success { round } => Some(round),
            _ => None,
        };
        let (prompt_tokens, completion_tokens) = trace.tokens();
        let mut info = json!({
            "model": model_label(self.setup),
            "repair_rounds": self.repair.rounds,
            "outcome": trace.outcome,
            "success_round": success_round,
            "local_fixes": trace.local_fix_count(),
            "prompt_tokens": prompt_tokens,
            "completion_tokens": completion_tokens,
            "prompt_estimated_tokens": self.prompt.estimated_tokens(),
        });
        if let Some(obj) = info.as_object_mut() {
            obj.extend(details);
            obj.insert("gold_replies".into(), json!(self.setup.is_gold()));
            obj.insert("calls".into(), json!(trace.attempts));
            obj.extend(after);
        }
        if matches!(self.setup.backend, Backend::Simulated(_)) {
            info["simulated_faults"] = json!(self.faults);
        }
        let over = self.meter.exceeded().filter(|_| success_round.is_none());
        if let Some(reason) = &over {
            info["budget_exceeded"] = json!(reason);
        }
        let status = match &over {
            Some(_) => "budget_exceeded",
            None => trace.outcome.status(),
        };
        let mut extra = serde_json::Map::new();
        extra.insert(self.key.into(), info);
        m2rc_benchmark::methods::Prediction {
            trajectory: trace.output.map(|c| c.route.trajectory).unwrap_or_default(),
            program: trace.final_program,
            notes: over
                .into_iter()
                .chain(self.setup.is_gold().then(|| {
                    format!(
                        "{GOLD_LABEL}: {} (the representation's ceiling)",
                        self.ceiling
                    )
                }))
                .collect(),
            status: (status != "ok").then(|| status.to_string()),
            extra,
        }
    }
}
