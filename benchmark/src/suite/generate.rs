//! Episode generation on one scene: destinations with unique descriptions, must-avoid rooms,
//! stage-scoped preferences of the five kinds, and from that one plan the instruction text, the
//! ground-truth annotation (Map2Route instruction JSON) and the gold `.m2r` program.
//!
//! An episode is kept only if its reference route exists: the shortest legal route through the
//! targets that never touches an active must-avoid. Compiler-side validity (unique grounding,
//! HCS = 1 of the gold program's own route) is checked afterwards by `suite::validate`.

use super::index::{MapIndex, category_words};
use super::paths::{Leg, chain_legs};
use super::refs::{
    DescriptionMemo, ObjRef, RoomRef, describe, pick_description, room_descriptions,
};
use super::text::{self, Position};
use crate::episode::{GENERATION_KEY, GOLD_PROGRAM_KEY};
use m2rc_planner::context::MapContext;
use m2rc_planner::{
    Area, CostProfile, Forbid, Origin, PlanProblem, PlannerKind, SegmentSpec, SoftKind, SoftTerm,
    StageRole, StageSpec, Target as PlanTarget,
};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::{MapQuery, Target};
use rand::seq::{IndexedRandom, SliceRandom};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};
use std::collections::BTreeMap;

/// Minimum spacing of consecutive destinations, cells (Map2Route `TEMPLATE_MIN_DISTANCE`).
const MIN_TARGET_SPACING: f64 = 40.0;
/// Radius of the start (record) region, cells.
const START_RADIUS: f64 = 3.0;
const ATTEMPTS: usize = 60;
/// A near candidate is an object the reference route passes at this distance range, metres.
const NEAR_MIN_PASS_M: f64 = 0.6;
const NEAR_MAX_PASS_M: f64 = 3.0;
/// A near object needs this many free cells 0.6-0.9 m from it with nothing closer.
const APPROACH_MIN_M: f64 = 0.6;
const APPROACH_MAX_M: f64 = 0.9;
const APPROACH_MIN_CELLS: usize = 10;
/// A near preference is stated only if the reference cost model, planning the leg with it, comes
/// at least this much closer to the object over R (evaluator's Near, metres) than both the leg
/// it plans without it and the shortest route: a preference that routes ignoring it already
/// satisfy would not tell a method that follows it from one that does not.
const NEAR_MIN_GAIN_M: f64 = 0.15;
/// Near candidates planned per preference slot (each costs two leg plans at most).
const NEAR_PLAN_TRIES: usize = 10;
/// A far object is one the reference route passes within this distance of, metres.
const FAR_MAX_PASS_M: f64 = 1.2;
/// A relative pair is one whose D_B/D_A on the reference route is at most this.
const RELATIVE_MAX_RATIO: f64 = 0.8;
/// Minimum footprint gap between the two objects of a relative preference, metres.
const MIN_SOFT_SPACING_M: f64 = 2.0;
/// Distance from an object's outline to its circle, metres (the language's `circle`).
const CIRCLE_OFFSET_M: f64 = 0.45;
/// The evaluator's DTW slack δ, cells: R extends this far beyond the loop.
const LOOP_SLACK_CELLS: f64 = 10.0;
/// A loop keeps this many cells off the destination's must-pass region.
const LOOP_GOAL_MARGIN: i64 = 6;
/// Share of must-avoids placed on object areas rather than rooms.
const OBJECT_AVOID_SHARE: f64 = 0.5;
/// Width of the "area around an object" that a must-avoid keeps out of, metres.
const AROUND_M: f64 = 0.5;
/// The destination room is a preference's region only if the scored window has this many
/// waypoints in it.
const MIN_ROOM_WAYPOINTS: usize = 20;
/// Fixed timestamp so that a suite is byte-identical from its seed.
const TIMESTAMP: &str = "2026-01-01T00:00:00Z";

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Difficulty {
    Easy,
    Hard,
}

impl Difficulty {
    pub fn as_str(self) -> &'static str {
        match self {
            Difficulty::Easy => "easy",
            Difficulty::Hard => "hard",
        }
    }
}

/// One reference expression in an episode, for the statistics.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RefStat {
    pub role: String,
    pub expression: String,
    pub category: String,
    pub depth: u32,
    pub candidates: usize,
}

/// Generation facts kept in the instruction file under the `m2rc` key (the reference format
/// allows extra keys), so statistics and the difficulty analysis need only the suite.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EpisodeMeta {
    pub references: Vec<RefStat>,
    pub destinations: usize,
    pub must_avoid: usize,
    /// Soft constraints the instruction states (the default clearance entry not counted).
    pub soft: BTreeMap<String, usize>,
    pub rooms_visited: usize,
    pub room_transitions: usize,
    pub reference_route_length_m: f64,
    pub max_depth: u32,
    pub max_candidates: usize,
}

pub struct GeneratedEpisode {
    pub id: u32,
    pub difficulty: Difficulty,
    pub instruction: Value,
    pub meta: EpisodeMeta,
    pub program: String,
    pub reference_route: Vec<Cell>,
}

impl GeneratedEpisode {
    /// Renumbers the episode (the suite numbers kept episodes without gaps).
    pub fn set_id(&mut self, id: u32) {
        self.id = id;
        self.instruction["id"] = json!(id);
        self.instruction["name"] = json!(format!("instruction_{id:06}"));
    }
}

/// Adds the generation record (generator, version, seed, source house, and the statistics
/// facts of [`EpisodeMeta`]) under the episode format's generation key.
pub fn attach_generation(value: &mut Value, seed: u64, house: &str) {
    if let Some(obj) = value.as_object_mut()
        && let Some(Value::Object(generation)) = obj.get_mut(GENERATION_KEY)
    {
        generation.insert("seed".into(), json!(seed));
        generation.insert("house".into(), json!(house));
    }
}

/// A soft preference of the plan, before rendering.
#[derive(Clone, Debug)]
enum Soft {
    Near(u32, ObjRef),
    Far(u32, ObjRef),
    Relative(u32, ObjRef, u32, ObjRef),
    Circle(Box<CircleSoft>),
    Clearance,
}

/// A circling preference with its annotation: the canonical loop and the area R it is measured
/// in (the area near the object that holds the loop, as the gold program's `within` says).
#[derive(Clone, Debug)]
struct CircleSoft {
    object: u32,
    desc: ObjRef,
    clockwise: bool,
    ring: Vec<Cell>,
    area: Vec<Cell>,
    within_m: f64,
}

/// What the evaluator will see of one stage on the reference route: where the stage starts (the
/// previous destination, where the planner starts its loops) and the active trajectory of a
/// stage-scoped preference (C.5: from the first waypoint in the previous must-pass region to the
/// first waypoint in this one).
struct LegView {
    from: Cell,
    window: Vec<Cell>,
    /// The room of the previous destination (none for the first stage). The planner walks on
    /// into that destination's 0.3 m goal band after the evaluator's window has already opened
    /// at its 1 m must-pass region, so in that room the scored window holds an excursion that
    /// no preference of this stage shaped; preferences are not measured there.
    prev_room: Option<u32>,
}

