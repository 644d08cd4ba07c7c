//! Checks that an imported map matches its house: every door and window hole where ProcTHOR
//! cuts it, every room the house connects reachable from the start, and no way between two rooms
//! the house keeps apart.
//!
//! The importer runs these on every house and turns failures into warnings; the tests and the
//! `map_check` bench run them over all 750 shared houses. The expected hole position is read off
//! the hole's own face (`wall0`, from its first bottom corner in its own direction, as
//! ProcTHOR's generator measures it), independently of how the importer merged the faces.

use super::house::House;
use super::raster::inside_or_on;
use crate::grid::{Cell, Grid};
use crate::map::SemanticMap;
use crate::query::find_passages;
use std::collections::{BTreeMap, BTreeSet, HashMap, VecDeque};

/// A door or window hole that is not where the house puts it.
#[derive(Clone, Debug, PartialEq)]
pub struct HoleIssue {
    /// `doors[3]` / `windows[1]`.
    pub path: String,
    pub id: String,
    /// Largest distance between the hole's ends in the map and in the house, along the face, m
    /// (infinite when the map has no cells for it).
    pub offset_m: f64,
    /// Cells of the hole that a wall still covers (doors only: a window sits in its wall).
    pub wall_cells: usize,
}

/// What [`check_map`] found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ImportCheck {
    /// Door and window holes checked.
    pub holes: usize,
    pub misplaced_holes: Vec<HoleIssue>,
    /// The start's room, when the start lies on a room's floor.
    pub start_room: Option<u32>,
    /// Rooms the house joins to the start's room through doors and open walls (the start's room
    /// included), map ids, sorted.
    pub connected_rooms: Vec<u32>,
    /// Of those, the rooms with no traversable cell reachable from the start, sorted.
    pub unreachable_rooms: Vec<u32>,
    /// Room pairs joined by traversable cells although the house has neither a door nor an open
    /// wall between them, sorted.
    pub leaks: Vec<(u32, u32)>,
}

impl ImportCheck {
    pub fn is_clean(&self) -> bool {
        self.misplaced_holes.is_empty()
            && self.unreachable_rooms.is_empty()
            && self.leaks.is_empty()
    }

    /// One line per problem, `(field path, message)`, as import warnings.
    pub fn warnings(&self, map: &SemanticMap) -> Vec<(String, String)> {
        let name = |id: u32| {
            map.room(id)
                .map_or_else(|| id.to_string(), |r| r.name.clone())
        };
        let mut out = Vec::new();
        for h in &self.misplaced_holes {
            let msg = if h.offset_m.is_finite() {
                format!(
                    "hole {} is cut {:.2} m from where the house puts it",
                    h.id, h.offset_m
                )
            } else {
                format!("hole {} covers no cell of the map", h.id)
            };
            let walls = if h.wall_cells > 0 {
                format!("; {} of its cells are still wall", h.wall_cells)
            } else {
                String::new()
            };
            out.push((h.path.clone(), format!("{msg}{walls}")));
        }
        for &r in &self.unreachable_rooms {
            out.push((
                "rooms".into(),
                format!(
                    "{} is connected to the start's room by doors or open walls but cannot be \
                     reached from the start over traversable cells (furniture or the robot \
                     radius closes the way)",
                    name(r)
                ),
            ));
        }
        for &(a, b) in &self.leaks {
            out.push((
                "walls".into(),
                format!(
                    "{} and {} are joined by traversable cells but the house has no door or open \
                     wall between them",
                    name(a),
                    name(b)
                ),
            ));
        }
        out
    }
}

/// Rooms reached from `start` over traversable cells (4-connected BFS, as the planner moves at
/// least this freely). The start itself need not be free: the search begins at the nearest free
/// cell of its room, or of the grid.
pub fn rooms_reachable_from(map: &SemanticMap, start: Cell) -> BTreeSet<u32> {
    let n = map.n();
    let mut out = BTreeSet::new();
    let Some(seed) = nearest_free(map, start) else {
        return out;
    };
    let mut seen = Grid::new(n, false);
    let mut queue = VecDeque::from([seed]);
    seen.set(seed, true);
    while let Some(c) = queue.pop_front() {
        let l = map.room_at(c);
        if l != 0 {
            out.insert(l);
        }
        let (r, k) = (c.row as i64, c.col as i64);
        for (dr, dc) in [(-1, 0), (1, 0), (0, -1), (0, 1)] {
            let (y, x) = (r + dr, k + dc);
            if y < 0 || x < 0 || y >= n as i64 || x >= n as i64 {
                continue;
            }
            let q = Cell::new(y as u32, x as u32);
            if map.is_free(q) && seen.get(q) == Some(&false) {
                seen.set(q, true);
                queue.push_back(q);
            }
        }
    }
    out
}

