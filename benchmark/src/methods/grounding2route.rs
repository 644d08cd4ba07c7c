//! `grounding2route`: the paper's method on m2rc. A language model lowers the instruction into
//! `.m2r` from a prompt generated from the built-in table, the scene catalog and worked examples;
//! the compiler checks, grounds and verifies it and the planner plans it; diagnostics drive up to
//! R repair rounds (unambiguous machine-applicable fixes are applied locally first). A planning
//! failure ends the episode, as in the paper, unless `repair_on_plan_failure` is set.
//!
//! The record gains a `grounding2route` object: the configuration's model label, the outcome,
//! the round that succeeded, every attempt (program, diagnostics, local fixes, tokens, latency,
//! outcome), and, for an episode that needed repairs, the metrics of the start-only route, so that
//! `bench report` can give the results for every smaller R from the same run (the reference's
//! truncation of the attempt history). An episode that never produces a plannable program is
//! scored on the start cell alone (the reference's `GROUNDING_FAILED` record).

use super::{Method, MethodError, Prediction, PreparedMap, start_cell};
use crate::budget::{EpisodeBudget, Meter};
use crate::episode::Episode;
use crate::pipeline::{CompiledRoute, PipelineOptions, compile_and_plan_with};
use m2rc_compiler::lower::{
    CatalogMode, ChatModel, Phase, Prompt, PromptOptions, RepairOptions, SceneCatalog, Trace,
    Verdict, run_episode,
};
use m2rc_llm::{Backend, Exchange, Fetch, HttpClient, SimulatedModel, Store};
use m2rc_planner::PlannerKind;
use m2rc_planner::context::MapContext;
use m2rc_stdlib::map::SemanticMap;
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};

/// Everything that changes this method's results (and nothing that does not: caches, batch
/// files, timeouts and concurrency are left out), for the run manifest and its fingerprint.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Grounding2RouteConfig {
    pub backend: Backend,
    /// The model name sent to the server, or the simulated model's name.
    pub model: String,
    /// The server, for `http` (shown in labels; not part of the configuration's identity, since
    /// replies are cached by model and request, so a run may resume against another mirror or
    /// offline from the cache).
    #[serde(skip)]
    pub base_url: Option<String>,
    pub temperature: f64,
    pub max_tokens: Option<u32>,
    pub repair: RepairOptions,
    pub prompt: PromptOptions,
    /// The planner of accepted programs: the paper's sequential planner, or the LTL backend for
    /// the CaG + LTL comparison (`ablate ltl-vs-routeir`). Left out of the configuration when
    /// sequential, so earlier runs keep their fingerprint.
    #[serde(default = "sequential", skip_serializing_if = "is_sequential")]
    pub planner: PlannerKind,
    /// Each episode's budget of compiling and planning (`crate::budget`); left out of the
    /// configuration at its defaults, so earlier runs keep their fingerprint. Its wall-time part
    /// is never in it (not reproducible).
    #[serde(default, skip_serializing_if = "EpisodeBudget::is_default")]
    pub budget: EpisodeBudget,
}

/// Why `--llm gold` is refused here: this method's gold is the simulated model at fault rate 0.
const GOLD_REFUSED: &str = "--llm gold is for the baselines; grounding2route's gold replies are \
     `--llm simulated:0` (the gold program, no faults)";

fn sequential() -> PlannerKind {
    PlannerKind::Sequential
}

fn is_sequential(p: &PlannerKind) -> bool {
    *p == PlannerKind::Sequential
}

impl Grounding2RouteConfig {
    /// A label for outputs; the simulated model is always named as such.
    pub fn label(&self) -> String {
        match &self.backend {
            Backend::Simulated(s) => s.label(),
            Backend::Gold => "[GOLD replies]".into(),
            Backend::Http => format!(
                "{} at {}",
                self.model,
                self.base_url.as_deref().unwrap_or("?")
            ),
        }
    }

    pub fn is_simulated(&self) -> bool {
        matches!(self.backend, Backend::Simulated(_))
    }
}

impl Default for Grounding2RouteConfig {
    fn default() -> Self {
        Grounding2RouteConfig {
            backend: Backend::Http,
            model: "default".into(),
            base_url: None,
            temperature: 0.0,
            max_tokens: Some(2048),
            repair: RepairOptions::default(),
            prompt: PromptOptions {
                catalog: CatalogMode::Counts,
                examples: 5,
            },
            planner: PlannerKind::Sequential,
            budget: EpisodeBudget::default(),
        }
    }
}

pub struct Grounding2Route {
    pub config: Grounding2RouteConfig,
    pub store: Store,
    /// The client for `http` (none for the simulated model).
    pub http: Option<HttpClient>,
}

/// Lowers `instruction` on `map` through `model` and plans it: the prompt and the whole trace.
#[allow(clippy::too_many_arguments)]
pub fn lower_and_plan(
    model: &dyn ChatModel,
    map: &SemanticMap,
    ctx: &MapContext,
    instruction: &str,
    episode_key: &str,
    prompt_opts: &PromptOptions,
    repair: &RepairOptions,
    pipeline: &PipelineOptions,
) -> (Prompt, Trace<CompiledRoute>) {
    let catalog = SceneCatalog::from_map(map, prompt_opts.catalog);
    let prompt = Prompt::new(&map.map_id, &catalog, instruction, prompt_opts);
    let mut verifier = |src: &str| match compile_and_plan_with(src, map, ctx, pipeline) {
        Ok(c) => Verdict::Accepted(c),
        Err(diagnostics) => Verdict::Rejected {
            phase: Phase::of_errors(&diagnostics),
            diagnostics,
        },
    };
    let trace = run_episode(model, &mut verifier, &prompt, episode_key, repair);
    (prompt, trace)
}

