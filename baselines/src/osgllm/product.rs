//! OSG-LLM's product-state A*: search states are (cell, residual formula), 8-connected, and a
//! move whose progression leaves the formula unsatisfiable is pruned.
//!
//! The residual formulas are the states of m2rc's LTLf automaton (`ltl::Dfa`, built by the same
//! progression and minimised), so two residuals that accept the same routes are one search state
//! where the adaptation's syntactic residuals might be two; moves, costs (1, √2) and the corner
//! rule are the planners'. What is OSG-LLM's own is kept: its heuristic, the octile distance to
//! the nearest of at most 64 sampled cells (plus the cell nearest the region's centre) of each
//! proposition the residual still waits for, the smallest over those propositions; and its
//! limits. The heuristic is not admissible (a sample may miss the nearest cell), so the route may
//! be longer than the shortest, as in the original.
//!
//! The limits are counts, never clocks: [`MAX_EXPANSIONS`] is the adaptation's 250 000, and its
//! 30 s wall-clock limit is read as [`TIME_LIMIT_EXPANSIONS`] (see there), so a run is the same
//! on every machine.

use super::graph::SceneGraph;
use m2rc_compiler::ltl::{Dfa, Formula};
use m2rc_stdlib::field::{LazySquaredDistances, NO_SOURCE};
use m2rc_stdlib::grid::Cell;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// The adaptation's expansion limit (`--max-expansions 250000`).
pub const MAX_EXPANSIONS: u64 = 250_000;
/// The adaptation's `--max-planning-seconds 30`, as expansions. Its product search is Python that
/// progresses a residual formula for each of the 8 neighbours of every expanded state; at an
/// estimated 10 000 expansions a second (the order such a loop reaches in CPython) 30 s is
/// 300 000 expansions. That is above [`MAX_EXPANSIONS`], so on the original's own terms the
/// expansion limit binds first and the clock only matters on a slower machine; we keep both
/// counts and stop at the smaller.
pub const TIME_LIMIT_EXPANSIONS: u64 = 300_000;
/// Cells sampled per proposition for the heuristic.
pub const HEURISTIC_SAMPLES: usize = 64;
/// The largest product (cells × automaton states) the search allocates tables for.
pub const MAX_PRODUCT_STATES: u64 = m2rc_planner::product::MAX_PRODUCT_STATES;

const SQRT2: f64 = std::f64::consts::SQRT_2;
const MOVES: [(i32, i32, f64); 8] = [
    (-1, 0, 1.0),
    (1, 0, 1.0),
    (0, -1, 1.0),
    (0, 1, 1.0),
    (-1, -1, SQRT2),
    (-1, 1, SQRT2),
    (1, -1, SQRT2),
    (1, 1, SQRT2),
];

/// A route found by the product search.
#[derive(Clone, Debug, PartialEq)]
pub struct ProductRoute {
    pub trajectory: Vec<Cell>,
    /// Length in cells.
    pub cost: f64,
    pub expansions: u64,
    pub automaton_states: usize,
}

#[derive(Clone, Debug, PartialEq)]
pub enum ProductError {
    /// The formula's automaton could not be built (too many atoms, over its work budget).
    Automaton(String),
    /// The start cell is not traversable, or reading it already falsifies the formula.
    StartRejected,
    /// Every reachable state was expanded and none accepts.
    NoRoute { expansions: u64 },
    /// The expansion (or time) limit ran out first.
    Limit { expansions: u64 },
    /// More product states than [`MAX_PRODUCT_STATES`].
    TooLarge { cells: usize, states: usize },
}

impl std::fmt::Display for ProductError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ProductError::Automaton(m) => write!(f, "the formula's automaton: {m}"),
            ProductError::StartRejected => {
                f.write_str("the start cell is blocked or already violates the formula")
            }
            ProductError::NoRoute { expansions } => {
                write!(f, "no accepting route ({expansions} expansions)")
            }
            ProductError::Limit { expansions } => {
                write!(
                    f,
                    "the expansion limit was reached ({expansions} expansions)"
                )
            }
            ProductError::TooLarge { cells, states } => write!(
                f,
                "{cells} cells x {states} automaton states is over {MAX_PRODUCT_STATES}"
            ),
        }
    }
}

impl ProductError {
    /// The record's word for it.
    pub fn kind(&self) -> &'static str {
        match self {
            ProductError::Automaton(_) => "automaton_failed",
            ProductError::StartRejected => "start_rejected",
            ProductError::NoRoute { .. } => "no_route",
            ProductError::Limit { .. } => "expansion_limit",
            ProductError::TooLarge { .. } => "too_large",
        }
    }
}

