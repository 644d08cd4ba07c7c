//! Property tests: the A* is optimal (against a plain Dijkstra and against the `pathfinding` crate),
//! its paths are legal, the global planner is never worse than the sequential one, and the
//! shortest-feasible baseline never enters an avoid region.

use m2rc_planner::astar::{AStar, Heuristic, Outcome, Query, Space};
use m2rc_planner::layout::{Layout, MOVES, NO_HEADING};
use m2rc_planner::{
    Area, CostProfile, Forbid, Origin, PlanProblem, SegmentSpec, SoftKind, SoftTerm, StageRole,
    StageSpec, Target, global, plan_sequential, plan_shortest,
};
use m2rc_stdlib::field;
use m2rc_stdlib::grid::{Cell, Grid};
use proptest::prelude::*;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

const SQRT2: f64 = std::f64::consts::SQRT_2;

/// Plain textbook Dijkstra on the unpadded grid, sharing no code with the planner.
fn dijkstra(n: usize, trav: &[bool], phi: &[f64], start: usize, goal: &[bool]) -> Option<f64> {
    #[derive(PartialEq)]
    struct E(f64, usize);
    impl Eq for E {}
    impl PartialOrd for E {
        fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
            Some(self.cmp(o))
        }
    }
    impl Ord for E {
        fn cmp(&self, o: &Self) -> Ordering {
            o.0.total_cmp(&self.0)
        }
    }
    let mut dist = vec![f64::INFINITY; n * n];
    let mut heap = BinaryHeap::new();
    dist[start] = 0.0;
    heap.push(E(0.0, start));
    while let Some(E(d, u)) = heap.pop() {
        if d > dist[u] {
            continue;
        }
        if goal[u] {
            return Some(d);
        }
        let (r, c) = ((u / n) as i64, (u % n) as i64);
        for (dr, dc) in MOVES {
            let (nr, nc) = (r + dr as i64, c + dc as i64);
            if nr < 0 || nc < 0 || nr >= n as i64 || nc >= n as i64 {
                continue;
            }
            let v = nr as usize * n + nc as usize;
            if !trav[v] {
                continue;
            }
            if dr != 0
                && dc != 0
                && (!trav[nr as usize * n + c as usize] || !trav[r as usize * n + nc as usize])
            {
                continue;
            }
            let step = if dr != 0 && dc != 0 { SQRT2 } else { 1.0 };
            let nd = d + step + phi[v];
            if nd < dist[v] {
                dist[v] = nd;
                heap.push(E(nd, v));
            }
        }
    }
    None
}

/// Checks a path is a legal 8-connected walk over `allowed` with no corner cutting on `trav`, and
/// returns its cost under `phi`.
fn check_path(
    n: usize,
    trav: &[bool],
    allowed: &[bool],
    phi: &[f64],
    path: &[Cell],
) -> Result<f64, String> {
    let mut cost = 0.0;
    for w in path.windows(2) {
        let (a, b) = (w[0], w[1]);
        let dr = b.row as i64 - a.row as i64;
        let dc = b.col as i64 - a.col as i64;
        if dr.abs() > 1 || dc.abs() > 1 || (dr == 0 && dc == 0) {
            return Err(format!("not a single 8-connected step: {a:?} -> {b:?}"));
        }
        let bi = b.row as usize * n + b.col as usize;
        if !allowed[bi] {
            return Err(format!("enters a cell it may not: {b:?}"));
        }
        if dr != 0 && dc != 0 {
            let s1 = b.row as usize * n + a.col as usize;
            let s2 = a.row as usize * n + b.col as usize;
            if !trav[s1] || !trav[s2] {
                return Err(format!("cuts a corner: {a:?} -> {b:?}"));
            }
        }
        cost += if dr != 0 && dc != 0 { SQRT2 } else { 1.0 } + phi[bi];
    }
    Ok(cost)
}

fn grid_strategy() -> impl Strategy<Value = (usize, Vec<bool>, Vec<f64>, usize, Vec<bool>)> {
    (4usize..18).prop_flat_map(|n| {
        (
            Just(n),
            proptest::collection::vec(proptest::bool::weighted(0.75), n * n),
            proptest::collection::vec(0.0f64..5.0, n * n),
            0..n * n,
            proptest::collection::vec(proptest::bool::weighted(0.04), n * n),
        )
    })
}

