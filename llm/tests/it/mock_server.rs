//! The client, cache, batch files and repair loop against mock OpenAI-compatible servers on
//! loopback: a scripted conversation, every transport and reply fault, the cache, and a batch
//! round trip. Retry waits are a few milliseconds.

use m2rc_compiler::lower::{
    CatalogMode, EpisodeOutcome, Phase, Prompt, PromptOptions, RepairOptions, SceneCatalog, Trace,
    Verdict, run_episode,
};
use m2rc_llm::{
    ApiKey, BatchOut, Exchange, HttpClient, LlmConfig, ResponseCache, Store, import_batch_files,
};
use m2rc_stdlib::vocab::Vocabulary;
use serde_json::{Value, json};
use std::path::Path;
use std::sync::{Arc, Mutex};
use std::time::Duration;

pub(crate) const KEY: &str = "sk-test-SECRET-4242";
pub(crate) const PATH: &str = "/v1/chat/completions";
pub(crate) const BAD: &str =
    "let c = objects(chiar).nearest(start)\nroute {\n  go area_near(objects(bed))\n  avoid c\n}\n";
pub(crate) const GOOD: &str = "let c = objects(chair).nearest(start)\nroute {\n  go area_near(objects(bed).nearest(start))\n  avoid c\n}\n";

pub(crate) fn config(url: &str) -> LlmConfig {
    LlmConfig {
        base_url: format!("{url}/v1"),
        model: "test-model".into(),
        timeout: Duration::from_secs(5),
        max_attempts: 3,
        backoff_base: Duration::from_millis(2),
        backoff_max: Duration::from_millis(20),
        api_key: ApiKey::new(KEY),
        ..LlmConfig::default()
    }
}

pub(crate) fn completion(content: &str, finish: &str) -> String {
    json!({
        "id": "x", "object": "chat.completion",
        "choices": [{"index": 0, "message": {"role": "assistant", "content": content}, "finish_reason": finish}],
        "usage": {"prompt_tokens": 1000, "completion_tokens": 50}
    })
    .to_string()
}

pub(crate) fn code(p: &str) -> String {
    completion(&format!("```m2r\n{p}```"), "stop")
}

pub(crate) fn prompt() -> Prompt {
    let map = m2rc_stdlib::demo::demo_map().unwrap();
    Prompt::new(
        &map.map_id,
        &SceneCatalog::from_map(&map, CatalogMode::Counts),
        "Go to the bed and stay out of the room with the nearest chair.",
        &PromptOptions::default(),
    )
}

pub(crate) fn check_only(source: &str) -> Verdict<()> {
    let r = m2rc_compiler::check(source, &Vocabulary::benchmark());
    if r.has_errors() {
        Verdict::Rejected {
            phase: Phase::of_errors(&r.diagnostics),
            diagnostics: r.diagnostics,
        }
    } else {
        Verdict::Accepted(())
    }
}

pub(crate) fn episode(client: &HttpClient, store: &Store, id: &str) -> Trace<()> {
    let model = Exchange {
        store,
        fetch: client,
    };
    let mut v = check_only;
    run_episode(&model, &mut v, &prompt(), id, &RepairOptions::default())
}

pub(crate) fn no_cache() -> Store {
    Store::new(None, None, false)
}

/// A mock that records each request body and answers `reply`.
fn recording(
    server: &mut mockito::ServerGuard,
    bodies: &Arc<Mutex<Vec<String>>>,
    reply: String,
) -> mockito::Mock {
    let bodies = bodies.clone();
    server
        .mock("POST", PATH)
        .match_header("authorization", format!("Bearer {KEY}").as_str())
        .with_header("content-type", "application/json")
        .with_body_from_request(move |req| {
            let body = req.body().map(|b| String::from_utf8_lossy(b).to_string());
            bodies.lock().unwrap().push(body.unwrap_or_default());
            reply.clone().into_bytes()
        })
        .expect(1)
        .create()
}

#[test]
fn scripted_conversation_repairs_from_the_diagnostics() {
    let mut server = mockito::Server::new();
    let bodies = Arc::new(Mutex::new(Vec::new()));
    let m1 = recording(&mut server, &bodies, code(BAD));
    let m2 = recording(&mut server, &bodies, code(GOOD));
    let client = HttpClient::new(config(&server.url())).unwrap();
    let t = episode(&client, &no_cache(), "demo/e1");
    m1.assert();
    m2.assert();
    assert_eq!(t.outcome, EpisodeOutcome::Success { round: 1 });
    let bodies = bodies.lock().unwrap();
    assert_eq!(bodies.len(), 2);
    let second: Value = serde_json::from_str(&bodies[1]).unwrap();
    assert_eq!(second["model"], "test-model");
    assert_eq!(second["temperature"], 0.0);
    let last = second["messages"].as_array().unwrap().last().unwrap()["content"]
        .as_str()
        .unwrap()
        .to_string();
    // The remaining error, as text and as JSON.
    let remaining = &t.attempts[0].diagnostics[0].code;
    assert!(last.contains(&format!("error[{remaining}]")), "{last}");
    assert!(
        last.contains(&format!("\"code\": \"{remaining}\"")),
        "{last}"
    );
    // The misspelt category was fixed locally and never reached the server.
    assert_eq!(t.attempts[0].local_fixes.len(), 1);
    assert!(!last.contains("chiar"));
    assert!(!bodies[0].contains("# Repair"));
    assert_eq!(t.tokens(), (2000, 100));
}

