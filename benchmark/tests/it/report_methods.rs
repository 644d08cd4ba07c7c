//! The done criterion of the benchmark on a CI-sized suite of real houses: the oracle (gold
//! program -> compiler -> planner) scores HCS = 1 on every episode; the shortest baseline also
//! scores HCS = 1 but is worse on Near, Far, Relative and Path-Shape over the suite and on most
//! of each kind's constraints; and the report renders in every format.

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
        scenes: 4,
        dev_scenes: 0,
        episodes_per_scene: 10,
        hard_fraction: 0.4,
        seed: 2,
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
        manifest.episodes.len() >= 36,
        "only {} episodes validated",
        manifest.episodes.len()
    );
    // Must-avoids on object areas are generated with an annotation that matches the gold
    // program's region (every episode below scores HCS = 1 for the oracle).
    let programs: String = manifest
        .episodes
        .iter()
        .map(|e| std::fs::read_to_string(suite.join(&e.program)).unwrap())
        .collect();
    assert!(
        programs.contains("avoid area_near(") || programs.contains("avoid area_between("),
        "no object-area must-avoid in the suite"
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
        // The planners (oracle, hard-only) and the shortest-route search move by the rule the
        // route validity check applies: every route of theirs is drivable.
        assert!(
            run.invalid_routes.is_empty(),
            "{}: {:?}",
            run.method,
            run.invalid_routes
        );
        for r in &run.records {
            assert_eq!(
                r["route_validity"]["valid"], true,
                "{}",
                r["instruction_id"]
            );
            assert_eq!(r["route_validity"]["occupancy_checked"], true);
        }
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
    eprintln!("{}", table::markdown(&t));
    let row = |m: &str| t.methods.iter().find(|r| r.method == m).unwrap().clone();
    let (oracle, shortest) = (row("oracle"), row("shortest"));
    assert_eq!(oracle.overall.hcs, Some(1.0));
    assert_eq!(shortest.overall.hcs, Some(1.0));
    // Over the whole suite (the overall block, Easy and Hard episodes together) the oracle is
    // better on every preference metric. The Easy and Hard blocks of a 40-episode suite hold a
    // handful of near preferences each, too few to rank two methods per block; docs/benchmark.md
    // has the per-block figures of the full suite.
    for key in ["Near", "Far", "Relative", "PathShape"] {
        let (ov, sv) = (oracle.overall.get(key), shortest.overall.get(key));
        let (Some(ov), Some(sv)) = (ov, sv) else {
            panic!("overall {key}: no value (oracle {ov:?}, shortest {sv:?})");
        };
        // Near is a distance to stay small; the others are to be large.
        let better = if key == "Near" { ov < sv } else { ov > sv };
        assert!(better, "overall {key}: oracle {ov} vs shortest {sv}");
    }
    // And constraint by constraint, on most of each kind.
    let per_constraint = |run: &str| {
        let run = runs.iter().find(|r| r.method == run).unwrap();
        let mut out = std::collections::BTreeMap::new();
        for r in &run.records {
            for c in r["metrics"]["details"]["soft_constraints"]
                .as_array()
                .unwrap()
            {
                if let Some(v) = c["raw_value"].as_f64() {
                    let key = (
                        r["map_id"].to_string(),
                        r["instruction_id"].to_string(),
                        c["constraint_id"].to_string(),
                    );
                    out.insert(key, (c["preference_type"].as_str().unwrap().to_string(), v));
                }
            }
        }
        out
    };
    let (o_values, s_values) = (per_constraint("oracle"), per_constraint("shortest"));
    for kind in [
        "near_preference",
        "far_preference",
        "relative_preference",
        "geometric_path_preference",
    ] {
        let (mut wins, mut total) = (0, 0);
        for (key, (k, ov)) in &o_values {
            if k == kind
                && let Some((_, sv)) = s_values.get(key)
            {
                total += 1;
                wins += usize::from(if kind == "near_preference" {
                    ov < sv
                } else {
                    ov > sv
                });
            }
        }
        assert!(total >= 2, "{kind}: only {total} constraints in the suite");
        // Near preferences are placed geometrically (suite v2), not by planning with the
        // reference cost model the oracle uses, so the oracle wins a smaller share of them. So
        // with path shapes: the oracle plans a circle through its waypoints, as the reference
        // does, and the clearance term pulls the loop off the canonical ring; on the default
        // suite it is better on 75 of 88 circles (and on 116 of 117 walls, patrols and through
        // chains), and a 40-episode suite holds a handful. A majority is required there, two
        // thirds elsewhere.
        let (num, den) = if kind == "near_preference" || kind == "geometric_path_preference" {
            (1, 2)
        } else {
            (2, 3)
        };
        assert!(
            wins * den >= total * num,
            "{kind}: oracle better on only {wins} of {total}"
        );
    }
    // The oracle follows the annotated loop: a clear nDTW margin, not a rounding error.
    let (ov, sv) = (
        oracle.overall.path_shape.unwrap(),
        shortest.overall.path_shape.unwrap(),
    );
    assert!(ov >= sv + 0.05, "path shape: oracle {ov} vs shortest {sv}");

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
