//! Runner behaviour on a real (one-scene) suite: records in the reference layout, resumption after
//! lost or torn records with identical results, and sharding plus merge equal to a single run.

use m2rc_benchmark::methods::method_by_name;
use m2rc_benchmark::runner::{self, RunOptions, Shard, read_records};
use m2rc_benchmark::suite::{ProcthorTools, SuiteConfig, SuiteManifest, build_suite};
use m2rc_stdlib::import::{AssetDb, ImportOptions};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn shared() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/procthor")
}

fn build(dir: &Path) -> SuiteManifest {
    let tools = ProcthorTools {
        assets: Some(AssetDb::load(&shared().join("assets/asset-database.json")).unwrap()),
        import: ImportOptions::default(),
        validators: vec![method_by_name("shortest").unwrap()],
    };
    let config = SuiteConfig {
        name: "runner-test".into(),
        scenes: 1,
        dev_scenes: 0,
        episodes_per_scene: 4,
        hard_fraction: 0.25,
        seed: 3,
    };
    build_suite(&shared().join("fixtures"), &config, &tools, dir, &|_, _| {}).unwrap()
}

/// Every file under `dir` (relative path -> bytes).
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.insert(
                    p.strip_prefix(dir).unwrap().display().to_string(),
                    std::fs::read(&p).unwrap(),
                );
            }
        }
    }
    out
}

fn opts(suite: &Path, out: &Path, shard: Option<Shard>) -> RunOptions {
    RunOptions {
        suite: suite.to_path_buf(),
        out: out.to_path_buf(),
        shard,
        split: "eval".into(),
        progress: false,
    }
}

#[test]
fn resume_and_shards_reproduce_a_single_run() {
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("suite");
    let manifest = build(&suite);
    let n = manifest.episodes.len();
    assert!(n >= 3, "suite too small: {n}");
    let shortest = method_by_name("shortest").unwrap();

    let full = tmp.path().join("full");
    let s = runner::run(shortest.as_ref(), &opts(&suite, &full, None)).unwrap();
    assert_eq!((s.episodes, s.written, s.skipped), (n, n, 0));
    let records = read_records(&full).unwrap();
    assert_eq!(records.len(), n);
    for r in &records {
        assert_eq!(r["method"], "shortest");
        assert_eq!(r["metrics_summary"]["HCS"], 1.0, "{}", r["instruction_id"]);
        assert!(r["trajectory"].as_array().is_some_and(|t| t.len() > 1));
        assert!(r["metrics"]["details"].is_object());
    }
    // Reference layout: <out>/<map_id>/instruction_<id>.json
    let first = &manifest.episodes[0];
    assert!(
        full.join(&first.map_id)
            .join(format!("{}.json", first.instruction_id))
            .is_file()
    );
    let reference = snapshot(&full);

    // A second run finds everything done.
    let s = runner::run(shortest.as_ref(), &opts(&suite, &full, None)).unwrap();
    assert_eq!((s.written, s.skipped), (0, n));

    // Lose one record and tear another (as a kill during a non-atomic write would); resume.
    let e0 = &manifest.episodes[0];
    let e1 = &manifest.episodes[1];
    std::fs::remove_file(runner::record_path(&full, &e0.map_id, &e0.instruction_id)).unwrap();
    let torn = runner::record_path(&full, &e1.map_id, &e1.instruction_id);
    let bytes = std::fs::read(&torn).unwrap();
    std::fs::write(&torn, &bytes[..bytes.len() / 2]).unwrap();
    let s = runner::run(shortest.as_ref(), &opts(&suite, &full, None)).unwrap();
    assert_eq!((s.written, s.skipped), (2, n - 2));
    assert_eq!(snapshot(&full), reference);

    // Two shards, merged, equal the single run.
    let mut shard_dirs = Vec::new();
    let mut covered = 0;
    for k in 1..=2 {
        let d = tmp.path().join(format!("shard{k}"));
        let s = runner::run(
            shortest.as_ref(),
            &opts(&suite, &d, Some(Shard { index: k, count: 2 })),
        )
        .unwrap();
        covered += s.episodes;
        shard_dirs.push(d);
    }
    assert_eq!(covered, n);
    let merged = tmp.path().join("merged");
    let m = runner::merge(&shard_dirs, &merged).unwrap();
    assert_eq!(m.records, n);
    let mut a = snapshot(&merged);
    let mut b = reference.clone();
    // run.json differs only in bookkeeping (it names no shard after a merge either way).
    let (ma, mb) = (a.remove("run.json").unwrap(), b.remove("run.json").unwrap());
    assert_eq!(a, b);
    let (ma, mb): (serde_json::Value, serde_json::Value) = (
        serde_json::from_slice(&ma).unwrap(),
        serde_json::from_slice(&mb).unwrap(),
    );
    assert_eq!(ma["method"], mb["method"]);
    assert_eq!(ma["episodes"], mb["episodes"]);

    // A different method refuses to write into this run directory.
    let oracle = method_by_name("hard-only").unwrap();
    assert!(runner::run(oracle.as_ref(), &opts(&suite, &full, None)).is_err());
}

#[test]
fn shard_syntax_is_checked() {
    assert_eq!(
        "2/8".parse::<Shard>().unwrap(),
        Shard { index: 2, count: 8 }
    );
    for bad in ["0/8", "9/8", "1/0", "x/2", "3"] {
        assert!(bad.parse::<Shard>().is_err(), "{bad}");
    }
}
