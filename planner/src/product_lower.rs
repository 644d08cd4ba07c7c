//! The LTL planner behind `PlannerKind::Ltl`: a [`PlanProblem`] (lowered from any RouteIR) read as
//! the LTLf skeleton of `m2rc_compiler::ltl::lower` — its destinations and passes as ordered
//! visits, its avoid regions as global `G !a` or stage-scoped until-formulas — turned into a
//! minimal automaton and planned with [`crate::product::search`]. Soft terms and path-shape
//! waypoint stages are dropped (the formula cannot say them). Atoms are named after the origins
//! (`t1` destination of stage 1, `p1_2` second pass of stage 1, `c3` constraint 3); visits of the
//! same cells share the atom of the first.
//!
//! Also [`plan_places`], for formulas written by hand over arbitrary place masks (the `ltl` route
//! form).

use crate::failure::PlanFailure;
use crate::goal;
use crate::problem::{Origin, PlanProblem, StageRole};
use crate::product::{ProductFailure, ProductProblem, ProductRoute, search};
use crate::route::{PlanStatus, PlannedRoute, PlannedSegment, PlannedStage, path_length_m};
use m2rc_compiler::ltl::{Dfa, Formula, Skeleton, Visit};
use m2rc_stdlib::grid::Cell;
use std::collections::HashMap;

/// Planner name in routes and reports.
pub const NAME: &str = "ltl";

/// The skeleton of `p`, the masks of its atoms and their names; the visits' origins and roles.
pub struct ProblemLtl {
    pub skeleton: Skeleton,
    pub names: Vec<String>,
    pub masks: Vec<Vec<bool>>,
    /// Per visit: (segment, origin, role).
    pub visits: Vec<(usize, Origin, StageRole)>,
    pub formula: Formula,
}

fn origin_name(o: Origin, k: usize) -> String {
    match o {
        Origin::Target { stage } => format!("t{}", stage + 1),
        Origin::Pass { stage, index } => format!("p{}_{}", stage + 1, index + 1),
        Origin::Constraint { index, .. } => format!("c{index}"),
        Origin::Unknown => format!("a{k}"),
    }
}

/// Reads `p` as an LTLf skeleton.
pub fn problem_ltl(p: &PlanProblem) -> ProblemLtl {
    let n = p.traversable.n();
    let trav = p.traversable.data();
    let radius = goal::goal_radius_cells(p.profile.goal_radius_m, p.resolution);
    let mut keys: Vec<(bool, Origin)> = Vec::new();
    let mut names = Vec::new();
    let mut masks: Vec<Vec<bool>> = Vec::new();
    // Visits of the same cells share one atom (the first origin names it): stages that return to
    // a place (`go bathroom`, `go kitchen`, `go bathroom`, ...) then add automaton states, not
    // atoms, and the guards stay over the few places there are instead of doubling per stage.
    let mut visit_atoms: HashMap<Vec<bool>, usize> = HashMap::new();
    let mut atom = |avoid: bool, o: Origin, mask: &dyn Fn() -> Vec<bool>| -> usize {
        if let Some(i) = keys.iter().position(|k| *k == (avoid, o)) {
            return i;
        }
        let m = mask();
        if !avoid && let Some(&i) = visit_atoms.get(&m) {
            return i;
        }
        keys.push((avoid, o));
        let mut name = origin_name(o, names.len());
        while names.contains(&name) {
            name.push('_');
        }
        names.push(name);
        if !avoid {
            visit_atoms.insert(m.clone(), keys.len() - 1);
        }
        masks.push(m);
        keys.len() - 1
    };
    let mut sk = Skeleton::default();
    let mut visits = Vec::new();
    // Which segments each avoid origin is active in.
    let mut avoid_segments: Vec<(usize, Vec<usize>)> = Vec::new();
    let mut per_segment_avoids: Vec<Vec<usize>> = Vec::new();
    for (si, seg) in p.segments.iter().enumerate() {
        let mut here = Vec::new();
        for f in &seg.forbidden {
            let a = atom(true, f.origin, &|| f.cells.to_mask(n));
            here.push(a);
            match avoid_segments.iter_mut().find(|(x, _)| *x == a) {
                Some((_, s)) => s.push(si),
                None => avoid_segments.push((a, vec![si])),
            }
        }
        per_segment_avoids.push(here);
    }
    let global: Vec<usize> = avoid_segments
        .iter()
        .filter(|(_, s)| s.len() == p.segments.len())
        .map(|(a, _)| *a)
        .collect();
    sk.global_avoids = global.clone();
    for (si, seg) in p.segments.iter().enumerate() {
        let scoped: Vec<usize> = per_segment_avoids[si]
            .iter()
            .copied()
            .filter(|a| !global.contains(a))
            .collect();
        for st in seg.stages.iter().filter(|s| s.role != StageRole::Waypoint) {
            let a = atom(false, st.origin, &|| {
                goal::goal_mask(&st.target, trav, n, radius)
            });
            sk.visits.push(Visit {
                atom: a,
                avoids: scoped.clone(),
            });
            visits.push((si, st.origin, st.role));
        }
    }
    let formula = sk.formula(&names);
    ProblemLtl {
        skeleton: sk,
        names,
        masks,
        visits,
        formula,
    }
}

