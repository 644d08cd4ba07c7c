//! A 20×20 hand-built map at 0.1 m per cell, small enough to reason about by hand in the tests of
//! the query semantics and of grounding (the demo house is larger and owned by the map layer).
//!
//! Bedroom (room 1) is columns 0..=8, kitchen (room 2) columns 10..=19; column 9 is a wall with a
//! single unlabelled door cell at row 8. Objects (id: rows × cols):
//! 1 bed 2..=4 × 2..=5 (0.5 m high), 2 lamp 3 × 7, 3 book 3 × 3..=4 on the bed (no parent record),
//! 4 shelf 2..=3 × 2..=3 hanging at 1.5 m, 5 chair 10..=11 × 3..=4, 6 rug 7 × 3..=4 (flat, free),
//! 7 plant 15 × 2, 8 fridge 2..=3 × 16..=17, 9 table 12..=14 × 12..=15, 10 cup 13 × 13 on the table.

use crate::grid::{Cell, Grid};
use crate::map::{FREE, GridFrame, OBSTACLE, Object, Room, SemanticMap};

fn rect(r0: u32, r1: u32, c0: u32, c1: u32) -> Vec<Cell> {
    let mut v = Vec::new();
    for r in r0..=r1 {
        for c in c0..=c1 {
            v.push(Cell::new(r, c));
        }
    }
    v
}

fn object(id: u32, category: &str, cells: Vec<Cell>, elev: f64, height: f64, room: u32) -> Object {
    let center = super::MapQuery::centroid(&cells).unwrap_or([0.0, 0.0]);
    Object {
        id,
        category: category.into(),
        name: format!("{category}_{id}"),
        footprint: cells,
        center,
        elevation_m: Some(elev),
        height_m: Some(height),
        room: Some(room),
        parent: None,
        attributes: vec![],
    }
}

pub fn two_rooms() -> SemanticMap {
    let n = 20;
    let mut occupancy = Grid::new(n, FREE);
    let mut room_layer = Grid::new(n, 0u32);
    let mut object_layer = Grid::new(n, 0u32);
    for r in 0..n as u32 {
        for c in 0..n as u32 {
            let cell = Cell::new(r, c);
            match c {
                0..=8 => room_layer.set(cell, 1),
                9 => {
                    if r != 8 {
                        occupancy.set(cell, OBSTACLE);
                    }
                }
                _ => room_layer.set(cell, 2),
            }
        }
    }
    let objects = vec![
        object(1, "bed", rect(2, 4, 2, 5), 0.0, 0.5, 1),
        object(2, "lamp", rect(3, 3, 7, 7), 0.0, 1.2, 1),
        object(3, "book", rect(3, 3, 3, 4), 0.5, 0.05, 1),
        object(4, "shelf", rect(2, 3, 2, 3), 1.5, 0.3, 1),
        object(5, "chair", rect(10, 11, 3, 4), 0.0, 0.9, 1),
        object(6, "rug", rect(7, 7, 3, 4), 0.0, 0.01, 1),
        object(7, "house_plant", rect(15, 15, 2, 2), 0.0, 0.6, 1),
        object(8, "fridge", rect(2, 3, 16, 17), 0.0, 1.8, 2),
        object(9, "dining_table", rect(12, 14, 12, 15), 0.0, 0.75, 2),
        object(10, "cup", rect(13, 13, 13, 13), 0.75, 0.1, 2),
    ];
    for o in &objects {
        for &c in &o.footprint {
            if o.category != "rug" && o.category != "shelf" {
                occupancy.set(c, OBSTACLE);
            }
            object_layer.set(c, o.id);
        }
    }
    let room = |id: u32, category: &str, area_m2: f64| Room {
        id,
        category: category.into(),
        name: format!("{category}_{id}"),
        area_m2,
        attributes: vec![],
    };
    SemanticMap {
        map_id: "test/two_rooms".into(),
        frame: GridFrame {
            resolution: 0.1,
            x_min: 0.0,
            z_min: 0.0,
        },
        occupancy,
        room_layer,
        object_layer,
        rooms: vec![room(1, "bedroom", 1.8), room(2, "kitchen", 2.0)],
        objects,
        start: Some(Cell::new(18, 2)),
        open_boundaries: Vec::new(),
    }
}
