//! Lookups the generator needs over one semantic map: objects by category and room, room cells,
//! the must-pass region rule, and the free-space mask. Built once per scene.

use super::paths::PassMask;
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::{Object, Relation, SemanticMap};
use std::collections::{BTreeMap, HashMap};
use std::sync::Mutex;

/// Categories that are part of the building, not things one is sent to.
pub const STRUCTURAL: &[&str] = &["wall", "doorway", "doorframe", "window", "floor", "door"];

/// Structural categories that references may still name: counted, kept away from, used as
/// anchors ("the box beside the window") and gone to ("head to the window next to the fridge").
pub const FIXTURES: &[&str] = &["window"];

/// Radius padding of a must-pass region, metres (Map2Route `TEMPLATE_HARD_CONSTRAINT_PADDING_METERS`).
pub const MUST_PASS_PADDING_M: f64 = 1.0;

pub struct MapIndex<'a> {
    pub map: &'a SemanticMap,
    pub free: PassMask,
    /// Non-structural object ids per category, ascending.
    pub objects_by_cat: BTreeMap<String, Vec<u32>>,
    /// Room ids per room category, ascending.
    pub rooms_by_cat: BTreeMap<String, Vec<u32>>,
    /// Cell indices per room id.
    pub room_cells: BTreeMap<u32, Vec<usize>>,
    /// Structural objects a person still names, counts, keeps away from and goes to (windows),
    /// by category.
    pub fixtures_by_cat: BTreeMap<String, Vec<u32>>,
    /// Footprint distances already computed (they are quadratic in footprint size).
    fp_cache: Mutex<HashMap<(u32, u32), f64>>,
}

impl<'a> MapIndex<'a> {
    pub fn new(map: &'a SemanticMap) -> Self {
        let n = map.n();
        let pass: Vec<bool> = map
            .occupancy
            .data()
            .iter()
            .map(|&v| v == m2rc_stdlib::map::FREE)
            .collect();
        let mut objects_by_cat: BTreeMap<String, Vec<u32>> = BTreeMap::new();
        let mut fixtures_by_cat: BTreeMap<String, Vec<u32>> = BTreeMap::new();
        for o in &map.objects {
            if FIXTURES.contains(&o.category.as_str()) && !o.footprint.is_empty() {
                fixtures_by_cat
                    .entry(o.category.clone())
                    .or_default()
                    .push(o.id);
            }
            if !STRUCTURAL.contains(&o.category.as_str()) && !o.footprint.is_empty() {
                objects_by_cat
                    .entry(o.category.clone())
                    .or_default()
                    .push(o.id);
            }
        }
        let mut rooms_by_cat: BTreeMap<String, Vec<u32>> = BTreeMap::new();
        for r in &map.rooms {
            rooms_by_cat
                .entry(r.category.clone())
                .or_default()
                .push(r.id);
        }
        let mut room_cells: BTreeMap<u32, Vec<usize>> = BTreeMap::new();
        for (i, &room) in map.room_layer.data().iter().enumerate() {
            if room != 0 {
                room_cells.entry(room).or_default().push(i);
            }
        }
        MapIndex {
            map,
            free: PassMask::new(n, pass),
            objects_by_cat,
            rooms_by_cat,
            room_cells,
            fixtures_by_cat,
            fp_cache: Mutex::default(),
        }
    }

