//! Per-map planning data that no program changes: the traversable and clearance-obstacle grids,
//! the door ids, each room's mask, and (computed on first use, then shared) the obstacle distance
//! field and the always-on clearance field.
//!
//! Building it is most of the fixed cost of a plan on a large map, and the same map is planned on
//! again and again: the plan → bind → re-plan loop of route-dependent places lowers one program
//! several times, the benchmark runner plans many episodes per house, the language server replans
//! on every edit. Build one [`MapContext`] per map and lower with [`crate::lower::lower_with`];
//! the problems it produces carry a handle to the shared [`MapFields`].

use crate::compile::Buffers;
use m2rc_stdlib::field;
use m2rc_stdlib::grid::Grid;
use m2rc_stdlib::map::{FREE, SemanticMap};
use std::sync::{Arc, Mutex, OnceLock};

/// A clearance field and its (radius in cells, weight) bits.
type ClearanceEntry = ((u64, u64), Arc<Vec<f64>>);

/// Most arrays of each kind kept between plans.
const MAX_STASHED: usize = 4;

/// The tag of the obstacle rule behind [`MapFields::obstacle_sq`] (occupied cells and non-door
/// objects; the non-traversable cells on a map without any): bumped when that rule changes, so a
/// field stored under an older rule (the prepared-map cache) is not offered.
pub const OBSTACLE_FIELD_TAG: u32 = 1;

/// Object categories the clearance term does not treat as obstacles.
pub const DOOR_CATEGORIES: [&str; 2] = ["doorway", "doorframe"];

/// A map prepared for lowering and planning many programs.
#[derive(Debug)]
pub struct MapContext {
    pub map_id: String,
    pub traversable: Grid<bool>,
    /// Non-free occupancy cells plus every object cell whose object is not a door.
    pub obstacles: Grid<bool>,
    /// Mask of each room by id, built on first use.
    room_masks: Vec<(u32, OnceLock<Arc<Grid<bool>>>)>,
    fields: Arc<MapFields>,
}

impl MapContext {
    /// Indexes `map`; fails when its layers disagree in size.
    pub fn new(map: &SemanticMap) -> Result<Self, String> {
        let n = map.n();
        let traversable = map.occupancy.map(|&o| o == FREE);
        let mut door_ids: Vec<u32> = map
            .objects
            .iter()
            .filter(|o| DOOR_CATEGORIES.contains(&o.category.as_str()))
            .map(|o| o.id)
            .collect();
        door_ids.sort_unstable();
        if map.object_layer.n() != n {
            return Err("object layer size does not match the occupancy layer".to_string());
        }
        let obstacles = Grid::from_vec(
            n,
            map.occupancy
                .data()
                .iter()
                .zip(map.object_layer.data())
                .map(|(&occ, &obj)| {
                    occ != FREE || (obj != 0 && door_ids.binary_search(&obj).is_err())
                })
                .collect(),
        )
        .ok_or_else(|| "object layer size does not match the occupancy layer".to_string())?;
        let mut room_masks: Vec<(u32, OnceLock<Arc<Grid<bool>>>)> =
            map.rooms.iter().map(|r| (r.id, OnceLock::new())).collect();
        room_masks.sort_by_key(|(id, _)| *id);
        room_masks.dedup_by_key(|(id, _)| *id);
        Ok(MapContext {
            map_id: map.map_id.clone(),
            fields: Arc::new(MapFields::new(&traversable, &obstacles)),
            traversable,
            obstacles,
            room_masks,
        })
    }

    pub fn n(&self) -> usize {
        self.traversable.n()
    }

    /// The mask of room `id`: the cells `map` (the map this context was built from) labels `id`.
    pub fn room_mask(&self, map: &SemanticMap, id: u32) -> Arc<Grid<bool>> {
        let make = || Arc::new(map.room_layer.map(|&r| r == id));
        match self.room_masks.binary_search_by_key(&id, |(r, _)| *r) {
            Ok(i) => self.room_masks[i].1.get_or_init(make).clone(),
            Err(_) => make(),
        }
    }

    /// The shared per-map fields, for [`crate::PlanProblem::map_fields`].
    pub fn fields(&self) -> Arc<MapFields> {
        Arc::clone(&self.fields)
    }
}

