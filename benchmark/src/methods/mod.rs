//! Route methods behind one trait, so the runner can score any of them the same way.
//!
//! * `oracle`: the episode's gold `.m2r` program, compiled and planned by m2rc: what the
//!   compiler achieves when the language step is perfect.
//! * `hard-only`: the gold program with every `prefer` removed: the value of the preferences.
//! * `shortest`: the shortest legal route through the annotated targets (no program at all).
//!
//! * `grounding2route`: a language model writes the program, the compiler's diagnostics drive
//!   a bounded repair loop (built from flags by the CLI, see [`grounding2route`]).
//!
//! Human demonstrations are not available for generated suites, so there is no `human` method.

pub mod grounding2route;
pub mod oracle;
pub mod shortest;

use crate::episode::Episode;
use crate::metrics::map::EvalMap;
use m2rc_planner::context::MapContext;
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use std::sync::OnceLock;

/// Why a method produced no route for an episode. The runner still scores the episode (with
/// the start cell as the route), so failures cost metrics instead of vanishing from the table.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct MethodError(pub String);

/// A method's answer for one episode.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Prediction {
    pub trajectory: Vec<Cell>,
    /// The program the method ran, when it has one.
    pub program: Option<String>,
    /// Warnings worth keeping in the prediction record.
    pub notes: Vec<String>,
    /// The record's status when it is not `ok` (e.g. `grounding_failed`, `pending`); `pending`
    /// makes the runner leave the episode for the next run instead of writing a record.
    pub status: Option<String>,
    /// Extra keys for the prediction record (a model method's attempts).
    pub extra: serde_json::Map<String, serde_json::Value>,
}

pub trait Method: Send + Sync {
    /// The name used on the command line, in prediction records and in report rows.
    fn name(&self) -> &str;
    fn predict(&self, map: &PreparedMap, episode: &Episode) -> Result<Prediction, MethodError>;
    /// Everything that decides this method's answers, as JSON: the run directory's method
    /// fingerprint is its hash, so a resume with another configuration is refused. A method with
    /// settings (a model, an endpoint, repair rounds, a planner) adds them as keys.
    fn config(&self) -> serde_json::Value {
        serde_json::json!({"method": self.name(), "m2rc": env!("CARGO_PKG_VERSION")})
    }
}

/// A map prepared once for the many episodes run on it: the evaluator's view of it, and the
/// planner's context (its distance fields), built on first use and shared by every thread, so that
/// an episode pays for its own program, not for the map again.
pub struct PreparedMap {
    pub map: SemanticMap,
    pub eval: EvalMap,
    planning: OnceLock<Result<MapContext, String>>,
    /// The obstacle field loaded with the map (the prepared-map cache's), for the planner.
    obstacle_sq: Option<std::sync::Arc<Vec<u32>>>,
    /// What methods derived from this map for all its episodes (see [`Self::derived`]).
    derived: std::sync::Mutex<Vec<Derived>>,
}

type Derived = (
    std::any::TypeId,
    std::sync::Arc<dyn std::any::Any + Send + Sync>,
);

impl PreparedMap {
    pub fn new(map: SemanticMap) -> Self {
        Self::with_obstacle_sq(map, None)
    }

    /// [`Self::new`] with the map's obstacle field already computed
    /// ([`crate::map_cache::Loaded::obstacle_sq`]): the evaluator and the planner use it instead
    /// of computing their own when it is this map's (`seed_*` check that).
    pub fn with_obstacle_sq(
        map: SemanticMap,
        obstacle_sq: Option<std::sync::Arc<Vec<u32>>>,
    ) -> Self {
        let eval = EvalMap::from_semantic_map(&map);
        if let Some(sq) = &obstacle_sq {
            eval.seed_clearance_sq(sq);
        }
        PreparedMap {
            map,
            eval,
            planning: OnceLock::new(),
            obstacle_sq,
            derived: std::sync::Mutex::new(Vec::new()),
        }
    }

