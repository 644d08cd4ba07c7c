//! Schema: the model writes a JSON intent graph (operators generated from the built-in table; the
//! model sees the scene's categories only, never ids or counts), which m2rc compiles
//! deterministically to `.m2r` and then through the ordinary compiler and planner. Compile errors
//! come back as diagnostics with JSON pointers into the graph, so R repair rounds run on it as on
//! a program; the reference's code runs it one-shot (R = 0), its table says R = 3.

use super::simulated::SimulatedJson;
use super::{JsonRecord, metered, with_model};
use crate::calls::ModelSetup;
use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::methods::{
    Method, MethodError, Prediction, PreparedMap, instruction_of, start_cell,
};
use m2rc_benchmark::pipeline::{CompiledRoute, PipelineOptions, compile_and_plan_with};
use m2rc_compiler::intent::{
    GraphDiagnostic, JsonVerdict, graph_feedback, graph_to_program, program_to_graph, reply_json,
    run_json_episode, schema_prompt,
};
use m2rc_compiler::lower::{CatalogMode, Phase, RepairOptions, SceneCatalog};
use m2rc_llm::Backend;
use serde_json::{Value, json};
use std::sync::Arc;

pub const NAME: &str = "schema";

/// Worked examples in the prompt (the CaG prompt's, as graphs).
pub const EXAMPLES: usize = 5;

pub struct Schema {
    pub setup: Arc<ModelSetup>,
    pub repair: RepairOptions,
    /// The name of the run (`schema`, or an ablation row's `schema-r3`).
    pub name: String,
}

/// The registry's Schema: one-shot, as the reference's code runs it.
pub fn make(setup: Arc<ModelSetup>) -> Box<dyn Method> {
    Box::new(Schema::new(setup, 0))
}

impl Schema {
    pub fn new(setup: Arc<ModelSetup>, rounds: usize) -> Schema {
        Schema {
            setup,
            repair: RepairOptions {
                rounds,
                ..RepairOptions::default()
            },
            name: NAME.into(),
        }
    }
}

/// A program written as the graph the model would send.
pub fn graph_text(program: &str) -> Option<String> {
    program_to_graph(program)
        .ok()
        .map(|g| serde_json::to_string(&g).unwrap_or_default())
}

/// Reads, compiles, grounds and plans one reply.
fn verify(text: &str, map: &PreparedMap, pipeline: &PipelineOptions) -> JsonVerdict<CompiledRoute> {
    let ctx = map
        .planning()
        .map_err(|e| (Phase::Plan, vec![plan_error(&e.0)]))?;
    let graph = reply_json(text).map_err(|d| (Phase::Check, vec![*d]))?;
    let compiled = graph_to_program(&graph).map_err(|d| (Phase::Check, d))?;
    match compile_and_plan_with(&compiled.program, &map.map, ctx, pipeline) {
        Ok(c) => Ok((c, compiled.program)),
        Err(diags) => Err((Phase::of_errors(&diags), graph_feedback(&compiled, &diags))),
    }
}

fn plan_error(message: &str) -> GraphDiagnostic {
    GraphDiagnostic::new(
        m2rc_compiler::diagnostic::Code::MalformedIr,
        "",
        message,
        None,
    )
}

impl Method for Schema {
    fn name(&self) -> &str {
        &self.name
    }

    fn config(&self) -> Value {
        json!({
            "method": NAME,
            "m2rc": env!("CARGO_PKG_VERSION"),
            "model": self.setup.config(),
            // Where the report looks for the simulated model, as in `grounding2route`'s.
            "backend": self.setup.backend,
            "repair_rounds": self.repair.rounds,
            "examples": EXAMPLES,
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
        let catalog = SceneCatalog::from_map(&map.map, CatalogMode::Counts);
        let prompt = schema_prompt(&map.map.map_id, &catalog, instruction, EXAMPLES);
        let gold_program = episode.m2rc_gold_program.as_deref();
        let needs_gold = matches!(self.setup.backend, Backend::Gold | Backend::Simulated(_));
        if needs_gold && gold_program.is_none() {
            return Err(MethodError(
                "gold and simulated replies need the episode's gold program".into(),
            ));
        }
        let gold = gold_program.unwrap_or_default();
        let (meter, pipeline) = metered(start);
        let mut faults: Vec<&'static str> = Vec::new();
        let trace = with_model(
            &self.setup,
            || graph_text(gold).ok_or_else(|| "the gold program has no intent graph".into()),
            |spec| {
                let (sim, f) = SimulatedJson::new(spec, NAME, &key, gold, &graph_text);
                faults = f;
                Box::new(sim)
            },
            |model| {
                let mut v = |t: &str| verify(t, map, &pipeline);
                run_json_episode(model, &mut v, &prompt, &key, &self.repair, "intent graph")
            },
        )
        .map_err(MethodError)?;
        let record = JsonRecord {
            key: NAME,
            setup: &self.setup,
            repair: &self.repair,
            prompt: &prompt,
            meter: &meter,
            faults: &faults,
            ceiling: "the gold program as an intent graph",
        };
        Ok(record.prediction(trace, Default::default(), Default::default()))
    }
}
