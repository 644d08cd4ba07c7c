//! Goal masks per target kind, with the reference fallbacks (method notes §4.2): a room is reached
//! at its first traversable cell; an object within a band of `goal radius` cells around its
//! footprint, inside its room; an unusable "near" region or object band falls back to the room's
//! traversable cell nearest the centre.

use crate::problem::{Fallback, Target};
use m2rc_stdlib::field;
use m2rc_stdlib::grid::Cell;

/// The goal mask (row-major, `n`×`n`) of `target`: target cells that are traversable, after the
/// fallbacks. All false means the target is empty.
pub fn goal_mask(
    target: &Target,
    traversable: &[bool],
    n: usize,
    goal_radius_cells: f64,
) -> Vec<bool> {
    match target {
        Target::Position(c) => {
            let mut m = vec![false; n * n];
            if (c.row as usize) < n && (c.col as usize) < n {
                let i = c.row as usize * n + c.col as usize;
                m[i] = traversable[i];
            }
            m
        }
        Target::Room(area) => intersect(area.to_mask(n), traversable),
        Target::Region { cells, fallback } => {
            let m = intersect(cells.to_mask(n), traversable);
            match fallback {
                Some(fb) if !m.iter().any(|v| *v) => fallback_mask(fb, traversable, n),
                _ => m,
            }
        }
        Target::Object {
            footprint,
            room,
            center,
        } => {
            let mut m = object_band(footprint, goal_radius_cells, n);
            if let Some(room) = room {
                let rm = room.to_mask(n);
                m.iter_mut().zip(&rm).for_each(|(a, b)| *a &= *b);
            }
            let m = intersect(m, traversable);
            if m.iter().any(|v| *v) {
                m
            } else {
                fallback_mask(
                    &Fallback {
                        room: room.clone(),
                        center: *center,
                    },
                    traversable,
                    n,
                )
            }
        }
        Target::AnyOf(members) => {
            let mut m = vec![false; n * n];
            for t in members {
                let g = goal_mask(t, traversable, n, goal_radius_cells);
                m.iter_mut().zip(&g).for_each(|(a, b)| *a |= *b);
            }
            m
        }
    }
}

/// Which member of a set target (`Target::AnyOf`) a route that ended at `end` reached: the first,
/// in the set's order, whose own goal holds `end`. `None` for other targets, or when no member's
/// goal holds it.
pub fn member_reached(
    target: &Target,
    end: Cell,
    traversable: &[bool],
    n: usize,
    goal_radius_cells: f64,
) -> Option<usize> {
    let Target::AnyOf(members) = target else {
        return None;
    };
    if end.row as usize >= n || end.col as usize >= n {
        return None;
    }
    let at = end.row as usize * n + end.col as usize;
    members
        .iter()
        .position(|t| goal_mask(t, traversable, n, goal_radius_cells)[at])
}

fn intersect(mut m: Vec<bool>, traversable: &[bool]) -> Vec<bool> {
    m.iter_mut().zip(traversable).for_each(|(a, b)| *a &= *b);
    m
}

/// Cells with `0 < d ≤ radius` from the footprint, computed on a window around the footprint only
/// (exact: the window holds every footprint cell and every cell within `radius` of one).
pub fn object_band(footprint: &[Cell], radius: f64, n: usize) -> Vec<bool> {
    let mut out = vec![false; n * n];
    let inside: Vec<Cell> = footprint
        .iter()
        .copied()
        .filter(|c| (c.row as usize) < n && (c.col as usize) < n)
        .collect();
    if inside.is_empty() {
        return out;
    }
    let pad = radius.ceil() as i64 + 1;
    let r0 = inside.iter().map(|c| c.row as i64).min().unwrap_or(0) - pad;
    let r1 = inside.iter().map(|c| c.row as i64).max().unwrap_or(0) + pad;
    let c0 = inside.iter().map(|c| c.col as i64).min().unwrap_or(0) - pad;
    let c1 = inside.iter().map(|c| c.col as i64).max().unwrap_or(0) + pad;
    let side = ((r1 - r0).max(c1 - c0) + 1) as usize;
    let mut src = vec![false; side * side];
    for c in &inside {
        src[(c.row as i64 - r0) as usize * side + (c.col as i64 - c0) as usize] = true;
    }
    let d = field::distances(&src, side);
    for wr in 0..side {
        let r = r0 + wr as i64;
        if r < 0 || r >= n as i64 {
            continue;
        }
        for wc in 0..side {
            let c = c0 + wc as i64;
            if c < 0 || c >= n as i64 {
                continue;
            }
            let v = d[wr * side + wc];
            if v > 0.0 && v <= radius {
                out[r as usize * n + c as usize] = true;
            }
        }
    }
    out
}

