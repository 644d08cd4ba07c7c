//! Ordered-waypoint path shapes: "weave past the sofa, then the armchair, as you cross the
//! living room", the language's `through`.
//!
//! Two or three objects of a room R the leg cannot avoid, each standing clear in the room (the
//! free floor within the language's 0.5 m reach of it lies wholly in R) and well off the
//! reference route, so the shortest route does not pass by them anyway. The canonical trajectory
//! enters R where the reference route does, reaches each waypoint region in turn by the shortest
//! path over R's legal floor, and leaves where the reference route leaves; of the orders of the
//! objects, the shortest is the one a person would say. The preference is kept only when that
//! trajectory is a bounded detour and the reference route's own nDTW against it is low: a route
//! that weaves scores well, the shortest route does not, by construction of the geometry alone.

use super::{LegCtx, ScopeRoom};
use crate::metrics::ndtw::ndtw;
use crate::suite::generate::Scene;
use crate::suite::paths::PassMask;
use crate::suite::plan::{Pref, ShapeKind, ShapePlan, SoftPlan, Subject};
use m2rc_compiler::eval::THROUGH_REACH_M as REACH_M;
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::Target;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// Each object keeps at least this far from the reference route, m.
const OFF_ROUTE_M: f64 = 1.5;
/// The objects keep at least this far from each other, m.
const SPREAD_M: f64 = 1.5;
/// The canonical trajectory is at most this much longer than the reference route's walk
/// through R, m.
const MAX_DETOUR_M: f64 = 8.0;
/// The reference route's nDTW against the canonical trajectory may be at most this.
const MAX_REFERENCE_NDTW: f64 = 0.5;
/// Candidate objects looked at per room.
const POOL: usize = 16;
/// Object sets tried per room.
const TRIES: usize = 4;

/// An object that may be a waypoint, with its waypoint region (grid indices, sorted).
struct Candidate {
    object: u32,
    region: Vec<usize>,
}

impl<'a> Scene<'a> {
    pub(crate) fn place_through(
        &self,
        rng: &mut ChaCha8Rng,
        leg: &LegCtx<'_>,
        scope: &ScopeRoom,
    ) -> Option<SoftPlan> {
        let ix = &self.ix;
        let res = ix.resolution();
        let (Some(&entry), Some(&exit)) = (scope.window.first(), scope.window.last()) else {
            return None;
        };
        let n = ix.map.n();
        let floor = ix.room_free_cells(scope.room);
        let mut pass = vec![false; n * n];
        for &i in &floor {
            pass[i] = leg.mask.passable(ix.cell(i));
        }
        let room_mask = PassMask::new(n, pass);
        let pool = self.floor_subjects(rng, leg, scope.room);
        let mut cands: Vec<Candidate> = Vec::new();
        for o in pool.into_iter().take(POOL) {
            let obj = ix.object(o);
            let off = scope
                .window
                .iter()
                .map(|c| c.nearest_dist(&obj.footprint))
                .fold(f64::INFINITY, f64::min)
                * res;
            if off < OFF_ROUTE_M {
                continue;
            }
            let cells: Vec<Cell> = self
                .q
                .area_near(Target::Object(obj), REACH_M)
                .into_iter()
                .filter(|&c| ix.free.passable(c))
                .collect();
            let clear = !cells.is_empty()
                && cells.iter().all(|&c| {
                    ix.room_at(c) == scope.room
                        && room_mask.passable(c)
                        && !leg.keep_off[ix.free.index(c)]
                });
            if clear {
                let mut region: Vec<usize> = cells.iter().map(|&c| ix.free.index(c)).collect();
                region.sort_unstable();
                cands.push(Candidate { object: o, region });
            }
        }
        let count = if rng.random_bool(0.3) { 3 } else { 2 };
        let walked = polyline_cells(&scope.window) * res;
        for t in 0..TRIES.min(cands.len()) {
            let chosen = self.spread_set(&cands, t, count);
            if chosen.len() < 2 {
                continue;
            }
            let Some((order, trajectory, len)) = best_order(&room_mask, entry, exit, &chosen)
            else {
                continue;
            };
            if len * res > walked + MAX_DETOUR_M || trajectory.len() < 20 {
                continue;
            }
            let points = |cells: &[Cell]| -> Vec<[f64; 2]> {
                cells.iter().map(|c| [c.row as f64, c.col as f64]).collect()
            };
            if ndtw(&points(&scope.window), &points(&trajectory)).score > MAX_REFERENCE_NDTW {
                continue;
            }
            let mut via: Vec<Subject> = Vec::new();
            for &i in &order {
                via.push(self.subject(rng, chosen[i].object, scope.room)?);
            }
            return Some(SoftPlan {
                pref: Pref::Shape(Box::new(ShapePlan {
                    kind: ShapeKind::Through,
                    object: None,
                    via,
                    clockwise: false,
                    reference: trajectory,
                    area: floor.clone(),
                    within_m: 0.0,
                })),
                room: scope.room,
                scope: scope.scope.clone(),
                region: floor,
                passing: false,
            });
        }
        None
    }

