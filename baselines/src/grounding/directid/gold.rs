//! Gold ids: the episode's gold RouteIR (its gold program, compiled) written as the Direct ID
//! reply that names the same places. It is the representation's ceiling: what a model that
//! picked every id right would get. Places the catalog cannot name (a doorway, a corner, the
//! area between two things, a patrol's exit) have no ids; they are listed in `lossy` and left
//! out (a destination among them is replaced by the room it lies in), never made up.

use super::build::catalog_ref;
use super::places::Ref;
use m2rc_compiler::eval::PlaceVal;
use m2rc_compiler::ir::{ConstraintKind, Direction, Place, PlaceKind, RouteIr, Shape, StageScope};
use m2rc_stdlib::query::{MapQuery, Target};
use serde_json::{Value, json};
use std::collections::BTreeMap;

/// A gold reply and what it could not say.
#[derive(Clone, Debug, PartialEq)]
pub struct GoldIds {
    pub reply: Value,
    /// One line per place or constraint the catalog cannot name.
    pub lossy: Vec<String>,
}

/// Catalog ids by the label the compiler gives their place (for the members of a union).
fn label_index(q: &MapQuery) -> BTreeMap<String, Ref> {
    let map = q.map();
    let mut out = BTreeMap::new();
    for r in &map.rooms {
        out.insert(PlaceVal::Room(r.id).label(q), Ref::Room(r.id));
    }
    for o in &map.objects {
        out.insert(PlaceVal::Object(o.id).label(q), Ref::Object(o.id));
    }
    out
}

/// The ids of a place, and the `within_m` of an `area_near` halo around them.
fn place_ids(p: &Place, index: &BTreeMap<String, Ref>) -> Option<(Vec<Ref>, Option<f64>)> {
    if let Some(r) = catalog_ref(p) {
        return Some((vec![r], None));
    }
    let PlaceKind::Region { construction } = &p.kind else {
        return None;
    };
    let members = |labels: &[String]| -> Option<Vec<Ref>> {
        labels.iter().map(|l| index.get(l).copied()).collect()
    };
    match construction.kind.as_str() {
        "union" => {
            // A union of halos is written with the halo's radius once.
            if let Some(refs) = members(&construction.from) {
                return Some((refs, None));
            }
            None
        }
        "area_near" => Some((members(&construction.from)?, construction.radius_m)),
        _ => None,
    }
}

fn ids(refs: &[Ref]) -> Value {
    json!(refs.iter().map(|r| r.id()).collect::<Vec<_>>())
}

/// The gold reply for `ir` on `q`'s map.
pub fn gold_ids(ir: &RouteIr, q: &MapQuery) -> GoldIds {
    let index = label_index(q);
    let mut lossy = Vec::new();
    let mut segments = Vec::new();
    let mut constraints = Vec::new();
    for (i, s) in ir.stages.iter().enumerate() {
        let target = match catalog_ref(&s.target) {
            Some(r) => r,
            _ => {
                let room = q.room_of(Target::Cells(s.target.cells.cells()));
                lossy.push(format!(
                    "destination `{}` has no catalog id{}",
                    s.target.label,
                    if room.is_some() {
                        "; its room is named instead"
                    } else {
                        ""
                    }
                ));
                match room {
                    Some(r) => Ref::Room(r),
                    None => continue,
                }
            }
        };
        segments.push(json!({"id": s.name, "target_id": target.id()}));
        for p in &s.passes {
            match catalog_ref(&p.place).filter(|r| *r != Ref::Start) {
                Some(r) => constraints.push(json!({
                    "kind": "require_visit",
                    "ref_ids": [r.id()],
                    "segment_ids": [ir.stages[i].name],
                })),
                None => lossy.push(format!("must-pass `{}` has no catalog id", p.place.label)),
            }
        }
    }
    for c in &ir.constraints {
        match constraint(c, &index) {
            Some(mut v) => {
                if let StageScope::Stages(s) = &c.stage_scope {
                    v["segment_ids"] = json!(
                        s.iter()
                            .filter_map(|&i| ir.stages.get(i))
                            .map(|s| s.name.clone())
                            .collect::<Vec<_>>()
                    );
                }
                if let Some(scope) = &c.spatial_scope {
                    match place_ids(scope, &index) {
                        Some((refs, None)) => v["spatial_scope_ids"] = ids(&refs),
                        _ => {
                            lossy.push(format!(
                                "scope `{}` of {} has no catalog id; dropped",
                                scope.label, c.id
                            ));
                        }
                    }
                }
                constraints.push(v);
            }
            None => lossy.push(format!(
                "{} ({}) names a place the catalog cannot; dropped",
                c.id,
                kind_name(&c.kind)
            )),
        }
    }
    GoldIds {
        reply: json!({"segments": segments, "constraints": constraints}),
        lossy,
    }
}

