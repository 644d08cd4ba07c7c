//! Route planning over the grid: cost fields from the soft constraints, a flat-array A*, the
//! reference sequential planner, an exact global planner over all stages, and the
//! shortest-feasible baseline. `lower` turns a compiler RouteIR into a [`PlanProblem`]; everything
//! else works on masks and cells only. Planning again on the same map: build a
//! [`context::MapContext`] once and lower with `lower::lower_with`, so the map's grids, obstacle
//! distances, clearance field and working arrays are shared between plans.
//!
//! See `docs/planner.md` for the cost model, its defaults and where it departs from the reference.

pub mod astar;
pub mod choice;
pub mod compile;
pub mod context;
pub mod costfield;
pub mod failure;
pub mod global;
pub mod goal;
pub mod layout;
pub mod lower;
mod open_list;
pub mod problem;
pub mod product;
pub mod product_lower;
pub mod route;
pub mod sequential;
pub mod shortest;

pub use failure::PlanFailure;
pub use global::plan_global;
pub use problem::{
    Area, CostProfile, Fallback, Forbid, Origin, PlanProblem, RelativeMode, SegmentSpec, SoftKind,
    SoftTerm, StageRole, StageSpec, Target, WaypointMode,
};
pub use route::{PlanStatus, PlannedRoute, PlannedSegment, PlannedStage};
pub use sequential::plan_sequential;
pub use shortest::plan_shortest;

/// Which planner to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PlannerKind {
    /// The reference greedy stage-by-stage A*.
    Sequential,
    /// Exact layered search over all stages.
    Global,
    /// Hard constraints only.
    Shortest,
    /// The RouteIR's hard constraints as an LTLf formula, planned on the product of the grid and
    /// the formula's automaton (`product_lower`).
    Ltl,
}

/// Plans `problem` with the chosen planner.
pub fn plan(problem: &PlanProblem, kind: PlannerKind) -> PlannedRoute {
    match kind {
        PlannerKind::Sequential => plan_sequential(problem),
        PlannerKind::Global => plan_global(problem),
        PlannerKind::Shortest => plan_shortest(problem),
        PlannerKind::Ltl => product_lower::plan_ltl(problem),
    }
}
