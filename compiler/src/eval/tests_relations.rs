//! Every relation built-in with every argument kind its signature admits, on the two-room fixture
//! (`m2rc_stdlib::query::fixture`), where each answer can be worked out by hand. A relation that
//! silently never holds for an admitted kind (issue 35 item 4: `next_to` of a corner) fails here.
//! Also the language gaps of items 7-9 on the same fixture: containment in a region, rankings to
//! the nearest member of a set, and a wall side chosen by exclusion.

use super::*;
use crate::ir::PlaceKind;
use m2rc_stdlib::query::fixture::two_rooms;

/// Grounds `route { go <dest> }` with corners 0.2 m wide, so that on the 0.9 m-wide bedroom a
/// corner is a patch of 2 × 2 cells and "beside a corner" can be false.
fn go(dest: &str) -> Grounded {
    go_with_corners(dest, 0.2)
}

fn go_with_corners(dest: &str, corner_radius_m: f64) -> Grounded {
    let src = format!("route {{ go {dest} }}");
    let parsed = m2rc_grammar::parse(&src);
    assert!(parsed.is_ok(), "{:?}", parsed.errors);
    let map = two_rooms();
    let mut q = MapQuery::new(&map);
    q.thresholds.corner_radius_m = corner_radius_m;
    ground(&parsed.program, &src, &q, &GroundOptions::default())
}

fn target(dest: &str) -> PlaceKind {
    let g = go(dest);
    assert!(
        g.problems.iter().all(|p| !p.is_error()),
        "{dest}: {:#?}",
        g.problems
    );
    g.ir.expect("ir").stages[0].target.kind.clone()
}

fn object(dest: &str) -> u32 {
    match target(dest) {
        PlaceKind::Object { id, .. } => id,
        other => panic!("{dest}: not an object: {other:?}"),
    }
}

fn region_cells(dest: &str) -> Vec<Cell> {
    let g = go(dest);
    assert!(
        g.problems.iter().all(|p| !p.is_error()),
        "{:#?}",
        g.problems
    );
    g.ir.expect("ir").stages[0].target.cells.cells().to_vec()
}

fn empty(dest: &str) -> bool {
    go(dest)
        .problems
        .iter()
        .any(|p| p.code == codes::EMPTY_SELECTION)
}

const BEDROOM_CORNERS: &str = "rooms(bedroom).only().corners()";

#[test]
fn next_to_an_object_a_set_of_objects_and_a_place_predicate() {
    // The lamp (row 3, col 7) is 0.2 m from the bed's east side (col 5).
    assert_eq!(
        object("objects(lamp).next_to(objects(bed).only()).only()"),
        2
    );
    assert_eq!(
        object("objects(lamp).next_to(objects(bed | fridge)).only()"),
        2
    );
    assert_eq!(
        object("objects(bed | chair).where(o => o.next_to(objects(lamp).only())).only()"),
        1
    );
    // The book rests on the bed: stacked objects are not beside each other.
    assert!(empty("objects(book).next_to(objects(bed)).only()"));
}

#[test]
fn next_to_a_corner_region_reads_its_cells() {
    // The plant (row 15, col 2) is 0.32 m from the south-west corner patch (rows 18-19,
    // cols 0-1); the chair (rows 10-11) is 0.73 m from it and near no other corner.
    let corner = region_cells(&format!(
        "{BEDROOM_CORNERS}.where(c => objects(house_plant).next_to(c).exists()).only()"
    ));
    assert!(corner.contains(&Cell::new(19, 0)), "{corner:?}");
    assert!(empty(&format!(
        "{BEDROOM_CORNERS}.where(c => objects(chair).next_to(c).exists()).only()"
    )));
    // The single-object predicate reads the same cells.
    let same = region_cells(&format!(
        "{BEDROOM_CORNERS}.where(c => objects(house_plant).only().next_to(c)).only()"
    ));
    assert_eq!(corner, same);
    // A set of regions: any of them. The chair is beside none of the four corners.
    assert_eq!(
        object(&format!(
            "objects(house_plant | chair).next_to({BEDROOM_CORNERS}).only()"
        )),
        7
    );
}