/// The single traversable cell of the fallback room nearest its centre (ties: lower row, then
/// lower column), or an empty mask when the room has no traversable cell.
pub fn fallback_mask(fb: &Fallback, traversable: &[bool], n: usize) -> Vec<bool> {
    let room = fb.room.as_ref().map(|r| r.to_mask(n));
    let mut best: Option<(f64, usize)> = None;
    for (i, &t) in traversable.iter().enumerate() {
        if !t || room.as_ref().is_some_and(|m| !m[i]) {
            continue;
        }
        let dr = (i / n) as f64 - fb.center[0];
        let dc = (i % n) as f64 - fb.center[1];
        let d = dr * dr + dc * dc;
        if best.is_none_or(|(bd, _)| d < bd) {
            best = Some((d, i));
        }
    }
    let mut out = vec![false; n * n];
    if let Some((_, i)) = best {
        out[i] = true;
    }
    out
}

/// `max(1, round(r / resolution))`, the reference goal radius in cells.
pub fn goal_radius_cells(goal_radius_m: f64, resolution: f64) -> f64 {
    (goal_radius_m / resolution).round().max(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::Area;

    fn cells_of(m: &[bool], n: usize) -> Vec<(usize, usize)> {
        m.iter()
            .enumerate()
            .filter(|(_, v)| **v)
            .map(|(i, _)| (i / n, i % n))
            .collect()
    }

    #[test]
    fn object_band_excludes_footprint_and_respects_radius() {
        let n = 7;
        let band = object_band(&[Cell::new(3, 3)], 1.0, n);
        assert_eq!(cells_of(&band, n), vec![(2, 3), (3, 2), (3, 4), (4, 3)]);
        let band = object_band(&[Cell::new(0, 0)], 1.5, n);
        assert_eq!(cells_of(&band, n), vec![(0, 1), (1, 0), (1, 1)]);
    }

    #[test]
    fn object_band_is_clipped_to_room_and_traversable() {
        let n = 5;
        let trav = vec![true; n * n];
        let room: Vec<bool> = (0..n * n).map(|i| i < n).collect(); // row 0 only
        let t = Target::Object {
            footprint: vec![Cell::new(1, 2)],
            room: Some(Area::mask(
                m2rc_stdlib::grid::Grid::from_vec(n, room).unwrap(),
            )),
            center: [1.0, 2.0],
        };
        assert_eq!(cells_of(&goal_mask(&t, &trav, n, 1.0), n), vec![(0, 2)]);
    }

    #[test]
    fn object_falls_back_to_nearest_room_cell() {
        // The band is all blocked: the fallback is the traversable room cell nearest the centre.
        let n = 5;
        let mut trav = vec![true; n * n];
        for r in 0..3 {
            for c in 0..3 {
                trav[r * n + c] = false;
            }
        }
        let t = Target::Object {
            footprint: vec![Cell::new(1, 1)],
            room: None,
            center: [1.0, 1.0],
        };
        assert_eq!(cells_of(&goal_mask(&t, &trav, n, 1.5), n), vec![(1, 3)]);
    }

    #[test]
    fn room_and_region_targets() {
        let n = 4;
        let mut trav = vec![true; n * n];
        trav[0] = false;
        let area = Area::Cells(vec![Cell::new(0, 0), Cell::new(0, 1)]);
        assert_eq!(
            cells_of(&goal_mask(&Target::Room(area.clone()), &trav, n, 1.0), n),
            vec![(0, 1)]
        );
        let blocked = Area::Cells(vec![Cell::new(0, 0)]);
        let no_fb = Target::Region {
            cells: blocked.clone(),
            fallback: None,
        };
        assert!(cells_of(&goal_mask(&no_fb, &trav, n, 1.0), n).is_empty());
        let fb = Target::Region {
            cells: blocked,
            fallback: Some(Fallback {
                room: None,
                center: [0.0, 0.0],
            }),
        };
        assert_eq!(cells_of(&goal_mask(&fb, &trav, n, 1.0), n), vec![(0, 1)]);
        assert!(
            cells_of(
                &goal_mask(&Target::Position(Cell::new(0, 0)), &trav, n, 1.0),
                n
            )
            .is_empty()
        );
        assert!(
            cells_of(
                &goal_mask(&Target::Position(Cell::new(9, 9)), &trav, n, 1.0),
                n
            )
            .is_empty()
        );
    }

    #[test]
    fn reference_goal_radius() {
        assert_eq!(goal_radius_cells(0.30, 0.05), 6.0);
        assert_eq!(goal_radius_cells(0.30, 1.0), 1.0);
    }
}
