//! Preference placement, neutral toward every method.
//!
//! A preference is placed on a leg of the reference route (the shortest legal route) only when
//! the geometry says it can be met clearly better than that route meets it, judged with the
//! generator's own tools (distance fields over the leg's legal free space and the plain
//! shortest-path search of [`super::paths`]), never with a planner or cost model that is being
//! benchmarked. For each kind ([`near`], [`far`], [`relative`], [`shape`], [`through`]) a *witness* route is
//! built (a legal detour that serves the preference) and compared with the reference route, in
//! the evaluator's scored window and region R; the preference is kept only when the witness is
//! better by a clear margin. Objects next to the destination (its support, what stands on it,
//! the anchors its description names, anything within 1 m of its must-pass region) and next to
//! where the leg starts are never subjects: every route passes them, so the reference route
//! would fail (far) or trivially meet (near) the preference by construction.
//!
//! R is a room the leg cannot avoid: the destination's room, the start room (first leg), the
//! room just before the destination's (when that room is the only way in), or another room
//! every legal route of the leg crosses; never the previous destination's room, where the
//! scored window holds the walk out of its goal band.

pub mod far;
pub mod near;
pub mod relative;
pub mod shape;
pub mod through;

use super::generate::Scene;
use super::paths::PassMask;
use super::plan::{RoomScope, Stage};
use super::refs::{ObjRef, room_descriptions};
use m2rc_stdlib::grid::Cell;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;
use std::cell::RefCell;
use std::collections::HashSet;

/// R must hold this many waypoints of the reference route's scored window.
pub const MIN_ROOM_WAYPOINTS: usize = 20;
/// Via cells of the witnesses [`Scene::detours_via`] offers keep this far apart, m.
pub const WITNESS_SPREAD_M: f64 = 0.5;
/// Subjects keep this far from the destination's must-pass region and from the leg's start, m.
pub const KEEP_OFF_GOAL_M: f64 = 1.0;

/// What the evaluator will see of one stage on the reference route: where the stage starts and
/// the active window of a stage-scoped preference (C.5: from the first waypoint in the previous
/// must-pass region to the first waypoint in this one).
pub struct LegView {
    pub from: Cell,
    pub window: Vec<Cell>,
    /// The room of the previous destination (none for the first stage).
    pub prev_room: Option<u32>,
}

/// One leg, as preferences for it are placed.
pub struct LegCtx<'s> {
    pub k: usize,
    pub stage: &'s Stage,
    pub view: &'s LegView,
    pub start_room: u32,
    /// The leg's legal free space (its active avoids removed).
    pub mask: PassMask,
    pub goal_mask: Vec<bool>,
    /// `mask` as a grid, and the legal travel distance from every cell to the goal over it
    /// (one distance field per leg, so a witness is two cheap walks).
    pub grid: m2rc_stdlib::grid::Grid<bool>,
    /// Built on first use (only detours need it).
    pub to_goal: std::cell::OnceCell<m2rc_stdlib::query::TravelField>,
    /// The legal travel distance from the leg's start, built on first use: with `to_goal` it
    /// gives every cell's detour (from → cell → goal, minus from → goal) without a search.
    pub from_start: std::cell::OnceCell<m2rc_stdlib::query::TravelField>,
    /// Cells within [`KEEP_OFF_GOAL_M`] of the goal region or of the leg's start.
    pub keep_off: Vec<bool>,
    pub mentioned: &'s Mentioned,
}

/// What the episode already talks about, which a preference subject must not be.
pub struct Mentioned {
    /// Object categories the episode's destinations name ([`named_categories`]).
    pub categories: HashSet<String>,
    /// Objects earlier preferences of the episode are about: each is described once.
    pub objects: RefCell<HashSet<u32>>,
}

/// A room R a preference of the leg may be measured in, with the reference window inside it.
pub struct ScopeRoom {
    pub room: u32,
    pub scope: RoomScope,
    pub window: Vec<Cell>,
}

