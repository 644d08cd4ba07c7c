//! Destinations: spread across the house (each the farthest of a few candidates from the
//! previous stop, in another room), mostly objects of categories with several instances (so a
//! reference must disambiguate, as the paper's 82 % ambiguity rate says), and sometimes a
//! conditional choice, a corner of a room, or the area between two objects.

use super::generate::{Difficulty, Scene};
use super::plan::{Dest, Stage};
use super::refs::{ObjRef, RoomRef, count_in, from_start, pick_description, room_descriptions};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::{MapQuery, Target};
use rand::Rng;
use rand::seq::{IndexedRandom, SliceRandom};
use rand_chacha::ChaCha8Rng;

/// Minimum spacing of consecutive destinations, cells (Map2Route `TEMPLATE_MIN_DISTANCE`).
const MIN_TARGET_SPACING: f64 = 40.0;
/// Candidates drawn per destination; the farthest from the previous stop is kept.
const SPREAD: usize = 4;
/// A window is accepted as a destination this often: windows line the outer walls, so the
/// farthest-of-[`SPREAD`] draw favours them; two of the 21 real instructions send the robot to
/// a window.
const WINDOW_ACCEPT: f64 = 0.5;
/// A category with a single instance is accepted as a destination this often.
const UNIQUE_ACCEPT: f64 = 0.2;
/// The last destination of a route with two or more is the start again this often ("visit the
/// kitchen and then return to the starting point").
const RETURN_P: f64 = 0.12;
/// A destination is "the other one" of an earlier destination's pair this often, when it can be.
const OTHER_P: f64 = 0.15;
/// A ranked corner must win by this factor.
const CORNER_MARGIN: f64 = 1.25;

impl<'a> Scene<'a> {
    /// `n` destinations from `start`.
    pub(crate) fn destinations(
        &self,
        rng: &mut ChaCha8Rng,
        start: Cell,
        n: usize,
        difficulty: Difficulty,
    ) -> Option<Vec<Stage>> {
        let ix = &self.ix;
        let pool: Vec<u32> = self.targets.keys().copied().collect();
        let mut stages: Vec<Stage> = Vec::new();
        let mut prev: [f64; 2] = [start.row as f64, start.col as f64];
        let mut prev_room = ix.room_at(start);
        let start_i = ix.free.index(start);
        let start_room = prev_room;
        for k in 0..n {
            if k >= 1
                && k + 1 == n
                && prev_room != start_room
                && (prev[0] - start.row as f64).hypot(prev[1] - start.col as f64)
                    > MIN_TARGET_SPACING
                && rng.random_bool(RETURN_P)
                && let Some(stage) = self.region_stage(
                    &super::generate::disc(start, super::generate::START_RADIUS),
                    start_room,
                    Dest::Return,
                    vec![],
                )
            {
                stages.push(stage);
                break;
            }
            if k >= 1
                && rng.random_bool(OTHER_P)
                && let Some(stage) = self.other_of_pair(&stages, prev, prev_room)
            {
                prev = stage.center;
                prev_room = stage.room;
                stages.push(stage);
                continue;
            }
            let mut cands: Vec<u32> = Vec::new();
            for _ in 0..40 {
                let t = *pool.choose(rng)?;
                let (center, _, cells) = &self.targets[&t];
                let cat = &ix.object(t).category;
                if stages.iter().any(|s| s.anchor_objects.contains(&t))
                    || cells.binary_search(&start_i).is_ok()
                    || ix.object(t).room == Some(prev_room)
                    || (prev[0] - center[0]).hypot(prev[1] - center[1]) <= MIN_TARGET_SPACING
                    || (ix.all_of_cat(cat).len() < 2 && !rng.random_bool(UNIQUE_ACCEPT))
                    || (!ix.fixtures_of(cat).is_empty() && !rng.random_bool(WINDOW_ACCEPT))
                {
                    continue;
                }
                cands.push(t);
                if cands.len() >= SPREAD {
                    break;
                }
            }
            let far = |t: &u32| {
                let c = self.targets[t].0;
                (prev[0] - c[0]).hypot(prev[1] - c[1])
            };
            let t = cands
                .iter()
                .copied()
                .max_by(|a, b| far(a).total_cmp(&far(b)).then(b.cmp(a)))?;
            let want = match difficulty {
                Difficulty::Easy => rng.random_range(1..=3u32),
                Difficulty::Hard => rng.random_range(2..=4u32),
            };
            let roll: f64 = rng.random();
            let stage = if roll < 0.06 {
                self.conditional(rng, t)
            } else if roll < 0.12 {
                self.corner(rng, t)
            } else if roll < 0.17 {
                self.between(rng, t)
            } else if roll < 0.23 {
                self.doorway(rng, t)
            } else {
                None
            }
            .or_else(|| {
                let mut descs = self.descriptions[&t].clone();
                if k == 0 && rng.random_bool(0.3) {
                    descs = from_start(ix, t, start, 3);
                    if descs.is_empty() {
                        descs = self.descriptions[&t].clone();
                    }
                }
                let desc = pick_description(&descs, want, rng)?;
                self.object_stage(t, Dest::Object { id: t, desc })
            })?;
            prev = stage.center;
            prev_room = stage.room;
            stages.push(stage);
        }
        Some(stages)
    }

