//! The spatial semantics of the `.m2r` built-ins over a [`SemanticMap`], in metres.
//!
//! A [`MapQuery`] indexes one map once (traversable grid, room cells, passages between rooms, object
//! boundaries) so that each query touches only the cells involved, which is what keeps grounding a
//! whole program within a few milliseconds on the largest houses. Every relation is defined on
//! footprints (all the cells an object covers), not on centres as in the Map2Route reference; the
//! definitions, thresholds and the differences from the reference are listed in `docs/semantics.md`.

mod distance;
mod regions;
mod relations;
mod rooms;
mod route;

pub use distance::TravelField;
pub use regions::{WaypointShape, loop_waypoints};
pub use relations::Thresholds;
pub use rooms::Passage;
pub use route::{RoomVisit, nominal_path, room_visits};

use crate::grid::{Cell, Grid};
use crate::map::{Object, SemanticMap};

/// Anything with cells that a query can measure: an object footprint, a room, a region.
#[derive(Clone, Copy, Debug)]
pub enum Target<'a> {
    Object(&'a Object),
    Room(u32),
    /// Explicit cells (a region), sorted.
    Cells(&'a [Cell]),
}

/// One map, indexed for queries. Build once per map and share it between groundings.
pub struct MapQuery<'m> {
    map: &'m SemanticMap,
    traversable: Grid<bool>,
    /// Cells of each room, indexed like `map.rooms`, sorted.
    room_cells: Vec<Vec<Cell>>,
    /// Cells of each object's footprint that touch a cell outside it, indexed like `map.objects`.
    boundaries: Vec<Vec<Cell>>,
    passages: Vec<Passage>,
    pub thresholds: Thresholds,
}

impl<'m> MapQuery<'m> {
    pub fn new(map: &'m SemanticMap) -> Self {
        let traversable = map.occupancy.map(|&v| v == crate::map::FREE);
        let mut room_cells = vec![Vec::new(); map.rooms.len()];
        for (cell, &label) in map.room_layer.iter_cells() {
            if label != 0
                && let Ok(i) = map.rooms.binary_search_by_key(&label, |r| r.id)
            {
                room_cells[i].push(cell);
            }
        }
        let boundaries = map.objects.iter().map(|o| boundary(&o.footprint)).collect();
        let passages = rooms::find_passages(map, &traversable);
        MapQuery {
            map,
            traversable,
            room_cells,
            boundaries,
            passages,
            thresholds: Thresholds::default(),
        }
    }