#[test]
fn next_to_a_doorway_region() {
    // The bedroom's one doorway is the door cell (8, 9) and the room cells beside it; the rug
    // (row 7, cols 3-4) is 0.41 m from (8, 8), the lamp (3, 7) 0.51 m.
    assert_eq!(
        object("objects(rug | lamp).next_to(rooms(bedroom).only().doorways()).only()"),
        6
    );
    assert_eq!(
        object("objects(rug | lamp).next_to(rooms(bedroom).only().doorways().only()).only()"),
        6
    );
}

#[test]
fn physical_relations_with_an_object_and_a_set_of_objects() {
    // The cup (row 13, col 13) stands on the table's top at 0.75 m; the shelf hangs at 1.5 m
    // over the bed and the book.
    assert_eq!(
        object("objects(cup).on(objects(dining_table).only()).only()"),
        10
    );
    assert_eq!(
        object("objects(cup | book).on(objects(dining_table)).only()"),
        10
    );
    assert_eq!(
        object("objects(cup | lamp).on(objects(bed | dining_table)).nearest()"),
        10
    );
    assert_eq!(
        object("objects(dining_table | bed).holding(objects(cup).only()).only()"),
        9
    );
    assert_eq!(
        object("objects(dining_table | bed).where(t => t.holding(objects(cup))).only()"),
        9
    );
    assert_eq!(
        object("objects(bed | chair).under(objects(shelf)).only()"),
        1
    );
    assert_eq!(
        object("objects(bed | chair).where(b => b.under(objects(shelf).only())).only()"),
        1
    );
    // On is not inside.
    assert!(empty("objects(cup).inside(objects(dining_table)).only()"));
}

#[test]
fn near_with_an_object_a_room_and_a_region() {
    // The lamp (col 7) is 0.3 m from the kitchen's first column (10), the plant (col 2) 0.8 m.
    assert_eq!(
        object("objects(lamp | house_plant).near(rooms(kitchen).only(), within: 50cm).only()"),
        2
    );
    assert_eq!(
        object(
            "objects(rug | house_plant).near(rooms(bedroom).only().doorways(), within: 50cm).only()"
        ),
        6
    );
    assert_eq!(
        object("objects(lamp | house_plant).near(objects(bed).only(), within: 50cm).only()"),
        2
    );
}

#[test]
fn in_and_contains_with_a_region() {
    // Within 0.2 m of the bed: the lamp (0.2 m east of it); the rug is 0.3 m south.
    assert_eq!(
        object(
            "objects(lamp | rug | chair).in(area_near(objects(bed).only(), within: 20cm)).only()"
        ),
        2
    );
    assert_eq!(
        object(
            "objects(lamp | rug).where(o => o.in(area_near(objects(bed).only(), within: 20cm))).only()"
        ),
        2
    );
    // Rooms still work, and a set of rooms and regions means any of them.
    assert_eq!(
        object("objects(fridge | bed).in(rooms(kitchen).only()).only()"),
        8
    );
    // The kitchen's corners at the default 0.75 m on this 1 m-wide room: the fridge (rows 2-3,
    // cols 16-17) lies in a northern one, and the lamp (in the bedroom) in none.
    let fridge_corners = "rooms(kitchen).only().corners().where(c => c.contains(objects(fridge)))";
    let g = go_with_corners(
        &format!("{fridge_corners}.nearest(to: objects(fridge).only())"),
        0.75,
    );
    assert!(
        g.problems.iter().all(|p| !p.is_error()),
        "{:#?}",
        g.problems
    );
    let corner = g.ir.expect("ir").stages[0].target.cells.cells().to_vec();
    assert!(corner.iter().all(|c| c.row < 10), "{corner:?}");
    let g = go_with_corners(
        &format!("objects(fridge | lamp).in({fridge_corners}).only()"),
        0.75,
    );
    assert!(
        g.problems.iter().all(|p| !p.is_error()),
        "{:#?}",
        g.problems
    );
    assert!(matches!(
        g.ir.expect("ir").stages[0].target.kind,
        PlaceKind::Object { id: 8, .. }
    ));
}

