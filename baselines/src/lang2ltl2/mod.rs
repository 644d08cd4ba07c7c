//! Lang2LTL-2 (IROS'24) as Map2Route adapted it: one recogniser call (SRER) returns the referring
//! expressions, spatial predicates and a lifted command; expressions are grounded to landmarks of
//! a pseudo-OSM map by embedding similarity (REG, top 10); spatial predicates are checked with the
//! upstream relation geometry in grid cells (SPG, [`spg`]); the lifted command is translated to
//! LTL; the formula (or, without one, the target sequence) is planned by Lang2LTL's AP-MDP. There
//! is no repair call. The fine-tuned T5 translator with type-constrained decoding cannot be
//! fetched here, so the translation is an LLM call with Lang2LTL's translation prompt (the mode
//! both authors describe). Soft preferences are ignored.

pub mod pylit;
pub mod spg;

use crate::calls::embed::cosine;
use crate::calls::{GOLD_LABEL, ModelSetup, Session};
use crate::common::failure::{Failure, prediction};
use crate::common::gold::Gold;
use crate::common::grid::GridSearch;
use crate::common::inventory::{Ap, Inventory};
use crate::common::labels::{OBJECT_LABEL_RADIUS_CELLS, label_cells};
use crate::common::prefix_ltl::to_prefix;
use crate::common::start_cell;
use crate::lang2ltl::{planner, prompts as lt_prompts, translate};
use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::methods::{Method, MethodError, Prediction, PreparedMap, instruction_of};
use m2rc_compiler::lower::Message;
use m2rc_compiler::ltl::Formula;
use m2rc_compiler::ltl::syntax::Kind;
use m2rc_stdlib::grid::Cell;
use serde_json::{Map, Value, json};
use std::sync::Arc;

pub const NAME: &str = "lang2ltl-2";

/// The lifted command's letters, in the order the recogniser assigns them.
pub const LETTERS: [&str; 7] = ["a", "b", "c", "d", "h", "j", "k"];

/// REG candidates kept per expression.
pub const TOP_K: usize = 10;

const SRER_SYSTEM: &str = "\
You analyse navigation commands for a mobile robot. Answer with exactly three lines, each value \
written as a Python literal:
Referring Expressions: a list of the phrases that name places or landmarks, in order
Spatial Predicates: a list of dicts {relation: [target, anchor, ...]} for every spatial relation \
the command states between a target and its anchor(s) (e.g. {'left of': ['the chair', 'the \
table']}); an empty list when there are none
Lifted Command: the command in double quotes with the referring expressions replaced, in order, \
by a, b, c, d, h, j, k (a target described by a relation is replaced as one expression)
Write nothing else.";

fn srer(instruction: &str) -> Vec<Message> {
    vec![
        Message::system(SRER_SYSTEM),
        Message::user(format!("Command: {instruction}")),
    ]
}

/// The recogniser's three lines.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Srer {
    pub expressions: Vec<String>,
    /// `(relation, target, anchors)`.
    pub predicates: Vec<(String, String, Vec<String>)>,
    pub lifted: String,
}

pub fn parse_srer(reply: &str) -> Result<Srer, String> {
    let line = |label: &str| -> Result<&str, String> {
        reply
            .lines()
            .map(str::trim)
            .find_map(|l| {
                let (k, v) = l.split_once(':')?;
                k.trim().eq_ignore_ascii_case(label).then_some(v.trim())
            })
            .ok_or_else(|| format!("the reply has no `{label}:` line"))
    };
    let exprs = pylit::parse(line("Referring Expressions")?)
        .map_err(|e| format!("Referring Expressions: {e}"))?;
    let expressions: Vec<String> = exprs
        .as_array()
        .ok_or("Referring Expressions is not a list")?
        .iter()
        .filter_map(|v| v.as_str().map(|s| s.trim().to_string()))
        .filter(|s| !s.is_empty())
        .take(LETTERS.len())
        .collect();
    let preds = pylit::parse(line("Spatial Predicates")?)
        .map_err(|e| format!("Spatial Predicates: {e}"))?;
    let mut predicates = vec![];
    for p in preds
        .as_array()
        .ok_or("Spatial Predicates is not a list")?
        .iter()
        .take(16)
    {
        for (rel, args) in p.as_object().into_iter().flatten() {
            // A bare string value is one argument (the adaptation normalises it to a list).
            let args: Vec<String> = match args {
                Value::String(s) => vec![s.clone()],
                Value::Array(a) => a
                    .iter()
                    .filter_map(|x| x.as_str().map(str::to_string))
                    .collect(),
                _ => vec![],
            };
            if let Some((t, anchors)) = args.split_first() {
                predicates.push((rel.clone(), t.clone(), anchors.to_vec()));
            }
        }
    }
    let lifted = pylit::parse(line("Lifted Command")?)
        .ok()
        .and_then(|v| v.as_str().map(str::to_string))
        .unwrap_or_else(|| {
            line("Lifted Command")
                .unwrap_or("")
                .trim_matches('"')
                .to_string()
        });
    Ok(Srer {
        expressions,
        predicates,
        lifted,
    })
}

