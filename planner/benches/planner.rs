//! Planner benchmarks (criterion; `cargo bench -p m2rc-planner`).
//!
//! * `astar/*`: one long single-goal query; throughput is reported in expansions per second. The
//!   same query runs through our flat-array A* and through `pathfinding::astar` on the same graph,
//!   the same heuristic table and integer-scaled costs (×1000, diagonal 1414, Φ rounded), so the
//!   two rates compare directly.
//! * `plan/*`: a complete four-stage plan (two segments, an avoid region, near/far terms and the
//!   always-on clearance term) from a `PlanProblem`, i.e. including every distance transform.
//!
//! * `full_plan/*`: what a user waits for after grounding: `lower` of a RouteIR grounded from a real
//!   `.m2r` program (four planned stages; near, far, relative and clearance preferences, an avoid
//!   region, spatial and stage scopes) plus the sequential plan, on fixture house 149; cold (map
//!   indexed inside the call) and with a per-map `MapContext` built once.
//!
//! * `ltl/house_149`: the LTL backend on a Hard-sized program with hard constraints only (four
//!   destinations, two stage-scoped and two global avoids: 8 atoms): automaton construction from
//!   the problem's formula, product-graph planning, and the global RouteIR planner on the same
//!   problem (shortest profile: no soft terms, no clearance), so the two planners compare directly.
//!
//! Maps: the largest house of `../shared/procthor/fixtures` imported at 0.05 m when the importer can
//! read it, and a synthetic 700×700 house (walls, doors, furniture) that always exists.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use m2rc_planner::astar::{AStar, Heuristic, Outcome, Query, Space};
use m2rc_planner::layout::{Layout, MOVES, NO_HEADING};
use m2rc_planner::{
    Area, CostProfile, Forbid, Origin, PlanProblem, SegmentSpec, SoftKind, SoftTerm, StageRole,
    StageSpec, Target, compile, costfield, plan_global, plan_sequential,
};
use m2rc_stdlib::field;
use m2rc_stdlib::grid::{Cell, Grid};
use std::collections::VecDeque;
use std::hint::black_box;
use std::path::Path;

struct Scene {
    name: String,
    n: usize,
    traversable: Vec<bool>,
    obstacles: Vec<bool>,
    /// Room id per cell (0 = none) for building targets.
    rooms: Vec<u32>,
    room_ids: Vec<u32>,
    start: Cell,
}

/// A deterministic 700×700 house: 3×3 rooms behind 4-cell walls, one 18-cell door per shared
/// wall, and furniture blocks in every room.
fn synthetic_house() -> Scene {
    let n = 700;
    let mut occ = vec![true; n * n];
    let mut rooms = vec![0u32; n * n];
    let (lo, hi) = (20usize, 680usize);
    let size = (hi - lo) / 3;
    for i in 0..3 {
        for j in 0..3 {
            let (r0, c0) = (lo + i * size + 4, lo + j * size + 4);
            for r in r0..lo + (i + 1) * size {
                for c in c0..lo + (j + 1) * size {
                    occ[r * n + c] = false;
                    rooms[r * n + c] = (i * 3 + j + 1) as u32;
                }
            }
        }
    }
    // Doors.
    for i in 0..3 {
        for j in 0..3 {
            let (rm, cm) = (lo + i * size + size / 2, lo + j * size + size / 2);
            if j < 2 {
                let c = lo + (j + 1) * size;
                for r in rm - 9..rm + 9 {
                    for cc in c..c + 4 {
                        occ[r * n + cc] = false;
                    }
                }
            }
            if i < 2 {
                let r = lo + (i + 1) * size;
                for c in cm - 9..cm + 9 {
                    for rr in r..r + 4 {
                        occ[rr * n + c] = false;
                    }
                }
            }
        }
    }
    // Furniture: an LCG places blocks away from the doors' rows and columns.
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut next = |m: usize| {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 33) as usize) % m
    };
    let mut obstacles = occ.clone();
    for i in 0..3 {
        for j in 0..3 {
            for _ in 0..7 {
                let (h, w) = (10 + next(30), 10 + next(40));
                let r = lo + i * size + 30 + next(size - 80);
                let c = lo + j * size + 30 + next(size - 80);
                for rr in r..r + h {
                    for cc in c..c + w {
                        occ[rr * n + cc] = true;
                        obstacles[rr * n + cc] = true;
                    }
                }
            }
        }
    }
    let traversable: Vec<bool> = occ.iter().map(|o| !o).collect();
    let start = Cell::new((lo + 40) as u32, (lo + 40) as u32);
    Scene {
        name: "synthetic_700".into(),
        n,
        traversable,
        obstacles,
        rooms,
        room_ids: (1..=9).collect(),
        start,
    }
}