    fn object_stage(&self, t: u32, dest: Dest) -> Option<Stage> {
        let (center, radius, cells) = self.targets.get(&t)?.clone();
        Some(Stage {
            dest,
            anchor_objects: vec![t],
            room: self.ix.object(t).room?,
            goal: cells,
            center,
            radius,
            avoids: vec![],
            softs: vec![],
        })
    }

    /// "If the bedroom has a lamp, go to it; otherwise go to the desk there."
    fn conditional(&self, rng: &mut ChaCha8Rng, t: u32) -> Option<Stage> {
        let ix = &self.ix;
        let room = ix.object(t).room?;
        let rr: RoomRef = room_descriptions(ix, room, 2).choose(rng).cloned()?;
        let cat = ix.object(t).category.clone();
        if count_in(ix, &cat, room) != 1 {
            return None;
        }
        let in_room = |c: &str| ObjRef::InRoom {
            cat: c.to_string(),
            room: rr.clone(),
        };
        let holds = rng.random_bool(0.5);
        let (cond_cat, then_desc, else_desc) = if holds {
            // The condition holds: the `then` object is the destination; the `else` one is
            // another single object of the room.
            let mut others: Vec<&String> = ix
                .objects_by_cat
                .keys()
                .filter(|c| **c != cat && count_in(ix, c, room) == 1)
                .collect();
            others.shuffle(rng);
            let other = others.first()?;
            (cat.clone(), in_room(&cat), in_room(other))
        } else {
            // The condition fails: a category the house has, but not this room.
            let mut absent: Vec<&String> = ix
                .objects_by_cat
                .keys()
                .filter(|c| count_in(ix, c, room) == 0 && ix.of_cat(c).len() >= 2)
                .collect();
            absent.shuffle(rng);
            let c = absent.first()?;
            ((*c).clone(), in_room(c), in_room(&cat))
        };
        let live = if holds { &then_desc } else { &else_desc };
        if !live.is_natural() || live.resolve(ix, None) != [t] {
            return None;
        }
        self.object_stage(
            t,
            Dest::Conditional {
                id: t,
                room: rr,
                cond_cat,
                holds,
                then_desc,
                else_desc,
            },
        )
    }

    /// "The corner of the kitchen nearest the fridge", ranked as the compiler ranks regions.
    fn corner(&self, rng: &mut ChaCha8Rng, t: u32) -> Option<Stage> {
        let ix = &self.ix;
        let room = ix.object(t).room?;
        let room_ref = room_descriptions(ix, room, 1).choose(rng).cloned()?;
        let anchor = self.descriptions[&t]
            .iter()
            .filter(|d| d.depth() <= 2 && d.rooms().is_empty())
            .collect::<Vec<_>>()
            .choose(rng)
            .map(|d| (*d).clone())?;
        let obj = ix.object(t);
        let corners = self.q.corners(room);
        let mut scored: Vec<(f64, usize)> = corners
            .iter()
            .enumerate()
            .filter_map(|(i, c)| {
                self.q
                    .distance_cells(Target::Cells(c), Target::Object(obj))
                    .map(|d| (d, i))
            })
            .collect();
        scored.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let best = match scored.as_slice() {
            [(_, i)] => *i,
            [(d0, i), (d1, _), ..] if *d1 >= CORNER_MARGIN * d0.max(1.0) => *i,
            _ => return None,
        };
        self.region_stage(
            &corners[best],
            room,
            Dest::Corner {
                room,
                room_ref,
                anchor,
            },
            vec![t],
        )
    }

