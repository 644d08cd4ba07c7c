//! LIMP (ICRA'25) as Map2Route adapted it (`LIMP-Nav-Prototype`, extended variant): two LLM
//! calls turn the instruction into LTL (stage 1 over nouns, stage 2 with `near[referent]`
//! predicates and composable referent descriptors), with at most one repair; referents are
//! grounded deterministically ([`ground`]); the planner progresses the formula to transition
//! regions ([`planner`]). The model sees no map. Calls sample at temperature 0.2, as the adaptation
//! does. Soft preferences are dropped by the prompts.

pub mod ground;
pub mod parse;
pub mod planner;
pub mod prompts;

use crate::calls::{GOLD_LABEL, ModelSetup, Session};
use crate::common::failure::{Failure, prediction};
use crate::common::gold::{Gold, GoldPlace};
use crate::common::grid::GridSearch;
use crate::common::inventory::{Ap, ApKind, Inventory};
use crate::common::prefix_ltl::{rename_atoms, to_prefix};
use crate::common::start_cell;
use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::methods::{Method, MethodError, Prediction, PreparedMap, instruction_of};
use m2rc_stdlib::grid::Cell;
use parse::Crd;
use serde_json::{Map, Value, json};
use std::sync::Arc;

pub const NAME: &str = "limp";

/// LIMP's sampling temperature.
pub const TEMPERATURE: f64 = 0.2;

/// Candidates ranked by path length in a tie-break (the nearest by straight line first).
pub const TIE_BREAK_CANDIDATES: usize = 24;

pub struct Limp {
    pub setup: Arc<ModelSetup>,
}

pub fn make(setup: Arc<ModelSetup>) -> Box<dyn Method> {
    Box::new(Limp { setup })
}

impl Method for Limp {
    fn name(&self) -> &str {
        NAME
    }

    fn config(&self) -> Value {
        json!({
            "method": NAME,
            "m2rc": env!("CARGO_PKG_VERSION"),
            "model": self.setup.config(),
            "temperature": TEMPERATURE,
            "variant": "extended",
            "near_cells": planner::NEAR_CELLS,
            "avoid_cells": planner::AVOID_CELLS,
            "max_stages": planner::MAX_STAGES,
        })
    }

    fn predict(&self, map: &PreparedMap, episode: &Episode) -> Result<Prediction, MethodError> {
        let instruction = instruction_of(episode)?;
        let start = start_cell(&map.map, episode)?;
        let mut session =
            Session::new(&self.setup, NAME, &map.map.map_id, episode).with_temperature(TEMPERATURE);
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
        block.insert("model".into(), json!(self.setup.chat_label()));
        block.insert("gold_replies".into(), json!(self.setup.is_gold()));
        block.insert("calls".into(), json!(session.calls));
        let notes = if self.setup.is_gold() {
            vec![format!(
                "{GOLD_LABEL}: both stages from the gold annotations, each referent the first \
                 descriptor (noun, isinside, isnextto) LIMP's grounding resolves to the annotated \
                 instance, else the plain noun; grounding and planner run as the method does"
            )]
        } else {
            vec![]
        };
        Ok(prediction(NAME, route, block, notes))
    }
}

/// The last non-empty line of a reply, without a code fence or an `Output:` label.
fn formula_line(reply: &str) -> String {
    let line = reply
        .lines()
        .map(str::trim)
        .rfind(|l| !l.is_empty() && !l.starts_with("```"))
        .unwrap_or("");
    line.strip_prefix("Output:")
        .unwrap_or(line)
        .trim()
        .to_string()
}

