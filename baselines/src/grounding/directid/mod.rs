//! Direct ID: the model reads a compact catalog of the map (every room and object under an id,
//! with centres, boxes, sizes and room adjacency: [`catalog`]) and answers with the route's
//! segments and constraints naming those ids. m2rc checks the ids, kinds and arities
//! ([`validate`], diagnostics with JSON pointers, so R repair rounds can run on it), builds the
//! RouteIR the compiler would build for the same places ([`build`]) and plans it on CaG's
//! planner ([`plan`]). The reference's code runs it one-shot (R = 0), its table says R = 3.
//!
//! The same path serves catalog-LTL ([`ltl`]): the ids written under a restricted LTL skeleton.
//! A [`Form`] is what differs between the two: prompt, reader, gold writer.

pub mod build;
pub mod catalog;
pub mod faults;
pub mod gold;
pub mod ltl;
pub mod places;
pub mod plan;
pub mod prompt;
pub mod schema;
pub mod validate;

use super::simulated::SimulatedJson;
use super::{JsonRecord, metered, with_model};
use crate::calls::ModelSetup;
use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::methods::{
    Method, MethodError, Prediction, PreparedMap, instruction_of, start_cell,
};
use m2rc_benchmark::pipeline::{CompiledRoute, PipelineOptions, compile_and_plan_with};
use m2rc_compiler::diagnostic::Code;
use m2rc_compiler::intent::{GraphDiagnostic, JsonVerdict, reply_json, run_json_episode};
use m2rc_compiler::lower::{Phase, Prompt, RepairOptions};
use m2rc_llm::Backend;
use m2rc_stdlib::query::MapQuery;
use serde_json::{Value, json};
use std::sync::Arc;

pub const NAME: &str = "directid";

/// What differs between the catalog-id representations.
pub struct Form {
    /// The method's name (`directid`, `catalog-ltl`).
    pub name: &'static str,
    /// The reply's name in repair prompts.
    pub what: &'static str,
    pub prompt: fn(&Value, &str) -> Prompt,
    /// A reply into a validated grounding (diagnostics point into the reply as written).
    pub read: fn(&Value, &MapQuery) -> Result<validate::Grounding, Vec<GraphDiagnostic>>,
    /// A Direct ID reply written in this form (for gold and simulated replies), and what it
    /// could not say.
    pub write: fn(&Value) -> (Value, Vec<String>),
}

pub const DIRECT_ID: Form = Form {
    name: NAME,
    what: "catalog-id grounding",
    prompt: prompt::direct_id_prompt,
    read: validate::validate,
    write: |v| (v.clone(), Vec::new()),
};

/// A catalog-id variant run: Direct ID or catalog-LTL, with R repair rounds.
pub struct CatalogIds {
    pub setup: Arc<ModelSetup>,
    pub repair: RepairOptions,
    /// The run's name (`directid`, or an ablation row's `directid-r3`).
    pub name: String,
    pub form: &'static Form,
}

/// The registry's Direct ID: one-shot, as the reference's code runs it.
pub fn make(setup: Arc<ModelSetup>) -> Box<dyn Method> {
    Box::new(CatalogIds::new(setup, 0, &DIRECT_ID))
}

impl CatalogIds {
    pub fn new(setup: Arc<ModelSetup>, rounds: usize, form: &'static Form) -> Self {
        CatalogIds {
            setup,
            repair: RepairOptions {
                rounds,
                ..RepairOptions::default()
            },
            name: form.name.into(),
            form,
        }
    }
}

/// The episode's gold RouteIR (its gold program compiled and planned), as gold ids.
pub fn gold_reply(
    program: &str,
    map: &PreparedMap,
    q: &MapQuery,
    start: m2rc_stdlib::grid::Cell,
) -> Result<gold::GoldIds, String> {
    let ctx = map.planning().map_err(|e| e.0.clone())?;
    let opts = PipelineOptions {
        start: Some(start),
        ..PipelineOptions::default()
    };
    let compiled = compile_and_plan_with(program, &map.map, ctx, &opts).map_err(|d| {
        format!(
            "the gold program does not compile: {}",
            d.first().map_or(String::new(), |d| d.message.clone())
        )
    })?;
    let mut g = gold::gold_ids(&compiled.ir, q);
    // What the ids cannot say and no place shows (a shape's `until`): the rebuilt route differs.
    if g.lossy.is_empty()
        && let Ok(v) = validate::validate(&g.reply, q)
        && let Ok(ir) = build::build(&v, q, start)
        && !gold::same_route(&ir, &compiled.ir)
    {
        g.lossy.push(
            "the ids rebuild a different RouteIR (a shape's until, passing or avoiding)".into(),
        );
    }
    Ok(g)
}

