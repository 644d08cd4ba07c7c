//! Product-graph planning: the 8-connected grid times an LTLf automaton, searched on the fly.
//!
//! A search state is (cell, automaton state). Moving into cell v reads v's letter (the set of
//! atoms whose masks contain v) and steps the automaton; the start cell is read first. Moves,
//! step costs (1 and √2) and the no-corner-cutting rule are those of the RouteIR planners
//! (`layout::MOVES`, checked on the base traversable grid). Avoid regions are not masks here: they
//! are atoms, and a move whose letter sends the automaton to a state that cannot accept any more
//! is pruned; so is a diagonal move whose corner cells' letters would, since the evaluator
//! counts a touched corner as entering (the hard-constraint-only profiles' corner rule,
//! `CostProfile::avoid_corners`; the formula has no soft terms, so it always applies here). The route is the cheapest path ending in an accepting state.
//!
//! A* with the heuristic "straight-line distance to the nearest cell whose letter moves the
//! automaton out of its current state to a live state", zero in accepting states: any accepting
//! continuation from a non-accepting state has to enter such a cell, and every step costs at least
//! its Euclidean length, so it is admissible (and consistent). One lazily-computed distance
//! transform per automaton state, only for the states the search reaches.
//!
//! Costs are path length only: soft preferences have no meaning in the formula (the caller says
//! which were dropped).

use crate::layout::{Layout, MOVES, corners_free};
use crate::open_list::OpenEntry;
use m2rc_compiler::ltl::Dfa;
use m2rc_stdlib::field::LazySquaredDistances;
use m2rc_stdlib::grid::Cell;
use std::collections::{BinaryHeap, HashMap};

const SQRT2: f64 = std::f64::consts::SQRT_2;
const STEP: [f64; 8] = [1.0, 1.0, 1.0, 1.0, SQRT2, SQRT2, SQRT2, SQRT2];

/// A product search problem: row-major masks of side `n`.
pub struct ProductProblem<'a> {
    pub n: usize,
    pub traversable: &'a [bool],
    /// One mask per atom of `dfa`, in `dfa.atoms` order.
    pub atoms: &'a [Vec<bool>],
    pub dfa: &'a Dfa,
    pub start: Cell,
    /// Expansions allowed; 0 = unlimited.
    pub max_expansions: u64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct ProductRoute {
    pub trajectory: Vec<Cell>,
    /// Length in cells.
    pub cost: f64,
    pub expansions: u64,
    /// Automaton state after each trajectory cell.
    pub states: Vec<usize>,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ProductFailure {
    /// The start cell is outside the grid or not traversable.
    StartBlocked,
    /// Reading the start cell already makes the formula unsatisfiable (e.g. it is avoided).
    StartRejected,
    /// No path reaches an accepting state.
    NoAcceptingRoute { expansions: u64 },
    /// The budget ran out first.
    Budget { expansions: u64 },
    /// Masks of the wrong size or count.
    Invalid(String),
    /// The grid times the automaton has more than [`MAX_PRODUCT_STATES`] states: refused before
    /// the search allocates its tables.
    TooLarge { cells: usize, states: usize },
}

/// Search states (grid cell, automaton state) the product may have: the search keeps about 13
/// bytes per state (distance, predecessor, closed flag), so this bounds it near 440 MB. The
/// largest fixture house (733 × 733 cells) fits an automaton of 62 states.
pub const MAX_PRODUCT_STATES: u64 = 1 << 25;

impl std::fmt::Display for ProductFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ProductFailure::StartBlocked => f.write_str("the start cell is not traversable"),
            ProductFailure::StartRejected => {
                f.write_str("the start cell already violates the formula")
            }
            ProductFailure::NoAcceptingRoute { expansions } => {
                write!(f, "no accepting route (after {expansions} expansions)")
            }
            ProductFailure::Budget { expansions } => {
                write!(f, "the search stopped after {expansions} expansions")
            }
            ProductFailure::Invalid(m) => f.write_str(m),
            ProductFailure::TooLarge { cells, states } => write!(
                f,
                "the product of the grid ({cells} cells) and the automaton ({states} states) has \
                 more than the planner's limit of {MAX_PRODUCT_STATES} search states"
            ),
        }
    }
}

