//! LTLCodeGen (IROS'25) as Map2Route adapted it: the model writes a `question()` program that
//! builds an LTL formula over an AP inventory with a small operator library; we run it in our own
//! sandbox ([`sandbox`]), strip top-level AP conjuncts as start-pose preconditions, and plan on
//! the product of the grid and the formula's automaton with no expansion limit (the product's
//! size bounds it). Up to three attempts, each retry shown the previous code and its failure.
//! See `docs/baselines.md`, "LTLCodeGen".

pub mod inventory;
pub mod method;
pub mod prompts;
pub mod sandbox;

use crate::osgllm::gold::{GoldGrounding, visits_formula};
use crate::osgllm::product::{self, Guess, ProductQuery};
use crate::osgllm::{Ask, CallError};
use inventory::Inventory;
use m2rc_compiler::ltl::Formula;
use m2rc_compiler::ltl::syntax::Kind;
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use serde_json::{Value, json};
use std::collections::BTreeMap;

pub const NAME: &str = "ltlcodegen";
/// Attempts per episode (the first call and two retries).
pub const MAX_ATTEMPTS: usize = 3;
/// Cells per region the heuristic measures to.
pub const HEURISTIC_CELLS: usize = 2000;
/// Call names, by attempt.
pub const CALLS: [&str; MAX_ATTEMPTS] = ["code", "retry_1", "retry_2"];

/// How an episode ended, with the `ltlcodegen` record block.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    pub trajectory: Vec<Cell>,
    /// `ok`, `codegen_failed`, `planning_failed` or `pending`.
    pub status: String,
    pub record: Value,
}

/// The formula without its top-level AP conjuncts (read as start-pose preconditions), and the
/// APs removed.
pub fn strip_initial_aps(f: Formula) -> (Formula, Vec<String>) {
    fn flatten(f: Formula, out: &mut Vec<Formula>) {
        match f.kind {
            Kind::And(a, b) => {
                flatten(*a, out);
                flatten(*b, out);
            }
            other => out.push(Formula::new(other)),
        }
    }
    let mut parts = Vec::new();
    flatten(f, &mut parts);
    let mut removed = Vec::new();
    parts.retain(|p| match &p.kind {
        Kind::Atom(a) => {
            removed.push(a.clone());
            false
        }
        _ => true,
    });
    (Formula::and_all(parts), removed)
}

pub fn run_episode(
    map: &SemanticMap,
    inv: &Inventory,
    traversable: &[bool],
    instruction: &str,
    start: Cell,
    ask: &mut dyn Ask,
) -> Outcome {
    let mut attempts: Vec<Value> = Vec::new();
    let mut previous: Option<(String, String)> = None;
    let mut evaluated = None;
    let inventory = inv.prompt_json();
    for call in CALLS {
        let user = prompts::user(
            instruction,
            &inventory,
            previous.as_ref().map(|(c, e)| (c.as_str(), e.as_str())),
        );
        let reply = match ask.ask(call, prompts::SYSTEM, &user) {
            Ok(r) => r,
            Err(CallError::Pending(id)) => {
                return end(start, "pending", attempts, json!({"waiting_for": id}));
            }
            Err(CallError::Failed(why)) => {
                attempts.push(json!({"call": call, "error": why}));
                return end(start, "codegen_failed", attempts, Value::Null);
            }
        };
        let code = prompts::extract_code(&reply);
        match sandbox::run(&code, &|ap| inv.is_listed(ap)) {
            Ok(e) => {
                attempts.push(json!({"call": call, "code": code, "steps": e.steps}));
                evaluated = Some(e);
                break;
            }
            Err(e) => {
                attempts.push(json!({"call": call, "code": code, "error": e.to_string()}));
                previous = Some((code, e.to_string()));
            }
        }
    }
    let Some(e) = evaluated else {
        return end(start, "codegen_failed", attempts, Value::Null);
    };
    let (formula, removed) = strip_initial_aps(e.formula);
    let mut regions: BTreeMap<String, Vec<u32>> = BTreeMap::new();
    for a in formula.atoms() {
        regions.insert(a.to_string(), inventory::label_cells(map, inv, a));
    }
    let region = |a: &str| regions.get(a).map(Vec::as_slice);
    let result = product::search(&ProductQuery {
        n: map.n(),
        traversable,
        formula: &formula,
        region: &region,
        start,
        max_expansions: u64::MAX,
        guess: Guess::EuclidSamples(HEURISTIC_CELLS),
    });
    let mut info = json!({
        "formula": formula.to_string(),
        "removed_initial_aps": removed,
        "aps": e.aps,
    });
    match result {
        Ok(r) => {
            info["planner"] = json!({"result": "found", "expansions": r.expansions,
                "automaton_states": r.automaton_states, "length_cells": r.cost});
            let mut o = end(start, "ok", attempts, info);
            o.trajectory = r.trajectory;
            o
        }
        Err(err) => {
            info["planner"] = json!({"result": err.kind(), "message": err.to_string()});
            end(start, "planning_failed", attempts, info)
        }
    }
}

fn end(start: Cell, status: &str, attempts: Vec<Value>, info: Value) -> Outcome {
    let mut rec = json!({"attempts": attempts});
    if let Value::Object(m) = info {
        for (k, v) in m {
            rec[k] = v;
        }
    }
    Outcome {
        trajectory: vec![start],
        status: status.into(),
        record: rec,
    }
}

/// The gold reply: a `question()` program over the inventory for the gold visits and avoids. An
/// object the inventory does not list is named by the first listed instance of its category,
/// as the prompt's duplicate-category rule tells the model (the note says so).
pub fn gold_code(
    map: &SemanticMap,
    inv: &Inventory,
    gold: &GoldGrounding,
) -> (String, Vec<String>) {
    let mut notes = gold.notes.clone();
    let mut name = |id: &String| -> String {
        if inv.is_listed(id) {
            return id.clone();
        }
        let category = id
            .strip_prefix("object_")
            .and_then(|x| x.parse::<u32>().ok())
            .and_then(|x| map.object(x))
            .map(|o| o.category.clone())
            .unwrap_or_default();
        match inv.first_of(&category) {
            Some(first) => {
                notes.push(format!(
                    "{id} is not listed; named by the first listed {category}, {first}"
                ));
                first.to_string()
            }
            None => id.clone(),
        }
    };
    let mut renamed = gold.clone();
    for (g, _) in &mut renamed.goals {
        *g = name(g);
    }
    for (a, _) in &mut renamed.avoids {
        *a = name(a);
    }
    let f = visits_formula(&renamed, &|id: &String| Formula::atom(id));
    (prompts::code_of(&f), notes)
}

#[cfg(test)]
mod tests;
