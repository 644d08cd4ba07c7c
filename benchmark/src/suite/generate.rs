//! Episode generation on one scene. An episode is planned in four steps, each in its own module:
//!
//! 1. destinations spread across the house ([`super::dest`]) and must-avoids ([`super::avoid`]);
//! 2. the reference route: the shortest legal route through the targets that never touches an
//!    active must-avoid (an episode without one is dropped);
//! 3. preferences placed along it by the neutral geometric tests of [`super::place`];
//! 4. the plan rendered ([`super::render`]) into the annotation (Map2Route instruction JSON),
//!    the gold `.m2r` program and the instruction text ([`super::realise`]).
//!
//! Compiler-side validity (unique grounding, HCS = 1 of the gold program's own route) is checked
//! afterwards by the suite's validators.

use super::index::MapIndex;
use super::paths::{Leg, chain_legs};
use super::place::{LegCtx, LegView, ScopeRoom};
use super::plan::{Avoid, SoftPlan, Stage};
use super::refs::{DescriptionMemo, ObjRef, describe};
use crate::episode::GENERATION_KEY;
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::MapQuery;
use rand::seq::{IndexedRandom, SliceRandom};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};
use std::collections::BTreeMap;

/// Radius of the start (record) region, cells.
pub const START_RADIUS: f64 = 3.0;
/// Plans drawn per episode slot; the first with every preference placed is kept, else the one
/// with the most.
const ATTEMPTS: usize = 5;
/// Must-avoids drawn per avoid slot before the slot is left empty.
const AVOID_TRIES: usize = 4;

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

/// One reference expression in an episode, for the statistics and the naturalness counters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RefStat {
    pub role: String,
    pub expression: String,
    pub category: String,
    pub depth: u32,
    pub candidates: usize,
    /// Object categories the chain names, head first.
    #[serde(default)]
    pub object_categories: Vec<String>,
    /// Room categories the chain names.
    #[serde(default)]
    pub room_categories: Vec<String>,
    /// For each superlative in the chain, the number of rooms it ranks.
    #[serde(default)]
    pub superlative_over: Vec<usize>,
}

/// One clause of the instruction and the gold-program statement it realises.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Clause {
    pub templates: Vec<String>,
    pub text: String,
    pub program: String,
}

/// Generation facts kept in the instruction file under the generation key (the reference format
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
    /// Full descriptions given per room id (a room described once is referred back to).
    #[serde(default)]
    pub room_descriptions: BTreeMap<u32, usize>,
    /// The instruction's clauses, each traced to the template(s) and program statement.
    #[serde(default)]
    pub clauses: Vec<Clause>,
    /// Every mention read back as written: how many were checked, and those whose words do not
    /// pick out the gold's object ([`super::determinacy`]).
    #[serde(default)]
    pub determinacy: super::determinacy::Determinacy,
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

/// Adds the generation record (generator, version, seed, source house) under the episode
/// format's generation key.
pub fn attach_generation(value: &mut Value, seed: u64, house: &str) {
    if let Some(obj) = value.as_object_mut()
        && let Some(Value::Object(generation)) = obj.get_mut(GENERATION_KEY)
    {
        generation.insert("seed".into(), json!(seed));
        generation.insert("house".into(), json!(house));
    }
}

/// Per-scene precomputation shared by all of its episodes.
pub struct Scene<'a> {
    pub ix: MapIndex<'a>,
    /// The compiler's spatial queries, so that annotated areas are the cells the gold program's
    /// places resolve to.
    pub(crate) q: MapQuery<'a>,
    pub map_key: String,
    /// Object id -> (centre, radius, must-pass region cells).
    pub(crate) targets: BTreeMap<u32, ([f64; 2], f64, Vec<usize>)>,
    pub(crate) descriptions: BTreeMap<u32, Vec<ObjRef>>,
    starts: Vec<Cell>,
    /// The connected free space the robot lives in.
    pub(crate) reach: Vec<bool>,
}

