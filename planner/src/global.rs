//! The exact global planner (`global_layered_dp`, method notes §4.6): all stages of all segments in
//! one layered search, so no stage endpoint is fixed before the later stages are known.
//!
//! Stage by stage, a multi-source Dijkstra starts from every arrival state of the previous stage
//! with its cumulative cost. Entering a goal cell records an arrival and does not continue through it
//! (first-entry semantics, the same thing the sequential A* does by stopping at its first goal pop).
//! While the current or a later stage charges turns, the state is (cell, heading of the last move),
//! which makes the turn penalty exact rather than the sequential planner's best-predecessor
//! approximation. After the last stage the cheapest arrival (ties: lowest state) is backtracked.
//!
//! Deviation from the reference: a source already inside the next stage's goal arrives at zero cost
//! (as in the sequential planner) instead of having to move out and back in; this keeps every
//! sequential plan inside the global search space, so the global cost is never higher.
//!
//! The sequential plan is computed first as the incumbent and returned whenever the global search
//! fails, and when it is not worse than the global plan.

use crate::astar::AStar;
use crate::compile::{self, CompiledSegment};
use crate::layout::{NO_HEADING, corners_free, turn_table};
use crate::open_list::OpenEntry;
use crate::problem::PlanProblem;
use crate::route::{
    PlanStatus, PlannedRoute, PlannedSegment, PlannedStage, append_path, path_length_m,
};
use crate::sequential::{self, SegmentCache};
use m2rc_stdlib::grid::Cell;
use std::collections::{BinaryHeap, HashMap};

const SOURCE: u8 = 255;
const SQRT2: f64 = std::f64::consts::SQRT_2;
const STEP: [f64; 8] = [1.0, 1.0, 1.0, 1.0, SQRT2, SQRT2, SQRT2, SQRT2];

/// One layer of the search: which segment and stage it plans, its state width, and how to walk back.
struct Layer {
    segment: usize,
    stage: usize,
    /// 9 when headings are part of the state, else 1.
    width: usize,
    /// Per state: the predecessor's heading (width 9) or the move taken (width 1); `SOURCE` for
    /// sources. Meaningful only for states reached in this layer.
    pred: Vec<u8>,
    /// Source state of this layer -> arrival state of the previous layer it came from.
    from: HashMap<usize, usize>,
    /// Cumulative cost of each source.
    source_cost: HashMap<usize, f64>,
    expansions: u64,
}

/// Plans `p` with the exact global planner (sequential incumbent as fallback).
pub fn plan_global(p: &PlanProblem) -> PlannedRoute {
    let prep = match compile::prepare(p) {
        Ok(prep) => prep,
        Err(f) => return PlannedRoute::failed("global", &p.profile.name, p.start, f),
    };
    let mut unlimited = p.clone();
    unlimited.profile.max_expansions = 0;
    let mut cache = SegmentCache::new(p.segments.len());
    let mut incumbent = sequential::run(
        &unlimited,
        &prep,
        &mut cache,
        &mut AStar::new(),
        "global",
        false,
    );
    for i in 0..p.segments.len() {
        if cache.get(p, &prep, i).is_err() {
            return incumbent;
        }
    }
    let l = prep.layout;
    if !l.contains(p.start) || !prep.traversable[l.idx(p.start)] {
        return incumbent;
    }
    let Some(compiled) = (0..p.segments.len())
        .map(|i| cache.peek(i))
        .collect::<Option<Vec<&CompiledSegment>>>()
    else {
        return incumbent;
    };
    match search(p, &prep, &compiled) {
        // Equal costs up to summation order count as a tie, which the global plan wins.
        Some(global)
            if !incumbent.is_success()
                || global.cost <= incumbent.cost + 1e-9 * incumbent.cost.abs().max(1.0) =>
        {
            global
        }
        _ => {
            incumbent.planner = "global".into();
            incumbent
        }
    }
}