    /// The other member of a pair an earlier destination belongs to (the house has exactly two
    /// of its category), when it is a fit next destination: a target, in another room than the
    /// previous stop, and not next to it.
    fn other_of_pair(&self, stages: &[Stage], prev: [f64; 2], prev_room: u32) -> Option<Stage> {
        let ix = &self.ix;
        stages.iter().enumerate().find_map(|(first, s)| {
            let Dest::Object { id, .. } = &s.dest else {
                return None;
            };
            let cat = &ix.object(*id).category;
            let [a, b] = ix.all_of_cat(cat) else {
                return None;
            };
            let other = if a == id { *b } else { *a };
            let (center, _, _) = self.targets.get(&other)?;
            if ix.object(other).room == Some(prev_room)
                || stages.iter().any(|s| s.anchor_objects.contains(&other))
                || (prev[0] - center[0]).hypot(prev[1] - center[1]) <= MIN_TARGET_SPACING
            {
                return None;
            }
            self.object_stage(
                other,
                Dest::Other {
                    id: other,
                    cat: cat.clone(),
                    first,
                },
            )
        })
    }

    /// "The doorway between the kitchen and the hall": a door of `t`'s room that is the only
    /// passage to the room behind it, both rooms nameable and of different categories (no two
    /// rooms of one category in one phrase).
    fn doorway(&self, rng: &mut ChaCha8Rng, t: u32) -> Option<Stage> {
        let ix = &self.ix;
        let room = ix.object(t).room?;
        let mut doors: Vec<&m2rc_stdlib::query::Passage> = self
            .q
            .doorways(room)
            .into_iter()
            .filter(|p| p.kind == m2rc_stdlib::query::PassageKind::Door)
            .filter(|p| self.q.doorways_between(p.rooms.0, p.rooms.1).len() == 1)
            .filter(|p| {
                ix.room_category(p.rooms.0) != ix.room_category(p.rooms.1)
                    && p.rooms.0 != 0
                    && p.rooms.1 != 0
            })
            .collect();
        doors.shuffle(rng);
        let door = doors.first()?;
        let other = if door.rooms.0 == room {
            door.rooms.1
        } else {
            door.rooms.0
        };
        let a = room_descriptions(ix, room, 1).choose(rng).cloned()?;
        let b = room_descriptions(ix, other, 1).choose(rng).cloned()?;
        let home = self.q.room_of(Target::Cells(&door.cells))?;
        self.region_stage(&door.cells, home, Dest::Doorway { a, b }, vec![])
    }

    /// "The small area between the counter and the fridge" (`area_between`).
    fn between(&self, rng: &mut ChaCha8Rng, t: u32) -> Option<Stage> {
        let ix = &self.ix;
        let res = ix.resolution();
        let room = ix.object(t).room?;
        let oa = ix.object(t);
        // "The small area between the dining table and its nearest window" (windows too).
        let mut partners: Vec<u32> = ix
            .objects_by_cat
            .values()
            .chain(ix.fixtures_by_cat.values())
            .flatten()
            .copied()
            .filter(|&b| {
                let ob = ix.object(b);
                b != t
                    && ob.room == Some(room)
                    && ob.category != oa.category
                    && ob.parent.is_none()
                    && self.descriptions.contains_key(&b)
                    && (0.5..=2.5).contains(&(ix.footprint_distance(t, b) * res))
            })
            .collect();
        partners.shuffle(rng);
        let b = *partners.first()?;
        let (da, db) = self.pair_descriptions(rng, t, b, 2)?;
        let cells = self
            .q
            .corridor(Target::Object(oa), Target::Object(ix.object(b)));
        self.region_stage(&cells, room, Dest::Between { a: da, b: db }, vec![t, b])
    }

    fn region_stage(
        &self,
        cells: &[Cell],
        room: u32,
        dest: Dest,
        anchors: Vec<u32>,
    ) -> Option<Stage> {
        let ix = &self.ix;
        let mut goal: Vec<usize> = cells
            .iter()
            .copied()
            .filter(|&c| {
                ix.free.passable(c) && self.reach.get(ix.free.index(c)).copied().unwrap_or(false)
            })
            .map(|c| ix.free.index(c))
            .collect();
        goal.sort_unstable();
        goal.dedup();
        if goal.len() < 4 {
            return None;
        }
        // The compiler's `room()` of the region must be the stage's room.
        if self.q.room_of(Target::Cells(cells)) != Some(room) {
            return None;
        }
        let pts: Vec<Cell> = goal.iter().map(|&i| ix.cell(i)).collect();
        let center = MapQuery::centroid(&pts)?;
        let radius = pts
            .iter()
            .map(|c| (c.row as f64 - center[0]).hypot(c.col as f64 - center[1]))
            .fold(1.0, f64::max);
        Some(Stage {
            dest,
            anchor_objects: anchors,
            room,
            goal,
            center: [round3(center[0]), round3(center[1])],
            radius: round3(radius),
            avoids: vec![],
            softs: vec![],
        })
    }
}

fn round3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}
