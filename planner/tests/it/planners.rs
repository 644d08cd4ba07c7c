//! Scenario tests for the planners: failure reasons and their origins, greedy versus global
//! endpoints, soft terms steering the route, and turn penalties.

use m2rc_planner::{
    Area, CostProfile, Forbid, Origin, PlanFailure, PlanProblem, PlanStatus, SegmentSpec, SoftKind,
    SoftTerm, StageRole, StageSpec, Target, global, plan_global, plan_sequential, plan_shortest,
};
use m2rc_stdlib::grid::{Cell, Grid};

/// Parses a picture: `#` blocked, anything else free. Returns the grid and the cells of each letter.
fn picture(rows: &[&str]) -> (Grid<bool>, impl Fn(char) -> Vec<Cell>) {
    let n = rows.len();
    assert!(rows.iter().all(|r| r.len() == n), "pictures are square");
    let data: Vec<bool> = rows
        .iter()
        .flat_map(|r| r.chars().map(|ch| ch != '#'))
        .collect();
    let owned: Vec<String> = rows.iter().map(|s| s.to_string()).collect();
    let find = move |letter: char| -> Vec<Cell> {
        let mut out = Vec::new();
        for (r, row) in owned.iter().enumerate() {
            for (c, ch) in row.chars().enumerate() {
                if ch == letter {
                    out.push(Cell::new(r as u32, c as u32));
                }
            }
        }
        out
    };
    (Grid::from_vec(n, data).unwrap(), find)
}

fn region(cells: Vec<Cell>) -> Target {
    Target::Region {
        cells: Area::Cells(cells),
        fallback: None,
    }
}

fn stage(target: Target, origin: Origin) -> StageSpec {
    StageSpec {
        target,
        role: StageRole::Destination,
        smoothness: None,
        origin,
    }
}

fn plain_profile() -> CostProfile {
    // Clearance off so hand-computed costs stay simple.
    CostProfile {
        clearance: false,
        ..CostProfile::reference()
    }
}

fn problem(grid: Grid<bool>, start: Cell, segments: Vec<SegmentSpec>) -> PlanProblem {
    PlanProblem {
        traversable: grid,
        obstacles: None,
        resolution: 0.05,
        start,
        segments,
        profile: plain_profile(),
        map_fields: None,
    }
}

fn seg(stages: Vec<StageSpec>, forbidden: Vec<Forbid>, soft: Vec<SoftTerm>) -> SegmentSpec {
    SegmentSpec {
        stages,
        forbidden,
        soft,
    }
}

const TARGET0: Origin = Origin::Target { stage: 0 };
const AVOID: Origin = Origin::Constraint { index: 3, part: 0 };
const AVOID2: Origin = Origin::Constraint { index: 4, part: 0 };

#[test]
fn start_blocked() {
    let (g, at) = picture(&["#....", ".....", ".....", ".....", "....G"]);
    let p = problem(
        g,
        Cell::new(0, 0),
        vec![seg(vec![stage(region(at('G')), TARGET0)], vec![], vec![])],
    );
    let r = plan_sequential(&p);
    assert_eq!(
        r.failure,
        Some(PlanFailure::StartBlocked {
            start: Cell::new(0, 0)
        })
    );
    assert_eq!(r.failure.as_ref().unwrap().code(), "E0701");
    assert_eq!(r.trajectory, vec![Cell::new(0, 0)]);
    let mut q = p.clone();
    q.start = Cell::new(50, 50);
    assert!(matches!(
        plan_sequential(&q).failure,
        Some(PlanFailure::StartBlocked { .. })
    ));
}

