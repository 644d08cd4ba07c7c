//! Legal shortest paths on the benchmark grid, with the evaluator's move rules: 8-connected, cost 1
//! and √2, a diagonal needs both orthogonal corner cells passable (no corner cutting), and a move
//! may not touch a forbidden cell even at a corner (a diagonal touches its two corner cells).
//!
//! The generator uses it to prove every episode feasible and to draw the reference route; the
//! `shortest` method uses it as its planner, so the baseline needs nothing but the annotation.

use crate::route::validity::diagonal_corners;
use m2rc_stdlib::grid::Cell;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// A passability mask over an N×N grid (true = a robot may stand there).
#[derive(Clone, Debug)]
pub struct PassMask {
    n: usize,
    pass: Vec<bool>,
}

#[derive(Clone, Copy, PartialEq)]
struct Entry {
    cost: f64,
    index: usize,
}

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        // Min-heap on cost; ties broken by index so that paths are deterministic.
        other
            .cost
            .total_cmp(&self.cost)
            .then_with(|| other.index.cmp(&self.index))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

const MOVES: [(i64, i64); 8] = [
    (-1, 0),
    (1, 0),
    (0, -1),
    (0, 1),
    (-1, -1),
    (-1, 1),
    (1, -1),
    (1, 1),
];

impl PassMask {
    pub fn new(n: usize, pass: Vec<bool>) -> Self {
        assert_eq!(pass.len(), n * n, "mask length must be n*n");
        PassMask { n, pass }
    }

    /// The mask as a grid (for the stdlib's distance fields).
    pub fn to_grid(&self) -> m2rc_stdlib::grid::Grid<bool> {
        m2rc_stdlib::grid::Grid::from_vec(self.n, self.pass.clone())
            .unwrap_or_else(|| m2rc_stdlib::grid::Grid::new(self.n, false))
    }

    pub fn n(&self) -> usize {
        self.n
    }

    pub fn index(&self, cell: Cell) -> usize {
        cell.row as usize * self.n + cell.col as usize
    }

    pub fn cell(&self, index: usize) -> Cell {
        Cell::new((index / self.n) as u32, (index % self.n) as u32)
    }

    pub fn passable(&self, cell: Cell) -> bool {
        (cell.row as usize) < self.n && (cell.col as usize) < self.n && self.pass[self.index(cell)]
    }

    /// A copy with `cells` made impassable.
    pub fn without(&self, cells: impl IntoIterator<Item = usize>) -> PassMask {
        let mut out = self.clone();
        for i in cells {
            if i < out.pass.len() {
                out.pass[i] = false;
            }
        }
        out
    }

    /// The shortest legal path from `start` to any cell whose `goal` flag is set, start included.
    /// `None` when the start is impassable or no goal cell is reachable.
    pub fn shortest_to(&self, start: Cell, goal: &[bool]) -> Option<(Vec<Cell>, f64)> {
        if !self.passable(start) {
            return None;
        }
        let n = self.n;
        let s = self.index(start);
        if goal.get(s).copied().unwrap_or(false) {
            return Some((vec![start], 0.0));
        }
        let mut dist = vec![f64::INFINITY; n * n];
        let mut prev = vec![usize::MAX; n * n];
        let mut heap = BinaryHeap::new();
        dist[s] = 0.0;
        heap.push(Entry {
            cost: 0.0,
            index: s,
        });
        while let Some(Entry { cost, index }) = heap.pop() {
            if cost > dist[index] {
                continue;
            }
            if goal.get(index).copied().unwrap_or(false) {
                let mut path = vec![self.cell(index)];
                let mut at = index;
                while prev[at] != usize::MAX {
                    at = prev[at];
                    path.push(self.cell(at));
                }
                path.reverse();
                return Some((path, cost));
            }
            let (r, c) = ((index / n) as i64, (index % n) as i64);
            for (dr, dc) in MOVES {
                let (nr, nc) = (r + dr, c + dc);
                if !self.ok(nr, nc) {
                    continue;
                }
                let corners = diagonal_corners([r, c], [nr, nc]);
                if corners.is_some_and(|cs| !cs.iter().all(|&[cr, cc]| self.ok(cr, cc))) {
                    continue;
                }
                let diagonal = corners.is_some();
                let next = nr as usize * n + nc as usize;
                let step = if diagonal {
                    std::f64::consts::SQRT_2
                } else {
                    1.0
                };
                let nd = cost + step;
                if nd < dist[next] {
                    dist[next] = nd;
                    prev[next] = index;
                    heap.push(Entry {
                        cost: nd,
                        index: next,
                    });
                }
            }
        }
        None
    }

