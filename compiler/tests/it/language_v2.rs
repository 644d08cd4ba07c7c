//! Grounding tests of the language v2 constructs on a real fixture house (ProcTHOR house 149 of
//! the hard validation split): unions and set literals, open-plan areas, k distinct rooms
//! (`tour`), no-revisit (`left_behind`), orderings, object sizes, enclosed areas,
//! house-level places, route history, path shapes without a direction, splitting a stage, and
//! deeply nested filters.

use m2rc_compiler::check::check;
use m2rc_compiler::eval::{GroundOptions, Grounded, ground_checked};
use m2rc_compiler::ir::{ConstraintKind, PlaceKind, RouteIr, StageScope};
use m2rc_stdlib::map::SemanticMap;
use m2rc_stdlib::query::{MapQuery, Target};
use m2rc_stdlib::vocab::Vocabulary;

const HOUSE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../shared/procthor/fixtures/procthor10k_uniform_hard_val_150_149.json"
);

fn house() -> SemanticMap {
    m2rc_stdlib::load::load_map(HOUSE).expect("fixture house 149 loads")
}

fn ground(map: &SemanticMap, src: &str) -> Grounded {
    let checked = check(src, &Vocabulary::from_map(map));
    assert!(
        !checked.has_errors(),
        "{src}\n{}",
        m2rc_compiler::diagnostic::render_text(&checked.diagnostics, "t.m2r", src)
    );
    let q = MapQuery::new(map);
    ground_checked(&checked, src, &q, &GroundOptions::default())
}

fn ir(map: &SemanticMap, src: &str) -> RouteIr {
    let g = ground(map, src);
    assert!(
        g.problems.iter().all(|p| !p.is_error()),
        "{src}\n{:#?}",
        g.problems
    );
    g.ir.expect("ir")
}

fn object_id(p: &PlaceKind) -> u32 {
    match p {
        PlaceKind::Object { id, .. } => *id,
        other => panic!("not an object: {other:?}"),
    }
}

#[test]
fn set_literals_and_unions_of_places_are_one_place() {
    let map = house();
    let r = ir(
        &map,
        "let kitchen_room = rooms(kitchen).only()\n\
         let baths = rooms(bathroom)\n\
         route {\n\
           go objects(bed).nearest() {\n\
             avoid [kitchen_room, baths.nearest()]\n\
             prefer far(objects(window)) within kitchen_room | baths.farthest()\n\
           }\n\
           go center(kitchen_room)\n\
         }",
    );
    let q = MapQuery::new(&map);
    let ConstraintKind::Avoid { place } = &r.constraints[0].kind else {
        panic!("{:?}", r.constraints[0].kind)
    };
    let kitchen = map
        .rooms
        .iter()
        .find(|x| x.category == "kitchen")
        .unwrap()
        .id;
    let kc = q.room_cells(kitchen);
    assert!(
        kc.iter().all(|&c| place.cells.contains(c)),
        "the union holds the kitchen"
    );
    assert!(place.cells.len() > kc.len(), "and the bathroom");
    let scope = r.constraints[1].spatial_scope.as_ref().unwrap();
    assert!(scope.cells.len() > kc.len());
    // `center` of a single room is a region inside the house.
    assert!(!r.stages[1].target.cells.is_empty());
}

