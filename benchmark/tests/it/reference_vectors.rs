//! The Map2Route reference evaluator's unit-test vectors (fact sheet sections D.1, D.2, D.4),
//! each as a named test with the exact expected numbers and statuses.
//!
//! Not covered: the D.4 "worked example" (its 12x12 map is not given in the fact sheet), and the
//! cache-building half of D.1 test 1 (m2rc keeps no metric caches; the on-demand result must be
//! the same, and is checked).

use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::metrics::{
    EpisodeMetrics, EpisodeRecord, EvalMap, EvalOptions, SoftDetail, aggregate, evaluate,
    evaluate_or_worst_case,
    geometry::{Freeform, Geom},
    ndtw::ndtw,
    soft_details, worst_case_metrics,
};
use serde_json::{Value, json};

const TOL: f64 = 1e-9;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= TOL
}

#[track_caller]
fn assert_close(a: f64, b: f64) {
    assert!(close(a, b), "{a} != {b}");
}

#[track_caller]
fn raw(d: &SoftDetail) -> f64 {
    d.raw_value
        .unwrap_or_else(|| panic!("raw_value is null: {d:?}"))
}

/// D.1 fixture: 5x5, free value 0, obstacle only at (0,0), object layer all 0, no metadata.
fn d1_map_json() -> Value {
    let mut occ = vec![vec![0; 5]; 5];
    occ[0][0] = 1;
    json!({
        "grid_size": 5,
        "layer_legends": {"occupancy": {"free": {"value": 0}}},
        "layers": {"occupancy": occ, "object_instance": vec![vec![0; 5]; 5]},
        "object_instances": []
    })
}

fn d1_map() -> EvalMap {
    EvalMap::from_json(&d1_map_json()).unwrap()
}

/// D.4 fixture: 5x5 all-free map, resolution 1.
fn free_map() -> EvalMap {
    EvalMap::from_json(&json!({
        "grid_size": 5,
        "layers": {"occupancy": vec![vec![0; 5]; 5], "object_instance": vec![vec![0; 5]; 5]}
    }))
    .unwrap()
}

/// The reference tests' `region` helper: a single-cell freeform constraint.
fn region(
    id: &str,
    r: i64,
    c: i64,
    order: Option<i64>,
    kind: &str,
    scope: Option<(i64, i64)>,
) -> Value {
    let scope = match scope {
        Some((a, b)) => json!({"type": "between_hard_constraints", "from_order": a, "to_order": b}),
        None => json!({"type": "global", "from_order": null, "to_order": null}),
    };
    json!({"constraint_id": id, "kind": kind, "shape": "freeform", "center": [r, c], "order": order,
           "scope": scope, "cells": [[r, c]]})
}

fn pass(id: &str, r: i64, c: i64, order: i64) -> Value {
    region(id, r, c, Some(order), "must_pass", None)
}

fn avoid(id: &str, r: i64, c: i64, scope: Option<(i64, i64)>) -> Value {
    region(id, r, c, None, "must_avoid", scope)
}

fn episode(hard: Vec<Value>, soft: Vec<Value>) -> Episode {
    Episode::from_value(
        json!({"hard_constraints": hard, "soft_constraints": soft}),
        "test.json",
    )
    .unwrap()
}

fn soft(kind: &str, cells: Value, extra: Value) -> Value {
    let mut v = json!({"constraint_id": format!("{kind}_1"), "preference_type": kind, "shape": "freeform",
                       "center": [0, 0], "cells": cells});
    for (k, x) in extra.as_object().unwrap() {
        v[k] = x.clone();
    }
    v
}

fn near(cells: Value, reference: Value) -> Value {
    soft(
        "near_preference",
        cells,
        json!({"reference_region": {"mode": "object", "object_id": 1, "cells": reference}}),
    )
}

fn relative(cells: Value, a: Value, b: Value, scope: Option<(i64, i64)>) -> Value {
    let mut v = soft(
        "relative_preference",
        cells,
        json!({"object_ids": [1, 2], "reference_regions": [{"object_id": 1, "cells": a}, {"object_id": 2, "cells": b}]}),
    );
    if let Some((f, t)) = scope {
        v["scope"] = json!({"type": "between_hard_constraints", "from_order": f, "to_order": t});
    }
    v
}

fn eval(traj: &[[i64; 2]], ep: &Episode, map: &EvalMap) -> EpisodeMetrics {
    evaluate(traj, ep, map, &EvalOptions::default()).unwrap()
}

