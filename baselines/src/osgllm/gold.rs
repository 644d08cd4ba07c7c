//! The gold oracle of `--llm gold`: OSG-LLM's three replies, in its own output format, built
//! from the episode's gold annotations (`common::gold`).
//!
//! * grounding: the goal entities are the annotated destinations in must-pass order; the avoid
//!   entities are the avoided places. OSG-LLM's graph names rooms and objects only, so a
//!   destination region (a doorway, a corner) is given as the room that holds most of its cells,
//!   and an avoided region as the object it surrounds, when it surrounds one (and is left out,
//!   with a note, when it does not: the area between two things).
//! * translation: the goals as a chain of eventualities, a global avoid as `G ! a`, and an avoid
//!   that holds only on some legs as an until over those legs (`U & ! g & ! a & g & ! a rest`),
//!   which the allowed operators can say exactly.
//! * heuristic: no annotation says which rooms a route should prefer; the reply names the goals'
//!   rooms, in order (the note says so).

use super::graph::SceneGraph;
use super::prefix::{alias, to_prefix};
use crate::common::gold::{Gold, GoldPlace};
use m2rc_benchmark::episode::{ConstraintKind, Episode, HardConstraint};
use m2rc_compiler::ltl::Formula;
use m2rc_compiler::ltl::syntax::Kind;
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use serde_json::json;
use std::collections::{BTreeMap, BTreeSet};

/// The gold visits and avoids as node ids.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GoldGrounding {
    /// (node id, its must-pass order), in visiting order.
    pub goals: Vec<(String, usize)>,
    /// (node id, the orders of the visits it holds for; `None` = the whole route).
    pub avoids: Vec<(String, Option<Vec<usize>>)>,
    /// What the reply could not say exactly.
    pub notes: Vec<String>,
}

/// The shared gold annotations ([`Gold`]) as node ids: each destination is its object, else its
/// room (a region is given as the room most of its cells are in: the graph has no node for it);
/// a scoped avoid holds for the destinations whose must-pass order lies in its scope.
///
/// An avoided region is said as what the graph can say of it ([`avoid_nodes`]): never as the
/// whole room it lies in, which would forbid far more than the instruction does (and often the
/// start or a destination).
pub fn from_common(gold: &Gold, map: &SemanticMap, episode: &Episode) -> GoldGrounding {
    let mut out = GoldGrounding::default();
    let id = |p: &GoldPlace| match (p.object_id, p.room_id) {
        (Some(o), _) => Some(format!("object_{o}")),
        (None, Some(r)) => Some(format!("room_{r}")),
        _ => None,
    };
    let name = |p: &GoldPlace| p.expression.clone().unwrap_or_else(|| "?".into());
    for (k, d) in gold.destinations.iter().enumerate() {
        match id(d) {
            Some(x) => out
                .goals
                .push((x, d.order.map_or(k, |o| o.max(0) as usize))),
            None => out.notes.push(format!(
                "destination `{}` left out: it is neither an object nor in a room",
                name(d)
            )),
        }
    }
    // `Gold::of` lists the must-avoid constraints in file order, as here.
    let avoided = episode
        .hard_constraints
        .iter()
        .filter(|h| h.kind == ConstraintKind::MustAvoid);
    for (a, h) in gold.avoids.iter().zip(avoided) {
        let ids = avoid_nodes(map, h);
        if ids.is_empty() {
            out.notes.push(format!(
                "avoid `{}` left out: the scene graph has no room or object for it",
                name(a)
            ));
        }
        let legs = a.scope.map(|(from, to)| {
            out.goals
                .iter()
                .map(|(_, o)| *o)
                .filter(|&o| (o as i64) > from && (o as i64) <= to)
                .collect::<Vec<usize>>()
        });
        for x in ids {
            if !out.avoids.iter().any(|(y, l)| *y == x && *l == legs) {
                out.avoids.push((x, legs.clone()));
            }
        }
    }
    out
}