/// House 149's kitchen has no wall to the living room (ProcTHOR leaves it out), and that living
/// room none to the second: `open_area` is the three rooms, from any of them.
#[test]
fn open_area_is_the_open_plan_rooms_around_a_room() {
    let map = house();
    let q = MapQuery::new(&map);
    let id = |cat: &str, k: usize| {
        map.rooms
            .iter()
            .filter(|r| r.category == cat)
            .nth(k)
            .unwrap_or_else(|| panic!("{cat} #{k}"))
            .id
    };
    let (kitchen, living) = (
        id("kitchen", 0),
        [id("living_room", 0), id("living_room", 1)],
    );
    let mut want = vec![kitchen, living[0], living[1]];
    want.sort_unstable();
    assert_eq!(
        q.open_area(kitchen),
        want,
        "fixture: the open plan as the map has it"
    );
    let r = ir(
        &map,
        "let kitchen_room = rooms(kitchen).only()\n\
         route {\n\
           go objects(bed).nearest() {\n\
             avoid kitchen_room.open_area()\n\
             prefer far(objects(window)) within rooms(living_room).open_area()\n\
           }\n\
         }",
    );
    let ConstraintKind::Avoid { place } = &r.constraints[0].kind else {
        panic!("{:?}", r.constraints[0].kind)
    };
    let cells = |rooms: &[u32]| rooms.iter().map(|&x| q.room_cells(x).len()).sum::<usize>();
    for &room in &want {
        assert!(
            q.room_cells(room).iter().all(|&c| place.cells.contains(c)),
            "room {room}"
        );
    }
    assert_eq!(
        place.cells.len(),
        cells(&want),
        "the area is the three rooms, no more"
    );
    // From the living rooms (a set), the same area.
    let scope = r.constraints[1].spatial_scope.as_ref().unwrap();
    assert_eq!(scope.cells.len(), cells(&want));
    // A room with no open boundary is its own area.
    let bath = id("bathroom", 0);
    assert_eq!(q.open_area(bath), vec![bath]);
}

fn room_id(p: &PlaceKind) -> u32 {
    match p {
        PlaceKind::Room { id, .. } => *id,
        other => panic!("not a room: {other:?}"),
    }
}

/// "Go through two rooms, then to the bed": `tour(2)` picks the two rooms, and their order, of
/// the shortest walk from the start, as a brute force over every ordered pair confirms.
#[test]
fn tour_picks_the_k_rooms_of_the_shortest_walk() {
    let map = house();
    let q = MapQuery::new(&map);
    let r = ir(
        &map,
        "route {\n\
           for r in rooms().except(start.room()).tour(2) { go r }\n\
           go objects(bed).nearest()\n\
         }",
    );
    assert_eq!(r.stages.len(), 3);
    let got = [
        room_id(&r.stages[0].target.kind),
        room_id(&r.stages[1].target.kind),
    ];
    assert_ne!(got[0], got[1], "distinct rooms");
    let start = map.start.unwrap();
    let start_room = q.room_at(start);
    let from_start = q.travel_field(Target::Cells(&[start]));
    let rooms: Vec<u32> = map
        .rooms
        .iter()
        .map(|r| r.id)
        .filter(|&r| r != start_room && from_start.to(q.room_cells(r)).is_some())
        .collect();
    let walk = |a: u32, b: u32| {
        from_start.to(q.room_cells(a)).unwrap()
            + q.travel_field(Target::Room(a))
                .to(q.room_cells(b))
                .unwrap_or(f64::INFINITY)
    };
    let best = rooms
        .iter()
        .flat_map(|&a| rooms.iter().filter(move |&&b| b != a).map(move |&b| (a, b)))
        .map(|(a, b)| walk(a, b))
        .fold(f64::INFINITY, f64::min);
    assert!(
        (walk(got[0], got[1]) - best).abs() < 1e-9,
        "tour {got:?} walks {} m, the best pair {best} m",
        walk(got[0], got[1])
    );
    // More rooms than the set has is an error at grounding, naming the count.
    let g = ground(&map, "route { for r in rooms(bathroom).tour(9) { go r } }");
    assert!(
        g.problems.iter().any(|p| p.code == "E0504"),
        "{:#?}",
        g.problems
    );
}