/// One leg of the episode being generated, as a preference for it is chosen.
struct LegCtx<'s> {
    stage: &'s Stage,
    view: &'s LegView,
    /// Cells the leg must not touch (its active avoids), as grid indices.
    forbidden: &'s [usize],
}

impl Soft {
    fn kind(&self) -> &'static str {
        match self {
            Soft::Near(..) => "near",
            Soft::Far(..) => "far",
            Soft::Relative(..) => "relative",
            Soft::Circle(..) => "path_shape",
            Soft::Clearance => "clearance",
        }
    }
}

/// What a must-avoid names: a room, the area around an object, or the area between two objects.
#[derive(Clone, Debug)]
pub enum AvoidPlace {
    Room(RoomRef),
    Around(ObjRef),
    Between(ObjRef, ObjRef),
}

/// A must-avoid with its region: the free cells of the place the gold program's `avoid` resolves
/// to (the room's cells, or the compiler's `area_near` / `area_between` region), which is also
/// the annotated freeform region.
#[derive(Clone, Debug)]
struct Avoid {
    place: AvoidPlace,
    cells: Vec<usize>,
}

impl Avoid {
    fn text(&self, rng: &mut ChaCha8Rng) -> (String, String) {
        match &self.place {
            AvoidPlace::Room(r) => (r.text(rng), r.m2r()),
            AvoidPlace::Around(x) => (
                x.text(rng),
                format!("area_near({}, within: {AROUND_M:.1}m)", x.m2r()),
            ),
            AvoidPlace::Between(a, b) => (
                format!("{} and {}", a.text(rng), b.text(rng)),
                format!("area_between({}, {})", a.m2r(), b.m2r()),
            ),
        }
    }
}

struct Stage {
    target: u32,
    desc: ObjRef,
    room: u32,
    room_desc: Option<RoomRef>,
    avoids: Vec<Avoid>,
    softs: Vec<Soft>,
}

/// Per-scene precomputation shared by all of its episodes.
pub struct Scene<'a> {
    pub ix: MapIndex<'a>,
    /// The compiler's spatial queries, so that annotated areas are the cells the gold program's
    /// places resolve to.
    q: MapQuery<'a>,
    /// Distance to the nearest obstacle (the clearance term's and the evaluator's obstacles),
    /// cells, row-major; empty when the map has no obstacle.
    clearance: Vec<f64>,
    pub map_key: String,
    /// Object id -> (centre, radius, region cells (all), region free reachable cells).
    targets: BTreeMap<u32, ([f64; 2], f64, Vec<usize>)>,
    descriptions: BTreeMap<u32, Vec<ObjRef>>,
    starts: Vec<Cell>,
    /// The planner's view of the map, for testing near preferences against the reference cost
    /// model; `None` when the map cannot be planned on (then no near preference is stated).
    plan_ctx: Option<MapContext>,
}

impl<'a> Scene<'a> {
    pub fn new(ix: MapIndex<'a>, map_key: String) -> Self {
        let map = ix.map;
        // The connected free space the robot lives in: the component of the map's start, else the
        // largest component among room cells.
        let seed_cell = map.start.filter(|&c| ix.free.passable(c)).or_else(|| {
            let mut best: Option<(usize, Cell)> = None;
            for cells in ix.room_cells.values() {
                let free: Vec<usize> = cells
                    .iter()
                    .copied()
                    .filter(|&i| ix.free.passable(ix.cell(i)))
                    .collect();
                if let Some(&first) = free.first()
                    && best.is_none_or(|(n, _)| free.len() > n)
                {
                    best = Some((free.len(), ix.cell(first)));
                }
            }
            best.map(|(_, c)| c)
        });
        let reach = seed_cell
            .map(|c| ix.free.reachable_from(c))
            .unwrap_or_default();
        let reachable = |i: usize| reach.get(i).copied().unwrap_or(false);
        let rooms = map.room_layer.data();
        let starts: Vec<Cell> = (0..reach.len())
            .filter(|&i| reachable(i) && rooms[i] != 0)
            .step_by(7)
            .map(|i| ix.cell(i))
            .collect();
        let mut targets = BTreeMap::new();
        let mut descriptions = BTreeMap::new();
        let mut memo = DescriptionMemo::new();
        for ids in ix.objects_by_cat.values() {
            for &id in ids {
                let Some((center, radius, cells)) = ix.must_pass_region(id) else {
                    continue;
                };
                if !cells.iter().any(|&i| reachable(i)) {
                    continue;
                }
                let descs = describe(&ix, id, 5, &mut memo);
                if descs.is_empty() {
                    continue;
                }
                targets.insert(id, (center, radius, cells));
                descriptions.insert(id, descs);
            }
        }
        let clearance = crate::metrics::map::EvalMap::from_semantic_map(map)
            .clearance_field()
            .map(|g| g.data().to_vec())
            .unwrap_or_default();
        Scene {
            plan_ctx: MapContext::new(map).ok(),
            q: MapQuery::new(ix.map),
            clearance,
            ix,
            map_key,
            targets,
            descriptions,
            starts,
        }
    }

    /// Objects that can be destinations.
    pub fn target_count(&self) -> usize {
        self.targets.len()
    }

    /// Generates episode `id` (1-based within the scene) of the given difficulty.
    pub fn episode(&self, seed: u64, id: u32, difficulty: Difficulty) -> Option<GeneratedEpisode> {
        let mut rng = ChaCha8Rng::seed_from_u64(mix(seed, &self.map_key, id));
        for _ in 0..ATTEMPTS {
            if let Some(ep) = self.try_episode(&mut rng, id, difficulty) {
                return Some(ep);
            }
        }
        None
    }

    fn describable(&self, id: u32, max_depth: u32) -> Vec<&ObjRef> {
        self.descriptions
            .get(&id)
            .map(|d| d.iter().filter(|r| r.depth() <= max_depth).collect())
            .unwrap_or_default()
    }

