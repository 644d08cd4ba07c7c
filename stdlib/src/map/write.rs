//! Writer of the Map2Route layered map JSON, streamed.
//!
//! The map is serialized straight from the model (layers row by row, one object at a time, the
//! per-cell object lists from one sorted vector) instead of through a `serde_json::Value` tree,
//! which cost about 250 bytes per grid cell and made fine-resolution maps of real houses run out
//! of memory. The same serializer builds the `Value` ([`write_map_value`]) and the text, so the
//! two cannot drift; the text is Python's `json.dump(..., indent=2)` layout (see `pyjson`).

use super::legend::build_legends;
use super::model::{MapDocument, MapExtra, Object, Relation, SemanticMap};
use super::open::open_boundaries_value;
use super::pyjson::{to_python_json, to_python_json_writer};
use crate::grid::{Cell, Grid};
use serde::ser::{Serialize, SerializeMap, SerializeSeq, Serializer};
use serde_json::{Map, Value, json};

/// Writes a map as Map2Route JSON bytes (no trailing newline, like Python's `json.dump`), with
/// metadata and legends generated from the model.
pub fn write_map_json(map: &SemanticMap) -> Vec<u8> {
    let extra = MapExtra::default();
    to_python_json(&MapSer { map, extra: &extra })
}

/// Writes a map document as Map2Route JSON bytes, carrying its extra content through.
pub fn write_map_document_json(doc: &MapDocument) -> Vec<u8> {
    to_python_json(&MapSer {
        map: &doc.map,
        extra: &doc.extra,
    })
}

/// [`write_map_document_json`] into a writer (a buffered file), without holding the text in
/// memory: what `m2rc map import` uses for large grids.
pub fn write_map_document_to<W: std::io::Write>(doc: &MapDocument, w: W) -> std::io::Result<()> {
    to_python_json_writer(
        &MapSer {
            map: &doc.map,
            extra: &doc.extra,
        },
        w,
    )
}

/// Builds the JSON of a map without extra content.
pub fn write_map_value(map: &SemanticMap) -> Value {
    let extra = MapExtra::default();
    serde_json::to_value(MapSer { map, extra: &extra }).unwrap_or(Value::Null)
}

/// Builds the JSON of a map document (key order and content as written to disk).
pub fn write_map_document(doc: &MapDocument) -> Value {
    serde_json::to_value(MapSer {
        map: &doc.map,
        extra: &doc.extra,
    })
    .unwrap_or(Value::Null)
}

pub(super) fn cell_value(c: Cell) -> Value {
    json!([c.row, c.col])
}

fn set_key(obj: &mut Map<String, Value>, key: &str, value: Value) {
    obj.insert(key.to_string(), value);
}

fn build_metadata(map: &SemanticMap, extra: &MapExtra) -> Map<String, Value> {
    let f = &map.frame;
    let n = map.n();
    let mut meta = extra.metadata.clone();
    set_key(&mut meta, "map_id", json!(map.map_id));
    let extent = (n.saturating_sub(1)) as f64 * f.resolution;
    match meta.get_mut("map_info") {
        Some(Value::Object(info)) => {
            set_key(info, "x_min", json!(f.x_min));
            set_key(info, "z_min", json!(f.z_min));
            set_key(info, "resolution", json!(f.resolution));
        }
        _ => {
            let info = json!({
                "x_min": f.x_min, "x_max": f.x_min + extent, "z_min": f.z_min, "z_max": f.z_min + extent,
                "resolution": f.resolution, "H": n, "W": n,
            });
            set_key(&mut meta, "map_info", info);
        }
    }
    let frame = json!({
        "index_order": "[row, col]", "row_axis": "world_z", "col_axis": "world_x",
        "resolution": f.resolution, "x_min": f.x_min, "z_min": f.z_min,
    });
    set_key(&mut meta, "grid_coordinate_frame", frame);
    match map.start {
        Some(c) => set_key(&mut meta, "start_grid", cell_value(c)),
        None => {
            meta.shift_remove("start_grid");
        }
    }
    meta
}