/// "... without going back through a room you have already crossed": `avoid left_behind()` in
/// the last stage avoids every room of the earlier stages but the one it starts in.
#[test]
fn left_behind_is_every_room_visited_but_the_current_one() {
    let map = house();
    let q = MapQuery::new(&map);
    let start_room = q.room_at(map.start.unwrap());
    let r = ir(
        &map,
        "let far_room = rooms().except(start.room()).farthest(by: travel)\n\
         route {\n\
           go far_room\n\
           go objects().in(far_room).farthest() {\n\
             avoid left_behind()\n\
           }\n\
         }",
    );
    let ConstraintKind::Avoid { place } = &r.constraints[0].kind else {
        panic!("{:?}", r.constraints[0].kind)
    };
    let far_room = room_id(&r.stages[0].target.kind);
    let b = r
        .route_bindings
        .iter()
        .find(|b| b.function == "left_behind")
        .expect("a route binding, re-bound after planning");
    // The start room was left behind; the room the stage starts in (the far room) was not.
    assert!(
        q.room_cells(start_room)
            .iter()
            .all(|&c| place.cells.contains(c)),
        "{}",
        b.resolved
    );
    assert!(
        q.room_cells(far_room)
            .iter()
            .all(|&c| !place.cells.contains(c)),
        "{}",
        b.resolved
    );
}

#[test]
fn orderings_follow_distance_key_and_position() {
    let map = house();
    let q = MapQuery::new(&map);
    let start = map.start.expect("the house has a start");
    let dist = |id: u32| {
        q.distance(
            Target::Object(map.object(id).unwrap()),
            Target::Cells(&[start]),
        )
        .unwrap()
    };
    let stages = |src: &str| -> Vec<u32> {
        ir(&map, src)
            .stages
            .iter()
            .map(|s| object_id(&s.target.kind))
            .collect()
    };
    let near = stages("route { for c in objects(chair).nearest_first() { go c } }");
    assert!(near.len() >= 3);
    assert!(
        near.windows(2).all(|w| dist(w[0]) <= dist(w[1])),
        "{near:?}"
    );
    let far = stages("route { for c in objects(chair).farthest_first() { go c } }");
    assert!(far.windows(2).all(|w| dist(w[0]) >= dist(w[1])), "{far:?}");
    let rev = stages("route { for c in objects(chair).nearest_first().reversed() { go c } }");
    let mut back = near.clone();
    back.reverse();
    // Same distances in the opposite order (ties may keep their set order).
    assert_eq!(
        rev.iter().map(|&i| dist(i)).collect::<Vec<_>>(),
        back.iter().map(|&i| dist(i)).collect::<Vec<_>>()
    );
    let second = stages("route { go objects(chair).nearest_first().kth(2) }");
    assert_eq!(second, vec![near[1]]);
    let kth2 = stages("route { go objects(chair).kth_nearest(2) }");
    assert_eq!(dist(kth2[0]), dist(second[0]));
    let desc = stages(
        "route { for c in objects(chair).sorted_by_descending(c => c.footprint_area()) { go c } }",
    );
    let area = |id: u32| map.object(id).unwrap().footprint.len();
    assert!(desc.windows(2).all(|w| area(w[0]) >= area(w[1])));
}

#[test]
fn object_sizes_rank_and_measure_footprints() {
    let map = house();
    let res = map.frame.resolution;
    let largest = object_id(
        &ir(&map, "route { go objects(chair).largest() }").stages[0]
            .target
            .kind,
    );
    let by_key = object_id(
        &ir(
            &map,
            "route { go objects(chair).max_by(c => c.footprint_area()) }",
        )
        .stages[0]
            .target
            .kind,
    );
    let most = map
        .objects
        .iter()
        .filter(|o| o.category == "chair")
        .map(|o| o.footprint.len())
        .max()
        .unwrap();
    assert_eq!(map.object(largest).unwrap().footprint.len(), most);
    assert_eq!(map.object(by_key).unwrap().footprint.len(), most);
    // Length is the longer side, squareness in (0, 1], and nothing is longer than the longest.
    let r = ir(
        &map,
        "let long = objects().max_by(o => o.length())\n\
         route {\n\
           for o in objects().where(o => o.length() < o.width() or o.squareness() <= 0 or o.squareness() > 1 or o.length() > long.length()) { go o }\n\
           go long\n\
         }",
    );
    assert_eq!(
        r.stages.len(),
        1,
        "{:?}",
        r.stages.iter().map(|s| &s.target.label).collect::<Vec<_>>()
    );
    let _ = res;
}