/// The global search alone, without the sequential incumbent: `None` when it finds no route.
/// For tests and ablations that need to see the search's own result.
pub fn search_only(p: &PlanProblem) -> Option<PlannedRoute> {
    let prep = compile::prepare(p).ok()?;
    let l = prep.layout;
    if !l.contains(p.start) || !prep.traversable[l.idx(p.start)] {
        return None;
    }
    let segs: Vec<CompiledSegment> = (0..p.segments.len())
        .map(|i| compile::compile_segment(p, &prep, i, &p.segments[i]))
        .collect::<Result<_, _>>()
        .ok()?;
    let refs: Vec<&CompiledSegment> = segs.iter().collect();
    search(p, &prep, &refs)
}

fn search(
    p: &PlanProblem,
    prep: &compile::Prepared,
    segs: &[&CompiledSegment],
) -> Option<PlannedRoute> {
    let l = prep.layout;
    let len = l.len();
    let offs = l.offsets();
    let w = l.w as isize;
    let turn = turn_table();
    let smooth_w = p.profile.smoothness_weight;
    let order: Vec<(usize, usize)> = segs
        .iter()
        .enumerate()
        .flat_map(|(si, s)| (0..s.stages.len()).map(move |ti| (si, ti)))
        .collect();
    if order.is_empty() {
        return None;
    }
    // Headings matter from the first stage to the last one that charges turns.
    let last_smooth = order
        .iter()
        .rposition(|&(si, ti)| smooth_w > 0.0 && segs[si].stages[ti].smooth.is_some());
    let width_of = |k: usize| {
        if last_smooth.is_some_and(|ls| k <= ls) {
            9
        } else {
            1
        }
    };

    let mut dist = vec![f64::INFINITY; len * 9];
    let mut tag = vec![0u32; len * 9];
    let mut generation = 0u32;
    let mut layers: Vec<Layer> = Vec::new();
    let start = l.idx(p.start);
    // Sources of the first layer: the start with no heading.
    let w0 = width_of(0);
    let mut sources: Vec<(usize, f64, usize)> = vec![(
        if w0 == 9 {
            start * 9 + NO_HEADING as usize
        } else {
            start
        },
        0.0,
        usize::MAX,
    )];
    let mut arrivals: Vec<(usize, f64)> = Vec::new();
    for (k, &(si, ti)) in order.iter().enumerate() {
        let seg = segs[si];
        let st = &seg.stages[ti];
        let corner_grid: &[bool] = if p.profile.avoid_corners {
            &seg.allowed
        } else {
            &prep.traversable
        };
        let width = width_of(k);
        let smooth = if smooth_w > 0.0 {
            st.smooth.as_deref()
        } else {
            None
        };
        let mut layer = Layer {
            segment: si,
            stage: ti,
            width,
            pred: vec![SOURCE; len * width],
            from: HashMap::new(),
            source_cost: HashMap::new(),
            expansions: 0,
        };
        generation += 2;
        let (open, closed) = (generation, generation + 1);
        let mut heap = BinaryHeap::new();
        let mut seq = 0u64;
        sources.sort_by_key(|s| s.0);
        for &(state, cost, prev) in &sources {
            let cell = state / width;
            if !seg.allowed[cell] {
                continue;
            }
            if tag[state] != open || cost < dist[state] {
                tag[state] = open;
                dist[state] = cost;
                layer.from.insert(state, prev);
                layer.source_cost.insert(state, cost);
                heap.push(OpenEntry {
                    key: cost,
                    seq,
                    state: state as u32,
                });
                seq += 1;
            }
        }
        arrivals.clear();
        while let Some(OpenEntry { state, .. }) = heap.pop() {
            let s = state as usize;
            if tag[s] == closed {
                continue;
            }
            tag[s] = closed;
            let (u, h) = (
                s / width,
                if width == 9 {
                    s % 9
                } else {
                    NO_HEADING as usize
                },
            );
            if st.goal[u] {
                arrivals.push((s, dist[s]));
                continue;
            }
            layer.expansions += 1;
            let du = dist[s];
            for m in 0..8 {
                let v = (u as isize + offs[m]) as usize;
                if !seg.allowed[v] {
                    continue;
                }
                if !corners_free(corner_grid, u, m, w as usize) {
                    continue;
                }
                let mut c = du + STEP[m];
                if let Some(phi) = seg.phi.as_deref() {
                    c += phi[v];
                }
                if let Some(mask) = smooth
                    && (mask[u] || mask[v])
                {
                    c += smooth_w * turn[h][m];
                }
                let t = if width == 9 { v * 9 + m } else { v };
                if tag[t] == closed {
                    continue;
                }
                if tag[t] != open || c < dist[t] {
                    tag[t] = open;
                    dist[t] = c;
                    layer.pred[t] = if width == 9 { h as u8 } else { m as u8 };
                    heap.push(OpenEntry {
                        key: c,
                        seq,
                        state: t as u32,
                    });
                    seq += 1;
                }
            }
        }
        layers.push(layer);
        if arrivals.is_empty() {
            return None;
        }
        // Sources of the next layer.
        let next_width = width_of(k + 1);
        sources.clear();
        if next_width == width {
            sources.extend(arrivals.iter().map(|&(s, c)| (s, c, s)));
        } else {
            // 9 -> 1: keep the cheapest heading per cell (ties: lowest heading).
            let mut best: HashMap<usize, (f64, usize)> = HashMap::new();
            for &(s, c) in &arrivals {
                let cell = s / 9;
                let e = best.entry(cell).or_insert((c, s));
                if c < e.0 || (c == e.0 && s < e.1) {
                    *e = (c, s);
                }
            }
            sources.extend(best.into_iter().map(|(cell, (c, s))| (cell, c, s)));
        }
    }
    // Cheapest final arrival, ties by state.
    let &(mut state, total) = arrivals
        .iter()
        .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))?;
    // Backtrack layer by layer.
    let mut stage_paths: Vec<(Vec<Cell>, f64, f64)> = Vec::new(); // (path, arrival cost, source cost)
    let mut arrival_cost = total;
    for layer in layers.iter().rev() {
        let width = layer.width;
        let mut cells = Vec::new();
        let mut s = state;
        loop {
            let v = s / width;
            cells.push(l.cell(v));
            if layer.pred[s] == SOURCE && layer.from.contains_key(&s) {
                break;
            }
            let b = layer.pred[s];
            if width == 9 {
                let m = s % 9;
                let u = (v as isize - offs[m]) as usize;
                s = u * 9 + b as usize;
            } else {
                let u = (v as isize - offs[b as usize]) as usize;
                s = u;
            }
        }
        cells.reverse();
        let source_cost = *layer.source_cost.get(&s)?;
        stage_paths.push((cells, arrival_cost, source_cost));
        arrival_cost = source_cost;
        state = *layer.from.get(&s)?;
    }
    stage_paths.reverse();
    // Assemble the route.
    let mut segments: Vec<PlannedSegment> = Vec::new();
    let mut trajectory = vec![p.start];
    for (layer, (cells, arr, src)) in layers.iter().zip(&stage_paths) {
        if segments.last().is_none_or(|s| s.index != layer.segment) {
            segments.push(PlannedSegment {
                index: layer.segment,
                status: PlanStatus::Success,
                path: vec![cells[0]],
                length_m: 0.0,
                cost: 0.0,
                expansions: 0,
                stages: Vec::new(),
            });
        }
        let seg = segments.last_mut()?;
        append_path(&mut seg.path, cells);
        seg.cost += arr - src;
        seg.expansions += layer.expansions;
        let st = &segs[layer.segment].stages[layer.stage];
        seg.stages.push(PlannedStage {
            role: st.role,
            origin: st.origin,
            endpoint: *cells.last()?,
            cost: arr - src,
            expansions: layer.expansions,
        });
    }
    for seg in &mut segments {
        seg.length_m = path_length_m(&seg.path, p.resolution);
        append_path(&mut trajectory, &seg.path);
    }
    Some(PlannedRoute {
        planner: "global".into(),
        profile: p.profile.name.clone(),
        status: PlanStatus::Success,
        length_m: path_length_m(&trajectory, p.resolution),
        trajectory,
        cost: total,
        expansions: layers.iter().map(|x| x.expansions).sum(),
        segments,
        failure: None,
    })
}