    pub fn object(&self, id: u32) -> &'a Object {
        self.map.object(id).expect("object ids come from the map")
    }

    pub fn resolution(&self) -> f64 {
        self.map.resolution()
    }

    /// Objects of `cat` (non-structural), ascending id.
    pub fn of_cat(&self, cat: &str) -> &[u32] {
        self.objects_by_cat
            .get(cat)
            .map(Vec::as_slice)
            .unwrap_or(&[])
    }

    /// Fixtures (windows) of `cat`, ascending id.
    pub fn fixtures_of(&self, cat: &str) -> &[u32] {
        self.fixtures_by_cat
            .get(cat)
            .map(Vec::as_slice)
            .unwrap_or(&[])
    }

    /// How many objects of any of `cats` the map has, structural ones (walls, doorways)
    /// included.
    pub fn count_any(&self, cats: &[&str]) -> usize {
        self.map
            .objects
            .iter()
            .filter(|o| cats.contains(&o.category.as_str()))
            .count()
    }

    /// Objects of `cat`, fixtures included: what `objects(cat)` means to the compiler.
    pub fn all_of_cat(&self, cat: &str) -> &[u32] {
        match self.fixtures_by_cat.get(cat) {
            Some(v) => v,
            None => self.of_cat(cat),
        }
    }

    /// The room an object lies in as the compiler's `room_of` decides it: its own room, else the
    /// room holding most of its footprint (ties to the smaller id).
    pub fn object_room(&self, id: u32) -> Option<u32> {
        let o = self.object(id);
        if o.room.is_some() {
            return o.room;
        }
        let mut counts: BTreeMap<u32, usize> = BTreeMap::new();
        for &c in &o.footprint {
            let r = self.room_at(c);
            if r != 0 {
                *counts.entry(r).or_default() += 1;
            }
        }
        counts
            .into_iter()
            .max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(&a.0)))
            .map(|(r, _)| r)
    }

    pub fn rooms_of_cat(&self, cat: &str) -> &[u32] {
        self.rooms_by_cat.get(cat).map(Vec::as_slice).unwrap_or(&[])
    }

    pub fn room_category(&self, room: u32) -> &str {
        self.map
            .room(room)
            .map(|r| r.category.as_str())
            .unwrap_or("room")
    }

    /// Whether `child` stands on `parent` according to the map's parent relation.
    pub fn is_on(&self, child: u32, parent: u32) -> bool {
        self.object(child)
            .parent
            .is_some_and(|p| p.id == parent && p.relation == Relation::On)
    }

    /// Free cells of a room, as indices.
    pub fn room_free_cells(&self, room: u32) -> Vec<usize> {
        let occ = self.map.occupancy.data();
        self.room_cells
            .get(&room)
            .map(|cells| {
                cells
                    .iter()
                    .copied()
                    .filter(|&i| occ[i] == m2rc_stdlib::map::FREE)
                    .collect()
            })
            .unwrap_or_default()
    }

    /// The must-pass region of an object, following the reference annotator: a disc at the
    /// object's centre whose radius is the footprint's extent plus 1 m, restricted to the
    /// object's room. Returns (centre, radius in cells, cell indices).
    pub fn must_pass_region(&self, id: u32) -> Option<([f64; 2], f64, Vec<usize>)> {
        let o = self.object(id);
        let room = o.room?;
        let [cr, cc] = o.center;
        let extent = o
            .footprint
            .iter()
            .map(|f| (f.row as f64 - cr).hypot(f.col as f64 - cc))
            .fold(0.0f64, f64::max);
        let radius = (extent + MUST_PASS_PADDING_M / self.resolution())
            .ceil()
            .max(1.0);
        let n = self.map.n() as i64;
        let (r0, r1) = (
            ((cr - radius).floor() as i64).max(0),
            ((cr + radius).ceil() as i64).min(n - 1),
        );
        let (c0, c1) = (
            ((cc - radius).floor() as i64).max(0),
            ((cc + radius).ceil() as i64).min(n - 1),
        );
        let rooms = self.map.room_layer.data();
        let mut cells = Vec::new();
        for r in r0..=r1 {
            for c in c0..=c1 {
                if (r as f64 - cr).hypot(c as f64 - cc) <= radius {
                    let i = r as usize * n as usize + c as usize;
                    if rooms[i] == room {
                        cells.push(i);
                    }
                }
            }
        }
        Some((o.center, radius, cells))
    }

    pub fn mask(&self, cells: &[usize]) -> Vec<bool> {
        let mut m = vec![false; self.map.n() * self.map.n()];
        for &i in cells {
            m[i] = true;
        }
        m
    }

    pub fn cell(&self, index: usize) -> Cell {
        self.free.cell(index)
    }

    /// Minimum centre-to-centre distance between two footprints, in cells.
    pub fn footprint_distance(&self, a: u32, b: u32) -> f64 {
        let key = (a.min(b), a.max(b));
        if let Some(d) = self.fp_cache.lock().expect("cache lock").get(&key) {
            return *d;
        }
        let (fa, fb) = (&self.object(a).footprint, &self.object(b).footprint);
        let best = fa
            .iter()
            .flat_map(|p| fb.iter().map(|q| p.dist_sq(*q)))
            .min()
            .map_or(f64::INFINITY, |d| (d as f64).sqrt());
        self.fp_cache.lock().expect("cache lock").insert(key, best);
        best
    }

    pub fn center_distance(&self, a: u32, b: u32) -> f64 {
        let (p, q) = (self.object(a).center, self.object(b).center);
        (p[0] - q[0]).hypot(p[1] - q[1])
    }

    /// The room a cell lies in (0 = none).
    pub fn room_at(&self, cell: Cell) -> u32 {
        self.map.room_layer.get(cell).copied().unwrap_or(0)
    }
}

/// Human wording of a snake_case category.
pub fn category_words(cat: &str) -> String {
    match cat {
        "tv_stand" => "TV stand".into(),
        "television" => "TV".into(),
        "counter_top" => "countertop".into(),
        "house_plant" => "houseplant".into(),
        "arm_chair" => "armchair".into(),
        "garbage_can" => "trash can".into(),
        "living_room" => "living room".into(),
        "cd" => "CD".into(),
        other => other.replace('_', " "),
    }
}
