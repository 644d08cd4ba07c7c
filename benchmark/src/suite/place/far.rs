//! Far preferences: an object the reference route passes that a legal route can keep clear of.
//!
//! Witness: the shortest legal route of the leg that keeps out of the disc of radius
//! (reference mean distance + [`FAR_MIN_GAIN_M`]) around the object. Kept when the witness's
//! evaluator Far (mean distance over its scored waypoints in R) is at least [`FAR_MIN_GAIN_M`]
//! above the reference route's. Objects by the destination or the leg's start are never
//! subjects (every route passes them). A quarter of far preferences are about every window of
//! the room ("stay away from the windows"), a quantified set.

use super::{LegCtx, ScopeRoom, in_room, mean_distance};
use crate::suite::generate::Scene;
use crate::suite::plan::{Pref, SoftPlan, Subject};
use rand::Rng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;

pub const FAR_MIN_GAIN_M: f64 = 0.6;
/// The reference route passes the object at most this far on average, metres.
pub const FAR_MAX_SHORTEST_M: f64 = 2.5;
const TRIES: usize = 8;

impl<'a> Scene<'a> {
    pub(crate) fn place_far(
        &self,
        rng: &mut ChaCha8Rng,
        leg: &LegCtx<'_>,
        scope: &ScopeRoom,
    ) -> Option<SoftPlan> {
        let ix = &self.ix;
        let mut pool: Vec<Vec<u32>> = self
            .subjects(leg, scope.room)
            .into_iter()
            .map(|o| vec![o])
            .collect();
        pool.shuffle(rng);
        // Windows of the room, as one quantified subject: "the windows" are all of the room's,
        // so every one of them must be fit to be a subject.
        let windows: Vec<u32> = ix
            .fixtures_of("window")
            .iter()
            .copied()
            .filter(|&w| ix.object_room(w) == Some(scope.room))
            .collect();
        let fit = |w: &u32| {
            !leg.mentioned.objects.borrow().contains(w)
                && ix
                    .object(*w)
                    .footprint
                    .iter()
                    .all(|&c| !leg.keep_off[ix.free.index(c)])
        };
        if windows.len() >= 2 && windows.iter().all(fit) && rng.random_bool(0.25) {
            pool.insert(0, windows);
        }
        let mut tries = 0;
        for ids in pool {
            let Some(gain) = self.far_gain(leg, scope, &ids, &mut tries) else {
                continue;
            };
            if gain < FAR_MIN_GAIN_M {
                continue;
            }
            let subject = if ids.len() > 1 {
                Subject::All {
                    cat: "window".into(),
                    ids,
                }
            } else {
                match self.subject(rng, ids[0], scope.room) {
                    Some(s) => s,
                    None => continue,
                }
            };
            return Some(SoftPlan {
                pref: Pref::Far(subject),
                room: scope.room,
                scope: scope.scope.clone(),
                region: ix.room_free_cells(scope.room),
                passing: false,
            });
        }
        None
    }

    /// Far(witness) − Far(reference) in metres for the subject `ids`, when testable.
    fn far_gain(
        &self,
        leg: &LegCtx<'_>,
        scope: &ScopeRoom,
        ids: &[u32],
        tries: &mut usize,
    ) -> Option<f64> {
        let ix = &self.ix;
        let res = ix.resolution();
        let fps: Vec<&[m2rc_stdlib::grid::Cell]> = ids
            .iter()
            .map(|&o| ix.object(o).footprint.as_slice())
            .collect();
        let d_ref = mean_distance(&scope.window, &fps) * res;
        if d_ref > FAR_MAX_SHORTEST_M {
            return None;
        }
        *tries += 1;
        if *tries > TRIES {
            return None;
        }
        let keep_out = self.band(leg, ids, None, 0.0, d_ref + FAR_MIN_GAIN_M);
        if keep_out.contains(&ix.free.index(leg.view.from)) {
            return None;
        }
        let mask = leg.mask.without(keep_out);
        let (route, _) = mask.shortest_to(leg.view.from, &leg.goal_mask)?;
        let witness = self.scored(leg, route);
        let w = in_room(ix, &witness, scope.room);
        if w.is_empty() {
            return None;
        }
        Some(mean_distance(&w, &fps) * res - d_ref)
    }
}