#[test]
fn server_errors_and_malformed_bodies_are_retried() {
    for (status, header, body) in [
        (500, None, "oops".to_string()),
        (429, Some("1"), "slow down".to_string()),
        (200, None, "{not json".to_string()),
        (200, None, json!({"id": "no choices key"}).to_string()),
    ] {
        let mut server = mockito::Server::new();
        let mut m = server
            .mock("POST", PATH)
            .with_status(status)
            .with_body(body);
        if let Some(h) = header {
            m = m.with_header("retry-after", h);
        }
        let m1 = m.expect(1).create();
        let m2 = server
            .mock("POST", PATH)
            .with_body(code(GOOD))
            .expect(1)
            .create();
        let client = HttpClient::new(config(&server.url())).unwrap();
        let t = episode(&client, &no_cache(), "demo/e1");
        m1.assert();
        m2.assert();
        assert_eq!(
            t.outcome,
            EpisodeOutcome::Success { round: 0 },
            "status {status}"
        );
    }
}

#[test]
fn persistent_failures_are_recorded_after_bounded_attempts() {
    let mut server = mockito::Server::new();
    let m = server
        .mock("POST", PATH)
        .with_status(503)
        .expect(3)
        .create();
    let client = HttpClient::new(config(&server.url())).unwrap();
    let t = episode(&client, &no_cache(), "demo/e1");
    m.assert();
    let EpisodeOutcome::ModelFailed { message } = &t.outcome else {
        panic!("{:?}", t.outcome)
    };
    assert!(
        message.contains("demo/e1/round0") && message.contains("3 attempt"),
        "{message}"
    );
    assert!(!message.contains(KEY));
    // A client error is not retried.
    let mut server = mockito::Server::new();
    let m = server
        .mock("POST", PATH)
        .with_status(401)
        .with_body("bad key")
        .expect(1)
        .create();
    let client = HttpClient::new(config(&server.url())).unwrap();
    let t = episode(&client, &no_cache(), "demo/e1");
    m.assert();
    assert_eq!(t.outcome.status(), "model_failed");
}

#[test]
fn connection_refused_and_timeouts_end_in_a_recorded_failure() {
    let port = {
        let l = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        l.local_addr().unwrap().port()
    };
    let client = HttpClient::new(config(&format!("http://127.0.0.1:{port}"))).unwrap();
    let t = episode(&client, &no_cache(), "demo/e1");
    let EpisodeOutcome::ModelFailed { message } = &t.outcome else {
        panic!("{:?}", t.outcome)
    };
    assert!(message.contains("cannot connect"), "{message}");
    // The URL tried is named, so a typo in --llm-base-url shows.
    assert!(
        message.contains(&format!("http://127.0.0.1:{port}/v1/chat/completions")),
        "{message}"
    );

    // A server that accepts and never answers.
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap();
    let held = std::thread::spawn(move || {
        let mut open = Vec::new();
        for _ in 0..2 {
            if let Ok((s, _)) = listener.accept() {
                open.push(s);
            }
        }
        std::thread::sleep(Duration::from_millis(600));
    });
    let cfg = LlmConfig {
        timeout: Duration::from_millis(200),
        max_attempts: 2,
        ..config(&format!("http://{addr}"))
    };
    let client = HttpClient::new(cfg).unwrap();
    let t = episode(&client, &no_cache(), "demo/e1");
    let EpisodeOutcome::ModelFailed { message } = &t.outcome else {
        panic!("{:?}", t.outcome)
    };
    assert!(message.contains("timed out"), "{message}");
    held.join().unwrap();
}

#[test]
fn empty_choices_no_code_and_cut_off_replies_are_answered_by_a_repair_round() {
    let cut = completion(
        "```m2r\nlet c = objects(chair).nearest(start)\nroute {\n  go obj",
        "length",
    );
    for (reply, kind, said) in [
        (
            json!({"choices": []}).to_string(),
            "empty_choice",
            "was empty",
        ),
        (
            completion("The bed is in the bedroom.", "stop"),
            "no_code",
            "no ```m2r block",
        ),
        (cut, "cut_off", "cut off"),
    ] {
        let mut server = mockito::Server::new();
        let bodies = Arc::new(Mutex::new(Vec::new()));
        let m1 = recording(&mut server, &bodies, reply);
        let m2 = recording(&mut server, &bodies, code(GOOD));
        let client = HttpClient::new(config(&server.url())).unwrap();
        let t = episode(&client, &no_cache(), "demo/e1");
        m1.assert();
        m2.assert();
        assert_eq!(t.attempts[0].reply, kind);
        assert_eq!(t.outcome, EpisodeOutcome::Success { round: 1 }, "{kind}");
        assert!(bodies.lock().unwrap()[1].contains(said), "{kind}");
    }
}