/// A free cell near `start`: in the first ring around it that has one, the nearest, preferring
/// cells of the start's own room (a start inside furniture or the robot-radius margin).
fn nearest_free(map: &SemanticMap, start: Cell) -> Option<Cell> {
    if map.is_free(start) {
        return Some(start);
    }
    let room = map.room_at(start);
    let n = map.n() as i64;
    let (r0, c0) = (start.row as i64, start.col as i64);
    let mut fallback: Option<Cell> = None;
    for ring in 1..n {
        let mut own: Option<(i64, Cell)> = None;
        let mut any: Option<(i64, Cell)> = None;
        for y in (r0 - ring).max(0)..=(r0 + ring).min(n - 1) {
            for x in (c0 - ring).max(0)..=(c0 + ring).min(n - 1) {
                if (y - r0).abs() != ring && (x - c0).abs() != ring {
                    continue;
                }
                let c = Cell::new(y as u32, x as u32);
                if !map.is_free(c) {
                    continue;
                }
                let d = (y - r0).pow(2) + (x - c0).pow(2);
                for slot in [&mut any]
                    .into_iter()
                    .chain((room != 0 && map.room_at(c) == room).then_some(&mut own))
                {
                    if slot.is_none_or(|(bd, bc)| d < bd || (d == bd && c < bc)) {
                        *slot = Some((d, c));
                    }
                }
            }
        }
        if let Some((_, c)) = own {
            return Some(c);
        }
        if fallback.is_none() {
            fallback = any.map(|(_, c)| c);
            if room == 0 && fallback.is_some() {
                return fallback;
            }
        }
    }
    fallback
}

/// Checks a map against the house document it was imported from (`file` names it in errors).
/// A map that cannot have been imported from this house is an error (its holes and rooms would
/// be compared with another house's, and every difference reported as a defect).
pub fn check_house(
    doc: &serde_json::Value,
    file: &str,
    map: &SemanticMap,
) -> Result<ImportCheck, crate::map::MapError> {
    let house = super::house::parse_house(doc, &crate::map::error::ErrCtx::new(file))?;
    if let Some(why) = not_made_from(&house, map) {
        return Err(crate::map::MapError::new(
            file,
            "rooms",
            format!("map `{}` was not made from this house: {why}", map.map_id),
        ));
    }
    Ok(check_map(&house, map))
}

/// Why `map` cannot have been imported from `house`, if it cannot. The importer numbers the rooms
/// in house order from 1, names each by its category and keeps the floor polygon's area, so a map
/// of this house has the same number of rooms and, room by room, the same category and (within
/// 5 % and 0.1 m², for maps made by other tools) the same area; when the map records the house's
/// room id (`procthor_room_id=`), that too. Another house of the same generator matches all of
/// these only by a coincidence of every room's area.
pub fn not_made_from(house: &House, map: &SemanticMap) -> Option<String> {
    if house.rooms.len() != map.rooms.len() {
        return Some(format!(
            "the house has {} rooms, the map {}",
            house.rooms.len(),
            map.rooms.len()
        ));
    }
    for (i, hr) in house.rooms.iter().enumerate() {
        let Some(mr) = map.room(i as u32 + 1) else {
            return Some(format!(
                "the map has no room {} (the house's {})",
                i + 1,
                hr.id
            ));
        };
        let category = super::naming::category_snake(&hr.room_type);
        if mr.category != category {
            return Some(format!(
                "the house's room {} is a {category}, the map's room {} ({}) a {}",
                hr.id, mr.id, mr.name, mr.category
            ));
        }
        let recorded = mr
            .attributes
            .iter()
            .find_map(|a| a.strip_prefix("procthor_room_id="));
        if let Some(id) = recorded
            && id != hr.id
        {
            return Some(format!(
                "the map's room {} ({}) was imported from {id}, the house's room {} is {}",
                mr.id,
                mr.name,
                i + 1,
                hr.id
            ));
        }
        let area = super::raster::polygon_area(&hr.polygon);
        if (area - mr.area_m2).abs() > 0.05 * area.max(mr.area_m2) + 0.1 {
            return Some(format!(
                "the house's room {} ({category}) has {area:.2} m², the map's room {} ({}) {:.2} m²",
                hr.id, mr.id, mr.name, mr.area_m2
            ));
        }
    }
    None
}

