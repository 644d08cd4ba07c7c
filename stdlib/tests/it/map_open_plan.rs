//! Doors cut along their own wall face, open (`"empty"`) walls as passages, the open-plan area,
//! and the importer's checks, on small synthetic houses whose answers are known by hand.

use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::import::check::check_house;
use m2rc_stdlib::import::{ImportOptions, import_house_document, import_warnings};
use m2rc_stdlib::map::{MapDocument, read_map_document_json, write_map_document_json};
use m2rc_stdlib::query::{MapQuery, PassageKind, open_area};
use serde_json::{Value, json};

fn face(id: &str, room: &str, a: [f64; 2], b: [f64; 2], empty: bool) -> Value {
    let mut w = json!({
        "id": id,
        "roomId": room,
        "polygon": [
            {"x": a[0], "y": 0, "z": a[1]},
            {"x": b[0], "y": 0, "z": b[1]},
            {"x": a[0], "y": 2.5, "z": a[1]},
            {"x": b[0], "y": 2.5, "z": b[1]},
        ],
    });
    if empty {
        w["empty"] = json!(true);
    }
    w
}

/// Two 4 x 3 m rooms, room|1 (z 0..3) below room|2 (z 3..6), sharing the wall z = 3. Room 2's face
/// of it is listed first and runs +x; room 1's face runs -x (from x = 4 to x = 0), so a hole
/// measured along room 1's face from x = 4 is mirrored if measured along room 2's.
fn two_rooms(shared_empty: bool, with_shared: bool) -> Value {
    let mut walls = vec![];
    if with_shared {
        walls.push(face(
            "wall|2|0.00|3.00|4.00|3.00",
            "room|2",
            [0.0, 3.0],
            [4.0, 3.0],
            shared_empty,
        ));
        walls.push(face(
            "wall|1|0.00|3.00|4.00|3.00",
            "room|1",
            [4.0, 3.0],
            [0.0, 3.0],
            shared_empty,
        ));
    }
    for (id, room, a, b) in [
        (
            "wall|1|0.00|0.00|4.00|0.00",
            "room|1",
            [0.0, 0.0],
            [4.0, 0.0],
        ),
        (
            "wall|1|4.00|0.00|4.00|3.00",
            "room|1",
            [4.0, 0.0],
            [4.0, 3.0],
        ),
        (
            "wall|1|0.00|0.00|0.00|3.00",
            "room|1",
            [0.0, 3.0],
            [0.0, 0.0],
        ),
        (
            "wall|2|4.00|3.00|4.00|6.00",
            "room|2",
            [4.0, 3.0],
            [4.0, 6.0],
        ),
        (
            "wall|2|0.00|6.00|4.00|6.00",
            "room|2",
            [4.0, 6.0],
            [0.0, 6.0],
        ),
        (
            "wall|2|0.00|3.00|0.00|6.00",
            "room|2",
            [0.0, 6.0],
            [0.0, 3.0],
        ),
    ] {
        walls.push(face(id, room, a, b, false));
    }
    let poly = |z0: f64, z1: f64| {
        json!([{"x": 0, "y": 0, "z": z0}, {"x": 4, "y": 0, "z": z0},
               {"x": 4, "y": 0, "z": z1}, {"x": 0, "y": 0, "z": z1}])
    };
    json!({
        "rooms": [
            {"id": "room|1", "roomType": "Kitchen", "floorPolygon": poly(0.0, 3.0)},
            {"id": "room|2", "roomType": "LivingRoom", "floorPolygon": poly(3.0, 6.0)},
        ],
        "walls": walls,
        "doors": [],
        "windows": [],
        "objects": [],
        "metadata": {"agent": {"position": {"x": 2.0, "y": 0.9, "z": 1.5},
                               "rotation": {"x": 0, "y": 90, "z": 0}}},
    })
}

fn with_door(mut h: Value, along: [f64; 2]) -> Value {
    h["doors"] = json!([{
        "id": "door|1|2", "assetId": "Doorway_1", "room0": "room|1", "room1": "room|2",
        "wall0": "wall|1|0.00|3.00|4.00|3.00", "wall1": "wall|2|0.00|3.00|4.00|3.00",
        "holePolygon": [{"x": along[0], "y": 0, "z": 0}, {"x": along[1], "y": 2.1, "z": 0}],
    }]);
    h
}

fn import(h: &Value) -> MapDocument {
    import_house_document(h, "house.json", None, &ImportOptions::default())
        .unwrap_or_else(|e| panic!("{e}"))
}

fn import_err(h: &Value) -> String {
    import_house_document(h, "house.json", None, &ImportOptions::default())
        .err()
        .map(|e| e.to_string())
        .unwrap_or_else(|| panic!("imported without an error"))
}

