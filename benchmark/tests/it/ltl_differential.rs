//! Differential test of the LTL backend against the RouteIR planners on real fixture houses.
//!
//! For every generated episode whose gold program, with its preferences removed, grounds to a
//! RouteIR of ordered destinations and avoid regions only, the LTL product planner and the global
//! RouteIR planner (on the same hard constraints: no soft terms, no clearance) must find routes of
//! the same optimal length (within one cell step) that score the same HCS on the episode's own
//! annotations.

use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::methods::oracle::strip_preferences;
use m2rc_benchmark::methods::{PreparedMap, method_by_name, start_cell};
use m2rc_benchmark::pipeline::{PipelineOptions, compile_and_plan_with};
use m2rc_benchmark::report::score::score;
use m2rc_benchmark::suite::{ProcthorTools, SuiteConfig, SuiteManifest, build_suite};
use m2rc_compiler::ir::ConstraintKind;
use m2rc_planner::{CostProfile, PlannerKind};
use m2rc_stdlib::import::{AssetDb, ImportOptions};
use std::path::PathBuf;

fn shared() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/procthor")
}

#[test]
fn ltl_planner_matches_the_global_planner_on_destinations_and_avoids() {
    if !shared().join("fixtures").exists() {
        eprintln!("fixture houses not found beside the repository; skipping");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let tools = ProcthorTools {
        assets: Some(AssetDb::load(&shared().join("assets/asset-database.json")).unwrap()),
        import: ImportOptions::default(),
        validators: vec![method_by_name("shortest").unwrap()],
    };
    let config = SuiteConfig {
        name: "ltl-differential".into(),
        scenes: 3,
        dev_scenes: 0,
        episodes_per_scene: 8,
        hard_fraction: 0.5,
        seed: 11,
    };
    let manifest: SuiteManifest = build_suite(
        &shared().join("fixtures"),
        &config,
        &tools,
        dir.path(),
        &|_, _| {},
    )
    .unwrap();
    let mut compared = 0;
    let mut with_avoids = 0;
    for scene in &manifest.scenes {
        let path = manifest.map_path(dir.path(), &scene.map_id).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let map = m2rc_stdlib::map::read_map_json(&bytes, "map").unwrap();
        let prepared = PreparedMap::new(map);
        for entry in manifest
            .episodes
            .iter()
            .filter(|e| e.map_id == scene.map_id)
        {
            let episode = Episode::read(&dir.path().join(&entry.file)).unwrap();
            let Some(gold) = episode.m2rc_gold_program.as_deref() else {
                continue;
            };
            let program = strip_preferences(gold).unwrap();
            let start = start_cell(&prepared.map, &episode).unwrap();
            let opts = |planner| PipelineOptions {
                planner,
                profile: CostProfile::shortest(),
                start: Some(start),
                ..PipelineOptions::default()
            };
            let ctx = prepared.planning().unwrap();
            let Ok(global) =
                compile_and_plan_with(&program, &prepared.map, ctx, &opts(PlannerKind::Global))
            else {
                continue;
            };
            let only_visits_and_avoids = global.ir.stages.iter().all(|s| s.passes.is_empty())
                && global
                    .ir
                    .constraints
                    .iter()
                    .all(|c| matches!(c.kind, ConstraintKind::Avoid { .. }));
            if !only_visits_and_avoids || !global.ir.route_bindings.is_empty() {
                continue;
            }
            let ltl = compile_and_plan_with(&program, &prepared.map, ctx, &opts(PlannerKind::Ltl))
                .unwrap_or_else(|d| panic!("{}: LTL planner failed: {d:?}", entry.file));
            let res = prepared.map.resolution();
            assert!(
                (ltl.route.length_m - global.route.length_m).abs()
                    <= res * std::f64::consts::SQRT_2 + 1e-9,
                "{}: LTL {} m, global {} m",
                entry.file,
                ltl.route.length_m,
                global.route.length_m
            );
            let hcs = |cells: &[m2rc_stdlib::grid::Cell]| {
                let traj: Vec<[i64; 2]> =
                    cells.iter().map(|c| [c.row as i64, c.col as i64]).collect();
                score(&traj, &episode, &prepared.eval).summary["HCS"].as_f64()
            };
            assert_eq!(
                hcs(&ltl.route.trajectory),
                hcs(&global.route.trajectory),
                "{}: HCS differs",
                entry.file
            );
            compared += 1;
            with_avoids += (!global.ir.constraints.is_empty()) as usize;
        }
    }
    eprintln!("compared {compared} episodes ({with_avoids} with avoid regions)");
    assert!(compared >= 5, "only {compared} episodes were comparable");
    assert!(with_avoids >= 1, "no compared episode had an avoid region");
}

/// Stages that return to the same place share its atom: twenty alternating `go bathroom` /
/// `go kitchen` stages are a formula over two atoms whose automaton is a chain, not one atom per
/// stage (whose guards double with every stage the route has passed).
#[test]
fn alternating_stages_share_two_atoms() {
    use m2rc_compiler::ltl::Dfa;
    use m2rc_planner::context::MapContext;
    use m2rc_planner::lower::lower_with;
    use m2rc_planner::product_lower::problem_ltl;
    let map = m2rc_stdlib::demo::demo_map().unwrap();
    let mut src = String::from(
        "let bathroom = rooms(bathroom).smallest()\nlet kitchen = rooms(kitchen).only()\nroute {\n",
    );
    for i in 0..20 {
        src.push_str(if i % 2 == 0 {
            "  go bathroom\n"
        } else {
            "  go kitchen\n"
        });
    }
    src.push_str("}\n");
    let compiled =
        m2rc_benchmark::pipeline::compile_and_plan(&src, &map, &PipelineOptions::default())
            .unwrap();
    let ctx = MapContext::new(&map).unwrap();
    let problem = lower_with(&compiled.ir, &map, &ctx, CostProfile::shortest()).unwrap();
    let lt = problem_ltl(&problem);
    assert_eq!(lt.names, vec!["t1", "t2"]);
    assert_eq!(lt.skeleton.visits.len(), 20);
    let dfa = Dfa::build(&lt.formula, &lt.names, true).unwrap();
    // Waiting for each of the 20 visits, done.
    assert_eq!(dfa.states(), 21);
    let planned = m2rc_planner::plan(&problem, PlannerKind::Ltl);
    assert!(planned.is_success(), "{:?}", planned.failure);
    assert_eq!(planned.segments.len(), 20);
}