#[test]
fn target_empty_names_the_stage() {
    let (g, at) = picture(&["S...", "....", "..##", "..#G"]);
    let blocked = vec![Cell::new(2, 2)];
    let p = problem(
        g,
        at('S')[0],
        vec![seg(
            vec![
                stage(region(at('G')), TARGET0),
                stage(region(blocked), Origin::Target { stage: 1 }),
            ],
            vec![],
            vec![],
        )],
    );
    // G itself is free (a letter), but the second target is a wall cell only.
    let r = plan_sequential(&p);
    let f = r.failure.unwrap();
    assert_eq!(
        f,
        PlanFailure::TargetEmpty {
            segment: 0,
            stage: 1,
            origin: Origin::Target { stage: 1 }
        }
    );
    assert_eq!(f.code(), "E0703");
    assert_eq!(f.reference_code(), "EMPTY_TARGET_REGION");
}

#[test]
fn goal_blocked_lists_the_avoid_regions_covering_it() {
    let (g, at) = picture(&["S....", ".....", ".....", ".....", "...GG"]);
    let p = problem(
        g,
        at('S')[0],
        vec![seg(
            vec![stage(region(at('G')), TARGET0)],
            vec![
                Forbid {
                    cells: Area::Cells(at('G')),
                    origin: AVOID,
                },
                Forbid {
                    cells: Area::Cells(vec![Cell::new(0, 4)]),
                    origin: AVOID2,
                },
            ],
            vec![],
        )],
    );
    let f = plan_sequential(&p).failure.unwrap();
    assert_eq!(
        f,
        PlanFailure::GoalBlocked {
            segment: 0,
            stage: 0,
            origin: TARGET0,
            forbids: vec![AVOID]
        }
    );
    assert_eq!(f.forbids(), &[AVOID]);
}

#[test]
fn unreachable_without_avoids_is_plain_unreachable() {
    let (g, at) = picture(&["S.#..", "..#..", "###..", ".....", "....G"]);
    // The ### wall plus the corner rule cut S off from G.
    let p = problem(
        g,
        at('S')[0],
        vec![seg(vec![stage(region(at('G')), TARGET0)], vec![], vec![])],
    );
    let f = plan_sequential(&p).failure.unwrap();
    assert_eq!(
        f,
        PlanFailure::Unreachable {
            segment: 0,
            stage: 0,
            origin: TARGET0,
            from: at('S')[0]
        }
    );
    assert_eq!(f.code(), "E0705");
}

#[test]
fn unreachable_under_avoids_points_at_the_blocking_avoid() {
    let (g, at) = picture(&["S.#..", "..#..", "..A..", "..#..", "..#.G"]);
    let p = problem(
        g,
        at('S')[0],
        vec![seg(
            vec![stage(region(at('G')), TARGET0)],
            vec![
                Forbid {
                    cells: Area::Cells(at('A')),
                    origin: AVOID,
                },
                Forbid {
                    cells: Area::Cells(vec![Cell::new(4, 0)]),
                    origin: AVOID2,
                },
            ],
            vec![],
        )],
    );
    let f = plan_sequential(&p).failure.unwrap();
    assert_eq!(
        f,
        PlanFailure::UnreachableUnderAvoids {
            segment: 0,
            stage: 0,
            origin: TARGET0,
            from: at('S')[0],
            forbids: vec![AVOID]
        }
    );
    assert_eq!(f.code(), "E0706");
    // Without the avoid the route goes through the door.
    let mut q = p.clone();
    q.segments[0].forbidden.remove(0);
    let r = plan_sequential(&q);
    assert!(r.is_success());
    assert!(r.trajectory.contains(&at('A')[0]));
}

#[test]
fn start_inside_an_avoid_region() {
    let (g, at) = picture(&["S....", ".....", ".....", ".....", "....G"]);
    let p = problem(
        g,
        at('S')[0],
        vec![seg(
            vec![stage(region(at('G')), TARGET0)],
            vec![Forbid {
                cells: Area::Cells(at('S')),
                origin: AVOID,
            }],
            vec![],
        )],
    );
    let f = plan_sequential(&p).failure.unwrap();
    assert_eq!(
        f,
        PlanFailure::StartInForbidden {
            segment: 0,
            start: at('S')[0],
            forbids: vec![AVOID]
        }
    );
}