    fn try_episode(
        &self,
        rng: &mut ChaCha8Rng,
        id: u32,
        difficulty: Difficulty,
    ) -> Option<GeneratedEpisode> {
        let ix = &self.ix;
        let total = match difficulty {
            Difficulty::Easy => rng.random_range(2..=4),
            Difficulty::Hard => rng.random_range(5..=8),
        };
        let destinations = match difficulty {
            Difficulty::Easy => rng.random_range(1..=2usize.min(total)),
            Difficulty::Hard => rng.random_range(2..=4),
        };
        let rest = total - destinations;
        // About the paper's must-avoid rate: 0.19 per Easy and 0.58 per Hard episode.
        let avoid_count = match difficulty {
            Difficulty::Easy => usize::from(rng.random_bool(0.2)),
            Difficulty::Hard => match rng.random_range(0..100) {
                0..50 => 0,
                50..92 => 1,
                _ => 2,
            },
        }
        .min(rest);
        let soft_count = rest - avoid_count;
        let depth_range = match difficulty {
            Difficulty::Easy => 1..=3u32,
            Difficulty::Hard => 2..=5u32,
        };

        let start = *self.starts.choose(rng)?;
        // Destinations.
        let pool: Vec<u32> = self.targets.keys().copied().collect();
        let mut stages: Vec<Stage> = Vec::new();
        let mut last_center: Option<[f64; 2]> = None;
        for _ in 0..destinations {
            let mut picked = None;
            for _ in 0..30 {
                let t = *pool.choose(rng)?;
                let (center, _, cells) = &self.targets[&t];
                if stages.iter().any(|s| s.target == t) || cells.contains(&ix.free.index(start)) {
                    continue;
                }
                if let Some(prev) = last_center
                    && (prev[0] - center[0]).hypot(prev[1] - center[1]) <= MIN_TARGET_SPACING
                {
                    continue;
                }
                picked = Some(t);
                break;
            }
            let t = picked?;
            let want = rng.random_range(depth_range.clone());
            let desc = pick_description(&self.descriptions[&t], want, rng)?;
            let room = ix.object(t).room?;
            let room_desc = room_descriptions(ix, room, 2).choose(rng).cloned();
            last_center = Some(self.targets[&t].0);
            stages.push(Stage {
                target: t,
                desc,
                room,
                room_desc,
                avoids: vec![],
                softs: vec![],
            });
        }

        // Must-avoids: rooms (never a destination's room or the start's room), or object areas
        // (around one object, or between two) away from the start and every destination.
        let start_room = ix.room_at(start);
        let mut global_avoids: Vec<Avoid> = Vec::new();
        let mut avoid_rooms: Vec<u32> = ix
            .map
            .rooms
            .iter()
            .map(|r| r.id)
            .filter(|&r| r != start_room && stages.iter().all(|s| s.room != r))
            .collect();
        avoid_rooms.shuffle(rng);
        for _ in 0..avoid_count {
            let avoid = if rng.random_bool(OBJECT_AVOID_SHARE) {
                match self.object_avoid(rng, start, &stages) {
                    Some(a) => a,
                    None => self.room_avoid(rng, &mut avoid_rooms)?,
                }
            } else {
                self.room_avoid(rng, &mut avoid_rooms)?
            };
            if rng.random_bool(0.5) {
                global_avoids.push(avoid);
            } else {
                let k = rng.random_range(0..stages.len());
                stages[k].avoids.push(avoid);
            }
        }

        // The reference route first: preferences are chosen along it, where the reference cost
        // model can act on them and the natural route does not already satisfy them.
        let route = self.reference_route(start, &stages, &global_avoids)?;
        let views = self.leg_views(start, &stages, &route);
        let forbidden: Vec<Vec<usize>> = (0..stages.len())
            .map(|k| self.stage_forbidden(&stages, &global_avoids, k))
            .collect();
        let mut used_clearance = false;
        for _ in 0..soft_count {
            let mut order: Vec<usize> = (0..stages.len()).collect();
            order.shuffle(rng);
            let soft = order.into_iter().find_map(|k| {
                let leg = LegCtx {
                    stage: &stages[k],
                    view: &views[k],
                    forbidden: &forbidden[k],
                };
                self.soft_for(rng, &leg, &mut used_clearance)
                    .map(|s| (k, s))
            });
            let (k, soft) = soft?;
            stages[k].softs.push(soft);
        }
        Some(self.render(rng, id, difficulty, start, stages, global_avoids, route))
    }

    /// Per stage, the stage start on the reference route and the evaluator's active window.
    fn leg_views(&self, start: Cell, stages: &[Stage], route: &[Cell]) -> Vec<LegView> {
        let ix = &self.ix;
        let start_region: Vec<Cell> = disc(start, START_RADIUS);
        let inside = |k: usize, c: Cell| -> bool {
            if k == 0 {
                start_region.contains(&c)
            } else {
                self.targets[&stages[k - 1].target]
                    .2
                    .binary_search(&ix.free.index(c))
                    .is_ok()
            }
        };
        // First waypoint hit of each must-pass region in order; the cursor stays on the hit.
        let mut hits: Vec<Option<usize>> = Vec::new();
        let mut cursor = 0;
        for k in 0..=stages.len() {
            let hit = (cursor..route.len()).find(|&i| inside(k, route[i]));
            if let Some(h) = hit {
                cursor = h;
            }
            hits.push(hit);
        }
        // Where each leg of the reference route ends (the first cell in its goal).
        let mut at = 0;
        let mut views = Vec::new();
        for k in 0..stages.len() {
            let from = route[at];
            let window = match (hits[k], hits[k + 1]) {
                (Some(f), Some(t)) if t >= f => route[f..=t].to_vec(),
                (Some(f), _) => route[f..].to_vec(),
                (None, Some(t)) => route[..=t].to_vec(),
                (None, None) => route.to_vec(),
            };
            let prev_room = k.checked_sub(1).map(|j| stages[j].room);
            views.push(LegView {
                from,
                window,
                prev_room,
            });
            if let Some(end) = (at..route.len()).find(|&i| inside(k + 1, route[i])) {
                at = end;
            }
        }
        views
    }