#[test]
fn enclosed_area_and_house_places() {
    let map = house();
    let q = MapQuery::new(&map);
    let r = ir(
        &map,
        "let chairs = objects(chair).nearest_first()\n\
         route {\n\
           go area_enclosed([chairs.kth(1), chairs.kth(2), chairs.kth(3)])\n\
           go house_corners().farthest()\n\
           go house_center()\n\
         }",
    );
    let enclosed = &r.stages[0].target;
    assert!(!enclosed.cells.is_empty());
    let PlaceKind::Region { construction } = &enclosed.kind else {
        panic!()
    };
    assert_eq!(construction.kind, "area_enclosed");
    assert_eq!(construction.from.len(), 3);
    // No cell of the enclosed area is under one of the three chairs.
    for o in map.objects.iter().filter(|o| o.category == "chair") {
        if construction
            .from
            .iter()
            .any(|l| l.starts_with(&format!("chair #{} ", o.id)))
        {
            assert!(o.footprint.iter().all(|&c| !enclosed.cells.contains(c)));
        }
    }
    let corner = &r.stages[1].target;
    assert!(
        corner.label.contains("corner of the house"),
        "{}",
        corner.label
    );
    assert!(corner.cells.cells().iter().all(|&c| q.room_at(c) != 0));
    assert!(!r.stages[2].target.cells.is_empty());
    // Fewer than three places is a grounding error, pointing at `area_between`.
    let g = ground(
        &map,
        "route { go area_enclosed([objects(chair).nearest(), objects(chair).farthest()]) }",
    );
    assert!(
        g.problems.iter().any(|p| p.code == "E0506"),
        "{:#?}",
        g.problems
    );
}

#[test]
fn route_history_kth_entered_and_visited() {
    let map = house();
    let first = ir(
        &map,
        "route { go first_entered(rooms().except(start.room())) }",
    );
    let kth1 = ir(
        &map,
        "route { go kth_entered(rooms().except(start.room()), 1) }",
    );
    assert_eq!(first.stages[0].target.label, kth1.stages[0].target.label);
    // Before planning, the k-th room entered is the k-th by travel distance from the start.
    let q = MapQuery::new(&map);
    let start = map.start.unwrap();
    let field = q.travel_field(Target::Cells(&[start]));
    let start_room = q.room_at(start);
    let mut by_travel: Vec<(f64, u32)> = map
        .rooms
        .iter()
        .filter(|r| r.id != start_room)
        .filter_map(|r| field.to(q.room_cells(r.id)).map(|d| (d, r.id)))
        .collect();
    by_travel.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    for (k, (_, want)) in by_travel.iter().enumerate() {
        let r = ir(
            &map,
            &format!(
                "route {{ go kth_entered(rooms().except(start.room()), {}) }}",
                k + 1
            ),
        );
        assert!(matches!(r.stages[0].target.kind, PlaceKind::Room { id, .. } if id == *want));
        assert!(r.route_bindings.iter().any(|b| b.function == "kth_entered"));
    }
    let beyond = format!(
        "route {{ go kth_entered(rooms().except(start.room()), {}) }}",
        by_travel.len() + 1
    );
    assert!(
        ground(&map, &beyond)
            .problems
            .iter()
            .any(|p| p.code == "E0507")
    );
    let g = ground(&map, "route { go kth_entered(rooms(kitchen), 2) }");
    assert!(
        g.problems.iter().any(|p| p.code == "E0507"),
        "{:#?}",
        g.problems
    );
    // After going into a bedroom, `visited()` holds the start room and that bedroom, so "a
    // bedroom you have not been in yet" is another one.
    let r = ir(
        &map,
        "let b1 = rooms(bedroom).nearest()\n\
         route {\n\
           go b1\n\
           go rooms(bedroom).except(visited()).nearest()\n\
         }",
    );
    assert_ne!(r.stages[0].target.label, r.stages[1].target.label);
    let v = r
        .route_bindings
        .iter()
        .find(|b| b.function == "visited")
        .unwrap();
    assert!(
        v.resolved.contains(&r.stages[0].target.label),
        "{}",
        v.resolved
    );
    // In a top-level `let`, only the start room has been visited.
    let top = ir(&map, "let seen = visited()\nroute { go seen.only() }");
    assert!(matches!(top.stages[0].target.kind, PlaceKind::Room { .. }));
}