/// The largest fixture house that imports, if any.
fn fixture_house() -> Option<Scene> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/procthor/fixtures");
    let mut best: Option<m2rc_stdlib::map::SemanticMap> = None;
    let mut entries: Vec<_> = std::fs::read_dir(&dir)
        .ok()?
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .collect();
    entries.sort();
    for path in entries {
        let Some(p) = path.to_str() else { continue };
        match m2rc_stdlib::load::load_map(p) {
            Ok(m) => {
                let free = |m: &m2rc_stdlib::map::SemanticMap| {
                    m.occupancy.data().iter().filter(|&&o| o == 0).count()
                };
                if best.as_ref().is_none_or(|b| free(&m) > free(b)) {
                    best = Some(m);
                }
            }
            Err(e) => eprintln!("skipping {p}: {e}"),
        }
    }
    let m = best?;
    let n = m.n();
    let traversable: Vec<bool> = m.occupancy.data().iter().map(|&o| o == 0).collect();
    let door: Vec<u32> = m
        .objects
        .iter()
        .filter(|o| o.category == "doorway" || o.category == "doorframe")
        .map(|o| o.id)
        .collect();
    let obstacles = m
        .occupancy
        .data()
        .iter()
        .zip(m.object_layer.data())
        .map(|(&o, &obj)| o != 0 || (obj != 0 && !door.contains(&obj)))
        .collect();
    let start = m
        .start
        .filter(|c| traversable[c.row as usize * n + c.col as usize])
        .or_else(|| {
            traversable
                .iter()
                .position(|t| *t)
                .map(|i| Cell::new((i / n) as u32, (i % n) as u32))
        })?;
    Some(Scene {
        name: format!("{} ({n}x{n})", m.map_id),
        n,
        traversable,
        obstacles,
        rooms: m.room_layer.data().to_vec(),
        room_ids: m.rooms.iter().map(|r| r.id).collect(),
        start,
    })
}

/// The reachable cell farthest (in BFS steps) from the start: the longest query on the map.
fn farthest(scene: &Scene) -> usize {
    let n = scene.n;
    let mut seen = vec![false; n * n];
    let s = scene.start.row as usize * n + scene.start.col as usize;
    let mut q = VecDeque::from([s]);
    seen[s] = true;
    let mut last = s;
    while let Some(u) = q.pop_front() {
        last = u;
        for (dr, dc) in MOVES {
            let (r, c) = ((u / n) as i64 + dr as i64, (u % n) as i64 + dc as i64);
            if r < 0 || c < 0 || r >= n as i64 || c >= n as i64 {
                continue;
            }
            let v = r as usize * n + c as usize;
            if !seen[v] && scene.traversable[v] {
                seen[v] = true;
                q.push_back(v);
            }
        }
    }
    last
}

struct Prepared {
    layout: Layout,
    trav: Vec<bool>,
    goal: Vec<bool>,
    h: Vec<f64>,
    phi: Vec<f64>,
    start: usize,
}

fn prepare_query(scene: &Scene) -> Prepared {
    let n = scene.n;
    let l = Layout::new(n);
    let g = farthest(scene);
    let mut goal = vec![false; n * n];
    goal[g] = true;
    let h = l.pad(&field::distances(&goal, n), 0.0);
    let profile = CostProfile::reference();
    let od = field::squared_distances(&scene.obstacles, n);
    let trav = l.pad(&scene.traversable, false);
    let ctx = costfield::FieldContext {
        n,
        resolution: 0.05,
        profile: &profile,
        obstacle_sq: &od,
        runs: &[],
    };
    let phi = l.pad(&costfield::clearance_field(&ctx), 0.0);
    Prepared {
        layout: l,
        trav,
        goal: l.pad(&goal, false),
        h,
        phi,
        start: l.idx(scene.start),
    }
}