fn soft1(traj: &[[i64; 2]], ep: &Episode, map: &EvalMap) -> SoftDetail {
    soft_details(traj, ep, map, &EvalOptions::default())
        .unwrap()
        .remove(0)
}

// ---------------------------------------------------------------- D.1 (14 tests)

#[test]
fn d1_01_spl_completed_with_l_star_equal_to_l() {
    let ep = episode(vec![pass("record", 1, 1, 1), pass("goal", 3, 3, 2)], vec![]);
    let m = eval(&[[1, 1], [2, 2], [3, 3]], &ep, &d1_map());
    assert_eq!(m.segment_wise_spl, 1.0);
    let s = &m.details.segments[0];
    assert_eq!(s.status, "completed");
    assert_close(s.l_star.unwrap(), 2.0 * 2f64.sqrt());
    assert_close(s.l.unwrap(), 2.0 * 2f64.sqrt());
}

#[test]
fn d1_02_global_avoid_zeroes_hcs_after_completion() {
    let ep = episode(
        vec![
            pass("record", 0, 0, 1),
            pass("goal", 0, 1, 2),
            avoid("global_avoid", 0, 2, None),
        ],
        vec![],
    );
    let m = eval(&[[0, 0], [0, 1], [0, 2]], &ep, &d1_map());
    assert_eq!(m.hcs, 0.0);
    assert_eq!(
        m.details.hcs.failure_type.as_deref(),
        Some("global_must_avoid_violation")
    );
    assert_eq!(
        m.details.hcs.global_must_avoid_violations,
        vec!["global_avoid".to_string()]
    );
}

#[test]
fn d1_03_near_empty_region_takes_farthest_region_cell() {
    let ep = episode(vec![], vec![near(json!([[0, 1], [0, 2]]), json!([[0, 0]]))]);
    let d = soft1(&[[4, 4]], &ep, &d1_map());
    assert_eq!(d.status, "empty_region_max_distance");
    assert_close(raw(&d), 2.0);
}

#[test]
fn d1_04_near_is_reported_in_metres() {
    let mut map = d1_map_json();
    map["metadata"] = json!({"grid_coordinate_frame": {"resolution": 0.5}});
    let map = EvalMap::from_json(&map).unwrap();
    let ep = episode(vec![], vec![near(json!([[0, 2]]), json!([[0, 0]]))]);
    let d = soft1(&[[0, 2]], &ep, &map);
    assert_close(raw(&d), 1.0);
    assert_eq!(d.unit.as_deref(), Some("m"));
}

#[test]
fn d1_05_far_empty_region_is_zero() {
    let ep = episode(
        vec![],
        vec![soft(
            "far_preference",
            json!([[0, 1]]),
            json!({"reference_region": {"cells": [[0, 0]]}}),
        )],
    );
    let d = soft1(&[[4, 4]], &ep, &d1_map());
    assert_eq!(d.status, "empty_region_zero_distance");
    assert_eq!(d.raw_value, Some(0.0));
}

#[test]
fn d1_06_relative_is_the_distance_ratio() {
    let ep = episode(
        vec![],
        vec![relative(
            json!([[1, 1], [1, 2]]),
            json!([[1, 0]]),
            json!([[1, 5]]),
            None,
        )],
    );
    let d = soft1(&[[1, 1], [1, 2]], &ep, &d1_map());
    assert_close(d.d_a.unwrap(), 1.5);
    assert_close(d.d_b.unwrap(), 3.5);
    assert_close(raw(&d), 3.5 / 1.5);
    assert_eq!(d.status, "computed");
}

#[test]
fn d1_07_relative_empty_region_scores_zero() {
    let ep = episode(
        vec![],
        vec![relative(
            json!([[1, 1], [1, 2]]),
            json!([[1, 0]]),
            json!([[1, 5]]),
            None,
        )],
    );
    let d = soft1(&[[4, 4]], &ep, &d1_map());
    assert_eq!(d.status, "empty_region_zero_score");
    assert_eq!(d.raw_value, Some(0.0));
    assert_eq!(d.region_waypoint_count, Some(0));
}

