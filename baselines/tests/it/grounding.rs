//! The grounding variants (issue 31): Schema's gold graph plans the gold program's route, the
//! simulated model's faults are repaired through pointer diagnostics, and a mock server's
//! conversation runs through the cache and the repair loop.

use crate::gold::{build, opts};
use crate::support::*;
use m2rc_baselines::grounding::schema::{Schema, graph_text};
use m2rc_baselines::{BaselineArgs, ModelSetup};
use m2rc_benchmark::methods::method_by_name;
use m2rc_benchmark::runner::{self, read_records};
use m2rc_llm::{Backend, ResponseCache, SimulatedSpec, Store};
use serde_json::{Value, json};
use std::sync::Arc;

fn simulated(rate: f64, seed: u64) -> ModelSetup {
    let mut s = gold_setup();
    s.backend = Backend::Simulated(SimulatedSpec {
        fault_rate: rate,
        seed,
    });
    s.model = format!("simulated:{rate}:{seed}");
    s
}

fn by_id(records: &[Value]) -> std::collections::BTreeMap<String, Value> {
    records
        .iter()
        .map(|r| {
            (
                format!("{}/{}", r["map_dir"], r["instruction_id"]),
                r.clone(),
            )
        })
        .collect()
}

/// Gold program -> intent graph -> program plans the same route as the gold program itself.
#[test]
fn schema_gold_graphs_plan_the_gold_programs_routes() {
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("suite");
    let m = build(&suite, 6);
    let (oracle, schema) = (tmp.path().join("oracle"), tmp.path().join("schema"));
    runner::run(
        method_by_name("oracle").unwrap().as_ref(),
        &opts(&suite, &oracle),
    )
    .unwrap();
    let method = Schema::new(Arc::new(gold_setup()), 0);
    runner::run(&method, &opts(&suite, &schema)).unwrap();
    let (o, s) = (
        by_id(&read_records(&oracle).unwrap()),
        by_id(&read_records(&schema).unwrap()),
    );
    assert_eq!(s.len(), m.episodes.len());
    let mut same = 0;
    for (k, r) in &s {
        assert_eq!(r["schema"]["gold_replies"], true);
        if o[k]["status"] == "ok" {
            assert_eq!(r["status"], "ok", "{k}: {}", r["schema"]);
            assert_eq!(r["trajectory"], o[k]["trajectory"], "{k}");
            same += 1;
        }
    }
    assert!(same >= 4, "{same}");
}

#[test]
fn simulated_faults_are_repaired_through_pointer_diagnostics() {
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("suite");
    let m = build(&suite, 8);
    let run = |rounds: usize, dir: &str| {
        let out = tmp.path().join(dir);
        // Without local fixes, so that every repair is the model's and costs a round.
        let mut method = Schema::new(Arc::new(simulated(0.9, 1)), rounds);
        method.repair.local_fixes = false;
        runner::run(&method, &opts(&suite, &out)).unwrap();
        read_records(&out).unwrap()
    };
    let (r0, r3, again) = (run(0, "r0"), run(3, "r3"), run(3, "r3b"));
    assert_eq!(r3, again, "same inputs, same records");
    assert_eq!(r3.len(), m.episodes.len());
    let ok = |rs: &[Value]| rs.iter().filter(|r| r["status"] == "ok").count();
    assert!(ok(&r3) > ok(&r0), "{} vs {}", ok(&r3), ok(&r0));
    let faults: usize = r3
        .iter()
        .map(|r| r["schema"]["simulated_faults"].as_array().unwrap().len())
        .sum();
    assert!(faults > 0);
    // A repaired episode's repair prompt spoke JSON pointers.
    let repaired = r3
        .iter()
        .find(|r| r["schema"]["success_round"].as_u64().is_some_and(|k| k > 0))
        .expect("some episode repaired");
    let attempts = repaired["schema"]["calls"].as_array().unwrap();
    assert!(
        attempts[0]["diagnostics"]
            .as_array()
            .unwrap()
            .iter()
            .any(|d| d["message"].as_str().unwrap().contains("(at `/")),
        "{attempts:?}"
    );
}

#[test]
fn schema_against_a_mock_server_repairs_and_replays_from_the_cache() {
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("suite");
    build(&suite, 1);
    let good = graph_text("route {\n  go objects(bed).nearest()\n}\n").unwrap();
    let bad = good.replace("\"bed\"", "\"bde\"");
    let mut server = mockito::Server::new();
    let calls = server
        .mock("POST", "/v1/chat/completions")
        .with_body_from_request(move |req| {
            let body: Value = serde_json::from_slice(req.body().unwrap()).unwrap();
            let n = body["messages"].as_array().unwrap().len();
            // First answer misspelt (no local fix: the test server's beds may differ); the
            // repair request carries the pointer diagnostics.
            let text = if n <= 2 {
                bad.clone()
            } else {
                let last = body["messages"][n - 1]["content"].as_str().unwrap();
                assert!(last.contains("\"pointer\""), "{last}");
                good.clone()
            };
            completion(&text).to_string().into_bytes()
        })
        .expect_at_least(1)
        .create();
    let cache = tmp.path().join("cache");
    let setup = |url: &str| {
        let mut s = server_setup(url, &cache, None);
        s.embed_http = None;
        s
    };
    let mut method = Schema::new(Arc::new(setup(&server.url())), 3);
    method.repair.local_fixes = false;
    let out = tmp.path().join("run");
    runner::run(&method, &opts(&suite, &out)).unwrap();
    let recs = read_records(&out).unwrap();
    let block = &recs[0]["schema"];
    assert_eq!(block["success_round"], 1, "{block}");
    calls.assert();
    // Offline from the cache: the same record, no request.
    let mut offline = setup("http://127.0.0.1:9");
    offline.store = Store::new(Some(ResponseCache::new(&cache)), None, true);
    let mut method = Schema::new(Arc::new(offline), 3);
    method.repair.local_fixes = false;
    let out2 = tmp.path().join("run2");
    runner::run(&method, &opts(&suite, &out2)).unwrap();
    let strip = |mut v: Value| {
        v["model"] = Value::Null;
        v
    };
    assert_eq!(
        strip(read_records(&out2).unwrap()[0]["schema"].clone()),
        strip(recs[0]["schema"].clone())
    );
}

#[test]
fn the_registry_builds_schema_with_the_simulated_model() {
    let tmp = tempfile::tempdir().unwrap();
    #[derive(clap::Parser)]
    struct Cli {
        #[command(flatten)]
        llm: m2rc_llm::LlmArgs,
    }
    let llm = <Cli as clap::Parser>::try_parse_from(["x", "--llm", "simulated:0.5:1"])
        .unwrap()
        .llm;
    let args = BaselineArgs {
        embed_model: "default".into(),
        embeddings: None,
    };
    let built = m2rc_baselines::build("schema", &llm, &args, tmp.path())
        .unwrap()
        .unwrap();
    assert_eq!(built.method.name(), "schema");
    assert_eq!(built.method.config()["repair_rounds"], json!(0));
    // The other baselines still refuse it.
    assert!(
        m2rc_baselines::build("lang2ltl", &llm, &args, tmp.path())
            .err()
            .is_some()
    );
}