/// Reads, validates, builds and plans one reply.
pub fn verify(
    text: &str,
    form: &Form,
    map: &PreparedMap,
    q: &MapQuery,
    start: m2rc_stdlib::grid::Cell,
    pipeline: &PipelineOptions,
) -> JsonVerdict<CompiledRoute> {
    let whole = |m: String| GraphDiagnostic::new(Code::MalformedIr, "", m, None);
    let ctx = map
        .planning()
        .map_err(|e| (Phase::Plan, vec![whole(e.0.clone())]))?;
    let reply = reply_json(text).map_err(|d| (Phase::Check, vec![*d]))?;
    let g = (form.read)(&reply, q).map_err(|d| (Phase::Check, d))?;
    let ir = build::build(&g, q, start).map_err(|d| (Phase::Ground, d))?;
    let canonical = serde_json::to_string(&reply).unwrap_or_default();
    match plan::plan_ir(ir, &map.map, q, ctx, pipeline) {
        Ok(c) => Ok((c, canonical)),
        Err(plan::PlanError::Verify(d)) => Err((
            Phase::Verify,
            d.into_iter()
                .filter(|d| d.is_error())
                .map(|d| GraphDiagnostic {
                    diagnostic: d,
                    pointer: String::new(),
                    patch: None,
                })
                .collect(),
        )),
        Err(plan::PlanError::Plan(d)) => Err((
            Phase::Plan,
            vec![GraphDiagnostic {
                diagnostic: *d,
                pointer: "/segments".into(),
                patch: None,
            }],
        )),
    }
}

/// The largest room or object id of the map (the simulated model's unknown ids are past it).
fn largest_id(q: &MapQuery) -> u32 {
    let m = q.map();
    let r = m.rooms.iter().map(|r| r.id).max().unwrap_or(0);
    let o = m.objects.iter().map(|o| o.id).max().unwrap_or(0);
    r.max(o)
}

impl Method for CatalogIds {
    fn name(&self) -> &str {
        &self.name
    }

    fn config(&self) -> Value {
        json!({
            "method": self.form.name,
            "m2rc": env!("CARGO_PKG_VERSION"),
            "model": self.setup.config(),
            "backend": self.setup.backend,
            "repair_rounds": self.repair.rounds,
            "catalog_schema_version": 1,
        })
    }

    fn predict(&self, map: &PreparedMap, episode: &Episode) -> Result<Prediction, MethodError> {
        let form = self.form;
        let instruction = instruction_of(episode)?;
        let start = start_cell(&map.map, episode)?;
        let key = format!(
            "{}/{}/{}",
            episode.map_id.as_deref().unwrap_or(&map.map.map_id),
            episode
                .instruction_id()
                .unwrap_or_else(|| "instruction".into()),
            form.name
        );
        let q = MapQuery::new(&map.map);
        let catalog = catalog::compact_catalog(&q, start);
        let prompt = (form.prompt)(&catalog, instruction);
        let needs_gold = matches!(self.setup.backend, Backend::Gold | Backend::Simulated(_));
        let gold = match (needs_gold, episode.m2rc_gold_program.as_deref()) {
            (false, _) => None,
            (true, None) => {
                return Err(MethodError(
                    "gold and simulated replies need the episode's gold program".into(),
                ));
            }
            (true, Some(p)) => Some(gold_reply(p, map, &q, start).map_err(MethodError)?),
        };
        let mut lossy: Vec<String> = Vec::new();
        let gold_form = gold.as_ref().map(|g| {
            let (v, more) = (form.write)(&g.reply);
            lossy = g.lossy.iter().cloned().chain(more).collect();
            v
        });
        let (meter, pipeline) = metered(start);
        let mut faults: Vec<&'static str> = Vec::new();
        let trace = with_model(
            &self.setup,
            || {
                gold_form
                    .as_ref()
                    .map(|v| serde_json::to_string(v).unwrap_or_default())
                    .ok_or_else(|| "no gold ids".into())
            },
            |spec| {
                let write =
                    |v: &Value| serde_json::to_string(&(form.write)(v).0).unwrap_or_default();
                let g = gold.as_ref().map_or(Value::Null, |g| g.reply.clone());
                // Seeded by the episode, not the form: Direct ID and catalog-LTL make the same
                // faults, so their rows differ only by the representation.
                let episode_key = key.trim_end_matches(form.name);
                let (first, f) = faults::first_answer(
                    &g,
                    spec.fault_rate,
                    spec.seed,
                    episode_key,
                    largest_id(&q),
                    &write,
                );
                faults = f;
                Box::new(SimulatedJson {
                    spec,
                    name: spec.model_name(),
                    variant: form.name,
                    episode: key.clone(),
                    first,
                })
            },
            |model| {
                let mut v = |t: &str| verify(t, form, map, &q, start, &pipeline);
                run_json_episode(model, &mut v, &prompt, &key, &self.repair, form.what)
            },
        )
        .map_err(MethodError)?;
        let record = JsonRecord {
            key: form.name,
            setup: &self.setup,
            repair: &self.repair,
            prompt: &prompt,
            meter: &meter,
            faults: &faults,
            ceiling: "the gold RouteIR as catalog ids",
        };
        let mut details = serde_json::Map::new();
        details.insert("catalog_objects".into(), json!(map.map.objects.len()));
        let mut after = serde_json::Map::new();
        if gold.is_some() {
            after.insert("gold_lossy".into(), json!(lossy));
        }
        Ok(record.prediction(trace, details, after))
    }
}