#[test]
fn door_is_cut_along_its_own_face() {
    // 0.5..1.5 m along room 1's face, which starts at x = 4 and runs -x: world x 2.5..3.5.
    let doc = import(&with_door(two_rooms(false, true), [0.5, 1.5]));
    let map = &doc.map;
    let door = map
        .objects
        .iter()
        .find(|o| o.category == "doorway")
        .unwrap();
    let xs: Vec<f64> = door
        .footprint
        .iter()
        .map(|&c| map.cell_to_world(c).0)
        .collect();
    let (lo, hi) = xs
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    assert!(
        (lo - 2.5).abs() < 0.051 && (hi - 3.5).abs() < 0.051,
        "door spans x {lo}..{hi}"
    );
    // The wall is open there and solid at the mirrored place.
    let walls: Vec<Cell> = map
        .objects
        .iter()
        .filter(|o| o.category == "wall")
        .flat_map(|o| o.footprint.clone())
        .collect();
    let at = |x: f64| map.world_to_cell(x, 3.0).unwrap();
    assert!(!walls.contains(&at(3.0)));
    assert!(walls.contains(&at(1.0)));
    // The rooms are joined through the door and the check is clean.
    let q = MapQuery::new(map);
    assert_eq!(q.adjacent_rooms(1), vec![2]);
    assert!(q.passages().iter().all(|p| p.kind == PassageKind::Door));
    let report = check_house(&with_door(two_rooms(false, true), [0.5, 1.5]), "h", map).unwrap();
    assert!(report.is_clean(), "{report:?}");
    assert_eq!(report.holes, 1);
    assert_eq!(report.connected_rooms, vec![1, 2]);
    assert!(
        import_warnings(&doc).is_empty(),
        "{:?}",
        import_warnings(&doc)
    );
}

#[test]
fn mirrored_hole_is_reported_by_the_check() {
    // The house as imported, checked against a house whose door sits elsewhere along the face:
    // the check measures from the face, so it sees the difference.
    let doc = import(&with_door(two_rooms(false, true), [0.5, 1.5]));
    let moved = with_door(two_rooms(false, true), [2.5, 3.5]);
    let report = check_house(&moved, "h", &doc.map).unwrap();
    assert_eq!(report.misplaced_holes.len(), 1, "{report:?}");
    assert!((report.misplaced_holes[0].offset_m - 2.0).abs() < 0.06);
}

#[test]
fn empty_wall_is_an_open_passage() {
    let h = two_rooms(true, true);
    let doc = import(&h);
    let map = &doc.map;
    assert_eq!(map.open_boundaries.len(), 1);
    assert_eq!(map.open_boundaries[0].rooms, (1, 2));
    // No wall object stands on the open boundary, and cells across it are free.
    assert!(
        map.objects
            .iter()
            .filter(|o| o.category == "wall")
            .all(|o| !o.footprint.contains(&map.world_to_cell(2.0, 3.0).unwrap()))
    );
    assert!(map.is_free(map.world_to_cell(2.0, 3.0).unwrap()));
    let q = MapQuery::new(map);
    assert_eq!(q.adjacent_rooms(1), vec![2]);
    assert!(!q.passages().is_empty());
    assert!(q.passages().iter().all(|p| p.kind == PassageKind::Open));
    assert_eq!(q.open_area(1), vec![1, 2]);
    assert_eq!(open_area(map, 2), vec![1, 2]);
    assert_eq!(map.room_links(), vec![(1, 2, PassageKind::Open)]);
    // Room labels stay as they are: both rooms keep their cells.
    assert!(!map.room_cells(1).is_empty() && !map.room_cells(2).is_empty());
    let report = check_house(&h, "h", map).unwrap();
    assert!(report.is_clean(), "{report:?}");
    assert!(report.unreachable_rooms.is_empty());
    // The open boundary survives the map JSON.
    let bytes = write_map_document_json(&doc);
    let back = read_map_document_json(&bytes, "m.json").unwrap();
    assert_eq!(back.map.open_boundaries, map.open_boundaries);
    assert_eq!(write_map_document_json(&back), bytes);
}

#[test]
fn solid_wall_without_door_keeps_rooms_apart() {
    let h = two_rooms(false, true);
    let doc = import(&h);
    let q = MapQuery::new(&doc.map);
    assert!(q.adjacent_rooms(1).is_empty());
    assert_eq!(q.open_area(1), vec![1]);
    // The start's room is the only connected one; nothing leaks.
    let report = check_house(&h, "h", &doc.map).unwrap();
    assert!(report.is_clean(), "{report:?}");
    assert_eq!(report.connected_rooms, vec![1]);
}

#[test]
fn missing_wall_leaks_and_is_reported() {
    // The shared wall is not listed at all: the floors touch, with no door and no open wall.
    let h = two_rooms(false, false);
    let doc = import(&h);
    let report = check_house(&h, "h", &doc.map).unwrap();
    assert_eq!(report.leaks, vec![(1, 2)]);
    let w = import_warnings(&doc);
    assert!(
        w.iter()
            .any(|w| w.contains("kitchen_1 and living_room_1 are joined")),
        "{w:?}"
    );
}

