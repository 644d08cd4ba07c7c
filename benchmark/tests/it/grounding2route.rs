//! `grounding2route` on a real one-scene suite: against a mock server (with one episode whose
//! server answers garbage), resumed from the cache with identical records, through the batch
//! round trip, and with the simulated model; and no file a run writes holds the API key.

use m2rc_benchmark::budget::EpisodeBudget;
use m2rc_benchmark::methods::grounding2route::{Grounding2Route, Grounding2RouteConfig};
use m2rc_benchmark::methods::{Method, method_by_name};
use m2rc_benchmark::report::{self, load_runs};
use m2rc_benchmark::runner::{self, RunOptions, read_records};
use m2rc_benchmark::suite::{ProcthorTools, SuiteConfig, SuiteManifest, build_suite};
use m2rc_llm::{
    ApiKey, Backend, BatchOut, HttpClient, LlmConfig, ResponseCache, SimulatedSpec, Store,
    import_batch_files,
};
use m2rc_stdlib::import::{AssetDb, ImportOptions};
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Duration;

const KEY: &str = "sk-bench-SECRET-777";

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
        name: "g2r-test".into(),
        scenes: 1,
        dev_scenes: 0,
        episodes_per_scene: 4,
        hard_fraction: 0.25,
        seed: 5,
    };
    build_suite(&shared().join("fixtures"), &config, &tools, dir, &|_, _| {}).unwrap()
}

fn opts(suite: &Path, out: &Path) -> RunOptions {
    RunOptions {
        suite: suite.to_path_buf(),
        out: out.to_path_buf(),
        shard: None,
        split: "eval".into(),
        progress: false,
    }
}

/// instruction text -> gold program, from the suite's episode files.
fn golds(suite: &Path, m: &SuiteManifest) -> BTreeMap<String, String> {
    m.episodes
        .iter()
        .map(|e| {
            let ep: Value =
                serde_json::from_slice(&std::fs::read(suite.join(&e.file)).unwrap()).unwrap();
            (
                ep["instruction"].as_str().unwrap().trim().to_string(),
                ep["m2rc_gold_program"].as_str().unwrap().to_string(),
            )
        })
        .collect()
}

/// The instruction inside a request body's first user message.
fn instruction_of(body: &Value) -> String {
    let user = body["messages"][1]["content"].as_str().unwrap_or("");
    let a = user.find("# Instruction\n\n").map(|i| i + 15).unwrap_or(0);
    let b = user[a..].find("\n\n# Output").map_or(user.len(), |i| a + i);
    user[a..b].trim().to_string()
}

fn completion(program: &str) -> Value {
    json!({"choices": [{"message": {"role": "assistant", "content": format!("```m2r\n{program}```")}, "finish_reason": "stop"}],
           "usage": {"prompt_tokens": 3000, "completion_tokens": 80}})
}

fn method(url: &str, store: Store) -> Grounding2Route {
    let cfg = LlmConfig {
        base_url: format!("{url}/v1"),
        model: "mock".into(),
        timeout: Duration::from_secs(10),
        max_attempts: 2,
        backoff_base: Duration::from_millis(1),
        backoff_max: Duration::from_millis(5),
        api_key: ApiKey::new(KEY),
        ..LlmConfig::default()
    };
    Grounding2Route {
        config: Grounding2RouteConfig {
            model: "mock".into(),
            ..Grounding2RouteConfig::default()
        },
        store,
        http: Some(HttpClient::new(cfg).unwrap()),
    }
}

fn cached(out: &Path, cache_only: bool) -> Store {
    Store::new(
        Some(ResponseCache::new(out.join("llm-cache"))),
        None,
        cache_only,
    )
}

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

fn by_id(dir: &Path) -> BTreeMap<String, Value> {
    read_records(dir)
        .unwrap()
        .into_iter()
        .map(|r| (r["instruction_id"].as_str().unwrap().to_string(), r))
        .collect()
}

