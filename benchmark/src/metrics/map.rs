//! What the evaluator needs from a map: traversability, the clearance obstacle set, the
//! resolution. Built leniently from raw map JSON (the reference's unit-test maps carry little
//! more than `grid_size` and two layers) or from a full [`SemanticMap`]. Per-map work (legal
//! move table, clearance field) is done once and shared by every episode on the map.

use crate::route::validity::diagonal_corners;
use m2rc_stdlib::field::distance_field;
use m2rc_stdlib::grid::Grid;
use m2rc_stdlib::map::SemanticMap;
use serde_json::Value;
use std::collections::HashMap;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, OnceLock};

/// Object categories that do not count as clearance obstacles (door openings).
pub const TRAVERSABLE_OBJECT_CATEGORIES: [&str; 2] = ["doorframe", "doorway"];

/// Errors building an [`EvalMap`] from JSON.
#[derive(Debug, thiserror::Error)]
#[error("map field `{field}`: {message}")]
pub struct MapError {
    pub field: String,
    pub message: String,
}

fn map_err(field: &str, message: impl Into<String>) -> MapError {
    MapError {
        field: field.to_string(),
        message: message.into(),
    }
}

/// The 8 grid moves `(d_row, d_col, cost)`, in the reference's order.
pub const MOVES: [(i64, i64, f64); 8] = [
    (-1, 0, 1.0),
    (1, 0, 1.0),
    (0, -1, 1.0),
    (0, 1, 1.0),
    (-1, -1, std::f64::consts::SQRT_2),
    (-1, 1, std::f64::consts::SQRT_2),
    (1, -1, std::f64::consts::SQRT_2),
    (1, 1, std::f64::consts::SQRT_2),
];

/// An evaluation map.
#[derive(Debug)]
pub struct EvalMap {
    n: usize,
    resolution: f64,
    /// Occupancy equals the free value; `None` when the map has no occupancy layer (then SPL
    /// cannot be computed, as in the reference).
    traversable: Option<Vec<bool>>,
    /// Clearance obstacles; `None` when the map lacks the occupancy or object layer, which the
    /// reference treats as "no obstacles".
    obstacles: Option<Vec<bool>>,
    /// Bit k set when move `MOVES[k]` out of the cell is legal by traversability alone.
    legal_moves: OnceLock<Vec<u8>>,
    /// Oracle searches started on this map (see [`Self::legal_for_search`]).
    searches: AtomicU32,
    clearance: OnceLock<Option<Clearance>>,
    /// Squared distances offered by [`Self::seed_clearance_sq`] and found to be this map's.
    clearance_seed: OnceLock<Arc<Vec<u32>>>,
}

/// The distance from every cell centre to the nearest obstacle cell centre, in cells (exact
/// float64). A route reads a few hundred cells of it, so a field stored as squared distances
/// (the prepared-map cache's) is read through, a square root per cell read, instead of being
/// converted whole.
#[derive(Debug, Clone)]
pub enum Clearance {
    Exact(Grid<f64>),
    Squared { n: usize, squared: Arc<Vec<u32>> },
}

impl Clearance {
    pub fn n(&self) -> usize {
        match self {
            Clearance::Exact(g) => g.n(),
            Clearance::Squared { n, .. } => *n,
        }
    }

    /// The distance at row-major index `i` (which must be inside the grid).
    pub fn at(&self, i: usize) -> f64 {
        match self {
            Clearance::Exact(g) => g.data()[i],
            Clearance::Squared { squared, .. } => (squared[i] as f64).sqrt(),
        }
    }

    /// Every cell's distance, row-major.
    pub fn to_vec(&self) -> Vec<f64> {
        (0..self.n() * self.n()).map(|i| self.at(i)).collect()
    }
}

impl PartialEq for Clearance {
    fn eq(&self, other: &Self) -> bool {
        self.n() == other.n() && self.to_vec() == other.to_vec()
    }
}

impl EvalMap {
    /// Builds from layers already decoded. `obstacles` as defined for clearance.
    pub fn from_parts(
        n: usize,
        resolution: f64,
        traversable: Option<Vec<bool>>,
        obstacles: Option<Vec<bool>>,
    ) -> Self {
        EvalMap {
            n,
            resolution,
            traversable,
            obstacles,
            legal_moves: OnceLock::new(),
            searches: AtomicU32::new(0),
            clearance: OnceLock::new(),
            clearance_seed: OnceLock::new(),
        }
    }

