//! L*, the oracle length of one SPL segment: the shortest legal 8-connected grid path from the
//! segment's start cell to any cell of the target region.
//!
//! A move is legal when its destination is traversable, a diagonal does not cut a blocked
//! corner, and the move segment does not meet any active must-avoid (corner touches count).
//! The search is A* with the octile distance to the target's bounding box, which is consistent,
//! so the first target cell popped carries the same shortest distance as the reference's
//! Dijkstra (up to floating-point summation order). Buffers are reused per thread.

use super::geometry::{Geom, Point};
use super::map::{EvalMap, Legal, MOVES};
use std::cell::RefCell;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

const FLAG_TARGET: u8 = 1;
const FLAG_AVOID_CELL: u8 = 2;
const FLAG_NEAR_AVOID: u8 = 4;

#[derive(Default)]
struct Buffers {
    g: Vec<f64>,
    stamp: Vec<u32>,
    closed: Vec<u32>,
    flags: Vec<u8>,
    touched_flags: Vec<usize>,
    generation: u32,
    heap: BinaryHeap<Reverse<(u64, u32)>>,
}

thread_local! {
    static BUFFERS: RefCell<Buffers> = RefCell::new(Buffers::default());
}

/// Shortest legal path length in cells, or `None` when the start is blocked, inside an avoid,
/// or no target cell is reachable. The caller guarantees the map has an occupancy layer.
pub(crate) fn shortest_legal_length(
    map: &EvalMap,
    start: [i64; 2],
    target: &Geom,
    avoids: &[&Geom],
) -> Option<f64> {
    if !map.is_traversable(start[0], start[1]) {
        return None;
    }
    let sp: Point = [start[0] as f64, start[1] as f64];
    if avoids.iter().any(|a| a.contains(sp)) {
        return None;
    }
    if target.contains_cell(start[0], start[1]) {
        return Some(0.0);
    }
    let legal = map.legal_for_search()?;
    BUFFERS.with(|b| {
        let mut b = b.borrow_mut();
        search(&mut b, map, &legal, start, target, avoids)
    })
}

