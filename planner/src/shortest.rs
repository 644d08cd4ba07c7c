//! The shortest-feasible baseline: the same stages, targets and avoid regions, but no soft field,
//! no clearance and no turn penalty, and shape waypoints dropped. What a route planner that only
//! understood the hard constraints would do; the gap between it and the reference planner measures
//! what the soft constraints buy.

use crate::problem::{CostProfile, PlanProblem, WaypointMode};
use crate::route::PlannedRoute;
use crate::sequential;

/// The hard-only version of `profile` (keeps its goal radius and heuristic choice).
pub fn hard_constraints_only(profile: &CostProfile) -> CostProfile {
    CostProfile {
        name: "shortest".into(),
        clearance: false,
        soft_scale: 0.0,
        smoothness_weight: 0.0,
        max_expansions: 0,
        waypoints: WaypointMode::Drop,
        avoid_corners: true,
        ..profile.clone()
    }
}

/// Plans `p` ignoring every soft preference.
pub fn plan_shortest(p: &PlanProblem) -> PlannedRoute {
    let mut q = p.clone();
    q.profile = hard_constraints_only(&p.profile);
    let mut route = sequential::plan_sequential(&q);
    route.planner = "shortest".into();
    route
}