    /// Builds from a full semantic map (occupancy there is normalized: 0 is free).
    pub fn from_semantic_map(map: &SemanticMap) -> Self {
        let n = map.n();
        let categories: HashMap<u32, &str> = map
            .objects
            .iter()
            .map(|o| (o.id, o.category.as_str()))
            .collect();
        let traversable: Vec<bool> = map
            .occupancy
            .data()
            .iter()
            .map(|&v| v == m2rc_stdlib::map::FREE)
            .collect();
        let obstacles: Vec<bool> = map
            .occupancy
            .data()
            .iter()
            .zip(map.object_layer.data())
            .map(|(&occ, &obj)| {
                occ != m2rc_stdlib::map::FREE
                    || object_blocks(obj as i64, &|id| {
                        u32::try_from(id)
                            .ok()
                            .and_then(|id| categories.get(&id).copied())
                    })
            })
            .collect();
        EvalMap::from_parts(
            n,
            resolution_or_one(map.resolution()),
            Some(traversable),
            Some(obstacles),
        )
    }

    /// Builds from raw map JSON. Needs `grid_size`; reads `layers.occupancy`,
    /// `layers.object_instance`, `layer_legends.occupancy.free.value`, `object_instances` and the
    /// resolution when present, exactly where the reference looks for them.
    pub fn from_json(map: &Value) -> Result<Self, MapError> {
        let obj = map
            .as_object()
            .ok_or_else(|| map_err(".", "a map must be a JSON object"))?;
        let n = obj
            .get("grid_size")
            .and_then(Value::as_u64)
            .ok_or_else(|| map_err("grid_size", "missing or not a non-negative integer"))?;
        if n > 20_000 {
            return Err(map_err("grid_size", format!("{n} is too large")));
        }
        let n = n as usize;
        let free = map
            .pointer("/layer_legends/occupancy/free/value")
            .and_then(Value::as_i64)
            .unwrap_or(0);
        let layers = obj.get("layers").and_then(Value::as_object);
        let occupancy = match layers.and_then(|l| l.get("occupancy")) {
            Some(v) => Some(read_layer(v, n, "layers.occupancy")?),
            None => None,
        };
        let objects = match layers.and_then(|l| l.get("object_instance")) {
            Some(v) => Some(read_layer(v, n, "layers.object_instance")?),
            None => None,
        };
        let mut categories: HashMap<i64, String> = HashMap::new();
        if let Some(list) = obj.get("object_instances").and_then(Value::as_array) {
            for inst in list {
                if let (Some(id), Some(cat)) = (
                    inst.get("id").and_then(Value::as_i64),
                    inst.get("category").and_then(Value::as_str),
                ) {
                    categories.insert(id, cat.to_string());
                }
            }
        }
        let traversable = occupancy
            .as_ref()
            .map(|occ| occ.iter().map(|v| *v == Some(free)).collect::<Vec<bool>>());
        let obstacles = match (&occupancy, &objects) {
            (Some(occ), Some(objs)) => Some(
                occ.iter()
                    .zip(objs)
                    .map(|(o, id)| {
                        o.is_none_or(|o| o != free)
                            || object_blocks(id.unwrap_or(0), &|id| {
                                categories.get(&id).map(String::as_str)
                            })
                    })
                    .collect(),
            ),
            _ => None,
        };
        Ok(EvalMap::from_parts(
            n,
            resolution_of(map),
            traversable,
            obstacles,
        ))
    }

    /// Side length N.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Metres per cell.
    pub fn resolution(&self) -> f64 {
        self.resolution
    }

    pub fn in_grid(&self, row: i64, col: i64) -> bool {
        row >= 0 && col >= 0 && (row as usize) < self.n && (col as usize) < self.n
    }

    pub fn traversable(&self) -> Option<&[bool]> {
        self.traversable.as_deref()
    }

    pub fn is_traversable(&self, row: i64, col: i64) -> bool {
        self.in_grid(row, col)
            && self
                .traversable
                .as_ref()
                .is_some_and(|t| t[row as usize * self.n + col as usize])
    }

    /// Per-cell bit masks of moves legal by traversability (no corner cutting, by the rule of
    /// [`diagonal_corners`]); empty when the map has no occupancy layer.
    pub fn legal_moves(&self) -> &[u8] {
        self.legal_moves.get_or_init(|| {
            let Some(t) = &self.traversable else {
                return Vec::new();
            };
            (0..t.len()).map(|i| legal_bits(t, self.n, i)).collect()
        })
    }