fn search(
    b: &mut Buffers,
    map: &EvalMap,
    legal: &Legal<'_>,
    start: [i64; 2],
    target: &Geom,
    avoids: &[&Geom],
) -> Option<f64> {
    let n = map.n();
    let nn = n * n;
    if b.g.len() != nn {
        b.g = vec![0.0; nn];
        b.stamp = vec![0; nn];
        b.closed = vec![0; nn];
        b.flags = vec![0; nn];
        b.touched_flags.clear();
        b.generation = 0;
    }
    b.generation = b.generation.wrapping_add(1);
    if b.generation == 0 {
        b.stamp.fill(0);
        b.closed.fill(0);
        b.generation = 1;
    }
    let generation = b.generation;
    for &i in &b.touched_flags {
        b.flags[i] = 0;
    }
    b.touched_flags.clear();
    b.heap.clear();

    // Target cells (in-grid, inside the region) and the heuristic's bounding box.
    let tb = target.bbox()?;
    let r0 = tb[0].floor().max(0.0);
    let r1 = tb[1].ceil().min(n as f64 - 1.0);
    let c0 = tb[2].floor().max(0.0);
    let c1 = tb[3].ceil().min(n as f64 - 1.0);
    if r0 > r1 || c0 > c1 {
        return None;
    }
    let mut any_target = false;
    for r in r0 as usize..=r1 as usize {
        for c in c0 as usize..=c1 as usize {
            if target.contains_cell(r as i64, c as i64) {
                let i = r * n + c;
                b.flags[i] |= FLAG_TARGET;
                b.touched_flags.push(i);
                any_target = true;
            }
        }
    }
    if !any_target {
        return None;
    }
    let heur_box = [tb[0].max(0.0), tb[1], tb[2].max(0.0), tb[3]];

    // Avoid cells (freeform) and the band around circle/rectangle avoids where moves need the
    // exact segment test: a move can only meet such a region if its destination lies within one
    // cell (Chebyshev) of the region's bounding box.
    let mut exact: Vec<&Geom> = Vec::new();
    for &a in avoids {
        match a {
            Geom::Freeform(f) => {
                for cell in &f.cells {
                    if map.in_grid(cell[0], cell[1]) {
                        let i = cell[0] as usize * n + cell[1] as usize;
                        b.flags[i] |= FLAG_AVOID_CELL;
                        b.touched_flags.push(i);
                    }
                }
            }
            _ => {
                exact.push(a);
                if let Some(bb) = a.bbox() {
                    let rr0 = (bb[0] - 1.5).floor().max(0.0);
                    let rr1 = (bb[1] + 1.5).ceil().min(n as f64 - 1.0);
                    let cc0 = (bb[2] - 1.5).floor().max(0.0);
                    let cc1 = (bb[3] + 1.5).ceil().min(n as f64 - 1.0);
                    if rr0 <= rr1 && cc0 <= cc1 {
                        for r in rr0 as usize..=rr1 as usize {
                            for c in cc0 as usize..=cc1 as usize {
                                let i = r * n + c;
                                b.flags[i] |= FLAG_NEAR_AVOID;
                                b.touched_flags.push(i);
                            }
                        }
                    }
                }
            }
        }
    }

    let h = |r: usize, c: usize| -> f64 {
        let (r, c) = (r as f64, c as f64);
        let dr = (heur_box[0] - r).max(r - heur_box[1]).max(0.0);
        let dc = (heur_box[2] - c).max(c - heur_box[3]).max(0.0);
        let (lo, hi) = if dr < dc { (dr, dc) } else { (dc, dr) };
        lo * std::f64::consts::SQRT_2 + (hi - lo)
    };

    let s = start[0] as usize * n + start[1] as usize;
    b.g[s] = 0.0;
    b.stamp[s] = generation;
    b.heap.push(Reverse((
        h(start[0] as usize, start[1] as usize).to_bits(),
        s as u32,
    )));
    while let Some(Reverse((_, u))) = b.heap.pop() {
        let u = u as usize;
        if b.closed[u] == generation {
            continue;
        }
        if b.flags[u] & FLAG_TARGET != 0 {
            return Some(b.g[u]);
        }
        b.closed[u] = generation;
        let (ur, uc) = (u / n, u % n);
        let gu = b.g[u];
        let bits = legal.at(u);
        for (k, &(dr, dc, cost)) in MOVES.iter().enumerate() {
            if bits & (1 << k) == 0 {
                continue;
            }
            let vr = (ur as i64 + dr) as usize;
            let vc = (uc as i64 + dc) as usize;
            let v = vr * n + vc;
            if b.closed[v] == generation {
                continue;
            }
            let fv = b.flags[v];
            if fv & FLAG_AVOID_CELL != 0 {
                continue;
            }
            if dr != 0 && dc != 0 {
                let corner1 = vr * n + uc;
                let corner2 = ur * n + vc;
                if (b.flags[corner1] | b.flags[corner2]) & FLAG_AVOID_CELL != 0 {
                    continue;
                }
            }
            if fv & FLAG_NEAR_AVOID != 0 {
                let a: Point = [ur as f64, uc as f64];
                let bpt: Point = [vr as f64, vc as f64];
                if exact.iter().any(|g| g.segment_intersects(a, bpt)) {
                    continue;
                }
            }
            let cand = gu + cost;
            if b.stamp[v] == generation && cand >= b.g[v] {
                continue;
            }
            b.g[v] = cand;
            b.stamp[v] = generation;
            b.heap
                .push(Reverse(((cand + h(vr, vc)).to_bits(), v as u32)));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::geometry::Freeform;

    fn open_map(n: usize, blocked: &[(usize, usize)]) -> EvalMap {
        let mut t = vec![true; n * n];
        for &(r, c) in blocked {
            t[r * n + c] = false;
        }
        EvalMap::from_parts(n, 1.0, Some(t), None)
    }

    fn cell(r: i64, c: i64) -> Geom {
        Geom::Freeform(Freeform::new(vec![[r, c]]))
    }

    /// Plain Dijkstra with per-edge exact tests, as a reference for the optimized search.
    fn brute(map: &EvalMap, start: [i64; 2], target: &Geom, avoids: &[&Geom]) -> Option<f64> {
        if !map.is_traversable(start[0], start[1]) {
            return None;
        }
        let sp = [start[0] as f64, start[1] as f64];
        if avoids.iter().any(|a| a.contains(sp)) {
            return None;
        }
        let n = map.n() as i64;
        let mut dist = vec![f64::INFINITY; (n * n) as usize];
        let mut done = vec![false; (n * n) as usize];
        dist[(start[0] * n + start[1]) as usize] = 0.0;
        loop {
            let mut best = None;
            for i in 0..(n * n) as usize {
                if !done[i] && dist[i].is_finite() && best.is_none_or(|b: usize| dist[i] < dist[b])
                {
                    best = Some(i);
                }
            }
            let u = best?;
            let (ur, uc) = (u as i64 / n, u as i64 % n);
            if target.contains_cell(ur, uc) {
                return Some(dist[u]);
            }
            done[u] = true;
            for &(dr, dc, cost) in &MOVES {
                let (vr, vc) = (ur + dr, uc + dc);
                if !map.is_traversable(vr, vc) {
                    continue;
                }
                if dr != 0
                    && dc != 0
                    && !(map.is_traversable(ur + dr, uc) && map.is_traversable(ur, uc + dc))
                {
                    continue;
                }
                let a = [ur as f64, uc as f64];
                let b = [vr as f64, vc as f64];
                if avoids.iter().any(|g| g.segment_intersects(a, b)) {
                    continue;
                }
                let v = (vr * n + vc) as usize;
                if dist[u] + cost < dist[v] {
                    dist[v] = dist[u] + cost;
                }
            }
        }
    }

    #[test]
    fn no_corner_cutting_around_an_obstacle() {
        let map = open_map(5, &[(1, 1)]);
        let l = shortest_legal_length(&map, [0, 0], &cell(2, 2), &[]).unwrap();
        assert!((l - 4.0).abs() < 1e-12, "{l}");
    }

    #[test]
    fn avoid_corner_touch_blocks_diagonals() {
        let map = open_map(3, &[]);
        let avoid = cell(0, 1);
        let l = shortest_legal_length(&map, [0, 0], &cell(1, 1), &[&avoid]).unwrap();
        assert!((l - 2.0).abs() < 1e-12, "{l}");
    }

    #[test]
    fn start_rules() {
        let map = open_map(3, &[(0, 0)]);
        assert_eq!(shortest_legal_length(&map, [0, 0], &cell(2, 2), &[]), None);
        assert_eq!(
            shortest_legal_length(&map, [2, 2], &cell(2, 2), &[]),
            Some(0.0)
        );
        let avoid = cell(1, 1);
        assert_eq!(
            shortest_legal_length(&map, [1, 1], &cell(2, 2), &[&avoid]),
            None
        );
        // Unreachable target.
        let walled = open_map(3, &[(0, 1), (1, 1), (2, 1)]);
        assert_eq!(
            shortest_legal_length(&walled, [0, 0], &cell(0, 2), &[]),
            None
        );
    }

    #[test]
    fn matches_plain_dijkstra_with_circle_and_rectangle_avoids() {
        let mut blocked = Vec::new();
        for r in 0..12 {
            if r != 6 {
                blocked.push((r, 7));
            }
        }
        blocked.push((3, 3));
        let map = open_map(14, &blocked);
        let circle = Geom::Circle {
            center: [9.3, 3.2],
            radius: 1.7,
        };
        let rect = Geom::Rect {
            center: [4.0, 10.0],
            width: 3.0,
            height: 2.5,
        };
        let target = Geom::Circle {
            center: [12.0, 12.0],
            radius: 1.2,
        };
        for start in [[0, 0], [13, 0], [5, 5], [0, 13]] {
            let fast = shortest_legal_length(&map, start, &target, &[&circle, &rect]);
            let slow = brute(&map, start, &target, &[&circle, &rect]);
            match (fast, slow) {
                (Some(a), Some(b)) => assert!((a - b).abs() < 1e-9, "{start:?}: {a} vs {b}"),
                (a, b) => assert_eq!(a, b, "{start:?}"),
            }
        }
    }

    proptest::proptest! {
        #[test]
        fn equals_plain_dijkstra_on_random_grids(
            n in 4usize..10,
            bits in proptest::collection::vec(proptest::bool::weighted(0.25), 100),
            avoid_cells in proptest::collection::vec((0i64..10, 0i64..10), 0..6),
            circle in (0.0f64..10.0, 0.0f64..10.0, 0.3f64..2.5),
            start in (0i64..10, 0i64..10),
            goal in (0i64..10, 0i64..10, 0.0f64..2.0),
        ) {
            let blocked: Vec<(usize, usize)> =
                (0..n * n).filter(|&i| bits[i]).map(|i| (i / n, i % n)).collect();
            let map = open_map(n, &blocked);
            let ff = Geom::Freeform(Freeform::new(avoid_cells.iter().map(|&(r, c)| [r, c]).collect()));
            let disc = Geom::Circle { center: [circle.0, circle.1], radius: circle.2 };
            let target = Geom::Circle { center: [goal.0 as f64, goal.1 as f64], radius: goal.2 + 0.1 };
            let s = [start.0 % n as i64, start.1 % n as i64];
            for avoids in [vec![], vec![&ff], vec![&ff, &disc]] {
                let fast = shortest_legal_length(&map, s, &target, &avoids);
                let slow = brute(&map, s, &target, &avoids);
                match (fast, slow) {
                    (Some(a), Some(b)) => proptest::prop_assert!((a - b).abs() < 1e-9, "{} vs {}", a, b),
                    (a, b) => proptest::prop_assert_eq!(a, b),
                }
            }
        }
    }
}
