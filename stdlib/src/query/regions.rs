//! Regions built from places: the area near a place, the centre of a set, and the waypoint chains
//! of loop-shaped preferences (circle, follow the walls, patrol).

use super::{MapQuery, Target};
use crate::grid::Cell;

/// Distance from an object's outline to the loop circled around it, metres.
const CIRCLE_OFFSET_M: f64 = 0.45;
/// Radius of each loop waypoint, metres.
const WAYPOINT_RADIUS_M: f64 = 0.25;
/// How far in from a room's corners the wall-following loop runs, metres.
const WALL_INSET_M: f64 = 0.5;
/// Radius of the region marking the centre of a set, metres.
const CENTER_RADIUS_M: f64 = 0.3;
/// Number of waypoints of a circle.
const CIRCLE_POINTS: usize = 8;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WaypointShape {
    Circle,
    /// Along the room's walls (also used for patrol).
    Walls,
}

impl MapQuery<'_> {
    /// Cells within `within_m` of the place (an object's own footprint excluded, since nobody can
    /// stand in it), sorted.
    pub fn area_near(&self, t: Target, within_m: f64) -> Vec<Cell> {
        let r = within_m / self.res();
        let own = self.cells(t);
        let mut out: Vec<Cell> = match t {
            // An object's outline is short: scanning its padded box once, in row-major (sorted)
            // order, beats a disk per outline cell and the sort of their union.
            Target::Object(_) => self.within_of(self.outline(t), r),
            _ => {
                let mut out: Vec<Cell> = Vec::new();
                for &c in self.outline(t) {
                    out.extend(self.disk([c.row as f64, c.col as f64], r));
                }
                out.sort_unstable();
                out.dedup();
                out
            }
        };
        match t {
            Target::Object(_) => out.retain(|c| own.binary_search(c).is_err()),
            _ => {
                out.extend_from_slice(own);
                out.sort_unstable();
                out.dedup();
            }
        }
        out
    }

    /// Cells whose centre is within `r` cells of some cell of `line` (the union of [`Self::disk`]
    /// around each of them, the same `1e-9` tolerance included), sorted.
    fn within_of(&self, line: &[Cell], r: f64) -> Vec<Cell> {
        let n = self.map.n() as i64;
        let r = r.max(0.0);
        let limit = r * r + 1e-9;
        // No cell lies farther than the grid's side, and a larger pad could overflow the bounds.
        let pad = r.ceil().min(n as f64) as i64;
        let (mut r0, mut c0, mut r1, mut c1) = (i64::MAX, i64::MAX, i64::MIN, i64::MIN);
        for c in line {
            let (row, col) = (c.row as i64, c.col as i64);
            (r0, c0, r1, c1) = (r0.min(row), c0.min(col), r1.max(row), c1.max(col));
        }
        let mut out = Vec::new();
        for row in (r0 - pad).max(0)..=(r1 + pad).min(n - 1) {
            for col in (c0 - pad).max(0)..=(c1 + pad).min(n - 1) {
                let cell = Cell::new(row as u32, col as u32);
                if line.iter().any(|f| cell.dist_sq(*f) as f64 <= limit) {
                    out.push(cell);
                }
            }
        }
        out
    }

    /// The centre of a set of places: a small disk around the mean of their centres, moved to the
    /// nearest traversable cell when the mean itself lies in furniture.
    pub fn center_of(&self, centers: &[[f64; 2]]) -> Vec<Cell> {
        if centers.is_empty() {
            return Vec::new();
        }
        let k = centers.len() as f64;
        let mean = [
            centers.iter().map(|c| c[0]).sum::<f64>() / k,
            centers.iter().map(|c| c[1]).sum::<f64>() / k,
        ];
        let r = (CENTER_RADIUS_M / self.res()).max(1.0);
        let disk = self.disk(mean, r);
        if disk.iter().any(|&c| self.is_traversable(c)) {
            return disk;
        }
        match self.nearest_traversable(mean, None) {
            Some(c) => self.disk([c.row as f64, c.col as f64], r),
            None => disk,
        }
    }
}