/// The nodes an avoided region is: its object; else its room when it covers at least half of
/// the room; else the objects at least half of whose footprint lies in it (the object of "keep
/// out of the area around the plant"); else none (the area between two things).
pub fn avoid_nodes(map: &SemanticMap, h: &HardConstraint) -> Vec<String> {
    if let Some(o) = h
        .object_id
        .and_then(|i| u32::try_from(i).ok())
        .and_then(|i| map.object(i))
    {
        return vec![format!("object_{}", o.id)];
    }
    let n = map.n() as i64;
    let cells: BTreeSet<Cell> = h
        .cells
        .iter()
        .flatten()
        .filter(|c| (0..n).contains(&c[0]) && (0..n).contains(&c[1]))
        .map(|c| Cell::new(c[0] as u32, c[1] as u32))
        .collect();
    let mut per_room: BTreeMap<u32, usize> = BTreeMap::new();
    for c in &cells {
        *per_room.entry(map.room_at(*c)).or_default() += 1;
    }
    for (&room, &k) in &per_room {
        let size = map.room_cells(room).len();
        if room != 0 && size > 0 && 2 * k >= size {
            return vec![format!("room_{room}")];
        }
    }
    map.objects
        .iter()
        .filter(|o| {
            !o.footprint.is_empty()
                && 2 * o.footprint.iter().filter(|c| cells.contains(c)).count() >= o.footprint.len()
        })
        .map(|o| format!("object_{}", o.id))
        .collect()
}

/// The three gold replies (grounding, translation, heuristic), as reply texts.
pub fn gold_replies(gold: &GoldGrounding, graph: &SceneGraph) -> [String; 3] {
    let goals: Vec<&String> = gold.goals.iter().map(|(g, _)| g).collect();
    let mut avoid_ids: Vec<&String> = Vec::new();
    for (a, _) in &gold.avoids {
        if !avoid_ids.contains(&a) {
            avoid_ids.push(a);
        }
    }
    let grounding = json!({
        "ordered_goal_entities": goals,
        "avoid_entities": avoid_ids,
        "entity_bindings": [],
        "unsupported_phrases": [],
    });
    let ap = |id: &String| graph.node(id).map(|n| n.ap.clone()).unwrap_or_default();
    let goal_aps: Vec<String> = goals.iter().map(|g| ap(g)).collect();
    let avoid_aps: Vec<String> = avoid_ids.iter().map(|a| ap(a)).collect();
    let allowed = super::allowed_aps(&goal_aps, &avoid_aps);
    let formula = gold_formula(gold, &allowed, &ap);
    let translation = json!({"ltl_prefix": to_prefix(&formula, &allowed), "notes": "gold"});
    let mut rooms: Vec<String> = Vec::new();
    for g in &goals {
        if let Some(r) = graph.node(g).and_then(|n| n.room) {
            let id = format!("room_{r}");
            if !rooms.contains(&id) {
                rooms.push(id);
            }
        }
    }
    let heuristic = json!({"preferred_nodes": rooms, "reason": "gold: the goals' rooms"});
    [
        grounding.to_string(),
        translation.to_string(),
        heuristic.to_string(),
    ]
}

fn gold_formula(
    gold: &GoldGrounding,
    allowed: &[String],
    ap: &dyn Fn(&String) -> String,
) -> Formula {
    let atom = |id: &String| {
        let name = ap(id);
        Formula::atom(&alias(
            allowed
                .iter()
                .position(|x| *x == name)
                .unwrap_or(usize::MAX),
        ))
    };
    visits_formula(gold, &atom)
}

/// The gold visits as a chain of eventualities, each leg's avoids as an until over that leg, and
/// the global avoids as `G ! a`; `atom` names a node id's proposition.
pub fn visits_formula(gold: &GoldGrounding, atom: &dyn Fn(&String) -> Formula) -> Formula {
    let not = |f: Formula| Formula::negation(f);
    let b = Box::new;
    let mut rest: Option<Formula> = None;
    for (id, stage) in gold.goals.iter().rev() {
        let scoped: Vec<Formula> = gold
            .avoids
            .iter()
            .filter(|(_, s)| s.as_ref().is_some_and(|s| s.contains(stage)))
            .map(|(a, _)| not(atom(a)))
            .collect();
        let here = match rest.take() {
            Some(r) => Formula::and_all(vec![atom(id), r]),
            None => atom(id),
        };
        rest = Some(if scoped.is_empty() {
            Formula::new(Kind::Eventually(b(here)))
        } else {
            let mut left = vec![not(atom(id))];
            left.extend(scoped.iter().cloned());
            let mut right = vec![here];
            right.extend(scoped);
            Formula::new(Kind::Until(
                b(Formula::and_all(left)),
                b(Formula::and_all(right)),
            ))
        });
    }
    let mut parts: Vec<Formula> = rest.into_iter().collect();
    for (a, s) in &gold.avoids {
        if s.is_none() {
            parts.push(Formula::new(Kind::Always(b(not(atom(a))))));
        }
    }
    Formula::and_all(parts)
}
