//! ILN's planner: Dijkstra over the area–passage graph with the adaptation's edge cost, then grid
//! A* from the start through each chosen passage's anchor to the destination area's medoid; a
//! passage whose anchor cannot be reached is dropped and the area route planned once more.

use super::graph::AreaGraph;
use crate::common::grid::{GridSearch, append_path};
use m2rc_stdlib::grid::Cell;
use std::collections::{BTreeMap, BTreeSet};

/// The cost of a passage the evaluator said nothing about.
pub const BASE_PASSAGE_COST: f64 = 10.0;

/// The cost of crossing passage `k` from area `from` to the other side: the straight distances
/// (cells) from the area's centroid to the anchor and from the anchor to the other centroid, plus
/// twice the passage's rated cost.
pub fn edge_cost(g: &AreaGraph, k: usize, from: usize, rated: f64) -> f64 {
    let p = &g.passages[k];
    let to = if p.areas.0 == from {
        p.areas.1
    } else {
        p.areas.0
    };
    let d = |a: [f64; 2], c: Cell| (a[0] - c.row as f64).hypot(a[1] - c.col as f64);
    d(g.areas[from].centroid, p.anchor) + d(g.areas[to].centroid, p.anchor) + 2.0 * rated
}

/// The cheapest sequence of passages from area `start` to area `dest`, skipping `banned`; ties
/// go to the lower area index, then the lower passage index. `None` when `dest` is unreachable.
pub fn dijkstra(
    g: &AreaGraph,
    costs: &BTreeMap<usize, f64>,
    start: usize,
    dest: usize,
    banned: &BTreeSet<usize>,
) -> Option<Vec<usize>> {
    let n = g.areas.len();
    let mut dist = vec![f64::INFINITY; n];
    let mut via: Vec<Option<(usize, usize)>> = vec![None; n];
    let mut done = vec![false; n];
    dist[start] = 0.0;
    // Areas are few (tens), so a linear scan for the next area is simpler than a heap.
    loop {
        let u = (0..n)
            .filter(|&i| !done[i] && dist[i].is_finite())
            .min_by(|&a, &b| dist[a].total_cmp(&dist[b]).then(a.cmp(&b)))?;
        if u == dest {
            break;
        }
        done[u] = true;
        for &k in &g.areas[u].passages {
            if banned.contains(&k) {
                continue;
            }
            let p = &g.passages[k];
            let v = if p.areas.0 == u { p.areas.1 } else { p.areas.0 };
            let rated = costs.get(&k).copied().unwrap_or(BASE_PASSAGE_COST);
            let nd = dist[u] + edge_cost(g, k, u, rated);
            if nd < dist[v] {
                dist[v] = nd;
                via[v] = Some((u, k));
            }
        }
    }
    let mut out = Vec::new();
    let mut at = dest;
    while let Some((prev, k)) = via[at] {
        out.push(k);
        at = prev;
    }
    out.reverse();
    Some(out)
}

/// How the grid realisation ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Realised {
    /// The whole route, and the passages it went through.
    Complete {
        route: Vec<Cell>,
        passages: Vec<usize>,
        replanned: bool,
    },
    /// No area route (the graph does not join the two areas).
    NoGraphPath { route: Vec<Cell> },
    /// A passage anchor or the medoid stayed unreachable after the one replan; the route so far.
    GridFailed {
        route: Vec<Cell>,
        passages: Vec<usize>,
        unreachable: String,
    },
}

/// Plans the area route and realises it on the grid, replanning once without a passage whose
/// anchor cannot be reached.
pub fn plan_and_realise(
    g: &AreaGraph,
    grid: &mut GridSearch<'_>,
    costs: &BTreeMap<usize, f64>,
    start_cell: Cell,
    start: usize,
    dest: usize,
) -> Realised {
    let mut banned = BTreeSet::new();
    let mut replanned = false;
    loop {
        let Some(passages) = dijkstra(g, costs, start, dest, &banned) else {
            return Realised::NoGraphPath {
                route: vec![start_cell],
            };
        };
        let mut route = vec![start_cell];
        let mut failed = None;
        for &k in &passages {
            let at = *route.last().expect("non-empty");
            match grid.path_to_any(at, &[g.passages[k].anchor], None) {
                Ok(leg) => append_path(&mut route, &leg.cells),
                Err(_) => {
                    failed = Some(k);
                    break;
                }
            }
        }
        match failed {
            Some(k) if !replanned => {
                banned.insert(k);
                replanned = true;
                continue;
            }
            Some(k) => {
                return Realised::GridFailed {
                    route,
                    passages,
                    unreachable: g.passages[k].id.clone(),
                };
            }
            None => {}
        }
        let at = *route.last().expect("non-empty");
        return match grid.path_to_any(at, &[g.areas[dest].medoid], None) {
            Ok(leg) => {
                append_path(&mut route, &leg.cells);
                Realised::Complete {
                    route,
                    passages,
                    replanned,
                }
            }
            Err(_) => Realised::GridFailed {
                route,
                passages,
                unreachable: format!("the medoid of {}", g.areas[dest].id),
            },
        };
    }
}
