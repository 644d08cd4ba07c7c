//! Verification of a grounded RouteIR against its map, before planning (codes E06xx).
//!
//! The reference verifier (Grounding2Route §3.3) checks structure that the `.m2r` type system
//! already guarantees (constraint kinds, arity, hardness, roles, argument kinds); what remains
//! is checked here: every reference has cells, stage scopes name real stages, targets can be reached
//! from the start and are not entirely forbidden, the start is not forbidden, spatial scopes meet
//! their constraint's place, and relative preferences compare places of one room (a warning: our
//! cost model does not need it, the reference rejects it). IR read from JSON is checked for
//! structure too (version, grid size, stage indices, unique ids).

use crate::eval::codes;
use crate::eval::{Level, Problem};
use crate::ir::{ConstraintKind, Place, PlaceKind, ROUTE_IR_VERSION, RouteIr, StageScope};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::{MapQuery, Target, TravelField};
use std::collections::BTreeSet;

/// Every finding about `ir` on the map behind `q`; empty when the IR is sound.
pub fn verify(ir: &RouteIr, q: &MapQuery) -> Vec<Problem> {
    let mut out = Vec::new();
    let n = q.map().n();
    let err =
        |code, span: crate::ir::SourceSpan, msg: String| Problem::error(code, span.span(), msg);
    if ir.version != ROUTE_IR_VERSION {
        out.push(Problem::error(
            codes::MALFORMED_IR,
            Default::default(),
            format!("RouteIR version {} is not {ROUTE_IR_VERSION}", ir.version),
        ));
    }
    if ir.grid_size != n {
        out.push(Problem::error(
            codes::MALFORMED_IR,
            Default::default(),
            format!(
                "the RouteIR is for a {0}×{0} grid but map `{1}` is {n}×{n}",
                ir.grid_size,
                q.map().map_id
            ),
        ));
        return out;
    }
    let off_grid = |p: &Place| {
        p.cells
            .cells()
            .iter()
            .any(|c| c.row as usize >= n || c.col as usize >= n)
    };
    if ir.stages.is_empty() {
        out.push(
            Problem::error(
                codes::NO_STAGES,
                Default::default(),
                "the route has no stage on this map",
            )
            .note("a `for` loop over an empty set produces no stage"),
        );
    }
    if !q.is_traversable(ir.start) {
        out.push(Problem::error(
            codes::MALFORMED_IR,
            Default::default(),
            format!(
                "start [{}, {}] is not a free cell",
                ir.start.row, ir.start.col
            ),
        ));
    }
    let from_start = TravelField::reachable(q.traversable(), &[ir.start]);
    let mut ids = BTreeSet::new();
    for c in &ir.constraints {
        if !ids.insert(c.id.as_str()) {
            out.push(err(
                codes::MALFORMED_IR,
                c.span,
                format!("duplicate constraint id `{}`", c.id),
            ));
        }
        if let StageScope::Stages(s) = &c.stage_scope
            && (s.is_empty() || s.iter().any(|&i| i >= ir.stages.len()))
        {
            out.push(err(
                codes::MALFORMED_IR,
                c.span,
                format!("constraint `{}` names a stage that does not exist", c.id),
            ));
        }
        for p in places(&c.kind).into_iter().chain(c.spatial_scope.as_ref()) {
            if off_grid(p) {
                out.push(err(
                    codes::MALFORMED_IR,
                    c.span,
                    format!("{} has cells outside the grid", p.label),
                ));
            } else if p.cells.is_empty() {
                out.push(err(
                    codes::EMPTY_REFERENCE,
                    c.span,
                    format!("{} covers no cell", p.label),
                ));
            }
        }
        if let Some(scope) = &c.spatial_scope {
            match &c.kind {
                ConstraintKind::Avoid { place }
                    if !place.cells.cells().iter().any(|&x| scope.cells.contains(x)) =>
                {
                    out.push(
                        Problem::warning(codes::SCOPE_MISMATCH, c.span.span(), format!("{} lies entirely outside {}", place.label, scope.label))
                            .note("the avoid constraint only counts inside its scope, so it can never matter"),
                    );
                }
                ConstraintKind::Avoid { .. } => {}
                _ if !scope.cells.cells().iter().any(|&x| q.is_traversable(x)) => {
                    out.push(Problem::warning(
                        codes::SCOPE_MISMATCH,
                        c.span.span(),
                        format!(
                            "the scope {} has no free cell, so the preference never applies",
                            scope.label
                        ),
                    ));
                }
                _ => {}
            }
        }
        if let ConstraintKind::Relative { closer, farther } = &c.kind {
            let (a, b) = (
                q.room_of(Target::Cells(closer.cells.cells())),
                q.room_of(Target::Cells(farther.cells.cells())),
            );
            if a != b {
                out.push(
                    Problem::warning(codes::RELATION_ROOMS, c.span.span(), format!("{} and {} are in different rooms", closer.label, farther.label))
                        .note("the Map2Route reference rejects this; m2rc plans it, comparing distances wherever the scope allows"),
                );
            }
        }
    }
    // The start and every stage target / must-pass place against the avoid regions active then.
    for (i, stage) in ir.stages.iter().enumerate() {
        let avoid = |cell: Cell| {
            ir.active(i).any(|c| match &c.kind {
                ConstraintKind::Avoid { place } => {
                    place.cells.contains(cell)
                        && c.spatial_scope
                            .as_ref()
                            .is_none_or(|s| s.cells.contains(cell))
                }
                _ => false,
            })
        };
        if i == 0 && avoid(ir.start) {
            out.push(err(
                codes::START_FORBIDDEN,
                stage.span,
                "the start lies in a region this stage must avoid".into(),
            ));
        }
        let targets = stage
            .passes
            .iter()
            .map(|p| (&p.place, p.span))
            .chain([(&stage.target, stage.span)]);
        for (place, span) in targets {
            if off_grid(place) {
                out.push(err(
                    codes::MALFORMED_IR,
                    span,
                    format!("{} has cells outside the grid", place.label),
                ));
                continue;
            }
            if place.cells.is_empty() {
                out.push(err(
                    codes::EMPTY_REFERENCE,
                    span,
                    format!("{} covers no cell", place.label),
                ));
                continue;
            }
            let mut band = q.band(Target::Cells(place.cells.cells()));
            if band.is_empty() {
                band = object_fallback(place, q).into_iter().collect();
            }
            if band.is_empty() {
                out.push(err(
                    codes::TARGET_UNREACHABLE,
                    span,
                    format!("{} has no free cell in or near it", place.label),
                ));
                continue;
            }
            if !band.iter().any(|&c| from_start.get(c) == Some(&true)) {
                out.push(
                    err(codes::TARGET_UNREACHABLE, span, format!("{} cannot be reached from the start", place.label))
                        .note("no path over free cells joins the start and this place, whatever the constraints"),
                );
                continue;
            }
            if band.iter().all(|&c| avoid(c)) {
                out.push(err(
                    codes::TARGET_FORBIDDEN,
                    span,
                    format!(
                        "every free cell at {} lies in a region this stage must avoid",
                        place.label
                    ),
                ));
            }
        }
    }
    out.sort_by_key(|p| (p.level != Level::Error, p.span.start, p.code));
    out
}

