//! Where an AP is true on the grid, the adaptation's label map: a room on the traversable cells of
//! its room-layer region; an object on the traversable cells within [`OBJECT_LABEL_RADIUS_CELLS`]
//! of its centre, or, when none is, on the nearest traversable cell within `max(80, 4 r)` cells.

use crate::common::inventory::{Ap, ApKind};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;

/// The object-label radius: 20 cells = 1 m at 0.05 m per cell.
pub const OBJECT_LABEL_RADIUS_CELLS: f64 = 20.0;

/// The traversable cells where `ap` holds, in row-major order.
pub fn label_cells(map: &SemanticMap, ap: &Ap, radius: f64) -> Vec<Cell> {
    match ap.kind {
        ApKind::Room(id) => map
            .room_layer
            .iter_cells()
            .filter(|(c, v)| **v == id && map.is_free(*c))
            .map(|(c, _)| c)
            .collect(),
        ApKind::Object(_) => {
            let near = disc(map, ap.center, radius);
            if !near.is_empty() {
                return near;
            }
            nearest_free(map, ap.center, (4.0 * radius).max(80.0))
                .into_iter()
                .collect()
        }
    }
}

/// Traversable cells whose centre lies within `radius` cells of `center` (`[row, col]`).
pub fn disc(map: &SemanticMap, center: [f64; 2], radius: f64) -> Vec<Cell> {
    let n = map.n() as i64;
    let r = radius.max(0.0);
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
            let cell = Cell::new(row as u32, col as u32);
            if dr.hypot(dc) <= r && map.is_free(cell) {
                out.push(cell);
            }
        }
    }
    out
}

/// The traversable cell nearest `center` within `max_radius` cells (ties: row-major first).
pub fn nearest_free(map: &SemanticMap, center: [f64; 2], max_radius: f64) -> Option<Cell> {
    disc(map, center, max_radius).into_iter().min_by(|a, b| {
        let d = |c: &Cell| (c.row as f64 - center[0]).hypot(c.col as f64 - center[1]);
        d(a).total_cmp(&d(b))
    })
}
