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
pub(crate) use rooms::find_passages;
pub use rooms::{Passage, PassageKind, open_area};
pub use route::{RoomVisit, nominal_path, room_visits};

use crate::grid::{Cell, Grid};
use crate::map::{Object, SemanticMap};
use std::sync::OnceLock;

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
    /// Cells of each room with a 4-neighbour outside it, indexed like `map.rooms`, sorted; built
    /// on first use (only distance queries on rooms need them).
    room_boundaries: Vec<OnceLock<Vec<Cell>>>,
    /// Cells of each object's footprint that touch a cell outside it, indexed like `map.objects`.
    boundaries: Vec<Vec<Cell>>,
    passages: Vec<Passage>,
    /// Bounding boxes (row0, col0, row1, col1) of each object's footprint and each room, indexed
    /// like `map.objects` and `map.rooms`; `None` when empty.
    object_boxes: Vec<Option<Bounds>>,
    room_boxes: Vec<Option<Bounds>>,
    pub thresholds: Thresholds,
}

/// Inclusive cell bounding box: (row0, col0, row1, col1).
type Bounds = (u32, u32, u32, u32);

fn bounds_of(cells: &[Cell]) -> Option<Bounds> {
    let first = cells.first()?;
    Some(cells.iter().fold(
        (first.row, first.col, first.row, first.col),
        |(r0, c0, r1, c1), c| (r0.min(c.row), c0.min(c.col), r1.max(c.row), c1.max(c.col)),
    ))
}