/// The keys written from the model, in the reference's order.
const WRITTEN: [&str; 9] = [
    "grid_size",
    "layer_legends",
    "metadata",
    "layers",
    "room_instances",
    "object_instances",
    "object_footprints",
    "cell_object_ids",
    "open_boundaries",
];

struct MapSer<'a> {
    map: &'a SemanticMap,
    extra: &'a MapExtra,
}

impl Serialize for MapSer<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let (map, extra) = (self.map, self.extra);
        let mut root = s.serialize_map(None)?;
        root.serialize_entry("grid_size", &map.n())?;
        root.serialize_entry("layer_legends", &build_legends(map, extra))?;
        root.serialize_entry("metadata", &Value::Object(build_metadata(map, extra)))?;
        root.serialize_entry("layers", &Layers(map))?;
        let rooms: Vec<Value> = map
            .rooms
            .iter()
            .map(|r| {
                let mut o = Map::new();
                set_key(&mut o, "id", json!(r.id));
                set_key(&mut o, "category", json!(r.category));
                set_key(&mut o, "name", json!(r.name));
                set_key(&mut o, "attributes", json!(r.attributes));
                set_key(&mut o, "area_m2", json!(r.area_m2));
                if let Some(extra) = extra.room_keys.get(&r.id) {
                    for (k, v) in extra {
                        o.entry(k.clone()).or_insert_with(|| v.clone());
                    }
                }
                Value::Object(o)
            })
            .collect();
        root.serialize_entry("room_instances", &rooms)?;
        root.serialize_entry("object_instances", &Objects(map, extra))?;
        root.serialize_entry("object_footprints", &Footprints(map, extra))?;
        root.serialize_entry("cell_object_ids", &CellIds(map))?;
        if !map.open_boundaries.is_empty() {
            root.serialize_entry("open_boundaries", &open_boundaries_value(map))?;
        }
        for (k, v) in &extra.top_level {
            if !WRITTEN.contains(&k.as_str()) {
                root.serialize_entry(k, v)?;
            }
        }
        root.end()
    }
}

struct Layers<'a>(&'a SemanticMap);

impl Serialize for Layers<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(3))?;
        m.serialize_entry("occupancy", &Layer(&self.0.occupancy))?;
        m.serialize_entry("room", &Layer(&self.0.room_layer))?;
        m.serialize_entry("object_instance", &Layer(&self.0.object_layer))?;
        m.end()
    }
}

struct Layer<'a, T>(&'a Grid<T>);

impl<T: Copy + Into<u64>> Serialize for Layer<'_, T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let n = self.0.n();
        let mut rows = s.serialize_seq(Some(n))?;
        for r in 0..n {
            rows.serialize_element(&Row(self.0.row(r)))?;
        }
        rows.end()
    }
}

struct Row<'a, T>(&'a [T]);

impl<T: Copy + Into<u64>> Serialize for Row<'_, T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut row = s.serialize_seq(Some(self.0.len()))?;
        for &v in self.0 {
            row.serialize_element(&v.into())?;
        }
        row.end()
    }
}

struct Objects<'a>(&'a SemanticMap, &'a MapExtra);

impl Serialize for Objects<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut seq = s.serialize_seq(Some(self.0.objects.len()))?;
        for o in &self.0.objects {
            seq.serialize_element(&object_value(self.1, o))?;
        }
        seq.end()
    }
}

struct Footprints<'a>(&'a SemanticMap, &'a MapExtra);

impl Serialize for Footprints<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(self.0.objects.len()))?;
        for o in &self.0.objects {
            m.serialize_entry(&o.id.to_string(), &Footprint(o, self.1))?;
        }
        m.end()
    }
}

struct Footprint<'a>(&'a Object, &'a MapExtra);

impl Serialize for Footprint<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let o = self.0;
        let mut f = s.serialize_map(None)?;
        f.serialize_entry("object_id", &o.id)?;
        f.serialize_entry("category", &o.category)?;
        f.serialize_entry("name", &o.name)?;
        f.serialize_entry("cells", &o.footprint)?;
        f.serialize_entry("center_grid", &json!(o.center))?;
        f.serialize_entry("room_id", &o.room)?;
        if let Some(src) = self
            .1
            .object_keys
            .get(&o.id)
            .and_then(|k| k.get("footprint_source"))
        {
            f.serialize_entry("footprint_source", src)?;
        }
        f.serialize_entry("num_grid_cells", &o.footprint.len())?;
        f.end()
    }
}

