//! Rooms: passages (doorways) between them, adjacency, corners, reachability.

use super::{MapQuery, Target};
use crate::grid::{Cell, Grid};
use crate::map::SemanticMap;
use std::collections::{BTreeMap, BTreeSet};

/// Largest unlabelled free patch still counted as a doorway joining the rooms around it, m². A
/// larger one (an unlabelled hall or the outdoors) is not a doorway.
const CONNECTOR_MAX_M2: f64 = 2.0;

/// A traversable connection between two rooms: one 8-connected group of free cells where the room
/// label changes (possibly through unlabelled door cells).
#[derive(Clone, Debug, PartialEq)]
pub struct Passage {
    /// The two rooms, smaller id first.
    pub rooms: (u32, u32),
    /// Sorted.
    pub cells: Vec<Cell>,
    /// Through a doorway, or across an open boundary (no wall at all).
    pub kind: PassageKind,
}

/// How a passage joins its rooms.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PassageKind {
    /// A doorway or door frame cut in a wall (any passage not on an open boundary).
    Door,
    /// An open boundary between open-plan rooms ([`crate::map::OpenBoundary`]).
    Open,
}

impl PassageKind {
    /// `door` / `open`, as `m2rc map info` prints it.
    pub fn name(self) -> &'static str {
        match self {
            PassageKind::Door => "door",
            PassageKind::Open => "open",
        }
    }
}

/// The passages of `map` over the `free` cells, ordered by room pair then position.
pub(crate) fn find_passages(map: &SemanticMap, free: &Grid<bool>) -> Vec<Passage> {
    let n = map.n();
    let label = |c: Cell| map.room_layer.get(c).copied().unwrap_or(0);
    let mut by_pair: BTreeMap<(u32, u32), BTreeSet<Cell>> = BTreeMap::new();
    // Label changes between 4-neighbours that are both free (over the raw rows: this visits every
    // cell of the map).
    let (labels, open) = (map.room_layer.data(), free.data());
    let ln = map.room_layer.n();
    let is_free = |i: usize, cell: Cell| {
        if free.n() == ln {
            open[i]
        } else {
            free.get(cell).copied().unwrap_or(false)
        }
    };
    for (i, &a) in labels.iter().enumerate() {
        if a == 0 || (free.n() == ln && !open[i]) {
            continue;
        }
        let cell = Cell::new((i / ln) as u32, (i % ln) as u32);
        if !is_free(i, cell) {
            continue;
        }
        let down =
            (cell.row as usize + 1 < ln).then(|| (i + ln, Cell::new(cell.row + 1, cell.col)));
        let right =
            (cell.col as usize + 1 < ln).then(|| (i + 1, Cell::new(cell.row, cell.col + 1)));
        for (j, q) in [down, right].into_iter().flatten() {
            let b = labels[j];
            if b != 0 && b != a && is_free(j, q) {
                let set = by_pair.entry((a.min(b), a.max(b))).or_default();
                set.insert(cell);
                set.insert(q);
            }
        }
    }
    // Small unlabelled free patches (door cells cut out of a wall) joining two or more rooms.
    let res = if map.frame.resolution > 0.0 {
        map.frame.resolution
    } else {
        1.0
    };
    let max_cells = (CONNECTOR_MAX_M2 / (res * res)).ceil() as usize;
    let mut seen = Grid::new(n, false);
    let same = free.n() == ln;
    for (i, &l) in labels.iter().enumerate() {
        if l != 0 || (same && !open[i]) {
            continue;
        }
        let cell = Cell::new((i / ln) as u32, (i % ln) as u32);
        if seen.get(cell) == Some(&true) || !is_free(i, cell) {
            continue;
        }
        let mut comp = vec![cell];
        seen.set(cell, true);
        let mut i = 0;
        let mut touching: BTreeMap<u32, BTreeSet<Cell>> = BTreeMap::new();
        while i < comp.len() {
            let c = comp[i];
            i += 1;
            for q in neighbours4(c, n) {
                if !free.get(q).copied().unwrap_or(false) {
                    continue;
                }
                match label(q) {
                    0 => {
                        if seen.get(q) == Some(&false) {
                            seen.set(q, true);
                            comp.push(q);
                        }
                    }
                    r => {
                        touching.entry(r).or_default().insert(q);
                    }
                }
            }
        }
        if comp.len() > max_cells || touching.len() < 2 {
            continue;
        }
        let rooms: Vec<u32> = touching.keys().copied().collect();
        for (i, &a) in rooms.iter().enumerate() {
            for &b in &rooms[i + 1..] {
                let set = by_pair.entry((a, b)).or_default();
                set.extend(comp.iter().copied());
                set.extend(touching[&a].iter().copied());
                set.extend(touching[&b].iter().copied());
            }
        }
    }
    let mut out = Vec::new();
    for (rooms, cells) in by_pair {
        let open: Vec<&[Cell]> = map
            .open_boundaries
            .iter()
            .filter(|o| o.rooms == rooms)
            .map(|o| o.cells.as_slice())
            .collect();
        for comp in components8(cells) {
            let on_open = comp
                .iter()
                .any(|c| open.iter().any(|o| o.binary_search(c).is_ok()));
            let kind = if on_open {
                PassageKind::Open
            } else {
                PassageKind::Door
            };
            out.push(Passage {
                rooms,
                cells: comp,
                kind,
            });
        }
    }
    out
}

