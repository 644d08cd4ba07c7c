//! Which member of each set goal (`go S`, `pass S`: [`Target::AnyOf`]) a planned route reached.
//! The search itself never chooses a member: its goal is every member's goal at once, and the
//! member is read off where the stage ended, so the choice is the route's, made under the
//! stage's constraints. Grounding reads these back to know where the next stage starts.

use crate::goal;
use crate::problem::{Origin, PlanProblem, Target};
use crate::route::PlannedRoute;
use m2rc_compiler::eval::Chosen;

/// The member reached for every set destination and set must-pass of `route` (planned from `p`),
/// in route order. Stages the route did not complete have none.
pub fn reached_members(p: &PlanProblem, route: &PlannedRoute) -> Vec<Chosen> {
    let n = p.traversable.n();
    let trav = p.traversable.data();
    let radius = goal::goal_radius_cells(p.profile.goal_radius_m, p.resolution);
    let mut out = Vec::new();
    for seg in &route.segments {
        let Some(spec) = p.segments.get(seg.index) else {
            continue;
        };
        for st in &seg.stages {
            let (stage, pass) = match st.origin {
                Origin::Target { stage } => (stage, None),
                Origin::Pass { stage, index } => (stage, Some(index)),
                _ => continue,
            };
            let Some(target) = spec
                .stages
                .iter()
                .find(|s| s.origin == st.origin)
                .map(|s| &s.target)
                .filter(|t| matches!(t, Target::AnyOf(_)))
            else {
                continue;
            };
            if let Some(member) = goal::member_reached(target, st.endpoint, trav, n, radius) {
                out.push(Chosen {
                    stage,
                    pass,
                    member,
                });
            }
        }
    }
    out
}