/// `cell_object_ids`: per covered cell (row-major), the ids of the objects covering it, larger
/// footprints first, then by id.
struct CellIds<'a>(&'a SemanticMap);

impl Serialize for CellIds<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        // (cell, larger footprint first, id): 16 bytes per footprint cell, sorted once.
        let mut all: Vec<(Cell, std::cmp::Reverse<u32>, u32)> =
            Vec::with_capacity(self.0.objects.iter().map(|o| o.footprint.len()).sum());
        for o in &self.0.objects {
            let size = std::cmp::Reverse(o.footprint.len() as u32);
            all.extend(o.footprint.iter().map(|&c| (c, size, o.id)));
        }
        all.sort_unstable();
        let mut m = s.serialize_map(None)?;
        let mut ids: Vec<u32> = Vec::new();
        let mut i = 0;
        while i < all.len() {
            let cell = all[i].0;
            ids.clear();
            while i < all.len() && all[i].0 == cell {
                if !ids.contains(&all[i].2) {
                    ids.push(all[i].2);
                }
                i += 1;
            }
            m.serialize_entry(&format!("{},{}", cell.row, cell.col), &ids)?;
        }
        m.end()
    }
}

fn object_value(extra: &MapExtra, o: &Object) -> Value {
    let mut v = Map::new();
    set_key(&mut v, "id", json!(o.id));
    set_key(&mut v, "category", json!(o.category));
    set_key(&mut v, "name", json!(o.name));
    set_key(&mut v, "attributes", json!(o.attributes));
    set_key(&mut v, "center_grid", json!(o.center));
    set_key(&mut v, "room_id", json!(o.room));
    set_key(&mut v, "num_grid_cells", json!(o.footprint.len()));
    if let Some(e) = o.elevation_m {
        set_key(&mut v, "elevation_m", json!(e));
    }
    if let Some(h) = o.height_m {
        set_key(&mut v, "height_m", json!(h));
    }
    if let Some(p) = o.parent {
        set_key(&mut v, "parent_id", json!(p.id));
        let rel = match p.relation {
            Relation::On => "on",
            Relation::Inside => "inside",
        };
        set_key(&mut v, "parent_relation", json!(rel));
    }
    if let Some(extra) = extra.object_keys.get(&o.id) {
        for (k, val) in extra {
            v.entry(k.clone()).or_insert_with(|| val.clone());
        }
    }
    Value::Object(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The streamed text, the in-memory text and the `Value` are one serialization.
    #[test]
    fn text_value_and_stream_agree() {
        let mut doc = crate::demo::demo_document(&crate::import::ImportOptions {
            resolution: 0.25,
            ..Default::default()
        })
        .unwrap();
        doc.map.open_boundaries = vec![crate::map::OpenBoundary {
            rooms: (1, 2),
            cells: vec![Cell::new(3, 4), Cell::new(3, 5)],
        }];
        let text = write_map_document_json(&doc);
        let mut streamed = Vec::new();
        write_map_document_to(&doc, &mut streamed).unwrap();
        assert_eq!(text, streamed);
        let parsed: Value = serde_json::from_slice(&text).unwrap();
        assert_eq!(parsed, write_map_document(&doc));
        let keys: Vec<&String> = parsed.as_object().unwrap().keys().collect();
        assert_eq!(keys.last().map(|k| k.as_str()), Some("open_boundaries"));
        // Per cell, larger footprints first, then by id.
        let ids = &parsed["cell_object_ids"];
        for (_, list) in ids.as_object().unwrap() {
            let list: Vec<u64> = list
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_u64().unwrap())
                .collect();
            let size = |id: u64| doc.map.object(id as u32).map_or(0, |o| o.footprint.len());
            assert!(
                list.windows(2)
                    .all(|w| size(w[0]) > size(w[1]) || (size(w[0]) == size(w[1]) && w[0] < w[1]))
            );
        }
    }
}
