//! `rooms.tour(k)`: "go through two bedrooms, then ..." without naming which. The compiler
//! chooses the k rooms and their order that make the shortest walk from where the stage starts,
//! so the writer never has to invent which rooms were meant.

use super::Call;
use crate::eval::value::{PlaceVal, Value};
use crate::eval::{Grounder, Problem, codes};
use std::rc::Rc;

/// Ordered choices searched exactly (8! of them); past that the nearest next room is taken.
const EXACT_LIMIT: u64 = 40_320;

/// `k` distinct reachable rooms of the receiver in the order of the shortest walk from `from`
/// that enters each in turn. The walk's length is the travel distance to the first room plus the
/// travel distances between consecutive rooms (nearest cells; crossing a room is not counted).
pub(super) fn tour(g: &mut Grounder, c: Call) -> Value {
    let (Some(Value::Set(s)), Some(Value::Place(from))) = (&c.recv, c.arg(1)) else {
        return g.unsupported(c.e);
    };
    let rooms: Vec<u32> = s
        .iter()
        .filter_map(|p| match p {
            PlaceVal::Room(r) => Some(*r),
            _ => None,
        })
        .collect();
    let k = c.number(0).unwrap_or(1.0) as i64;
    let first = g.travel_from(&from);
    let reachable: Vec<(u32, f64)> = rooms
        .iter()
        .filter_map(|&r| first.to(g.q.room_cells(r)).map(|d| (r, d)))
        .collect();
    let n = reachable.len() as i64;
    if k < 1 || k > n {
        return g.report(
            Problem::error(
                codes::ORDINAL_OUT_OF_RANGE,
                c.arg_span(0),
                format!(
                    "k = {k}, but {n} of these {} room(s) can be reached from here",
                    rooms.len()
                ),
            )
            .label(
                c.recv_span(),
                format!("{} room(s) on this map", rooms.len()),
            ),
        );
    }
    let fields: Vec<Rc<m2rc_stdlib::query::TravelField>> = reachable
        .iter()
        .map(|&(r, _)| g.travel_from(&PlaceVal::Room(r)))
        .collect();
    let between: Vec<Vec<f64>> = fields
        .iter()
        .map(|f| {
            reachable
                .iter()
                .map(|&(r, _)| f.to(g.q.room_cells(r)).unwrap_or(f64::INFINITY))
                .collect()
        })
        .collect();
    let start: Vec<f64> = reachable.iter().map(|&(_, d)| d).collect();
    let order = best_order(&start, &between, k as usize);
    Value::Set(
        order
            .into_iter()
            .map(|i| PlaceVal::Room(reachable[i].0))
            .collect(),
    )
}

/// The cheapest sequence of `k` distinct indices (cost: `start[first]` plus `between[a][b]` per
/// step), the first in index order among equals; exact up to [`EXACT_LIMIT`] sequences, greedy
/// beyond.
fn best_order(start: &[f64], between: &[Vec<f64>], k: usize) -> Vec<usize> {
    let m = start.len();
    let sequences = (0..k).try_fold(1u64, |acc, i| acc.checked_mul((m - i) as u64));
    if sequences.is_none_or(|s| s > EXACT_LIMIT) {
        let mut out: Vec<usize> = Vec::with_capacity(k);
        while out.len() < k {
            let cost = |i: usize| out.last().map_or(start[i], |&a| between[a][i]);
            let next = (0..m)
                .filter(|i| !out.contains(i))
                .min_by(|&a, &b| cost(a).total_cmp(&cost(b)).then(a.cmp(&b)));
            out.extend(next);
        }
        return out;
    }
    let mut best = (f64::INFINITY, Vec::new());
    let mut path = Vec::with_capacity(k);
    search(start, between, k, 0.0, &mut path, &mut best);
    best.1
}

fn search(
    start: &[f64],
    between: &[Vec<f64>],
    k: usize,
    cost: f64,
    path: &mut Vec<usize>,
    best: &mut (f64, Vec<usize>),
) {
    if cost >= best.0 && !best.1.is_empty() {
        return;
    }
    if path.len() == k {
        *best = (cost, path.clone());
        return;
    }
    for i in 0..start.len() {
        if path.contains(&i) {
            continue;
        }
        let step = path.last().map_or(start[i], |&a| between[a][i]);
        path.push(i);
        search(start, between, k, cost + step, path, best);
        path.pop();
    }
}

#[cfg(test)]
mod tests {
    use super::best_order;

    #[test]
    fn the_shortest_walk_is_chosen_not_the_nearest_first() {
        // Room 0 is nearest, but 1 then 2 are adjacent to each other and 0 is out of the way.
        let start = [1.0, 2.0, 3.0];
        let inf = 100.0;
        let between = vec![
            vec![0.0, inf, inf],
            vec![inf, 0.0, 0.5],
            vec![inf, 0.5, 0.0],
        ];
        assert_eq!(best_order(&start, &between, 2), vec![1, 2]);
        assert_eq!(best_order(&start, &between, 1), vec![0]);
    }

    #[test]
    fn ties_keep_the_set_order_and_large_sets_fall_back_to_greedy() {
        let start = [1.0, 1.0];
        let between = vec![vec![0.0, 1.0], vec![1.0, 0.0]];
        assert_eq!(best_order(&start, &between, 2), vec![0, 1]);
        let n = 12;
        let start: Vec<f64> = (0..n).map(|i| i as f64).collect();
        let between: Vec<Vec<f64>> = (0..n)
            .map(|a| (0..n).map(|b| (a as f64 - b as f64).abs()).collect())
            .collect();
        assert_eq!(best_order(&start, &between, 6), vec![0, 1, 2, 3, 4, 5]);
    }
}