/// The cheapest accepting route of `p`.
pub fn search(p: &ProductProblem) -> Result<ProductRoute, ProductFailure> {
    let n = p.n;
    let d = p.dfa;
    let nq = d.states();
    if p.traversable.len() != n * n || p.atoms.iter().any(|m| m.len() != n * n) {
        return Err(ProductFailure::Invalid(format!(
            "masks must be {n}x{n} = {} cells",
            n * n
        )));
    }
    if p.atoms.len() != d.atoms.len() || p.atoms.len() > 64 {
        return Err(ProductFailure::Invalid(format!(
            "{} atom masks for an automaton over {} atoms",
            p.atoms.len(),
            d.atoms.len()
        )));
    }
    let l = Layout::new(n);
    let len = l.len();
    if (len as u128) * (nq as u128) > MAX_PRODUCT_STATES as u128 {
        return Err(ProductFailure::TooLarge {
            cells: len,
            states: nq,
        });
    }
    if !l.contains(p.start) || !p.traversable[p.start.row as usize * n + p.start.col as usize] {
        return Err(ProductFailure::StartBlocked);
    }
    let trav = l.pad(p.traversable, false);
    // Letters, deduplicated into classes, and the step table per (state, class).
    let mut letter_plain = vec![0u64; n * n];
    for (k, m) in p.atoms.iter().enumerate() {
        for (i, &v) in m.iter().enumerate() {
            if v {
                letter_plain[i] |= 1 << k;
            }
        }
    }
    let mut classes: Vec<u64> = Vec::new();
    let mut class_of: HashMap<u64, u32> = HashMap::new();
    let mut cls_plain = vec![0u32; n * n];
    for (i, &lt) in letter_plain.iter().enumerate() {
        cls_plain[i] = *class_of.entry(lt).or_insert_with(|| {
            classes.push(lt);
            classes.len() as u32 - 1
        });
    }
    let cls = l.pad(&cls_plain, 0);
    let nc = classes.len();
    let table: Vec<u32> = (0..nq)
        .flat_map(|q| classes.iter().map(move |&lt| d.step(q, lt) as u32))
        .collect();
    let live = d.live();
    let next = |q: usize, c: u32| table[q * nc + c as usize] as usize;

    let start = l.idx(p.start);
    let q0 = next(d.initial, cls[start]);
    if !live[q0] {
        return Err(ProductFailure::StartRejected);
    }
    // Heuristic tables, built when a state is first reached.
    let mut h: Vec<Option<LazySquaredDistances>> = (0..nq).map(|_| None).collect();
    let mut heur = |q: usize, cell: usize| -> f64 {
        if d.accepting[q] {
            return 0.0;
        }
        let t = h[q].get_or_insert_with(|| {
            let progress: Vec<bool> = (0..n * n)
                .map(|i| {
                    let q2 = next(q, cls_plain[i]);
                    q2 != q && live[q2] && p.traversable[i]
                })
                .collect();
            LazySquaredDistances::new(&progress, n)
        });
        let (r, c) = (cell / l.w - 1, cell % l.w - 1);
        let v = t.get(r * n + c);
        if v == m2rc_stdlib::field::NO_SOURCE {
            f64::INFINITY
        } else {
            (v as f64).sqrt()
        }
    };
    let offs = l.offsets();
    let w = l.w as isize;
    let total = len * nq;
    let mut dist = vec![f64::INFINITY; total];
    let mut pred = vec![u32::MAX; total];
    let mut closed = vec![false; total];
    let mut heap = BinaryHeap::new();
    let s0 = start * nq + q0;
    dist[s0] = 0.0;
    let mut seq = 0u64;
    let h0 = heur(q0, start);
    if h0.is_finite() {
        heap.push(OpenEntry {
            key: h0,
            seq,
            state: s0 as u32,
        });
    }
    let mut expansions = 0u64;
    while let Some(OpenEntry { state, .. }) = heap.pop() {
        let s = state as usize;
        if closed[s] {
            continue;
        }
        closed[s] = true;
        let (u, q) = (s / nq, s % nq);
        if d.accepting[q] {
            return Ok(rebuild(s, nq, &pred, &dist, l, expansions));
        }
        expansions += 1;
        if p.max_expansions > 0 && expansions > p.max_expansions {
            return Err(ProductFailure::Budget { expansions });
        }
        let du = dist[s];
        for m in 0..8 {
            let v = (u as isize + offs[m]) as usize;
            if !trav[v] {
                continue;
            }
            if !corners_free(&trav, u, m, l.w) {
                continue;
            }
            // The corners' letters too: a diagonal step past the corner of an avoided cell
            // touches it in the evaluator's segment test, so it must not kill the automaton.
            if m >= 4 {
                let (dr, dc) = MOVES[m];
                let a = (u as isize + dr as isize * w) as usize;
                let b = (u as isize + dc as isize) as usize;
                if !live[next(q, cls[a])] || !live[next(q, cls[b])] {
                    continue;
                }
            }
            let q2 = next(q, cls[v]);
            if !live[q2] {
                continue;
            }
            let t = v * nq + q2;
            if closed[t] {
                continue;
            }
            let c = du + STEP[m];
            if c < dist[t] {
                let hv = heur(q2, v);
                if !hv.is_finite() {
                    continue;
                }
                dist[t] = c;
                pred[t] = s as u32;
                seq += 1;
                heap.push(OpenEntry {
                    key: c + hv,
                    seq,
                    state: t as u32,
                });
            }
        }
    }
    Err(ProductFailure::NoAcceptingRoute { expansions })
}

