//! Pins the routes planned for a real program on fixture house 149 (the largest, 733×733 at
//! 0.05 m): trajectory hash, length, cost bits and expansions. Any change to the cost fields, the
//! heuristics or the search order shows up here, so speed work must keep these numbers.
//! Re-pinned when the importer started cutting doors along their own wall face and leaving
//! ProcTHOR's empty walls open (issue 12): the map itself changed.

use m2rc_compiler::check::check;
use m2rc_compiler::eval::{GroundOptions, ground_checked};
use m2rc_compiler::ir::RouteIr;
use m2rc_planner::context::MapContext;
use m2rc_planner::lower::{lower, lower_with};
use m2rc_planner::{
    CostProfile, PlannedRoute, compile, plan_global, plan_sequential, plan_shortest,
};
use m2rc_stdlib::map::SemanticMap;
use m2rc_stdlib::query::MapQuery;
use m2rc_stdlib::vocab::Vocabulary;

const HOUSE: &str = "procthor10k_uniform_hard_val_150_149.json";
const PROGRAM: &str = include_str!("../../benches/house149_tour.m2r");

fn grounded() -> Option<(SemanticMap, RouteIr)> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/procthor/fixtures")
        .join(HOUSE);
    if !path.exists() {
        eprintln!("fixture house {HOUSE} not found beside the repository; skipping");
        return None;
    }
    let map = m2rc_stdlib::load::load_map(&path.to_string_lossy()).expect("fixture loads");
    let checked = check(PROGRAM, &Vocabulary::from_map(&map));
    assert!(!checked.has_errors(), "{:#?}", checked.diagnostics);
    let q = MapQuery::new(&map);
    let g = ground_checked(&checked, PROGRAM, &q, &GroundOptions::default());
    assert!(
        !g.problems.iter().any(|p| p.is_error()),
        "{:#?}",
        g.problems
    );
    let ir = g.ir.expect("grounds");
    Some((map, ir))
}

/// FNV-1a over the trajectory cells.
fn trajectory_hash(r: &PlannedRoute) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for c in &r.trajectory {
        for b in c.row.to_le_bytes().into_iter().chain(c.col.to_le_bytes()) {
            h ^= b as u64;
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    }
    h
}

fn summary(r: &PlannedRoute) -> (u64, usize, u64, u64, usize) {
    assert!(r.is_success(), "{:?}", r.failure);
    (
        trajectory_hash(r),
        r.trajectory.len(),
        r.cost.to_bits(),
        r.expansions,
        r.segments.iter().map(|s| s.stages.len()).sum(),
    )
}

/// FNV-1a over the allowed masks, goal masks, and the bits of every cost-field value and heuristic
/// entry on an allowed cell, of every compiled segment.
fn fields_hash(problem: &m2rc_planner::PlanProblem) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |x: u64| {
        for b in x.to_le_bytes() {
            h ^= b as u64;
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    };
    let prep = compile::prepare(problem).expect("prepares");
    for (i, spec) in problem.segments.iter().enumerate() {
        let seg = compile::compile_segment(problem, &prep, i, spec).expect("compiles");
        // Only what a search can read: Φ and h are looked up on cells it may enter.
        let phi = seg.phi.as_deref();
        for (i, &ok) in seg.allowed.iter().enumerate() {
            eat(ok as u64);
            if ok {
                eat(phi.map_or(0, |phi| phi[i].to_bits()));
            }
        }
        for st in &seg.stages {
            st.goal.iter().for_each(|&v| eat(v as u64));
            for (i, &ok) in seg.allowed.iter().enumerate() {
                if ok {
                    eat(st.h.as_ref().map_or(0, |h| h.get(i) as u64));
                }
            }
        }
    }
    h
}

#[test]
fn house149_tour_routes_are_pinned() {
    let Some((map, ir)) = grounded() else { return };
    let problem = lower(&ir, &map, CostProfile::reference()).expect("lowers");
    let seq = plan_sequential(&problem);
    let glob = plan_global(&problem);
    let short = plan_shortest(&lower(&ir, &map, CostProfile::shortest()).expect("lowers"));
    // (trajectory hash, cells, cost bits, expansions, stages)
    assert_eq!(
        summary(&seq),
        (13430348108772913780, 373, 4666824705466240664, 190490, 4)
    );
    assert_eq!(
        summary(&glob),
        (3439986097760335752, 369, 4666785196281412542, 467934, 4)
    );
    assert_eq!(
        summary(&short),
        (4475485422371421501, 372, 4646137895548461303, 10219, 4)
    );
    assert_eq!(fields_hash(&problem), 0xb293e61aa6d2a26b);
}

#[test]
fn a_shared_context_plans_the_same_routes_and_computes_its_fields_once() {
    let Some((map, ir)) = grounded() else { return };
    let ctx = MapContext::new(&map).expect("indexes");
    let first = lower_with(&ir, &map, &ctx, CostProfile::reference()).expect("lowers");
    let second = lower_with(&ir, &map, &ctx, CostProfile::reference()).expect("lowers");
    assert_eq!(
        first,
        lower(&ir, &map, CostProfile::reference()).expect("lowers")
    );
    let a = compile::prepare(&first).expect("prepares");
    let b = compile::prepare(&second).expect("prepares");
    assert!(std::sync::Arc::ptr_eq(&a.obstacle_sq, &b.obstacle_sq));
    assert!(
        matches!((&a.clearance, &b.clearance), (Some(x), Some(y)) if std::sync::Arc::ptr_eq(x, y))
    );
    for p in [&first, &second] {
        assert_eq!(
            summary(&plan_sequential(p)),
            (13430348108772913780, 373, 4666824705466240664, 190490, 4)
        );
    }
    // A context for another map is refused, not misused.
    let mut other = map.clone();
    other.map_id = "another".into();
    assert!(lower_with(&ir, &other, &ctx, CostProfile::reference()).is_err());
}