impl<'m> MapQuery<'m> {
    pub fn new(map: &'m SemanticMap) -> Self {
        let traversable = map.occupancy.map(|&v| v == crate::map::FREE);
        let mut room_cells = vec![Vec::new(); map.rooms.len()];
        let n = map.room_layer.n();
        // Room index by label, looked up once per run of equal labels.
        let mut last: (u32, Option<usize>) = (0, None);
        for (r, row) in map.room_layer.data().chunks_exact(n.max(1)).enumerate() {
            for (c, &l) in row.iter().enumerate() {
                if l == 0 {
                    continue;
                }
                if l != last.0 {
                    last = (l, map.rooms.binary_search_by_key(&l, |x| x.id).ok());
                }
                if let Some(i) = last.1 {
                    room_cells[i].push(Cell::new(r as u32, c as u32));
                }
            }
        }
        let room_boundaries = (0..map.rooms.len()).map(|_| OnceLock::new()).collect();
        let boundaries = map.objects.iter().map(|o| boundary(&o.footprint)).collect();
        let object_boxes = map
            .objects
            .iter()
            .map(|o| bounds_of(&o.footprint))
            .collect();
        let room_boxes = room_cells.iter().map(|c| bounds_of(c)).collect();
        let passages = rooms::find_passages(map, &traversable);
        MapQuery {
            map,
            traversable,
            room_cells,
            room_boundaries,
            boundaries,
            passages,
            object_boxes,
            room_boxes,
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

    /// The bounding box of a place's cells (precomputed for objects and rooms).
    fn bounds(&self, t: Target<'_>) -> Option<Bounds> {
        match t {
            Target::Object(o) => match self.map.objects.binary_search_by_key(&o.id, |x| x.id) {
                Ok(i) if std::ptr::eq(&self.map.objects[i], o) => self.object_boxes[i],
                _ => bounds_of(&o.footprint),
            },
            Target::Room(r) => match self.map.rooms.binary_search_by_key(&r, |x| x.id) {
                Ok(i) => self.room_boxes[i],
                Err(_) => None,
            },
            Target::Cells(c) => bounds_of(c),
        }
    }

    /// A lower bound of [`MapQuery::distance_cells`]: the gap between the two bounding boxes, in
    /// cells (`None` when a place has no cells). Lets a "within d" test reject far pairs without
    /// looking at their cells.
    pub(crate) fn box_gap_cells(&self, a: Target<'_>, b: Target<'_>) -> Option<f64> {
        let (a, b) = (self.bounds(a)?, self.bounds(b)?);
        let gap = |lo1: u32, hi1: u32, lo2: u32, hi2: u32| -> f64 {
            if hi1 < lo2 {
                (lo2 - hi1) as f64
            } else if hi2 < lo1 {
                (lo1 - hi2) as f64
            } else {
                0.0
            }
        };
        let (dr, dc) = (gap(a.0, a.2, b.0, b.2), gap(a.1, a.3, b.1, b.3));
        Some((dr * dr + dc * dc).sqrt())
    }

    /// Whether two places share a cell. Room membership is read off the room layer, so a room of
    /// thousands of cells costs one lookup per cell of the other place.
    fn overlap(&self, a: Target<'_>, b: Target<'_>) -> bool {
        match (a, b) {
            (Target::Room(r), Target::Room(s)) => r == s && !self.room_cells(r).is_empty(),
            (Target::Room(r), other) | (other, Target::Room(r)) => {
                !self.room_cells(r).is_empty()
                    && self.cells(other).iter().any(|&c| self.room_at(c) == r)
            }
            _ => {
                let (ca, cb) = (self.cells(a), self.cells(b));
                if !boxes_meet(ca, cb) {
                    return false;
                }
                let (small, large) = if ca.len() <= cb.len() {
                    (ca, cb)
                } else {
                    (cb, ca)
                };
                small.iter().any(|c| large.binary_search(c).is_ok())
            }
        }
    }

    /// The cells that can be nearest to a disjoint place: an object's or a room's boundary, the
    /// cells of a region. (Of two disjoint cell sets, the nearest pair lies on both boundaries: an
    /// inner cell always has a neighbour of its own set nearer to any outside cell.)
    fn rim<'a>(&'a self, t: Target<'a>) -> &'a [Cell] {
        match t {
            Target::Room(r) => match self.map.rooms.binary_search_by_key(&r, |x| x.id) {
                Ok(i) => self.room_boundaries[i].get_or_init(|| {
                    let label = |r: i64, c: i64| {
                        if r < 0 || c < 0 {
                            return 0;
                        }
                        self.room_at(Cell::new(r as u32, c as u32))
                    };
                    self.room_cells[i]
                        .iter()
                        .copied()
                        .filter(|cell| {
                            let (r, c) = (cell.row as i64, cell.col as i64);
                            let l = self.map.rooms[i].id;
                            label(r - 1, c) != l
                                || label(r + 1, c) != l
                                || label(r, c - 1) != l
                                || label(r, c + 1) != l
                        })
                        .collect()
                }),
                Err(_) => &[],
            },
            _ => self.outline(t),
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

/// Whether the bounding boxes of two non-empty cell sets intersect (a cheap disjointness test).
fn boxes_meet(a: &[Cell], b: &[Cell]) -> bool {
    let bbox = |cells: &[Cell]| {
        cells
            .iter()
            .fold((u32::MAX, u32::MAX, 0, 0), |(r0, c0, r1, c1), c| {
                (r0.min(c.row), c0.min(c.col), r1.max(c.row), c1.max(c.col))
            })
    };
    let (a, b) = (bbox(a), bbox(b));
    a.0 <= b.2 && b.0 <= a.2 && a.1 <= b.3 && b.1 <= a.3
}

/// Footprint cells with a 4-neighbour outside the footprint (sorted input expected).
fn boundary(cells: &[Cell]) -> Vec<Cell> {
    // Membership through a bitmap of the bounding box (one lookup per neighbour), falling back to
    // binary search for a footprint too spread out for one.
    let Some((r0, c0, r1, c1)) = bounds_of(cells) else {
        return Vec::new();
    };
    let (h, w) = ((r1 - r0 + 1) as usize, (c1 - c0 + 1) as usize);
    let bitmap = (h.saturating_mul(w) <= 64 * cells.len().max(64)).then(|| {
        let mut m = vec![false; h * w];
        for c in cells {
            m[(c.row - r0) as usize * w + (c.col - c0) as usize] = true;
        }
        m
    });
    let has = |r: i64, c: i64| match &bitmap {
        Some(m) => {
            r >= r0 as i64
                && c >= c0 as i64
                && r <= r1 as i64
                && c <= c1 as i64
                && m[(r - r0 as i64) as usize * w + (c - c0 as i64) as usize]
        }
        None => r >= 0 && c >= 0 && cells.binary_search(&Cell::new(r as u32, c as u32)).is_ok(),
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
