//! Flat-array A* over the padded grid: the one search every planner calls.
//!
//! It reproduces the reference search exactly (method notes §4.1, §4.5): moves in the order up,
//! down, left, right, then the diagonals; diagonals need both orthogonal neighbours traversable
//! (no corner cutting, checked on the base grid, or on the avoid mask too when the profile asks); entering a cell costs the step
//! (1 or √2) plus its field value Φ plus the turn penalty; the open list is ordered by
//! `(f, push counter)` so ties pop first-in first-out; a node is updated only on strict improvement;
//! closed nodes are never re-expanded; the goal test happens at pop time.
//!
//! Buffers are reused between searches; a generation tag per cell marks which entries belong to the
//! current search, so starting a search costs nothing proportional to the grid.

use crate::layout::{Layout, NO_HEADING, turn_table};
use crate::open_list::OpenEntry;
use m2rc_stdlib::field::LazySquaredDistances;
use std::collections::BinaryHeap;

/// The grid a search runs on, in the padded layout.
#[derive(Clone, Copy)]
pub struct Space<'a> {
    pub layout: Layout,
    /// The cells a diagonal step may pass the corner of ([`crate::layout::corners_free`]): the
    /// base traversability (the reference rule), or the allowed cells when avoided cells'
    /// corners count too ([`crate::problem::CostProfile::avoid_corners`]).
    pub traversable: &'a [bool],
    /// Cells the search may enter: traversable and not avoided.
    pub allowed: &'a [bool],
    /// Extra cost of entering each cell; `None` = 0 everywhere.
    pub phi: Option<&'a [f64]>,
}

/// Lower bound of the remaining cost from a cell.
#[derive(Clone, Copy)]
pub enum Heuristic<'a> {
    /// Dijkstra.
    Zero,
    /// A per-cell table (padded), e.g. the distance to the nearest target cell.
    Table(&'a [f64]),
    /// A per-cell table of squared distances (padded); the square root is taken when a node is
    /// pushed, which halves the table's memory traffic and skips a full pass to build it.
    SquaredTable(&'a [u32]),
    /// [`Heuristic::SquaredTable`] computed a row at a time as the search reaches it (padded).
    LazySquared(&'a LazySquaredDistances),
    /// Straight-line distance to a box `[r0, r1] × [c0, c1]` of padded rows and columns.
    Box {
        r0: usize,
        r1: usize,
        c0: usize,
        c1: usize,
    },
}

/// Turn penalty inside a mask (loop-waypoint stages).
#[derive(Clone, Copy)]
pub struct Smooth<'a> {
    pub mask: &'a [bool],
    pub weight: f64,
}

#[derive(Clone, Copy)]
pub struct Query<'a> {
    /// Padded index of the start cell.
    pub start: usize,
    /// Padded goal mask.
    pub goal: &'a [bool],
    pub heuristic: Heuristic<'a>,
    pub smooth: Option<Smooth<'a>>,
    /// Heading slot of the move that reached the start (8 = none).
    pub initial_heading: u8,
    /// Maximum expansions; 0 = unlimited.
    pub budget: u64,
}

/// A path found by [`AStar::search`].
#[derive(Clone, Debug, PartialEq)]
pub struct Found {
    /// Padded indices from the start to the goal cell, both included.
    pub path: Vec<usize>,
    pub cost: f64,
    pub expansions: u64,
    /// Heading slot of the last move (the start's heading for a zero-length path).
    pub final_heading: u8,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    Found(Found),
    /// The open list emptied: no goal cell is reachable.
    Exhausted {
        expansions: u64,
    },
    /// The budget ran out first.
    OverBudget {
        expansions: u64,
    },
}

/// Reusable A* search state.
pub struct AStar {
    g: Vec<f64>,
    parent: Vec<u32>,
    heading: Vec<u8>,
    /// `tag == gen`: open (g valid); `tag == gen + 1`: closed.
    tag: Vec<u32>,
    gen_: u32,
    heap: BinaryHeap<OpenEntry>,
    turn: [[f64; 8]; 9],
}