    /// A preference for one stage, chosen along the reference route's active window in the
    /// stage's destination room (the region R every object preference is measured in):
    ///
    /// * `near`: an object the natural route passes at 0.6-3 m, with open floor toward it
    ///   ([`Scene::open_approach`]), that the reference cost model actually approaches: the leg
    ///   planned with the preference comes at least 0.15 m closer to it over R than the leg
    ///   planned without it and than the shortest route (the near term, 8 against clearance's
    ///   36 and flat beyond 1.5 m, moves a route only where a small bend brings it in reach);
    /// * `far`: an object the natural route passes within 1.2 m of;
    /// * `relative`: a pair the natural route is closer to the wrong one of (D_B/D_A ≤ 0.8);
    /// * `circle`: a floor-standing object whose loop stays clear of the destination's must-pass
    ///   region (entering it ends the scored window), alone in its leg;
    /// * `clearance` at most once per episode.
    fn soft_for(
        &self,
        rng: &mut ChaCha8Rng,
        leg: &LegCtx<'_>,
        used_clearance: &mut bool,
    ) -> Option<Soft> {
        let ix = &self.ix;
        let (stage, view) = (leg.stage, leg.view);
        // R is the destination room, which every route of the leg must enter: a preference
        // scoped to a room the leg merely may cross would make the planner avoid that room (its
        // soft cost is zero outside the scope). Not when the previous destination lies in the
        // same room, nor when the window has too few waypoints there to measure, and one object
        // preference per leg, so that none is measured against another's pull.
        let w_r: Vec<Cell> = view
            .window
            .iter()
            .copied()
            .filter(|&c| ix.room_at(c) == stage.room)
            .collect();
        let measurable = view.prev_room != Some(stage.room)
            && w_r.len() >= MIN_ROOM_WAYPOINTS
            && stage.softs.iter().all(|s| matches!(s, Soft::Clearance));
        let mut in_room: Vec<u32> = Vec::new();
        if measurable {
            in_room = self
                .descriptions
                .keys()
                .copied()
                .filter(|&o| ix.object(o).room == Some(stage.room) && o != stage.target)
                .collect();
            in_room.shuffle(rng);
        }
        let mut kinds = vec!["near", "far", "relative", "path_shape"];
        let has_circle = stage.softs.iter().any(|s| matches!(s, Soft::Circle(..)));
        kinds.retain(|k| !has_circle && stage.softs.iter().all(|s| s.kind() != *k));
        if !*used_clearance {
            kinds.push("clearance");
        }
        // Tried in a random order weighted toward the paper's mix (near and far about two and a
        // half times as common as relative and path-shape preferences).
        let weight = |k: &&str| match *k {
            "near" | "far" => 3.0,
            "clearance" => 1.5,
            _ => 1.2,
        };
        // Efraimidis-Spirakis: sorting by u^(1/w) draws a weighted order without replacement.
        let mut keyed: Vec<(f64, &str)> = kinds
            .iter()
            .map(|k| (rng.random::<f64>().powf(1.0 / weight(k)), *k))
            .collect();
        keyed.sort_by(|a, b| b.0.total_cmp(&a.0));
        for (_, kind) in keyed {
            if kind == "clearance" {
                *used_clearance = true;
                return Some(Soft::Clearance);
            }
            if measurable && let Some(soft) = self.object_soft(rng, kind, leg, &in_room, &w_r) {
                return Some(soft);
            }
        }
        None
    }

    /// An object preference of `kind` in the leg's destination room (see [`Scene::soft_for`]).
    fn object_soft(
        &self,
        rng: &mut ChaCha8Rng,
        kind: &str,
        leg: &LegCtx<'_>,
        in_room: &[u32],
        w_r: &[Cell],
    ) -> Option<Soft> {
        let ix = &self.ix;
        let (stage, view) = (leg.stage, leg.view);
        let res = ix.resolution();
        let describe = |o: u32, rng: &mut ChaCha8Rng| {
            let d = self.describable(o, 3);
            d.choose(rng).map(|r| (*r).clone())
        };
        let floor = |o: u32| ix.object(o).parent.is_none();
        {
            match kind {
                "near" => {
                    // The leg as the cost model plans it without the preference (clearance on),
                    // planned once, on the first candidate.
                    let mut base: Option<Option<Vec<Cell>>> = None;
                    let candidates = in_room.iter().copied().filter(|&o| {
                        let min = route_distance(w_r, &ix.object(o).footprint).0 * res;
                        (NEAR_MIN_PASS_M..=NEAR_MAX_PASS_M).contains(&min) && self.open_approach(o)
                    });
                    for o in candidates.take(NEAR_PLAN_TRIES) {
                        let Some(without) = base
                            .get_or_insert_with(|| self.planned_window(leg, None))
                            .as_ref()
                        else {
                            break;
                        };
                        let Some(with) = self.planned_window(leg, Some(o)) else {
                            continue;
                        };
                        let fp = &ix.object(o).footprint;
                        let near_m = |window: &[Cell]| {
                            let in_r: Vec<Cell> = window
                                .iter()
                                .copied()
                                .filter(|&c| ix.room_at(c) == stage.room)
                                .collect();
                            (!in_r.is_empty()).then(|| route_distance(&in_r, fp).1 * res)
                        };
                        let shortest = route_distance(w_r, fp).1 * res;
                        if let (Some(b), Some(w)) = (near_m(without), near_m(&with))
                            && b.min(shortest) - w >= NEAR_MIN_GAIN_M
                            && let Some(d) = describe(o, rng)
                        {
                            return Some(Soft::Near(o, d));
                        }
                    }
                }
                "far" => {
                    let pick = in_room.iter().copied().find(|&o| {
                        route_distance(w_r, &ix.object(o).footprint).0 * res <= FAR_MAX_PASS_M
                    });
                    if let Some(o) = pick
                        && let Some(d) = describe(o, rng)
                    {
                        return Some(Soft::Far(o, d));
                    }
                }
                "relative" => {
                    let means: Vec<(u32, f64)> = in_room
                        .iter()
                        .map(|&o| (o, route_distance(w_r, &ix.object(o).footprint).1))
                        .collect();
                    let pair = means.iter().find_map(|&(a, da)| {
                        means
                            .iter()
                            .find(|&&(b, db)| {
                                ix.object(a).category != ix.object(b).category
                                    && da > 1e-6
                                    && db / da <= RELATIVE_MAX_RATIO
                                    && ix.footprint_distance(a, b) * res >= MIN_SOFT_SPACING_M
                            })
                            .map(|&(b, _)| (a, b))
                    });
                    if let Some((a, b)) = pair
                        && let (Some(da), Some(db)) = (describe(a, rng), describe(b, rng))
                    {
                        return Some(Soft::Relative(a, da, b, db));
                    }
                }
                // A loop reshapes the whole leg: alone in it.
                "path_shape" if stage.softs.is_empty() => {
                    let clockwise = rng.random_bool(0.3);
                    let goal = &self.targets[&stage.target].2;
                    let near_goal = dilate(ix.map.n(), goal, LOOP_GOAL_MARGIN);
                    for &o in in_room.iter().filter(|&&o| floor(o)) {
                        let ring = self.ring(o, clockwise, view.from);
                        if ring.len() < 8 || ring.iter().any(|&c| near_goal[ix.free.index(c)]) {
                            continue;
                        }
                        let Some(desc) = describe(o, rng) else {
                            continue;
                        };
                        let obj = ix.object(o);
                        let farthest = ring_extent(&ring, &obj.footprint);
                        // R holds the loop with the evaluator's DTW slack (δ = 10 cells) around it.
                        let within_m = ((farthest + LOOP_SLACK_CELLS) * res / 0.05).ceil() * 0.05;
                        let within_m: f64 = format!("{within_m:.2}").parse().unwrap_or(within_m);
                        let area: Vec<Cell> = self
                            .q
                            .area_near(Target::Object(obj), within_m)
                            .into_iter()
                            .filter(|&c| ix.free.passable(c))
                            .collect();
                        return Some(Soft::Circle(Box::new(CircleSoft {
                            object: o,
                            desc,
                            clockwise,
                            ring,
                            area,
                            within_m,
                        })));
                    }
                }
                _ => {}
            }
        }
        None
    }

