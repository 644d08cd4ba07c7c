//! Lang2LTL's planner as the adaptation runs it (`vanilla`, the "AP-MDP"): a uniform-cost search
//! over (cell, residual formula) states. An action goes, by masked A*, to the nearest cell
//! labelled with one of the residual's positive "eventually" APs whose label would advance it; the
//! residual is then advanced by the labels of that **target cell only**, never by the cells on the
//! way (so an avoided room crossed on the way is not seen, unless it is a global `G !ap`, whose
//! cells are masked). At most [`EXPANSION_LIMIT`] AP-states are expanded. When that yields no
//! movement, the `fast` fallback visits the positive eventual APs in order with plain A*, going to
//! the reachable cell closest to an AP's centre when its cells cannot be reached.

use crate::common::failure::Failure;
use crate::common::grid::{GridSearch, SearchFail, append_path, mask_of};
use crate::common::prefix_ltl::to_prefix;
use crate::common::progress::{accepting, eventual_atoms, global_avoids, progress, same};
use m2rc_compiler::ltl::Formula;
use m2rc_compiler::ltl::syntax::Kind;
use m2rc_stdlib::grid::Cell;
use serde::Serialize;
use std::collections::{BTreeMap, BinaryHeap, HashMap};

/// AP-states the search may expand.
pub const EXPANSION_LIMIT: usize = 5_000;

/// Where each AP of the formula holds.
pub struct Labels {
    pub atoms: Vec<String>,
    pub cells: Vec<Vec<Cell>>,
    pub masks: Vec<Vec<bool>>,
    pub centers: Vec<[f64; 2]>,
}

impl Labels {
    pub fn new(n: usize, atoms: Vec<(String, Vec<Cell>, [f64; 2])>) -> Self {
        let mut l = Labels {
            atoms: vec![],
            cells: vec![],
            masks: vec![],
            centers: vec![],
        };
        for (a, cells, c) in atoms {
            l.masks.push(mask_of(n, &cells));
            l.atoms.push(a);
            l.cells.push(cells);
            l.centers.push(c);
        }
        l
    }

    fn index(&self, atom: &str) -> Option<usize> {
        self.atoms.iter().position(|a| a == atom)
    }

    fn holds_at(&self, cell: Cell, n: usize) -> impl Fn(&str) -> bool + '_ {
        let i = cell.row as usize * n + cell.col as usize;
        move |a: &str| self.index(a).is_some_and(|k| self.masks[k][i])
    }
}

/// What the planner did.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct PlanTrace {
    /// `ap-mdp`, or `fast` when the AP-MDP yielded no movement.
    pub mode: String,
    pub ap_states_expanded: usize,
    pub grid_expansions: u64,
    /// Why the AP-MDP gave way to the fallback, when it did.
    pub fallback_reason: Option<String>,
    /// The APs visited, in order, with the residual after each.
    pub visits: Vec<(String, String)>,
    pub accepted: bool,
}

struct State {
    cell: Cell,
    residual: Formula,
    parent: Option<usize>,
    via: Option<(String, Vec<Cell>)>,
}

#[derive(PartialEq)]
struct Open(f64, usize);
impl Eq for Open {}
impl PartialOrd for Open {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Open {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        o.0.total_cmp(&self.0).then(o.1.cmp(&self.1))
    }
}

