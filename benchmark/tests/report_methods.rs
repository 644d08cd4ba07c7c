//! The done criterion of the benchmark on a CI-sized suite of real houses: the oracle (gold
//! program -> compiler -> planner) scores HCS = 1 on every episode; the shortest baseline also
//! scores HCS = 1 but is measurably worse on Near, Far and Relative; and the report renders in
//! every format.

use m2rc_benchmark::methods::method_by_name;
use m2rc_benchmark::report::{self, load_runs, table};
use m2rc_benchmark::runner::{self, RunOptions};
use m2rc_benchmark::suite::{ProcthorTools, SuiteConfig, build_suite};
use m2rc_stdlib::import::{AssetDb, ImportOptions};
use std::path::PathBuf;

fn shared() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/procthor")
}

#[test]
fn oracle_is_perfect_and_shortest_loses_on_preferences() {
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("suite");
    let tools = ProcthorTools {
        assets: Some(AssetDb::load(&shared().join("assets/asset-database.json")).unwrap()),
        import: ImportOptions::default(),
        validators: vec![
            method_by_name("oracle").unwrap(),
            method_by_name("shortest").unwrap(),
        ],
    };
    let config = SuiteConfig {
        name: "report-test".into(),
        scenes: 2,
        dev_scenes: 0,
        episodes_per_scene: 5,
        hard_fraction: 0.4,
        seed: 11,
    };
    let manifest = build_suite(
        &shared().join("fixtures"),
        &config,
        &tools,
        &suite,
        &|_, _| {},
    )
    .unwrap();
    assert!(
        manifest.episodes.len() >= 6,
        "only {} episodes validated",
        manifest.episodes.len()
    );

    let mut dirs = Vec::new();
    for name in ["oracle", "hard-only", "shortest"] {
        let m = method_by_name(name).unwrap();
        let out = tmp.path().join(name);
        runner::run(
            m.as_ref(),
            &RunOptions {
                suite: suite.clone(),
                out: out.clone(),
                shard: None,
                split: "eval".into(),
                progress: false,
            },
        )
        .unwrap();
        dirs.push(out);
    }
    let runs = load_runs(&dirs).unwrap();
    for run in &runs {
        if run.method == "oracle" || run.method == "shortest" {
            for r in &run.records {
                assert_eq!(
                    r["metrics_summary"]["HCS"], 1.0,
                    "{} {}",
                    run.method, r["instruction_id"]
                );
            }
        }
    }
    let t = table::table(&runs);
    let row = |m: &str| {
        t.methods
            .iter()
            .find(|r| r.method == m)
            .unwrap()
            .overall
            .clone()
    };
    let (oracle, shortest) = (row("oracle"), row("shortest"));
    eprintln!("{}", table::markdown(&t));
    assert_eq!(oracle.hcs, Some(1.0));
    assert_eq!(shortest.hcs, Some(1.0));
    if let (Some(o), Some(s)) = (oracle.near, shortest.near) {
        assert!(o < s, "near: oracle {o} vs shortest {s}");
    }
    if let (Some(o), Some(s)) = (oracle.far, shortest.far) {
        assert!(o > s, "far: oracle {o} vs shortest {s}");
    }
    if let (Some(o), Some(s)) = (oracle.relative, shortest.relative) {
        assert!(o > s, "relative: oracle {o} vs shortest {s}");
    }
    assert!(
        oracle.near.is_some() || oracle.far.is_some() || oracle.relative.is_some(),
        "no soft preferences generated"
    );

    // JSON shape: {"methods": [{"method", "easy", "hard", "overall"}]} with the eight keys.
    let json: serde_json::Value = serde_json::from_str(&table::json(&t)).unwrap();
    let methods = json["methods"].as_array().unwrap();
    assert_eq!(methods.len(), 3);
    for m in methods {
        for block in ["easy", "hard", "overall"] {
            let keys: Vec<&String> = m[block].as_object().unwrap().keys().collect();
            assert_eq!(
                keys,
                table::KEYS
                    .iter()
                    .map(|k| k.to_string())
                    .collect::<Vec<_>>()
                    .iter()
                    .collect::<Vec<_>>()
            );
        }
    }
    let csv = table::csv(&t);
    assert_eq!(csv.lines().count(), 1 + 3 * 3);
    let md = report::markdown_report(&runs);
    assert!(
        md.contains("| oracle |")
            && md.contains("| shortest |")
            && md.contains("Human demonstrations are not available")
    );
    assert!(md.contains("Mean HCS by reference depth"));

    let plots = report::write_plots(&runs, &tmp.path().join("plots")).unwrap();
    assert_eq!(plots.len(), 3);
    for p in plots {
        assert_eq!(&std::fs::read(p).unwrap()[..4], b"\x89PNG");
    }
}
