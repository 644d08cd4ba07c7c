//! A failed plan, explained: what the picture of it shows (the avoided regions, the unreachable
//! target, where the failing stage starts, the doorways that cut the way) and one sentence that
//! says which avoided region cuts the way and through which doorway ("bedroom_3's only door opens
//! into the avoided kitchen_1").
//!
//! The explanation works on the map, not on the planner's search: the free cells outside every
//! active avoid region split into the part the stage can reach from its start and the part around
//! its target. The smaller part is the one shut in; the doorways (map passages) leading out of it
//! that an avoid region covers are the cut. It lives here, beside the pipeline, because it needs
//! the RouteIR (labels, scopes), the map (rooms, doorways) and the planner's failure.

use m2rc_compiler::ir::{ConstraintKind, PlaceKind, RouteIr};
use m2rc_planner::{Origin, PlanFailure};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use m2rc_stdlib::query::{MapQuery, PassageKind};
use m2rc_stdlib::render::{Overlay, RegionKind, RenderOptions};
use std::collections::{BTreeSet, VecDeque};

/// A plan that failed, with everything its picture and its diagnostic need.
#[derive(Clone, Debug)]
pub struct FailedPlan {
    pub ir: RouteIr,
    pub failure: PlanFailure,
    /// The route planned before the failing stage (just the start when the first stage failed).
    pub route_so_far: Vec<Cell>,
    /// The RouteIR stage that failed (0-based), when the failure belongs to one.
    pub stage: Option<usize>,
    /// Where the failing stage starts.
    pub from: Option<Cell>,
    /// The planned part that could not be reached (destination, must-pass place, waypoint).
    pub target: Option<(String, Vec<Cell>)>,
    /// The avoid regions active in the failing stage, each restricted to its spatial scope.
    pub avoids: Vec<(String, Vec<Cell>)>,
    /// The doorways that cut the way, each as its cells and what it is.
    pub blocking: Vec<(String, Vec<Cell>)>,
    /// Which avoided region cuts the way and through which doorway, when the map says.
    pub why: Option<String>,
}

impl FailedPlan {
    /// Collects the picture's parts and the explanation of `failure` for `ir` on `map`.
    pub fn new(
        ir: &RouteIr,
        failure: &PlanFailure,
        route_so_far: Vec<Cell>,
        q: &MapQuery<'_>,
        goal_radius_m: f64,
    ) -> FailedPlan {
        let stage = failure.segment();
        let from = match failure {
            PlanFailure::Unreachable { from, .. }
            | PlanFailure::UnreachableUnderAvoids { from, .. } => Some(*from),
            PlanFailure::StartInForbidden { start, .. } | PlanFailure::StartBlocked { start } => {
                Some(*start)
            }
            _ => route_so_far.last().copied(),
        };
        let target = failure.target().and_then(|o| target_of(ir, o));
        let avoids = stage.map_or_else(Vec::new, |s| active_avoids(ir, s));
        let mut plan = FailedPlan {
            ir: ir.clone(),
            failure: failure.clone(),
            route_so_far,
            stage,
            from,
            target,
            avoids,
            blocking: Vec::new(),
            why: None,
        };
        if let (PlanFailure::UnreachableUnderAvoids { .. }, Some(from), Some((_, cells))) =
            (failure, from, &plan.target)
        {
            let radius = if q.map().resolution() > 0.0 {
                (goal_radius_m / q.map().resolution()).ceil().max(1.0) as usize
            } else {
                1
            };
            let cut = Cut::find(q, &plan.avoids, from, cells, radius);
            if let Some(cut) = cut {
                let (why, blocking) = cut.explain(q, ir, &plan, failure);
                plan.why = Some(why);
                plan.blocking = blocking;
            }
        }
        plan
    }
}

/// The label and cells of the planned part an origin names.
fn target_of(ir: &RouteIr, o: Origin) -> Option<(String, Vec<Cell>)> {
    let place = match o {
        Origin::Target { stage } => &ir.stages.get(stage)?.target,
        Origin::Pass { stage, index } => &ir.stages.get(stage)?.passes.get(index)?.place,
        Origin::Constraint { index, part } => match &ir.constraints.get(index)?.kind {
            ConstraintKind::PathShape { waypoints, .. } => waypoints.get(part)?,
            _ => return None,
        },
        Origin::Unknown => return None,
    };
    Some((place.label.clone(), place.cells.cells().to_vec()))
}