#[test]
fn d1_08_scoped_relative_is_gated_when_segment_not_completed() {
    let ep = episode(
        vec![pass("record", 0, 0, 1), pass("goal", 4, 4, 2)],
        vec![relative(
            json!([[1, 1]]),
            json!([[1, 0]]),
            json!([[1, 4]]),
            Some((1, 2)),
        )],
    );
    let d = soft1(&[[0, 0], [1, 1]], &ep, &d1_map());
    assert_eq!(d.status, "segment_not_completed_worst_case");
    assert_eq!(d.raw_value, Some(0.0));
    assert_eq!(d.region_waypoint_count, Some(0));
    assert_eq!(d.active_waypoint_count, 0);
    assert_eq!(d.ungated_active_waypoint_count, Some(2));
    assert_eq!(d.segment_succeeded, Some(false));
}

#[test]
fn d1_09_scoped_relative_is_computed_when_segment_completed() {
    let ep = episode(
        vec![pass("record", 0, 0, 1), pass("goal", 1, 2, 2)],
        vec![relative(
            json!([[1, 1]]),
            json!([[1, 0]]),
            json!([[1, 4]]),
            Some((1, 2)),
        )],
    );
    let d = soft1(&[[0, 0], [1, 1], [1, 2]], &ep, &d1_map());
    assert_eq!(d.status, "computed");
    assert_close(raw(&d), 3.0);
    assert_eq!(d.region_waypoint_count, Some(1));
    assert_eq!(d.segment_succeeded, Some(true));
}

#[test]
fn d1_10_target_reached_after_an_active_avoid_gates_the_stage() {
    let ep = episode(
        vec![
            pass("record", 0, 0, 1),
            pass("goal", 0, 2, 2),
            avoid("avoid", 0, 1, Some((1, 2))),
        ],
        vec![relative(
            json!([[0, 1]]),
            json!([[1, 1]]),
            json!([[4, 4]]),
            Some((1, 2)),
        )],
    );
    let d = soft1(&[[0, 0], [0, 1], [0, 2]], &ep, &d1_map());
    assert_eq!(d.status, "segment_not_completed_worst_case");
    assert_eq!(d.raw_value, Some(0.0));
    assert_eq!(d.segment_succeeded, Some(false));
}

#[test]
fn d1_11_geometric_path_empty_region_scores_zero() {
    let ep = episode(
        vec![],
        vec![soft(
            "geometric_path_preference",
            json!([[1, 1], [1, 2]]),
            json!({"reference_trajectory": [[1, 1], [1, 2]]}),
        )],
    );
    let d = soft1(&[[4, 4]], &ep, &d1_map());
    assert_eq!(d.status, "empty_region_zero_score");
    assert_eq!(d.raw_value, Some(0.0));
    assert_eq!(d.ndtw, Some(0.0));
    assert_eq!(d.region_waypoint_count, Some(0));
}

#[test]
fn d1_12_clearance_is_the_mean_obstacle_distance() {
    let ep = episode(vec![], vec![json!({"preference_type": "clearance"})]);
    let d = soft1(&[[0, 1], [0, 2]], &ep, &d1_map());
    assert_close(raw(&d), 1.5);
    assert_eq!(d.status, "computed");
}

#[test]
fn d1_13_unfinished_final_segment_scores_zero() {
    let ep = episode(
        vec![
            pass("record", 1, 1, 1),
            pass("a", 1, 2, 2),
            pass("b", 1, 3, 3),
        ],
        vec![],
    );
    let m = eval(&[[1, 1], [1, 2]], &ep, &d1_map());
    let s = &m.details.segments;
    assert_eq!((s[0].s, s[0].spl), (1, 1.0));
    assert_eq!((s[1].s, s[1].spl), (0, 0.0));
    assert_close(m.segment_wise_spl, 0.5);
}

#[test]
fn d1_14_embedded_path_shape_annotation_overrides_the_legacy_reference() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("instruction_000001.json");
    let constraint = soft(
        "path_shape_preference",
        json!([[1, 1], [1, 2], [1, 3]]),
        json!({
            "reference_trajectory": [[3, 1], [3, 2]],
            "path_shape_annotation": {
                "version": 1,
                "annotation_type": "canonical_path_shape_reference",
                "shape_reference_trajectory": [[1, 1], [1, 2], [1, 3]],
                "shape_reference_source": "human_expert_canonical_v1"
            }
        }),
    );
    let doc = json!({"id": 1, "hard_constraints": [], "soft_constraints": [constraint]});
    std::fs::write(&path, serde_json::to_string_pretty(&doc).unwrap()).unwrap();
    let ep = Episode::read(&path).unwrap();
    let d = soft1(&[[1, 1], [1, 2], [1, 3]], &ep, &d1_map());
    assert_eq!(d.ndtw, Some(1.0));
    assert_eq!(d.raw_value, Some(1.0));
    assert_eq!(
        d.reference_trajectory_source.as_deref(),
        Some("human_expert_canonical_v1")
    );
    assert_eq!(d.reference_waypoint_count, Some(3));
    assert_eq!(
        d.reference_trajectory_file.as_deref(),
        Some(path.display().to_string().as_str())
    );
    // Without the annotation the legacy reference is used.
    let mut legacy = ep.clone();
    legacy.soft_constraints[0].path_shape_annotation = None;
    let d = soft1(&[[1, 1], [1, 2], [1, 3]], &legacy, &d1_map());
    assert_eq!(
        d.reference_trajectory_source.as_deref(),
        Some("instruction_reference_trajectory")
    );
    assert_eq!(d.reference_waypoint_count, Some(2));
    assert_eq!(d.reference_trajectory_file, None);
}