    /// The leg as the reference cost model plans it (the oracle's planner and profile, clearance
    /// on) from where the reference route starts the leg, with a near preference for `near` scoped
    /// to the destination room when given; the cells up to the first one in the destination's
    /// must-pass region, where the evaluator's scored window ends.
    fn planned_window(&self, leg: &LegCtx<'_>, near: Option<u32>) -> Option<Vec<Cell>> {
        let ctx = self.plan_ctx.as_ref()?;
        let ix = &self.ix;
        let target = ix.object(leg.stage.target);
        let soft = near
            .map(|o| SoftTerm {
                kind: SoftKind::Near {
                    reference: Area::Cells(ix.object(o).footprint.clone()),
                },
                weight: None,
                scope: Some(Area::Mask(ctx.room_mask(ix.map, leg.stage.room))),
                origin: Origin::Unknown,
            })
            .into_iter()
            .collect();
        let problem = PlanProblem {
            traversable: ctx.traversable.clone(),
            obstacles: Some(ctx.obstacles.clone()),
            resolution: ix.resolution(),
            start: leg.view.from,
            segments: vec![SegmentSpec {
                stages: vec![StageSpec {
                    target: PlanTarget::Object {
                        footprint: target.footprint.clone(),
                        room: target.room.map(|r| Area::Mask(ctx.room_mask(ix.map, r))),
                        center: target.center,
                    },
                    role: StageRole::Destination,
                    smoothness: None,
                    origin: Origin::Unknown,
                }],
                forbidden: vec![Forbid {
                    cells: Area::Cells(leg.forbidden.iter().map(|&i| ix.cell(i)).collect()),
                    origin: Origin::Unknown,
                }],
                soft,
            }],
            profile: CostProfile::reference(),
            map_fields: Some(ctx.fields()),
        };
        let planned = m2rc_planner::plan(&problem, PlannerKind::Sequential);
        if !planned.is_success() {
            return None;
        }
        let goal = &self.targets[&leg.stage.target].2;
        let mut t = planned.trajectory;
        if let Some(end) = t
            .iter()
            .position(|&c| goal.binary_search(&ix.free.index(c)).is_ok())
        {
            t.truncate(end + 1);
        }
        (!t.is_empty()).then_some(t)
    }

    /// Whether a route can come close to `o` without the clearance term pushing it back: the
    /// floor around `o` has room to stand 0.6-0.9 m from it with nothing else closer (other
    /// furniture, such as the chairs around a table, or a wall would keep a planned route off).
    fn open_approach(&self, o: u32) -> bool {
        let ix = &self.ix;
        let res = ix.resolution();
        let fp = &ix.object(o).footprint;
        let dist = |c: Cell| fp.iter().map(|f| c.dist(*f)).fold(f64::INFINITY, f64::min);
        let (lo, hi) = (APPROACH_MIN_M / res, APPROACH_MAX_M / res);
        let (mut r0, mut c0, mut r1, mut c1) = (u32::MAX, u32::MAX, 0, 0);
        for f in fp {
            (r0, c0, r1, c1) = (r0.min(f.row), c0.min(f.col), r1.max(f.row), c1.max(f.col));
        }
        let pad = hi.ceil() as u32;
        let n = ix.map.n() as u32;
        let mut open = 0;
        for r in r0.saturating_sub(pad)..=(r1 + pad).min(n - 1) {
            for c in c0.saturating_sub(pad)..=(c1 + pad).min(n - 1) {
                let cell = Cell::new(r, c);
                if !ix.free.passable(cell) {
                    continue;
                }
                let d = dist(cell);
                let clear = self
                    .clearance
                    .get(ix.free.index(cell))
                    .copied()
                    .unwrap_or(0.0);
                if (lo..=hi).contains(&d) && clear + 1.0 >= d.min(lo) {
                    open += 1;
                }
            }
        }
        open >= APPROACH_MIN_CELLS
    }

