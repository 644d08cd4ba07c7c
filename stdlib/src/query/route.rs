//! Places that depend on the route: the room before entering a room, the doorway used to enter or
//! leave it, the first room of a set that the route enters.
//!
//! They are read off a path (a planned route, or before planning the shortest traversable path),
//! as the sequence of rooms it visits; unlabelled cells (door cells, walls) do not end a visit.

use super::{MapQuery, Target};
use crate::grid::Cell;

/// One stay of a path in a room: path indices of the first and last cell in it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RoomVisit {
    pub room: u32,
    pub enter: usize,
    pub leave: usize,
}

/// The rooms a path passes through, in order.
pub fn room_visits(q: &MapQuery, path: &[Cell]) -> Vec<RoomVisit> {
    let mut out: Vec<RoomVisit> = Vec::new();
    for (i, &c) in path.iter().enumerate() {
        let l = q.room_at(c);
        if l == 0 {
            continue;
        }
        match out.last_mut() {
            Some(v) if v.room == l => v.leave = i,
            _ => out.push(RoomVisit {
                room: l,
                enter: i,
                leave: i,
            }),
        }
    }
    out
}

/// The shortest traversable path from `from` to the nearest reachable cell of `to`; `None` when no
/// cell of `to` can be reached.
pub fn nominal_path(q: &MapQuery, from: Target, to: &[Cell]) -> Option<Vec<Cell>> {
    let field = q.travel_field(from);
    let goal = to
        .iter()
        .copied()
        .filter(|&c| field.cells_to(c).is_finite())
        .min_by(|a, b| {
            field
                .cells_to(*a)
                .total_cmp(&field.cells_to(*b))
                .then(a.cmp(b))
        })?;
    field.path_to(q.traversable(), goal)
}

impl MapQuery<'_> {
    /// The room the path was in just before it first entered `room` (a start inside `room` does
    /// not count as entering it).
    pub fn room_before_entering(&self, path: &[Cell], room: u32) -> Option<u32> {
        let v = room_visits(self, path);
        (1..v.len())
            .find(|&k| v[k].room == room)
            .map(|k| v[k - 1].room)
    }

    /// The doorway the path crossed when it first entered `room`.
    pub fn doorway_entering(&self, path: &[Cell], room: u32) -> Option<Vec<Cell>> {
        let v = room_visits(self, path);
        let k = (1..v.len()).find(|&k| v[k].room == room)?;
        Some(self.crossing(path, v[k - 1].room, room, v[k - 1].leave, v[k].enter))
    }

    /// The doorway the path crossed when it first left `room`.
    pub fn doorway_leaving(&self, path: &[Cell], room: u32) -> Option<Vec<Cell>> {
        let v = room_visits(self, path);
        let k = (0..v.len().saturating_sub(1)).find(|&k| v[k].room == room)?;
        Some(self.crossing(path, room, v[k + 1].room, v[k].leave, v[k + 1].enter))
    }

    /// The first room of `rooms` that the path enters; the start room counts only when the path
    /// enters no other room of the set.
    pub fn first_entered(&self, path: &[Cell], rooms: &[u32]) -> Option<u32> {
        let v = room_visits(self, path);
        v.iter()
            .skip(1)
            .chain(v.first())
            .find(|x| rooms.contains(&x.room))
            .map(|x| x.room)
    }

    /// The passage between `a` and `b` nearest to where the path crossed (path indices `i..=j`);
    /// when the map has no passage there, the crossed cells themselves.
    fn crossing(&self, path: &[Cell], a: u32, b: u32, i: usize, j: usize) -> Vec<Cell> {
        let crossed = &path[i.min(j)..=j.max(i).min(path.len() - 1)];
        let best = self
            .doorways_between(a, b)
            .into_iter()
            .map(|p| {
                let d = p
                    .cells
                    .iter()
                    .flat_map(|c| crossed.iter().map(move |x| c.dist(*x)))
                    .fold(f64::INFINITY, f64::min);
                (d, p)
            })
            .min_by(|x, y| x.0.total_cmp(&y.0));
        match best {
            Some((_, p)) => p.cells.clone(),
            None => {
                let mut v = crossed.to_vec();
                v.sort_unstable();
                v.dedup();
                v
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::fixture::two_rooms;
    use super::*;

    #[test]
    fn nominal_path_reads_rooms_and_doorways() {
        let map = two_rooms();
        let q = MapQuery::new(&map);
        let start = [Cell::new(18, 2)];
        let kitchen = q.room_cells(2).to_vec();
        let path = nominal_path(&q, Target::Cells(&start), &kitchen).unwrap();
        assert_eq!(path[0], Cell::new(18, 2));
        assert_eq!(q.room_at(*path.last().unwrap()), 2);
        let visits = room_visits(&q, &path);
        assert_eq!(
            visits.iter().map(|v| v.room).collect::<Vec<_>>(),
            vec![1, 2]
        );
        assert_eq!(q.room_before_entering(&path, 2), Some(1));
        assert_eq!(
            q.room_before_entering(&path, 1),
            None,
            "the route starts in the bedroom"
        );
        let door = q.doorway_entering(&path, 2).unwrap();
        assert!(door.contains(&Cell::new(8, 9)));
        assert_eq!(q.doorway_leaving(&path, 1), Some(door));
        assert_eq!(
            q.doorway_leaving(&path, 2),
            None,
            "the route ends in the kitchen"
        );
        assert_eq!(q.first_entered(&path, &[1, 2]), Some(2));
        assert_eq!(q.first_entered(&path, &[1]), Some(1));
    }
}