/// Exact octile costs `a + b·√2` for `pathfinding` (which needs `Ord` costs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
struct Octile {
    a: i64,
    b: i64,
}
impl Octile {
    fn value(self) -> f64 {
        self.a as f64 + self.b as f64 * SQRT2
    }
}
impl std::ops::Add for Octile {
    type Output = Octile;
    fn add(self, o: Octile) -> Octile {
        Octile {
            a: self.a + o.a,
            b: self.b + o.b,
        }
    }
}
impl pathfinding::num_traits::Zero for Octile {
    fn zero() -> Self {
        Octile { a: 0, b: 0 }
    }
    fn is_zero(&self) -> bool {
        self.a == 0 && self.b == 0
    }
}
impl Ord for Octile {
    /// Exact comparison of `a1 + b1√2` and `a2 + b2√2`: compare `da` with `db·√2` by squares.
    fn cmp(&self, o: &Self) -> Ordering {
        let da = self.a - o.a; // compare da + db√2 with 0
        let db = self.b - o.b;
        let sign = |x: i64| x.cmp(&0);
        match (sign(da), sign(db)) {
            (Ordering::Equal, s) | (s, Ordering::Equal) => s,
            (Ordering::Greater, Ordering::Greater) => Ordering::Greater,
            (Ordering::Less, Ordering::Less) => Ordering::Less,
            (Ordering::Greater, Ordering::Less) => (da * da).cmp(&(2 * db * db)),
            (Ordering::Less, Ordering::Greater) => (2 * db * db).cmp(&(da * da)),
        }
    }
}
impl PartialOrd for Octile {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

fn run_astar(n: usize, trav: &[bool], phi: Option<&[f64]>, start: usize, goal: &[bool]) -> Outcome {
    let l = Layout::new(n);
    let ptrav = l.pad(trav, false);
    let pgoal = l.pad(goal, false);
    let pphi = phi.map(|p| l.pad(p, 0.0));
    let h = l.pad(&field::distances(goal, n), 0.0);
    let space = Space {
        layout: l,
        traversable: &ptrav,
        allowed: &ptrav,
        phi: pphi.as_deref(),
    };
    let q = Query {
        start: l.idx_of_plain(start),
        goal: &pgoal,
        heuristic: Heuristic::Table(&h),
        smooth: None,
        initial_heading: NO_HEADING,
        budget: 0,
    };
    AStar::new().search(space, q)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn astar_equals_dijkstra_and_paths_are_legal((n, trav, phi, start, goal) in grid_strategy()) {
        let mut trav = trav;
        trav[start] = true;
        let goal: Vec<bool> = goal.iter().zip(&trav).map(|(g, t)| *g && *t).collect();
        let expected = dijkstra(n, &trav, &phi, start, &goal);
        match run_astar(n, &trav, Some(&phi), start, &goal) {
            Outcome::Found(f) => {
                let l = Layout::new(n);
                let want = expected.expect("A* found a path Dijkstra did not");
                prop_assert!((f.cost - want).abs() < 1e-9, "A* {} vs Dijkstra {}", f.cost, want);
                let cells: Vec<Cell> = f.path.iter().map(|&i| l.cell(i)).collect();
                prop_assert_eq!(cells[0], Cell::new((start / n) as u32, (start % n) as u32));
                let last = cells[cells.len() - 1];
                prop_assert!(goal[last.row as usize * n + last.col as usize]);
                let recomputed = check_path(n, &trav, &trav, &phi, &cells).map_err(TestCaseError::fail)?;
                prop_assert!((recomputed - f.cost).abs() < 1e-9);
            }
            Outcome::Exhausted { .. } => prop_assert!(expected.is_none(), "Dijkstra found {:?}", expected),
            Outcome::OverBudget { .. } => prop_assert!(false, "unlimited search ran over budget"),
        }
    }

    #[test]
    fn astar_equals_pathfinding_on_uniform_costs((n, trav, _phi, start, goal) in grid_strategy(), gi in 0usize..400) {
        let mut trav = trav;
        trav[start] = true;
        let g = gi % (n * n);
        trav[g] = true;
        let _ = goal;
        let target = (g / n, g % n);
        let succ = |&(r, c): &(usize, usize)| {
            let mut out = Vec::new();
            for (dr, dc) in MOVES {
                let (nr, nc) = (r as i64 + dr as i64, c as i64 + dc as i64);
                if nr < 0 || nc < 0 || nr >= n as i64 || nc >= n as i64 || !trav[nr as usize * n + nc as usize] {
                    continue;
                }
                if dr != 0 && dc != 0 && (!trav[nr as usize * n + c] || !trav[r * n + nc as usize]) {
                    continue;
                }
                let cost = if dr != 0 && dc != 0 { Octile { a: 0, b: 1 } } else { Octile { a: 1, b: 0 } };
                out.push(((nr as usize, nc as usize), cost));
            }
            out
        };
        let heur = |&(r, c): &(usize, usize)| {
            let dr = r.abs_diff(target.0) as i64;
            let dc = c.abs_diff(target.1) as i64;
            Octile { a: (dr - dc).abs(), b: dr.min(dc) }
        };
        let theirs = pathfinding::prelude::astar(&(start / n, start % n), succ, heur, |&p| p == target);
        let mut goal = vec![false; n * n];
        goal[g] = true;
        match (run_astar(n, &trav, None, start, &goal), theirs) {
            (Outcome::Found(f), Some((_, c))) => prop_assert!((f.cost - c.value()).abs() < 1e-9, "{} vs {}", f.cost, c.value()),
            (Outcome::Exhausted { .. }, None) => {}
            (ours, theirs) => prop_assert!(false, "ours {:?}, pathfinding {:?}", ours, theirs),
        }
    }
}

fn random_cells(seed: &[u16], n: usize, count: usize) -> Vec<Cell> {
    seed.iter()
        .take(count)
        .map(|&s| {
            let i = s as usize % (n * n);
            Cell::new((i / n) as u32, (i % n) as u32)
        })
        .collect()
}

fn multi_stage_problem(
    n: usize,
    trav: Vec<bool>,
    seeds: &[u16],
    smooth: bool,
    forbid: bool,
) -> PlanProblem {
    let mut trav = trav;
    let start = seeds[0] as usize % (n * n);
    trav[start] = true;
    let mut segments = Vec::new();
    let mut k = 1;
    for s in 0..2 {
        let mut stages = Vec::new();
        for t in 0..2 {
            let cells = random_cells(&seeds[k..], n, 3);
            k += 3;
            let role = if t == 1 {
                StageRole::Destination
            } else {
                StageRole::Waypoint
            };
            stages.push(StageSpec {
                target: Target::Region {
                    cells: Area::Cells(cells),
                    fallback: None,
                },
                role,
                smoothness: (smooth && t == 0).then(|| Area::mask(Grid::new(n, true))),
                origin: Origin::Unknown,
            });
        }
        let soft = vec![
            SoftTerm {
                kind: SoftKind::Near {
                    reference: Area::Cells(random_cells(&seeds[k..], n, 2)),
                },
                weight: None,
                scope: None,
                origin: Origin::Unknown,
            },
            SoftTerm {
                kind: SoftKind::Far {
                    reference: Area::Cells(random_cells(&seeds[k + 2..], n, 1)),
                },
                weight: Some(10.0 + s as f64),
                scope: None,
                origin: Origin::Unknown,
            },
        ];
        k += 3;
        let forbidden = if forbid {
            vec![Forbid {
                cells: Area::Cells(random_cells(&seeds[k..], n, 4)),
                origin: Origin::Unknown,
            }]
        } else {
            Vec::new()
        };
        k += 4;
        segments.push(SegmentSpec {
            stages,
            forbidden,
            soft,
        });
    }
    PlanProblem {
        traversable: Grid::from_vec(n, trav).unwrap(),
        obstacles: None,
        resolution: 0.25,
        start: Cell::new((start / n) as u32, (start % n) as u32),
        segments,
        profile: CostProfile {
            smoothness_weight: if smooth { 0.5 } else { 0.02 },
            ..CostProfile::reference()
        },
        map_fields: None,
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn global_never_worse_than_sequential(
        n in 5usize..14,
        trav in proptest::collection::vec(proptest::bool::weighted(0.8), 196),
        seeds in proptest::collection::vec(any::<u16>(), 40),
        smooth in any::<bool>(),
        forbid in any::<bool>(),
    ) {
        let p = multi_stage_problem(n, trav[..n * n].to_vec(), &seeds, smooth, forbid);
        let seq = plan_sequential(&p);
        let glob = global::search_only(&p);
        if seq.is_success() {
            let g = glob.expect("global search failed where the sequential planner succeeded");
            prop_assert!(g.cost <= seq.cost + 1e-9, "global {} > sequential {}", g.cost, seq.cost);
            let t = p.traversable.data();
            for (seg, spec) in g.segments.iter().zip(&p.segments) {
                let mut allowed = t.to_vec();
                for f in &spec.forbidden {
                    for c in f.cells.cells() { allowed[c.row as usize * n + c.col as usize] = false; }
                }
                check_path(n, t, &allowed, &vec![0.0; n * n], &seg.path).map_err(TestCaseError::fail)?;
            }
        }
        // The public planner returns the better of the two.
        let best = m2rc_planner::plan_global(&p);
        if seq.is_success() {
            prop_assert!(best.is_success() && best.cost <= seq.cost + 1e-9);
        }
    }

    #[test]
    fn shortest_never_enters_avoid_regions(
        n in 5usize..16,
        trav in proptest::collection::vec(proptest::bool::weighted(0.85), 256),
        seeds in proptest::collection::vec(any::<u16>(), 40),
    ) {
        let p = multi_stage_problem(n, trav[..n * n].to_vec(), &seeds, false, true);
        let r = plan_shortest(&p);
        let t = p.traversable.data();
        for seg in &r.segments {
            let spec = &p.segments[seg.index];
            let mut allowed = t.to_vec();
            for f in &spec.forbidden {
                for c in f.cells.cells() { allowed[c.row as usize * n + c.col as usize] = false; }
            }
            check_path(n, t, &allowed, &vec![0.0; n * n], &seg.path).map_err(TestCaseError::fail)?;
        }
        // Uniform costs: each segment's cost is its length in cells (waypoint stages are dropped).
        if r.is_success() {
            for seg in &r.segments {
                prop_assert!((seg.cost - seg.length_m / p.resolution).abs() < 1e-9);
            }
        }
    }
}