#[test]
fn budget_exhaustion() {
    let (g, at) = picture(&[
        "S.......", "........", "........", "........", "........", "........", "........",
        ".......G",
    ]);
    let mut p = problem(
        g,
        at('S')[0],
        vec![seg(vec![stage(region(at('G')), TARGET0)], vec![], vec![])],
    );
    p.profile.max_expansions = 3;
    let f = plan_sequential(&p).failure.unwrap();
    assert_eq!(
        f,
        PlanFailure::BudgetExceeded {
            segment: 0,
            stage: 0,
            origin: TARGET0,
            budget: 3
        }
    );
    p.profile.max_expansions = 0;
    assert!(plan_sequential(&p).is_success());
}

#[test]
fn partial_trajectory_is_kept_up_to_the_failing_segment() {
    let (g, at) = picture(&["S...", "....", "..##", "..#G"]);
    let p = problem(
        g,
        at('S')[0],
        vec![
            seg(
                vec![stage(Target::Position(Cell::new(0, 3)), TARGET0)],
                vec![],
                vec![],
            ),
            seg(
                vec![stage(region(at('G')), Origin::Target { stage: 1 })],
                vec![],
                vec![],
            ),
        ],
    );
    let r = plan_sequential(&p);
    assert_eq!(r.status, PlanStatus::Failed);
    assert_eq!(r.failure.as_ref().unwrap().segment(), Some(1));
    assert_eq!(
        r.trajectory,
        vec![
            Cell::new(0, 0),
            Cell::new(0, 1),
            Cell::new(0, 2),
            Cell::new(0, 3)
        ]
    );
}

#[test]
fn greedy_endpoint_is_beaten_by_the_global_planner() {
    // Stage 1: reach either A (near, left) or B (right). Stage 2: reach G on the far right.
    let (g, at) = picture(&[
        "...........",
        "...........",
        "A....S....B",
        "...........",
        "...........",
        "...........",
        "...........",
        "...........",
        "...........",
        "...........",
        "..........G",
    ]);
    let mut a = at('A');
    a.extend(at('B'));
    // From (2, 4), A is 4 steps away and B 6, but only B is on the way to G.
    let start = Cell::new(2, 4);
    let p = problem(
        g,
        start,
        vec![
            seg(vec![stage(region(a), TARGET0)], vec![], vec![]),
            seg(
                vec![stage(region(at('G')), Origin::Target { stage: 1 })],
                vec![],
                vec![],
            ),
        ],
    );
    let seq = plan_sequential(&p);
    let glob = plan_global(&p);
    assert!(seq.is_success() && glob.is_success());
    assert_eq!(seq.segments[0].stages[0].endpoint, Cell::new(2, 0));
    assert_eq!(glob.segments[0].stages[0].endpoint, Cell::new(2, 10));
    assert!(
        glob.cost + 1.0 < seq.cost,
        "global {} sequential {}",
        glob.cost,
        seq.cost
    );
    assert_eq!(glob.planner, "global");
}

#[test]
fn far_preference_moves_the_route_away() {
    // Open 21×21 room; going from the left to the right edge, a far() reference just above the
    // straight line pushes the route down.
    let n = 21;
    let g = Grid::new(n, true);
    let start = Cell::new(10, 0);
    let goal = Target::Position(Cell::new(10, 20));
    let base = problem(
        g,
        start,
        vec![seg(vec![stage(goal, TARGET0)], vec![], vec![])],
    );
    let straight = plan_sequential(&base);
    assert!(straight.trajectory.iter().all(|c| c.row == 10));
    let mut far = base.clone();
    far.resolution = 0.5; // σ_far = 3 cells
    far.segments[0].soft.push(SoftTerm {
        kind: SoftKind::Far {
            reference: Area::Cells(vec![Cell::new(8, 10)]),
        },
        weight: None,
        scope: None,
        origin: Origin::Constraint { index: 0, part: 0 },
    });
    let r = plan_sequential(&far);
    assert!(r.is_success());
    let mid = r.trajectory.iter().find(|c| c.col == 10).unwrap();
    assert!(
        mid.row > 10,
        "route passes the reference at row {}",
        mid.row
    );
    // The shortest baseline ignores the preference.
    let s = plan_shortest(&far);
    assert!(s.trajectory.iter().all(|c| c.row == 10));
}

