//! LTLCodeGen as a benchmark method: up to three calls through the shared [`Session`], the gold
//! oracle writing the `question()` program of the annotated route.

use super::inventory::Inventory;
use super::{CALLS, NAME, gold_code, run_episode};
use crate::calls::{ModelSetup, Session};
use crate::common::failure::{Failure, PENDING, prediction};
use crate::common::gold::Gold;
use crate::common::start_cell;
use crate::osgllm::gold::from_common;
use crate::osgllm::graph::nearest_traversable;
use crate::osgllm::method::{START_SNAP_CELLS, SessionAsk};
use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::methods::{Method, MethodError, Prediction, PreparedMap};
use m2rc_stdlib::grid::Cell;
use serde_json::{Value, json};
use std::sync::Arc;

/// A map's inventory and traversability, built once per map.
pub struct MapView {
    pub inventory: Inventory,
    pub traversable: Vec<bool>,
}

pub struct LtlCodeGen {
    pub setup: Arc<ModelSetup>,
}

pub fn make(setup: Arc<ModelSetup>) -> Box<dyn Method> {
    Box::new(LtlCodeGen::new(setup))
}

impl LtlCodeGen {
    pub fn new(setup: Arc<ModelSetup>) -> Self {
        LtlCodeGen { setup }
    }

    /// The map's inventory and traversability, built once per map and kept with it.
    pub fn view(&self, map: &PreparedMap) -> Arc<MapView> {
        map.derived(|map| {
            let n = map.n();
            MapView {
                inventory: Inventory::build(map),
                traversable: (0..n * n)
                    .map(|i| map.is_free(Cell::new((i / n) as u32, (i % n) as u32)))
                    .collect(),
            }
        })
    }
}

impl Method for LtlCodeGen {
    fn name(&self) -> &str {
        NAME
    }

    fn config(&self) -> Value {
        json!({
            "method": NAME,
            "m2rc": env!("CARGO_PKG_VERSION"),
            "model": self.setup.config(),
            "max_attempts": super::MAX_ATTEMPTS,
            "max_prompt_objects": super::inventory::MAX_PROMPT_OBJECTS,
            "object_label_radius_cells": crate::common::labels::OBJECT_LABEL_RADIUS_CELLS,
            "heuristic_cells": super::HEURISTIC_CELLS,
            "sandbox": {
                "max_source_bytes": super::sandbox::MAX_SOURCE_BYTES,
                "max_steps": super::sandbox::MAX_STEPS,
                "max_formula_nodes": super::sandbox::MAX_FORMULA_NODES,
            },
        })
    }

    fn predict(&self, map: &PreparedMap, episode: &Episode) -> Result<Prediction, MethodError> {
        let view = self.view(map);
        let pose = start_cell(&map.map, episode)?;
        let mut session = Session::new(&self.setup, NAME, &map.map.map_id, episode);
        let Some(start) =
            nearest_traversable(&view.traversable, map.map.n(), pose, START_SNAP_CELLS)
        else {
            let f = Failure::new(
                "start_blocked",
                format!("no traversable cell within {START_SNAP_CELLS} cells of the start pose"),
            );
            return Ok(prediction(
                "ltlcodegen",
                Err(f),
                serde_json::Map::new(),
                vec![],
            ));
        };
        let mut notes = Vec::new();
        // The gold program is the same for every attempt (the first one runs).
        let gold = session.is_gold().then(|| {
            Gold::of(&map.map, episode).map(|g| {
                let (code, n) = gold_code(
                    &map.map,
                    &view.inventory,
                    &from_common(&g, &map.map, episode),
                );
                notes.extend(n);
                CALLS
                    .iter()
                    .map(|c| (c.to_string(), code.clone()))
                    .collect()
            })
        });
        let instruction = episode.instruction.clone().unwrap_or_default();
        let mut ask = SessionAsk {
            session: &mut session,
            gold,
            last_failure: None,
        };
        let out = run_episode(
            &map.map,
            &view.inventory,
            &view.traversable,
            &instruction,
            start,
            &mut ask,
        );
        let last = ask.last_failure.take();
        let mut block = match out.record {
            Value::Object(m) => m,
            _ => serde_json::Map::new(),
        };
        block.insert("calls".into(), Value::Array(session.calls));
        block.insert("model".into(), json!(self.setup.chat_label()));
        block.insert("gold_replies".into(), json!(self.setup.is_gold()));
        if self.setup.is_gold() {
            notes.insert(
                0,
                format!("{}: the question() program from the gold annotations; the sandbox and the planner run as the method does", crate::calls::GOLD_LABEL),
            );
        }
        let route = if out.status == "ok" {
            Ok(out.trajectory)
        } else {
            let status = match &last {
                Some(f) if f.status == PENDING || f.status == "gold_unavailable" => {
                    f.status.clone()
                }
                _ => out.status.clone(),
            };
            let message = last.map_or_else(|| out.status.replace('_', " "), |f| f.to_string());
            Err(Failure::new(&status, message))
        };
        Ok(prediction(NAME, route, block, notes))
    }
}