    fn ok(&self, r: i64, c: i64) -> bool {
        r >= 0
            && c >= 0
            && (r as usize) < self.n
            && (c as usize) < self.n
            && self.pass[r as usize * self.n + c as usize]
    }

    /// Cells reachable from `start` (flood fill with the same move rules).
    pub fn reachable_from(&self, start: Cell) -> Vec<bool> {
        let mut seen = vec![false; self.n * self.n];
        if !self.passable(start) {
            return seen;
        }
        let n = self.n;
        let mut stack = vec![self.index(start)];
        seen[self.index(start)] = true;
        while let Some(index) = stack.pop() {
            let (r, c) = ((index / n) as i64, (index % n) as i64);
            for (dr, dc) in MOVES {
                let (nr, nc) = (r + dr, c + dc);
                if !self.ok(nr, nc) {
                    continue;
                }
                if dr != 0 && dc != 0 && !(self.ok(r + dr, c) && self.ok(r, c + dc)) {
                    continue;
                }
                let next = nr as usize * n + nc as usize;
                if !seen[next] {
                    seen[next] = true;
                    stack.push(next);
                }
            }
        }
        seen
    }
}

/// One leg of a sequential route: reach `goal` while `forbidden` cells are never touched.
pub struct Leg<'a> {
    pub goal: &'a [bool],
    pub forbidden: &'a [usize],
}

/// Chains legs from `start`: each leg starts where the previous one ended. Returns the full
/// trajectory (no repeated junction cells) and its length in cells.
pub fn chain_legs(free: &PassMask, start: Cell, legs: &[Leg<'_>]) -> Option<(Vec<Cell>, f64)> {
    let mut route = vec![start];
    let mut length = 0.0;
    let mut at = start;
    for leg in legs {
        let mask = free.without(leg.forbidden.iter().copied());
        let (path, cost) = mask.shortest_to(at, leg.goal)?;
        route.extend(path.iter().skip(1).copied());
        length += cost;
        at = *path.last()?;
    }
    Some((route, length))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn open(n: usize) -> PassMask {
        PassMask::new(n, vec![true; n * n])
    }

    #[test]
    fn diagonal_never_cuts_a_blocked_corner() {
        let mut mask = open(3);
        mask.pass[4] = false; // centre (1,1)
        let mut goal = vec![false; 9];
        goal[8] = true;
        let (path, cost) = mask.shortest_to(Cell::new(0, 0), &goal).unwrap();
        assert_eq!(cost, 4.0, "{path:?}");
    }

    #[test]
    fn forbidden_cells_are_not_touched_at_corners() {
        let free = open(3);
        let mut goal = vec![false; 9];
        goal[4] = true; // (1,1)
        // Forbidding (0,1) makes the diagonal from (0,0) illegal: it would touch (0,1) at a corner.
        let forbidden = [1usize];
        let (route, len) = chain_legs(
            &free,
            Cell::new(0, 0),
            &[Leg {
                goal: &goal,
                forbidden: &forbidden,
            }],
        )
        .unwrap();
        assert_eq!(
            route,
            vec![Cell::new(0, 0), Cell::new(1, 0), Cell::new(1, 1)]
        );
        assert_eq!(len, 2.0);
    }

    #[test]
    fn unreachable_goal_is_none() {
        let mut mask = open(3);
        for i in [1, 4, 7] {
            mask.pass[i] = false;
        }
        let mut goal = vec![false; 9];
        goal[2] = true;
        assert!(mask.shortest_to(Cell::new(0, 0), &goal).is_none());
    }
}
