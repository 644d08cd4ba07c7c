//! What the `grounding2route` method costs per episode beyond the oracle's, with every model
//! reply cached: the prompt (built-in reference, scene catalog, worked examples), the cache
//! lookup (request body, key hash, file read, reply parse), code extraction and the repair loop's
//! bookkeeping (target: under 5 ms).
//!
//! * `method_only`: exactly that overhead: the scene catalog, the prompt and the repair loop
//!   around a cached reply, with a verifier that accepts at once (the compile and plan that the
//!   oracle does too are left out);
//! * `grounding2route_cached` and `oracle`: the whole episode both ways, compiling and planning
//!   the same program on the same warm map context. Their difference is the same overhead, but
//!   within the planner's run-to-run noise (tens of milliseconds), hence the first figure.
//!
//! `cargo bench -p m2rc-benchmark --bench method_overhead`.

use criterion::{Criterion, criterion_group, criterion_main};
use m2rc_benchmark::methods::grounding2route::lower_and_plan;
use m2rc_benchmark::pipeline::{PipelineOptions, compile_and_plan_with};
use m2rc_compiler::lower::{
    CatalogMode, Prompt, PromptOptions, RepairOptions, SceneCatalog, Verdict, run_episode,
};
use m2rc_llm::cache::ResponseCache;
use m2rc_llm::config::SimulatedSpec;
use m2rc_llm::{Exchange, SimulatedModel, Store};
use m2rc_planner::context::MapContext;
use std::hint::black_box;

const HOUSE: &str = "procthor10k_uniform_hard_val_150_149.json";
/// The planner benchmark's real instruction on house 149 (four stages, every preference kind).
const PROGRAM: &str = include_str!("../../planner/benches/house149_tour.m2r");
const INSTRUCTION: &str = "Go to the TV in the bedroom through the bathroom door, staying near \
    the table and clear of the chairs; then lie down on the bed, away from what stands beside it \
    and closer to the bed than to the dresser; then back to the sink, near the toilet. Keep away \
    from the sofa until the bed, and keep 40 cm from furniture.";

fn overhead(c: &mut Criterion) {
    let path = format!(
        "{}/../../shared/procthor/fixtures/{HOUSE}",
        env!("CARGO_MANIFEST_DIR")
    );
    let Ok(map) = m2rc_stdlib::load::load_map(&path) else {
        eprintln!("fixture house {HOUSE} not found beside the repository; skipping");
        return;
    };
    let ctx = MapContext::new(&map).expect("indexes");
    let pipeline = PipelineOptions::default();
    let prompt = PromptOptions {
        catalog: CatalogMode::Counts,
        examples: 5,
    };
    let repair = RepairOptions::default();
    let cache_dir = tempfile::tempdir().expect("temporary cache");
    let store = Store::new(Some(ResponseCache::new(cache_dir.path())), None, false);
    // Fault rate 0: the reply is the gold program, so both sides plan the same program.
    let spec = SimulatedSpec {
        fault_rate: 0.0,
        seed: 0,
    };
    let fetch = SimulatedModel::new(spec, PROGRAM, "bench/house149");
    let model = Exchange {
        store: &store,
        fetch: &fetch,
    };
    let method = || {
        lower_and_plan(
            &model,
            &map,
            &ctx,
            INSTRUCTION,
            "bench/house149",
            &prompt,
            &repair,
            &pipeline,
        )
    };
    let oracle = || compile_and_plan_with(PROGRAM, &map, &ctx, &pipeline);
    // Warm the cache: the first call fetches from the simulated model, every later one hits.
    let (_, trace) = method();
    assert!(trace.output.is_some(), "the gold program plans: {trace:#?}");
    assert!(oracle().is_ok());
    assert_eq!(store.stats().fetched, 1);

    let method_only = || {
        let catalog = SceneCatalog::from_map(&map, prompt.catalog);
        let first = Prompt::new(&map.map_id, &catalog, INSTRUCTION, &prompt);
        let mut accept = |_: &str| Verdict::Accepted(());
        run_episode(&model, &mut accept, &first, "bench/house149", &repair)
    };
    let once = method_only();
    assert!(
        once.output.is_some(),
        "the cached reply is accepted: {once:#?}"
    );
    assert_eq!(
        store.stats().fetched,
        1,
        "every timed reply comes from the cache"
    );

    let mut group = c.benchmark_group("method_overhead/house_149");
    group.bench_function("method_only", |b| b.iter(|| black_box(method_only())));
    group.sample_size(20);
    group.bench_function("grounding2route_cached", |b| b.iter(|| black_box(method())));
    group.bench_function("oracle", |b| b.iter(|| black_box(oracle().ok())));
    group.finish();
    assert_eq!(
        store.stats().fetched,
        1,
        "every timed reply came from the cache"
    );
}

criterion_group!(benches, overhead);
criterion_main!(benches);