fn neighbours4(c: Cell, n: usize) -> impl Iterator<Item = Cell> {
    let (r, k, n) = (c.row as i64, c.col as i64, n as i64);
    [(-1, 0), (1, 0), (0, -1), (0, 1)]
        .into_iter()
        .filter_map(move |(dr, dc)| {
            let (y, x) = (r + dr, k + dc);
            (y >= 0 && x >= 0 && y < n && x < n).then(|| Cell::new(y as u32, x as u32))
        })
}

/// 8-connected components of a cell set, each sorted, ordered by first cell.
fn components8(cells: BTreeSet<Cell>) -> Vec<Vec<Cell>> {
    let mut left = cells;
    let mut out = Vec::new();
    while let Some(&first) = left.iter().next() {
        left.remove(&first);
        let mut comp = vec![first];
        let mut i = 0;
        while i < comp.len() {
            let c = comp[i];
            i += 1;
            for dr in -1i64..=1 {
                for dc in -1i64..=1 {
                    let (y, x) = (c.row as i64 + dr, c.col as i64 + dc);
                    if y < 0 || x < 0 {
                        continue;
                    }
                    let q = Cell::new(y as u32, x as u32);
                    if left.remove(&q) {
                        comp.push(q);
                    }
                }
            }
        }
        comp.sort_unstable();
        out.push(comp);
    }
    out
}