/// The avoid regions active in `stage`, each inside its spatial scope.
fn active_avoids(ir: &RouteIr, stage: usize) -> Vec<(String, Vec<Cell>)> {
    ir.active(stage)
        .filter_map(|c| match &c.kind {
            ConstraintKind::Avoid { place } => {
                let cells: Vec<Cell> = match &c.spatial_scope {
                    Some(s) => place
                        .cells
                        .cells()
                        .iter()
                        .copied()
                        .filter(|&x| s.cells.contains(x))
                        .collect(),
                    None => place.cells.cells().to_vec(),
                };
                Some((place.label.clone(), cells))
            }
            _ => None,
        })
        .collect()
}

/// The part of the free floor shut in by the avoid regions, and where it touches them.
struct Cut {
    /// Cells of the shut-in part (row-major mask).
    inside: Vec<bool>,
    /// Whether the shut-in part is the start's side (else the target's).
    start_side: bool,
    /// Avoid index per cell (`usize::MAX` outside every avoid region).
    avoided: Vec<usize>,
}

impl Cut {
    fn find(
        q: &MapQuery<'_>,
        avoids: &[(String, Vec<Cell>)],
        from: Cell,
        target: &[Cell],
        radius: usize,
    ) -> Option<Cut> {
        let map = q.map();
        let n = map.n();
        let mut avoided = vec![usize::MAX; n * n];
        for (i, (_, cells)) in avoids.iter().enumerate() {
            for c in cells {
                if let Some(k) = idx(n, *c)
                    && avoided[k] == usize::MAX
                {
                    avoided[k] = i;
                }
            }
        }
        let open: Vec<bool> = (0..n * n)
            .map(|k| avoided[k] == usize::MAX && map.is_free(cell(n, k)))
            .collect();
        let start = idx(n, from).filter(|&k| open[k])?;
        let reach_start = flood(n, &open, [start]);
        // The target side: its own open cells, else the open cells within the goal radius of it
        // (an object's footprint is never free).
        let mut seeds: Vec<usize> = target
            .iter()
            .filter_map(|&c| idx(n, c))
            .filter(|&k| open[k])
            .collect();
        if seeds.is_empty() {
            seeds = near(n, target, radius)
                .into_iter()
                .filter(|&k| open[k])
                .collect();
        }
        if seeds.is_empty() || seeds.iter().any(|&k| reach_start[k]) {
            return None;
        }
        let reach_target = flood(n, &open, seeds);
        let count = |m: &[bool]| m.iter().filter(|x| **x).count();
        let start_side = count(&reach_start) < count(&reach_target);
        Some(Cut {
            inside: if start_side {
                reach_start
            } else {
                reach_target
            },
            start_side,
            avoided,
        })
    }