/// The search's guess of the distance still to go.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Guess {
    /// OSG-LLM: octile distance to [`HEURISTIC_SAMPLES`] sampled cells plus the centre cell.
    OctileSamples,
    /// LTLCodeGen: Euclidean distance to at most this many cells of each region.
    EuclidSamples(usize),
}

/// What one search needs.
pub struct ProductQuery<'a> {
    pub n: usize,
    /// Row-major traversability.
    pub traversable: &'a [bool],
    pub formula: &'a Formula,
    /// The cells (row-major indices, ascending) where a formula atom is true.
    pub region: &'a dyn Fn(&str) -> Option<&'a [u32]>,
    pub start: Cell,
    /// Expansions allowed (`u64::MAX`: none but the product's size).
    pub max_expansions: u64,
    pub guess: Guess,
}

impl<'a> ProductQuery<'a> {
    /// OSG-LLM's search over `graph`, the formula over aliases of `aps`.
    pub fn osg(
        graph: &'a SceneGraph,
        formula: &'a Formula,
        region: &'a dyn Fn(&str) -> Option<&'a [u32]>,
        start: Cell,
        max_expansions: u64,
    ) -> Self {
        ProductQuery {
            n: graph.n,
            traversable: &graph.traversable,
            formula,
            region,
            start,
            max_expansions,
            guess: Guess::OctileSamples,
        }
    }
}

/// The region of an alias `p<i>` of `aps` in `graph`.
pub fn alias_region<'a>(graph: &'a SceneGraph, aps: &'a [String], atom: &str) -> Option<&'a [u32]> {
    let i: usize = atom.strip_prefix('p')?.parse().ok()?;
    graph.node_by_ap(aps.get(i)?).map(|x| x.cells.as_slice())
}