#[test]
fn path_shapes_without_a_direction_take_the_shorter_way_and_say_so() {
    let map = house();
    let r = ir(
        &map,
        "let here_room = start.room()\n\
         route {\n\
           go objects().farthest() {\n\
             prefer follow_wall(here_room)\n\
           }\n\
         }",
    );
    let b = r
        .route_bindings
        .iter()
        .find(|b| b.function == "follow_wall")
        .expect("the chosen direction is recorded");
    assert!(
        b.resolved.starts_with("clockwise") || b.resolved.starts_with("counterclockwise"),
        "{}",
        b.resolved
    );
    assert!(b.resolved.contains("shorter") || b.resolved.contains("equally"));
    // `until:` ends the walk at that doorway; `passing:` picks a side and says why.
    let r = ir(
        &map,
        "let here_room = start.room()\n\
         let door = here_room.doorways().farthest()\n\
         route {\n\
           go objects().farthest() {\n\
             prefer follow_wall(here_room, until: door, passing: objects().in(here_room).farthest())\n\
           }\n\
         }",
    );
    let ConstraintKind::PathShape { waypoints, .. } = &r.constraints[0].kind else {
        panic!("{:?}", r.constraints[0].kind)
    };
    let full = ir(
        &map,
        "route { go objects().farthest() { prefer follow_wall(start.room(), clockwise) } }",
    );
    let ConstraintKind::PathShape { waypoints: all, .. } = &full.constraints[0].kind else {
        panic!()
    };
    assert!(waypoints.len() <= all.len() + 1);
    let b = r
        .route_bindings
        .iter()
        .find(|b| b.function == "follow_wall")
        .unwrap();
    assert!(
        b.resolved.contains("passing")
            || b.resolved.contains("equally")
            || b.resolved.contains("shorter"),
        "{}",
        b.resolved
    );
    // A given direction is used as written, with no binding.
    assert!(
        full.route_bindings
            .iter()
            .all(|b| b.function != "follow_wall")
    );
}

#[test]
fn a_preference_from_partway_is_a_split_stage() {
    let map = house();
    let r = ir(
        &map,
        "let first_room = start.room()\n\
         route {\n\
           go objects().in(first_room).nearest()\n\
           go doorway_leaving(first_room) as leave_first_room\n\
           go objects(sofa).nearest() {\n\
             prefer far(objects(window))\n\
           }\n\
         }",
    );
    assert_eq!(r.stages.len(), 3);
    let far = r
        .constraints
        .iter()
        .find(|c| matches!(c.kind, ConstraintKind::Far { .. }))
        .unwrap();
    assert_eq!(far.stage_scope, StageScope::Stages(vec![2]));
}

/// Ten nested filters, each relating its candidate to its parent's, ground (memoised) to the same
/// rooms as the flat statement of the same fact: every room with a neighbour.
#[test]
fn deeply_nested_filters_ground_and_agree_with_the_flat_form() {
    let map = house();
    let mut body = "a10.adjacent_to(a9)".to_string();
    for i in (2..10).rev() {
        body = format!(
            "a{i}.adjacent_to(a{}) and rooms().where(a{} => {body}).exists()",
            i - 1,
            i + 1
        );
    }
    let deep = format!(
        "route {{ for r in rooms().where(a1 => rooms().where(a2 => {body}).exists()) {{ go r }} }}"
    );
    let flat = "route { for r in rooms().where(a => rooms().where(b => b.adjacent_to(a)).exists()) { go r } }";
    let labels = |src: &str| -> Vec<String> {
        ir(&map, src)
            .stages
            .iter()
            .map(|s| s.target.label.clone())
            .collect()
    };
    // Any room with a neighbour starts an adjacency walk of any length (it can step back).
    assert_eq!(labels(&deep), labels(flat));
}