impl MapQuery<'_> {
    pub fn passages(&self) -> &[Passage] {
        &self.passages
    }

    /// Passages touching `room`, ordered by the other room's id then position.
    pub fn doorways(&self, room: u32) -> Vec<&Passage> {
        let mut v: Vec<&Passage> = self
            .passages
            .iter()
            .filter(|p| p.rooms.0 == room || p.rooms.1 == room)
            .collect();
        v.sort_by_key(|p| (other(p, room), p.cells.first().copied()));
        v
    }

    /// Passages between two rooms, in position order.
    pub fn doorways_between(&self, a: u32, b: u32) -> Vec<&Passage> {
        let key = (a.min(b), a.max(b));
        self.passages.iter().filter(|p| p.rooms == key).collect()
    }

    /// Rooms sharing at least one passage with `room`, by id.
    pub fn adjacent_rooms(&self, room: u32) -> Vec<u32> {
        let mut v: Vec<u32> = self.doorways(room).iter().map(|p| other(p, room)).collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    pub fn adjacent(&self, a: u32, b: u32) -> bool {
        a != b && !self.doorways_between(a, b).is_empty()
    }

    /// The open-plan area `room` belongs to: `room` and every room joined to it by open
    /// boundaries (walls ProcTHOR leaves out, typically kitchen and living room), directly or
    /// through other open-plan rooms; sorted. A room with no open boundary is its own area.
    /// The rooms keep their own labels: the area is a set of rooms, not a new room.
    pub fn open_area(&self, room: u32) -> Vec<u32> {
        open_area(self.map, room)
    }

    /// `room.only_reachable_through(through)`: the room has at least one neighbour and every
    /// neighbour is in `through` (so any way in crosses one of them).
    pub fn only_reachable_through(&self, room: u32, through: &[u32]) -> bool {
        let adj = self.adjacent_rooms(room);
        !adj.is_empty() && adj.iter().all(|r| through.contains(r))
    }

    /// Floor area in m²: the map's figure, or the cell count when the map gives none.
    pub fn room_area(&self, room: u32) -> f64 {
        match self.map.room(room) {
            Some(r) if r.area_m2 > 0.0 => r.area_m2,
            _ => self.room_cells(room).len() as f64 * self.res() * self.res(),
        }
    }

    /// The corners of a room's outline (convex and concave), each as the room cells within
    /// `corner_radius_m` of the corner, clockwise on screen starting from the west.
    pub fn corners(&self, room: u32) -> Vec<Vec<Cell>> {
        let cells = self.room_cells(room);
        let inside = |r: i64, c: i64| {
            r >= 0 && c >= 0 && self.room_at(Cell::new(r as u32, c as u32)) == room
        };
        // A corner is a lattice point (cell vertex) where the room's outline turns: among the
        // four cells around it, one or three are in the room.
        let mut points: BTreeSet<(i64, i64)> = BTreeSet::new();
        for c in cells {
            let (r, k) = (c.row as i64, c.col as i64);
            for (vr, vc) in [(r, k), (r, k + 1), (r + 1, k), (r + 1, k + 1)] {
                let around = [
                    inside(vr - 1, vc - 1),
                    inside(vr - 1, vc),
                    inside(vr, vc - 1),
                    inside(vr, vc),
                ];
                let count = around.iter().filter(|&&x| x).count();
                let diagonal = count == 2 && around[0] == around[3];
                if count == 1 || count == 3 || diagonal {
                    points.insert((vr, vc));
                }
            }
        }
        let Some(centre) = Self::centroid(cells) else {
            return Vec::new();
        };
        // Rasterised diagonal walls produce staircases of tiny corners; keep corners at least a
        // corner radius apart.
        let radius = self.thresholds.corner_radius_m / self.res();
        let mut kept: Vec<[f64; 2]> = Vec::new();
        for (r, c) in points {
            let p = [r as f64 - 0.5, c as f64 - 0.5];
            if kept
                .iter()
                .all(|q| (q[0] - p[0]).hypot(q[1] - p[1]) >= radius)
            {
                kept.push(p);
            }
        }
        let angle = |p: &[f64; 2]| (p[0] - centre[0]).atan2(p[1] - centre[1]);
        kept.sort_by(|a, b| angle(a).total_cmp(&angle(b)));
        kept.into_iter()
            .map(|p| {
                self.disk(p, radius)
                    .into_iter()
                    .filter(|&c| self.room_at(c) == room)
                    .collect()
            })
            .filter(|v: &Vec<Cell>| !v.is_empty())
            .collect()
    }

    /// The room a place is in: an object's room, the room holding most of the cells otherwise.
    pub fn room_of(&self, t: Target) -> Option<u32> {
        match t {
            Target::Room(r) => Some(r),
            Target::Object(o) if o.room.is_some() => o.room,
            _ => {
                let mut counts: BTreeMap<u32, usize> = BTreeMap::new();
                for &c in self.cells(t) {
                    let l = self.room_at(c);
                    if l != 0 {
                        *counts.entry(l).or_default() += 1;
                    }
                }
                // Most cells wins; ties go to the smaller id.
                counts
                    .into_iter()
                    .max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(&a.0)))
                    .map(|(r, _)| r)
            }
        }
    }
}

