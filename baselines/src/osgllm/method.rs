//! OSG-LLM as a benchmark method: the calls go through the shared [`Session`] (cache, batch,
//! server, or the gold oracle), the scene graph is built once per map.

use super::gold::{from_common, gold_replies};
use super::graph::{SceneGraph, nearest_traversable};
use super::{Ask, CALLS, CallError, NAME, run_episode};
use crate::calls::{ModelSetup, Session};
use crate::common::failure::{Failure, PENDING, prediction};
use crate::common::gold::Gold;
use crate::common::start_cell;
use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::methods::{Method, MethodError, Prediction, PreparedMap};
use m2rc_compiler::lower::Message;
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::sync::Arc;

/// How far from the start pose the start may be moved onto a traversable cell (4 m).
pub const START_SNAP_CELLS: u32 = 80;
pub struct OsgLlm {
    pub setup: Arc<ModelSetup>,
}

pub fn make(setup: Arc<ModelSetup>) -> Box<dyn Method> {
    Box::new(OsgLlm::new(setup))
}

impl OsgLlm {
    pub fn new(setup: Arc<ModelSetup>) -> Self {
        OsgLlm { setup }
    }

    /// The map's scene graph, built once per map and kept with it.
    pub fn graph(&self, map: &PreparedMap) -> Arc<SceneGraph> {
        map.derived(SceneGraph::build)
    }
}

/// The session as OSG-LLM's [`Ask`]: gold replies by call, the session's failure kept.
pub struct SessionAsk<'s, 'a> {
    pub session: &'s mut Session<'a>,
    /// The gold replies by call name (gold runs), or why there are none.
    pub gold: Option<Result<BTreeMap<String, String>, String>>,
    pub last_failure: Option<Failure>,
}

impl Ask for SessionAsk<'_, '_> {
    fn ask(&mut self, call: &str, system: &str, user: &str) -> Result<String, CallError> {
        let gold = || match &self.gold {
            Some(Ok(m)) => m
                .get(call)
                .cloned()
                .ok_or_else(|| format!("no gold reply for `{call}`")),
            Some(Err(e)) => Err(e.clone()),
            None => Err("not a gold run".into()),
        };
        let r = self.session.chat(
            call,
            vec![Message::system(system), Message::user(user)],
            &gold,
        );
        r.map_err(|f| {
            let e = if f.status == PENDING {
                CallError::Pending(f.message.clone())
            } else {
                CallError::Failed(f.to_string())
            };
            self.last_failure = Some(f);
            e
        })
    }
}

impl Method for OsgLlm {
    fn name(&self) -> &str {
        NAME
    }

    fn config(&self) -> Value {
        json!({
            "method": NAME,
            "m2rc": env!("CARGO_PKG_VERSION"),
            "model": self.setup.config(),
            "max_expansions": super::product::MAX_EXPANSIONS,
            "time_limit_expansions": super::product::TIME_LIMIT_EXPANSIONS,
            "object_reach_cells": super::graph::OBJECT_REACH_CELLS,
            "heuristic_samples": super::product::HEURISTIC_SAMPLES,
            "candidate_cells": super::fallback::CANDIDATE_CELLS,
        })
    }

    fn predict(&self, map: &PreparedMap, episode: &Episode) -> Result<Prediction, MethodError> {
        let graph = self.graph(map);
        let pose = start_cell(&map.map, episode)?;
        let mut session = Session::new(&self.setup, NAME, &map.map.map_id, episode);
        let mut block = serde_json::Map::new();
        let Some(start) = nearest_traversable(&graph.traversable, graph.n, pose, START_SNAP_CELLS)
        else {
            let f = Failure::new(
                "start_blocked",
                format!("no traversable cell within {START_SNAP_CELLS} cells of the start pose"),
            );
            return Ok(prediction(NAME, Err(f), block, vec![]));
        };
        let mut notes = Vec::new();
        let gold = session.is_gold().then(|| {
            Gold::of(&map.map, episode).map(|g| {
                let gg = from_common(&g, &map.map, episode);
                notes.extend(gg.notes.iter().cloned());
                CALLS
                    .iter()
                    .map(|c| c.to_string())
                    .zip(gold_replies(&gg, &graph))
                    .collect()
            })
        });
        let instruction = episode.instruction.clone().unwrap_or_default();
        let mut ask = SessionAsk {
            session: &mut session,
            gold,
            last_failure: None,
        };
        let out = run_episode(&map.map, &graph, &instruction, start, &mut ask);
        let last = ask.last_failure.take();
        if let Value::Object(m) = out.record {
            block = m;
        }
        block.insert("calls".into(), Value::Array(session.calls));
        block.insert("model".into(), json!(self.setup.chat_label()));
        block.insert("gold_replies".into(), json!(self.setup.is_gold()));
        if self.setup.is_gold() {
            notes.insert(
                0,
                format!("{}: grounding, translation and heuristic replies from the gold annotations; the planners run as the method does", crate::calls::GOLD_LABEL),
            );
        }
        let route = if out.status == "ok" {
            Ok(out.trajectory)
        } else {
            let message = block
                .get("error")
                .and_then(Value::as_str)
                .unwrap_or("no route")
                .to_string();
            // Waiting for a batch, or no gold reply to give: the harness's status, not the method's.
            let status = match &last {
                Some(f) if f.status == PENDING || f.status == "gold_unavailable" => {
                    f.status.clone()
                }
                _ => out.status.clone(),
            };
            Err(Failure::new(&status, message))
        };
        Ok(prediction(NAME, route, block, notes))
    }
}