/// The planner's goal for an object with no free cell near it (`MapQuery::room_fallback`, method
/// notes §4.2). Without it, an object on a bed or in a shelf that the reference reaches would be
/// rejected here.
fn object_fallback(place: &Place, q: &MapQuery) -> Option<Cell> {
    let PlaceKind::Object { id, room, .. } = &place.kind else {
        return None;
    };
    let center = q.map().object(*id).map(|o| o.center)?;
    q.room_fallback((*room)?, center)
}

fn places(k: &ConstraintKind) -> Vec<&Place> {
    match k {
        ConstraintKind::Avoid { place } => vec![place],
        ConstraintKind::Near { reference } | ConstraintKind::Far { reference } => vec![reference],
        ConstraintKind::Relative { closer, farther } => vec![closer, farther],
        ConstraintKind::PathShape { waypoints, .. } => waypoints.iter().collect(),
        ConstraintKind::Clearance { .. } => vec![],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::{GroundOptions, ground};
    use m2rc_stdlib::query::fixture::two_rooms;

    fn grounded(src: &str) -> (RouteIr, m2rc_stdlib::map::SemanticMap) {
        let parsed = m2rc_grammar::parse(src);
        let map = two_rooms();
        let q = MapQuery::new(&map);
        let g = ground(&parsed.program, src, &q, &GroundOptions::default());
        (g.ir.expect("grounds"), map)
    }

    #[test]
    fn sound_ir_has_no_findings() {
        let (ir, map) =
            grounded("route { go objects(fridge).only() { prefer near(objects(lamp)) } }");
        assert!(verify(&ir, &MapQuery::new(&map)).is_empty());
    }

    #[test]
    fn forbidden_target_and_start_are_errors() {
        let (ir, map) =
            grounded("route { go objects(fridge).only() { avoid rooms(kitchen).only() } }");
        let v = verify(&ir, &MapQuery::new(&map));
        assert!(
            v.iter().any(|p| p.code == codes::TARGET_FORBIDDEN),
            "{v:#?}"
        );
        let (ir, map) =
            grounded("route { go objects(fridge).only() { avoid rooms(bedroom).only() } }");
        let v = verify(&ir, &MapQuery::new(&map));
        assert!(v.iter().any(|p| p.code == codes::START_FORBIDDEN), "{v:#?}");
    }

    #[test]
    fn unreachable_targets_scope_mismatch_and_structure() {
        let (mut ir, mut map) = grounded(
            "route { go objects(fridge).only() { avoid objects(lamp).only() within rooms(kitchen).only() } }",
        );
        // Close the door: the kitchen becomes unreachable.
        map.occupancy
            .set(Cell::new(8, 9), m2rc_stdlib::map::OBSTACLE);
        ir.constraints.push(ir.constraints[0].clone());
        let v = verify(&ir, &MapQuery::new(&map));
        let codes_found: Vec<&str> = v.iter().map(|p| p.code).collect();
        assert!(codes_found.contains(&codes::TARGET_UNREACHABLE), "{v:#?}");
        assert!(codes_found.contains(&codes::SCOPE_MISMATCH), "{v:#?}");
        assert!(
            codes_found.contains(&codes::MALFORMED_IR),
            "duplicate id: {v:#?}"
        );
    }

    /// An object with no free cell within the band's reach (walled in on a shelf, say) is still a
    /// destination: the planner takes the free cell of its room nearest its centre, as the
    /// reference does, so the verifier must not reject it; a room with no free cell at all is.
    #[test]
    fn walled_in_object_falls_back_to_its_room() {
        let (ir, mut map) = grounded("route { go objects(fridge).only() }");
        use m2rc_stdlib::map::{FREE, OBSTACLE};
        for r in 0..=9 {
            for c in 10..=19 {
                map.occupancy.set(Cell::new(r, c), OBSTACLE);
            }
        }
        map.occupancy.set(Cell::new(15, 9), FREE);
        let v = verify(&ir, &MapQuery::new(&map));
        assert!(v.is_empty(), "{v:#?}");
        for r in 0..20 {
            for c in 10..20 {
                map.occupancy.set(Cell::new(r, c), OBSTACLE);
            }
        }
        let v = verify(&ir, &MapQuery::new(&map));
        assert!(
            v.iter().any(|p| p.code == codes::TARGET_UNREACHABLE),
            "{v:#?}"
        );
    }
}
