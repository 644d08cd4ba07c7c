//! ILN as a benchmark method: builds the graph for the episode's map, runs the two calls through
//! the baselines' LLM-call helper, and writes the route (partial on failure, as the reference's
//! runner does) with the `iln` block.

use super::graph::AreaGraph;
use crate::ModelSetup;
use crate::calls::{GOLD_LABEL, Session};
use crate::common::failure::{Failure, PENDING, prediction};
use crate::common::gold::Gold;
use crate::common::grid::GridSearch;
use crate::common::labels::nearest_free;
use crate::common::start_cell;
use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::methods::{Method, MethodError, Prediction, PreparedMap, instruction_of};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use serde_json::{Value, json};
use std::sync::Arc;

pub const NAME: &str = "iln";

pub struct Iln {
    pub setup: Arc<ModelSetup>,
}

pub fn make(setup: Arc<ModelSetup>) -> Box<dyn Method> {
    Box::new(Iln { setup })
}

impl Method for Iln {
    fn name(&self) -> &str {
        NAME
    }

    fn config(&self) -> Value {
        json!({
            "method": NAME,
            "m2rc": env!("CARGO_PKG_VERSION"),
            "model": self.setup.config(),
            "base_passage_cost": super::route::BASE_PASSAGE_COST,
        })
    }

    fn predict(&self, map: &PreparedMap, episode: &Episode) -> Result<Prediction, MethodError> {
        let instruction = instruction_of(episode)?;
        let m = &map.map;
        let start = drive_start(m, episode)?;
        let g = AreaGraph::build(m);
        let mut grid = GridSearch::new(m);
        let gold_dest = Gold::of(m, episode)
            .ok()
            .and_then(|g| g.destinations.last().and_then(|d| d.room_id))
            .map(|r| format!("room_{r}"));
        let mut session = Session::new(&self.setup, NAME, &m.map_id, episode);
        let out = super::run(
            m,
            &g,
            &mut grid,
            instruction,
            start,
            gold_dest.as_deref(),
            &mut |step, messages, gold| session.chat(step, messages, gold),
        );
        let mut block = match out.info {
            Value::Object(b) => b,
            _ => serde_json::Map::new(),
        };
        block.insert("calls".into(), json!(session.calls));
        block.insert("model".into(), json!(self.setup.chat_label()));
        block.insert("gold_replies".into(), json!(self.setup.is_gold()));
        let notes = gold_note(
            &self.setup,
            "the destination is the room of the last annotated target, every passage at the \
             neutral cost",
        );
        Ok(finish(NAME, out.status, out.trajectory, block, notes))
    }
}

/// The prediction of a graph baseline's episode: the route it drove (the start at least), its
/// status, and its block; a pending episode gets no route, so the runner leaves it for later.
pub fn finish(
    key: &str,
    status: String,
    route: Vec<m2rc_stdlib::grid::Cell>,
    block: serde_json::Map<String, Value>,
    notes: Vec<String>,
) -> Prediction {
    if status == PENDING {
        let message = block
            .get("failure_reason")
            .and_then(Value::as_str)
            .unwrap_or("waiting for a batch reply")
            .to_string();
        return prediction(key, Err(Failure::new(PENDING, message)), block, notes);
    }
    let mut p = prediction(key, Ok(route), block, notes);
    if status != "ok" {
        p.status = Some(status);
    }
    p
}

/// How far the reference looks for a free cell around a blocked start (cells).
pub const START_RADIUS: f64 = 80.0;

/// Where the robot starts driving: the episode's start cell when it is free, else the nearest
/// free cell within [`START_RADIUS`] (the reference adapters' rule).
pub fn drive_start(map: &SemanticMap, episode: &Episode) -> Result<Cell, MethodError> {
    let s = start_cell(map, episode)?;
    if map.is_free(s) {
        return Ok(s);
    }
    nearest_free(map, [s.row as f64, s.col as f64], START_RADIUS).ok_or_else(|| {
        MethodError(format!(
            "no free cell within {START_RADIUS} cells of the start [{}, {}]",
            s.row, s.col
        ))
    })
}

/// The record's note of a gold run: the label and what the oracle answered.
pub fn gold_note(setup: &ModelSetup, what: &str) -> Vec<String> {
    if setup.is_gold() {
        vec![format!("{GOLD_LABEL}: {what}")]
    } else {
        vec![]
    }
}
