//! Untrusted replies against mock servers on loopback: bodies past the size limit, replies
//! longer than a program, redirects, token counts that are not counts, and batch replies that do
//! not belong to the requests this run exported (issue 28, items 4, 6, 12, 15 and 19).

use crate::mock_server::{GOOD, PATH, check_only, code, config, episode, no_cache};
use m2rc_compiler::lower::{
    CatalogMode, EpisodeOutcome, Prompt, PromptOptions, RepairOptions, SceneCatalog, run_episode,
};
use m2rc_llm::{
    BatchOut, Exchange, HttpClient, LlmConfig, ResponseCache, Store, import_batch_files,
};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

fn failure(outcome: &EpisodeOutcome) -> &str {
    match outcome {
        EpisodeOutcome::ModelFailed { message } => message,
        other => panic!("expected model_failed, got {other:?}"),
    }
}

#[test]
fn bodies_past_the_limit_fail_at_once_without_being_read() {
    // Declared too long: refused from its Content-Length, and not retried.
    let mut server = mockito::Server::new();
    let big = code(&format!("// {}\n{GOOD}", "x".repeat(5000)));
    let m = server.mock("POST", PATH).with_body(big).expect(1).create();
    let cfg = LlmConfig {
        max_response_bytes: 1000,
        ..config(&server.url())
    };
    let t = episode(&HttpClient::new(cfg).unwrap(), &no_cache(), "demo/e1");
    m.assert();
    let message = failure(&t.outcome);
    assert!(
        message.contains("more than the limit of 1000 bytes"),
        "{message}"
    );
    // Streamed without a length: read to one byte past the limit, then refused.
    let mut server = mockito::Server::new();
    let m = server
        .mock("POST", PATH)
        .with_chunked_body(|w| {
            for _ in 0..64 {
                w.write_all(&[b' '; 16 * 1024])?;
            }
            Ok(())
        })
        .expect(1)
        .create();
    let cfg = LlmConfig {
        max_response_bytes: 1000,
        ..config(&server.url())
    };
    let t = episode(&HttpClient::new(cfg).unwrap(), &no_cache(), "demo/e1");
    m.assert();
    let message = failure(&t.outcome);
    assert!(message.contains("--llm-max-response-mb"), "{message}");
    assert!(t.attempts[0].program.is_none());
}

#[test]
fn a_reply_longer_than_a_program_is_never_compiled_or_recorded() {
    let mut server = mockito::Server::new();
    let long = format!("{GOOD}// {}\n", "x".repeat(300 * 1024));
    let m = server
        .mock("POST", PATH)
        .with_body(code(&long))
        .expect(1)
        .create();
    let store = no_cache();
    let t = episode(
        &HttpClient::new(config(&server.url())).unwrap(),
        &store,
        "demo/e1",
    );
    m.assert();
    let message = failure(&t.outcome);
    assert!(message.contains("262144 bytes of a program"), "{message}");
    assert_eq!(t.attempts.len(), 1);
    assert!(t.attempts[0].program.is_none() && t.final_program.is_none());
    assert_eq!(store.stats().oversized, 1);
    assert!(store.warnings().iter().any(|w| w.contains("program limit")));
}

#[test]
fn a_redirect_of_the_post_is_not_followed() {
    let mut elsewhere = mockito::Server::new();
    let never = elsewhere.mock("POST", PATH).expect(0).create();
    let mut server = mockito::Server::new();
    let target = format!("{}{PATH}", elsewhere.url());
    let m = server
        .mock("POST", PATH)
        .with_status(307)
        .with_header("location", &target)
        .expect(1)
        .create();
    let t = episode(
        &HttpClient::new(config(&server.url())).unwrap(),
        &no_cache(),
        "demo/e1",
    );
    m.assert();
    never.assert();
    let message = failure(&t.outcome);
    assert!(
        message.contains("307") && message.contains(&target) && message.contains("not followed"),
        "{message}"
    );
}