    /// The canonical circling trajectory around an object, as the language defines `circle`
    /// (`docs/semantics.md`): a circle about the footprint's centroid of radius half its larger
    /// extent + 0.45 m, turning in the requested direction as seen on the map image (clockwise =
    /// increasing atan2(row, col)), over the free cells of the object's room, starting at the
    /// point nearest where the stage starts and closed.
    fn ring(&self, o: u32, clockwise: bool, from: Cell) -> Vec<Cell> {
        let ix = &self.ix;
        let obj = ix.object(o);
        let cells: Vec<Cell> = obj.footprint.clone();
        let Some([cr, cc]) = MapQuery::centroid(&cells) else {
            return Vec::new();
        };
        let (mut r0, mut c0, mut r1, mut c1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
        for c in &cells {
            let (r, k) = (c.row as f64, c.col as f64);
            (r0, c0, r1, c1) = (r0.min(r), c0.min(k), r1.max(r), c1.max(k));
        }
        let radius = (r1 - r0).max(c1 - c0) / 2.0 + CIRCLE_OFFSET_M / ix.resolution();
        let steps = ((std::f64::consts::TAU * radius).ceil() as usize).clamp(16, 720);
        let mut out: Vec<Cell> = Vec::new();
        for s in 0..steps {
            let mut theta = std::f64::consts::TAU * s as f64 / steps as f64;
            if !clockwise {
                theta = -theta;
            }
            let r = (cr + radius * theta.sin()).round();
            let c = (cc + radius * theta.cos()).round();
            if r < 0.0 || c < 0.0 {
                continue;
            }
            let cell = Cell::new(r as u32, c as u32);
            if ix.free.passable(cell)
                && ix.room_at(cell) == obj.room.unwrap_or(0)
                && out.last() != Some(&cell)
                && out.first() != Some(&cell)
            {
                out.push(cell);
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
        out
    }

    fn room_avoid(&self, rng: &mut ChaCha8Rng, rooms: &mut Vec<u32>) -> Option<Avoid> {
        let room = rooms.pop()?;
        let desc = room_descriptions(&self.ix, room, 2).choose(rng).cloned()?;
        Some(Avoid {
            place: AvoidPlace::Room(desc),
            cells: self.ix.room_free_cells(room),
        })
    }

    /// "Keep out of the area around the dining table" (the compiler's `area_near(x, 0.5 m)`) or
    /// "don't walk between the sofa and the TV" (`area_between`, two objects of one room 0.5-3 m
    /// apart). The region may not touch the start region or any destination's must-pass region,
    /// so that it forbids a way of getting there, never the getting there.
    fn object_avoid(&self, rng: &mut ChaCha8Rng, start: Cell, stages: &[Stage]) -> Option<Avoid> {
        let ix = &self.ix;
        let res = ix.resolution();
        let n = ix.map.n();
        let mut blocked = vec![false; n * n];
        for c in disc(start, START_RADIUS + 2.0) {
            if (c.row as usize) < n && (c.col as usize) < n {
                blocked[ix.free.index(c)] = true;
            }
        }
        for s in stages {
            for (i, b) in dilate(n, &self.targets[&s.target].2, 2)
                .into_iter()
                .enumerate()
            {
                blocked[i] |= b;
            }
        }
        let targets: Vec<u32> = stages.iter().map(|s| s.target).collect();
        let mut pool: Vec<u32> = self
            .descriptions
            .keys()
            .copied()
            .filter(|o| !targets.contains(o) && ix.object(*o).parent.is_none())
            .collect();
        pool.shuffle(rng);
        let describe = |o: u32, rng: &mut ChaCha8Rng| {
            let d = self.describable(o, 2);
            d.choose(rng).map(|r| (*r).clone())
        };
        let region = |cells: Vec<Cell>| -> Option<Vec<usize>> {
            let free: Vec<usize> = cells
                .into_iter()
                .filter(|&c| ix.free.passable(c))
                .map(|c| ix.free.index(c))
                .collect();
            (!free.is_empty() && free.iter().all(|&i| !blocked[i])).then_some(free)
        };
        let between = rng.random_bool(0.5);
        for (i, &a) in pool.iter().enumerate().take(40) {
            let oa = ix.object(a);
            if between {
                let partner = pool[i + 1..].iter().copied().find(|&b| {
                    let ob = ix.object(b);
                    let gap = ix.footprint_distance(a, b) * res;
                    ob.room == oa.room && ob.category != oa.category && (0.5..=3.0).contains(&gap)
                });
                let Some(b) = partner else { continue };
                let cells = self
                    .q
                    .corridor(Target::Object(oa), Target::Object(ix.object(b)));
                if let Some(cells) = region(cells)
                    && let (Some(da), Some(db)) = (describe(a, rng), describe(b, rng))
                {
                    return Some(Avoid {
                        place: AvoidPlace::Between(da, db),
                        cells,
                    });
                }
            } else {
                let cells = self.q.area_near(Target::Object(oa), AROUND_M);
                if let Some(cells) = region(cells)
                    && let Some(d) = describe(a, rng)
                {
                    return Some(Avoid {
                        place: AvoidPlace::Around(d),
                        cells,
                    });
                }
            }
        }
        None
    }

    fn stage_forbidden(&self, stages: &[Stage], global: &[Avoid], k: usize) -> Vec<usize> {
        let ix = &self.ix;
        let mut cells: Vec<usize> = Vec::new();
        for a in global.iter().chain(stages[k].avoids.iter()) {
            cells.extend(a.cells.iter().copied());
        }
        // An avoid of the next leg must not be touched where this leg ends: the evaluator would
        // count it against the next leg (its exit coincides with the goal entry).
        if let Some(next) = stages.get(k + 1) {
            let near_goal = dilate(ix.map.n(), &self.targets[&stages[k].target].2, 2);
            for a in &next.avoids {
                cells.extend(a.cells.iter().copied().filter(|&i| near_goal[i]));
            }
        }
        cells
    }

    fn reference_route(
        &self,
        start: Cell,
        stages: &[Stage],
        global: &[Avoid],
    ) -> Option<Vec<Cell>> {
        let ix = &self.ix;
        let goals: Vec<Vec<bool>> = stages
            .iter()
            .map(|s| ix.mask(&self.targets[&s.target].2))
            .collect();
        let forbidden: Vec<Vec<usize>> = (0..stages.len())
            .map(|k| self.stage_forbidden(stages, global, k))
            .collect();
        // The start itself must be outside every avoid.
        let s = ix.free.index(start);
        if forbidden.iter().any(|f| f.contains(&s)) {
            return None;
        }
        let legs: Vec<Leg<'_>> = goals
            .iter()
            .zip(&forbidden)
            .map(|(g, f)| Leg {
                goal: g,
                forbidden: f,
            })
            .collect();
        chain_legs(&ix.free, start, &legs).map(|(route, _)| route)
    }

    #[allow(clippy::too_many_arguments)]
    fn render(
        &self,
        rng: &mut ChaCha8Rng,
        id: u32,
        difficulty: Difficulty,
        start: Cell,
        stages: Vec<Stage>,
        global_avoids: Vec<Avoid>,
        route: Vec<Cell>,
    ) -> GeneratedEpisode {
        let ix = &self.ix;
        let res = ix.resolution();
        let mut sentences: Vec<String> = Vec::new();
        let mut refs: Vec<RefStat> = Vec::new();
        let mut stat = |role: String, r: &ObjRef, text: &str| {
            refs.push(RefStat {
                role,
                expression: text.to_string(),
                category: r.category().to_string(),
                depth: r.depth(),
                candidates: r.candidates(ix),
            });
        };
        let mut hard: Vec<Value> = Vec::new();
        let mut soft_json: Vec<Value> = Vec::new();
        let mut objects_json: Vec<Value> = Vec::new();
        let mut soft_counts: BTreeMap<String, usize> = BTreeMap::new();
        let mut program_lets: Vec<String> = Vec::new();
        let mut program_route: Vec<String> = Vec::new();

        // Record (start) region.
        let start_cells: Vec<Value> = disc(start, START_RADIUS)
            .into_iter()
            .filter(|&c| ix.free.passable(c))
            .map(|c| json!([c.row, c.col]))
            .collect();
        hard.push(json!({
            "constraint_id": "start", "kind": "must_pass", "shape": "freeform",
            "center": [start.row as f64, start.col as f64], "radius": START_RADIUS,
            "width": 2.0 * START_RADIUS, "height": 2.0 * START_RADIUS, "order": 1, "source": "custom",
            "object_id": null, "scope": global_scope(), "label": "start", "cells": start_cells,
        }));

        let n_stages = stages.len();
        let mut avoid_no = 0usize;
        let mut soft_no = 0usize;
        for (k, stage) in stages.iter().enumerate() {
            let order = k as u32 + 2;
            let obj = ix.object(stage.target);
            let target_text = stage.desc.text(rng);
            stat(format!("destination {}", k + 1), &stage.desc, &target_text);
            let pos = match (n_stages, k) {
                (1, _) => Position::Only,
                (_, 0) => Position::First,
                (n, k) if k + 1 == n => Position::Last,
                _ => Position::Middle,
            };
            sentences.push(text::destination(rng, pos, &target_text));
            let (center, radius, cells) = &self.targets[&stage.target];
            hard.push(json!({
                "constraint_id": format!("target_{}", k + 1), "kind": "must_pass", "shape": "freeform",
                "center": center, "radius": radius, "width": 2.0 * radius, "height": 2.0 * radius,
                "order": order, "source": "template_object", "object_id": stage.target,
                "scope": global_scope(), "label": target_text, "cells": cells_json(ix, cells),
            }));
            objects_json.push(json!({
                "order": k + 1, "object_id": stage.target, "name": obj.name, "category": obj.category,
                "center": [round3(center[0]), round3(center[1])],
            }));
            let var = format!("t{}", k + 1);
            program_lets.push(format!("let {var} = {}", stage.desc.m2r()));
            let stage_scope = json!({"type": "between_hard_constraints", "from_order": order - 1, "to_order": order});
            let room_text = match &stage.room_desc {
                Some(r) => r.text(rng),
                None => format!("the room with the {}", category_words(&obj.category)),
            };
            let room_m2r = match &stage.room_desc {
                Some(r) => r.m2r(),
                None => format!("{var}.room()"),
            };
            let mut body: Vec<String> = Vec::new();
            for avoid in &stage.avoids {
                avoid_no += 1;
                let (t, m2r) = avoid.text(rng);
                sentences.push(text::avoid(rng, &avoid.place, &t, false));
                hard.push(avoid_json(
                    ix,
                    avoid_no,
                    &avoid.cells,
                    &t,
                    stage_scope.clone(),
                ));
                body.push(format!("avoid {m2r}"));
            }
            let region_cells = ix.room_free_cells(stage.room);
            let room_center = cells_center(ix, &region_cells);
            for soft in &stage.softs {
                soft_no += 1;
                *soft_counts.entry(soft.kind().to_string()).or_default() += 1;
                let mut c = soft_base(
                    soft_no,
                    soft.kind(),
                    room_center,
                    stage_scope.clone(),
                    &room_text,
                    ix,
                    &region_cells,
                );
                match soft {
                    Soft::Near(o, d) | Soft::Far(o, d) => {
                        let t = d.text(rng);
                        stat(format!("{} preference", soft.kind()), d, &t);
                        let near = matches!(soft, Soft::Near(..));
                        sentences.push(if near {
                            text::near(rng, &t, &room_text)
                        } else {
                            text::far(rng, &t, &room_text)
                        });
                        c["preference_type"] = json!(if near {
                            "near_preference"
                        } else {
                            "far_preference"
                        });
                        c["object_ids"] = json!([o]);
                        c["reference_region"] = json!({"mode": "object", "object_id": o, "cells": footprint_json(ix, *o)});
                        body.push(format!(
                            "prefer {}({}) within {room_m2r}",
                            if near { "near" } else { "far" },
                            d.m2r()
                        ));
                    }
                    Soft::Relative(a, da, b, db) => {
                        let (ta, tb) = (da.text(rng), db.text(rng));
                        stat("relative preference (preferred)".into(), da, &ta);
                        stat("relative preference (other)".into(), db, &tb);
                        sentences.push(text::relative(rng, &ta, &tb, &room_text));
                        c["preference_type"] = json!("relative_preference");
                        c["object_ids"] = json!([a, b]);
                        c["reference_regions"] = json!([
                            {"object_id": a, "cells": footprint_json(ix, *a)},
                            {"object_id": b, "cells": footprint_json(ix, *b)},
                        ]);
                        body.push(format!(
                            "prefer closer({}, {}) within {room_m2r}",
                            da.m2r(),
                            db.m2r()
                        ));
                    }
                    Soft::Circle(circle) => {
                        let CircleSoft {
                            object: o,
                            desc: d,
                            clockwise,
                            ring,
                            area,
                            within_m,
                        } = circle.as_ref();
                        let t = d.text(rng);
                        stat("path-shape preference".into(), d, &t);
                        sentences.push(text::circle(rng, &t, *clockwise));
                        let ring: Vec<Value> = ring.iter().map(|c| json!([c.row, c.col])).collect();
                        let dir = if *clockwise {
                            "clockwise"
                        } else {
                            "counterclockwise"
                        };
                        let area_ix: Vec<usize> = area.iter().map(|&c| ix.free.index(c)).collect();
                        c["center"] = json!(cells_center(ix, &area_ix));
                        c["cells"] = cells_json(ix, &area_ix);
                        c["label"] = json!(format!("path_shape around {t}"));
                        c["preference_type"] = json!("path_shape_preference");
                        c["object_ids"] = json!([o]);
                        c["reference_region"] = json!({"mode": "object", "object_id": o, "cells": footprint_json(ix, *o)});
                        c["reference_waypoint_count"] = json!(ring.len());
                        c["reference_trajectory"] = json!(ring.clone());
                        c["path_shape_annotation"] = json!({
                            "version": 1, "annotation_type": "canonical_path_shape_reference",
                            "shape_spec": {"type": "circle", "direction": dir, "ordered_control_points": ring.clone()},
                            "shape_reference_trajectory": ring, "shape_reference_source": "m2rc_canonical_circle_v2",
                            "annotator_id": "m2rc-suite",
                            "notes": "generated: circle about the footprint centroid, radius half the larger extent + 0.45 m, from the point nearest the stage start, closed; R = the area within `within` of the object",
                            "created_at": TIMESTAMP, "updated_at": TIMESTAMP, "history": [],
                        });
                        body.push(format!(
                            "prefer circle({}, {dir}) within area_near({}, within: {within_m:.2}m)",
                            d.m2r(),
                            d.m2r()
                        ));
                    }
                    Soft::Clearance => {
                        sentences.push(text::clearance(rng));
                        c["preference_type"] = json!("clearance");
                        c["shape"] = json!("freeform");
                        c["cells"] = json!([]);
                        body.push("prefer clearance(0.5m)".to_string());
                    }
                }
                soft_json.push(c);
            }
            if body.is_empty() {
                program_route.push(format!("  go {var}"));
            } else {
                program_route.push(format!("  go {var} {{"));
                program_route.extend(body.iter().map(|b| format!("    {b}")));
                program_route.push("  }".to_string());
            }
        }
        for avoid in &global_avoids {
            avoid_no += 1;
            let (t, m2r) = avoid.text(rng);
            sentences.push(text::avoid(rng, &avoid.place, &t, true));
            hard.push(avoid_json(ix, avoid_no, &avoid.cells, &t, global_scope()));
            program_route.push(format!("  avoid {m2r}"));
        }
        // The annotator's default clearance entry, always present.
        soft_json.push(json!({
            "constraint_id": "__global_clearance__", "preference_type": "clearance", "shape": "freeform",
            "center": [0.0, 0.0], "radius": 1.0, "width": 1.0, "height": 1.0, "object_ids": [],
            "reference_regions": [], "reference_region": null, "reference_trajectory": [],
            "reference_waypoint_count": 0, "scope": global_scope(), "label": "Clearance", "cells": [],
        }));

        let instruction = sentences.join(" ");
        let mut program = String::new();
        program.push_str(&format!("// map: {}\n", self.map_key));
        for line in wrap(&format!("\"{instruction}\""), 96) {
            program.push_str(&format!("// {line}\n"));
        }
        for l in &program_lets {
            program.push_str(l);
            program.push('\n');
        }
        program.push_str("\nroute {\n");
        for l in &program_route {
            program.push_str(l);
            program.push('\n');
        }
        program.push_str("}\n");

        let (rooms_visited, room_transitions) = room_traversal(ix, &route);
        let length_cells: f64 = route.windows(2).map(|w| w[0].dist(w[1])).sum();
        let meta = EpisodeMeta {
            max_depth: refs.iter().map(|r| r.depth).max().unwrap_or(0),
            max_candidates: refs.iter().map(|r| r.candidates).max().unwrap_or(0),
            references: refs,
            destinations: n_stages,
            must_avoid: avoid_no,
            soft: soft_counts,
            rooms_visited,
            room_transitions,
            reference_route_length_m: length_cells * res,
        };
        let ordering = (1..=n_stages)
            .map(|k| format!("obj{k}"))
            .collect::<Vec<_>>()
            .join(" -> ");
        let instruction_json = json!({
            "id": id,
            "map_id": self.map_key,
            "template_instruction_id": format!("m2rc_{:06}", id),
            "object_count": n_stages,
            "objects": objects_json,
            "human_expert_trajectory": [],
            "start_pose": {"row": start.row, "col": start.col},
            "feasible": true,
            "name": format!("instruction_{id:06}"),
            "notes": "generated by m2rc suite build; no human demonstration",
            "created_by": "m2rc-suite",
            "hard_constraints": hard,
            "soft_constraints": soft_json,
            "ordering": ordering,
            "difficulty_level": difficulty.as_str(),
            "created_at": TIMESTAMP,
            "updated_at": TIMESTAMP,
            "instruction": instruction,
        });
        let mut generation = json!({
            "generator": "m2rc-suite",
            "version": env!("CARGO_PKG_VERSION"),
            "template": format!("m2rc-suite/{}", difficulty.as_str()),
        });
        if let (Some(g), Value::Object(m)) = (
            generation.as_object_mut(),
            serde_json::to_value(&meta).expect("meta serializes"),
        ) {
            g.extend(m);
        }
        let mut instruction_json = instruction_json;
        instruction_json[GOLD_PROGRAM_KEY] = json!(program);
        instruction_json[GENERATION_KEY] = generation;
        GeneratedEpisode {
            id,
            difficulty,
            instruction: instruction_json,
            meta,
            program,
            reference_route: route,
        }
    }
}

/// (minimum, mean) over waypoints of the distance to the nearest footprint cell, cells.
fn route_distance(points: &[Cell], footprint: &[Cell]) -> (f64, f64) {
    if points.is_empty() || footprint.is_empty() {
        return (f64::INFINITY, f64::INFINITY);
    }
    let mut min = f64::INFINITY;
    let mut sum = 0.0;
    for p in points {
        let d = footprint
            .iter()
            .map(|f| p.dist(*f))
            .fold(f64::INFINITY, f64::min);
        min = min.min(d);
        sum += d;
    }
    (min, sum / points.len() as f64)
}

/// The largest distance from a ring cell to the footprint, cells.
fn ring_extent(ring: &[Cell], footprint: &[Cell]) -> f64 {
    ring.iter()
        .map(|p| {
            footprint
                .iter()
                .map(|f| p.dist(*f))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

fn global_scope() -> Value {
    json!({"type": "global", "from_order": null, "to_order": null})
}

fn avoid_json(ix: &MapIndex<'_>, no: usize, cells: &[usize], label: &str, scope: Value) -> Value {
    let center = cells_center(ix, cells);
    json!({
        "constraint_id": format!("avoid_{no}"), "kind": "must_avoid", "shape": "freeform",
        "center": center, "radius": 1.0, "width": 1.0, "height": 1.0, "order": null, "source": "custom",
        "object_id": null, "scope": scope, "label": label, "cells": cells_json(ix, cells),
    })
}

#[allow(clippy::too_many_arguments)]
fn soft_base(
    no: usize,
    kind: &str,
    center: [f64; 2],
    scope: Value,
    room: &str,
    ix: &MapIndex<'_>,
    cells: &[usize],
) -> Value {
    json!({
        "constraint_id": format!("soft_{no}"), "preference_type": kind, "shape": "freeform",
        "center": center, "radius": 1.0, "width": 1.0, "height": 1.0, "object_ids": [],
        "reference_regions": [], "reference_region": null, "D_ref": null, "Q_relative_ref": null,
        "C_smooth_ref": null, "C_clear_ref": null, "reference_trajectory": [], "reference_waypoint_count": 0,
        "reference_valid_path_length": 0.0, "reference_metric_status": null, "relative_reference_status": null,
        "scope": scope, "label": format!("{kind} in {room}"), "cells": cells_json(ix, cells),
    })
}

fn cells_json(ix: &MapIndex<'_>, cells: &[usize]) -> Value {
    Value::Array(
        cells
            .iter()
            .map(|&i| {
                let c = ix.cell(i);
                json!([c.row, c.col])
            })
            .collect(),
    )
}

fn footprint_json(ix: &MapIndex<'_>, o: u32) -> Value {
    Value::Array(
        ix.object(o)
            .footprint
            .iter()
            .map(|c| json!([c.row, c.col]))
            .collect(),
    )
}

fn cells_center(ix: &MapIndex<'_>, cells: &[usize]) -> [f64; 2] {
    if cells.is_empty() {
        return [0.0, 0.0];
    }
    let (mut r, mut c) = (0.0, 0.0);
    for &i in cells {
        let cell = ix.cell(i);
        r += cell.row as f64;
        c += cell.col as f64;
    }
    [
        round3(r / cells.len() as f64),
        round3(c / cells.len() as f64),
    ]
}

fn round3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

fn disc(center: Cell, radius: f64) -> Vec<Cell> {
    let r = radius.ceil() as i64;
    let mut out = Vec::new();
    for dr in -r..=r {
        for dc in -r..=r {
            let (row, col) = (center.row as i64 + dr, center.col as i64 + dc);
            if row >= 0 && col >= 0 && ((dr * dr + dc * dc) as f64).sqrt() <= radius {
                out.push(Cell::new(row as u32, col as u32));
            }
        }
    }
    out
}

/// Cells within Chebyshev distance `by` of any cell in `cells`.
fn dilate(n: usize, cells: &[usize], by: i64) -> Vec<bool> {
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

/// Rooms visited and room transitions along a route (consecutive distinct non-zero room ids), as
/// in the reference statistics.
pub fn room_traversal(ix: &MapIndex<'_>, route: &[Cell]) -> (usize, usize) {
    let mut seq: Vec<u32> = Vec::new();
    for &c in route {
        let r = ix.room_at(c);
        if r != 0 && seq.last() != Some(&r) {
            seq.push(r);
        }
    }
    (seq.len(), seq.len().saturating_sub(1))
}

fn wrap(s: &str, width: usize) -> Vec<String> {
    let mut lines = vec![String::new()];
    for word in s.split_whitespace() {
        let last = lines.last_mut().expect("non-empty");
        if !last.is_empty() && last.len() + 1 + word.len() > width {
            lines.push(word.to_string());
        } else {
            if !last.is_empty() {
                last.push(' ');
            }
            last.push_str(word);
        }
    }
    lines
}

/// A stable per-episode seed: FNV-1a over the suite seed, the map key and the episode id.
pub fn mix(seed: u64, key: &str, id: u32) -> u64 {
    let mut h: u64 = 0xcbf29ce484222325;
    for b in seed
        .to_le_bytes()
        .iter()
        .chain(key.as_bytes())
        .chain(id.to_le_bytes().iter())
    {
        h ^= *b as u64;
        h = h.wrapping_mul(0x100000001b3);
    }
    h
}