fn ours(p: &Prepared, astar: &mut AStar, with_phi: bool) -> u64 {
    let space = Space {
        layout: p.layout,
        traversable: &p.trav,
        allowed: &p.trav,
        phi: with_phi.then_some(&p.phi[..]),
    };
    let q = Query {
        start: p.start,
        goal: &p.goal,
        heuristic: Heuristic::Table(&p.h),
        smooth: None,
        initial_heading: NO_HEADING,
        budget: 0,
    };
    match astar.search(space, q) {
        Outcome::Found(f) => f.expansions,
        other => panic!("benchmark query has no path: {other:?}"),
    }
}

/// `pathfinding::astar` on the same padded graph; returns (expansions, cost).
fn theirs(p: &Prepared, with_phi: bool) -> (u64, u64) {
    let offs = p.layout.offsets();
    let w = p.layout.w as isize;
    let phi_i: Vec<u64> = p.phi.iter().map(|v| (v * 1000.0).round() as u64).collect();
    let h_i: Vec<u64> = p.h.iter().map(|v| (v * 1000.0).floor() as u64).collect();
    let mut expansions = 0u64;
    let res = pathfinding::prelude::astar(
        &(p.start as u32),
        |&u| {
            expansions += 1;
            let u = u as usize;
            let trav = &p.trav;
            let phi_i = &phi_i;
            (0..8).filter_map(move |k| {
                let v = (u as isize + offs[k]) as usize;
                if !trav[v] {
                    return None;
                }
                if k >= 4 {
                    let (dr, dc) = MOVES[k];
                    if !trav[(u as isize + dr as isize * w) as usize]
                        || !trav[(u as isize + dc as isize) as usize]
                    {
                        return None;
                    }
                }
                let step = if k >= 4 { 1414 } else { 1000 };
                Some((v as u32, step + if with_phi { phi_i[v] } else { 0 }))
            })
        },
        |&u| h_i[u as usize],
        |&u| p.goal[u as usize],
    );
    (expansions, res.map(|r| r.1).unwrap_or(0))
}

fn plan_problem(scene: &Scene) -> PlanProblem {
    let n = scene.n;
    let room = |id: u32| {
        Area::mask(Grid::from_vec(n, scene.rooms.iter().map(|&r| r == id).collect()).unwrap())
    };
    let ids = &scene.room_ids;
    let pick = |k: usize| ids[k % ids.len()];
    let cells_of = |id: u32| -> Vec<Cell> {
        scene
            .rooms
            .iter()
            .enumerate()
            .filter(|(i, r)| **r == id && scene.traversable[*i])
            .map(|(i, _)| Cell::new((i / n) as u32, (i % n) as u32))
            .collect()
    };
    // A small "object": a 6×6 block at the centre of a room's traversable cells.
    let object_in = |id: u32| -> (Vec<Cell>, [f64; 2]) {
        let c = cells_of(id);
        let m = c[c.len() / 2];
        let fp: Vec<Cell> = (0..6)
            .flat_map(|dr| (0..6).map(move |dc| Cell::new(m.row + dr, m.col + dc)))
            .collect();
        (fp, [m.row as f64 + 2.5, m.col as f64 + 2.5])
    };
    let (fp_a, ca) = object_in(pick(2));
    let (fp_b, _) = object_in(pick(1));
    let (fp_c, cc) = object_in(pick(5));
    let stage = |target, role| StageSpec {
        target,
        role,
        smoothness: None,
        origin: Origin::Unknown,
    };
    let soft = |kind, scope| SoftTerm {
        kind,
        weight: None,
        scope,
        origin: Origin::Unknown,
    };
    let seg1 = SegmentSpec {
        stages: vec![
            stage(Target::Room(room(pick(1))), StageRole::Pass),
            stage(
                Target::Object {
                    footprint: fp_a.clone(),
                    room: Some(room(pick(2))),
                    center: ca,
                },
                StageRole::Destination,
            ),
        ],
        forbidden: vec![Forbid {
            cells: Area::Cells(fp_b.clone()),
            origin: Origin::Unknown,
        }],
        soft: vec![
            soft(
                SoftKind::Near {
                    reference: Area::Cells(fp_a.clone()),
                },
                Some(room(pick(2))),
            ),
            soft(
                SoftKind::Far {
                    reference: Area::Cells(fp_b),
                },
                None,
            ),
        ],
    };
    let seg2 = SegmentSpec {
        stages: vec![
            stage(Target::Room(room(pick(4))), StageRole::Pass),
            stage(
                Target::Object {
                    footprint: fp_c.clone(),
                    room: Some(room(pick(5))),
                    center: cc,
                },
                StageRole::Destination,
            ),
        ],
        forbidden: Vec::new(),
        soft: vec![soft(
            SoftKind::Far {
                reference: Area::Cells(fp_a),
            },
            Some(room(pick(4))),
        )],
    };
    let obstacles = Grid::from_vec(n, scene.obstacles.clone()).unwrap();
    PlanProblem {
        traversable: Grid::from_vec(n, scene.traversable.clone()).unwrap(),
        obstacles: Some(obstacles),
        resolution: 0.05,
        start: scene.start,
        segments: vec![seg1, seg2],
        profile: CostProfile::reference(),
        map_fields: None,
    }
}