/// LIMP on one instruction; the block receives every step's trace.
pub fn run(
    map: &PreparedMap,
    instruction: &str,
    start: Cell,
    gold: Option<&Result<Gold, String>>,
    session: &mut Session<'_>,
    block: &mut Map<String, Value>,
) -> Result<Vec<Cell>, Failure> {
    let inventory = Inventory::from_map(&map.map);
    let mut search = GridSearch::new(&map.map);
    let gold = || -> Result<&Gold, String> {
        match gold {
            Some(Ok(g)) => Ok(g),
            Some(Err(e)) => Err(e.clone()),
            None => Err("no gold annotations".into()),
        }
    };
    let gold_stage1 = || -> Result<String, String> {
        let g = gold()?;
        let noun = |p: &GoldPlace| {
            place_ap(&inventory, p)
                .map(|a| a.category.clone())
                .unwrap_or_else(|| "place".into())
        };
        let f = g.sequence_formula(&|i| noun(&g.destinations[i]), &|j| noun(&g.avoids[j]));
        Ok(f.to_string())
    };
    let stage1 =
        formula_line(&session.chat("stage1", prompts::stage1(instruction), &gold_stage1)?);
    block.insert("stage1_ltl".into(), json!(stage1));
    let gold_stage2 = || -> Result<String, String> {
        let g = gold()?;
        let mut s = GridSearch::new(&map.map);
        let crd_of = |p: &GoldPlace, s: &mut GridSearch<'_>| gold_crd(map, &inventory, p, start, s);
        let dests: Vec<String> = g
            .destinations
            .iter()
            .map(|p| crd_of(p, &mut s))
            .collect::<Result<_, _>>()?;
        let avoids: Vec<String> = g
            .avoids
            .iter()
            .map(|p| crd_of(p, &mut s))
            .collect::<Result<_, _>>()?;
        let f = g.sequence_formula(&|i| format!("q{i}"), &|j| format!("r{j}"));
        let f = rename_atoms(&f, &|a| {
            let k: usize = a[1..].parse().ok()?;
            let crd = if a.starts_with('q') {
                dests.get(k)
            } else {
                avoids.get(k)
            }?;
            Some(format!("near[{crd}]"))
        });
        Ok(f.to_string())
    };
    let reply = session.chat(
        "stage2",
        prompts::stage2(instruction, &stage1),
        &gold_stage2,
    )?;
    let encoded = match parse::parse_stage2(&reply) {
        Ok(e) => e,
        Err(e) => {
            block.insert("stage2_error".into(), json!(e));
            let bad = formula_line(&reply);
            let reply = session.chat(
                "repair",
                prompts::repair(instruction, &stage1, &bad, &e),
                &gold_stage2,
            )?;
            parse::parse_stage2(&reply).map_err(|e| {
                Failure::new(
                    "translation_failed",
                    format!("stage 2 after the repair: {e}"),
                )
            })?
        }
    };
    block.insert("stage2_ltl".into(), json!(encoded.formula.to_string()));
    block.insert(
        "encoding_map".into(),
        json!(
            encoded
                .predicates
                .iter()
                .map(|(a, c)| (a.clone(), json!(c.to_string())))
                .collect::<Map<String, Value>>()
        ),
    );
    // Grounding.
    let negated = planner::negated_atoms(&encoded.formula);
    let mut regions = vec![];
    let mut groundings = Map::new();
    for (atom, crd) in &encoded.predicates {
        let ap = resolve(map, &inventory, crd, start, &mut search)?;
        let cells = match ap.kind {
            ApKind::Room(id) => {
                let n = map.map.n();
                let mut m = vec![false; n * n];
                for c in map.map.room_cells(id) {
                    if search.is_free(c) {
                        m[c.row as usize * n + c.col as usize] = true;
                    }
                }
                m
            }
            ApKind::Object(_) => {
                let r = if negated.contains(atom) {
                    planner::AVOID_CELLS
                } else {
                    planner::NEAR_CELLS
                };
                planner::near_region(&search, &ground::instance_cells(&map.map, ap), r)
            }
        };
        groundings.insert(
            atom.clone(),
            json!({"referent": crd.to_string(), "instance": ap.name, "label": ap.label}),
        );
        regions.push((atom.clone(), cells));
    }
    block.insert("groundings".into(), Value::Object(groundings));
    block.insert("formula".into(), json!(to_prefix(&encoded.formula)));
    let (route, stages) = planner::plan(&mut search, start, &encoded.formula, &regions)?;
    block.insert("planner_segments".into(), json!(stages));
    Ok(route)
}

/// The instance a descriptor grounds to: its candidates, and the extended variant's tie-break
/// when more than one is left.
pub fn resolve<'i>(
    map: &PreparedMap,
    inventory: &'i Inventory,
    crd: &Crd,
    start: Cell,
    search: &mut GridSearch<'_>,
) -> Result<&'i Ap, Failure> {
    let cands = ground::candidates(crd, inventory, &map.map)?;
    match cands.len() {
        0 => Err(Failure::new(
            "grounding_failed",
            format!("no instance matches `{crd}`"),
        )),
        1 => Ok(cands[0]),
        _ => tie_break(map, cands, ground::selector(&crd.noun), start, search),
    }
}