impl Method for Grounding2Route {
    fn name(&self) -> &str {
        "grounding2route"
    }

    fn config(&self) -> Value {
        serde_json::to_value(&self.config).unwrap_or(Value::Null)
    }

    fn predict(&self, map: &PreparedMap, episode: &Episode) -> Result<Prediction, MethodError> {
        let instruction = super::instruction_of(episode)?;
        let start = start_cell(&map.map, episode)?;
        let ctx = map.planning()?;
        let key = format!(
            "{}/{}",
            episode.map_id.as_deref().unwrap_or(&map.map.map_id),
            episode
                .instruction_id()
                .unwrap_or_else(|| "instruction".into())
        );
        let simulated;
        let mut faults = Vec::new();
        let fetch: &dyn Fetch = match (&self.config.backend, &self.http) {
            (Backend::Simulated(spec), _) => {
                let gold = episode.m2rc_gold_program.as_deref().ok_or_else(|| {
                    MethodError("the simulated model needs the episode's gold program".into())
                })?;
                simulated = SimulatedModel::new(*spec, gold, &key);
                faults = simulated.first_program().1;
                &simulated
            }
            (Backend::Http, Some(h)) => h,
            (Backend::Http, None) => return Err(MethodError("no LLM client configured".into())),
            (Backend::Gold, _) => return Err(MethodError(GOLD_REFUSED.into())),
        };
        let model = Exchange {
            store: &self.store,
            fetch,
        };
        let meter = std::sync::Arc::new(Meter::new(self.config.budget.clone()));
        let pipeline = PipelineOptions {
            start: Some(start),
            planner: self.config.planner,
            meter: Some(meter.clone()),
            ..PipelineOptions::default()
        };
        let (prompt, trace) = lower_and_plan(
            &model,
            &map.map,
            ctx,
            instruction,
            &key,
            &self.config.prompt,
            &self.config.repair,
            &pipeline,
        );
        let success_round = match trace.outcome {
            m2rc_compiler::lower::EpisodeOutcome::Success { round } => Some(round),
            _ => None,
        };
        let (prompt_tokens, completion_tokens) = trace.tokens();
        let mut info = json!({
            "model": self.config.label(),
            "simulated": self.config.is_simulated(),
            "repair_rounds": self.config.repair.rounds,
            "outcome": trace.outcome,
            "success_round": success_round,
            "first_try_ok": trace.attempts.first().is_some_and(|a| a.outcome == "accepted" && a.local_fixes.is_empty()),
            "first_try_checked": trace.attempts.first().is_some_and(|a| a.outcome == "accepted"),
            "local_fixes": trace.local_fix_count(),
            "prompt_tokens": prompt_tokens,
            "completion_tokens": completion_tokens,
            "latency_ms": trace.attempts.iter().map(|a| a.latency_ms).sum::<f64>(),
            "prompt_estimated_tokens": prompt.estimated_tokens(),
            "attempts": trace.attempts,
        });
        if self.config.is_simulated() {
            info["simulated_faults"] = json!(faults);
        }
        // Only when some are: records of well-behaved servers keep their bytes.
        if trace.unknown_usage() > 0 {
            info["usage_unknown_attempts"] = json!(trace.unknown_usage());
        }
        if success_round.is_some_and(|r| r > 0) {
            let start_only = [[start.row as i64, start.col as i64]];
            let scored = crate::report::score::score(&start_only, episode, &map.eval);
            info["fallback_metrics"] = json!({
                "metrics": scored.metrics,
                "metrics_summary": scored.summary,
            });
        }
        // An episode stopped by its budget says so, whatever round it was in.
        let over = meter.exceeded().filter(|_| success_round.is_none());
        if let Some(reason) = &over {
            info["budget_exceeded"] = json!(reason);
        }
        let mut extra = serde_json::Map::new();
        extra.insert("grounding2route".into(), info);
        let status = match &over {
            Some(_) => "budget_exceeded",
            None => trace.outcome.status(),
        };
        Ok(Prediction {
            trajectory: trace.output.map(|c| c.route.trajectory).unwrap_or_default(),
            program: trace.final_program,
            notes: over.into_iter().collect(),
            status: (status != "ok").then(|| status.to_string()),
            extra,
        })
    }
}

impl Grounding2Route {
    /// Builds the method from the `--llm-*` and lowering flags; the cache defaults to
    /// `default_cache` (`<run dir>/llm-cache`). Also returns a note about imported batch replies.
    pub fn from_args(
        llm: &m2rc_llm::LlmArgs,
        lower: &m2rc_llm::LowerArgs,
        default_cache: &std::path::Path,
    ) -> Result<(Grounding2Route, Option<String>), String> {
        if llm.backend == Backend::Gold {
            return Err(GOLD_REFUSED.into());
        }
        let http = llm.http_client()?;
        let (store, note) = llm.store(default_cache)?;
        let config = Grounding2RouteConfig {
            backend: llm.backend.clone(),
            model: match &llm.backend {
                Backend::Simulated(s) => s.model_name(),
                Backend::Http | Backend::Gold => llm.llm_model.clone(),
            },
            base_url: match &llm.backend {
                Backend::Http => llm.llm_base_url.clone(),
                Backend::Simulated(_) | Backend::Gold => None,
            },
            temperature: llm.llm_temperature,
            max_tokens: match &llm.backend {
                Backend::Http => Some(llm.llm_max_tokens),
                Backend::Simulated(_) | Backend::Gold => None,
            },
            repair: lower.repair_options(),
            prompt: lower.prompt_options(),
            planner: PlannerKind::Sequential,
            budget: EpisodeBudget::from_args(&lower.budget)?,
        };
        Ok((
            Grounding2Route {
                config,
                store,
                http,
            },
            note,
        ))
    }
}