fn benches(c: &mut Criterion) {
    let mut scenes = vec![synthetic_house()];
    if let Some(s) = fixture_house() {
        scenes.insert(0, s);
    }
    for scene in &scenes {
        let p = prepare_query(scene);
        let mut astar = AStar::new();
        let mut group = c.benchmark_group(format!("astar/{}", scene.name));
        group.sample_size(20);
        for with_phi in [false, true] {
            let label = if with_phi {
                "clearance_field"
            } else {
                "zero_field"
            };
            let exp = ours(&p, &mut astar, with_phi);
            let (their_exp, their_cost) = theirs(&p, with_phi);
            eprintln!(
                "[{}] {label}: ours {exp} expansions; pathfinding {their_exp} expansions, cost {:.3}",
                scene.name,
                their_cost as f64 / 1000.0
            );
            group.throughput(Throughput::Elements(exp));
            group.bench_function(BenchmarkId::new("m2rc", label), |b| {
                b.iter(|| black_box(ours(&p, &mut astar, with_phi)))
            });
            group.throughput(Throughput::Elements(their_exp));
            group.bench_function(BenchmarkId::new("pathfinding", label), |b| {
                b.iter(|| black_box(theirs(&p, with_phi)))
            });
        }
        group.finish();

        let problem = plan_problem(scene);
        let r = plan_sequential(&problem);
        eprintln!(
            "[{}] 4-stage plan: {:?}, {:.2} m, cost {:.1}, {} expansions",
            scene.name, r.status, r.length_m, r.cost, r.expansions
        );
        let mut group = c.benchmark_group(format!("plan/{}", scene.name));
        group.sample_size(20);
        group.bench_function("sequential_4_stage", |b| {
            b.iter(|| black_box(plan_sequential(&problem)))
        });
        group.bench_function("prepare_and_compile_only", |b| {
            b.iter(|| {
                let prep = compile::prepare(&problem).ok();
                let segs: Vec<_> = prep
                    .iter()
                    .flat_map(|prep| {
                        (0..2).map(|i| {
                            compile::compile_segment(&problem, prep, i, &problem.segments[i])
                                .is_ok()
                        })
                    })
                    .collect();
                black_box(segs)
            })
        });
        group.sample_size(10);
        group.bench_function("global_4_stage", |b| {
            b.iter(|| black_box(plan_global(&problem)))
        });
        group.finish();
    }
}

/// House 149 of the fixtures, the largest, at 0.05 m.
const HOUSE: &str = "procthor10k_uniform_hard_val_150_149.json";

/// A real instruction on house 149 (whose start reaches only the start bathroom and one bedroom):
/// four planned stages, every soft-term kind, an avoid region, spatial and stage scopes.
const PROGRAM: &str = include_str!("house149_tour.m2r");