impl<'a> Scene<'a> {
    pub(crate) fn leg_ctx<'s>(
        &self,
        k: usize,
        stage: &'s Stage,
        view: &'s LegView,
        forbidden: &[usize],
        start_room: u32,
        mentioned: &'s Mentioned,
    ) -> LegCtx<'s> {
        let ix = &self.ix;
        let n = ix.map.n();
        let mask = ix.free.without(forbidden.iter().copied());
        let goal_mask = ix.mask(&stage.goal);
        let by = (KEEP_OFF_GOAL_M / ix.resolution()).ceil() as i64;
        let mut keep_off = dilate(n, &stage.goal, by);
        let from = [ix.free.index(view.from)];
        for (i, b) in dilate(n, &from, by).into_iter().enumerate() {
            keep_off[i] |= b;
        }
        let grid = mask.to_grid();
        let to_goal = std::cell::OnceCell::new();
        LegCtx {
            k,
            stage,
            view,
            start_room,
            mask,
            goal_mask,
            grid,
            to_goal,
            from_start: std::cell::OnceCell::new(),
            keep_off,
            mentioned,
        }
    }

    /// The rooms R of a leg, in a fixed order (destination, start, before, crossed).
    pub(crate) fn scope_rooms(&self, leg: &LegCtx<'_>) -> Vec<ScopeRoom> {
        let ix = &self.ix;
        let dest = leg.stage.room;
        let mut seq: Vec<u32> = Vec::new();
        for &c in &leg.view.window {
            let r = ix.room_at(c);
            if r != 0 && seq.last() != Some(&r) {
                seq.push(r);
            }
        }
        let in_room = |room: u32| -> Vec<Cell> {
            leg.view
                .window
                .iter()
                .copied()
                .filter(|&c| ix.room_at(c) == room)
                .collect()
        };
        let mut out = Vec::new();
        let push = |room: u32, scope: RoomScope, out: &mut Vec<ScopeRoom>| {
            let window = in_room(room);
            if leg.view.prev_room != Some(room)
                && window.len() >= MIN_ROOM_WAYPOINTS
                && out.iter().all(|s: &ScopeRoom| s.room != room)
            {
                out.push(ScopeRoom {
                    room,
                    scope,
                    window,
                });
            }
        };
        push(dest, RoomScope::Destination, &mut out);
        if leg.k == 0 && leg.start_room != 0 && leg.start_room != dest {
            push(leg.start_room, RoomScope::Start, &mut out);
        }
        // The room right before the destination's, when it is the only way in.
        if let Some(pos) = seq.iter().rposition(|&r| r == dest)
            && pos > 0
        {
            let before = seq[pos - 1];
            if self.q.adjacent_rooms(dest) == [before] && before != leg.start_room {
                push(before, RoomScope::Before, &mut out);
            }
        }
        for &room in seq.iter() {
            if room == dest || room == leg.start_room || out.iter().any(|s| s.room == room) {
                continue;
            }
            if !self.unavoidable(leg, room) {
                continue;
            }
            let Some(rr) = room_descriptions(ix, room, 2).into_iter().next() else {
                continue;
            };
            push(room, RoomScope::Crossed(rr), &mut out);
        }
        out
    }

    /// Whether every legal route of the leg crosses `room`.
    fn unavoidable(&self, leg: &LegCtx<'_>, room: u32) -> bool {
        let ix = &self.ix;
        let cells = ix.room_cells.get(&room).cloned().unwrap_or_default();
        if ix.room_at(leg.view.from) == room {
            return true;
        }
        let without = leg.mask.without(cells);
        let reach = without.reachable_from(leg.view.from);
        !leg.stage
            .goal
            .iter()
            .any(|&i| reach.get(i).copied().unwrap_or(false))
    }

    /// Objects of `room` that may be the subject of a preference on this leg: never of a
    /// category a destination of the episode names, in any room. "Go to the spray bottle that
    /// is not on a shelf" and, on another leg, "stay closer to the spray bottle than to the mug"
    /// reads as the same spray bottle, whatever room the second is scoped to. Nor of an object
    /// an earlier preference is about: "stay close to the trash can", then on another leg "stay
    /// as close to the bin as you can", reads as two things.
    pub(crate) fn subjects(&self, leg: &LegCtx<'_>, room: u32) -> Vec<u32> {
        let ix = &self.ix;
        let stage = leg.stage;
        let used = leg.mentioned.objects.borrow();
        let mut out: Vec<u32> = Vec::new();
        for ids in ix.objects_by_cat.values() {
            for &o in ids {
                let obj = ix.object(o);
                if ix.object_room(o) != Some(room) || stage.anchor_objects.contains(&o) {
                    continue;
                }
                // Not the destination's support, nor what stands on it.
                let related = stage.anchor_objects.iter().any(|&d| {
                    obj.parent.is_some_and(|p| p.id == d)
                        || ix.object(d).parent.is_some_and(|p| p.id == o)
                });
                if related || leg.mentioned.categories.contains(&obj.category) || used.contains(&o)
                {
                    continue;
                }
                if obj
                    .footprint
                    .iter()
                    .any(|&c| leg.keep_off[ix.free.index(c)])
                {
                    continue;
                }
                out.push(o);
            }
        }
        out
    }

    /// The floor-standing subjects of `room`, shuffled: a path shape goes around or past an
    /// object on the floor, never one standing on furniture.
    pub(crate) fn floor_subjects(
        &self,
        rng: &mut ChaCha8Rng,
        leg: &LegCtx<'_>,
        room: u32,
    ) -> Vec<u32> {
        let mut pool: Vec<u32> = self
            .subjects(leg, room)
            .into_iter()
            .filter(|&o| self.ix.object(o).parent.is_none())
            .collect();
        pool.shuffle(rng);
        pool
    }

    /// The first `n` cells of a route up to (and including) its first cell in the leg's goal:
    /// the part the evaluator scores.
    pub(crate) fn scored(&self, leg: &LegCtx<'_>, mut route: Vec<Cell>) -> Vec<Cell> {
        if let Some(end) = route
            .iter()
            .position(|&c| leg.goal_mask[self.ix.free.index(c)])
        {
            route.truncate(end + 1);
        }
        route
    }

    /// The shortest legal witness route of the leg through a cell of `via` (from the leg's start
    /// to that cell, then on to the goal); `None` when it is more than `max_detour_m` longer than
    /// the leg's shortest legal route. A preference whose witness needs a long detour is one a
    /// person would not ask for in passing ("keep near the lamp" of a lamp across the room), and
    /// one no route-length-aware planner would take.
    pub(crate) fn detour_via(
        &self,
        leg: &LegCtx<'_>,
        via: &[usize],
        max_detour_m: f64,
    ) -> Option<Vec<Cell>> {
        self.detours_via(leg, via, max_detour_m, 1).pop()
    }

    /// Up to `k` witnesses of [`Self::detour_via`]'s kind through via cells at least
    /// [`WITNESS_SPREAD_M`] apart, shortest first: the shortest detour to a band need not be the
    /// one that stays near the object longest, and a preference is kept when some legal route
    /// within the detour bound meets it.
    pub(crate) fn detours_via(
        &self,
        leg: &LegCtx<'_>,
        via: &[usize],
        max_detour_m: f64,
        k: usize,
    ) -> Vec<Vec<Cell>> {
        let ix = &self.ix;
        let res = ix.resolution();
        let to_goal = leg.to_goal.get_or_init(|| {
            let goal: Vec<Cell> = leg.stage.goal.iter().map(|&i| ix.cell(i)).collect();
            m2rc_stdlib::query::TravelField::new(&leg.grid, &goal, res)
        });
        let from = leg
            .from_start
            .get_or_init(|| m2rc_stdlib::query::TravelField::new(&leg.grid, &[leg.view.from], res));
        let direct = to_goal.cells_to(leg.view.from);
        // Via cells within the bound, shortest route first (the lowest index on ties).
        let mut ranked: Vec<(f64, Cell)> = via
            .iter()
            .map(|&i| {
                let c = ix.cell(i);
                (from.cells_to(c) + to_goal.cells_to(c), c)
            })
            .filter(|(d, _)| d.is_finite() && (d - direct) * res <= max_detour_m)
            .collect();
        ranked.sort_by(|a, b| a.0.total_cmp(&b.0));
        let spread = (WITNESS_SPREAD_M / res).powi(2);
        let mut mids: Vec<Cell> = Vec::new();
        for (_, c) in ranked {
            if mids.len() == k {
                break;
            }
            if mids.iter().all(|m| m.dist_sq(c) as f64 >= spread) {
                mids.push(c);
            }
        }
        mids.into_iter()
            .filter_map(|mid| {
                let mut route = from.path_to(&leg.grid, mid)?;
                let mut second = to_goal.path_to(&leg.grid, mid)?;
                second.reverse();
                route.extend(second.into_iter().skip(1));
                Some(self.scored(leg, route))
            })
            .collect()
    }

    /// Free cells (of `room` when given), legal on the leg, whose distance to the footprint of
    /// `ids` lies in [lo, hi] metres, as ascending grid indices (a band is a thin ring, so a list
    /// keeps its users off a scan of the whole grid).
    pub(crate) fn band(
        &self,
        leg: &LegCtx<'_>,
        ids: &[u32],
        room: Option<u32>,
        lo: f64,
        hi: f64,
    ) -> Vec<usize> {
        let ix = &self.ix;
        let n = ix.map.n();
        let res = ix.resolution();
        let mut seen = vec![false; n * n];
        let mut out = Vec::new();
        let (lo, hi) = (lo / res, hi / res);
        for &o in ids {
            let fp = outline(&ix.object(o).footprint);
            let (mut r0, mut c0, mut r1, mut c1) = (u32::MAX, u32::MAX, 0, 0);
            for f in &fp {
                (r0, c0, r1, c1) = (r0.min(f.row), c0.min(f.col), r1.max(f.row), c1.max(f.col));
            }
            let pad = hi.ceil() as u32;
            for r in r0.saturating_sub(pad)..=(r1 + pad).min(n as u32 - 1) {
                for c in c0.saturating_sub(pad)..=(c1 + pad).min(n as u32 - 1) {
                    let cell = Cell::new(r, c);
                    let i = ix.free.index(cell);
                    if seen[i]
                        || !leg.mask.passable(cell)
                        || room.is_some_and(|r| ix.room_at(cell) != r)
                    {
                        continue;
                    }
                    if (lo..=hi).contains(&cell.nearest_dist(&fp)) {
                        seen[i] = true;
                        out.push(i);
                    }
                }
            }
        }
        out.sort_unstable();
        out
    }
}