#[test]
fn token_counts_that_are_not_counts_are_unknown_and_warned_about() {
    let mut server = mockito::Server::new();
    let body = json!({
        "choices": [{"message": {"role": "assistant", "content": format!("```m2r\n{GOOD}```")}, "finish_reason": "stop"}],
        "usage": {"prompt_tokens": -5, "completion_tokens": 1e300}
    });
    let m = server
        .mock("POST", PATH)
        .with_body(body.to_string())
        .expect(1)
        .create();
    let store = no_cache();
    let t = episode(
        &HttpClient::new(config(&server.url())).unwrap(),
        &store,
        "demo/e1",
    );
    m.assert();
    assert_eq!(t.outcome, EpisodeOutcome::Success { round: 0 });
    let a = serde_json::to_value(&t.attempts[0]).unwrap();
    assert_eq!(
        (&a["prompt_tokens"], &a["completion_tokens"]),
        (&Value::Null, &Value::Null)
    );
    assert_eq!((t.tokens(), t.unknown_usage()), ((0, 0), 1));
    let w = store.warnings();
    assert!(w.len() == 1 && w[0].contains("unknown"), "{w:?}");
}

/// A run of `episodes` on the instruction `instruction` whose requests go to `batch`, through
/// the cache in `cache`; returns the exported lines.
fn export(cache: &Path, batch: &Path, model: &str, instruction: &str, ids: &[&str]) -> Vec<Value> {
    let client = HttpClient::new(LlmConfig {
        model: model.into(),
        ..config("http://127.0.0.1:9")
    })
    .unwrap();
    let store = Store::new(
        Some(ResponseCache::new(cache)),
        Some(BatchOut::new(batch)),
        false,
    );
    let map = m2rc_stdlib::demo::demo_map().unwrap();
    let prompt = Prompt::new(
        &map.map_id,
        &SceneCatalog::from_map(&map, CatalogMode::Counts),
        instruction,
        &PromptOptions::default(),
    );
    for id in ids {
        let model = Exchange {
            store: &store,
            fetch: &client,
        };
        let mut v = check_only;
        let t = run_episode(&model, &mut v, &prompt, id, &RepairOptions::default());
        assert_eq!(t.outcome.status(), "pending");
    }
    store.batch.as_ref().unwrap().finish().unwrap();
    std::fs::read_to_string(batch)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

/// A Batch output line answering `request` with `body`.
fn reply_line(request: &Value, body: Value) -> String {
    json!({"id": "b", "custom_id": request["custom_id"], "response": {"status_code": 200, "body": body}, "error": null})
        .to_string()
}

fn program_body(program: &str) -> Value {
    serde_json::from_str(&code(program)).unwrap()
}

fn write(path: &Path, lines: &[String]) -> PathBuf {
    std::fs::write(path, lines.join("\n") + "\n").unwrap();
    path.to_path_buf()
}

const GO: &str = "Go to the bed and stay out of the room with the nearest chair.";

#[test]
fn batch_replies_must_answer_the_request_this_run_exported() {
    let tmp = tempfile::tempdir().unwrap();
    let cache_dir = tmp.path().join("cache");
    let ours = export(
        &cache_dir,
        &tmp.path().join("ours.jsonl"),
        "test-model",
        GO,
        &["demo/e1"],
    );
    let id = ours[0]["custom_id"].as_str().unwrap();
    let (name, digest) = id.rsplit_once('#').unwrap();
    assert_eq!(name, "demo/e1/round0");
    assert_eq!(digest.len(), 16);
    // The same names exported by runs with another model and another instruction.
    let other_model = export(
        &tmp.path().join("c2"),
        &tmp.path().join("m.jsonl"),
        "other-model",
        GO,
        &["demo/e1"],
    );
    let other_prompt = export(
        &tmp.path().join("c3"),
        &tmp.path().join("p.jsonl"),
        "test-model",
        "Go to the sofa.",
        &["demo/e1"],
    );
    let cache = ResponseCache::new(&cache_dir);
    for (what, theirs) in [("model", &other_model), ("prompt", &other_prompt)] {
        assert_ne!(theirs[0]["custom_id"], ours[0]["custom_id"], "{what}");
        let file = write(
            &tmp.path().join(format!("{what}-out.jsonl")),
            &[reply_line(&theirs[0], program_body(GOOD))],
        );
        let r = import_batch_files(&[file], &cache).unwrap();
        assert_eq!(r.imported, 0, "{what}");
        assert!(
            r.failed[0].contains("answers another request"),
            "{what}: {r:?}"
        );
        assert!(cache.pending_key(name).is_some(), "{what}: still pending");
    }
    // An id without a digest (an older export, or a hand-made file) is not trusted either.
    let bare =
        json!({"custom_id": name, "response": {"status_code": 200, "body": program_body(GOOD)}});
    let file = write(&tmp.path().join("bare.jsonl"), &[bare.to_string()]);
    let r = import_batch_files(&[file], &cache).unwrap();
    assert_eq!((r.imported, r.unknown.len()), (0, 1));
    assert!(r.unknown[0].contains("no request digest"), "{r:?}");
    // Our own request, answered by a model of another name: imported, with a warning.
    let mut body = program_body(GOOD);
    body["model"] = json!("gpt-somebody-else");
    let file = write(
        &tmp.path().join("mine.jsonl"),
        &[reply_line(&ours[0], body)],
    );
    let r = import_batch_files(&[file], &cache).unwrap();
    assert_eq!(r.imported, 1);
    assert!(
        r.warnings[0].contains("asked of model `test-model`")
            && r.warnings[0].contains("gpt-somebody-else"),
        "{r:?}"
    );
}

#[test]
fn batch_import_names_every_bad_line_and_refuses_conflicts() {
    let tmp = tempfile::tempdir().unwrap();
    let cache_dir = tmp.path().join("cache");
    let lines = export(
        &cache_dir,
        &tmp.path().join("b.jsonl"),
        "test-model",
        GO,
        &["demo/e1", "demo/e2", "demo/e3"],
    );
    let cache = ResponseCache::new(&cache_dir);
    let good = |i: usize| reply_line(&lines[i], program_body(GOOD));
    // e1 twice with the same reply, e2 twice with different replies, e3 a body that is not a
    // chat completion; a line of bad bytes and a line of garbage between them.
    let out = tmp.path().join("out.jsonl");
    let mut bytes = Vec::new();
    for l in [
        good(0),
        good(0),
        good(1),
        reply_line(
            &lines[1],
            program_body("route { go rooms(kitchen).only() }\n"),
        ),
    ] {
        bytes.extend_from_slice(l.as_bytes());
        bytes.push(b'\n');
    }
    bytes.extend_from_slice(b"{\"custom_id\": \"\xff\xfe\"}\n");
    bytes.extend_from_slice(reply_line(&lines[2], json!({"id": "not a completion"})).as_bytes());
    bytes.extend_from_slice(b"\n{not json\n");
    std::fs::write(&out, &bytes).unwrap();
    let r = import_batch_files(std::slice::from_ref(&out), &cache).unwrap();
    assert_eq!(r.imported, 1, "{r:?}");
    let o = out.display().to_string();
    assert!(
        r.already
            .iter()
            .any(|a| a.starts_with(&format!("{o}:2:")) && a.contains("repeats")),
        "{r:?}"
    );
    let has = |prefix: &str, text: &str| {
        r.failed
            .iter()
            .any(|f| f.starts_with(prefix) && f.contains(text))
    };
    assert!(has(&format!("{o}:3:"), "different reply"), "{r:?}");
    assert!(has(&format!("{o}:5:"), "not UTF-8"), "{r:?}");
    assert!(has(&format!("{o}:6:"), "not a chat completion"), "{r:?}");
    assert!(has(&format!("{o}:7:"), "not JSON"), "{r:?}");
    assert!(r.unknown.is_empty(), "{r:?}");
    // The conflicting and the malformed ones stay pending, to be exported again.
    assert!(cache.pending_key("demo/e1/round0").is_none());
    assert!(cache.pending_key("demo/e2/round0").is_some());
    assert!(cache.pending_key("demo/e3/round0").is_some());
    // A compressed file is named as one, not as bad text.
    let gz = tmp.path().join("out.jsonl.gz");
    std::fs::write(&gz, [0x1f, 0x8b, 8, 0, 0, 0, 0, 0]).unwrap();
    let e = import_batch_files(&[gz], &cache).unwrap_err();
    assert!(e.contains("gzip-compressed") && e.contains("gunzip"), "{e}");
    // A line as long as a huge reply is skipped by its number, not read whole.
    let long = tmp.path().join("long.jsonl");
    let huge = reply_line(&lines[2], program_body(&"x".repeat(9 * 1024 * 1024)));
    write(&long, &[huge, good(2)]);
    let r = import_batch_files(std::slice::from_ref(&long), &cache).unwrap();
    assert_eq!(r.imported, 1, "{r:?}");
    assert!(r.failed[0].contains(":1: longer than"), "{r:?}");
}