// ---------------------------------------------------------------- D.2

fn d2_episode() -> Episode {
    episode(
        vec![],
        vec![
            near(json!([[0, 0], [2, 0]]), json!([[0, 0]])),
            soft(
                "far_preference",
                json!([[1, 1]]),
                json!({"reference_region": {"cells": [[0, 0]]}}),
            ),
            relative(json!([[1, 1]]), json!([[1, 0]]), json!([[1, 4]]), None),
            soft(
                "path_shape_preference",
                json!([[1, 1]]),
                json!({"reference_trajectory": [[1, 1], [1, 2]]}),
            ),
            json!({"preference_type": "clearance"}),
        ],
    )
}

#[test]
fn d2_evaluator_exception_gives_worst_case() {
    let map = EvalMap::from_json(&json!({"grid_size": 5})).unwrap();
    let ep = d2_episode();
    // No must-pass regions: HCS raises, so the worst case applies.
    let m = evaluate_or_worst_case(&[[0, 0], [0, 3]], &ep, &map, &EvalOptions::default());
    assert_eq!(m.hcs, 0.0);
    assert_eq!(m.segment_wise_spl, 0.0);
    assert_eq!(m.pl, 3.0);
    let fb = m.details.evaluation_fallback.as_ref().unwrap();
    assert_eq!(fb.policy, "worst_case");
    let s = &m.details.soft_constraints;
    assert_close(raw(&s[0]), 2.0);
    assert_eq!(s[0].status, "evaluation_error_worst_case_max_distance");
    for d in &s[1..] {
        assert_eq!(d.raw_value, Some(0.0), "{d:?}");
        assert_eq!(d.status, "evaluation_error_worst_case_zero");
    }
}

#[test]
fn d2_malformed_prediction_summary() {
    let map = EvalMap::from_json(&json!({"grid_size": 5})).unwrap();
    let ep = episode(
        vec![],
        vec![relative(
            json!([[1, 1]]),
            json!([[1, 0]]),
            json!([[1, 4]]),
            None,
        )],
    );
    let m = worst_case_metrics(None, &ep, &map, "malformed prediction JSON");
    let records = [EpisodeRecord {
        map_id: "m",
        instruction_id: "instruction_000001",
        difficulty: Some("easy"),
        metrics: &m,
    }];
    let agg = aggregate(&records);
    assert_eq!(agg.overall.metric.hcs, Some(0.0));
    assert_eq!(agg.overall.metric.scs.relative, Some(0.0));
    assert_eq!(agg.easy.record_count, 1);
    assert_eq!(agg.hard.record_count, 0);
}

#[test]
fn d2_near_without_cells_falls_back_to_the_map_diagonal() {
    let map = EvalMap::from_json(&json!({"grid_size": 5})).unwrap();
    let ep = episode(vec![], vec![near(json!([]), json!([[0, 0]]))]);
    let m = worst_case_metrics(None, &ep, &map, "x");
    let d = &m.details.soft_constraints[0];
    assert_eq!(d.status, "evaluation_error_worst_case_map_diagonal");
    assert_close(raw(d), 2f64.sqrt() * 4.0);
}

// ---------------------------------------------------------------- D.4 (V1..V13)

fn rec() -> Value {
    pass("record", 0, 0, 1)
}

fn hcs(hard: Vec<Value>, traj: &[[i64; 2]]) -> EpisodeMetrics {
    eval(traj, &episode(hard, vec![]), &free_map())
}