/// Object categories the destinations of an episode name: each destination's own category and
/// those its description names (anchors, supports), none of which may be a preference subject.
pub fn named_categories(ix: &super::index::MapIndex<'_>, stages: &[Stage]) -> HashSet<String> {
    let mut out = HashSet::new();
    for stage in stages {
        out.extend(stage_cats(stage));
        for &o in &stage.anchor_objects {
            out.insert(ix.object(o).category.clone());
        }
        if let super::plan::Dest::Other { cat, .. } = &stage.dest {
            out.insert(cat.clone());
        }
    }
    out
}

/// Categories the destination's description names (its anchors and parents).
fn stage_cats(stage: &Stage) -> HashSet<String> {
    use super::plan::Dest;
    let descs: Vec<&ObjRef> = match &stage.dest {
        Dest::Object { desc, .. } => vec![desc],
        Dest::Conditional {
            then_desc,
            else_desc,
            ..
        } => vec![then_desc, else_desc],
        Dest::Corner { anchor, .. } => vec![anchor],
        Dest::Between { a, b } => vec![a, b],
        Dest::Return | Dest::Doorway { .. } | Dest::Other { .. } => vec![],
    };
    descs
        .into_iter()
        .flat_map(|d| d.object_cats().into_iter().map(str::to_string))
        .collect()
}

