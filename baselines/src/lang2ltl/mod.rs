//! Lang2LTL (CoRL'23) as Map2Route adapted it: a recogniser call extracts the referring
//! expressions; each is grounded to one room or object AP by embedding similarity against the
//! APs' text descriptions (the map reaches the method only this way; no map data is in a prompt);
//! the command is lifted to letters and translated into prefix LTL, repaired up to twice, else
//! replaced by the sequential-eventual formula; the AP-MDP planner ([`planner`]) plans it. Soft
//! preferences are ignored. The T5 translator cannot be fetched here, so the translation is the
//! LLM mode the authors describe; a local seq2seq model would plug in at [`translate_lifted`].

pub mod planner;
pub mod prompts;
pub mod translate;

use crate::calls::{ModelSetup, Session};
use crate::common::failure::{Failure, prediction};
use crate::common::gold::Gold;
use crate::common::grid::GridSearch;
use crate::common::inventory::Inventory;
use crate::common::labels::{OBJECT_LABEL_RADIUS_CELLS, label_cells};
use crate::common::prefix_ltl::to_prefix;
use crate::common::start_cell;
use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::methods::{Method, MethodError, Prediction, PreparedMap, instruction_of};
use m2rc_compiler::ltl::Formula;
use m2rc_compiler::ltl::syntax::Kind;
use serde_json::{Map, Value, json};
use std::sync::Arc;
use translate::Grounding;

pub const NAME: &str = "lang2ltl";

/// Repair calls after a translation the parser cannot read.
pub const MAX_REPAIRS: usize = 2;

/// What translated the lifted command.
pub const TRANSLATOR: &str = "llm (the fine-tuned T5 translator cannot be fetched here; the \
                              authors' LLM translation mode is used instead)";

pub struct Lang2Ltl {
    pub setup: Arc<ModelSetup>,
    pub expansion_limit: usize,
}

pub fn make(setup: Arc<ModelSetup>) -> Box<dyn Method> {
    Box::new(Lang2Ltl {
        setup,
        expansion_limit: planner::EXPANSION_LIMIT,
    })
}

impl Method for Lang2Ltl {
    fn name(&self) -> &str {
        NAME
    }

    fn config(&self) -> Value {
        json!({
            "method": NAME,
            "m2rc": env!("CARGO_PKG_VERSION"),
            "model": self.setup.config(),
            "translator": "llm",
            "expansion_limit": self.expansion_limit,
            "max_repairs": MAX_REPAIRS,
            "object_label_radius_cells": OBJECT_LABEL_RADIUS_CELLS,
        })
    }

    fn predict(&self, map: &PreparedMap, episode: &Episode) -> Result<Prediction, MethodError> {
        let instruction = instruction_of(episode)?;
        let start = start_cell(&map.map, episode)?;
        let mut session = Session::new(&self.setup, NAME, &map.map.map_id, episode);
        let gold = if self.setup.is_gold() {
            Some(Gold::of(&map.map, episode))
        } else {
            None
        };
        let mut block = Map::new();
        let route = self.run(
            map,
            instruction,
            start,
            gold.as_ref(),
            &mut session,
            &mut block,
        );
        block.insert("model".into(), json!(self.setup.label()));
        block.insert("gold_replies".into(), json!(self.setup.is_gold()));
        block.insert("translator".into(), json!(TRANSLATOR));
        block.insert("calls".into(), json!(session.calls));
        let mut notes = vec![];
        if self.setup.is_gold() {
            notes.push(format!(
                "{}: recogniser and translator replies from the gold annotations; the grounding \
                 (embeddings) and the planner run as the method does",
                crate::calls::GOLD_LABEL
            ));
        }
        Ok(prediction(NAME, route, block, notes))
    }
}