/// A landmark's text as the pseudo-OSM map gives it: the JSON of its semantics entry.
pub fn landmark_text(ap: &Ap) -> String {
    json!({
        "name": ap.name,
        "kind": if ap.is_room() { "room" } else { "object" },
        "category": ap.category,
        "description": if ap.is_room() { format!("a {} room", ap.category_words()) } else { format!("a {}", ap.category_words()) },
        "lat": 0,
        "long": 0,
    })
    .to_string()
}

pub struct Lang2Ltl2 {
    pub setup: Arc<ModelSetup>,
}

pub fn make(setup: Arc<ModelSetup>) -> Box<dyn Method> {
    Box::new(Lang2Ltl2 { setup })
}

impl Method for Lang2Ltl2 {
    fn name(&self) -> &str {
        NAME
    }

    fn config(&self) -> Value {
        json!({
            "method": NAME,
            "m2rc": env!("CARGO_PKG_VERSION"),
            "model": self.setup.config(),
            "translator": "llm",
            "top_k": TOP_K,
            "max_range_cells": spg::MAX_RANGE,
            "planner": "vanilla",
            "expansion_limit": planner::EXPANSION_LIMIT,
            "object_label_radius_cells": OBJECT_LABEL_RADIUS_CELLS,
        })
    }

    fn predict(&self, map: &PreparedMap, episode: &Episode) -> Result<Prediction, MethodError> {
        let instruction = instruction_of(episode)?;
        let start = start_cell(&map.map, episode)?;
        let mut session = Session::new(&self.setup, NAME, &map.map.map_id, episode);
        let gold = self.setup.is_gold().then(|| Gold::of(&map.map, episode));
        let mut block = Map::new();
        let route = run(
            map,
            instruction,
            start,
            gold.as_ref(),
            &mut session,
            &mut block,
        );
        block.insert("model".into(), json!(self.setup.label()));
        block.insert("gold_replies".into(), json!(self.setup.is_gold()));
        block.insert("translator".into(), json!(crate::lang2ltl::TRANSLATOR));
        block.insert("calls".into(), json!(session.calls));
        let notes = if self.setup.is_gold() {
            vec![format!(
                "{GOLD_LABEL}: recogniser and translator replies from the gold annotations; the \
                 gold recogniser states no spatial predicate (the annotations give none in the \
                 format's relations), so grounding is by embeddings alone; REG and the planner \
                 run as the method does"
            )]
        } else {
            vec![]
        };
        Ok(prediction(NAME, route, block, notes))
    }
}

fn gold_of(gold: Option<&Result<Gold, String>>) -> Result<&Gold, String> {
    match gold {
        Some(Ok(g)) => Ok(g),
        Some(Err(e)) => Err(e.clone()),
        None => Err("no gold annotations".into()),
    }
}