fn rebuild(
    goal: usize,
    nq: usize,
    pred: &[u32],
    dist: &[f64],
    l: Layout,
    expansions: u64,
) -> ProductRoute {
    let mut cells = Vec::new();
    let mut states = Vec::new();
    let mut s = goal;
    loop {
        cells.push(l.cell(s / nq));
        states.push(s % nq);
        let p = pred[s];
        if p == u32::MAX {
            break;
        }
        s = p as usize;
    }
    cells.reverse();
    states.reverse();
    ProductRoute {
        trajectory: cells,
        cost: dist[goal],
        expansions,
        states,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use m2rc_compiler::ltl::parse;

    fn mask(n: usize, cells: &[(usize, usize)]) -> Vec<bool> {
        let mut m = vec![false; n * n];
        for &(r, c) in cells {
            m[r * n + c] = true;
        }
        m
    }

    fn plan(
        formula: &str,
        atoms: &[Vec<bool>],
        trav: &[bool],
        n: usize,
    ) -> Result<ProductRoute, ProductFailure> {
        let names: Vec<String> = ["a", "b", "c"][..atoms.len()]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let dfa = Dfa::build(&parse(formula).unwrap(), &names, true).unwrap();
        search(&ProductProblem {
            n,
            traversable: trav,
            atoms,
            dfa: &dfa,
            start: Cell::new(0, 0),
            max_expansions: 0,
        })
    }

    #[test]
    fn ordered_visits_and_avoid_on_a_small_grid() {
        let n = 5;
        let trav = vec![true; n * n];
        let a = mask(n, &[(4, 0)]);
        let b = mask(n, &[(0, 4)]);
        let c = mask(n, &[(2, 1), (2, 2), (2, 3), (1, 2), (3, 2)]);
        let r = plan(
            "F(a & F b) & G !c",
            &[a.clone(), b.clone(), c.clone()],
            &trav,
            n,
        )
        .unwrap();
        assert_eq!(r.trajectory.first(), Some(&Cell::new(0, 0)));
        assert_eq!(r.trajectory.last(), Some(&Cell::new(0, 4)));
        assert!(r.trajectory.contains(&Cell::new(4, 0)));
        assert!(
            r.trajectory
                .iter()
                .all(|x| !c[x.row as usize * n + x.col as usize])
        );
        // Without the avoid: down 4, then 4 diagonal steps; the plus in the middle forces a detour.
        let straight = plan("F(a & F b)", &[a.clone(), b.clone()], &trav, n).unwrap();
        assert!(
            (straight.cost - (4.0 + 4.0 * SQRT2)).abs() < 1e-9,
            "{}",
            straight.cost
        );
        assert!(r.cost > straight.cost);
        // The start inside an avoided place is rejected; an unreachable goal has no route.
        let c0 = mask(n, &[(0, 0)]);
        assert_eq!(
            plan("F a & G !c", &[a.clone(), b.clone(), c0], &trav, n),
            Err(ProductFailure::StartRejected)
        );
        let wall = mask(n, &[(3, 0), (3, 1), (3, 2), (3, 3), (3, 4)]);
        assert!(matches!(
            plan("F a & G !c", &[a, b, wall], &trav, n),
            Err(ProductFailure::NoAcceptingRoute { .. })
        ));
    }

    #[test]
    fn corners_are_not_cut() {
        let n = 3;
        // A blocked cell at (0, 1) and (1, 0): the diagonal from (0, 0) to (1, 1) is illegal.
        let mut trav = vec![true; n * n];
        trav[1] = false;
        trav[n] = false;
        let a = mask(n, &[(1, 1)]);
        assert!(matches!(
            plan("F a", &[a], &trav, n),
            Err(ProductFailure::NoAcceptingRoute { .. })
        ));
    }

    #[test]
    fn corners_of_avoided_cells_are_not_clipped() {
        // Start (0,0), goal (1,2), avoided (0,1) and (1,0): the diagonal (0,0) -> (1,1) passes
        // both avoided cells' corners, so the route cannot leave the start at all.
        let n = 3;
        let trav = vec![true; n * n];
        let a = mask(n, &[(1, 2)]);
        let c = mask(n, &[(0, 1), (1, 0)]);
        assert!(matches!(
            plan("F a & G !b", &[a.clone(), c], &trav, n),
            Err(ProductFailure::NoAcceptingRoute { .. })
        ));
        // With only (0,1) avoided, the walls-only rule would take (0,0) -> (1,1) -> (1,2)
        // (1 + √2), past (0,1)'s corner; the route goes down first instead (length 3).
        let c = mask(n, &[(0, 1)]);
        let r = plan("F a & G !b", &[a, c], &trav, n).unwrap();
        assert_eq!(
            r.trajectory,
            vec![
                Cell::new(0, 0),
                Cell::new(1, 0),
                Cell::new(1, 1),
                Cell::new(1, 2)
            ]
        );
    }
}
