//! Near preferences: an object off the reference route that a legal detour can approach.
//!
//! Witnesses: legal routes of the leg through the free floor [`BAND_M`] from the object (inside
//! the scope room), then on to the destination, each at most [`NEAR_MAX_DETOUR_M`] longer than
//! the leg's shortest route (a thing near the way, not across the house); up to [`WITNESSES`],
//! through band cells apart, since the shortest detour only touches the band and another within
//! the bound may stay near the object longer. The evaluator's Near is the mean distance over the
//! scored waypoints in R, and a preference is kept in one of two forms:
//! - **room**: R is the scope room; kept when the reference route keeps at least
//!   [`NEAR_MIN_SHORTEST_M`] + [`NEAR_MIN_GAIN_M`] away on average and some witness is
//!   [`NEAR_MIN_GAIN_M`] closer;
//! - **passing** ("stay close to the lamp as you pass it"): R is the room's floor within
//!   [`PASSING_WITHIN_M`] of the object, which the reference route must cross
//!   ([`PASSING_MIN_WAYPOINTS`]); kept when the reference route keeps at least
//!   [`NEAR_MIN_SHORTEST_M`] + [`PASSING_MIN_GAIN_M`] away there on average and some witness is
//!   [`PASSING_MIN_GAIN_M`] closer. The gold program scopes it to the room all the same: a
//!   scope of the area itself would make the preference's cost push routes out of the area.

use super::{LegCtx, ScopeRoom, in_room, mean_distance};
use crate::suite::generate::Scene;
use crate::suite::plan::{Pref, SoftPlan};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::Target;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;

pub const NEAR_MIN_GAIN_M: f64 = 1.0;
pub const NEAR_MIN_SHORTEST_M: f64 = 0.6;
/// The witness may be at most this much longer than the leg's shortest legal route, m.
pub const NEAR_MAX_DETOUR_M: f64 = 1.0;
/// The witness passes through the floor this far from the object, m: close, yet outside the
/// 0.75 m the Clearance metric asks of every route, so the witness does not buy Near with
/// Clearance.
pub const BAND_M: (f64, f64) = (0.75, 1.25);
/// R of a passing preference: the floor within this distance of the object, m.
pub const PASSING_WITHIN_M: f64 = 2.5;
pub const PASSING_MIN_GAIN_M: f64 = 1.0;
/// Reference-route waypoints a passing preference's R must hold.
pub const PASSING_MIN_WAYPOINTS: usize = 20;
/// Witnesses tried per candidate (through band cells at least `WITNESS_SPREAD_M` apart).
pub const WITNESSES: usize = 12;
/// Candidates tested per placement (a detour is two distance-field look-ups per band cell).
const TRIES: usize = 30;

impl<'a> Scene<'a> {
    pub(crate) fn place_near(
        &self,
        rng: &mut ChaCha8Rng,
        leg: &LegCtx<'_>,
        scope: &ScopeRoom,
    ) -> Option<SoftPlan> {
        let ix = &self.ix;
        let res = ix.resolution();
        let mut pool = self.subjects(leg, scope.room);
        pool.shuffle(rng);
        let mut tries = 0;
        for o in pool {
            let fp = ix.object(o).footprint.as_slice();
            let line = super::outline(fp);
            // Cells of the room about as close as the passing form's R (the exact R, the
            // compiler's `area_near`, is built only for a preference that is kept).
            let near_enough = |c: &Cell| {
                ix.room_at(*c) == scope.room
                    && c.nearest_dist(&line) * res <= PASSING_WITHIN_M + res
            };
            let d_room = mean_distance(&scope.window, &[fp]) * res;
            let ref_near: Vec<Cell> = scope.window.iter().copied().filter(near_enough).collect();
            let room_ok = d_room >= NEAR_MIN_SHORTEST_M + NEAR_MIN_GAIN_M;
            let area_ok = ref_near.len() >= PASSING_MIN_WAYPOINTS
                && mean_distance(&ref_near, &[fp]) * res
                    >= NEAR_MIN_SHORTEST_M + PASSING_MIN_GAIN_M;
            if !room_ok && !area_ok {
                continue;
            }
            let via = self.band(leg, &[o], Some(scope.room), BAND_M.0, BAND_M.1);
            if via.is_empty() {
                continue;
            }
            tries += 1;
            if tries > TRIES {
                break;
            }
            let witnesses = self.detours_via(leg, &via, NEAR_MAX_DETOUR_M, WITNESSES);
            // The passing form's exact R and the reference route's Near in it, built once.
            let mut passing: Option<(Vec<usize>, f64)> = None;
            let region = witnesses.iter().find_map(|witness| {
                if room_ok
                    && d_room - mean_distance(&in_room(ix, witness, scope.room), &[fp]) * res
                        >= NEAR_MIN_GAIN_M
                {
                    return Some((ix.room_free_cells(scope.room), false));
                }
                if !area_ok {
                    return None;
                }
                let in_area = |area: &[usize], route: &[Cell]| -> Vec<Cell> {
                    route
                        .iter()
                        .copied()
                        .filter(|&c| area.binary_search(&ix.free.index(c)).is_ok())
                        .collect()
                };
                let (area, d_area) = passing.get_or_insert_with(|| {
                    let area = self.passing_area(o, scope.room);
                    let reference = in_area(&area, &scope.window);
                    let d = if reference.len() >= PASSING_MIN_WAYPOINTS {
                        mean_distance(&reference, &[fp]) * res
                    } else {
                        f64::NEG_INFINITY
                    };
                    (area, d)
                });
                (*d_area >= NEAR_MIN_SHORTEST_M + PASSING_MIN_GAIN_M
                    && *d_area - mean_distance(&in_area(area, witness), &[fp]) * res
                        >= PASSING_MIN_GAIN_M)
                    .then(|| (area.clone(), true))
            });
            if let Some((region, passing)) = region
                && let Some(subject) = self.subject(rng, o, scope.room)
            {
                return Some(SoftPlan {
                    pref: Pref::Near(subject),
                    room: scope.room,
                    scope: scope.scope.clone(),
                    region,
                    passing,
                });
            }
        }
        None
    }

    /// Free cells of `room` within [`PASSING_WITHIN_M`] of object `o` (grid indices, ascending).
    fn passing_area(&self, o: u32, room: u32) -> Vec<usize> {
        let ix = &self.ix;
        let mut area: Vec<usize> = self
            .q
            .area_near(Target::Object(ix.object(o)), PASSING_WITHIN_M)
            .into_iter()
            .filter(|&c| ix.free.passable(c) && ix.room_at(c) == room)
            .map(|c| ix.free.index(c))
            .collect();
        area.sort_unstable();
        area
    }
}
