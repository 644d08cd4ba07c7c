//! Path-shape preferences, each with a canonical reference trajectory:
//!
//! * **circle** an object that has a free ring: the language's `circle` (radius half the
//!   footprint's larger extent + 0.45 m about its centroid), at least 90 % of the ring free and
//!   in the object's room, clear of the destination and of the leg's start; R is the area within
//!   the loop's reach plus the DTW slack, and the reference route must cross R (so it is scored
//!   on its shape, not on its absence);
//! * **patrol** the start room (first leg only) along its walls, clockwise or counterclockwise,
//!   ending at the doorway the reference route leaves by: the language's `patrol`;
//! * **follow the walls** of the start room once around: the language's `follow_wall`;
//! * **weave past** two or three objects of a room in order: the language's `through`
//!   ([`super::through`]).
//!
//! Wall loops use the waypoints of the stdlib's `loop_waypoints` (the compiler's own), joined
//! by shortest paths over the room's free floor.

use super::{LegCtx, ScopeRoom};
use crate::suite::generate::Scene;
use crate::suite::plan::{Pref, RoomScope, ShapeKind, ShapePlan, SoftPlan};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::{MapQuery, Target, WaypointShape, loop_waypoints};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// Distance from an object's outline to its circle, metres (the language's `circle`).
const CIRCLE_OFFSET_M: f64 = 0.45;
/// The evaluator's DTW slack δ, cells: R extends this far beyond the loop.
const LOOP_SLACK_CELLS: f64 = 10.0;
/// Share of the ideal ring that must be free floor of the object's room.
const MIN_FREE_RING: f64 = 0.9;
/// Share of path-shape slots (outside a start-room wall loop) that try `through` first.
const THROUGH_SHARE: f64 = 0.35;
/// The reference route must have this many waypoints in a circle's R.
const MIN_CROSSING: usize = 5;

impl<'a> Scene<'a> {
    pub(crate) fn place_shape(
        &self,
        rng: &mut ChaCha8Rng,
        leg: &LegCtx<'_>,
        scopes: &[ScopeRoom],
    ) -> Option<SoftPlan> {
        let clockwise = rng.random_bool(0.4);
        let through_first = rng.random_bool(THROUGH_SHARE);
        let start = scopes.iter().find(|s| s.scope == RoomScope::Start);
        if let Some(s) = start
            && rng.random_bool(0.5)
        {
            let kind = if rng.random_bool(0.6) {
                ShapeKind::Patrol
            } else {
                ShapeKind::FollowWall
            };
            if let Some(p) = self.wall_loop(leg, s, kind, clockwise) {
                return Some(p);
            }
        }
        if through_first {
            for s in scopes {
                if let Some(p) = self.place_through(rng, leg, s) {
                    return Some(p);
                }
            }
        }
        for s in scopes {
            if let Some(p) = self.circle(rng, leg, s, clockwise) {
                return Some(p);
            }
        }
        None
    }

    fn circle(
        &self,
        rng: &mut ChaCha8Rng,
        leg: &LegCtx<'_>,
        scope: &ScopeRoom,
        clockwise: bool,
    ) -> Option<SoftPlan> {
        let ix = &self.ix;
        let res = ix.resolution();
        let pool = self.floor_subjects(rng, leg, scope.room);
        for o in pool.into_iter().take(12) {
            let (ring, free_share) = self.ring(o, clockwise, leg.view.from);
            if ring.len() < 12
                || free_share < MIN_FREE_RING
                || ring.iter().any(|&c| leg.keep_off[ix.free.index(c)])
            {
                continue;
            }
            let obj = ix.object(o);
            let farthest = ring
                .iter()
                .map(|p| p.nearest_dist(&obj.footprint))
                .fold(0.0, f64::max);
            let within_m = ((farthest + LOOP_SLACK_CELLS) * res / 0.05).ceil() * 0.05;
            let within_m: f64 = format!("{within_m:.2}").parse().unwrap_or(within_m);
            let area: Vec<usize> = self
                .q
                .area_near(Target::Object(obj), within_m)
                .into_iter()
                .filter(|&c| ix.free.passable(c))
                .map(|c| ix.free.index(c))
                .collect();
            let crossing = leg
                .view
                .window
                .iter()
                .filter(|&&c| area.binary_search(&ix.free.index(c)).is_ok())
                .count();
            if crossing < MIN_CROSSING {
                continue;
            }
            let Some(subject) = self.subject(rng, o, scope.room) else {
                continue;
            };
            let desc = match subject {
                crate::suite::plan::Subject::One(_, d) => d,
                _ => None,
            };
            return Some(SoftPlan {
                pref: Pref::Shape(Box::new(ShapePlan {
                    kind: ShapeKind::Circle,
                    object: Some((o, desc)),
                    via: Vec::new(),
                    clockwise,
                    reference: ring,
                    area,
                    within_m,
                })),
                room: scope.room,
                scope: scope.scope.clone(),
                region: Vec::new(),
                passing: false,
            });
        }
        None
    }