/// Every file under `dir`, for the credential grep.
pub(crate) fn files(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            if e.path().is_dir() {
                stack.push(e.path());
            } else {
                out.push(e.path());
            }
        }
    }
    out
}

#[test]
fn the_cache_answers_first_and_survives_corruption() {
    let tmp = tempfile::tempdir().unwrap();
    let mut server = mockito::Server::new();
    let m = server
        .mock("POST", PATH)
        .with_body(code(GOOD))
        .expect(2)
        .create();
    let client = HttpClient::new(config(&server.url())).unwrap();
    let store = || Store::new(Some(ResponseCache::new(tmp.path())), None, false);
    assert_eq!(
        episode(&client, &store(), "demo/e1").outcome,
        EpisodeOutcome::Success { round: 0 }
    );
    // A hit makes no request.
    let s = store();
    assert_eq!(
        episode(&client, &s, "demo/e1").outcome,
        EpisodeOutcome::Success { round: 0 }
    );
    assert_eq!(s.stats().cache_hits, 1);
    // A corrupt entry is ignored and fetched again.
    for f in files(tmp.path()) {
        std::fs::write(f, b"{\"key\": 1").unwrap();
    }
    assert_eq!(
        episode(&client, &store(), "demo/e1").outcome,
        EpisodeOutcome::Success { round: 0 }
    );
    m.assert();
    // Cache-only never touches the network: a miss names the request.
    let empty = tempfile::tempdir().unwrap();
    let s = Store::new(Some(ResponseCache::new(empty.path())), None, true);
    let t = episode(&client, &s, "demo/e9");
    let EpisodeOutcome::ModelFailed { message } = &t.outcome else {
        panic!()
    };
    assert!(message.contains("demo/e9/round0") && message.contains("--llm-cache-only"));
    for f in files(tmp.path()) {
        assert!(
            !std::fs::read_to_string(&f)
                .unwrap_or_default()
                .contains(KEY)
        );
    }
}

/// Answers every line of a batch input file with `program`, in the Batch output format.
pub(crate) fn answer(batch: &Path, out: &Path, program: &str) -> usize {
    let text = std::fs::read_to_string(batch).unwrap();
    let mut lines = String::new();
    for l in text.lines() {
        let req: Value = serde_json::from_str(l).unwrap();
        assert_eq!(req["method"], "POST");
        assert_eq!(req["url"], "/v1/chat/completions");
        assert_eq!(req["body"]["model"], "test-model");
        let body: Value = serde_json::from_str(&code(program)).unwrap();
        lines.push_str(
            &json!({"id": "b", "custom_id": req["custom_id"], "response": {"status_code": 200, "body": body}, "error": null})
                .to_string(),
        );
        lines.push('\n');
    }
    std::fs::write(out, lines).unwrap();
    text.lines().count()
}

#[test]
fn batch_round_trip_export_answer_import_continue() {
    let tmp = tempfile::tempdir().unwrap();
    let cache_dir = tmp.path().join("cache");
    let (batch, replies) = (tmp.path().join("batch.jsonl"), tmp.path().join("out.jsonl"));
    // No server at all: every reply comes through the files.
    let client = HttpClient::new(config("http://127.0.0.1:9")).unwrap();
    let run = || {
        let store = Store::new(
            Some(ResponseCache::new(&cache_dir)),
            Some(BatchOut::new(&batch)),
            false,
        );
        let t = episode(&client, &store, "demo/e1");
        store.batch.as_ref().unwrap().finish().unwrap();
        t
    };
    let t = run();
    assert_eq!(
        t.outcome,
        EpisodeOutcome::Pending {
            custom_id: "demo/e1/round0".into()
        }
    );
    assert_eq!(answer(&batch, &replies, BAD), 1);
    let cache = ResponseCache::new(&cache_dir);
    assert_eq!(
        import_batch_files(std::slice::from_ref(&replies), &cache)
            .unwrap()
            .imported,
        1
    );
    // Round 0 now comes from the cache; round 1 is exported.
    let t = run();
    assert_eq!(
        t.outcome,
        EpisodeOutcome::Pending {
            custom_id: "demo/e1/round1".into()
        }
    );
    assert!(
        std::fs::read_to_string(&batch)
            .unwrap()
            .contains("demo/e1/round1")
    );
    assert_eq!(answer(&batch, &replies, GOOD), 1);
    let imported = import_batch_files(std::slice::from_ref(&replies), &cache).unwrap();
    assert_eq!(imported.imported, 1);
    let t = run();
    assert_eq!(t.outcome, EpisodeOutcome::Success { round: 1 });
    assert_eq!(std::fs::read_to_string(&batch).unwrap(), "");
    // A reply imported before is reported as such, not imported again.
    let again = import_batch_files(std::slice::from_ref(&replies), &cache).unwrap();
    assert_eq!((again.imported, again.already.len()), (0, 1));
    for f in files(tmp.path()) {
        assert!(
            !std::fs::read_to_string(&f)
                .unwrap_or_default()
                .contains(KEY),
            "{}",
            f.display()
        );
    }
}