#[test]
fn clearance_keeps_the_route_off_walls() {
    // A corridor between rows 0 and 14 (blocked): without clearance the route hugs the wall it
    // starts on; with it the route moves towards the middle row 7.
    let n = 30;
    let data: Vec<bool> = (0..n * n).map(|i| i / n != 0 && i / n < 14).collect();
    let g = Grid::from_vec(n, data).unwrap();
    let mut p = problem(
        g,
        Cell::new(1, 0),
        vec![seg(
            vec![stage(Target::Position(Cell::new(1, 29)), TARGET0)],
            vec![],
            vec![],
        )],
    );
    p.resolution = 0.1; // R_c = 7.5 cells
    p.profile.clearance = true;
    let r = plan_sequential(&p);
    assert!(
        r.trajectory.iter().any(|c| c.row >= 6),
        "{:?}",
        r.trajectory
    );
    let s = plan_shortest(&p);
    assert!(s.trajectory.iter().all(|c| c.row == 1));
}

#[test]
fn start_inside_target_is_a_zero_length_stage() {
    let (g, at) = picture(&["S..", "...", "..G"]);
    let mut t = at('S');
    t.extend(at('G'));
    let p = problem(
        g,
        at('S')[0],
        vec![seg(vec![stage(region(t), TARGET0)], vec![], vec![])],
    );
    let r = plan_sequential(&p);
    assert_eq!(r.trajectory, vec![at('S')[0]]);
    assert_eq!(r.segments[0].stages[0].cost, 0.0);
    let g = global::search_only(&p).unwrap();
    assert_eq!(g.cost, 0.0);
}

#[test]
fn turn_penalty_prefers_straighter_paths_in_the_mask() {
    // With a huge λ_s inside the mask the path to a diagonal goal makes one turn instead of many.
    let n = 9;
    let g = Grid::new(n, true);
    let mut p = problem(
        g,
        Cell::new(0, 0),
        vec![seg(
            vec![StageSpec {
                target: Target::Position(Cell::new(3, 8)),
                role: StageRole::Waypoint,
                smoothness: Some(Area::mask(Grid::new(n, true))),
                origin: TARGET0,
            }],
            vec![],
            vec![],
        )],
    );
    p.profile.smoothness_weight = 10.0;
    let turns = |path: &[Cell]| {
        path.windows(3)
            .filter(|w| {
                let d1 = (
                    w[1].row as i64 - w[0].row as i64,
                    w[1].col as i64 - w[0].col as i64,
                );
                let d2 = (
                    w[2].row as i64 - w[1].row as i64,
                    w[2].col as i64 - w[1].col as i64,
                );
                d1 != d2
            })
            .count()
    };
    let r = plan_sequential(&p);
    assert!(turns(&r.trajectory) <= 1, "{:?}", r.trajectory);
    let g = plan_global(&p);
    assert!(turns(&g.trajectory) <= 1);
    assert!(g.cost <= r.cost + 1e-9);
}