/// Plans `p` with the LTL product planner.
pub fn plan_ltl(p: &PlanProblem) -> PlannedRoute {
    let profile = p.profile.name.clone();
    let fail = |f: PlanFailure| PlannedRoute::failed(NAME, &profile, p.start, f);
    if let Err(m) = p.profile.validate() {
        return fail(PlanFailure::InvalidProblem { message: m });
    }
    if !(p.resolution.is_finite() && p.resolution > 0.0) {
        return fail(PlanFailure::InvalidProblem {
            message: format!("resolution must be positive, got {}", p.resolution),
        });
    }
    let lt = problem_ltl(p);
    let dfa = match Dfa::build(&lt.formula, &lt.names, true) {
        Ok(d) => d,
        Err(e) => {
            return fail(PlanFailure::InvalidProblem {
                message: format!(
                    "the route's LTL formula ({} visits over {} places and avoided areas) has no \
                     automaton within the LTL planner's limits: {e}",
                    lt.skeleton.visits.len(),
                    lt.names.len()
                ),
            });
        }
    };
    let n = p.traversable.n();
    let budget = p
        .profile
        .max_expansions
        .saturating_mul(p.segments.len().max(1) as u64);
    let result = search(&ProductProblem {
        n,
        traversable: p.traversable.data(),
        atoms: &lt.masks,
        dfa: &dfa,
        start: p.start,
        max_expansions: budget,
    });
    match result {
        Ok(r) => route_of(p, &lt, r),
        Err(e) => fail(explain(p, e, budget)),
    }
}

/// A product failure in the RouteIR planners' terms where possible: the shortest-feasible
/// planner on the same hard constraints names the stage and the avoid regions responsible.
fn explain(p: &PlanProblem, e: ProductFailure, budget: u64) -> PlanFailure {
    match e {
        ProductFailure::StartBlocked => PlanFailure::StartBlocked { start: p.start },
        ProductFailure::Invalid(message) => PlanFailure::InvalidProblem { message },
        e @ ProductFailure::TooLarge { .. } => PlanFailure::InvalidProblem {
            message: e.to_string(),
        },
        ProductFailure::Budget { .. } => PlanFailure::BudgetExceeded {
            segment: 0,
            stage: 0,
            origin: Origin::Unknown,
            budget,
        },
        ProductFailure::StartRejected | ProductFailure::NoAcceptingRoute { .. } => {
            let shortest = crate::plan_shortest(p);
            shortest.failure.unwrap_or(PlanFailure::InvalidProblem {
                message: "no route satisfies the route's LTL formula on this map".into(),
            })
        }
    }
}

/// Splits the product route into the RouteIR segments: a visit is reached at the first cell of
/// the route, after the previous visit, that lies in it (as HCS reads it).
fn route_of(p: &PlanProblem, lt: &ProblemLtl, r: ProductRoute) -> PlannedRoute {
    let mut segments: Vec<PlannedSegment> = Vec::new();
    let mut at = 0usize;
    let mut seg_start = 0usize;
    let traj = &r.trajectory;
    let mut stages: Vec<PlannedStage> = Vec::new();
    for (k, v) in lt.skeleton.visits.iter().enumerate() {
        let mask = &lt.masks[v.atom];
        let n = p.traversable.n();
        while at < traj.len() && !mask[traj[at].row as usize * n + traj[at].col as usize] {
            at += 1;
        }
        let end = at.min(traj.len() - 1);
        let (si, origin, role) = lt.visits[k];
        stages.push(PlannedStage {
            role,
            origin,
            endpoint: traj[end],
            cost: 0.0,
            expansions: 0,
        });
        let last_of_segment = lt.visits.get(k + 1).is_none_or(|x| x.0 != si);
        if last_of_segment {
            let path: Vec<Cell> = traj[seg_start..=end].to_vec();
            let len = path_length_m(&path, p.resolution);
            segments.push(PlannedSegment {
                index: si,
                status: PlanStatus::Success,
                cost: len / p.resolution,
                length_m: len,
                path,
                expansions: 0,
                stages: std::mem::take(&mut stages),
            });
            seg_start = end;
        }
    }
    // The route may go on after the last visit only if the formula needs it; keep it whole.
    if let Some(last) = segments.last_mut()
        && seg_start + 1 < traj.len()
    {
        last.path.extend_from_slice(&traj[seg_start + 1..]);
        last.length_m = path_length_m(&last.path, p.resolution);
    }
    if let Some(first) = segments.first_mut() {
        first.expansions = r.expansions;
    }
    PlannedRoute {
        planner: NAME.into(),
        profile: p.profile.name.clone(),
        status: PlanStatus::Success,
        length_m: path_length_m(traj, p.resolution),
        cost: r.cost,
        expansions: r.expansions,
        trajectory: r.trajectory,
        segments,
        failure: None,
    }
}

/// Plans a formula over explicit place masks (the `ltl` route form): the cheapest route from
/// `start` the automaton accepts.
pub fn plan_places(
    traversable: &m2rc_stdlib::grid::Grid<bool>,
    masks: &[Vec<bool>],
    dfa: &Dfa,
    start: Cell,
    max_expansions: u64,
) -> Result<ProductRoute, ProductFailure> {
    search(&ProductProblem {
        n: traversable.n(),
        traversable: traversable.data(),
        atoms: masks,
        dfa,
        start,
        max_expansions,
    })
}