impl Default for AStar {
    fn default() -> Self {
        AStar::new()
    }
}

const SQRT2: f64 = std::f64::consts::SQRT_2;
const STEP: [f64; 8] = [1.0, 1.0, 1.0, 1.0, SQRT2, SQRT2, SQRT2, SQRT2];

impl AStar {
    pub fn new() -> Self {
        AStar {
            g: Vec::new(),
            parent: Vec::new(),
            heading: Vec::new(),
            tag: Vec::new(),
            gen_: 0,
            heap: BinaryHeap::new(),
            turn: turn_table(),
        }
    }

    fn prepare(&mut self, len: usize) {
        if self.tag.len() != len {
            self.g = vec![0.0; len];
            self.parent = vec![0; len];
            self.heading = vec![NO_HEADING; len];
            self.tag = vec![0; len];
            self.gen_ = 0;
        }
        if self.gen_ >= u32::MAX - 4 {
            self.tag.iter_mut().for_each(|t| *t = 0);
            self.gen_ = 0;
        }
        self.gen_ += 2;
        self.heap.clear();
    }

    /// Runs one search. The start must be an allowed cell (callers check and report it).
    pub fn search(&mut self, space: Space<'_>, q: Query<'_>) -> Outcome {
        let len = space.layout.len();
        debug_assert_eq!(space.allowed.len(), len);
        debug_assert_eq!(q.goal.len(), len);
        self.prepare(len);
        let w = space.layout.w;
        let offs = space.layout.offsets();
        let open = self.gen_;
        let closed = open + 1;
        let h = |i: usize| -> f64 {
            match q.heuristic {
                Heuristic::Zero => 0.0,
                Heuristic::Table(t) => t[i],
                Heuristic::SquaredTable(t) => (t[i] as f64).sqrt(),
                Heuristic::LazySquared(t) => (t.get(i) as f64).sqrt(),
                Heuristic::Box { r0, r1, c0, c1 } => {
                    let (r, c) = (i / w, i % w);
                    let dr = if r < r0 { r0 - r } else { r.saturating_sub(r1) } as f64;
                    let dc = if c < c0 { c0 - c } else { c.saturating_sub(c1) } as f64;
                    dr.hypot(dc)
                }
            }
        };
        let mut seq: u64 = 0;
        let start = q.start;
        self.g[start] = 0.0;
        self.tag[start] = open;
        self.parent[start] = start as u32;
        self.heading[start] = q.initial_heading;
        self.heap.push(OpenEntry {
            key: h(start),
            seq,
            state: start as u32,
        });
        seq += 1;
        let mut expansions: u64 = 0;
        let trav = space.traversable;
        let allowed = space.allowed;
        while let Some(OpenEntry { state: idx, .. }) = self.heap.pop() {
            let u = idx as usize;
            if self.tag[u] == closed {
                continue;
            }
            self.tag[u] = closed;
            if q.goal[u] {
                return Outcome::Found(self.reconstruct(start, u, expansions));
            }
            expansions += 1;
            if q.budget != 0 && expansions > q.budget {
                return Outcome::OverBudget {
                    expansions: expansions - 1,
                };
            }
            let gu = self.g[u];
            let hu = self.heading[u] as usize;
            let smooth_here = q.smooth.map(|s| (s, s.mask[u]));
            for k in 0..8 {
                let v = (u as isize + offs[k]) as usize;
                if !allowed[v] || self.tag[v] == closed {
                    continue;
                }
                if !crate::layout::corners_free(trav, u, k, w) {
                    continue;
                }
                let mut ng = gu + STEP[k];
                if let Some(phi) = space.phi {
                    ng += phi[v];
                }
                if let Some((s, inside_u)) = smooth_here
                    && (inside_u || s.mask[v])
                {
                    ng += s.weight * self.turn[hu][k];
                }
                if self.tag[v] != open || ng < self.g[v] {
                    self.tag[v] = open;
                    self.g[v] = ng;
                    self.parent[v] = u as u32;
                    self.heading[v] = k as u8;
                    self.heap.push(OpenEntry {
                        key: ng + h(v),
                        seq,
                        state: v as u32,
                    });
                    seq += 1;
                }
            }
        }
        Outcome::Exhausted { expansions }
    }

