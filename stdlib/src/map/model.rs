//! The semantic map model: what every part of m2rc knows about a building.
//!
//! It mirrors the Map2Route layered map (square grid, `[row][col]` layers, room and object instances)
//! and adds what the reference format lacks but the language needs: object heights and parent
//! relations (`on` / `inside`), and an optional start pose. Readers and writers of the Map2Route JSON
//! live in `map::format`; the ProcTHOR importer in `import`.

use crate::grid::{Cell, Grid};
use serde::{Deserialize, Serialize};

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
        self.rooms.binary_search_by_key(&id, |r| r.id).ok().map(|i| &self.rooms[i])
    }

    pub fn object(&self, id: u32) -> Option<&Object> {
        self.objects.binary_search_by_key(&id, |o| o.id).ok().map(|i| &self.objects[i])
    }
}
