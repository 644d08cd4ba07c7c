//! The semantic map model: what every part of m2rc knows about a building.
//!
//! It mirrors the Map2Route layered map (square grid, `[row][col]` layers, room and object instances)
//! and adds what the reference format lacks but the language needs: object heights and parent
//! relations (`on` / `inside`), and an optional start pose. Readers and writers of the Map2Route JSON
//! live in `map::format`; the ProcTHOR importer in `import`.

use crate::grid::{Cell, Grid};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Occupancy values, as in `layer_legends.occupancy` of the Map2Route maps.
pub const FREE: u8 = 0;
pub const OBSTACLE: u8 = 1;
pub const UNKNOWN: u8 = 2;

/// Where the grid sits in the world. `col = round((x - x_min) / resolution)`,
/// `row = round((z - z_min) / resolution)`; cell centres lie at `x_min + col * resolution`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GridFrame {
    /// Metres per cell (0.05 on the benchmark maps; 1.0 when a map does not say).
    pub resolution: f64,
    pub x_min: f64,
    pub z_min: f64,
}

/// How a child object relates to its parent object.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Relation {
    On,
    Inside,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Parent {
    pub id: u32,
    pub relation: Relation,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Room {
    /// Positive id, the value used in the room layer.
    pub id: u32,
    /// One of `bathroom`, `bedroom`, `kitchen`, `living_room`.
    pub category: String,
    pub name: String,
    /// Floor area in square metres (true polygon area when the source knows it).
    pub area_m2: f64,
    /// Free-form `key=value` attributes carried through from the source map.
    pub attributes: Vec<String>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// Positive id, the value used in the object layer; not necessarily contiguous.
    pub id: u32,
    /// Map2Route snake_case category (`arm_chair`, `counter_top`, `wall`, `doorway`, `window`, ...).
    pub category: String,
    pub name: String,
    /// Every cell the object covers, sorted and deduplicated (not only the cells it won in the layer).
    pub footprint: Vec<Cell>,
    /// Centre `[row, col]` in cell units (centroid of the footprint unless the source gives one).
    pub center: [f64; 2],
    /// Height of the object's bottom above the floor, metres, when known.
    pub elevation_m: Option<f64>,
    /// Height of the object itself, metres, when known.
    pub height_m: Option<f64>,
    /// The room the object belongs to (dominant room over its footprint), when any.
    pub room: Option<u32>,
    /// The object this one stands on or sits inside, when the source knows it.
    pub parent: Option<Parent>,
    pub attributes: Vec<String>,
}

/// A semantic map: the grid layers plus room and object instances.
#[derive(Clone, Debug, PartialEq)]
pub struct SemanticMap {
    /// Map key (`procthor/003_valunseen`, `demo`, ...).
    pub map_id: String,
    pub frame: GridFrame,
    /// 0 free, 1 obstacle, 2 unknown. Anything other than free is not traversable.
    pub occupancy: Grid<u8>,
    /// Room id per cell, 0 = none.
    pub room_layer: Grid<u32>,
    /// The single winning object id per cell, 0 = none.
    pub object_layer: Grid<u32>,
    /// Sorted by id.
    pub rooms: Vec<Room>,
    /// Sorted by id.
    pub objects: Vec<Object>,
    /// Where a robot starts when the map itself says (ProcTHOR agent pose, the demo house).
    pub start: Option<Cell>,
    /// Boundaries between two rooms with no wall at all (ProcTHOR's `"empty": true` walls, the
    /// open-plan kitchen and living room): passable like a doorway, drawn open, and what joins
    /// rooms into one open-plan area ([`crate::query::MapQuery::open_area`]). Sorted by rooms.
    pub open_boundaries: Vec<OpenBoundary>,
}

/// A boundary between two rooms that is left open: no wall, no door, just the line where one
/// room's floor meets the other's. The two rooms keep their own labels (as in Map2Route).
#[derive(Clone, Debug, PartialEq)]
pub struct OpenBoundary {
    /// The two rooms, smaller id first.
    pub rooms: (u32, u32),
    /// The cells along the boundary (where the wall would stand), sorted.
    pub cells: Vec<Cell>,
}

/// A map as read from or written to a file: the model plus the file content the model has no
/// field for, so that a map read and written again loses nothing. Code that only needs the map
/// uses [`SemanticMap`]; readers and writers that must round-trip use this.
#[derive(Clone, Debug, PartialEq)]
pub struct MapDocument {
    pub map: SemanticMap,
    pub extra: MapExtra,
}

/// Parts of a Map2Route map file that are carried through unchanged: the `metadata` block (with
/// `map_info` and the source's identity keys), the legends, unknown top-level keys, and unknown
/// keys of room and object instances.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MapExtra {
    /// The `metadata` object as read (or as built by an importer), in file order.
    pub metadata: serde_json::Map<String, serde_json::Value>,
    /// `layer_legends` as read; the writer regenerates legends when this is `None`.
    pub layer_legends: Option<serde_json::Value>,
    /// Top-level keys other than the Map2Route ones, in file order.
    pub top_level: serde_json::Map<String, serde_json::Value>,
    /// Per room id: instance keys the model has no field for.
    pub room_keys: BTreeMap<u32, serde_json::Map<String, serde_json::Value>>,
    /// Per object id: instance keys the model has no field for (`footprint_source`, ...).
    pub object_keys: BTreeMap<u32, serde_json::Map<String, serde_json::Value>>,
}