/// [`MapQuery::open_area`] on a map without building a query index.
pub fn open_area(map: &SemanticMap, room: u32) -> Vec<u32> {
    let mut area = vec![room];
    let mut i = 0;
    while i < area.len() {
        let r = area[i];
        i += 1;
        for o in &map.open_boundaries {
            let next = if o.rooms.0 == r {
                o.rooms.1
            } else if o.rooms.1 == r {
                o.rooms.0
            } else {
                continue;
            };
            if !area.contains(&next) {
                area.push(next);
            }
        }
    }
    area.sort_unstable();
    area
}

fn other(p: &Passage, room: u32) -> u32 {
    if p.rooms.0 == room {
        p.rooms.1
    } else {
        p.rooms.0
    }
}

#[cfg(test)]
mod tests {
    use super::super::fixture::two_rooms;
    use super::*;

    #[test]
    fn door_cells_join_rooms() {
        let map = two_rooms();
        let q = MapQuery::new(&map);
        assert_eq!(q.passages().len(), 1);
        let p = &q.passages()[0];
        assert_eq!(p.rooms, (1, 2));
        assert!(p.cells.contains(&Cell::new(8, 9)));
        assert_eq!(q.adjacent_rooms(1), vec![2]);
        assert!(q.adjacent(2, 1));
        assert!(!q.adjacent(1, 1));
        assert!(q.only_reachable_through(2, &[1]));
        assert!(!q.only_reachable_through(2, &[]));
        assert_eq!(q.doorways_between(2, 1).len(), 1);
    }

    /// The map's adjacency and the queries' passages are one definition: the same room pairs.
    #[test]
    fn map_adjacency_is_the_passage_adjacency() {
        let house = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../shared/procthor/fixtures/procthor10k_uniform_hard_val_150_149.json"
        );
        let mut maps = vec![two_rooms(), crate::demo::demo_map().expect("demo map")];
        if std::path::Path::new(house).exists() {
            maps.push(crate::load::load_map(house).expect("fixture house loads"));
        }
        for map in &maps {
            let q = MapQuery::new(map);
            let mut pairs: Vec<(u32, u32)> = q.passages().iter().map(|p| p.rooms).collect();
            pairs.dedup();
            assert_eq!(map.room_adjacency(), pairs, "{}", map.map_id);
            for r in &map.rooms {
                assert_eq!(
                    map.neighbours(r.id),
                    q.adjacent_rooms(r.id),
                    "{}",
                    map.map_id
                );
            }
        }
    }

    #[test]
    fn rectangular_room_has_four_corners_clockwise() {
        let map = two_rooms();
        let q = MapQuery::new(&map);
        let corners = q.corners(1);
        assert_eq!(corners.len(), 4);
        // Clockwise from the west: top-left, top-right, bottom-right, bottom-left.
        let c: Vec<[f64; 2]> = corners
            .iter()
            .map(|c| MapQuery::centroid(c).unwrap())
            .collect();
        assert!(c[0][0] < 5.0 && c[0][1] < 4.0, "{c:?}");
        assert!(c[1][0] < 5.0 && c[1][1] > 4.0, "{c:?}");
        assert!(c[2][0] > 15.0 && c[2][1] > 4.0, "{c:?}");
        assert!(c[3][0] > 15.0 && c[3][1] < 4.0, "{c:?}");
        assert!(corners.iter().all(|c| c.iter().all(|&x| q.room_at(x) == 1)));
        assert!((q.room_area(1) - 1.8).abs() < 1e-9);
    }

    #[test]
    fn room_of_regions_is_majority_room() {
        let map = two_rooms();
        let q = MapQuery::new(&map);
        let cells = [Cell::new(5, 8), Cell::new(5, 10), Cell::new(5, 11)];
        assert_eq!(q.room_of(Target::Cells(&cells)), Some(2));
    }
}