    /// The sentence and the blocking doorways.
    fn explain(
        &self,
        q: &MapQuery<'_>,
        ir: &RouteIr,
        plan: &FailedPlan,
        failure: &PlanFailure,
    ) -> (String, Vec<(String, Vec<Cell>)>) {
        let map = q.map();
        let n = map.n();
        // Rooms with floor inside the shut-in part, the one the sentence names first.
        let mut rooms: BTreeSet<u32> = BTreeSet::new();
        for (k, _) in self.inside.iter().enumerate().filter(|(_, v)| **v) {
            let r = map.room_at(cell(n, k));
            if r != 0 {
                rooms.insert(r);
            }
        }
        let named = if self.start_side {
            plan.from.map(|c| map.room_at(c)).filter(|r| *r != 0)
        } else {
            target_room(ir, failure, plan, map)
        };
        let mut order: Vec<u32> = named.filter(|r| rooms.contains(r)).into_iter().collect();
        order.extend(rooms.iter().copied().filter(|r| Some(*r) != named));
        let touches = |c: &Cell| {
            let k = idx(n, *c);
            k.is_some_and(|k| self.inside[k]) || neighbours(n, *c).any(|k| self.inside[k])
        };
        let mut items = Vec::new();
        let mut blocking = Vec::new();
        for p in q.passages() {
            let (a, b) = p.rooms;
            let (near_room, far_room) = match (rooms.contains(&a), rooms.contains(&b)) {
                (true, false) => (a, b),
                (false, true) => (b, a),
                _ => continue,
            };
            let Some(avoid) = p
                .cells
                .iter()
                .filter_map(|&c| idx(n, c))
                .map(|k| self.avoided[k])
                .find(|&i| i != usize::MAX)
            else {
                continue;
            };
            if !p.cells.iter().any(touches) {
                continue;
            }
            let label = &plan.avoids[avoid].0;
            let door = match p.kind {
                PassageKind::Door => "door",
                PassageKind::Open => "opening",
            };
            let far = room_label(map, far_room);
            let into_avoided_room = avoided_room(ir, plan.stage, label) == Some(far_room);
            let what = if into_avoided_room {
                format!("the {door} into the avoided {label}")
            } else {
                format!(
                    "the {door} between {} and {far}, inside the avoided {label}",
                    room_label(map, near_room)
                )
            };
            // A passage is a line of cells; widened a little so the picture shows it.
            let shown = near(n, &p.cells, 2)
                .into_iter()
                .map(|k| cell(n, k))
                .collect();
            blocking.push((
                format!("blocked {door}: {} – {far}", room_label(map, near_room)),
                shown,
            ));
            items.push((near_room, what, into_avoided_room, label.clone(), door, far));
        }
        let place = match named.map(|r| room_label(map, r)) {
            Some(name) if order.len() == 1 => name,
            _ => listing(order.iter().map(|&r| room_label(map, r)).collect()),
        };
        let side = if self.start_side {
            format!(
                "the start of stage {} is shut in: ",
                plan.stage.map_or(1, |s| s + 1)
            )
        } else {
            String::new()
        };
        let sentence = match items.as_slice() {
            [] => {
                let culprits: Vec<String> = failure
                    .forbids()
                    .iter()
                    .filter_map(|o| match o {
                        Origin::Constraint { index, .. } => ir.constraints.get(*index),
                        _ => None,
                    })
                    .filter_map(|c| match &c.kind {
                        ConstraintKind::Avoid { place } => Some(place.label.clone()),
                        _ => None,
                    })
                    .collect();
                format!(
                    "the avoided {} cut{} every way out of {place}",
                    listing(culprits.clone()),
                    if culprits.len() == 1 { "s" } else { "" }
                )
            }
            [(near_room, _, true, label, door, _)]
                if order.len() == 1 && q.doorways(*near_room).len() == 1 =>
            {
                format!("{place}'s only {door} opens into the avoided {label}")
            }
            [(near_room, _, false, label, door, far)]
                if order.len() == 1 && q.doorways(*near_room).len() == 1 =>
            {
                format!("{place}'s only {door}, to {far}, lies inside the avoided {label}")
            }
            [(_, what, ..)] => format!("the only way out of {place} is {what}"),
            many => format!(
                "every way out of {place} is avoided: {}",
                many.iter()
                    .map(|i| i.1.clone())
                    .collect::<Vec<_>>()
                    .join("; ")
            ),
        };
        (format!("{side}{sentence}"), blocking)
    }
}

/// The room the failing target lies in: the room itself, an object's room, or the room most of
/// a region's cells are in.
fn target_room(
    ir: &RouteIr,
    failure: &PlanFailure,
    plan: &FailedPlan,
    map: &SemanticMap,
) -> Option<u32> {
    if let Some(Origin::Target { stage }) = failure.target() {
        match &ir.stages.get(stage)?.target.kind {
            PlaceKind::Room { id, .. } => return Some(*id),
            PlaceKind::Object { room: Some(r), .. } => return Some(*r),
            _ => {}
        }
    }
    let (_, cells) = plan.target.as_ref()?;
    m2rc_stdlib::map::format::dominant_room(cells, &map.room_layer)
}

/// The room an avoid constraint of `stage` labelled `label` avoids, when it avoids one room.
fn avoided_room(ir: &RouteIr, stage: Option<usize>, label: &str) -> Option<u32> {
    ir.active(stage?).find_map(|c| match &c.kind {
        ConstraintKind::Avoid { place } if place.label == label => match &place.kind {
            PlaceKind::Room { id, .. } => Some(*id),
            _ => None,
        },
        _ => None,
    })
}

fn room_label(map: &SemanticMap, id: u32) -> String {
    match map.room(id) {
        Some(r) => m2rc_compiler::eval::room_name(r),
        None => format!("room {id}"),
    }
}

/// `a`, `a and b`, `a, b and c`.
fn listing(names: Vec<String>) -> String {
    match names.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, init)) => format!("{} and {last}", init.join(", ")),
        None => "the target's surroundings".into(),
    }
}

fn idx(n: usize, c: Cell) -> Option<usize> {
    ((c.row as usize) < n && (c.col as usize) < n).then(|| c.row as usize * n + c.col as usize)
}