/// Ordered waypoint regions of a loop around `around` (an object or a room), turning `clockwise`
/// on screen (or not), starting with the waypoint nearest `from` and closed (the first waypoint is
/// repeated at the end). Waypoints are traversable cells of `room` when given.
pub fn loop_waypoints(
    q: &MapQuery,
    shape: WaypointShape,
    around: Target,
    room: Option<u32>,
    clockwise: bool,
    from: Option<Cell>,
) -> Vec<Vec<Cell>> {
    let cells = q.cells(around);
    let Some(centre) = MapQuery::centroid(cells) else {
        return Vec::new();
    };
    let (mut r0, mut c0, mut r1, mut c1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
    for c in cells {
        let (r, k) = (c.row as f64, c.col as f64);
        (r0, c0, r1, c1) = (r0.min(r), c0.min(k), r1.max(r), c1.max(k));
    }
    let mut ideal: Vec<[f64; 2]> = Vec::new();
    match (shape, around) {
        (WaypointShape::Circle, Target::Object(_)) => {
            let radius = (r1 - r0).max(c1 - c0) / 2.0 + CIRCLE_OFFSET_M / q.res();
            for i in 0..CIRCLE_POINTS {
                let t = std::f64::consts::TAU * i as f64 / CIRCLE_POINTS as f64;
                ideal.push([centre[0] + radius * t.sin(), centre[1] + radius * t.cos()]);
            }
        }
        (WaypointShape::Circle, _) => {
            let min = 0.3 / q.res();
            let (ry, rx) = ((0.36 * (r1 - r0)).max(min), (0.36 * (c1 - c0)).max(min));
            for i in 0..CIRCLE_POINTS {
                let t = std::f64::consts::TAU * i as f64 / CIRCLE_POINTS as f64;
                ideal.push([centre[0] + ry * t.sin(), centre[1] + rx * t.cos()]);
            }
        }
        (WaypointShape::Walls, _) => {
            let corners: Vec<[f64; 2]> = match around {
                Target::Room(r) => q
                    .corners(r)
                    .iter()
                    .filter_map(|c| MapQuery::centroid(c))
                    .collect(),
                _ => vec![[r0, c0], [r0, c1], [r1, c1], [r1, c0]],
            };
            let inset = WALL_INSET_M / q.res();
            let toward = |p: [f64; 2]| {
                let (dr, dc) = (centre[0] - p[0], centre[1] - p[1]);
                let len = dr.hypot(dc).max(1e-9);
                let s = (inset / len).min(0.5);
                [p[0] + dr * s, p[1] + dc * s]
            };
            for (i, &p) in corners.iter().enumerate() {
                let next = corners[(i + 1) % corners.len()];
                ideal.push(toward(p));
                ideal.push(toward([(p[0] + next[0]) / 2.0, (p[1] + next[1]) / 2.0]));
            }
        }
    }
    // Clockwise on screen (rows down) is increasing atan2(row, col).
    let angle = |p: &[f64; 2]| (p[0] - centre[0]).atan2(p[1] - centre[1]);
    ideal.sort_by(|a, b| angle(a).total_cmp(&angle(b)));
    if !clockwise {
        ideal.reverse();
    }
    let radius = WAYPOINT_RADIUS_M / q.res();
    // Only cells reachable from where the loop starts, so no waypoint sits in a pocket behind
    // furniture.
    let reach = from
        .filter(|&f| q.is_traversable(f))
        .map(|f| super::TravelField::new(q.traversable(), &[f], q.res()));
    let reachable = |c: Cell| reach.as_ref().is_none_or(|f| f.cells_to(c).is_finite());
    let mut snapped: Vec<Cell> = Vec::new();
    for p in ideal {
        if let Some(c) = q.nearest_traversable_where(p, room, reachable)
            && !snapped.contains(&c)
        {
            snapped.push(c);
        }
    }
    if let Some(from) = from
        && let Some(first) = (0..snapped.len())
            .min_by(|&a, &b| snapped[a].dist(from).total_cmp(&snapped[b].dist(from)))
    {
        snapped.rotate_left(first);
    }
    if snapped.len() > 1 {
        snapped.push(snapped[0]);
    }
    snapped
        .into_iter()
        .map(|c| {
            q.disk([c.row as f64, c.col as f64], radius)
                .into_iter()
                .filter(|&x| {
                    q.is_traversable(x) && room.is_none_or(|r| q.room_at(x) == r) && reachable(x)
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::fixture::two_rooms;
    use super::*;

    #[test]
    fn area_near_excludes_the_object_and_reaches_the_radius() {
        let map = two_rooms();
        let q = MapQuery::new(&map);
        let lamp = map.object(2).unwrap();
        let area = q.area_near(Target::Object(lamp), 0.2);
        assert!(!area.contains(&Cell::new(3, 7)));
        assert!(area.contains(&Cell::new(3, 9)) && area.contains(&Cell::new(1, 7)));
        assert!(!area.contains(&Cell::new(3, 10)));
    }

    /// The box scan of an object's area is the union of a disk around each outline cell, at
    /// every radius (fractional ones included, where the `1e-9` tolerance decides).
    #[test]
    fn area_near_of_an_object_is_the_union_of_its_outline_disks() {
        let map = two_rooms();
        let q = MapQuery::new(&map);
        for obj in &map.objects {
            let t = Target::Object(obj);
            for within_m in [0.0, 0.05, 0.1, 0.2, 0.25, 0.5, 1.0] {
                let r = within_m / q.res();
                let mut union: Vec<Cell> = q
                    .outline(t)
                    .iter()
                    .flat_map(|c| q.disk([c.row as f64, c.col as f64], r))
                    .collect();
                union.sort_unstable();
                union.dedup();
                union.retain(|c| obj.footprint.binary_search(c).is_err());
                assert_eq!(
                    q.area_near(t, within_m),
                    union,
                    "object {} within {within_m} m",
                    obj.id
                );
            }
        }
    }

    #[test]
    fn circle_runs_clockwise_around_the_table_and_closes() {
        let map = two_rooms();
        let q = MapQuery::new(&map);
        let table = map.object(9).unwrap();
        let from = Cell::new(18, 13);
        let cw = loop_waypoints(
            &q,
            WaypointShape::Circle,
            Target::Object(table),
            Some(2),
            true,
            Some(from),
        );
        assert!(cw.len() >= 5);
        assert_eq!(cw.first(), cw.last());
        assert!(
            cw.iter()
                .all(|w| !w.is_empty()
                    && w.iter().all(|&c| q.is_traversable(c) && q.room_at(c) == 2))
        );
        // The first waypoint is the one nearest the start, south of the table.
        assert!(cw[0].iter().all(|c| c.row > 14));
        // Clockwise on screen from the south goes west next.
        let centre = |w: &Vec<Cell>| MapQuery::centroid(w).unwrap();
        assert!(centre(&cw[1])[1] < centre(&cw[0])[1]);
        let ccw = loop_waypoints(
            &q,
            WaypointShape::Circle,
            Target::Object(table),
            Some(2),
            false,
            Some(from),
        );
        assert!(centre(&ccw[1])[1] > centre(&ccw[0])[1]);
    }

    #[test]
    fn wall_loop_stays_in_the_room() {
        let map = two_rooms();
        let q = MapQuery::new(&map);
        let w = loop_waypoints(
            &q,
            WaypointShape::Walls,
            Target::Room(1),
            Some(1),
            true,
            Some(Cell::new(18, 2)),
        );
        assert!(w.len() >= 6);
        assert!(w.iter().all(|x| x.iter().all(|&c| q.room_at(c) == 1)));
        let c = q.center_of(&[[3.0, 3.5], [10.5, 3.5]]);
        assert!(c.iter().any(|&x| q.is_traversable(x)));
    }
}
