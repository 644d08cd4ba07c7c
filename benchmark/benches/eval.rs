//! Evaluator throughput: 1,000 synthetic episodes on the largest real ProcTHOR fixture house,
//! with no caches (the map's clearance field and move table are rebuilt inside every timed run).
//!
//! `cargo bench -p m2rc-benchmark --bench eval`. The `eval_1000_episodes` figure is the time for
//! the whole batch on all cores (rayon), the benchmark's "1,000 episodes under 30 s" target.

use criterion::{Criterion, criterion_group, criterion_main};
use m2rc_benchmark::episode::{
    ConstraintKind, Episode, HardConstraint, ReferenceRegion, Scope, Shape, SoftConstraint,
};
use m2rc_benchmark::metrics::{EvalMap, EvalOptions, evaluate_or_worst_case};
use m2rc_stdlib::map::SemanticMap;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::hint::black_box;
use std::time::{Duration, Instant};

const HOUSE: &str = "procthor10k_uniform_hard_val_150_149.json";

fn load_house() -> SemanticMap {
    let path = format!(
        "{}/../../shared/procthor/fixtures/{HOUSE}",
        env!("CARGO_MANIFEST_DIR")
    );
    m2rc_stdlib::load::load_map(&path).unwrap_or_else(|e| panic!("cannot load {path}: {e}"))
}

fn circle(id: String, kind: ConstraintKind, c: [i64; 2], r: f64) -> HardConstraint {
    let mut h = HardConstraint::freeform(&id, kind, Vec::new());
    h.shape = Shape::Circle;
    h.center = Some([c[0] as f64, c[1] as f64]);
    h.radius = Some(r);
    h.width = Some(2.0 * r);
    h.height = Some(2.0 * r);
    h.cells = Some(Vec::new());
    h
}

/// A dense 8-connected polyline through `stops` (not necessarily collision-free, like a weak
/// method's output).
fn dense_route(stops: &[[i64; 2]]) -> Vec<[i64; 2]> {
    let mut out = vec![stops[0]];
    for w in stops.windows(2) {
        let (mut p, q) = (w[0], w[1]);
        while p != q {
            p[0] += (q[0] - p[0]).signum();
            p[1] += (q[1] - p[1]).signum();
            out.push(p);
        }
    }
    out
}

fn synth_episodes(map: &SemanticMap, count: usize) -> Vec<(Episode, Vec<[i64; 2]>)> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let free: Vec<[i64; 2]> = map
        .occupancy
        .iter_cells()
        .filter(|(_, v)| **v == 0)
        .map(|(c, _)| [c.row as i64, c.col as i64])
        .collect();
    let objects: Vec<&m2rc_stdlib::map::Object> = map
        .objects
        .iter()
        .filter(|o| !o.footprint.is_empty())
        .collect();
    let footprint = |o: &m2rc_stdlib::map::Object| -> Vec<[i64; 2]> {
        o.footprint
            .iter()
            .map(|c| [c.row as i64, c.col as i64])
            .collect()
    };
    (0..count)
        .map(|e| {
            let k = rng.random_range(2..=5usize);
            let stops: Vec<[i64; 2]> = (0..k)
                .map(|_| free[rng.random_range(0..free.len())])
                .collect();
            let mut hard: Vec<HardConstraint> = stops
                .iter()
                .enumerate()
                .map(|(i, &s)| {
                    let mut c = circle(format!("p{i}"), ConstraintKind::MustPass, s, 20.0);
                    c.order = Some(i as i64 + 1);
                    c
                })
                .collect();
            if rng.random_bool(0.3) {
                let mut a = circle(
                    "avoid".into(),
                    ConstraintKind::MustAvoid,
                    free[rng.random_range(0..free.len())],
                    8.0,
                );
                a.scope = Some(if rng.random_bool(0.5) {
                    Scope::global()
                } else {
                    Scope::between(1, 2)
                });
                hard.push(a);
            }
            let center = stops[1];
            let region = |t: &str| SoftConstraint {
                constraint_id: Some(format!("{t}_{e}")),
                preference_type: Some(t.to_string()),
                shape: Some(Shape::Rectangle),
                center: Some([center[0] as f64, center[1] as f64]),
                width: Some(60.0),
                height: Some(60.0),
                cells: Some(Vec::new()),
                ..SoftConstraint::default()
            };
            let oa = objects[rng.random_range(0..objects.len())];
            let ob = objects[rng.random_range(0..objects.len())];
            let mut soft = vec![SoftConstraint {
                constraint_id: Some("__global_clearance__".into()),
                preference_type: Some("clearance".into()),
                ..SoftConstraint::default()
            }];
            let mut near = region("near_preference");
            near.reference_region = Some(ReferenceRegion {
                cells: Some(footprint(oa)),
                ..ReferenceRegion::default()
            });
            let mut rel = region("relative_preference");
            rel.reference_regions = Some(vec![
                ReferenceRegion {
                    cells: Some(footprint(oa)),
                    ..ReferenceRegion::default()
                },
                ReferenceRegion {
                    cells: Some(footprint(ob)),
                    ..ReferenceRegion::default()
                },
            ]);
            rel.scope = Some(Scope::between(1, 2));
            let mut shape = region("path_shape_preference");
            shape.reference_trajectory = Some(dense_route(&[stops[0], stops[1]]));
            soft.extend([near, rel, shape]);
            let episode = Episode {
                difficulty_level: Some(if e % 10 < 7 { "easy" } else { "hard" }.into()),
                hard_constraints: hard,
                soft_constraints: soft,
                ..Episode::default()
            };
            (episode, dense_route(&stops))
        })
        .collect()
}

fn run_batch(map: &SemanticMap, episodes: &[(Episode, Vec<[i64; 2]>)]) -> f64 {
    let eval = EvalMap::from_semantic_map(map);
    let opts = EvalOptions::default();
    episodes
        .par_iter()
        .map(|(ep, route)| evaluate_or_worst_case(route, ep, &eval, &opts).segment_wise_spl)
        .sum()
}

fn bench(c: &mut Criterion) {
    let map = load_house();
    let episodes = synth_episodes(&map, 1000);
    let t = Instant::now();
    let total = run_batch(&map, &episodes);
    eprintln!(
        "map {}x{}: 1000 episodes evaluated in {:.2} s on {} threads (mean SPL {:.3})",
        map.n(),
        map.n(),
        t.elapsed().as_secs_f64(),
        rayon::current_num_threads(),
        total / 1000.0
    );
    let mut group = c.benchmark_group("evaluator");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(60));
    group.bench_function("eval_1000_episodes", |b| {
        b.iter(|| black_box(run_batch(&map, &episodes)))
    });
    group.finish();
    let one = &episodes[..1];
    c.bench_function("eval_one_episode_with_map_setup", |b| {
        b.iter(|| black_box(run_batch(&map, one)))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