fn cell(n: usize, k: usize) -> Cell {
    Cell::new((k / n) as u32, (k % n) as u32)
}

/// Indices of the 4-neighbours of `c` inside the grid.
fn neighbours(n: usize, c: Cell) -> impl Iterator<Item = usize> {
    let (r, k) = (c.row as i64, c.col as i64);
    [(r - 1, k), (r + 1, k), (r, k - 1), (r, k + 1)]
        .into_iter()
        .filter(move |&(r, k)| r >= 0 && k >= 0 && (r as usize) < n && (k as usize) < n)
        .map(move |(r, k)| r as usize * n + k as usize)
}

/// The cells 4-connected to `seeds` over `open`. Diagonal steps that cut no corner connect the
/// same cells, so this is the planner's reachability.
fn flood(n: usize, open: &[bool], seeds: impl IntoIterator<Item = usize>) -> Vec<bool> {
    let mut seen = vec![false; n * n];
    let mut queue = VecDeque::new();
    for s in seeds {
        if open[s] && !seen[s] {
            seen[s] = true;
            queue.push_back(s);
        }
    }
    while let Some(k) = queue.pop_front() {
        for m in neighbours(n, cell(n, k)) {
            if open[m] && !seen[m] {
                seen[m] = true;
                queue.push_back(m);
            }
        }
    }
    seen
}

/// Cells within `radius` 8-neighbour steps of `cells` (over every cell of the grid).
fn near(n: usize, cells: &[Cell], radius: usize) -> Vec<usize> {
    let mut dist = std::collections::HashMap::new();
    let mut queue = VecDeque::new();
    for &c in cells {
        if let Some(k) = idx(n, c)
            && dist.insert(k, 0usize).is_none()
        {
            queue.push_back(k);
        }
    }
    while let Some(k) = queue.pop_front() {
        let d = dist[&k];
        if d >= radius {
            continue;
        }
        let c = cell(n, k);
        for dr in -1i64..=1 {
            for dc in -1i64..=1 {
                let (r, q) = (c.row as i64 + dr, c.col as i64 + dc);
                if r < 0 || q < 0 || r as usize >= n || q as usize >= n {
                    continue;
                }
                let m = r as usize * n + q as usize;
                if let std::collections::hash_map::Entry::Vacant(e) = dist.entry(m) {
                    e.insert(d + 1);
                    queue.push_back(m);
                }
            }
        }
    }
    let mut out: Vec<usize> = dist.into_keys().collect();
    out.sort_unstable();
    out
}

impl FailedPlan {
    /// The picture of the failed plan: the avoided regions, the unreachable target, the doorways
    /// that cut the way, the route planned so far, the start, and where the failing stage starts;
    /// the failure and its explanation as the caption.
    pub fn render_options(&self, code: &str) -> RenderOptions {
        let n = self.stage.map_or(1, |s| s + 1);
        let mut overlays = Vec::new();
        for (label, cells) in &self.avoids {
            overlays.push(Overlay::Region {
                cells: cells.clone(),
                kind: RegionKind::Avoid,
                label: Some(format!("avoid {label}")),
            });
        }
        if let Some((label, cells)) = &self.target {
            overlays.push(Overlay::Region {
                cells: cells.clone(),
                kind: RegionKind::Destination,
                label: Some(format!("{n}: {label} (not reached)")),
            });
        }
        for (label, cells) in &self.blocking {
            overlays.push(Overlay::Region {
                cells: cells.clone(),
                kind: RegionKind::Blocked,
                label: Some(label.clone()),
            });
        }
        if self.route_so_far.len() > 1 {
            overlays.push(Overlay::Route {
                cells: self.route_so_far.clone(),
                label: Some(format!("planned before stage {n}")),
                color: None,
            });
        }
        if let Some(&start) = self.route_so_far.first() {
            overlays.push(Overlay::Marker {
                cell: start,
                label: "S".into(),
            });
        }
        if let Some(from) = self.from
            && self.route_so_far.first() != Some(&from)
        {
            overlays.push(Overlay::Marker {
                cell: from,
                label: format!("stage {n} starts here"),
            });
        }
        let mut caption = vec![format!("error[{code}]: {}", self.failure)];
        if let Some(why) = &self.why {
            caption.push(format!("why: {why}"));
        }
        RenderOptions {
            overlays,
            title: Some(format!("{}: stage {n} cannot be planned", self.ir.map_id)),
            caption,
            ..RenderOptions::default()
        }
    }
}
