//! OSG-LLM's fallbacks when the product search finds nothing (adaptation's `amra` mode, used
//! only when the instruction has no avoids):
//!
//! 1. the room skeleton: a breadth-first search over room adjacency from the current room to
//!    each goal's room, trying the model's preferred rooms first among neighbours, whose rooms
//!    become `enter(room)` goals inserted before the goal;
//! 2. sequential AP A* over that augmented list: for each goal, the shortest path to the 96
//!    cells of its region nearest the current cell;
//! 3. failing that, sequential AP A* over the original goals.
//!
//! Sequential A* is one Dijkstra search per goal whose targets are the 96 candidate cells: the
//! shortest of the 96 separate searches the adaptation runs, found at once.

use super::graph::SceneGraph;
use m2rc_planner::astar::{AStar, Heuristic, Outcome, Query, Space};
use m2rc_planner::layout::{Layout, NO_HEADING};
use m2rc_stdlib::grid::Cell;
use std::collections::{BTreeSet, VecDeque};

/// Candidate cells per goal in sequential A*.
pub const CANDIDATE_CELLS: usize = 96;

/// The goal list with the skeleton's rooms inserted, or `None` when the start or a goal has no
/// room to search from or to, or a goal's room cannot be reached over the room graph.
pub fn skeleton_goals(
    graph: &SceneGraph,
    start_room: Option<u32>,
    goals: &[String],
    preferred: &[u32],
) -> Option<Vec<String>> {
    let mut current = start_room?;
    let mut out: Vec<String> = Vec::new();
    for goal in goals {
        let target = graph.node_by_ap(goal)?.room?;
        let path = bfs(graph, current, target, preferred)?;
        for room in path.into_iter().skip(1) {
            let ap = format!("enter(room_{room})");
            if out.last() != Some(&ap) && &ap != goal {
                out.push(ap);
            }
        }
        out.push(goal.clone());
        current = target;
    }
    Some(out)
}

/// Rooms from `from` to `to` inclusive, breadth first, neighbours in preference order (preferred
/// rooms first, in the model's order, then the rest by id).
fn bfs(graph: &SceneGraph, from: u32, to: u32, preferred: &[u32]) -> Option<Vec<u32>> {
    let mut prev: std::collections::BTreeMap<u32, u32> = Default::default();
    let mut seen: BTreeSet<u32> = BTreeSet::from([from]);
    let mut queue = VecDeque::from([from]);
    while let Some(r) = queue.pop_front() {
        if r == to {
            let mut path = vec![to];
            let mut at = to;
            while let Some(&p) = prev.get(&at) {
                path.push(p);
                at = p;
            }
            path.reverse();
            return Some(path);
        }
        let mut next: Vec<u32> = graph.adjacency.get(&r).cloned().unwrap_or_default();
        next.sort_by_key(|x| {
            (
                preferred.iter().position(|p| p == x).unwrap_or(usize::MAX),
                *x,
            )
        });
        for x in next {
            if seen.insert(x) {
                prev.insert(x, r);
                queue.push_back(x);
            }
        }
    }
    None
}

/// Why sequential A* stopped.
#[derive(Clone, Debug, PartialEq)]
pub struct SequentialFailure {
    /// The goal it could not reach (its AP).
    pub goal: String,
    /// Goals reached before it.
    pub reached: usize,
}

/// Visits `goals` in order from `start`, each by the shortest path to its nearest candidate
/// cells. The route starts at `start`; consecutive legs share their joining cell once.
pub fn sequential(
    graph: &SceneGraph,
    start: Cell,
    goals: &[String],
) -> Result<Vec<Cell>, SequentialFailure> {
    let n = graph.n;
    let layout = Layout::new(n);
    let trav = layout.pad(&graph.traversable, false);
    let space = Space {
        layout,
        traversable: &trav,
        allowed: &trav,
        phi: None,
    };
    let mut astar = AStar::new();
    let mut route = vec![start];
    let mut at = start;
    for (k, goal) in goals.iter().enumerate() {
        let fail = || SequentialFailure {
            goal: goal.clone(),
            reached: k,
        };
        let node = graph.node_by_ap(goal).ok_or_else(fail)?;
        let mut cands: Vec<(u64, u32)> = node
            .cells
            .iter()
            .map(|&i| {
                let c = Cell::new((i as usize / n) as u32, (i as usize % n) as u32);
                (c.dist_sq(at), i)
            })
            .collect();
        cands.sort_unstable();
        cands.truncate(CANDIDATE_CELLS);
        if cands.is_empty() {
            return Err(fail());
        }
        let mut goal_mask = vec![false; layout.len()];
        for &(_, i) in &cands {
            goal_mask[layout.idx_of_plain(i as usize)] = true;
        }
        let outcome = astar.search(
            space,
            Query {
                start: layout.idx(at),
                goal: &goal_mask,
                heuristic: Heuristic::Zero,
                smooth: None,
                initial_heading: NO_HEADING,
                budget: 0,
            },
        );
        match outcome {
            Outcome::Found(found) => {
                route.extend(found.path.iter().skip(1).map(|&p| layout.cell(p)));
                at = *route.last().unwrap_or(&at);
            }
            _ => return Err(fail()),
        }
    }
    Ok(route)
}