#[test]
fn v1_geometric_crossing_completes_hcs_but_not_spl() {
    let m = hcs(vec![rec(), pass("g", 0, 2, 2)], &[[0, 0], [0, 4]]);
    assert_eq!(m.hcs, 1.0);
    assert_eq!(m.segment_wise_spl, 0.0);
    assert_eq!(m.details.segments[0].status, "target_not_completed");
}

#[test]
fn v2_avoid_before_goal_fails_and_after_goal_does_not() {
    let m = hcs(
        vec![rec(), pass("g", 0, 3, 2), avoid("x", 0, 2, Some((1, 2)))],
        &[[0, 0], [0, 4]],
    );
    assert_eq!(m.hcs, 0.0);
    let m = hcs(
        vec![rec(), pass("g", 0, 2, 2), avoid("x", 0, 3, Some((1, 2)))],
        &[[0, 0], [0, 4]],
    );
    assert_eq!(m.hcs, 1.0);
}

#[test]
fn v3_tie_between_goal_and_avoid_is_a_failure() {
    let m = hcs(
        vec![rec(), pass("g", 0, 2, 2), avoid("x", 0, 2, Some((1, 2)))],
        &[[0, 0], [0, 2]],
    );
    assert_eq!(m.hcs, 0.0);
}

#[test]
fn v4_diagonal_touches_the_corner_cell() {
    let g = Geom::Freeform(Freeform::new(vec![[0, 1]]));
    assert_eq!(g.segment_interval([0.0, 0.0], [1.0, 1.0]), Some((0.5, 0.5)));
    let m = hcs(
        vec![rec(), pass("g", 1, 1, 2), avoid("x", 0, 1, Some((1, 2)))],
        &[[0, 0], [1, 1]],
    );
    assert_eq!(m.hcs, 0.0);
}

#[test]
fn v5c_avoid_scoped_to_a_later_stage_is_inactive() {
    let m = hcs(
        vec![
            rec(),
            pass("a", 0, 3, 2),
            pass("b", 2, 3, 3),
            avoid("x", 0, 1, Some((2, 3))),
        ],
        &[[0, 0], [0, 1], [0, 2], [0, 3], [1, 3], [2, 3]],
    );
    assert_eq!(m.hcs, 1.0);
}

#[test]
fn v5d_avoid_ending_where_the_goal_begins_counts_for_the_next_stage() {
    let m = hcs(
        vec![
            rec(),
            pass("a", 0, 2, 2),
            pass("b", 2, 2, 3),
            avoid("x", 0, 1, Some((2, 3))),
        ],
        &[[0, 0], [0, 1], [0, 2], [1, 2], [2, 2]],
    );
    assert_eq!(m.hcs, 0.5);
    assert_eq!(
        m.details.hcs.failure_type.as_deref(),
        Some("must_avoid_violation")
    );
    assert_eq!(
        m.details.hcs.first_must_avoid_violation.as_deref(),
        Some("x")
    );
}

#[test]
fn v6_start_inside_a_target_counts() {
    let m = hcs(
        vec![rec(), pass("a", 0, 0, 2), pass("b", 0, 2, 3)],
        &[[0, 0]],
    );
    assert_eq!(m.hcs, 0.5);
}

#[test]
fn v7_global_avoid_touched_only_by_a_segment() {
    let m = hcs(
        vec![rec(), pass("g", 0, 2, 2), avoid("x", 0, 1, None)],
        &[[0, 0], [0, 2]],
    );
    assert_eq!(m.hcs, 0.0);
    assert_eq!(
        m.details.hcs.failure_type.as_deref(),
        Some("global_must_avoid_violation")
    );
}

#[test]
fn v8_ndtw_vectors() {
    let r = ndtw(&[[0.0, 0.0], [0.0, 5.0]], &[[0.0, 0.0], [0.0, 5.0]]);
    assert_eq!((r.score, r.cost, r.mean, r.steps), (1.0, 0.0, 0.0, 2));
    let r = ndtw(&[[12.0, 0.0], [12.0, 5.0]], &[[0.0, 0.0], [0.0, 5.0]]);
    assert_close(r.score, 0.6065306597126334);
    assert_close(r.cost, 4.0);
    assert_close(r.mean, 2.0);
    assert_eq!(r.steps, 2);
    let r = ndtw(&[[20.0, 0.0]], &[[0.0, 0.0], [0.0, 1.0], [0.0, 2.0]]);
    assert_close(r.score, 0.08123617416335172);
    assert_close(r.cost, 30.124735636742567);
    assert_close(r.mean, 10.041578545580856);
    assert_eq!(r.steps, 3);
}

