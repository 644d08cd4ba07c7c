//! `go S` on a set ("proceed to a box"): one search with every member's goal, on a map where the
//! box nearest in a straight line is the far one by route, so a member chosen before planning by
//! distance would be the wrong one; and a stage whose `pass` makes the other box the cheaper one,
//! so the choice follows the stage's constraints, not the stage's start.

use crate::fixture::{cells, object};
use m2rc_compiler::check::check;
use m2rc_compiler::eval::{Chosen, GroundOptions, ground_checked};
use m2rc_compiler::ir::{BoundAgainst, PlaceKind, RouteIr};
use m2rc_planner::choice::reached_members;
use m2rc_planner::lower::lower;
use m2rc_planner::{CostProfile, PlannedRoute, PlannerKind, plan};
use m2rc_stdlib::grid::{Cell, Grid};
use m2rc_stdlib::map::{FREE, GridFrame, OBSTACLE, Room, SemanticMap};
use m2rc_stdlib::query::MapQuery;
use m2rc_stdlib::vocab::Vocabulary;

const N: usize = 40;
const START: Cell = Cell { row: 3, col: 15 };
/// Box #1, across the wall from the start: 12 cells away in a straight line, about 70 by route.
const NEAR_BY_DISTANCE: u32 = 1;
/// Box #2, down the start's own room: 26 cells away in a straight line, about 20 by route.
const NEAR_BY_ROUTE: u32 = 2;

/// Room 1 (columns 0..20) and room 2 (columns 21..40), a wall in column 20 open only in rows
/// 34..40. Box #1 in room 2 by the wall's top, box #2 at the bottom of room 1, a lamp by room 2's
/// far wall.
fn map() -> SemanticMap {
    let mut occ = Grid::new(N, FREE);
    let mut rooms = Grid::new(N, 0u32);
    let mut objects = Grid::new(N, 0u32);
    for r in 0..N as u32 {
        for c in 0..N as u32 {
            let cell = Cell::new(r, c);
            rooms.set(cell, if c < 20 { 1 } else { 2 });
            if c == 20 && r < 34 {
                occ.set(cell, OBSTACLE);
                rooms.set(cell, 0);
            }
        }
    }
    let near_by_distance = object(NEAR_BY_DISTANCE, "box", cells(2..4, 27..29), 2);
    let near_by_route = object(NEAR_BY_ROUTE, "box", cells(28..30, 3..5), 1);
    let lamp = object(3, "floor_lamp", cells(12..14, 36..38), 2);
    for o in [&near_by_distance, &near_by_route, &lamp] {
        for c in &o.footprint {
            occ.set(*c, OBSTACLE);
            objects.set(*c, o.id);
        }
    }
    let room = |id: u32, category: &str| Room {
        id,
        category: category.into(),
        name: format!("{category} {id}"),
        area_m2: 2.0,
        attributes: vec![],
    };
    SemanticMap {
        map_id: "box_behind_wall".into(),
        frame: GridFrame {
            resolution: 0.05,
            x_min: 0.0,
            z_min: 0.0,
        },
        occupancy: occ,
        room_layer: rooms,
        object_layer: objects,
        rooms: vec![room(1, "living_room"), room(2, "bedroom")],
        objects: vec![near_by_distance, near_by_route, lamp],
        start: Some(START),
        open_boundaries: Vec::new(),
    }
}

fn ground(map: &SemanticMap, src: &str, chosen: Vec<Chosen>) -> RouteIr {
    let checked = check(src, &Vocabulary::from_map(map));
    assert!(!checked.has_errors(), "{:#?}", checked.diagnostics);
    let g = ground_checked(
        &checked,
        src,
        &MapQuery::new(map),
        &GroundOptions {
            chosen,
            ..Default::default()
        },
    );
    assert!(
        !g.problems.iter().any(|p| p.is_error()),
        "{:#?}",
        g.problems
    );
    g.ir.expect("grounds")
}

fn box_id(ir: &RouteIr, member: usize) -> u32 {
    let PlaceKind::AnyOf { members } = &ir.stages[0].target.kind else {
        panic!(
            "the stage's goal is not a set: {:?}",
            ir.stages[0].target.kind
        );
    };
    match members[member].kind {
        PlaceKind::Object { id, .. } => id,
        ref k => panic!("member {member} is not an object: {k:?}"),
    }
}

fn planned(map: &SemanticMap, ir: &RouteIr, kind: PlannerKind) -> (PlannedRoute, Vec<Chosen>) {
    let profile = match kind {
        PlannerKind::Shortest => CostProfile::shortest(),
        _ => CostProfile::reference(),
    };
    let p = lower(ir, map, profile).expect("lowers");
    let r = plan(&p, kind);
    assert!(r.is_success(), "{kind:?}: {:?}", r.failure);
    let chosen = reached_members(&p, &r);
    (r, chosen)
}