/// Lang2LTL-2 on one instruction; the block receives every step's trace.
pub fn run(
    map: &PreparedMap,
    instruction: &str,
    start: Cell,
    gold: Option<&Result<Gold, String>>,
    session: &mut Session<'_>,
    block: &mut Map<String, Value>,
) -> Result<Vec<Cell>, Failure> {
    let inventory = Inventory::from_map(&map.map);
    let gold_exprs = || -> Result<Vec<String>, String> {
        let g = gold_of(gold)?;
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
            if !out.iter().any(|o| o.eq_ignore_ascii_case(&e)) && out.len() < LETTERS.len() {
                out.push(e);
            }
        }
        Ok(out)
    };
    let gold_srer = || -> Result<String, String> {
        let exprs = gold_exprs()?;
        let mut order: Vec<(usize, &String)> = exprs.iter().enumerate().collect();
        order.sort_by_key(|(_, e)| std::cmp::Reverse(e.len()));
        let mut lifted = instruction.to_string();
        for (i, e) in order {
            lifted = translate::replace_ci(&lifted, e, LETTERS[i]);
        }
        Ok(format!(
            "Referring Expressions: {}\nSpatial Predicates: []\nLifted Command: {}",
            json!(exprs),
            json!(lifted)
        ))
    };
    let reply = session.chat("srer", srer(instruction), &gold_srer)?;
    let parsed =
        parse_srer(&reply).map_err(|e| Failure::new("translation_failed", format!("srer: {e}")))?;
    block.insert("srer".into(), json!(parsed));
    // REG over every phrase the recogniser named.
    let mut phrases: Vec<String> = parsed.expressions.clone();
    for (_, t, anchors) in &parsed.predicates {
        for p in std::iter::once(t).chain(anchors) {
            if !phrases.contains(p) {
                phrases.push(p.clone());
            }
        }
    }
    let letters_used: Vec<&str> = LETTERS[..parsed.expressions.len()].to_vec();
    let mut ground_of: Vec<(String, String)> = vec![]; // expression -> AP
    let mut reg_trace = Map::new();
    let mut spg_trace = vec![];
    if !phrases.is_empty() {
        let texts: Vec<String> = inventory.aps.iter().map(landmark_text).collect();
        let lm = session.embed_map_level("landmark_embeddings", &texts)?;
        let qs = session.embed("expression_embeddings", &phrases)?;
        let top: Vec<Vec<(usize, f64)>> = qs
            .iter()
            .map(|q| {
                let mut s: Vec<(usize, f64)> = lm
                    .iter()
                    .enumerate()
                    .map(|(i, v)| (i, cosine(q, v)))
                    .collect();
                s.sort_by(|a, b| {
                    b.1.total_cmp(&a.1)
                        .then(inventory.aps[a.0].name.cmp(&inventory.aps[b.0].name))
                });
                s.truncate(TOP_K);
                s
            })
            .collect();
        for (p, t) in phrases.iter().zip(&top) {
            reg_trace.insert(
                p.clone(),
                json!(
                    t.iter()
                        .map(|(i, s)| (inventory.aps[*i].name.clone(), *s))
                        .collect::<Vec<_>>()
                ),
            );
        }
        let idx = |p: &str| phrases.iter().position(|x| x == p);
        // SPG: the first valid combination, by the product of the scores.
        let mut relation_vectors: Option<Vec<Vec<f32>>> = None;
        let robot = [start.row as f64, start.col as f64];
        for (rel, target, anchors) in &parsed.predicates {
            let canon = match spg::canonical(rel) {
                Some(c) => c.to_string(),
                None => {
                    if relation_vectors.is_none() {
                        let known: Vec<String> =
                            spg::KNOWN_RELATIONS.iter().map(|s| s.to_string()).collect();
                        relation_vectors =
                            Some(session.embed_map_level("known_relation_embeddings", &known)?);
                    }
                    let q = session.embed(
                        &format!("relation_embedding_{}", spg_trace.len()),
                        std::slice::from_ref(rel),
                    )?;
                    let known = relation_vectors.as_ref().expect("embedded");
                    let best = known
                        .iter()
                        .enumerate()
                        .max_by(|a, b| cosine(&q[0], a.1).total_cmp(&cosine(&q[0], b.1)))
                        .map(|(i, _)| spg::KNOWN_RELATIONS[i])
                        .unwrap_or("near");
                    best.to_string()
                }
            };
            let (Some(ti), Some(ais)) = (
                idx(target),
                anchors.iter().map(|a| idx(a)).collect::<Option<Vec<_>>>(),
            ) else {
                continue;
            };
            let mut combos: Vec<(f64, usize, Vec<usize>)> = vec![];
            for &(t, ts) in &top[ti] {
                let mut partial: Vec<(f64, Vec<usize>)> = vec![(ts, vec![])];
                for &ai in &ais {
                    partial = partial
                        .into_iter()
                        .flat_map(|(s, v)| {
                            top[ai]
                                .iter()
                                .map(move |&(a, as_)| (s * as_, [v.clone(), vec![a]].concat()))
                        })
                        .collect();
                }
                combos.extend(partial.into_iter().map(|(s, v)| (s, t, v)));
            }
            combos.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
            let win = combos.iter().find(|(_, t, a)| {
                !a.contains(t)
                    && spg::holds(
                        &canon,
                        inventory.aps[*t].center,
                        &a.iter()
                            .map(|i| inventory.aps[*i].center)
                            .collect::<Vec<_>>(),
                        robot,
                    )
            });
            let chosen = win.map(|(_, t, _)| inventory.aps[*t].name.clone());
            spg_trace.push(json!({"relation": rel, "as": canon, "target": target, "anchors": anchors, "valid": chosen.is_some(), "target_ap": chosen}));
            if let Some(ap) = chosen {
                ground_of.push((target.clone(), ap));
            }
        }
        for (p, t) in phrases.iter().zip(&top) {
            if !ground_of.iter().any(|(e, _)| e == p)
                && let Some((i, _)) = t.first()
            {
                ground_of.push((p.clone(), inventory.aps[*i].name.clone()));
            }
        }
    }
    block.insert("reg".into(), Value::Object(reg_trace));
    block.insert("spg".into(), json!(spg_trace));
    let letter_ap: Vec<(String, String)> = letters_used
        .iter()
        .zip(&parsed.expressions)
        .filter_map(|(l, e)| {
            ground_of
                .iter()
                .find(|(x, _)| x == e)
                .map(|(_, ap)| (l.to_string(), ap.clone()))
        })
        .collect();
    block.insert(
        "letters".into(),
        json!(
            letter_ap
                .iter()
                .map(|(l, a)| (l.clone(), json!(a)))
                .collect::<Map<String, Value>>()
        ),
    );
    // Target sequence: the letters in the order the lifted command names them, outside "start
    // from X" contexts.
    let target_sequence = target_sequence(&parsed.lifted, &letter_ap);
    block.insert("target_sequence".into(), json!(target_sequence));
    // LT (LLM translation; no repair).
    let mut formula: Option<Formula> = None;
    if !letter_ap.is_empty() && !parsed.lifted.trim().is_empty() {
        let names: Vec<String> = letter_ap.iter().map(|(l, _)| l.clone()).collect();
        let gold_lt = || -> Result<String, String> {
            let g = gold_of(gold)?;
            let exprs = gold_exprs()?;
            let letter = |e: &Option<String>| -> Result<String, String> {
                let e = e.as_deref().ok_or("a place without an expression")?;
                exprs
                    .iter()
                    .position(|x| x.eq_ignore_ascii_case(e))
                    .map(|i| LETTERS[i].to_string())
                    .ok_or_else(|| format!("`{e}` has no letter"))
            };
            let d: Vec<String> = g
                .destinations
                .iter()
                .map(|p| letter(&p.expression))
                .collect::<Result<_, _>>()?;
            let a: Vec<String> = g
                .avoids
                .iter()
                .map(|p| letter(&p.expression))
                .collect::<Result<_, _>>()?;
            Ok(to_prefix(
                &g.sequence_formula(&|i| d[i].clone(), &|j| a[j].clone()),
            ))
        };
        let reply = session.chat(
            "translate",
            lt_prompts::translate(&names, &parsed.lifted),
            &gold_lt,
        )?;
        match translate::read_formula(&reply, &letter_ap) {
            Ok((lifted, grounded)) => {
                block.insert("ltl_lifted".into(), json!(to_prefix(&lifted)));
                formula = Some(grounded);
            }
            Err(e) => {
                block.insert("lt_error".into(), json!(e));
            }
        }
    }
    let (formula, source) = match formula {
        Some(f) => (f, "translation"),
        None if !target_sequence.is_empty() => (sequential(&target_sequence), "target sequence"),
        None => {
            // Lang2LTL's heuristic: the first instance of each category named in the text.
            let aps: Vec<String> = translate::categories_in_text(&inventory, instruction)
                .iter()
                .filter_map(|w| {
                    inventory
                        .aps
                        .iter()
                        .find(|a| a.category_words() == *w)
                        .map(|a| a.name.clone())
                })
                .collect();
            if aps.is_empty() {
                return Err(Failure::new(
                    "grounding_failed",
                    "no formula, no target sequence and no category in the text",
                ));
            }
            (sequential(&aps), "category heuristic")
        }
    };
    block.insert("formula_source".into(), json!(source));
    block.insert("formula".into(), json!(to_prefix(&formula)));
    let mut atoms = vec![];
    for a in formula.atoms() {
        if atoms
            .iter()
            .any(|(x, _, _): &(String, Vec<Cell>, [f64; 2])| x == a)
        {
            continue;
        }
        let ap = inventory.get(a).ok_or_else(|| {
            Failure::new(
                "grounding_failed",
                format!("`{a}` is not a landmark of the map"),
            )
        })?;
        atoms.push((
            a.to_string(),
            label_cells(&map.map, ap, OBJECT_LABEL_RADIUS_CELLS),
            ap.center,
        ));
    }
    let labels = planner::Labels::new(map.map.n(), atoms);
    let mut search = GridSearch::new(&map.map);
    let (route, trace) = planner::plan(
        &mut search,
        start,
        &formula,
        &labels,
        planner::EXPANSION_LIMIT,
    )?;
    block.insert("planner".into(), json!(trace));
    Ok(route)
}

