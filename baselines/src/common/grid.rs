//! Grid search for the baselines over m2rc's A* (`m2rc_planner::astar`): 8-connected, steps 1 and
//! √2, no corner cutting, which is the adaptation's shared A*. A goal is a set of cells (the
//! search ends at the nearest one by path length); blocked cells are masked. Every search has an
//! expansion budget, so no instruction can make a method search forever.

use m2rc_planner::astar::{AStar, Heuristic, Outcome, Query, Space};
use m2rc_planner::layout::{Layout, NO_HEADING};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;

/// Expansions one search may use: a few times the largest map's cell count.
pub const SEARCH_BUDGET: u64 = 4_000_000;

/// Why a search found no path.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SearchFail {
    /// No goal cell is reachable from the start without entering a blocked cell.
    Unreachable,
    /// The budget ran out.
    OverBudget,
    /// The start is outside the map or not traversable, or the goal set is empty.
    BadQuery(String),
}

/// A path (start and goal included) and the expansions it took.
#[derive(Clone, Debug, PartialEq)]
pub struct Path {
    pub cells: Vec<Cell>,
    pub cost: f64,
    pub expansions: u64,
}

/// The search state for one map (padded masks and A* buffers, reused across searches).
pub struct GridSearch<'m> {
    pub map: &'m SemanticMap,
    layout: Layout,
    traversable: Vec<bool>,
    astar: AStar,
    /// Expansions used by every search so far.
    pub expansions: u64,
}

impl<'m> GridSearch<'m> {
    pub fn new(map: &'m SemanticMap) -> Self {
        let n = map.n();
        let layout = Layout::new(n);
        let plain: Vec<bool> = (0..n * n)
            .map(|i| map.is_free(Cell::new((i / n) as u32, (i % n) as u32)))
            .collect();
        GridSearch {
            map,
            layout,
            traversable: layout.pad(&plain, false),
            astar: AStar::new(),
            expansions: 0,
        }
    }

    pub fn n(&self) -> usize {
        self.layout.n
    }

    pub fn is_free(&self, c: Cell) -> bool {
        self.layout.contains(c) && self.traversable[self.layout.idx(c)]
    }

    /// The shortest path from `start` to the nearest of `goals`, never entering a cell of
    /// `blocked` (a row-major N×N mask; the start itself may be blocked, so a robot standing in an
    /// avoided region can leave it).
    pub fn path_to_any(
        &mut self,
        start: Cell,
        goals: &[Cell],
        blocked: Option<&[bool]>,
    ) -> Result<Path, SearchFail> {
        if !self.is_free(start) {
            return Err(SearchFail::BadQuery(format!(
                "the start [{}, {}] is not a traversable cell",
                start.row, start.col
            )));
        }
        let mut goal = vec![false; self.layout.len()];
        let mut any = false;
        for g in goals.iter().filter(|g| self.layout.contains(**g)) {
            goal[self.layout.idx(*g)] = true;
            any = true;
        }
        if !any {
            return Err(SearchFail::BadQuery("no goal cell inside the map".into()));
        }
        let allowed: Vec<bool> = match blocked {
            Some(mask) => {
                let n = self.layout.n;
                let mut a = self.traversable.clone();
                for (i, &b) in mask.iter().enumerate().take(n * n) {
                    if b {
                        a[self.layout.idx_of_plain(i)] = false;
                    }
                }
                a[self.layout.idx(start)] = true;
                a
            }
            None => self.traversable.clone(),
        };
        let space = Space {
            layout: self.layout,
            traversable: &self.traversable,
            allowed: &allowed,
            phi: None,
        };
        let q = Query {
            start: self.layout.idx(start),
            goal: &goal,
            heuristic: Heuristic::Zero,
            smooth: None,
            initial_heading: NO_HEADING,
            budget: SEARCH_BUDGET,
        };
        match self.astar.search(space, q) {
            Outcome::Found(f) => {
                self.expansions += f.expansions;
                Ok(Path {
                    cells: f.path.iter().map(|&i| self.layout.cell(i)).collect(),
                    cost: f.cost,
                    expansions: f.expansions,
                })
            }
            Outcome::Exhausted { expansions } => {
                self.expansions += expansions;
                Err(SearchFail::Unreachable)
            }
            Outcome::OverBudget { expansions } => {
                self.expansions += expansions;
                Err(SearchFail::OverBudget)
            }
        }
    }

    /// Cells reachable from `start` (row-major mask), avoiding `blocked`.
    pub fn reachable(&self, start: Cell, blocked: Option<&[bool]>) -> Vec<bool> {
        let n = self.layout.n;
        let mut seen = vec![false; n * n];
        if !self.is_free(start) {
            return seen;
        }
        let ok = |c: Cell| {
            self.is_free(c) && blocked.is_none_or(|b| !b[c.row as usize * n + c.col as usize])
        };
        let mut stack = vec![start];
        seen[start.row as usize * n + start.col as usize] = true;
        while let Some(c) = stack.pop() {
            for (dr, dc) in [
                (-1i64, 0i64),
                (1, 0),
                (0, -1),
                (0, 1),
                (-1, -1),
                (-1, 1),
                (1, -1),
                (1, 1),
            ] {
                let (r, cc) = (c.row as i64 + dr, c.col as i64 + dc);
                if r < 0 || cc < 0 || r >= n as i64 || cc >= n as i64 {
                    continue;
                }
                let next = Cell::new(r as u32, cc as u32);
                if dr != 0 && dc != 0 {
                    let a = Cell::new(r as u32, c.col);
                    let b = Cell::new(c.row, cc as u32);
                    if !self.is_free(a) || !self.is_free(b) {
                        continue;
                    }
                }
                let i = next.row as usize * n + next.col as usize;
                if !seen[i] && ok(next) {
                    seen[i] = true;
                    stack.push(next);
                }
            }
        }
        seen
    }
}

/// A row-major N×N mask with `cells` set.
pub fn mask_of(n: usize, cells: &[Cell]) -> Vec<bool> {
    let mut m = vec![false; n * n];
    for c in cells {
        if (c.row as usize) < n && (c.col as usize) < n {
            m[c.row as usize * n + c.col as usize] = true;
        }
    }
    m
}

/// `a` followed by `b` without repeating their shared cell.
pub fn append_path(route: &mut Vec<Cell>, path: &[Cell]) {
    let skip = usize::from(route.last().is_some() && route.last() == path.first());
    route.extend_from_slice(&path[skip.min(path.len())..]);
}