/// Plans `formula` from `start`; `limit` is the AP-state expansion limit.
pub fn plan(
    search: &mut GridSearch<'_>,
    start: Cell,
    formula: &Formula,
    labels: &Labels,
    limit: usize,
) -> Result<(Vec<Cell>, PlanTrace), Failure> {
    let n = search.n();
    let mut trace = PlanTrace {
        mode: "ap-mdp".into(),
        ..PlanTrace::default()
    };
    let mut blocked = vec![false; n * n];
    for a in global_avoids(formula) {
        if let Some(k) = labels.index(&a) {
            for (b, m) in blocked.iter_mut().zip(&labels.masks[k]) {
                *b |= *m;
            }
        }
    }
    let mut states = vec![State {
        cell: start,
        residual: formula.clone(),
        parent: None,
        via: None,
    }];
    let mut best: HashMap<(Cell, String), f64> = HashMap::new();
    let mut paths: HashMap<(Cell, usize), Option<Vec<Cell>>> = HashMap::new();
    let mut open = BinaryHeap::from([Open(0.0, 0)]);
    let mut found = None;
    let mut over_limit = false;
    while let Some(Open(cost, id)) = open.pop() {
        if accepting(&states[id].residual) {
            found = Some(id);
            break;
        }
        if trace.ap_states_expanded >= limit {
            over_limit = true;
            break;
        }
        trace.ap_states_expanded += 1;
        let (cell, residual) = (states[id].cell, states[id].residual.clone());
        for atom in eventual_atoms(&residual) {
            let Some(k) = labels.index(&atom) else {
                continue;
            };
            if labels.cells[k].is_empty() {
                continue;
            }
            if same(&progress(&residual, &|a| a == atom), &residual) {
                continue;
            }
            let path = paths
                .entry((cell, k))
                .or_insert_with(|| {
                    search
                        .path_to_any(cell, &labels.cells[k], Some(&blocked))
                        .ok()
                        .map(|p| p.cells)
                })
                .clone();
            let Some(path) = path else { continue };
            let target = *path.last().unwrap_or(&cell);
            let next = progress(&residual, &labels.holds_at(target, n));
            if next.kind == Kind::False {
                continue;
            }
            let step = path_length(&path);
            let key = (target, to_prefix(&next));
            if best.get(&key).is_some_and(|c| *c <= cost + step) {
                continue;
            }
            best.insert(key, cost + step);
            states.push(State {
                cell: target,
                residual: next,
                parent: Some(id),
                via: Some((atom.clone(), path)),
            });
            open.push(Open(cost + step, states.len() - 1));
        }
    }
    trace.grid_expansions = search.expansions;
    if let Some(id) = found {
        let mut chain = vec![];
        let mut cur = Some(id);
        while let Some(c) = cur {
            chain.push(c);
            cur = states[c].parent;
        }
        chain.reverse();
        let mut route = vec![start];
        for &c in &chain {
            if let Some((atom, path)) = &states[c].via {
                append_path(&mut route, path);
                trace
                    .visits
                    .push((atom.clone(), to_prefix(&states[c].residual)));
            }
        }
        trace.accepted = true;
        if route.len() > 1 {
            return Ok((route, trace));
        }
        trace.fallback_reason = Some("the formula is accepted without moving".into());
    } else {
        trace.fallback_reason = Some(if over_limit {
            format!("the AP-MDP expanded its limit of {limit} AP-states")
        } else {
            "no accepting AP-state is reachable".into()
        });
    }
    trace.mode = "fast".into();
    trace.visits.clear();
    let route = fast(search, start, formula, labels, &mut trace)?;
    trace.grid_expansions = search.expansions;
    Ok((route, trace))
}

fn path_length(p: &[Cell]) -> f64 {
    p.windows(2).map(|w| w[0].dist(w[1])).sum()
}

/// The `fast` fallback: the positive eventual APs in order, plain A* (no masks); an unreachable
/// AP is replaced by the reachable cell closest to its centre.
fn fast(
    search: &mut GridSearch<'_>,
    start: Cell,
    formula: &Formula,
    labels: &Labels,
    trace: &mut PlanTrace,
) -> Result<Vec<Cell>, Failure> {
    let mut route = vec![start];
    let mut cur = start;
    let mut reach: BTreeMap<Cell, Vec<bool>> = BTreeMap::new();
    for atom in eventual_atoms(formula) {
        let Some(k) = labels.index(&atom) else {
            continue;
        };
        let path = match search.path_to_any(cur, &labels.cells[k], None) {
            Ok(p) => p.cells,
            Err(SearchFail::BadQuery(m)) => return Err(Failure::new("planner_failed", m)),
            Err(_) => {
                let seen = reach
                    .entry(cur)
                    .or_insert_with(|| search.reachable(cur, None));
                let c = labels.centers[k];
                let n = search.n();
                let Some(i) = (0..seen.len()).filter(|&i| seen[i]).min_by(|&a, &b| {
                    let d = |i: usize| ((i / n) as f64 - c[0]).hypot((i % n) as f64 - c[1]);
                    d(a).total_cmp(&d(b))
                }) else {
                    continue;
                };
                let goal = Cell::new((i / n) as u32, (i % n) as u32);
                match search.path_to_any(cur, &[goal], None) {
                    Ok(p) => p.cells,
                    Err(_) => continue,
                }
            }
        };
        cur = *path.last().unwrap_or(&cur);
        append_path(&mut route, &path);
        trace.visits.push((atom, String::new()));
    }
    Ok(route)
}