#[test]
fn mock_server_cache_resume_batch_and_simulated() {
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("suite");
    let manifest = build(&suite);
    let n = manifest.episodes.len();
    assert!(n >= 3);
    let golds = golds(&suite, &manifest);
    let faulty = golds.keys().next().unwrap().clone();
    // Episodes whose instruction is the faulty one (a suite may say the same thing twice).
    let faulty_episodes = manifest
        .episodes
        .iter()
        .filter(|e| {
            let ep: Value =
                serde_json::from_slice(&std::fs::read(suite.join(&e.file)).unwrap()).unwrap();
            ep["instruction"].as_str().unwrap().trim() == faulty
        })
        .count();

    // Oracle for comparison.
    let oracle_out = tmp.path().join("oracle");
    runner::run(
        method_by_name("oracle").unwrap().as_ref(),
        &opts(&suite, &oracle_out),
    )
    .unwrap();
    let oracle = by_id(&oracle_out);

    // 1. Live against a mock server; one episode's server answers garbage.
    let mut server = mockito::Server::new();
    let (g, f) = (golds.clone(), faulty.clone());
    let _m = server
        .mock("POST", "/v1/chat/completions")
        .match_header("authorization", format!("Bearer {KEY}").as_str())
        .with_body_from_request(move |req| {
            let body: Value = serde_json::from_slice(req.body().unwrap()).unwrap();
            let instr = instruction_of(&body);
            if instr == f {
                return b"{\"choices\": [".to_vec();
            }
            completion(&g[&instr]).to_string().into_bytes()
        })
        .expect_at_least(1)
        .create();
    let live = tmp.path().join("live");
    let m = method(&server.url(), cached(&live, false));
    let s = runner::run(&m, &opts(&suite, &live)).unwrap();
    assert_eq!(
        (s.written, s.method_failures, s.pending),
        (n, faulty_episodes, 0)
    );
    let recs = by_id(&live);
    for (id, r) in &recs {
        let g2r = &r["grounding2route"];
        if r["status"] == "model_failed" {
            assert!(
                g2r["attempts"][0]["error"]
                    .as_str()
                    .unwrap()
                    .contains("not JSON")
            );
            continue;
        }
        assert_eq!(r["status"], "ok", "{id}");
        assert_eq!(g2r["success_round"], 0);
        assert_eq!(g2r["first_try_ok"], true);
        assert_eq!(g2r["prompt_tokens"], 3000);
        assert_eq!(r["trajectory"], oracle[id]["trajectory"], "{id}");
    }
    let manifest_json: Value =
        serde_json::from_slice(&std::fs::read(live.join("run.json")).unwrap()).unwrap();
    assert_eq!(manifest_json["method_config"]["repair"]["rounds"], 3);

    // 2. Killed and resumed: lost records are recomputed from the cache, byte for byte, with
    //    no server at all.
    let before = snapshot(&live);
    let ok_ids: Vec<&String> = recs.keys().filter(|k| recs[*k]["status"] == "ok").collect();
    for id in ok_ids.iter().take(2) {
        let map_dir = recs[*id]["map_dir"].as_str().unwrap();
        std::fs::remove_file(runner::record_path(&live, map_dir, id)).unwrap();
    }
    drop(server);
    let m = method("http://127.0.0.1:9", cached(&live, true));
    let s = runner::run(&m, &opts(&suite, &live)).unwrap();
    assert_eq!((s.written, s.skipped), (2, n - 2));
    assert_eq!(snapshot(&live), before);

    // 3. Batch round trip: export, answer, import, continue.
    let batch_out = tmp.path().join("batch");
    let batch = tmp.path().join("requests.jsonl");
    let replies = tmp.path().join("replies.jsonl");
    let with_batch = || {
        Store::new(
            Some(ResponseCache::new(batch_out.join("llm-cache"))),
            Some(BatchOut::new(&batch)),
            false,
        )
    };
    let m = method("http://127.0.0.1:9", with_batch());
    let s = runner::run(&m, &opts(&suite, &batch_out)).unwrap();
    m.store.batch.as_ref().unwrap().finish().unwrap();
    assert_eq!((s.written, s.pending), (0, n));
    assert_eq!(report::count_pending(&batch_out), n);
    // A run still waiting for replies is refused by a strict report, and says why.
    let refused = load_runs(std::slice::from_ref(&batch_out)).err().unwrap();
    assert!(
        refused
            .to_string()
            .contains(&format!("{n} waiting for a model reply"))
    );
    let runs = report::load_runs_with(
        std::slice::from_ref(&batch_out),
        report::LoadOptions {
            allow_incomplete: true,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(report::model::markdown(&runs, &Default::default()).contains(&format!("| {n} |")));
    let mut lines = String::new();
    for l in std::fs::read_to_string(&batch).unwrap().lines() {
        let req: Value = serde_json::from_str(l).unwrap();
        assert!(req["custom_id"].as_str().unwrap().contains("/round0#"));
        let program = &golds[&instruction_of(&req["body"])];
        lines.push_str(&json!({"custom_id": req["custom_id"], "response": {"status_code": 200, "body": completion(program)}}).to_string());
        lines.push('\n');
    }
    std::fs::write(&replies, lines).unwrap();
    let cache = ResponseCache::new(batch_out.join("llm-cache"));
    assert_eq!(
        import_batch_files(std::slice::from_ref(&replies), &cache)
            .unwrap()
            .imported,
        n
    );
    let m = method("http://127.0.0.1:9", with_batch());
    let s = runner::run(&m, &opts(&suite, &batch_out)).unwrap();
    assert_eq!((s.written, s.pending, s.method_failures), (n, 0, 0));
    assert_eq!(report::count_pending(&batch_out), 0);
    for (id, r) in by_id(&batch_out) {
        assert_eq!(r["trajectory"], oracle[&id]["trajectory"], "{id}");
    }

    // 4. The simulated model: labelled, deterministic, with the repair-round table.
    let sim = |out: &Path| {
        let m = Grounding2Route {
            config: Grounding2RouteConfig {
                backend: Backend::Simulated(SimulatedSpec {
                    fault_rate: 0.9,
                    seed: 2,
                }),
                model: "simulated:0.9:2".into(),
                ..Grounding2RouteConfig::default()
            },
            store: cached(out, false),
            http: None,
        };
        assert!(m.config()["backend"]["backend"] == "simulated");
        runner::run(&m, &opts(&suite, out)).unwrap()
    };
    let (s1, s2) = (tmp.path().join("sim1"), tmp.path().join("sim2"));
    sim(&s1);
    sim(&s2);
    assert_eq!(snapshot(&s1), snapshot(&s2));
    let recs = by_id(&s1);
    assert!(recs.values().all(|r| {
        r["grounding2route"]["model"]
            .as_str()
            .unwrap()
            .contains("SIMULATED")
    }));
    assert!(recs.values().any(|r| {
        !r["grounding2route"]["simulated_faults"]
            .as_array()
            .unwrap()
            .is_empty()
    }));
    let runs = load_runs(std::slice::from_ref(&s1)).unwrap();
    assert!(runs[0].method.contains("SIMULATED"));
    let md = report::markdown_report_with(&runs, &Default::default());
    for r in 0..=3 {
        assert!(md.contains(&format!("[SIMULATED model] | {r} |")), "{md}");
    }

    // 5. An episode over its budget is recorded with the reason, and the run goes on: with a
    //    work budget of 10 expansions no plan can finish, and every episode says why.
    let tight = tmp.path().join("tight");
    let m = Grounding2Route {
        config: Grounding2RouteConfig {
            backend: Backend::Simulated(SimulatedSpec {
                fault_rate: 0.0,
                seed: 0,
            }),
            model: "simulated:0:0".into(),
            budget: EpisodeBudget {
                max_expansions: 10,
                ..EpisodeBudget::default()
            },
            ..Grounding2RouteConfig::default()
        },
        store: cached(&tight, false),
        http: None,
    };
    assert_eq!(m.config()["budget"]["max_expansions"], 10);
    let s = runner::run(&m, &opts(&suite, &tight)).unwrap();
    assert_eq!((s.written, s.method_failures), (n, n));
    for (id, r) in by_id(&tight) {
        assert_eq!(r["status"], "budget_exceeded", "{id}");
        let why = r["notes"][0].as_str().unwrap();
        assert!(
            why.contains("work budget of 10 planner expansions"),
            "{id}: {why}"
        );
        assert_eq!(r["grounding2route"]["budget_exceeded"], why);
    }
    // At its defaults the budget is not part of the configuration (fingerprints unchanged).
    assert!(Grounding2RouteConfig::default().budget.is_default());
    assert!(
        serde_json::to_value(Grounding2RouteConfig::default())
            .unwrap()
            .get("budget")
            .is_none()
    );

    // 6. No file any run wrote holds the API key.
    for (name, bytes) in snapshot(tmp.path()) {
        assert!(
            !String::from_utf8_lossy(&bytes).contains(KEY),
            "{name} holds the API key"
        );
    }
}
