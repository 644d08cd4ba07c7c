//! The compact scene catalog Direct ID's model reads: every room and every object of the map
//! under a stable id (`room_<id>`, `object_<id>`, `task_start`), with where it is and how big,
//! and which rooms share passages. It replaces the program's queries: the model picks ids here
//! instead of describing how to find them, so the catalog is all it knows of the map.
//!
//! Minified JSON in a fixed key order (the reference's `schema_version: 1` layout); numbers are
//! rounded to one decimal so the prompt is the same bytes on every machine.

use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::{MapQuery, Target};
use serde_json::{Value, json};
use std::collections::BTreeMap;

/// The catalog id of the route's start.
pub const START_ID: &str = "task_start";

pub fn room_id(id: u32) -> String {
    format!("room_{id}")
}

pub fn object_id(id: u32) -> String {
    format!("object_{id}")
}

fn round1(x: f64) -> f64 {
    (x * 10.0).round() / 10.0
}

fn centre_json(c: [f64; 2]) -> Value {
    json!([round1(c[0]), round1(c[1])])
}

/// `[r0, c0, r1, c1]`, inclusive; `None` for no cells.
fn bbox(cells: &[Cell]) -> Option<[u32; 4]> {
    let first = cells.first()?;
    let mut b = [first.row, first.col, first.row, first.col];
    for c in cells {
        b = [
            b[0].min(c.row),
            b[1].min(c.col),
            b[2].max(c.row),
            b[3].max(c.col),
        ];
    }
    Some(b)
}

/// The catalog of `q`'s map for a route starting at `start`.
pub fn compact_catalog(q: &MapQuery, start: Cell) -> Value {
    let map = q.map();
    let room_ref = |r: Option<u32>| match r {
        Some(r) if r != 0 && map.room(r).is_some() => json!(room_id(r)),
        _ => Value::Null,
    };
    let rooms: Vec<Value> = map
        .rooms
        .iter()
        .map(|r| {
            let cells = q.room_cells(r.id);
            json!({
                "id": room_id(r.id),
                "category": r.category,
                "center_grid": MapQuery::centroid(cells).map_or(Value::Null, centre_json),
                "bbox_grid": bbox(cells),
                "area_cells": cells.len(),
            })
        })
        .collect();
    let objects: Vec<Value> = map
        .objects
        .iter()
        .map(|o| {
            json!({
                "id": object_id(o.id),
                "category": o.category,
                "room_id": room_ref(o.room),
                "center_grid": centre_json(o.center),
                "bbox_grid": bbox(q.cells(Target::Object(o))),
                "footprint_cell_count": o.footprint.len(),
            })
        })
        .collect();
    let mut pairs: BTreeMap<(u32, u32), usize> = BTreeMap::new();
    for p in q.passages() {
        *pairs.entry(p.rooms).or_default() += 1;
    }
    let adjacency: Vec<Value> = pairs
        .iter()
        .filter(|((a, b), _)| *a != 0 && *b != 0)
        .map(|((a, b), n)| json!({"room_ids": [room_id(*a), room_id(*b)], "passage_count": n}))
        .collect();
    json!({
        "schema_version": 1,
        "coordinate_frame": {
            "type": "grid_row_col",
            "resolution_m": q.res(),
            "grid_size": map.n(),
        },
        "start": {
            "id": START_ID,
            "room_id": room_ref(Some(q.room_at(start))),
            "center_grid": [start.row, start.col],
        },
        "rooms": rooms,
        "objects": objects,
        "room_adjacency": adjacency,
    })
}
