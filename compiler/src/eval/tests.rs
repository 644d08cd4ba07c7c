//! Grounding tests on the hand-built two-room map (`m2rc_stdlib::query::fixture`).

use super::*;
use crate::ir::{ConstraintKind, PlaceKind, StageScope};
use m2rc_stdlib::query::fixture::two_rooms;

fn run(src: &str) -> Grounded {
    run_with(src, None)
}

fn run_with(src: &str, route: Option<Vec<Cell>>) -> Grounded {
    let parsed = m2rc_grammar::parse(src);
    assert!(parsed.is_ok(), "{:?}", parsed.errors);
    let map = two_rooms();
    let q = MapQuery::new(&map);
    ground(
        &parsed.program,
        src,
        &q,
        &GroundOptions {
            start: None,
            route,
            ..Default::default()
        },
    )
}

fn ir(src: &str) -> RouteIr {
    let g = run(src);
    assert!(
        g.problems.iter().all(|p| !p.is_error()),
        "{:#?}",
        g.problems
    );
    g.ir.expect("ir")
}

#[test]
fn grounds_stages_and_scoped_constraints() {
    let ir = ir("let bed = objects(bed).only()\n\
         route {\n\
           go bed as first { prefer near(objects(lamp)) within rooms(bedroom).only() }\n\
           go objects(fridge).nearest() as second\n\
           avoid objects(rug).only() during first\n\
           prefer clearance(30cm)\n\
         }");
    assert_eq!(ir.stages.len(), 2);
    assert_eq!(ir.stages[0].name, "first");
    assert!(matches!(
        ir.stages[0].target.kind,
        PlaceKind::Object { id: 1, .. }
    ));
    assert!(matches!(
        ir.stages[1].target.kind,
        PlaceKind::Object { id: 8, .. }
    ));
    assert_eq!(ir.constraints.len(), 3);
    let near = &ir.constraints[0];
    assert!(
        matches!(&near.kind, ConstraintKind::Near { reference } if reference.label.starts_with("lamp #2"))
    );
    assert_eq!(near.stage_scope, StageScope::Stages(vec![0]));
    assert!(
        matches!(&near.spatial_scope, Some(p) if matches!(p.kind, PlaceKind::Room { id: 1, .. }))
    );
    assert_eq!(ir.constraints[1].stage_scope, StageScope::Stages(vec![0]));
    assert!(
        matches!(ir.constraints[2].kind, ConstraintKind::Clearance { distance_m } if (distance_m - 0.3).abs() < 1e-12)
    );
    assert_eq!(ir.constraints[2].stage_scope, StageScope::Global);
    assert_eq!(ir.start, Cell::new(18, 2));
    let line = ir.stages[1].span.line;
    assert_eq!(line, 4);
}

#[test]
fn ambiguous_and_empty_selections_are_all_reported_with_candidates() {
    let src = "let a = objects().in(rooms(kitchen).only()).only()\n\
               let b = objects(toilet).only()\n\
               route { go a }";
    let g = run(src);
    assert!(g.ir.is_none());
    let errs: Vec<&Problem> = g.problems.iter().filter(|p| p.is_error()).collect();
    assert_eq!(errs.len(), 2, "{errs:#?}");
    let amb = errs
        .iter()
        .find(|p| p.code == codes::AMBIGUOUS_SELECTION)
        .unwrap();
    assert_eq!(
        &src[amb.span.start..amb.span.end],
        "objects().in(rooms(kitchen).only()).only()"
    );
    assert_eq!(amb.notes.len(), 3, "fridge, table, cup: {:?}", amb.notes);
    assert!(
        amb.notes
            .iter()
            .any(|n| n.contains("object 8 `fridge` in kitchen_2") && n.contains(" m from"))
    );
    let empty = errs
        .iter()
        .find(|p| p.code == codes::EMPTY_SELECTION)
        .unwrap();
    assert!(
        empty.notes.iter().any(|n| n.contains("no `toilet`")),
        "{:?}",
        empty.notes
    );
}

#[test]
fn rankings_filters_and_lambdas() {
    // Nearest to the start by travel: the chair (rows 10-11) beats the bed.
    let ir1 = ir("route { go objects(bed | chair).nearest(by: travel) }");
    assert!(matches!(
        ir1.stages[0].target.kind,
        PlaceKind::Object { id: 5, .. }
    ));
    let ir2 = ir("route { go objects().where(o => o.on(objects(bed))).only() }");
    assert!(
        matches!(ir2.stages[0].target.kind, PlaceKind::Object { id: 3, .. }),
        "the book"
    );
    let ir3 = ir("route { go rooms().max_by(r => objects().in(r).count()) }");
    assert!(
        matches!(ir3.stages[0].target.kind, PlaceKind::Room { id: 1, .. }),
        "7 objects in the bedroom"
    );
    let ir4 = ir("route { go objects().between(objects(bed), objects(chair)).only() }");
    assert!(
        matches!(ir4.stages[0].target.kind, PlaceKind::Object { id: 6, .. }),
        "the rug"
    );
    let ir5 = ir("route { go rooms().where(r => r.area() > 1.9).only() }");
    assert!(matches!(
        ir5.stages[0].target.kind,
        PlaceKind::Room { id: 2, .. }
    ));
    let g = run("route { go objects(bed).kth_nearest(3) }");
    assert!(
        g.problems
            .iter()
            .any(|p| p.code == codes::ORDINAL_OUT_OF_RANGE)
    );
}