/// Checks `map` against the house it was imported from.
pub(super) fn check_map(house: &House, map: &SemanticMap) -> ImportCheck {
    let res = map.resolution();
    let mut report = ImportCheck::default();
    let room_ids: HashMap<&str, u32> = house
        .rooms
        .iter()
        .enumerate()
        .map(|(i, r)| (r.id.as_str(), i as u32 + 1))
        .collect();
    let faces: HashMap<&str, ([f64; 2], [f64; 2])> = house
        .walls
        .iter()
        .map(|w| (w.id.as_str(), (w.a, w.b)))
        .collect();
    let mut by_source: HashMap<&str, Vec<&crate::map::Object>> = HashMap::new();
    for o in &map.objects {
        if let Some(id) = o
            .attributes
            .iter()
            .find_map(|a| a.strip_prefix("procthor_object_id="))
        {
            by_source.entry(id).or_default().push(o);
        }
    }
    let wall_cells: BTreeSet<Cell> = map
        .objects
        .iter()
        .filter(|o| o.category == "wall")
        .flat_map(|o| o.footprint.iter().copied())
        .collect();

    // Holes, along their own face.
    let holes = house
        .doors
        .iter()
        .enumerate()
        .map(|(i, h)| (format!("doors[{i}]"), h, true))
        .chain(
            house
                .windows
                .iter()
                .enumerate()
                .map(|(i, h)| (format!("windows[{i}]"), h, false)),
        );
    for (path, hole, is_door) in holes {
        let Some(&(a, b)) = faces.get(hole.wall0.as_str()) else {
            continue; // a house without walls[]: nothing independent to check against
        };
        report.holes += 1;
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        let dir = [(b[0] - a[0]) / len, (b[1] - a[1]) / len];
        let (lo, hi) = (hole.along[0].max(0.0), hole.along[1].min(len));
        let obj = by_source.get(hole.id.as_str()).and_then(|v| {
            let cat_ok = |c: &str| {
                if is_door {
                    c == "doorway" || c == "doorframe" || c == "door"
                } else {
                    c == "window"
                }
            };
            v.iter().find(|o| cat_ok(&o.category))
        });
        let cells: &[Cell] = obj.map_or(&[], |o| o.footprint.as_slice());
        let (mut tmin, mut tmax) = (f64::INFINITY, f64::NEG_INFINITY);
        for &c in cells {
            let (x, z) = map.cell_to_world(c);
            let t = (x - a[0]) * dir[0] + (z - a[1]) * dir[1];
            tmin = tmin.min(t);
            tmax = tmax.max(t);
        }
        let offset = if cells.is_empty() {
            f64::INFINITY
        } else {
            (tmin - lo).abs().max((tmax - hi).abs())
        };
        let walled = if is_door {
            cells.iter().filter(|c| wall_cells.contains(c)).count()
        } else {
            0
        };
        if offset > res + 1e-6 || walled > 0 {
            report.misplaced_holes.push(HoleIssue {
                path,
                id: hole.id.clone(),
                offset_m: offset,
                wall_cells: walled,
            });
        }
    }

    // What the house joins: doors between two rooms, open walls.
    let mut joined: BTreeSet<(u32, u32)> = BTreeSet::new();
    for d in &house.doors {
        if let (Some(&p), Some(&q)) = (
            room_ids.get(d.room0.as_str()),
            room_ids.get(d.room1.as_str()),
        ) && p != q
        {
            joined.insert((p.min(q), p.max(q)));
        }
    }
    for o in &map.open_boundaries {
        joined.insert(o.rooms);
    }
    let mut empty_faces: BTreeMap<[i64; 4], Vec<u32>> = BTreeMap::new();
    for w in house.walls.iter().filter(|w| w.empty) {
        let q = |v: f64| (v * 100.0).round() as i64;
        let (p, r) = ([q(w.a[0]), q(w.a[1])], [q(w.b[0]), q(w.b[1])]);
        let key = if p <= r {
            [p[0], p[1], r[0], r[1]]
        } else {
            [r[0], r[1], p[0], p[1]]
        };
        if let Some(&id) = w.room_id.as_deref().and_then(|r| room_ids.get(r)) {
            empty_faces.entry(key).or_default().push(id);
        }
    }
    for ids in empty_faces.values() {
        if let [p, q] = ids[..]
            && p != q
        {
            joined.insert((p.min(q), p.max(q)));
        }
    }

    // Reachability from the start.
    let start_room = house.agent.and_then(|(p, _)| {
        house
            .rooms
            .iter()
            .position(|r| inside_or_on(p, &r.polygon))
            .map(|i| i as u32 + 1)
    });
    report.start_room = start_room;
    if let (Some(sr), Some(start)) = (start_room, map.start) {
        let mut connected = vec![sr];
        let mut i = 0;
        while i < connected.len() {
            let r = connected[i];
            i += 1;
            for &(p, q) in &joined {
                let next = if p == r {
                    q
                } else if q == r {
                    p
                } else {
                    continue;
                };
                if !connected.contains(&next) {
                    connected.push(next);
                }
            }
        }
        connected.sort_unstable();
        let reached = rooms_reachable_from(map, start);
        report.unreachable_rooms = connected
            .iter()
            .copied()
            .filter(|r| !reached.contains(r))
            .collect();
        report.connected_rooms = connected;
    }

    // Leaks: passages over traversable cells that the house does not have.
    let free = map.occupancy.map(|&v| v == crate::map::FREE);
    let mut leaks: BTreeSet<(u32, u32)> = BTreeSet::new();
    for p in find_passages(map, &free) {
        if !joined.contains(&p.rooms) {
            leaks.insert(p.rooms);
        }
    }
    report.leaks = leaks.into_iter().collect();
    report
}
