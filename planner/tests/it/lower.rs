//! RouteIR lowering on a small hand-made two-room map: stages, avoid regions, soft terms and
//! clearance obstacles come out as documented, and failures map back to source spans.

use crate::fixture::{cells, object};
use m2rc_compiler::ir::{
    CellSet, Constraint, ConstraintKind, Construction, Direction, Pass, Place, PlaceKind,
    ROUTE_IR_VERSION, RouteIr, Shape, SourceSpan, Stage, StageScope,
};
use m2rc_planner::lower::{lower, span_of};
use m2rc_planner::{CostProfile, Origin, PlanFailure, StageRole, Target, plan_sequential};
use m2rc_stdlib::grid::{Cell, Grid};
use m2rc_stdlib::map::{FREE, GridFrame, OBSTACLE, Room, SemanticMap};

const N: usize = 20;

/// Room 1 = columns 0..10, room 2 = columns 11..20, a wall in column 10 with a door in rows 8..12.
/// A bed (blocked) in room 2, a rug (free floor, but an object) in room 1.
fn map() -> SemanticMap {
    let mut occ = Grid::new(N, FREE);
    let mut rooms = Grid::new(N, 0u32);
    let mut objects = Grid::new(N, 0u32);
    for r in 0..N as u32 {
        for c in 0..N as u32 {
            let cell = Cell::new(r, c);
            rooms.set(
                cell,
                if c < 10 {
                    1
                } else if c > 10 {
                    2
                } else {
                    0
                },
            );
            if c == 10 && !(8..12).contains(&r) {
                occ.set(cell, OBSTACLE);
            }
        }
    }
    let door = object(7, "doorway", cells(8..12, 10..11), 1);
    let bed = object(5, "bed", cells(3..6, 14..17), 2);
    let rug = object(6, "rug", cells(14..16, 3..6), 1);
    for c in &bed.footprint {
        occ.set(*c, OBSTACLE);
        objects.set(*c, 5);
    }
    for c in &rug.footprint {
        objects.set(*c, 6);
    }
    for c in &door.footprint {
        objects.set(*c, 7);
    }
    let room = |id: u32, category: &str| Room {
        id,
        category: category.into(),
        name: format!("{category} {id}"),
        area_m2: 1.0,
        attributes: vec![],
    };
    SemanticMap {
        map_id: "two_rooms".into(),
        frame: GridFrame {
            resolution: 0.05,
            x_min: 0.0,
            z_min: 0.0,
        },
        occupancy: occ,
        room_layer: rooms,
        object_layer: objects,
        rooms: vec![room(1, "living_room"), room(2, "bedroom")],
        objects: vec![bed, rug, door],
        start: None,
        open_boundaries: Vec::new(),
    }
}

fn span(start: usize, end: usize) -> SourceSpan {
    SourceSpan {
        start,
        end,
        line: 1,
        col: start as u32 + 1,
    }
}

fn region(label: &str, kind: &str, c: Vec<Cell>) -> Place {
    Place {
        kind: PlaceKind::Region {
            construction: Construction {
                kind: kind.into(),
                from: vec![],
                radius_m: None,
            },
        },
        label: label.into(),
        cells: CellSet::new(c),
    }
}

fn bed_place() -> Place {
    Place {
        kind: PlaceKind::Object {
            id: 5,
            category: "bed".into(),
            room: Some(2),
        },
        label: "bed #5".into(),
        cells: CellSet::new(cells(3..6, 14..17)),
    }
}