fn kind_name(k: &ConstraintKind) -> &'static str {
    match k {
        ConstraintKind::Avoid { .. } => "forbid",
        ConstraintKind::Near { .. } => "prefer_near",
        ConstraintKind::Far { .. } => "prefer_far",
        ConstraintKind::Relative { .. } => "prefer_relative",
        ConstraintKind::PathShape { .. } => "prefer_path_shape",
        ConstraintKind::Clearance { .. } => "clearance",
    }
}

fn with_within(kind: &str, (refs, within): (Vec<Ref>, Option<f64>)) -> Option<Value> {
    // The catalog has one id per near/far reference (the reference's arity).
    if matches!(kind, "prefer_near" | "prefer_far") && refs.len() != 1 {
        return None;
    }
    if refs.contains(&Ref::Start) && kind == "forbid" {
        return None;
    }
    let mut v = json!({"kind": kind, "ref_ids": ids(&refs)});
    if let Some(w) = within {
        v["within_m"] = json!(w);
    }
    Some(v)
}

fn constraint(c: &m2rc_compiler::ir::Constraint, index: &BTreeMap<String, Ref>) -> Option<Value> {
    match &c.kind {
        ConstraintKind::Avoid { place } => with_within("forbid", place_ids(place, index)?),
        ConstraintKind::Near { reference } => {
            with_within("prefer_near", place_ids(reference, index)?)
        }
        ConstraintKind::Far { reference } => {
            with_within("prefer_far", place_ids(reference, index)?)
        }
        ConstraintKind::Relative { closer, farther } => {
            let a = catalog_ref(closer).filter(|r| *r != Ref::Start)?;
            let b = catalog_ref(farther).filter(|r| *r != Ref::Start)?;
            Some(
                json!({"kind": "prefer_relative", "ref_ids": [a.id(), b.id()], "relation": "closer_to"}),
            )
        }
        ConstraintKind::PathShape {
            shape,
            direction,
            around,
            ..
        } => {
            let (t, refs) = match shape {
                Shape::Circle => (
                    "circle",
                    vec![catalog_ref(around).filter(|r| *r != Ref::Start)?],
                ),
                Shape::FollowWall => (
                    "follow_wall",
                    vec![catalog_ref(around).filter(|r| matches!(r, Ref::Room(_)))?],
                ),
                Shape::Through => {
                    let (refs, w) = place_ids(around, index)?;
                    if w.is_some() || refs.contains(&Ref::Start) || !(2..=4).contains(&refs.len()) {
                        return None;
                    }
                    ("through", refs)
                }
                Shape::Patrol => return None,
            };
            let mut ps = json!({"type": t});
            if let Some(d) = direction.filter(|_| *shape != Shape::Through) {
                ps["direction"] = json!(match d {
                    Direction::Clockwise => "clockwise",
                    Direction::Counterclockwise => "counterclockwise",
                });
            }
            Some(json!({"kind": "prefer_path_shape", "ref_ids": ids(&refs), "path_shape": ps}))
        }
        ConstraintKind::Clearance { .. } => None,
    }
}

/// Whether two RouteIRs ask for the same route: stages, must-pass places and constraints, not
/// where in a source they came from.
pub fn same_route(a: &RouteIr, b: &RouteIr) -> bool {
    let stages = |ir: &RouteIr| -> Vec<_> {
        ir.stages
            .iter()
            .map(|s| {
                let passes: Vec<_> = s.passes.iter().map(|p| p.place.clone()).collect();
                (s.name.clone(), s.target.clone(), passes)
            })
            .collect()
    };
    let constraints = |ir: &RouteIr| -> Vec<_> {
        ir.constraints
            .iter()
            .map(|c| {
                (
                    c.kind.clone(),
                    c.stage_scope.clone(),
                    c.spatial_scope.clone(),
                )
            })
            .collect()
    };
    a.start == b.start && stages(a) == stages(b) && constraints(a) == constraints(b)
}