#[test]
fn route_dependent_places_bind_nominally_then_to_the_planned_route() {
    let src = "let k = rooms(kitchen).only()\n\
               route { go objects(fridge).only() { prefer near(doorway_entering(k)) within room_before_entering(k) } }";
    let ir = ir(src);
    let c = &ir.constraints[0];
    assert!(matches!(&c.spatial_scope, Some(p) if matches!(p.kind, PlaceKind::Room { id: 1, .. })));
    let ConstraintKind::Near { reference } = &c.kind else {
        panic!()
    };
    assert!(reference.cells.contains(Cell::new(8, 9)));
    assert_eq!(ir.route_bindings.len(), 2);
    assert!(
        ir.route_bindings
            .iter()
            .all(|b| b.against == crate::ir::BoundAgainst::Nominal)
    );
    // A planned route that starts in the kitchen never enters it: a runtime error at the call.
    let route = vec![Cell::new(5, 12), Cell::new(5, 13)];
    let g = run_with(src, Some(route));
    let p = g
        .problems
        .iter()
        .find(|p| p.code == codes::ROUTE_PLACE_UNDEFINED)
        .expect("undefined");
    assert!(
        src[p.span.start..p.span.end].starts_with("doorway_entering")
            || src[p.span.start..p.span.end].starts_with("room_before")
    );
}

#[test]
fn for_loops_expand_stages_and_during_scopes() {
    let ir = ir("route {\n\
           for r in rooms().sorted_by(r => r.area()) { go r as visit }\n\
           prefer far(objects(lamp)) during visit\n\
           prefer circle(objects(dining_table).only(), clockwise)\n\
         }");
    assert_eq!(ir.stages.len(), 2);
    assert!(
        matches!(ir.stages[0].target.kind, PlaceKind::Room { id: 1, .. }),
        "smaller first"
    );
    assert_eq!(
        ir.constraints[0].stage_scope,
        StageScope::Stages(vec![0, 1])
    );
    let ConstraintKind::PathShape { waypoints, .. } = &ir.constraints[1].kind else {
        panic!()
    };
    assert!(waypoints.len() >= 5);
    assert_eq!(
        waypoints.first().map(|w| &w.cells),
        waypoints.last().map(|w| &w.cells)
    );
}

#[test]
fn missing_start_is_a_diagnostic_not_a_panic() {
    let parsed = m2rc_grammar::parse("route { go objects(bed).only() }");
    let mut map = two_rooms();
    map.start = None;
    let q = MapQuery::new(&map);
    let g = ground(&parsed.program, "", &q, &GroundOptions::default());
    assert_eq!(g.problems[0].code, codes::NO_START);
    let g = ground(
        &parsed.program,
        "",
        &q,
        &GroundOptions {
            start: Some(Cell::new(2, 3)),
            route: None,
            ..Default::default()
        },
    );
    assert!(
        g.ir.is_some(),
        "a start on the bed snaps to the nearest free cell"
    );
    // ... and says so, with where the route starts instead.
    let moved: Vec<_> = g
        .problems
        .iter()
        .filter(|p| p.code == codes::START_MOVED)
        .collect();
    assert_eq!(moved.len(), 1, "{:#?}", g.problems);
    assert!(!moved[0].is_error());
    let used = g.ir.as_ref().unwrap().start;
    assert_ne!(used, Cell::new(2, 3));
    assert!(
        moved[0]
            .message
            .contains(&format!("the route starts at [{}, {}]", used.row, used.col)),
        "{}",
        moved[0].message
    );
    // A start on a free cell is used as given, without a warning.
    let g = ground(
        &parsed.program,
        "",
        &q,
        &GroundOptions {
            start: Some(used),
            route: None,
            ..Default::default()
        },
    );
    assert!(g.problems.iter().all(|p| p.code != codes::START_MOVED));
}

#[test]
fn through_keeps_the_written_order_and_free_floor_near_each_place() {
    let src = |a: &str, b: &str| {
        format!(
            "route {{ go objects(fridge).nearest() {{ prefer through(objects({a}).only(), objects({b}).only()) }} }}"
        )
    };
    let map = two_rooms();
    let q = MapQuery::new(&map);
    let chain = |s: String| {
        let ir = ir(&s);
        let ConstraintKind::PathShape {
            shape,
            direction,
            waypoints,
            ..
        } = ir.constraints[0].kind.clone()
        else {
            panic!("{:?}", ir.constraints[0].kind)
        };
        assert_eq!(shape, crate::ir::Shape::Through);
        assert_eq!(direction, None, "a chain has no turning sense");
        waypoints
    };
    let forward = chain(src("bed", "lamp"));
    let backward = chain(src("lamp", "bed"));
    assert_eq!(forward.len(), 2);
    assert_eq!(forward[0].cells, backward[1].cells);
    assert_eq!(forward[1].cells, backward[0].cells);
    for (w, cat) in forward.iter().zip(["bed", "lamp"]) {
        let o = map.objects.iter().find(|o| o.category == cat).unwrap();
        let near = q.area_near(m2rc_stdlib::query::Target::Object(o), 0.5);
        assert!(!w.cells.cells().is_empty());
        for &c in w.cells.cells() {
            assert!(q.is_traversable(c), "{cat}: {c:?} is not free floor");
            assert!(
                near.binary_search(&c).is_ok(),
                "{cat}: {c:?} is beyond 0.5 m"
            );
        }
    }
}
