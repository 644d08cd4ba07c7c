//! SayPlan as a benchmark method: builds the scene graph for the episode, runs the search and
//! planning loops through the baselines' LLM-call helper, and writes the accepted route (or the
//! longest attempted one) with the `sayplan` block.

use super::graph::SceneGraph;
use crate::ModelSetup;
use crate::calls::Session;
use crate::common::gold::Gold;
use crate::common::grid::GridSearch;
use crate::iln::method::{drive_start, finish, gold_note};
use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::methods::{Method, MethodError, Prediction, PreparedMap, instruction_of};
use serde_json::{Value, json};
use std::sync::Arc;

pub const NAME: &str = "sayplan";

pub struct SayPlan {
    pub setup: Arc<ModelSetup>,
}

pub fn make(setup: Arc<ModelSetup>) -> Box<dyn Method> {
    Box::new(SayPlan { setup })
}

impl Method for SayPlan {
    fn name(&self) -> &str {
        NAME
    }

    fn config(&self) -> Value {
        json!({
            "method": NAME,
            "m2rc": env!("CARGO_PKG_VERSION"),
            "model": self.setup.config(),
            "max_search_steps": super::MAX_SEARCH_STEPS,
            "max_plans": super::MAX_PLANS,
            "max_json_reasks": super::MAX_JSON_REASKS,
        })
    }

    fn predict(&self, map: &PreparedMap, episode: &Episode) -> Result<Prediction, MethodError> {
        let instruction = instruction_of(episode)?;
        let m = &map.map;
        let start = drive_start(m, episode)?;
        let g = SceneGraph::build(m, start);
        let mut grid = GridSearch::new(m);
        let script = Gold::of(m, episode).map(|gold| super::gold_script(&g, &gold.destinations));
        let mut session = Session::new(&self.setup, NAME, &m.map_id, episode);
        let out = super::run(
            &g,
            &mut grid,
            instruction,
            script.as_ref().map_err(String::as_str),
            &mut |step, messages, gold| session.chat(step, messages, gold),
        );
        let mut block = match out.info {
            Value::Object(b) => b,
            _ => serde_json::Map::new(),
        };
        block.insert("inference_contract_version".into(), json!(2));
        block.insert("calls".into(), json!(session.calls));
        block.insert("model".into(), json!(self.setup.chat_label()));
        block.insert("gold_replies".into(), json!(self.setup.is_gold()));
        let notes = gold_note(
            &self.setup,
            "the search expands each room holding an annotated target object, the plan goes to \
             the targets in order",
        );
        Ok(finish(NAME, out.status, out.trajectory, block, notes))
    }
}