impl Lang2Ltl {
    /// The whole pipeline of one instruction; the block receives every step's trace.
    pub fn run(
        &self,
        map: &PreparedMap,
        instruction: &str,
        start: m2rc_stdlib::grid::Cell,
        gold: Option<&Result<Gold, String>>,
        session: &mut Session<'_>,
        block: &mut Map<String, Value>,
    ) -> Result<Vec<m2rc_stdlib::grid::Cell>, Failure> {
        let inventory = Inventory::from_map(&map.map);
        // 1. RER.
        let gold_rer = || -> Result<String, String> {
            let g = gold_of(gold)?;
            Ok(json!({"referring_expressions": gold_expressions(g, instruction)}).to_string())
        };
        let reply = session.chat("rer", prompts::rer(instruction), &gold_rer)?;
        let mut expressions = translate::parse_rer(&reply)
            .map_err(|e| Failure::new("translation_failed", format!("rer: {e}")))?;
        if expressions.is_empty() {
            expressions = translate::categories_in_text(&inventory, instruction);
            block.insert("expressions_from".into(), json!("categories in the text"));
        }
        block.insert("expressions".into(), json!(expressions));
        if expressions.is_empty() {
            return Err(Failure::new(
                "grounding_failed",
                "no referring expression and no map category in the instruction",
            ));
        }
        // 2. REG.
        let descriptions: Vec<String> = inventory.aps.iter().map(translate::description).collect();
        let ap_vectors = session.embed_map_level("ap_embeddings", &descriptions)?;
        let expr_vectors = session.embed("expression_embeddings", &expressions)?;
        let groundings = translate::ground(&inventory, &ap_vectors, &expressions, &expr_vectors);
        block.insert("groundings".into(), json!(groundings));
        // 3. Lifting.
        let (lifted, letters) = translate::lift(instruction, &groundings)
            .map_err(|e| Failure::new("translation_failed", e))?;
        block.insert("lifted".into(), json!(lifted));
        block.insert(
            "letters".into(),
            json!(
                letters
                    .iter()
                    .map(|(l, ap)| (l.clone(), json!(ap)))
                    .collect::<Map<String, Value>>()
            ),
        );
        // 4-5. Translation with repairs, else the sequential-eventual formula.
        let (formula, source) =
            translate_lifted(session, &lifted, &letters, &groundings, gold, block)?;
        block.insert("formula_source".into(), json!(source));
        block.insert("formula".into(), json!(to_prefix(&formula)));
        // Planning.
        let mut atoms: Vec<(String, Vec<m2rc_stdlib::grid::Cell>, [f64; 2])> = vec![];
        for a in formula.atoms() {
            if atoms.iter().any(|(x, _, _)| x == a) {
                continue;
            }
            let ap = inventory.get(a).ok_or_else(|| {
                Failure::new("grounding_failed", format!("`{a}` is not an AP of the map"))
            })?;
            atoms.push((
                a.to_string(),
                label_cells(&map.map, ap, OBJECT_LABEL_RADIUS_CELLS),
                ap.center,
            ));
        }
        let labels = planner::Labels::new(map.map.n(), atoms);
        let mut search = GridSearch::new(&map.map);
        let (route, trace) =
            planner::plan(&mut search, start, &formula, &labels, self.expansion_limit)?;
        block.insert("planner".into(), json!(trace));
        Ok(route)
    }
}

fn gold_of(gold: Option<&Result<Gold, String>>) -> Result<&Gold, String> {
    match gold {
        Some(Ok(g)) => Ok(g),
        Some(Err(e)) => Err(e.clone()),
        None => Err("no gold annotations".into()),
    }
}

/// The gold recogniser reply: the annotated destinations' and avoided places' expressions, in the
/// order they appear in the instruction.
fn gold_expressions(g: &Gold, instruction: &str) -> Vec<String> {
    let lower = instruction.to_lowercase();
    let mut found: Vec<(usize, String)> = g
        .destinations
        .iter()
        .chain(&g.avoids)
        .filter_map(|p| p.expression.clone())
        .map(|e| (lower.find(&e.to_lowercase()).unwrap_or(usize::MAX), e))
        .collect();
    found.sort_by_key(|(p, _)| *p);
    let mut out: Vec<String> = vec![];
    for (_, e) in found {
        if !out.iter().any(|o| o.eq_ignore_ascii_case(&e)) {
            out.push(e);
        }
    }
    out
}