    /// The legal moves for an oracle search: the table when it exists or this map has been
    /// searched before (a run scores many segments on one map), else read cell by cell, since
    /// one search visits a small part of a suite map and the whole table was a third of a
    /// single `m2rc eval`. `None` when the map has no occupancy layer.
    pub(crate) fn legal_for_search(&self) -> Option<Legal<'_>> {
        let t = self.traversable.as_deref()?;
        if let Some(table) = self.legal_moves.get() {
            return Some(Legal::Table(table));
        }
        if self.searches.fetch_add(1, Ordering::Relaxed) > 0 {
            return Some(Legal::Table(self.legal_moves()));
        }
        Some(Legal::Cells {
            traversable: t,
            n: self.n,
        })
    }

    /// Distance from every cell centre to the nearest obstacle cell centre, in cells (exact
    /// float64); `None` when the map has no obstacle at all.
    pub fn clearance_field(&self) -> Option<&Clearance> {
        self.clearance
            .get_or_init(|| {
                if let Some(squared) = self.clearance_seed.get() {
                    return Some(Clearance::Squared {
                        n: self.n,
                        squared: squared.clone(),
                    });
                }
                let obstacles = self.obstacles.as_ref()?;
                if !obstacles.iter().any(|&b| b) {
                    return None;
                }
                let sources = Grid::from_vec(self.n, obstacles.clone())?;
                Some(Clearance::Exact(distance_field(&sources)))
            })
            .as_ref()
    }

    /// Offers the squared distances to the nearest obstacle computed earlier (the prepared-map
    /// cache's, by the planner's rule): used for [`Self::clearance_field`] when its zero cells are
    /// exactly this map's clearance obstacles, which makes its square roots the exact field; else
    /// ignored. Whether it was used.
    pub fn seed_clearance_sq(&self, squared: &Arc<Vec<u32>>) -> bool {
        let Some(obstacles) = &self.obstacles else {
            return false;
        };
        let fits = squared.len() == obstacles.len()
            && obstacles.iter().any(|&b| b)
            && squared.iter().zip(obstacles).all(|(&d, &b)| (d == 0) == b);
        if !fits {
            return false;
        }
        self.clearance.get().is_none() && self.clearance_seed.set(squared.clone()).is_ok()
    }

    /// Distance from an arbitrary point to the nearest obstacle cell centre, by scanning (used
    /// only for points off the grid, which the field does not cover).
    pub fn nearest_obstacle_distance(&self, p: [f64; 2]) -> f64 {
        let Some(obstacles) = &self.obstacles else {
            return f64::INFINITY;
        };
        obstacles
            .iter()
            .enumerate()
            .filter(|(_, b)| **b)
            .map(|(i, _)| (p[0] - (i / self.n) as f64).hypot(p[1] - (i % self.n) as f64))
            .fold(f64::INFINITY, f64::min)
    }
}

/// Where an oracle search reads a cell's legal moves from.
pub(crate) enum Legal<'a> {
    Table(&'a [u8]),
    Cells { traversable: &'a [bool], n: usize },
}

impl Legal<'_> {
    /// Bit k set when `MOVES[k]` out of row-major cell `i` is legal.
    pub(crate) fn at(&self, i: usize) -> u8 {
        match self {
            Legal::Table(t) => t[i],
            Legal::Cells { traversable, n } => legal_bits(traversable, *n, i),
        }
    }
}

/// The legal-move bits of cell `i` of an `n` x `n` grid with traversability `t`.
fn legal_bits(t: &[bool], n: usize, i: usize) -> u8 {
    let n = n as i64;
    let (r, c) = ((i as i64) / n, (i as i64) % n);
    let free = |r: i64, c: i64| r >= 0 && c >= 0 && r < n && c < n && t[(r * n + c) as usize];
    let mut bits = 0u8;
    for (k, &(dr, dc, _)) in MOVES.iter().enumerate() {
        let (nr, nc) = (r + dr, c + dc);
        let ok = free(nr, nc)
            && diagonal_corners([r, c], [nr, nc])
                .is_none_or(|cs| cs.iter().all(|&[cr, cc]| free(cr, cc)));
        if ok {
            bits |= 1 << k;
        }
    }
    bits
}

fn object_blocks<'a>(id: i64, category: &dyn Fn(i64) -> Option<&'a str>) -> bool {
    id != 0 && !category(id).is_some_and(|c| TRAVERSABLE_OBJECT_CATEGORIES.contains(&c))
}

fn resolution_or_one(r: f64) -> f64 {
    if r.is_finite() && r > 0.0 { r } else { 1.0 }
}