/// Preferences per episode (the clearance entry not counted), from the paper's histogram of
/// soft constraints including clearance (one clearance each): Easy 74 / 476 / 139 / 11 episodes
/// with 0..3, Hard 2 / 19 / 110 / 119 / 39 / 10 / 1 with 0..6.
fn soft_count(rng: &mut ChaCha8Rng, d: Difficulty) -> usize {
    let hist: &[u32] = match d {
        Difficulty::Easy => &[74, 476, 139, 11],
        Difficulty::Hard => &[2, 19, 110, 119, 39, 10, 1],
    };
    weighted_index(rng, hist)
}

/// Preference kinds, tried in a weighted order (near, far, relative, path shape). The weights are
/// not the paper's mix itself (Easy 284 / 288 / 126 / 89, Hard 274 / 303 / 98 / 133): a near
/// preference is placed far less often than the others (its witness must gain a metre with a
/// detour of at most a metre), a far one most often, and a kind that cannot be placed falls
/// through to the next, so near is tried first most of the time for the placed mix to come out
/// as near the paper's as the houses allow.
fn soft_kinds(rng: &mut ChaCha8Rng, d: Difficulty) -> Vec<&'static str> {
    let w: [f64; 4] = match d {
        Difficulty::Easy => [2600.0, 420.0, 1000.0, 30.0],
        Difficulty::Hard => [1200.0, 500.0, 330.0, 240.0],
    };
    let kinds = ["near", "far", "relative", "path_shape"];
    // Efraimidis-Spirakis: sorting by u^(1/w) draws a weighted order without replacement.
    let mut keyed: Vec<(f64, &str)> = kinds
        .iter()
        .zip(w)
        .map(|(k, w)| (rng.random::<f64>().powf(1.0 / w), *k))
        .collect();
    keyed.sort_by(|a, b| b.0.total_cmp(&a.0));
    keyed.into_iter().map(|(_, k)| k).collect()
}