    /// The value of type `T` a method derives from this map (a scene graph, an inventory), built
    /// by `make` on first use and shared by every episode on the map. It lives with the map, so
    /// it is freed with it and can never be read for another map, which a method's own cache
    /// keyed by map id could (two maps may share an id).
    pub fn derived<T: std::any::Any + Send + Sync>(
        &self,
        make: impl FnOnce(&SemanticMap) -> T,
    ) -> std::sync::Arc<T> {
        let key = std::any::TypeId::of::<T>();
        let find = |slots: &[Derived]| {
            slots
                .iter()
                .find(|(k, _)| *k == key)
                .and_then(|(_, v)| v.clone().downcast::<T>().ok())
        };
        let lock = || match self.derived.lock() {
            Ok(g) => g,
            Err(poisoned) => poisoned.into_inner(),
        };
        if let Some(v) = find(&lock()) {
            return v;
        }
        // Built outside the lock; a thread that built it meanwhile wins.
        let built = std::sync::Arc::new(make(&self.map));
        let mut slots = lock();
        if let Some(v) = find(&slots) {
            return v;
        }
        slots.push((key, built.clone()));
        built
    }

    /// The planner's context for this map.
    pub fn planning(&self) -> Result<&MapContext, MethodError> {
        self.planning
            .get_or_init(|| {
                let ctx = MapContext::new(&self.map)?;
                if let Some(sq) = &self.obstacle_sq {
                    ctx.fields().seed_obstacle_sq(sq.clone());
                }
                Ok(ctx)
            })
            .as_ref()
            .map_err(|e| MethodError(format!("the map cannot be planned on: {e}")))
    }
}

/// Methods that use a language model; the CLI builds them from the `--llm-*` flags.
pub const MODEL_METHOD_NAMES: &[&str] = &["grounding2route"];

/// Names accepted by [`method_by_name`].
pub const METHOD_NAMES: &[&str] = &["oracle", "shortest", "hard-only"];

pub fn method_by_name(name: &str) -> Option<Box<dyn Method>> {
    match name {
        "oracle" => Some(Box::new(oracle::Oracle { soft: true })),
        "hard-only" => Some(Box::new(oracle::Oracle { soft: false })),
        "shortest" => Some(Box::new(shortest::Shortest)),
        _ => None,
    }
}

/// The episode's instruction text, which every language method reads; none, or only blanks, is
/// a method error with one wording for all of them.
pub fn instruction_of(episode: &Episode) -> Result<&str, MethodError> {
    episode
        .instruction
        .as_deref()
        .filter(|s| !s.trim().is_empty())
        .ok_or_else(|| MethodError("the episode has no instruction text".into()))
}

/// The episode's start cell: `start_pose`, else the first expert waypoint, else the centre of the
/// record (first must-pass) region.
pub fn start_cell(map: &SemanticMap, episode: &Episode) -> Result<Cell, MethodError> {
    let n = map.n() as i64;
    let in_grid = |r: i64, c: i64| (0..n).contains(&r) && (0..n).contains(&c);
    if let Some(p) = &episode.start_pose
        && let (Some(r), Some(c)) = (p.row, p.col)
    {
        if in_grid(r, c) {
            return Ok(Cell::new(r as u32, c as u32));
        }
        return Err(MethodError(format!(
            "start_pose [{r}, {c}] is outside the {n}x{n} map"
        )));
    }
    if let Some(first) = episode
        .human_expert_trajectory
        .as_ref()
        .and_then(|t| t.first())
        && in_grid(first[0], first[1])
    {
        return Ok(Cell::new(first[0] as u32, first[1] as u32));
    }
    Err(MethodError(
        "the episode has no start_pose and no expert trajectory".into(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_derived_value_is_built_once_per_map_and_never_crosses_maps() {
        let demo = || {
            m2rc_stdlib::demo::demo_document(&Default::default())
                .unwrap()
                .map
        };
        let a = PreparedMap::new(demo());
        let mut other = demo();
        other.objects.pop();
        let b = PreparedMap::new(other);
        assert_eq!(a.map.map_id, b.map.map_id, "the same id, other contents");
        let builds = std::sync::atomic::AtomicUsize::new(0);
        let count = |m: &SemanticMap| {
            builds.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            m.objects.len()
        };
        let first = a.derived(count);
        let again = a.derived(|_: &SemanticMap| -> usize { unreachable!("built once") });
        assert!(std::sync::Arc::ptr_eq(&first, &again));
        assert_eq!(*b.derived(count), *first - 1);
        assert_eq!(builds.load(std::sync::atomic::Ordering::Relaxed), 2);
        // Another type is another slot.
        assert_eq!(
            *a.derived(|m| m.rooms.len() as u32),
            a.map.rooms.len() as u32
        );
    }
}