/// `metadata.grid_coordinate_frame.resolution`, else `metadata.map_info.resolution`, else 1.0
/// (only positive numbers count).
pub fn resolution_of(map: &Value) -> f64 {
    for key in [
        "/metadata/grid_coordinate_frame/resolution",
        "/metadata/map_info/resolution",
    ] {
        if let Some(r) = map.pointer(key).and_then(Value::as_f64)
            && r > 0.0
            && r.is_finite()
        {
            return r;
        }
    }
    1.0
}

/// An N x N integer layer; a non-integer cell reads as `None` (never free, never an object).
fn read_layer(v: &Value, n: usize, field: &str) -> Result<Vec<Option<i64>>, MapError> {
    let rows = v
        .as_array()
        .ok_or_else(|| map_err(field, "must be a list of rows"))?;
    if rows.len() != n {
        return Err(map_err(
            field,
            format!("has {} rows, grid_size is {n}", rows.len()),
        ));
    }
    let mut out = Vec::with_capacity(n * n);
    for (r, row) in rows.iter().enumerate() {
        let row = row
            .as_array()
            .ok_or_else(|| map_err(&format!("{field}[{r}]"), "must be a list"))?;
        if row.len() != n {
            return Err(map_err(
                &format!("{field}[{r}]"),
                format!("has {} cells, grid_size is {n}", row.len()),
            ));
        }
        out.extend(row.iter().map(|x| match x {
            Value::Number(num) => num.as_i64().or_else(|| {
                num.as_f64()
                    .filter(|f| f.is_finite())
                    .map(|f| f.trunc() as i64)
            }),
            _ => None,
        }));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn minimal_map_reads_layers_and_resolution() {
        let m = json!({
            "grid_size": 3,
            "layers": {
                "occupancy": [[1, 0, 0], [0, 0, 0], [0, 0, 0]],
                "object_instance": [[0, 0, 0], [0, 7, 0], [0, 0, 9]]
            },
            "object_instances": [{"id": 7, "category": "doorway"}, {"id": 9, "category": "bed"}],
            "metadata": {"grid_coordinate_frame": {"resolution": 0.5}}
        });
        let m = EvalMap::from_json(&m).unwrap();
        assert_eq!(m.resolution(), 0.5);
        assert!(!m.is_traversable(0, 0));
        assert!(m.is_traversable(1, 1));
        let f = m.clearance_field().unwrap();
        // (1,1) is a doorway: not an obstacle; nearest obstacles are (0,0) and (2,2).
        assert_eq!(f.at(4), 2f64.sqrt());
        assert_eq!(f.at(8), 0.0);
    }

    #[test]
    fn missing_layers_mean_no_field_and_no_traversability() {
        let m = EvalMap::from_json(&json!({"grid_size": 5})).unwrap();
        assert!(m.clearance_field().is_none());
        assert!(m.traversable().is_none());
        assert!(EvalMap::from_json(&json!({"grid_size": "x"})).is_err());
        let bad = json!({"grid_size": 2, "layers": {"occupancy": [[0, 0]]}});
        assert!(
            EvalMap::from_json(&bad)
                .unwrap_err()
                .to_string()
                .contains("layers.occupancy")
        );
    }

    #[test]
    fn legal_moves_forbid_corner_cutting() {
        let m = json!({"grid_size": 2, "layers": {"occupancy": [[0, 1], [0, 0]]}});
        let m = EvalMap::from_json(&m).unwrap();
        let moves = m.legal_moves();
        // From (0,0): down (k=1) legal, right (k=3) blocked, diagonal (1,1) (k=7) cuts (0,1).
        assert_ne!(moves[0] & (1 << 1), 0);
        assert_eq!(moves[0] & (1 << 3), 0);
        assert_eq!(moves[0] & (1 << 7), 0);
    }

    #[test]
    fn a_search_reads_the_same_moves_cell_by_cell_as_from_the_table() {
        let n = 13;
        // A pseudo-random pattern of blocked cells, corners included.
        let t: Vec<bool> = (0..n * n).map(|i| (i * 7919 + i / n) % 5 != 0).collect();
        let m = EvalMap::from_parts(n, 0.05, Some(t), None);
        let Some(Legal::Cells { .. }) = m.legal_for_search() else {
            panic!("the first search of a map reads cells");
        };
        let Some(Legal::Table(table)) = m.legal_for_search() else {
            panic!("the second builds the table");
        };
        let cells = Legal::Cells {
            traversable: m.traversable().unwrap(),
            n,
        };
        assert!(table.iter().any(|&b| b != 0 && b != 0xff));
        for (i, &bits) in table.iter().enumerate() {
            assert_eq!(cells.at(i), bits, "cell {i}");
        }
        let none = EvalMap::from_parts(n, 0.05, None, None);
        assert!(none.legal_for_search().is_none());
    }
}