fn weighted_index(rng: &mut ChaCha8Rng, w: &[u32]) -> usize {
    let total: u32 = w.iter().sum();
    let mut x = rng.random_range(0..total.max(1));
    for (i, &v) in w.iter().enumerate() {
        if x < v {
            return i;
        }
        x -= v;
    }
    w.len() - 1
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
        // Windows are destinations too ("head to the window next to the fridge").
        for ids in ix
            .objects_by_cat
            .values()
            .chain(ix.fixtures_by_cat.values())
        {
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
        Scene {
            q: MapQuery::new(ix.map),
            ix,
            map_key,
            targets,
            descriptions,
            starts,
            reach,
        }
    }

    /// Objects that can be destinations.
    pub fn target_count(&self) -> usize {
        self.targets.len()
    }

    /// Generates episode `id` (1-based within the scene) of the given difficulty.
    pub fn episode(&self, seed: u64, id: u32, difficulty: Difficulty) -> Option<GeneratedEpisode> {
        let mut rng = ChaCha8Rng::seed_from_u64(mix(seed, &self.map_key, id));
        let mut best: Option<(usize, GeneratedEpisode)> = None;
        for _ in 0..ATTEMPTS {
            let Some((missing, ep)) = self.try_episode(&mut rng, id, difficulty) else {
                continue;
            };
            if missing == 0 {
                return Some(ep);
            }
            if best.as_ref().is_none_or(|(m, _)| missing < *m) {
                best = Some((missing, ep));
            }
        }
        best.map(|(_, ep)| ep)
    }

    pub(crate) fn describable(&self, id: u32, max_depth: u32) -> Vec<&ObjRef> {
        self.descriptions
            .get(&id)
            .map(|d| d.iter().filter(|r| r.depth() <= max_depth).collect())
            .unwrap_or_default()
    }

    /// Descriptions of the two members of a pair ("between the sofa and the TV"), each of which
    /// does not name the other's category: never "between the window nearest the fridge and the
    /// fridge".
    pub(crate) fn pair_descriptions(
        &self,
        rng: &mut ChaCha8Rng,
        a: u32,
        b: u32,
        max_depth: u32,
    ) -> Option<(ObjRef, ObjRef)> {
        let pick = |o: u32, other: u32, rng: &mut ChaCha8Rng| {
            let other_cat = self.ix.object(other).category.as_str();
            self.describable(o, max_depth)
                .into_iter()
                .filter(|d| !d.object_cats().contains(&other_cat))
                .collect::<Vec<_>>()
                .choose(rng)
                .map(|d| (*d).clone())
        };
        Some((pick(a, b, rng)?, pick(b, a, rng)?))
    }

    /// One plan; returns how many of the drawn preferences could not be placed, and the episode.
    fn try_episode(
        &self,
        rng: &mut ChaCha8Rng,
        id: u32,
        difficulty: Difficulty,
    ) -> Option<(usize, GeneratedEpisode)> {
        // Destinations and must-avoids at the paper's rates: Easy 1.30 destinations and 0.19
        // avoids per episode, Hard 3.03 and 0.58.
        let destinations = match difficulty {
            Difficulty::Easy => 1 + weighted_index(rng, &[72, 25, 3]),
            Difficulty::Hard => 2 + weighted_index(rng, &[25, 50, 25]),
        };
        let avoid_count = match difficulty {
            Difficulty::Easy => usize::from(rng.random_bool(0.19)),
            Difficulty::Hard => weighted_index(rng, &[50, 42, 8]),
        };
        let soft_wanted = soft_count(rng, difficulty);
        let start = *self.starts.choose(rng)?;
        let start_room = self.ix.room_at(start);
        let mut stages = self.destinations(rng, start, destinations, difficulty)?;

        let mut rooms = self.avoidable_rooms(rng, start, &stages);
        let mut global_avoids: Vec<Avoid> = Vec::new();
        // The route of the last accepted avoid: a rejected one is taken back, so it stays valid.
        let mut route = None;
        for _ in 0..avoid_count {
            // An avoid that cuts every legal route (the only hallway, say) is replaced rather than
            // the plan dropped: dropping it would keep plans with fewer avoids, and the suite
            // would come out under the drawn rate.
            for _ in 0..AVOID_TRIES {
                let Some(avoid) = self.avoid(rng, start, &stages, &mut rooms) else {
                    break;
                };
                // Global, or active on one stage.
                let on_stage = (!rng.random_bool(0.5)).then(|| rng.random_range(0..stages.len()));
                match on_stage {
                    Some(k) => stages[k].avoids.push(avoid),
                    None => global_avoids.push(avoid),
                }
                if let Some(r) = self.reference_route(start, &stages, &global_avoids) {
                    route = Some(r);
                    break;
                }
                match on_stage {
                    Some(k) => stages[k].avoids.pop(),
                    None => global_avoids.pop(),
                };
            }
        }

        let route = match route {
            Some(r) => r,
            None => self.reference_route(start, &stages, &global_avoids)?,
        };
        let views = self.leg_views(start, &stages, &route);
        let forbidden: Vec<Vec<usize>> = (0..stages.len())
            .map(|k| self.stage_forbidden(&stages, &global_avoids, k))
            .collect();
        let mut legs: Vec<Option<LegCtx<'_>>> = (0..stages.len()).map(|_| None).collect();
        let mut scopes: Vec<Option<Vec<ScopeRoom>>> = (0..stages.len()).map(|_| None).collect();
        let mut placed: Vec<(usize, SoftPlan)> = Vec::new();
        let mentioned = super::place::Mentioned {
            categories: super::place::named_categories(&self.ix, &stages),
            objects: Default::default(),
        };
        for _ in 0..soft_wanted {
            let kinds = soft_kinds(rng, difficulty);
            let mut order: Vec<usize> = (0..stages.len()).collect();
            order.shuffle(rng);
            let mut found = None;
            'kinds: for kind in kinds {
                for &k in &order {
                    let mine: Vec<&SoftPlan> = placed
                        .iter()
                        .filter(|(j, _)| *j == k)
                        .map(|(_, s)| s)
                        .collect();
                    // A loop reshapes the whole leg: alone in it. Otherwise one object
                    // preference per room R of a leg, so none is measured against another's pull.
                    if mine.iter().any(|s| s.kind() == "path_shape")
                        || (kind == "path_shape" && !mine.is_empty())
                    {
                        continue;
                    }
                    let leg: &LegCtx<'_> = legs[k].get_or_insert_with(|| {
                        self.leg_ctx(
                            k,
                            &stages[k],
                            &views[k],
                            &forbidden[k],
                            start_room,
                            &mentioned,
                        )
                    });
                    let rooms_for_leg = scopes[k].get_or_insert_with(|| self.scope_rooms(leg));
                    let free: Vec<&ScopeRoom> = rooms_for_leg
                        .iter()
                        .filter(|s| mine.iter().all(|m| m.room != s.room))
                        .collect();
                    if free.is_empty() {
                        continue;
                    }
                    let soft = match kind {
                        "path_shape" => self.place_shape(rng, leg, rooms_for_leg),
                        _ => free.iter().find_map(|s| match kind {
                            "near" => self.place_near(rng, leg, s),
                            "far" => self.place_far(rng, leg, s),
                            _ => self.place_relative(rng, leg, s),
                        }),
                    };
                    if let Some(s) = soft {
                        found = Some((k, s));
                        break 'kinds;
                    }
                }
            }
            match found {
                Some(f) => {
                    mentioned.objects.borrow_mut().extend(f.1.subject_ids());
                    placed.push(f);
                }
                None => break,
            }
        }
        drop(legs);
        let missing = soft_wanted - placed.len();
        for (k, s) in placed {
            stages[k].softs.push(s);
        }
        let ep = self.render(rng, id, difficulty, start, stages, global_avoids, route);
        // A plan whose instruction names anything the gold does not take (the realiser rewords
        // what it can: a scope said, a room described again) is drawn again, never kept: it
        // would score luck, not grounding.
        if !ep.meta.determinacy.underdetermined.is_empty() {
            return None;
        }
        Some((missing, ep))
    }

    /// Per stage, the stage start on the reference route and the evaluator's active window.
    fn leg_views(&self, start: Cell, stages: &[Stage], route: &[Cell]) -> Vec<LegView> {
        let ix = &self.ix;
        let start_region: Vec<Cell> = disc(start, START_RADIUS);
        let inside = |k: usize, c: Cell| -> bool {
            if k == 0 {
                start_region.contains(&c)
            } else {
                stages[k - 1].goal.binary_search(&ix.free.index(c)).is_ok()
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

    fn stage_forbidden(&self, stages: &[Stage], global: &[Avoid], k: usize) -> Vec<usize> {
        let ix = &self.ix;
        let mut cells: Vec<usize> = Vec::new();
        for a in global.iter().chain(stages[k].avoids.iter()) {
            cells.extend(a.cells.iter().copied());
        }
        // An avoid of the next leg must not be touched where this leg ends: the evaluator would
        // count it against the next leg (its exit coincides with the goal entry).
        if let Some(next) = stages.get(k + 1) {
            let near_goal = super::place::dilate(ix.map.n(), &stages[k].goal, 2);
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
        let goals: Vec<Vec<bool>> = stages.iter().map(|s| ix.mask(&s.goal)).collect();
        let forbidden: Vec<Vec<usize>> = (0..stages.len())
            .map(|k| self.stage_forbidden(stages, global, k))
            .collect();
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

    /// The subject of a preference about object `o` measured in `room`.
    pub(crate) fn subject(
        &self,
        rng: &mut ChaCha8Rng,
        o: u32,
        room: u32,
    ) -> Option<super::plan::Subject> {
        use super::plan::Subject;
        let ix = &self.ix;
        if super::refs::count_in(ix, &ix.object(o).category, room) == 1 {
            return Some(Subject::One(o, None));
        }
        let d = self.describable(o, 3);
        d.choose(rng).map(|r| Subject::One(o, Some((*r).clone())))
    }
}

pub fn disc(center: Cell, radius: f64) -> Vec<Cell> {
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
