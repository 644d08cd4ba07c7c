//! A CI-sized suite from the real ProcTHOR houses: two scenes, a handful of episodes, validated by
//! the methods that must score HCS = 1 on their own annotation.

use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::methods::method_by_name;
use m2rc_benchmark::suite::{ProcthorTools, SuiteConfig, SuiteManifest, build_suite};
use m2rc_stdlib::import::{AssetDb, ImportOptions};
use std::path::PathBuf;

fn shared() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/procthor")
}

fn tools(validators: &[&str]) -> ProcthorTools {
    ProcthorTools {
        assets: Some(
            AssetDb::load(&shared().join("assets/asset-database.json")).expect("asset database"),
        ),
        import: ImportOptions::default(),
        validators: validators
            .iter()
            .map(|m| method_by_name(m).expect("method"))
            .collect(),
    }
}

fn small_config() -> SuiteConfig {
    SuiteConfig {
        name: "ci".into(),
        scenes: 2,
        dev_scenes: 0,
        episodes_per_scene: 5,
        hard_fraction: 0.4,
        seed: 7,
    }
}

#[test]
fn builds_a_small_suite_from_real_houses() {
    let dir = tempfile::tempdir().unwrap();
    let houses = shared().join("houses/procthor10k_uniform_hard_val_150.jsonl.gz");
    let m = build_suite(
        &houses,
        &small_config(),
        &tools(&["shortest"]),
        dir.path(),
        &|_, _| {},
    )
    .unwrap();
    assert_eq!(m.scenes.len(), 2);
    eprintln!("{}", serde_json::to_string_pretty(&m.scenes).unwrap());
    assert!(m.episodes.len() >= 8, "only {} episodes", m.episodes.len());
    for e in &m.episodes {
        let ep = Episode::read(&dir.path().join(&e.file)).unwrap();
        eprintln!(
            "{} {:?}: {}",
            e.instruction_id,
            e.difficulty,
            ep.instruction.as_deref().unwrap_or("")
        );
        eprintln!("{}", ep.m2rc_gold_program.as_deref().unwrap_or(""));
    }
    let reread = SuiteManifest::read(dir.path()).unwrap();
    assert_eq!(reread, m);
}
