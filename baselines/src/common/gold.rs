//! What a gold oracle may read of an episode: its annotated destinations (in order) and
//! must-avoid regions, each with the expression that names it in the instruction (the constraint's
//! label) and the instance it is (an object id, else the room its cells lie in). Each method turns
//! this into replies in its own output format; nothing else of the annotations reaches a method.

use m2rc_benchmark::episode::{ConstraintKind, Episode, HardConstraint};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use serde::Serialize;
use std::collections::BTreeMap;

/// One annotated place.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GoldPlace {
    /// The referring expression (the constraint's label), when annotated.
    pub expression: Option<String>,
    pub object_id: Option<u32>,
    /// The room: the object's, or the room most of the region's cells are in.
    pub room_id: Option<u32>,
    /// The place itself is a room (no object id).
    pub is_room: bool,
    /// 1-based must-pass order (destinations), or the scope's `(from, to)` orders (scoped avoids).
    pub order: Option<i64>,
    pub scope: Option<(i64, i64)>,
}

/// An episode's gold places.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Gold {
    pub destinations: Vec<GoldPlace>,
    pub avoids: Vec<GoldPlace>,
}

impl Gold {
    /// The gold of `episode` on `map`; an error when it has no destination to derive a reply from.
    pub fn of(map: &SemanticMap, episode: &Episode) -> Result<Gold, String> {
        let mut passes: Vec<&HardConstraint> = episode
            .hard_constraints
            .iter()
            .filter(|h| h.kind == ConstraintKind::MustPass && !is_start(h))
            .collect();
        passes.sort_by_key(|h| h.order.unwrap_or(i64::MAX));
        let destinations: Vec<GoldPlace> = passes.iter().map(|h| place(map, h)).collect();
        if destinations.is_empty() {
            return Err(
                "the episode has no annotated destination to build gold replies from".into(),
            );
        }
        let avoids = episode
            .hard_constraints
            .iter()
            .filter(|h| h.kind == ConstraintKind::MustAvoid)
            .map(|h| place(map, h))
            .collect();
        Ok(Gold {
            destinations,
            avoids,
        })
    }
}

fn is_start(h: &HardConstraint) -> bool {
    h.constraint_id.as_deref() == Some("start") || h.label.as_deref() == Some("start")
}

fn place(map: &SemanticMap, h: &HardConstraint) -> GoldPlace {
    let object = h
        .object_id
        .and_then(|id| u32::try_from(id).ok())
        .and_then(|id| map.object(id));
    let room_id = match object {
        Some(o) => o.room,
        None => majority_room(map, h),
    };
    GoldPlace {
        expression: h.label.clone(),
        object_id: object.map(|o| o.id),
        room_id,
        is_room: object.is_none(),
        order: h.order,
        scope: h
            .scope
            .as_ref()
            .filter(|s| s.is_between())
            .and_then(|s| Some((s.from_order?, s.to_order?))),
    }
}

/// The room most of the constraint's cells (or its centre) lie in.
fn majority_room(map: &SemanticMap, h: &HardConstraint) -> Option<u32> {
    let mut votes = BTreeMap::<u32, usize>::new();
    let n = map.n() as i64;
    let cells: Vec<Cell> = h
        .cells
        .iter()
        .flatten()
        .filter(|c| (0..n).contains(&c[0]) && (0..n).contains(&c[1]))
        .map(|c| Cell::new(c[0] as u32, c[1] as u32))
        .collect();
    for c in &cells {
        let r = map.room_at(*c);
        if r != 0 {
            *votes.entry(r).or_default() += 1;
        }
    }
    if votes.is_empty()
        && let Some([r, c]) = h.center
        && r >= 0.0
        && c >= 0.0
    {
        let room = map.room_at(Cell::new(r.round() as u32, c.round() as u32));
        return (room != 0).then_some(room);
    }
    votes
        .into_iter()
        .max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(&a.0)))
        .map(|(r, _)| r)
}

impl Gold {
    /// The hard constraints as one LTLf formula over the names `dest(i)` and `avoid(j)` give the
    /// places: the destinations in order (`F (d1 & F (d2 & ...))`), each leg under its scoped
    /// avoids (`(!c U (d & ...))` instead of `F`), and `G !c` for every global avoid. The
    /// LTL-family oracles write this in their own formats.
    pub fn sequence_formula(
        &self,
        dest: &dyn Fn(usize) -> String,
        avoid: &dyn Fn(usize) -> String,
    ) -> m2rc_compiler::ltl::Formula {
        use crate::common::progress::not;
        let and = |a: Formula, b: Formula| Formula::new(Kind::And(Box::new(a), Box::new(b)));
        use m2rc_compiler::ltl::Formula;
        use m2rc_compiler::ltl::syntax::Kind;
        let atom = |s: String| Formula::new(Kind::Atom(s));
        let mut rest: Option<Formula> = None;
        for (i, d) in self.destinations.iter().enumerate().rev() {
            let reach = match rest.take() {
                Some(r) => and(atom(dest(i)), r),
                None => atom(dest(i)),
            };
            let order = d.order.unwrap_or(i as i64 + 2);
            let active: Vec<Formula> = self
                .avoids
                .iter()
                .enumerate()
                .filter(|(_, a)| {
                    a.scope
                        .is_some_and(|(from, to)| from < order && order <= to)
                })
                .map(|(j, _)| not(atom(avoid(j))))
                .collect();
            rest = Some(if active.is_empty() {
                Formula::new(Kind::Eventually(Box::new(reach)))
            } else {
                let guard = active.into_iter().reduce(and).expect("non-empty");
                Formula::new(Kind::Until(Box::new(guard), Box::new(reach)))
            });
        }
        let mut out = rest.unwrap_or_else(|| Formula::new(Kind::True));
        for (j, a) in self.avoids.iter().enumerate() {
            if a.scope.is_none() {
                let g = Formula::new(Kind::Always(Box::new(not(atom(avoid(j))))));
                out = Formula::new(Kind::And(Box::new(out), Box::new(g)));
            }
        }
        out
    }
}