/// House 149 and `program` grounded on it: `None` when the fixtures are not beside the repository.
fn grounded_on_house_149(
    program: &str,
) -> Option<(m2rc_stdlib::map::SemanticMap, m2rc_compiler::ir::RouteIr)> {
    use m2rc_compiler::check::check;
    use m2rc_compiler::eval::{GroundOptions, ground_checked};
    use m2rc_stdlib::query::MapQuery;
    use m2rc_stdlib::vocab::Vocabulary;

    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/procthor/fixtures")
        .join(HOUSE);
    let Ok(map) = m2rc_stdlib::load::load_map(&path.to_string_lossy()) else {
        eprintln!("fixture house {HOUSE} not found beside the repository; skipping");
        return None;
    };
    let checked = check(program, &Vocabulary::from_map(&map));
    assert!(!checked.has_errors(), "{:#?}", checked.diagnostics);
    let q = MapQuery::new(&map);
    let g = ground_checked(&checked, program, &q, &GroundOptions::default());
    assert!(
        !g.problems.iter().any(|p| p.is_error()),
        "{:#?}",
        g.problems
    );
    let ir = g.ir.expect("the bench program grounds on house 149");
    Some((map, ir))
}

fn full_plan(c: &mut Criterion) {
    use m2rc_planner::context::MapContext;
    use m2rc_planner::lower::{lower, lower_with};

    let Some((map, ir)) = grounded_on_house_149(PROGRAM) else {
        return;
    };
    let profile = CostProfile::reference();
    let problem = lower(&ir, &map, profile.clone()).expect("lowers");
    let r = plan_sequential(&problem);
    assert!(r.is_success(), "{:?}", r.failure);
    eprintln!(
        "[house 149] full plan: {:?}, {} segments, {} stages, {:.2} m, cost {:.3}, {} expansions",
        r.status,
        r.segments.len(),
        r.segments.iter().map(|s| s.stages.len()).sum::<usize>(),
        r.length_m,
        r.cost,
        r.expansions
    );
    let mut group = c.benchmark_group("full_plan/house_149");
    group.sample_size(20);
    // Cold: the map is indexed and every field computed inside the timed call.
    group.bench_function("lower_and_plan_sequential", |b| {
        b.iter(|| {
            let p = lower(black_box(&ir), &map, profile.clone()).expect("lowers");
            black_box(plan_sequential(&p))
        })
    });
    // Warm: one context per map, as in the re-plan loop, the runner and the language server.
    let ctx = MapContext::new(&map).expect("indexes");
    group.bench_function("lower_with_context_and_plan_sequential", |b| {
        b.iter(|| {
            let p = lower_with(black_box(&ir), &map, &ctx, profile.clone()).expect("lowers");
            black_box(plan_sequential(&p))
        })
    });
    group.finish();
}

/// Four destinations, two stage-scoped and two global avoids on house 149: 8 LTL atoms.
const HARD_PROGRAM: &str = include_str!("house149_hard.m2r");

fn ltl_vs_global(c: &mut Criterion) {
    use m2rc_compiler::ltl::Dfa;
    use m2rc_planner::context::MapContext;
    use m2rc_planner::lower::lower_with;
    use m2rc_planner::product_lower::{plan_ltl, problem_ltl};

    let Some((map, ir)) = grounded_on_house_149(HARD_PROGRAM) else {
        return;
    };
    let ctx = MapContext::new(&map).expect("indexes");
    let problem = lower_with(&ir, &map, &ctx, CostProfile::shortest()).expect("lowers");
    let lt = problem_ltl(&problem);
    let dfa = Dfa::build(&lt.formula, &lt.names, true).expect("builds");
    let (product, global) = (plan_ltl(&problem), plan_global(&problem));
    assert!(product.is_success(), "{:?}", product.failure);
    assert!(global.is_success(), "{:?}", global.failure);
    eprintln!(
        "[house 149] {} atoms, {} automaton states; product {:.2} m ({} expansions), global {:.2} m ({} expansions)",
        lt.names.len(),
        dfa.states(),
        product.length_m,
        product.expansions,
        global.length_m,
        global.expansions
    );
    let mut group = c.benchmark_group("ltl/house_149");
    group.bench_function("dfa_8_atoms", |b| {
        b.iter(|| black_box(Dfa::build(black_box(&lt.formula), &lt.names, true)))
    });
    group.sample_size(10);
    group.bench_function("product_plan", |b| {
        b.iter(|| black_box(plan_ltl(black_box(&problem))))
    });
    group.bench_function("global_plan_same_hard_constraints", |b| {
        b.iter(|| black_box(plan_global(black_box(&problem))))
    });
    group.finish();
}

criterion_group!(planner, benches, full_plan, ltl_vs_global);
criterion_main!(planner);