impl SemanticMap {
    /// Side length N of the square grid.
    pub fn n(&self) -> usize {
        self.occupancy.n()
    }

    pub fn resolution(&self) -> f64 {
        self.frame.resolution
    }

    pub fn is_free(&self, cell: Cell) -> bool {
        self.occupancy.get(cell) == Some(&FREE)
    }

    pub fn room(&self, id: u32) -> Option<&Room> {
        self.rooms
            .binary_search_by_key(&id, |r| r.id)
            .ok()
            .map(|i| &self.rooms[i])
    }

    pub fn object(&self, id: u32) -> Option<&Object> {
        self.objects
            .binary_search_by_key(&id, |o| o.id)
            .ok()
            .map(|i| &self.objects[i])
    }

    /// Cells whose room layer value is `id`, in row-major order.
    pub fn room_cells(&self, id: u32) -> Vec<Cell> {
        self.room_layer
            .iter_cells()
            .filter(|(_, v)| **v == id)
            .map(|(c, _)| c)
            .collect()
    }

    /// Room id at `cell` (0 outside every room or outside the grid).
    pub fn room_at(&self, cell: Cell) -> u32 {
        self.room_layer.get(cell).copied().unwrap_or(0)
    }

    /// Objects whose room is `id`, in id order.
    pub fn objects_in_room(&self, id: u32) -> impl Iterator<Item = &Object> {
        self.objects.iter().filter(move |o| o.room == Some(id))
    }

    /// Objects whose parent is `id`, in id order.
    pub fn children_of(&self, id: u32) -> impl Iterator<Item = &Object> {
        self.objects
            .iter()
            .filter(move |o| o.parent.map(|p| p.id) == Some(id))
    }

    /// Object count per category, sorted by category.
    pub fn category_counts(&self) -> BTreeMap<&str, usize> {
        let mut out = BTreeMap::new();
        for o in &self.objects {
            *out.entry(o.category.as_str()).or_insert(0) += 1;
        }
        out
    }

    /// Pairs of rooms `(a, b)` with `a < b` joined by a passage, sorted: free cells where the room
    /// label changes, directly or through a small unlabelled door patch. This is the one definition
    /// of adjacency, shared with the `.m2r` queries (`adjacent_to`, `doorways`) through
    /// [`crate::query::MapQuery::passages`]; walls without an opening do not join rooms.
    pub fn room_adjacency(&self) -> Vec<(u32, u32)> {
        let free = self.occupancy.map(|&o| o == FREE);
        let mut pairs: Vec<(u32, u32)> = crate::query::find_passages(self, &free)
            .into_iter()
            .map(|p| p.rooms)
            .collect();
        pairs.dedup();
        pairs
    }

    /// [`SemanticMap::room_adjacency`] with how each pair is joined: `Door` when some passage
    /// between them is a doorway, else `Open` (an open boundary only). Sorted by pair.
    pub fn room_links(&self) -> Vec<(u32, u32, crate::query::PassageKind)> {
        let free = self.occupancy.map(|&o| o == FREE);
        let mut out: Vec<(u32, u32, crate::query::PassageKind)> = Vec::new();
        for p in crate::query::find_passages(self, &free) {
            match out.last_mut() {
                Some(last) if (last.0, last.1) == p.rooms => last.2 = last.2.min(p.kind),
                _ => out.push((p.rooms.0, p.rooms.1, p.kind)),
            }
        }
        out
    }

    /// Rooms adjacent to `id` through a doorway or an open boundary, sorted.
    pub fn neighbours(&self, id: u32) -> Vec<u32> {
        let mut out: Vec<u32> = self
            .room_adjacency()
            .into_iter()
            .filter_map(|(a, b)| {
                if a == id {
                    Some(b)
                } else if b == id {
                    Some(a)
                } else {
                    None
                }
            })
            .collect();
        out.sort_unstable();
        out
    }

    /// Whether rooms `a` and `b` share an open boundary (no wall between them).
    pub fn open_between(&self, a: u32, b: u32) -> bool {
        let key = (a.min(b), a.max(b));
        self.open_boundaries.iter().any(|o| o.rooms == key)
    }

    /// World `(x, z)` of a cell centre, metres.
    pub fn cell_to_world(&self, cell: Cell) -> (f64, f64) {
        (
            self.frame.x_min + cell.col as f64 * self.frame.resolution,
            self.frame.z_min + cell.row as f64 * self.frame.resolution,
        )
    }

    /// The cell containing world `(x, z)` (Python's round-half-to-even, as the reference), or
    /// `None` outside the grid.
    pub fn world_to_cell(&self, x: f64, z: f64) -> Option<Cell> {
        let col = ((x - self.frame.x_min) / self.frame.resolution).round_ties_even();
        let row = ((z - self.frame.z_min) / self.frame.resolution).round_ties_even();
        let n = self.n() as f64;
        (row >= 0.0 && col >= 0.0 && row < n && col < n).then(|| Cell::new(row as u32, col as u32))
    }
}
