//! Near preferences: an object off the reference route that a legal detour can approach.
//!
//! Witness: the shortest legal route of the leg through the free floor 0.3–0.7 m from the
//! object (inside R), then on to the destination. Kept when the witness's evaluator Near (mean
//! distance over its scored waypoints in R) is at least [`NEAR_MIN_GAIN_M`] below the reference
//! route's, and the reference route keeps at least [`NEAR_MIN_SHORTEST_M`] away on average.

use super::{LegCtx, ScopeRoom, in_room, mean_distance};
use crate::suite::generate::Scene;
use crate::suite::plan::{Pref, SoftPlan};
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;

pub const NEAR_MIN_GAIN_M: f64 = 0.6;
pub const NEAR_MIN_SHORTEST_M: f64 = 1.0;
/// Candidates tested per placement (each costs two shortest-path searches).
const TRIES: usize = 6;

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
            let d_ref = mean_distance(&scope.window, &[fp]) * res;
            if d_ref < NEAR_MIN_SHORTEST_M + NEAR_MIN_GAIN_M {
                continue;
            }
            let via = self.band(leg, &[o], Some(scope.room), 0.3, 0.7);
            if !via.iter().any(|&b| b) {
                continue;
            }
            tries += 1;
            if tries > TRIES {
                break;
            }
            let Some(witness) = self.detour_via(leg, &via) else {
                continue;
            };
            let d_wit = mean_distance(&in_room(ix, &witness, scope.room), &[fp]) * res;
            if d_ref - d_wit >= NEAR_MIN_GAIN_M
                && let Some(subject) = self.subject(rng, o, scope.room)
            {
                return Some(SoftPlan {
                    pref: Pref::Near(subject),
                    room: scope.room,
                    scope: scope.scope.clone(),
                    region: ix.room_free_cells(scope.room),
                });
            }
        }
        None
    }
}