    fn reconstruct(&self, start: usize, goal: usize, expansions: u64) -> Found {
        let mut path = vec![goal];
        let mut cur = goal;
        while cur != start {
            cur = self.parent[cur] as usize;
            path.push(cur);
        }
        path.reverse();
        Found {
            path,
            cost: self.g[goal],
            expansions,
            final_heading: self.heading[goal],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use m2rc_stdlib::grid::Cell;

    fn open_space(n: usize) -> (Layout, Vec<bool>) {
        let l = Layout::new(n);
        (l, l.pad(&vec![true; n * n], false))
    }

    #[test]
    fn straight_and_diagonal_costs() {
        let (l, trav) = open_space(5);
        let mut goal = vec![false; l.len()];
        goal[l.idx(Cell::new(4, 4))] = true;
        let mut a = AStar::new();
        let space = Space {
            layout: l,
            traversable: &trav,
            allowed: &trav,
            phi: None,
        };
        let q = Query {
            start: l.idx(Cell::new(0, 0)),
            goal: &goal,
            heuristic: Heuristic::Zero,
            smooth: None,
            initial_heading: NO_HEADING,
            budget: 0,
        };
        let Outcome::Found(f) = a.search(space, q) else {
            panic!("no path")
        };
        assert!((f.cost - 4.0 * SQRT2).abs() < 1e-12);
        assert_eq!(f.path.len(), 5);
    }

    #[test]
    fn no_corner_cutting() {
        // . #
        // # .   the diagonal between the two free cells is blocked.
        let l = Layout::new(2);
        let trav = l.pad(&[true, false, false, true], false);
        let mut goal = vec![false; l.len()];
        goal[l.idx(Cell::new(1, 1))] = true;
        let space = Space {
            layout: l,
            traversable: &trav,
            allowed: &trav,
            phi: None,
        };
        let q = Query {
            start: l.idx(Cell::new(0, 0)),
            goal: &goal,
            heuristic: Heuristic::Zero,
            smooth: None,
            initial_heading: NO_HEADING,
            budget: 0,
        };
        assert!(matches!(
            AStar::new().search(space, q),
            Outcome::Exhausted { expansions: 1 }
        ));
    }

    #[test]
    fn budget_stops_search() {
        let (l, trav) = open_space(20);
        let mut goal = vec![false; l.len()];
        goal[l.idx(Cell::new(19, 19))] = true;
        let space = Space {
            layout: l,
            traversable: &trav,
            allowed: &trav,
            phi: None,
        };
        let q = Query {
            start: l.idx(Cell::new(0, 0)),
            goal: &goal,
            heuristic: Heuristic::Zero,
            smooth: None,
            initial_heading: NO_HEADING,
            budget: 10,
        };
        assert_eq!(
            AStar::new().search(space, q),
            Outcome::OverBudget { expansions: 10 }
        );
    }

    #[test]
    fn fifo_ties_prefer_first_move_in_order() {
        // From the centre of an open 3×3 grid with the whole border as goal, the first move in the
        // reference order (up) wins the tie among the four cost-1 goals.
        let (l, trav) = open_space(3);
        let mut goal = vec![false; l.len()];
        for r in 0..3 {
            for c in 0..3 {
                if (r, c) != (1, 1) {
                    goal[l.idx(Cell::new(r, c))] = true;
                }
            }
        }
        let space = Space {
            layout: l,
            traversable: &trav,
            allowed: &trav,
            phi: None,
        };
        let q = Query {
            start: l.idx(Cell::new(1, 1)),
            goal: &goal,
            heuristic: Heuristic::Zero,
            smooth: None,
            initial_heading: NO_HEADING,
            budget: 0,
        };
        let Outcome::Found(f) = AStar::new().search(space, q) else {
            panic!()
        };
        assert_eq!(l.cell(*f.path.last().unwrap()), Cell::new(0, 1));
    }
}