/// Translation of the lifted command (the LLM mode; a local seq2seq translator would answer the
/// same request here), read back onto APs, with up to [`MAX_REPAIRS`] repairs and the
/// sequential-eventual fallback.
pub fn translate_lifted(
    session: &mut Session<'_>,
    lifted: &str,
    letters: &[(String, String)],
    groundings: &[Grounding],
    gold: Option<&Result<Gold, String>>,
    block: &mut Map<String, Value>,
) -> Result<(Formula, String), Failure> {
    let names: Vec<String> = letters.iter().map(|(l, _)| l.clone()).collect();
    // The gold formula in letters: each annotated place takes the letter of the AP its
    // expression was grounded to.
    let gold_formula = || -> Result<String, String> {
        let g = gold_of(gold)?;
        let letter_of = |e: &Option<String>| -> Result<String, String> {
            let e = e.as_deref().ok_or("a place without an expression")?;
            let ap = groundings
                .iter()
                .find(|x| x.expression.eq_ignore_ascii_case(e))
                .map(|x| &x.ap)
                .ok_or_else(|| format!("`{e}` was not among the recognised expressions"))?;
            Ok(letters
                .iter()
                .find(|(_, a)| a == ap)
                .expect("lettered")
                .0
                .clone())
        };
        let dests: Vec<String> = g
            .destinations
            .iter()
            .map(|d| letter_of(&d.expression))
            .collect::<Result<_, _>>()?;
        let avoids: Vec<String> = g
            .avoids
            .iter()
            .map(|d| letter_of(&d.expression))
            .collect::<Result<_, _>>()?;
        Ok(to_prefix(
            &g.sequence_formula(&|i| dests[i].clone(), &|j| avoids[j].clone()),
        ))
    };
    let mut reply = session.chat(
        "translate",
        prompts::translate(&names, lifted),
        &gold_formula,
    )?;
    let mut errors = vec![];
    for round in 0..=MAX_REPAIRS {
        match translate::read_formula(&reply, letters) {
            Ok((lifted_formula, grounded)) => {
                block.insert("formula_lifted".into(), json!(to_prefix(&lifted_formula)));
                block.insert("translation_errors".into(), json!(errors));
                let source = if round == 0 {
                    "translation".to_string()
                } else {
                    format!("repair {round}")
                };
                return Ok((grounded, source));
            }
            Err(e) => {
                errors.push(e.clone());
                if round == MAX_REPAIRS {
                    break;
                }
                reply = session.chat(
                    &format!("repair{}", round + 1),
                    prompts::repair(&names, lifted, reply.lines().last().unwrap_or(""), &e),
                    &gold_formula,
                )?;
            }
        }
    }
    block.insert("translation_errors".into(), json!(errors));
    // The sequential-eventual formula over the grounded APs, in expression order.
    let mut aps: Vec<&str> = vec![];
    for g in groundings {
        if !aps.contains(&g.ap.as_str()) {
            aps.push(&g.ap);
        }
    }
    let mut f: Option<Formula> = None;
    for ap in aps.iter().rev() {
        let atom = Formula::new(Kind::Atom(ap.to_string()));
        let reach = match f.take() {
            Some(rest) => Formula::new(Kind::And(Box::new(atom), Box::new(rest))),
            None => atom,
        };
        f = Some(Formula::new(Kind::Eventually(Box::new(reach))));
    }
    f.map(|f| (f, "sequential fallback".to_string()))
        .ok_or_else(|| Failure::new("translation_failed", "no formula and no grounded AP"))
}