    pub fn map(&self) -> &'m SemanticMap {
        self.map
    }

    pub fn traversable(&self) -> &Grid<bool> {
        &self.traversable
    }

    pub fn is_traversable(&self, cell: Cell) -> bool {
        self.traversable.get(cell).copied().unwrap_or(false)
    }

    /// Metres per cell.
    pub fn res(&self) -> f64 {
        let r = self.map.frame.resolution;
        if r.is_finite() && r > 0.0 { r } else { 1.0 }
    }

    /// All cells of a room (traversable or not); empty for an unknown id.
    pub fn room_cells(&self, room: u32) -> &[Cell] {
        match self.map.rooms.binary_search_by_key(&room, |r| r.id) {
            Ok(i) => &self.room_cells[i],
            Err(_) => &[],
        }
    }

    /// The cells a target covers.
    pub fn cells<'a>(&'a self, t: Target<'a>) -> &'a [Cell] {
        match t {
            Target::Object(o) => &o.footprint,
            Target::Room(r) => self.room_cells(r),
            Target::Cells(c) => c,
        }
    }

    /// The cells that can be closest to something outside: an object's boundary, else all cells.
    fn outline<'a>(&'a self, t: Target<'a>) -> &'a [Cell] {
        match t {
            Target::Object(o) => match self.map.objects.binary_search_by_key(&o.id, |x| x.id) {
                Ok(i) if !self.boundaries[i].is_empty() => &self.boundaries[i],
                _ => &o.footprint,
            },
            _ => self.cells(t),
        }
    }

    /// The room label of a cell (0 = none).
    pub fn room_at(&self, cell: Cell) -> u32 {
        self.map.room_layer.get(cell).copied().unwrap_or(0)
    }

    /// Mean of the cells, `[row, col]` in cell units; `None` for no cells.
    pub fn centroid(cells: &[Cell]) -> Option<[f64; 2]> {
        if cells.is_empty() {
            return None;
        }
        let (mut r, mut c) = (0.0, 0.0);
        for x in cells {
            r += x.row as f64;
            c += x.col as f64;
        }
        let n = cells.len() as f64;
        Some([r / n, c / n])
    }

    /// Cells within `radius_cells` of the point, clipped to the grid, sorted.
    pub fn disk(&self, center: [f64; 2], radius_cells: f64) -> Vec<Cell> {
        let n = self.map.n() as i64;
        let r = radius_cells.max(0.0);
        let (r0, r1) = (
            (center[0] - r).floor() as i64,
            (center[0] + r).ceil() as i64,
        );
        let (c0, c1) = (
            (center[1] - r).floor() as i64,
            (center[1] + r).ceil() as i64,
        );
        let mut out = Vec::new();
        for row in r0.max(0)..=r1.min(n - 1) {
            for col in c0.max(0)..=c1.min(n - 1) {
                let (dr, dc) = (row as f64 - center[0], col as f64 - center[1]);
                if dr * dr + dc * dc <= r * r + 1e-9 {
                    out.push(Cell::new(row as u32, col as u32));
                }
            }
        }
        out
    }

    /// The traversable cell nearest to the point (ties by row, then col), searching outward ring by
    /// ring and restricted to `allowed` when given; `None` when no such cell exists.
    pub fn nearest_traversable(&self, point: [f64; 2], allowed: Option<u32>) -> Option<Cell> {
        self.nearest_traversable_where(point, allowed, |_| true)
    }

    /// [`MapQuery::nearest_traversable`] among the cells that also pass `keep`.
    pub fn nearest_traversable_where(
        &self,
        point: [f64; 2],
        allowed: Option<u32>,
        keep: impl Fn(Cell) -> bool,
    ) -> Option<Cell> {
        let n = self.map.n() as i64;
        if n == 0 {
            return None;
        }
        let pr = (point[0].round() as i64).clamp(0, n - 1);
        let pc = (point[1].round() as i64).clamp(0, n - 1);
        let ok = |c: Cell| {
            self.is_traversable(c) && allowed.is_none_or(|room| self.room_at(c) == room) && keep(c)
        };
        let mut best: Option<(f64, Cell)> = None;
        for ring in 0..n {
            // Once a candidate is known, rings farther than its distance cannot beat it.
            if let Some((d, _)) = best
                && (ring as f64) > d + 1.0
            {
                break;
            }
            for row in (pr - ring).max(0)..=(pr + ring).min(n - 1) {
                for col in (pc - ring).max(0)..=(pc + ring).min(n - 1) {
                    if (row - pr).abs() != ring && (col - pc).abs() != ring {
                        continue;
                    }
                    let cell = Cell::new(row as u32, col as u32);
                    if !ok(cell) {
                        continue;
                    }
                    let d = (row as f64 - point[0]).hypot(col as f64 - point[1]);
                    if best.is_none_or(|(bd, bc)| {
                        d < bd - 1e-12 || ((d - bd).abs() <= 1e-12 && cell < bc)
                    }) {
                        best = Some((d, cell));
                    }
                }
            }
        }
        best.map(|(_, c)| c)
    }
}

/// Footprint cells with a 4-neighbour outside the footprint (sorted input expected).
fn boundary(cells: &[Cell]) -> Vec<Cell> {
    let has = |r: i64, c: i64| {
        r >= 0 && c >= 0 && cells.binary_search(&Cell::new(r as u32, c as u32)).is_ok()
    };
    cells
        .iter()
        .copied()
        .filter(|c| {
            let (r, k) = (c.row as i64, c.col as i64);
            !(has(r - 1, k) && has(r + 1, k) && has(r, k - 1) && has(r, k + 1))
        })
        .collect()
}

pub mod fixture;
