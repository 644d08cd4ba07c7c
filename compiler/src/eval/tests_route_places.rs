//! Route-dependent places read off the path from a stage that starts at furniture with no free
//! floor beside it (issue 35 item 3: a credit card on a sofa made every room "unreachable").

use super::*;
use m2rc_stdlib::map::{FREE, OBSTACLE, SemanticMap};
use m2rc_stdlib::query::fixture::two_rooms;

/// The two-room fixture with the bedroom's south half (rows 9-19) blocked: the house plant
/// (row 15, col 2) has no free cell within 0.6 m, only the planner's fallback, the bedroom's free
/// cell nearest its centre (row 8, col 2).
fn plant_walled_in() -> SemanticMap {
    let mut map = two_rooms();
    for r in 9..20 {
        for c in 0..9 {
            map.occupancy.set(Cell::new(r, c), OBSTACLE);
        }
    }
    map
}

fn ground_on(map: &SemanticMap, src: &str) -> Grounded {
    let parsed = m2rc_grammar::parse(src);
    assert!(parsed.is_ok(), "{:?}", parsed.errors);
    let q = MapQuery::new(map);
    let opts = GroundOptions {
        start: Some(Cell::new(18, 15)),
        route: None,
        ..Default::default()
    };
    ground(&parsed.program, src, &q, &opts)
}

#[test]
fn a_stage_starting_at_furniture_without_free_floor_starts_from_the_planners_fallback() {
    let map = plant_walled_in();
    let q = MapQuery::new(&map);
    let plant = map.object(7).expect("plant");
    assert_eq!(
        q.band(m2rc_stdlib::query::Target::Object(plant)),
        vec![Cell::new(8, 2)]
    );
    let src = "let k = rooms(kitchen).only()\n\
               route {\n\
                 go objects(house_plant).only()\n\
                 go objects(fridge).only() { prefer near(doorway_entering(k)) }\n\
               }";
    let g = ground_on(&map, src);
    assert!(
        g.problems.iter().all(|p| !p.is_error()),
        "{:#?}",
        g.problems
    );
    let ir = g.ir.expect("ir");
    let b = &ir.route_bindings[0];
    assert_eq!(b.function, "doorway_entering");
    assert!(b.resolved.contains("kitchen"), "{}", b.resolved);
}

#[test]
fn a_room_that_cannot_be_reached_names_the_stage_start() {
    let mut map = two_rooms();
    // Close the only door: from the kitchen the bedroom cannot be reached.
    map.occupancy.set(Cell::new(8, 9), OBSTACLE);
    let src = "let b = rooms(bedroom).only()\n\
               route {\n\
                 go objects(fridge).only()\n\
                 go objects(dining_table).only() { prefer near(doorway_entering(b)) }\n\
               }";
    let g = ground_on(&map, src);
    let e = g
        .problems
        .iter()
        .find(|p| p.code == codes::ROUTE_PLACE_UNDEFINED)
        .expect("E0507");
    assert!(
        e.message.contains(
            "no free path leads from this stage's start (fridge #8 (kitchen_2)) into bedroom_1"
        ),
        "{}",
        e.message
    );
    assert_eq!(map.occupancy.get(Cell::new(8, 8)), Some(&FREE));
}
