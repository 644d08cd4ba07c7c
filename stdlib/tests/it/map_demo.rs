//! The built-in demo house: what the documentation promises about it, and that it loads through
//! the same entry point as files.

use m2rc_stdlib::demo::demo_map;
use m2rc_stdlib::load::load_map;
use m2rc_stdlib::map::{Relation, read_map_json, vocab, write_map_json};

#[test]
fn demo_has_rooms_doors_and_relations() {
    let map = demo_map().unwrap();
    let cats: Vec<&str> = map.rooms.iter().map(|r| r.category.as_str()).collect();
    assert_eq!(
        cats,
        [
            "living_room",
            "kitchen",
            "bedroom",
            "bathroom",
            "bedroom",
            "bedroom",
            "bathroom"
        ]
    );
    let total: f64 = map.rooms.iter().map(|r| r.area_m2).sum();
    assert!((total - 120.0).abs() < 1e-9, "12 x 10 m house, got {total}");
    // Doors join the living room to four rooms, the kitchen to bedroom 3, bedroom 2 to bathroom 2.
    assert_eq!(
        map.room_adjacency(),
        vec![(1, 2), (1, 3), (1, 4), (1, 5), (2, 6), (5, 7)]
    );
    let rel = |child: &str, parent: &str, relation: Relation| {
        map.objects.iter().any(|o| {
            o.category == child
                && o.parent.is_some_and(|p| {
                    p.relation == relation && map.object(p.id).unwrap().category == parent
                })
        })
    };
    assert!(rel("mug", "microwave", Relation::Inside));
    assert!(rel("egg", "fridge", Relation::Inside));
    assert!(rel("microwave", "counter_top", Relation::On));
    assert!(rel("apple", "bowl", Relation::On));
    assert!(rel("cloth", "dresser", Relation::Inside));
    assert!(rel("box", "dresser", Relation::On));
    assert!(rel("sink_basin", "sink", Relation::Inside));
    assert_eq!(
        map.objects
            .iter()
            .filter(|o| o.category == "window")
            .count(),
        6
    );
    assert!(
        map.objects
            .iter()
            .all(|o| !o.footprint.is_empty() && o.room.is_some())
    );
    // Every category is a benchmark category.
    for o in &map.objects {
        assert!(
            vocab::is_benchmark_object_category(&o.category),
            "{}",
            o.category
        );
    }
    // The start is free, and every room has free space reachable through its doors.
    let start = map.start.unwrap();
    assert!(map.is_free(start));
    assert_eq!(map.room_at(start), 1);
    let reach = reachable(&map, start);
    for r in &map.rooms {
        assert!(
            map.room_cells(r.id)
                .iter()
                .any(|c| reach[map.occupancy.index(*c)]),
            "room {} unreachable",
            r.name
        );
    }
}

fn reachable(map: &m2rc_stdlib::map::SemanticMap, start: m2rc_stdlib::grid::Cell) -> Vec<bool> {
    let n = map.n();
    let mut seen = vec![false; n * n];
    let mut stack = vec![start];
    seen[map.occupancy.index(start)] = true;
    while let Some(c) = stack.pop() {
        for (dr, dc) in [(0i64, 1i64), (0, -1), (1, 0), (-1, 0)] {
            let (r, col) = (c.row as i64 + dr, c.col as i64 + dc);
            if map.occupancy.contains(r, col) {
                let nc = m2rc_stdlib::grid::Cell::new(r as u32, col as u32);
                let i = map.occupancy.index(nc);
                if !seen[i] && map.is_free(nc) {
                    seen[i] = true;
                    stack.push(nc);
                }
            }
        }
    }
    seen
}

#[test]
fn demo_loads_by_name_and_round_trips() {
    let map = load_map("demo").unwrap();
    assert_eq!(map.map_id, "demo");
    let bytes = write_map_json(&map);
    let back = read_map_json(&bytes, "demo.json").unwrap();
    assert_eq!(back, map);
    assert_eq!(write_map_json(&back), bytes);
}

#[test]
fn missing_files_are_errors() {
    let e = load_map("/nonexistent/house.json").unwrap_err().to_string();
    assert!(e.starts_with("/nonexistent/house.json: cannot read"), "{e}");
}
