//! `--llm gold` end to end on a real one-scene suite: every baseline writes a record for every
//! episode, offline, labelled, and the same bytes twice; where the gold descriptor grounds to the
//! annotated instances, the route passes every destination (HCS 1).

use m2rc_baselines::calls::ModelSetup;
use m2rc_benchmark::methods::method_by_name;
use m2rc_benchmark::runner::{self, RunOptions, read_records};
use m2rc_benchmark::suite::{ProcthorTools, SuiteConfig, SuiteManifest, build_suite};
use m2rc_stdlib::import::{AssetDb, ImportOptions};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn shared() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/procthor")
}

pub fn build(dir: &Path, episodes: usize) -> SuiteManifest {
    let tools = ProcthorTools {
        assets: Some(AssetDb::load(&shared().join("assets/asset-database.json")).unwrap()),
        import: ImportOptions::default(),
        validators: vec![method_by_name("shortest").unwrap()],
    };
    let config = SuiteConfig {
        name: "baselines-test".into(),
        scenes: 1,
        dev_scenes: 0,
        episodes_per_scene: episodes,
        hard_fraction: 0.25,
        seed: 5,
    };
    build_suite(&shared().join("fixtures"), &config, &tools, dir, &|_, _| {}).unwrap()
}

pub fn opts(suite: &Path, out: &Path) -> RunOptions {
    RunOptions {
        suite: suite.to_path_buf(),
        out: out.to_path_buf(),
        shard: None,
        split: "eval".into(),
        progress: false,
    }
}

fn gold() -> Arc<ModelSetup> {
    Arc::new(crate::support::gold_setup())
}

#[test]
fn gold_replies_run_every_episode_offline_and_deterministically() {
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("suite");
    let m = build(&suite, 4);
    assert!(m2rc_baselines::BASELINES.len() >= 2);
    for b in m2rc_baselines::BASELINES {
        let method = (b.make)(gold());
        let (one, two) = (
            tmp.path().join(format!("{}-1", b.name)),
            tmp.path().join(format!("{}-2", b.name)),
        );
        let s = runner::run(method.as_ref(), &opts(&suite, &one)).unwrap();
        assert_eq!((s.written, s.pending), (m.episodes.len(), 0), "{}", b.name);
        runner::run((b.make)(gold()).as_ref(), &opts(&suite, &two)).unwrap();
        let (r1, r2) = (read_records(&one).unwrap(), read_records(&two).unwrap());
        assert_eq!(r1, r2, "{}: same inputs, same records", b.name);
        assert_eq!(r1.len(), m.episodes.len());
        for r in &r1 {
            let block = &r[b.name];
            assert_eq!(block["gold_replies"], true, "{}", b.name);
            assert!(
                block["model"]
                    .as_str()
                    .unwrap()
                    .starts_with("[GOLD replies]")
            );
            assert!(
                block["calls"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .filter(|c| c.get("gold").is_some())
                    .all(|c| c["gold"] == true)
            );
            assert!(
                r["notes"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .any(|n| n.as_str().unwrap().contains("[GOLD replies]"))
            );
        }
    }
}

/// LIMP's gold: where every referent grounds to its annotated instance, the route ends near the
/// last destination (within LIMP's 1.2 m, which is not always inside the evaluator's region).
#[test]
fn limp_gold_reaches_the_annotated_destinations() {
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("suite");
    let m = build(&suite, 4);
    let out = tmp.path().join("limp");
    runner::run(
        m2rc_baselines::limp::make(gold()).as_ref(),
        &opts(&suite, &out),
    )
    .unwrap();
    let mut checked = 0;
    for r in read_records(&out).unwrap() {
        let entry = m
            .episodes
            .iter()
            .find(|e| e.map_id == r["map_dir"] && e.instruction_id == r["instruction_id"])
            .unwrap();
        let ep: Value =
            serde_json::from_slice(&std::fs::read(suite.join(&entry.file)).unwrap()).unwrap();
        let golds: Vec<String> = ep["hard_constraints"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|h| h["kind"] == "must_pass" && h["object_id"].is_u64())
            .map(|h| format!("object_{}", h["object_id"]))
            .collect();
        let grounded: Vec<String> = r["limp"]["groundings"]
            .as_object()
            .map(|g| {
                g.values()
                    .map(|v| v["instance"].as_str().unwrap().to_string())
                    .collect()
            })
            .unwrap_or_default();
        if r["status"] == "ok"
            && !golds.is_empty()
            && golds.iter().all(|g| grounded.contains(g))
            && ep["hard_constraints"]
                .as_array()
                .unwrap()
                .iter()
                .all(|h| h["kind"] == "must_pass")
        {
            checked += 1;
            // The route ends near (LIMP's 1.2 m) the last annotated destination's footprint.
            let path = m.map_path(&suite, &entry.map_id).unwrap();
            let map =
                m2rc_stdlib::map::read_map_json(&std::fs::read(&path).unwrap(), "map").unwrap();
            let last = golds
                .last()
                .unwrap()
                .trim_start_matches("object_")
                .parse::<u32>()
                .unwrap();
            let end = r["trajectory"].as_array().unwrap().last().unwrap();
            let end = m2rc_stdlib::grid::Cell::new(
                end[0].as_u64().unwrap() as u32,
                end[1].as_u64().unwrap() as u32,
            );
            let d = end.nearest_dist(&map.object(last).unwrap().footprint);
            assert!(
                d <= m2rc_baselines::limp::planner::NEAR_CELLS,
                "{}: {d}",
                r["instruction_id"]
            );
        }
    }
    assert!(
        checked >= 1,
        "at least one episode grounded to its annotations"
    );
}