#[test]
fn the_member_nearest_by_route_is_reached_not_the_nearest_by_distance() {
    let map = map();
    let src = "route { go objects(box) }";
    let ir = ground(&map, src, vec![]);
    // The fixture is what it claims: box #1 is the nearer in a straight line.
    let q = MapQuery::new(&map);
    let start = [START.row as f64, START.col as f64];
    let dist = |id: u32| {
        let o = map.object(id).unwrap();
        (o.center[0] - start[0]).hypot(o.center[1] - start[1])
    };
    assert!(dist(NEAR_BY_DISTANCE) < dist(NEAR_BY_ROUTE) / 2.0);
    assert!(q.is_traversable(START));
    assert_eq!(ir.stages.len(), 1);
    for kind in [
        PlannerKind::Sequential,
        PlannerKind::Global,
        PlannerKind::Shortest,
        PlannerKind::Ltl,
    ] {
        let (route, chosen) = planned(&map, &ir, kind);
        assert_eq!(chosen.len(), 1, "{kind:?}");
        assert_eq!((chosen[0].stage, chosen[0].pass), (0, None));
        assert_eq!(box_id(&ir, chosen[0].member), NEAR_BY_ROUTE, "{kind:?}");
        // The route stays in room 1: it never went round the wall towards box #1.
        assert!(route.trajectory.iter().all(|c| c.col < 20), "{kind:?}");
        assert!(route.length_m < 1.5, "{kind:?}: {} m", route.length_m);
    }
}

#[test]
fn a_pass_in_the_stage_makes_the_other_member_the_cheaper_one() {
    let map = map();
    let src = "route { go objects(box) { pass objects(floor_lamp).only() } }";
    let nominal = ground(&map, src, vec![]);
    // Before planning the stage stands for the member nearest by travel from its start ...
    let b = &nominal.route_bindings[0];
    assert_eq!(
        (b.function.as_str(), b.against),
        ("go", BoundAgainst::Nominal)
    );
    assert!(b.resolved.starts_with("box #2"), "{}", b.resolved);
    // ... but the route passes the lamp first, from where box #1 is the nearer.
    let (_, chosen) = planned(&map, &nominal, PlannerKind::Sequential);
    assert_eq!(chosen.len(), 1);
    assert_eq!(box_id(&nominal, chosen[0].member), NEAR_BY_DISTANCE);
    // Grounded again with the route's choice, the binding says what the route did.
    let bound = ground(&map, src, chosen);
    let b = &bound.route_bindings[0];
    assert_eq!(b.against, BoundAgainst::Planned);
    assert!(b.resolved.starts_with("box #1"), "{}", b.resolved);
    assert_eq!(bound.stages, nominal.stages);
}

#[test]
fn pass_on_a_set_passes_any_one_member() {
    let map = map();
    let src = "route { go objects(floor_lamp).only() { pass objects(box) } }";
    let ir = ground(&map, src, vec![]);
    assert_eq!(ir.stages[0].passes.len(), 1);
    let (_, chosen) = planned(&map, &ir, PlannerKind::Sequential);
    assert_eq!(chosen.len(), 1);
    assert_eq!((chosen[0].stage, chosen[0].pass), (0, Some(0)));
    let PlaceKind::AnyOf { members } = &ir.stages[0].passes[0].place.kind else {
        panic!("pass is not a set");
    };
    // On the way to the lamp the route passes the box in its own room's way, box #2.
    assert!(members[chosen[0].member].label.starts_with("box #2"));
}

#[test]
fn an_empty_set_is_an_error_at_its_span() {
    let map = map();
    let src = "route { go objects(floor_lamp).in(rooms(living_room).only()) }";
    let checked = check(src, &Vocabulary::from_map(&map));
    assert!(!checked.has_errors(), "{:#?}", checked.diagnostics);
    let g = ground_checked(
        &checked,
        src,
        &MapQuery::new(&map),
        &GroundOptions::default(),
    );
    assert!(g.ir.is_none());
    let e = g.problems.iter().find(|p| p.is_error()).expect("an error");
    let d = e.clone().into_diagnostic();
    assert_eq!(d.code.id(), "E0602");
    assert_eq!(
        &src[d.span.start..d.span.end],
        "objects(floor_lamp).in(rooms(living_room).only())"
    );
    assert!(d.message.contains("the set is empty"), "{}", d.message);
}