/// The footprint cells with a 4-neighbour outside it (distances to a footprint are distances to
/// its outline from outside).
pub fn outline(fp: &[Cell]) -> Vec<Cell> {
    let set: HashSet<(u32, u32)> = fp.iter().map(|c| (c.row, c.col)).collect();
    fp.iter()
        .copied()
        .filter(|c| {
            let (r, k) = (c.row, c.col);
            r == 0
                || k == 0
                || !set.contains(&(r - 1, k))
                || !set.contains(&(r + 1, k))
                || !set.contains(&(r, k - 1))
                || !set.contains(&(r, k + 1))
        })
        .collect()
}

/// Mean distance of `points` to the union of `footprints`, cells (the evaluator's Near / Far
/// raw value before the resolution).
pub fn mean_distance(points: &[Cell], footprints: &[&[Cell]]) -> f64 {
    if points.is_empty() {
        return f64::INFINITY;
    }
    let line: Vec<Cell> = footprints.iter().flat_map(|f| outline(f)).collect();
    let sum: f64 = points.iter().map(|p| p.nearest_dist(&line)).sum();
    sum / points.len() as f64
}

/// The cells of `route` in `room`.
pub fn in_room(ix: &super::index::MapIndex<'_>, route: &[Cell], room: u32) -> Vec<Cell> {
    route
        .iter()
        .copied()
        .filter(|&c| ix.room_at(c) == room)
        .collect()
}

/// Cells within Chebyshev distance `by` of any cell in `cells`.
pub fn dilate(n: usize, cells: &[usize], by: i64) -> Vec<bool> {
    let mut out = vec![false; n * n];
    for &i in cells {
        let (r, c) = ((i / n) as i64, (i % n) as i64);
        for dr in -by..=by {
            for dc in -by..=by {
                let (rr, cc) = (r + dr, c + dc);
                if rr >= 0 && cc >= 0 && (rr as usize) < n && (cc as usize) < n {
                    out[rr as usize * n + cc as usize] = true;
                }
            }
        }
    }
    out
}