fn sequential(aps: &[String]) -> Formula {
    let mut f: Option<Formula> = None;
    for ap in aps.iter().rev() {
        let atom = Formula::new(Kind::Atom(ap.clone()));
        let reach = match f.take() {
            Some(rest) => Formula::new(Kind::And(Box::new(atom), Box::new(rest))),
            None => atom,
        };
        f = Some(Formula::new(Kind::Eventually(Box::new(reach))));
    }
    f.unwrap_or_else(|| Formula::new(Kind::True))
}

/// The grounded letters in the order the lifted command names them, skipping a letter right after
/// "start from" / "starting at" / "from" at the very start.
fn target_sequence(lifted: &str, letters: &[(String, String)]) -> Vec<String> {
    let words: Vec<String> = lifted
        .split(|c: char| !c.is_alphanumeric())
        .filter(|w| !w.is_empty())
        .map(str::to_lowercase)
        .collect();
    let mut out: Vec<String> = vec![];
    for (i, w) in words.iter().enumerate() {
        let Some((_, ap)) = letters.iter().find(|(l, _)| l == w) else {
            continue;
        };
        let before: Vec<&str> = words[i.saturating_sub(2)..i]
            .iter()
            .map(String::as_str)
            .collect();
        if before.ends_with(&["start", "from"])
            || before.ends_with(&["starting", "from"])
            || before.ends_with(&["start", "at"])
            || before.ends_with(&["starting", "at"])
        {
            continue;
        }
        if out.last() != Some(ap) {
            out.push(ap.clone());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srer_replies() {
        let s = parse_srer(
            "Referring Expressions: ['the lamp', 'the bed']\nSpatial Predicates: [{'left of': ['the lamp', 'the bed']}, {'near': 'the bed'}]\nLifted Command: \"go to a, then b\"",
        )
        .unwrap();
        assert_eq!(s.expressions, ["the lamp", "the bed"]);
        assert_eq!(
            s.predicates[0],
            ("left of".into(), "the lamp".into(), vec!["the bed".into()])
        );
        assert_eq!(s.predicates[1], ("near".into(), "the bed".into(), vec![]));
        assert_eq!(s.lifted, "go to a, then b");
        assert!(parse_srer("Referring Expressions: ['x'").is_err());
        assert!(parse_srer("nothing").is_err());
        let letters = vec![
            ("a".into(), "object_1".into()),
            ("b".into(), "room_2".into()),
        ];
        assert_eq!(
            target_sequence("start from b and go to a, then b", &letters),
            ["object_1", "room_2"]
        );
    }
}