fn tie_break<'i>(
    map: &PreparedMap,
    mut cands: Vec<&'i Ap>,
    selector: Option<&str>,
    start: Cell,
    search: &mut GridSearch<'_>,
) -> Result<&'i Ap, Failure> {
    let straight = |a: &Ap| (a.center[0] - start.row as f64).hypot(a.center[1] - start.col as f64);
    match selector {
        Some("farthest") => {
            return Ok(cands
                .into_iter()
                .max_by(|a, b| straight(a).total_cmp(&straight(b)))
                .expect("non-empty"));
        }
        Some(s @ ("largest" | "smallest")) => {
            let size = |a: &Ap| ground::instance_cells(&map.map, a).len();
            let it = cands.into_iter();
            return Ok(if s == "largest" {
                it.max_by_key(|a| size(a))
            } else {
                it.min_by_key(|a| size(a))
            }
            .expect("non-empty"));
        }
        _ => {}
    }
    cands.sort_by(|a, b| {
        straight(a)
            .total_cmp(&straight(b))
            .then(a.name.cmp(&b.name))
    });
    cands.truncate(TIE_BREAK_CANDIDATES);
    let n = search.n();
    let mut ranked: Vec<(f64, &Ap)> = vec![];
    for a in cands {
        let region: Vec<usize> = match a.kind {
            ApKind::Room(id) => map
                .map
                .room_cells(id)
                .into_iter()
                .filter(|c| search.is_free(*c))
                .map(|c| c.row as usize * n + c.col as usize)
                .collect(),
            ApKind::Object(_) => {
                let m = planner::near_region(
                    search,
                    &ground::instance_cells(&map.map, a),
                    planner::NEAR_CELLS,
                );
                m.iter()
                    .enumerate()
                    .filter(|(_, v)| **v)
                    .map(|(i, _)| i)
                    .collect()
            }
        };
        // One distance field from the start serves every candidate.
        let dist = search.distances_from(start);
        let d = region
            .iter()
            .map(|&i| dist[i])
            .fold(f64::INFINITY, f64::min);
        if d.is_finite() {
            ranked.push((d, a));
        }
    }
    ranked.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.name.cmp(&y.1.name)));
    let pick = match selector {
        Some("second") => 1,
        Some("third") => 2,
        _ => 0,
    };
    ranked
        .get(pick)
        .or(ranked.last())
        .map(|(_, a)| *a)
        .ok_or_else(|| {
            Failure::new(
                "grounding_failed",
                "no candidate is reachable from the start",
            )
        })
}

fn place_ap<'i>(inventory: &'i Inventory, p: &GoldPlace) -> Option<&'i Ap> {
    match (p.object_id, p.room_id) {
        (Some(o), _) => inventory.by_kind(ApKind::Object(o)),
        (None, Some(r)) => inventory.by_kind(ApKind::Room(r)),
        _ => None,
    }
}

/// The gold descriptor of a place: the first of a few LIMP can say (the noun; the noun inside its
/// room's category; the noun next to a nearby object's category; a room containing a category)
/// that LIMP's own grounding resolves to the annotated instance, else the plain noun.
fn gold_crd(
    map: &PreparedMap,
    inventory: &Inventory,
    p: &GoldPlace,
    start: Cell,
    search: &mut GridSearch<'_>,
) -> Result<String, String> {
    let ap =
        place_ap(inventory, p).ok_or("an annotated place that is no room or object of the map")?;
    let noun = ap.category.clone();
    let plain = Crd {
        noun: noun.clone(),
        relation: None,
    };
    let mut options = vec![plain.clone()];
    let rel = |pred: &str, arg: &str| Crd {
        noun: noun.clone(),
        relation: Some((
            pred.into(),
            vec![Crd {
                noun: arg.into(),
                relation: None,
            }],
        )),
    };
    if let (false, Some(rc)) = (ap.is_room(), &ap.room_category) {
        options.push(rel("isinside", rc));
    }
    let mut others: Vec<&Ap> = inventory
        .aps
        .iter()
        .filter(|o| !o.is_room() && o.name != ap.name && o.category != ap.category)
        .filter(|o| {
            if ap.is_room() {
                o.room == ap.room
            } else {
                true
            }
        })
        .collect();
    others.sort_by(|a, b| {
        let d = |o: &Ap| (o.center[0] - ap.center[0]).hypot(o.center[1] - ap.center[1]);
        d(a).total_cmp(&d(b)).then(a.name.cmp(&b.name))
    });
    let mut seen = vec![];
    for o in others {
        if seen.len() >= 6 {
            break;
        }
        if !seen.contains(&o.category) {
            seen.push(o.category.clone());
            options.push(rel(
                if ap.is_room() { "contains" } else { "isnextto" },
                &o.category,
            ));
        }
    }
    for crd in &options {
        if resolve(map, inventory, crd, start, search).is_ok_and(|a| a.name == ap.name) {
            return Ok(crd.to_string());
        }
    }
    Ok(plain.to_string())
}
