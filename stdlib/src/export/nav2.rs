//! A map written as a Nav2 map with its semantic layer: the `map_server` YAML, a PGM image and
//! the GeoJSON of `docs/maps.md` ("Nav2 import"). What `m2rc map export --to nav2` writes and
//! what the round-trip tests import back: rooms and objects travel as MultiPolygons of their
//! cells' row runs, so the import's cell-centre rule gives back exactly the same cells, and
//! objects are listed in the order that paints the object layer as it was.

use crate::grid::Cell;
use crate::map::frame::MapFrame;
use crate::map::{FREE, OBSTACLE, Relation, SemanticMap};
use serde_json::{Value, json};
use std::collections::{BTreeMap, BTreeSet};

/// The three files of a Nav2 map.
pub struct Nav2Files {
    pub yaml: String,
    pub pgm: Vec<u8>,
    pub geojson: Value,
}

/// `image` is the PGM's file name as the YAML should name it.
pub fn to_nav2(map: &SemanticMap, frame: &MapFrame, image: &str) -> Nav2Files {
    let n = map.n();
    let mut pgm = format!("P5\n{n} {n}\n255\n").into_bytes();
    for img_row in 0..n {
        let row = n - 1 - img_row;
        pgm.extend(map.occupancy.row(row).iter().map(|&o| match o {
            FREE => 254u8,
            OBSTACLE => 0,
            _ => 205,
        }));
    }
    let [ox, oy, yaw] = frame.origin;
    let yaml = format!(
        "image: {image}\nmode: trinary\nresolution: {}\norigin: [{ox}, {oy}, {yaw}]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
        frame.resolution
    );
    let mut features = Vec::new();
    let room_name: BTreeMap<u32, &str> =
        map.rooms.iter().map(|r| (r.id, r.name.as_str())).collect();
    for r in &map.rooms {
        let cells = map.room_cells(r.id);
        if cells.is_empty() {
            continue;
        }
        features.push(json!({
            "type": "Feature",
            "properties": {"kind": "room", "category": r.category, "name": r.name},
            "geometry": runs_geometry(frame, &cells),
        }));
    }
    for ob in &map.open_boundaries {
        let (Some(a), Some(b)) = (room_name.get(&ob.rooms.0), room_name.get(&ob.rooms.1)) else {
            continue;
        };
        if ob.cells.is_empty() {
            continue;
        }
        features.push(json!({
            "type": "Feature",
            "properties": {"kind": "open_boundary", "rooms": [a, b]},
            "geometry": runs_geometry(frame, &ob.cells),
        }));
    }
    let obj_name: BTreeMap<u32, &str> = map
        .objects
        .iter()
        .map(|o| (o.id, o.name.as_str()))
        .collect();
    for id in paint_order(map) {
        let Some(o) = map.object(id) else { continue };
        if o.footprint.is_empty() {
            continue;
        }
        let mut props = serde_json::Map::new();
        props.insert("kind".into(), json!("object"));
        props.insert("category".into(), json!(o.category));
        props.insert("name".into(), json!(o.name));
        if let Some(r) = o.room.and_then(|r| room_name.get(&r)) {
            props.insert("room".into(), json!(r));
        }
        if let Some(h) = o.height_m {
            props.insert("height".into(), json!(h));
        }
        if let Some(e) = o.elevation_m.filter(|e| *e >= 0.0) {
            props.insert("elevation".into(), json!(e));
        }
        if let Some(p) = o.parent
            && let Some(name) = obj_name.get(&p.id)
        {
            props.insert("parent".into(), json!(name));
            let rel = match p.relation {
                Relation::On => "on",
                Relation::Inside => "inside",
            };
            props.insert("parent_relation".into(), json!(rel));
        }
        features.push(json!({
            "type": "Feature",
            "id": o.id,
            "properties": props,
            "geometry": runs_geometry(frame, &o.footprint),
        }));
    }
    Nav2Files {
        yaml,
        pgm,
        geojson: json!({"type": "FeatureCollection", "features": features}),
    }
}

/// A MultiPolygon with one rectangle per run of consecutive cells in a row.
fn runs_geometry(frame: &MapFrame, cells: &[Cell]) -> Value {
    let mut sorted = cells.to_vec();
    sorted.sort_unstable();
    let mut polys = Vec::new();
    let mut i = 0;
    while i < sorted.len() {
        let (row, c0) = (sorted[i].row, sorted[i].col);
        let mut c1 = c0;
        while i + 1 < sorted.len() && sorted[i + 1].row == row && sorted[i + 1].col == c1 + 1 {
            i += 1;
            c1 += 1;
        }
        i += 1;
        let (r, a, b) = (row as f64, c0 as f64, c1 as f64 + 1.0);
        let ring: Vec<Value> = [(r, a), (r, b), (r + 1.0, b), (r + 1.0, a), (r, a)]
            .iter()
            .map(|&(rr, cc)| {
                let (x, y) = frame.corner_to_map(rr, cc);
                json!([x, y])
            })
            .collect();
        polys.push(json!([ring]));
    }
    json!({"type": "MultiPolygon", "coordinates": polys})
}

/// Object ids ordered so that painting their footprints in turn (later over earlier) gives the
/// map's object layer: every object that a cell's winner covers up comes before the winner.
fn paint_order(map: &SemanticMap) -> Vec<u32> {
    let mut covering: BTreeMap<Cell, Vec<u32>> = BTreeMap::new();
    for o in &map.objects {
        for &c in &o.footprint {
            covering.entry(c).or_default().push(o.id);
        }
    }
    let mut after: BTreeMap<u32, BTreeSet<u32>> = BTreeMap::new();
    let mut indegree: BTreeMap<u32, usize> = map.objects.iter().map(|o| (o.id, 0)).collect();
    for (cell, ids) in &covering {
        let winner = map.object_layer.get(*cell).copied().unwrap_or(0);
        for &id in ids {
            if id != winner && winner != 0 && after.entry(id).or_default().insert(winner) {
                *indegree.entry(winner).or_insert(0) += 1;
            }
        }
    }
    let mut ready: BTreeSet<u32> = indegree
        .iter()
        .filter(|(_, d)| **d == 0)
        .map(|(i, _)| *i)
        .collect();
    let mut out = Vec::new();
    while let Some(id) = ready.pop_first() {
        out.push(id);
        for w in after.get(&id).into_iter().flatten() {
            let d = indegree.get_mut(w).expect("known object");
            *d -= 1;
            if *d == 0 {
                ready.insert(*w);
            }
        }
    }
    // A cycle cannot come from one winner per cell under a total order; keep the rest anyway.
    let seen: BTreeSet<u32> = out.iter().copied().collect();
    out.extend(
        map.objects
            .iter()
            .map(|o| o.id)
            .filter(|i| !seen.contains(i)),
    );
    out
}