fn ir(avoid: Vec<Cell>) -> RouteIr {
    RouteIr {
        version: ROUTE_IR_VERSION,
        map_id: "two_rooms".into(),
        grid_size: N,
        resolution_m: 0.05,
        start: Cell::new(18, 2),
        stages: vec![Stage {
            name: "stage1".into(),
            target: bed_place(),
            passes: vec![Pass {
                place: region("door", "doorway", cells(8..12, 10..11)),
                span: span(20, 30),
            }],
            span: span(0, 100),
        }],
        constraints: vec![
            Constraint {
                id: "c0".into(),
                kind: ConstraintKind::Avoid {
                    place: region("left top", "area_near", avoid),
                },
                stage_scope: StageScope::Global,
                spatial_scope: None,
                span: span(110, 130),
            },
            Constraint {
                id: "c1".into(),
                kind: ConstraintKind::Near {
                    reference: bed_place(),
                },
                stage_scope: StageScope::Stages(vec![0]),
                spatial_scope: Some(Place {
                    kind: PlaceKind::Room {
                        id: 2,
                        category: "bedroom".into(),
                    },
                    label: "bedroom 2".into(),
                    cells: CellSet::new(cells(0..20, 11..20)),
                }),
                span: span(40, 60),
            },
            Constraint {
                id: "c2".into(),
                kind: ConstraintKind::PathShape {
                    shape: Shape::Circle,
                    direction: Some(Direction::Clockwise),
                    around: bed_place(),
                    waypoints: vec![region("wp0", "waypoint", vec![Cell::new(1, 15)])],
                },
                stage_scope: StageScope::Stages(vec![0]),
                spatial_scope: None,
                span: span(10, 18),
            },
        ],
        route_bindings: vec![],
    }
}

#[test]
fn lowering_builds_ordered_stages_avoids_terms_and_obstacles() {
    let m = map();
    let p = lower(&ir(cells(0..8, 0..10)), &m, CostProfile::reference()).unwrap();
    assert_eq!(p.segments.len(), 1);
    let s = &p.segments[0];
    // The circle (span 10..18) is written before the pass (span 20..30).
    let roles: Vec<StageRole> = s.stages.iter().map(|st| st.role).collect();
    assert_eq!(
        roles,
        vec![StageRole::Waypoint, StageRole::Pass, StageRole::Destination]
    );
    assert_eq!(s.stages[0].origin, Origin::Constraint { index: 2, part: 0 });
    assert!(
        s.stages[0].smoothness.is_some(),
        "shape waypoints charge turns in the shape's room"
    );
    assert_eq!(s.stages[1].origin, Origin::Pass { stage: 0, index: 0 });
    assert!(matches!(s.stages[2].target, Target::Object { .. }));
    assert_eq!(s.forbidden.len(), 1);
    assert_eq!(s.soft.len(), 1);
    let obs = p.obstacles.as_ref().unwrap();
    assert_eq!(
        obs.get(Cell::new(14, 3)),
        Some(&true),
        "a floor object is a clearance obstacle"
    );
    assert_eq!(obs.get(Cell::new(9, 10)), Some(&false), "doorways are not");
    assert_eq!(obs.get(Cell::new(0, 10)), Some(&true));

    let r = plan_sequential(&p);
    assert!(r.is_success(), "{:?}", r.failure);
    assert!(
        r.trajectory.iter().all(|c| !(c.row < 8 && c.col < 10)),
        "entered the avoided area"
    );
    assert!(
        r.trajectory.contains(&Cell::new(1, 15))
            || r.segments[0].stages[0].endpoint == Cell::new(1, 15)
    );
    let end = *r.trajectory.last().unwrap();
    assert!(end.col > 10, "ends in the bed's room");
    let d = cells(3..6, 14..17)
        .iter()
        .map(|c| c.dist(end))
        .fold(f64::INFINITY, f64::min);
    assert!(d > 0.0 && d <= 6.0, "ends within the goal band, at {d}");
}

#[test]
fn blocking_the_door_is_reported_against_the_avoid_span() {
    let m = map();
    let mut i = ir(cells(6..14, 9..10));
    i.constraints.truncate(2);
    i.stages[0].passes.clear();
    let p = lower(&i, &m, CostProfile::reference()).unwrap();
    let r = plan_sequential(&p);
    let f = r.failure.expect("the door is blocked");
    assert!(
        matches!(f, PlanFailure::UnreachableUnderAvoids { .. }),
        "{f:?}"
    );
    assert_eq!(f.forbids(), &[Origin::Constraint { index: 0, part: 0 }]);
    assert_eq!(span_of(&i, f.forbids()[0]), Some(span(110, 130)));
    assert_eq!(span_of(&i, f.target().unwrap()), Some(span(0, 100)));
}

#[test]
fn mismatched_grid_is_an_error() {
    let mut i = ir(vec![]);
    i.grid_size = 30;
    let e = lower(&i, &map(), CostProfile::reference()).unwrap_err();
    assert!(e.contains("30×30"), "{e}");
}