#[derive(PartialEq)]
struct Open {
    f: f64,
    seq: u64,
    state: usize,
}
impl Eq for Open {}
impl Ord for Open {
    fn cmp(&self, o: &Self) -> Ordering {
        o.f.total_cmp(&self.f).then(o.seq.cmp(&self.seq))
    }
}
impl PartialOrd for Open {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

fn octile(a: (i64, i64), b: (i64, i64)) -> f64 {
    let (dr, dc) = ((a.0 - b.0).abs() as f64, (a.1 - b.1).abs() as f64);
    dr.max(dc) + (SQRT2 - 1.0) * dr.min(dc)
}

/// Up to `k` evenly spaced cells of a region, plus (with `centre`) its cell nearest the centre.
fn samples(cells: &[u32], n: usize, k: usize, centre: bool) -> Vec<(i64, i64)> {
    let rc = |i: u32| ((i as usize / n) as i64, (i as usize % n) as i64);
    if cells.is_empty() || k == 0 {
        return Vec::new();
    }
    let len = cells.len();
    let mut out: Vec<(i64, i64)> = if len <= k {
        cells.iter().map(|&i| rc(i)).collect()
    } else {
        (0..k).map(|j| rc(cells[j * len / k])).collect()
    };
    if !centre {
        return out;
    }
    let (sr, sc) = cells.iter().fold((0f64, 0f64), |s, &i| {
        let (r, c) = rc(i);
        (s.0 + r as f64, s.1 + c as f64)
    });
    let centre = (sr / len as f64, sc / len as f64);
    let near = cells.iter().map(|&i| rc(i)).min_by(|a, b| {
        let d = |x: &(i64, i64)| (x.0 as f64 - centre.0).powi(2) + (x.1 as f64 - centre.1).powi(2);
        d(a).total_cmp(&d(b))
    });
    out.extend(near);
    out
}

/// The cheapest route the search finds, or why none.
pub fn search(q: &ProductQuery) -> Result<ProductRoute, ProductError> {
    let n = q.n;
    let trav = q.traversable;
    let atoms: Vec<String> = q.formula.atoms().into_iter().map(String::from).collect();
    let dfa =
        Dfa::build(q.formula, &atoms, true).map_err(|e| ProductError::Automaton(e.to_string()))?;
    let nq = dfa.states();
    if (n as u128 * n as u128) * nq as u128 > MAX_PRODUCT_STATES as u128 {
        return Err(ProductError::TooLarge {
            cells: n * n,
            states: nq,
        });
    }
    // The AP of each automaton atom, and the letter (atom bit mask) of every cell.
    let mut letter = vec![0u64; n * n];
    let mut regions: Vec<&[u32]> = Vec::new();
    for (k, a) in atoms.iter().enumerate() {
        let cells: &[u32] = (q.region)(a).unwrap_or(&[]);
        for &i in cells {
            if let Some(l) = letter.get_mut(i as usize) {
                *l |= 1 << k;
            }
        }
        regions.push(cells);
    }
    let live = dfa.live();
    let idx = |c: Cell| c.row as usize * n + c.col as usize;
    if q.start.row as usize >= n
        || q.start.col as usize >= n
        || trav.len() != n * n
        || !trav[idx(q.start)]
    {
        return Err(ProductError::StartRejected);
    }
    let q0 = dfa.step(dfa.initial, letter[idx(q.start)]);
    if !live[q0] {
        return Err(ProductError::StartRejected);
    }
    // Per automaton state: the sampled cells of the propositions it waits for (the positive atoms
    // of an edge to another live state).
    let atom_samples: Vec<Vec<(i64, i64)>> = regions
        .iter()
        .map(|c| match q.guess {
            Guess::OctileSamples => samples(c, n, HEURISTIC_SAMPLES, true),
            Guess::EuclidSamples(k) => samples(c, n, k, false),
        })
        .collect();
    let pending: Vec<Vec<usize>> = (0..nq)
        .map(|s| {
            let mut bits = 0u64;
            for e in &dfa.edges[s] {
                if e.to != s && live[e.to] {
                    for c in &e.guard.0 {
                        bits |= c.pos;
                    }
                }
            }
            (0..atoms.len()).filter(|k| bits >> k & 1 == 1).collect()
        })
        .collect();
    // The Euclidean guess is the exact distance to the nearest sampled cell, read from one lazy
    // distance transform per automaton state (2 000 samples per region are too many to scan at
    // every push); the octile guess scans its 65 samples per region.
    let mut fields: Vec<Option<LazySquaredDistances>> = (0..nq).map(|_| None).collect();
    let mut heur = |s: usize, cell: usize| -> f64 {
        if dfa.accepting[s] || pending[s].is_empty() {
            return 0.0;
        }
        match q.guess {
            Guess::OctileSamples => {
                let here = ((cell / n) as i64, (cell % n) as i64);
                pending[s]
                    .iter()
                    .flat_map(|&k| atom_samples[k].iter().map(move |&p| octile(here, p)))
                    .min_by(f64::total_cmp)
                    .unwrap_or(0.0)
            }
            Guess::EuclidSamples(_) => {
                let field = fields[s].get_or_insert_with(|| {
                    let mut mask = vec![false; n * n];
                    for &k in &pending[s] {
                        for &(r, c) in &atom_samples[k] {
                            mask[r as usize * n + c as usize] = true;
                        }
                    }
                    LazySquaredDistances::new(&mask, n)
                });
                match field.get(cell) {
                    NO_SOURCE => 0.0,
                    v => (v as f64).sqrt(),
                }
            }
        }
    };
    let total = n * n * nq;
    let mut dist = vec![f64::INFINITY; total];
    let mut pred = vec![u32::MAX; total];
    let mut closed = vec![false; total];
    let mut heap = BinaryHeap::new();
    let s0 = idx(q.start) * nq + q0;
    dist[s0] = 0.0;
    heap.push(Open {
        f: heur(q0, idx(q.start)),
        seq: 0,
        state: s0,
    });
    let mut seq = 1u64;
    let mut expansions = 0u64;
    while let Some(Open { state, .. }) = heap.pop() {
        if closed[state] {
            continue;
        }
        closed[state] = true;
        let (u, s) = (state / nq, state % nq);
        if dfa.accepting[s] {
            let mut cells = Vec::new();
            let mut at = state;
            loop {
                cells.push(Cell::new((at / nq / n) as u32, (at / nq % n) as u32));
                if pred[at] == u32::MAX {
                    break;
                }
                at = pred[at] as usize;
            }
            cells.reverse();
            return Ok(ProductRoute {
                trajectory: cells,
                cost: dist[state],
                expansions,
                automaton_states: nq,
            });
        }
        if expansions >= q.max_expansions {
            return Err(ProductError::Limit { expansions });
        }
        expansions += 1;
        let (r, c) = ((u / n) as i32, (u % n) as i32);
        for &(dr, dc, step) in &MOVES {
            let (r2, c2) = (r + dr, c + dc);
            if r2 < 0 || c2 < 0 || r2 as usize >= n || c2 as usize >= n {
                continue;
            }
            let v = r2 as usize * n + c2 as usize;
            if !trav[v] {
                continue;
            }
            if dr != 0
                && dc != 0
                && (!trav[(r + dr) as usize * n + c as usize]
                    || !trav[r as usize * n + (c + dc) as usize])
            {
                continue;
            }
            let s2 = dfa.step(s, letter[v]);
            if !live[s2] {
                continue;
            }
            let t = v * nq + s2;
            let d = dist[state] + step;
            if !closed[t] && d < dist[t] {
                dist[t] = d;
                pred[t] = state as u32;
                heap.push(Open {
                    f: d + heur(s2, v),
                    seq,
                    state: t,
                });
                seq += 1;
            }
        }
    }
    Err(ProductError::NoRoute { expansions })
}