    /// A patrol or wall-following loop of the start room.
    fn wall_loop(
        &self,
        leg: &LegCtx<'_>,
        scope: &ScopeRoom,
        kind: ShapeKind,
        clockwise: bool,
    ) -> Option<SoftPlan> {
        let ix = &self.ix;
        let room = scope.room;
        let wps = loop_waypoints(
            &self.q,
            WaypointShape::Walls,
            Target::Room(room),
            Some(room),
            clockwise,
            Some(leg.view.from),
        );
        let mut points: Vec<Cell> = std::iter::once(leg.view.from)
            .chain(wps.iter().filter_map(|d| centre_cell(d)))
            .collect();
        if points.len() < 5 {
            return None;
        }
        if kind == ShapeKind::Patrol {
            let door = self.q.doorway_leaving(&leg.view.window, room)?;
            points.push(centre_cell(&door)?);
        }
        let floor: Vec<usize> = ix.room_free_cells(room);
        let n = ix.map.n();
        let mut pass = vec![false; n * n];
        for &i in &floor {
            pass[i] = leg.mask.passable(ix.cell(i));
        }
        let room_mask = super::super::paths::PassMask::new(n, pass);
        let mut reference: Vec<Cell> = vec![points[0]];
        for w in points.windows(2) {
            let mut goal = vec![false; n * n];
            goal[ix.free.index(w[1])] = true;
            let (seg, _) = room_mask.shortest_to(w[0], &goal)?;
            reference.extend(seg.into_iter().skip(1));
        }
        reference.dedup();
        if reference.len() < 20 {
            return None;
        }
        Some(SoftPlan {
            pref: Pref::Shape(Box::new(ShapePlan {
                kind,
                object: None,
                via: Vec::new(),
                clockwise,
                reference,
                area: floor,
                within_m: 0.0,
            })),
            room,
            scope: RoomScope::Start,
            region: Vec::new(),
            passing: false,
        })
    }

    /// The canonical circling trajectory around an object, as the language defines `circle`
    /// (`docs/semantics.md`), over the free cells of the object's room, starting at the point
    /// nearest where the stage starts and closed; with the share of the ideal ring that is free.
    fn ring(&self, o: u32, clockwise: bool, from: Cell) -> (Vec<Cell>, f64) {
        let ix = &self.ix;
        let obj = ix.object(o);
        let cells: Vec<Cell> = obj.footprint.clone();
        let Some([cr, cc]) = MapQuery::centroid(&cells) else {
            return (Vec::new(), 0.0);
        };
        let (mut r0, mut c0, mut r1, mut c1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
        for c in &cells {
            let (r, k) = (c.row as f64, c.col as f64);
            (r0, c0, r1, c1) = (r0.min(r), c0.min(k), r1.max(r), c1.max(k));
        }
        let radius = (r1 - r0).max(c1 - c0) / 2.0 + CIRCLE_OFFSET_M / ix.resolution();
        let steps = ((std::f64::consts::TAU * radius).ceil() as usize).clamp(16, 720);
        let mut out: Vec<Cell> = Vec::new();
        let mut free = 0usize;
        for s in 0..steps {
            let mut theta = std::f64::consts::TAU * s as f64 / steps as f64;
            if !clockwise {
                theta = -theta;
            }
            let r = (cr + radius * theta.sin()).round();
            let c = (cc + radius * theta.cos()).round();
            if r < 0.0 || c < 0.0 || r >= ix.map.n() as f64 || c >= ix.map.n() as f64 {
                continue;
            }
            let cell = Cell::new(r as u32, c as u32);
            if ix.free.passable(cell) && ix.room_at(cell) == obj.room.unwrap_or(0) {
                free += 1;
                if out.last() != Some(&cell) && out.first() != Some(&cell) {
                    out.push(cell);
                }
            }
        }
        if let Some(first) =
            (0..out.len()).min_by(|&a, &b| out[a].dist(from).total_cmp(&out[b].dist(from)))
        {
            out.rotate_left(first);
        }
        if out.len() > 1 {
            out.push(out[0]);
        }
        (out, free as f64 / steps as f64)
    }
}

/// The cell of a region nearest its centroid.
fn centre_cell(cells: &[Cell]) -> Option<Cell> {
    let [r, c] = MapQuery::centroid(cells)?;
    cells.iter().copied().min_by(|a, b| {
        let d = |x: &Cell| (x.row as f64 - r).hypot(x.col as f64 - c);
        d(a).total_cmp(&d(b)).then(a.cmp(b))
    })
}