/// Distance and clearance fields of one map, computed on first use and shared by every problem
/// lowered from the same [`MapContext`]. Only valid for problems whose traversable and obstacle
/// grids are the ones it was built from (the lowering guarantees it).
pub struct MapFields {
    /// Row-major squared distance to the nearest clearance obstacle, from the obstacle grid, or from
    /// the non-traversable cells when the grid has no obstacle at all (as `compile::prepare` does).
    obstacle_source: Vec<bool>,
    n: usize,
    obstacle_sq: OnceLock<Arc<Vec<u32>>>,
    /// Padded clearance fields by (radius in cells, weight) bits.
    clearance: Mutex<Vec<ClearanceEntry>>,
    /// Arrays left by finished plans, for the next plan on this map.
    buffers: Mutex<Buffers>,
}

impl std::fmt::Debug for MapFields {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MapFields")
            .field("n", &self.n)
            .field("obstacle_sq", &self.obstacle_sq.get().is_some())
            .finish_non_exhaustive()
    }
}

/// Fields are a pure function of the grids they were built from: equal sources, equal fields.
impl PartialEq for MapFields {
    fn eq(&self, other: &Self) -> bool {
        self.n == other.n && self.obstacle_source == other.obstacle_source
    }
}

impl MapFields {
    fn new(traversable: &Grid<bool>, obstacles: &Grid<bool>) -> Self {
        let mut src = obstacles.data().to_vec();
        if !src.iter().any(|v| *v) {
            src = traversable.data().iter().map(|t| !t).collect();
        }
        MapFields {
            obstacle_source: src,
            n: traversable.n(),
            obstacle_sq: OnceLock::new(),
            clearance: Mutex::new(Vec::new()),
            buffers: Mutex::new(Buffers::default()),
        }
    }

    pub fn n(&self) -> usize {
        self.n
    }

    /// Squared distance to the nearest clearance obstacle, row-major.
    pub fn obstacle_sq(&self) -> Arc<Vec<u32>> {
        Arc::clone(
            self.obstacle_sq
                .get_or_init(|| Arc::new(field::squared_distances(&self.obstacle_source, self.n))),
        )
    }

    /// Offers a squared-distance field computed earlier (the prepared-map cache's): it is used
    /// when it has this map's size and its zero cells are exactly this map's obstacle cells (which
    /// determines the exact transform), else ignored. Whether it was used.
    pub fn seed_obstacle_sq(&self, squared: Arc<Vec<u32>>) -> bool {
        let fits = squared.len() == self.obstacle_source.len()
            && if self.obstacle_source.iter().any(|&s| s) {
                squared
                    .iter()
                    .zip(&self.obstacle_source)
                    .all(|(&d, &s)| (d == 0) == s)
            } else {
                squared.iter().all(|&d| d == field::NO_SOURCE)
            };
        fits && self.obstacle_sq.set(squared).is_ok()
    }

    /// The arrays stashed by earlier plans (empty when another plan holds them).
    pub(crate) fn take_buffers(&self) -> Buffers {
        match self.buffers.try_lock() {
            Ok(mut b) => std::mem::take(&mut *b),
            Err(_) => Buffers::default(),
        }
    }

    /// Keeps a finished plan's arrays: one plan's worth (a few per kind), so the memory held stays
    /// bounded by what a single plan needs at once.
    pub(crate) fn stash(&self, mut more: Buffers) {
        if let Ok(mut b) = self.buffers.try_lock() {
            more.phi.truncate(MAX_STASHED);
            more.h.truncate(MAX_STASHED);
            if more.phi.len() + more.h.len() >= b.phi.len() + b.h.len() {
                *b = more;
            }
        }
    }

    /// The padded clearance field for `key` (radius, weight bits), built by `make` on first use.
    pub(crate) fn clearance(
        &self,
        key: (u64, u64),
        make: impl FnOnce() -> Vec<f64>,
    ) -> Arc<Vec<f64>> {
        let mut cache = match self.clearance.lock() {
            Ok(c) => c,
            Err(poisoned) => poisoned.into_inner(),
        };
        if let Some((_, f)) = cache.iter().find(|(k, _)| *k == key) {
            return Arc::clone(f);
        }
        let f = Arc::new(make());
        // A handful of profiles at most; keep the latest few.
        if cache.len() >= 4 {
            cache.remove(0);
        }
        cache.push((key, Arc::clone(&f)));
        f
    }
}