#[test]
fn rankings_to_a_set_measure_to_its_nearest_member() {
    // To the fridge alone the lamp (row 3, col 7) beats the chair (rows 10-11, cols 3-4); with
    // the plant (row 15, col 2) in the set, the chair is 0.4 m from it and wins.
    assert_eq!(
        object("objects(lamp | chair).nearest(to: objects(fridge).only())"),
        2
    );
    assert_eq!(
        object("objects(lamp | chair).nearest(to: objects(fridge | house_plant))"),
        5
    );
    assert_eq!(
        object("objects(lamp | chair).farthest(to: objects(fridge | house_plant))"),
        2
    );
    assert_eq!(
        object("objects(lamp | chair).kth_nearest(2, to: objects(fridge | house_plant))"),
        2
    );
    assert_eq!(
        object("objects(lamp | chair).nearest_first(to: objects(fridge | house_plant)).kth(1)"),
        5
    );
}

/// Issue 35 item 7: "take the side along the wall that does not pass by x" chooses by exclusion,
/// the opposite side to `passing: x`, and the binding says why.
#[test]
fn follow_wall_avoiding_takes_the_side_passing_does_not() {
    let binding = |arg: &str| {
        let src = format!(
            "route {{ go objects(fridge).only() {{ prefer follow_wall(rooms(bedroom).only(), until: doorway_leaving(rooms(bedroom).only()), {arg}: objects(lamp).only()) }} }}"
        );
        let parsed = m2rc_grammar::parse(&src);
        assert!(parsed.is_ok(), "{:?}", parsed.errors);
        let map = two_rooms();
        let q = MapQuery::new(&map);
        let g = ground(&parsed.program, &src, &q, &GroundOptions::default());
        assert!(
            g.problems.iter().all(|p| !p.is_error()),
            "{:#?}",
            g.problems
        );
        g.ir.expect("ir")
            .route_bindings
            .into_iter()
            .find(|b| b.function == "follow_wall")
            .expect("a follow_wall binding")
            .resolved
    };
    let passing = binding("passing");
    let avoiding = binding("avoiding");
    assert!(passing.contains("the side passing lamp"), "{passing}");
    assert!(avoiding.contains("the side avoiding lamp"), "{avoiding}");
    let side = |s: &str| s.split(' ').next().unwrap_or("").to_string();
    assert_ne!(side(&passing), side(&avoiding), "{passing} / {avoiding}");
}

/// Issue 35 item 8: "stay close to all the dressers" is one near term per member; `near(set)`
/// stays one term measured to the nearest member.
#[test]
fn near_each_is_one_near_term_per_member_with_the_same_scopes() {
    let constraints = |pref: &str| {
        let src = format!(
            "route {{ go objects(fridge).only() {{ prefer {pref} within rooms(bedroom).only() }} }}"
        );
        let parsed = m2rc_grammar::parse(&src);
        assert!(parsed.is_ok(), "{:?}", parsed.errors);
        let map = two_rooms();
        let q = MapQuery::new(&map);
        let g = ground(&parsed.program, &src, &q, &GroundOptions::default());
        assert!(
            g.problems.iter().all(|p| !p.is_error()),
            "{:#?}",
            g.problems
        );
        g.ir.expect("ir").constraints
    };
    let each = constraints("near_each(objects(bed | lamp))");
    assert_eq!(each.len(), 2);
    let labels: Vec<String> = each
        .iter()
        .map(|c| match &c.kind {
            crate::ir::ConstraintKind::Near { reference } => reference.label.clone(),
            other => panic!("{other:?}"),
        })
        .collect();
    assert!(
        labels[0].starts_with("bed #1") && labels[1].starts_with("lamp #2"),
        "{labels:?}"
    );
    for c in &each {
        assert_eq!(c.stage_scope, crate::ir::StageScope::Stages(vec![0]));
        assert!(
            matches!(&c.spatial_scope, Some(p) if matches!(p.kind, PlaceKind::Room { id: 1, .. }))
        );
    }
    assert_eq!(constraints("near(objects(bed | lamp))").len(), 1);
}