#[test]
fn door_too_narrow_for_the_robot_is_reported_unreachable() {
    // A 0.25 m opening: the 0.2 m robot radius closes it, so room 2 is connected but unreachable.
    let h = with_door(two_rooms(false, true), [0.5, 0.75]);
    let doc = import(&h);
    let report = check_house(&h, "h", &doc.map).unwrap();
    assert_eq!(report.connected_rooms, vec![1, 2]);
    assert_eq!(report.unreachable_rooms, vec![2], "{report:?}");
    assert!(
        import_warnings(&doc)
            .iter()
            .any(|w| w.contains("living_room_1 is connected to the start's room")),
        "{:?}",
        import_warnings(&doc)
    );
    // A wide door lets the robot through.
    let h = with_door(two_rooms(false, true), [0.5, 1.5]);
    let doc = import(&h);
    let reach = m2rc_stdlib::import::check::rooms_reachable_from(&doc.map, doc.map.start.unwrap());
    assert!(reach.contains(&2));
}

#[test]
fn input_errors_name_the_field() {
    // A door on a wall the house does not have.
    let mut h = with_door(two_rooms(false, true), [0.5, 1.5]);
    h["doors"][0]["wall0"] = json!("wall|1|9.00|9.00|9.00|12.00");
    let e = import_err(&h);
    assert!(
        e.contains("doors[0].wall0: names no wall of the house"),
        "{e}"
    );

    // A room with zero area.
    let mut h = two_rooms(false, true);
    h["rooms"][1]["floorPolygon"] = json!([{"x": 0, "z": 3}, {"x": 4, "z": 3}, {"x": 2, "z": 3}]);
    let e = import_err(&h);
    assert!(
        e.contains("rooms[1].floorPolygon: encloses no floor (zero area)"),
        "{e}"
    );

    // A hole entirely beyond its wall.
    let e = import_err(&with_door(two_rooms(false, true), [5.0, 6.0]));
    assert!(
        e.contains("doors[0].holePolygon: spans 5.00..6.00 m along wall"),
        "{e}"
    );

    // Far-out coordinates.
    for big in [1e20, 1e300] {
        let mut h = two_rooms(false, true);
        h["rooms"][0]["floorPolygon"][2]["x"] = json!(big);
        let e = import_err(&h);
        assert!(
            e.contains("rooms[0].floorPolygon[2].x:") && e.contains("beyond"),
            "{e}"
        );
    }

    // A house within the cell cap that needs more memory than allowed.
    let mut h = two_rooms(false, true);
    h["rooms"][0]["floorPolygon"][2]["x"] = json!(500.0);
    let e = import_err(&h);
    assert!(
        e.contains("more than the 4.0 GB memory limit") && e.contains("--max-memory"),
        "{e}"
    );
    let opts = ImportOptions {
        resolution: 0.5,
        ..ImportOptions::default()
    };
    assert!(import_house_document(&h, "h", None, &opts).is_ok());
}

#[test]
fn usable_oddities_are_warnings() {
    // A hole reaching past its wall's end is cut to the end.
    let doc = import(&with_door(two_rooms(false, true), [3.5, 4.6]));
    let w = import_warnings(&doc);
    assert!(
        w.iter()
            .any(|w| w.starts_with("doors[0].holePolygon: spans 3.50..4.60 m")),
        "{w:?}"
    );

    // rotation null, an object outside the house, a start outside the house.
    let mut h = two_rooms(false, true);
    h["objects"] = json!([
        {"id": "Chair|1", "assetId": "Chair_1", "objectType": "Chair",
         "position": {"x": 1.0, "y": 0.4, "z": 1.0}, "rotation": null},
        {"id": "Chair|2", "assetId": "Chair_2", "objectType": "Chair",
         "position": {"x": 9.0, "y": 0.4, "z": 1.0}, "rotation": {"x": 0, "y": 0, "z": 0}},
    ]);
    h["metadata"]["agent"]["position"]["x"] = json!(-0.8);
    let doc = import(&h);
    let w = import_warnings(&doc);
    let has = |s: &str| w.iter().any(|w| w.starts_with(s));
    assert!(has("objects[0].rotation: is null"), "{w:?}");
    assert!(
        has("objects[1].position: Chair|2 at (9.00, 1.00) is outside"),
        "{w:?}"
    );
    assert!(
        has("metadata.agent.position: (-0.80, 1.50) is outside every room"),
        "{w:?}"
    );
    assert!(doc.map.start.is_some());
    h["metadata"]["agent"]["position"]["x"] = json!(-40.0);
    let doc = import(&h);
    assert!(doc.map.start.is_none());
    assert!(
        import_warnings(&doc)
            .iter()
            .any(|w| w.contains("outside the map's grid; the map has no start"))
    );
}