    /// Up to `count` candidates from position `first` on, each at least [`SPREAD_M`] from those
    /// already taken.
    fn spread_set<'c>(
        &self,
        cands: &'c [Candidate],
        first: usize,
        count: usize,
    ) -> Vec<&'c Candidate> {
        let ix = &self.ix;
        let spread = SPREAD_M / ix.resolution();
        let mut out: Vec<&Candidate> = Vec::new();
        for c in cands.iter().skip(first) {
            let fp = &ix.object(c.object).footprint;
            let apart = out.iter().all(|o| {
                fp.iter()
                    .map(|p| p.nearest_dist(&ix.object(o.object).footprint))
                    .fold(f64::INFINITY, f64::min)
                    >= spread
            });
            if apart {
                out.push(c);
                if out.len() == count {
                    break;
                }
            }
        }
        out
    }
}

/// Of every order of the waypoints, the one with the shortest trajectory entry -> each region in
/// turn -> exit over `mask`: (the order, the trajectory, its length in cells).
fn best_order(
    mask: &PassMask,
    entry: Cell,
    exit: Cell,
    chosen: &[&Candidate],
) -> Option<(Vec<usize>, Vec<Cell>, f64)> {
    let n2 = mask.n() * mask.n();
    let mut best: Option<(Vec<usize>, Vec<Cell>, f64)> = None;
    for order in permutations(chosen.len()) {
        let mut goals: Vec<Vec<bool>> = order
            .iter()
            .map(|&i| {
                let mut g = vec![false; n2];
                for &k in &chosen[i].region {
                    g[k] = true;
                }
                g
            })
            .collect();
        let mut end = vec![false; n2];
        end[mask.index(exit)] = true;
        goals.push(end);
        let mut at = entry;
        let mut trajectory = vec![entry];
        let mut total = 0.0;
        let mut ok = true;
        for g in &goals {
            match mask.shortest_to(at, g) {
                Some((seg, len)) => {
                    at = *seg.last().unwrap_or(&at);
                    trajectory.extend(seg.into_iter().skip(1));
                    total += len;
                }
                None => {
                    ok = false;
                    break;
                }
            }
        }
        trajectory.dedup();
        if ok && best.as_ref().is_none_or(|b| total < b.2 - 1e-9) {
            best = Some((order, trajectory, total));
        }
    }
    best
}

/// Every order of `0..k`, lexicographic (k is 2 or 3).
fn permutations(k: usize) -> Vec<Vec<usize>> {
    let mut out: Vec<Vec<usize>> = vec![Vec::new()];
    for _ in 0..k {
        let mut next = Vec::new();
        for p in &out {
            for i in (0..k).filter(|i| !p.contains(i)) {
                let mut q = p.clone();
                q.push(i);
                next.push(q);
            }
        }
        out = next;
    }
    out
}

/// Length of a cell path, in cells.
fn polyline_cells(cells: &[Cell]) -> f64 {
    cells.windows(2).map(|w| w[0].dist(w[1])).sum()
}

#[cfg(test)]
mod tests {
    use super::permutations;

    #[test]
    fn permutations_are_every_order_once() {
        let p = permutations(3);
        assert_eq!(p.len(), 6);
        let mut sorted = p.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted, p, "lexicographic and distinct");
        assert_eq!(permutations(2), vec![vec![0, 1], vec![1, 0]]);
    }
}