#[test]
fn v9_l_star_does_not_cut_corners() {
    let map = EvalMap::from_json(&json!({
        "grid_size": 5,
        "layers": {"occupancy": [[0,0,0,0,0],[0,1,0,0,0],[0,0,0,0,0],[0,0,0,0,0],[0,0,0,0,0]],
                   "object_instance": vec![vec![0; 5]; 5]}
    }))
    .unwrap();
    let ep = episode(vec![rec(), pass("g", 2, 2, 2)], vec![]);
    let m = eval(&[[0, 0], [0, 1], [0, 2], [1, 2], [2, 2]], &ep, &map);
    let s = &m.details.segments[0];
    assert_close(s.l_star.unwrap(), 4.0);
    assert_close(s.l.unwrap(), 4.0);
    assert_eq!(m.segment_wise_spl, 1.0);
}

#[test]
fn v10_region_waypoints_are_not_deduplicated_by_default() {
    let ep = episode(vec![], vec![near(json!([[0, 1], [0, 2]]), json!([[0, 0]]))]);
    let traj = [[0, 1], [0, 1], [0, 2]];
    assert_close(raw(&soft1(&traj, &ep, &free_map())), 4.0 / 3.0);
    let paper = EvalOptions {
        dedup_region_waypoints: true,
    };
    let d = soft_details(&traj, &ep, &free_map(), &paper)
        .unwrap()
        .remove(0);
    assert_close(raw(&d), 1.5);
}

#[test]
fn v11_zero_distance_to_the_preferred_object_is_pending() {
    let ep = episode(
        vec![],
        vec![relative(
            json!([[1, 1]]),
            json!([[1, 1]]),
            json!([[3, 3]]),
            None,
        )],
    );
    let d = soft1(&[[1, 1]], &ep, &free_map());
    assert_eq!(d.raw_value, None);
    assert_eq!(d.status, "zero_distance_to_preferred_object_pending_policy");
}

#[test]
fn v12_clearance_without_obstacles_is_null() {
    let ep = episode(vec![], vec![json!({"preference_type": "clearance"})]);
    let d = soft1(&[[1, 1]], &ep, &free_map());
    assert_eq!(d.raw_value, None);
    assert_eq!(d.status, "no_nontraversable_cells");
}

#[test]
fn v13_one_waypoint_can_complete_two_targets() {
    let m = hcs(
        vec![rec(), pass("a", 0, 1, 2), pass("b", 0, 1, 3)],
        &[[0, 0], [0, 1]],
    );
    let s = &m.details.segments;
    assert_eq!((s[0].spl, s[1].spl), (1.0, 1.0));
    assert_close(s[0].l.unwrap(), 1.0);
    assert_close(s[1].l.unwrap(), 0.0);
    assert_eq!(m.segment_wise_spl, 1.0);
    assert_eq!(m.hcs, 1.0);
}

// ---------------------------------------------------------------- several candidate objects

/// A target with several candidate objects is one must-pass region holding all of them (a freeform
/// region painted over each, as an annotator draws "a box"): HCS completes at whichever member
/// the route enters, and SPL's L* is the shortest legal path to the *nearest* member, so reaching a
/// farther one completes the target at a lower SPL. `m2rc eval` scores a `go S` route exactly so.
#[test]
fn a_target_of_several_candidates_completes_at_any_member_and_spl_measures_the_nearest() {
    let goal = json!({"constraint_id": "goal", "kind": "must_pass", "shape": "freeform",
        "center": [2, 2], "order": 2, "cells": [[0, 2], [4, 4]],
        "scope": {"type": "global", "from_order": null, "to_order": null}});
    let ep = episode(vec![pass("record", 0, 0, 1), goal], vec![]);
    let far = eval(&[[0, 0], [1, 1], [2, 2], [3, 3], [4, 4]], &ep, &free_map());
    assert_eq!(far.hcs, 1.0);
    let s = &far.details.segments[0];
    assert_eq!(s.status, "completed");
    assert_close(s.l_star.unwrap(), 2.0);
    assert_close(s.l.unwrap(), 4.0 * 2f64.sqrt());
    assert_close(far.segment_wise_spl, 2.0 / (4.0 * 2f64.sqrt()));
    let near = eval(&[[0, 0], [0, 1], [0, 2]], &ep, &free_map());
    assert_eq!((near.hcs, near.segment_wise_spl), (1.0, 1.0));
}