#[test]
fn invalid_profile_is_reported_not_panicked() {
    let (g, at) = picture(&["S..", "...", "..G"]);
    let mut p = problem(
        g,
        at('S')[0],
        vec![seg(vec![stage(region(at('G')), TARGET0)], vec![], vec![])],
    );
    p.profile.far_weight = f64::NAN;
    let f = plan_sequential(&p).failure.unwrap();
    assert_eq!(f.code(), "E0708");
    assert!(f.to_string().contains("far_weight"));
    p.profile.far_weight = 1.0;
    p.resolution = 0.0;
    assert_eq!(plan_global(&p).failure.unwrap().code(), "E0708");
}

#[test]
fn route_serializes_to_json() {
    let (g, at) = picture(&["S..", "...", "..G"]);
    let p = problem(
        g,
        at('S')[0],
        vec![seg(vec![stage(region(at('G')), TARGET0)], vec![], vec![])],
    );
    let r = plan_sequential(&p);
    let v = serde_json::to_value(&r).unwrap();
    assert_eq!(v["status"], "success");
    assert_eq!(v["trajectory"], serde_json::json!([[0, 0], [1, 1], [2, 2]]));
    assert_eq!(
        v["segments"][0]["stages"][0]["origin"],
        serde_json::json!({"kind": "target", "stage": 0})
    );
    let back: m2rc_planner::PlannedRoute = serde_json::from_value(v).unwrap();
    assert_eq!(back, r);
    let f = PlanFailure::GoalBlocked {
        segment: 0,
        stage: 1,
        origin: TARGET0,
        forbids: vec![AVOID],
    };
    let fv = serde_json::to_value(&f).unwrap();
    assert_eq!(fv["reason"], "goal_blocked");
}

/// The diagonal steps of `route` that pass a corner of one of `cells`.
fn corner_touches(route: &[Cell], cells: &[Cell]) -> Vec<(Cell, Cell)> {
    route
        .windows(2)
        .filter(|w| {
            let (a, b) = (w[0], w[1]);
            a.row != b.row
                && a.col != b.col
                && (cells.contains(&Cell::new(b.row, a.col))
                    || cells.contains(&Cell::new(a.row, b.col)))
        })
        .map(|w| (w[0], w[1]))
        .collect()
}

#[test]
fn hard_constraint_only_profiles_keep_off_the_corners_of_avoided_cells() {
    // The shortest way from S to G steps diagonally past A's corner, which the evaluator's
    // segment test counts as entering the avoided cell.
    let (g, at) = picture(&["..G", ".A.", "S.."]);
    let mut p = problem(
        g,
        at('S')[0],
        vec![seg(
            vec![stage(region(at('G')), TARGET0)],
            vec![Forbid {
                cells: Area::Cells(at('A')),
                origin: AVOID,
            }],
            vec![],
        )],
    );
    // The reference rule tests walls only: the route clips A's corner.
    let reference = plan_sequential(&p);
    assert!(reference.is_success());
    assert!((reference.cost - (2.0 + 2f64.sqrt())).abs() < 1e-9);
    assert!(!corner_touches(&reference.trajectory, &at('A')).is_empty());
    // Every hard-constraint-only planning keeps off it, at the cost of a longer route.
    let shortest = plan_shortest(&p);
    p.profile = CostProfile {
        clearance: false,
        ..CostProfile::hard_only()
    };
    let hard_only = plan_sequential(&p);
    p.profile = CostProfile::shortest();
    let global = plan_global(&p);
    for (name, r) in [
        ("shortest", &shortest),
        ("hard_only", &hard_only),
        ("global shortest", &global),
    ] {
        assert!(r.is_success(), "{name}: {:?}", r.failure);
        assert_eq!(r.trajectory.first(), Some(&at('S')[0]), "{name}");
        assert_eq!(r.trajectory.last(), Some(&at('G')[0]), "{name}");
        assert_eq!(
            corner_touches(&r.trajectory, &at('A')),
            vec![],
            "{name}: {:?}",
            r.trajectory
        );
    }
    assert!(CostProfile::shortest().avoid_corners && CostProfile::hard_only().avoid_corners);
    assert!(!CostProfile::reference().avoid_corners);
}
