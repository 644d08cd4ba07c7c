//! The LLM-call helper: chat and embeddings through the store (mock server, cache, refusals,
//! malformed replies, wrong dimensions), gold replies, and the batch round trip with both kinds
//! of request.

use crate::support::*;
use m2rc_baselines::ModelSetup;
use m2rc_baselines::Session;
use m2rc_benchmark::episode::Episode;
use m2rc_compiler::lower::Message;
use m2rc_llm::{ResponseCache, Store, import_batch_files};
use serde_json::{Value, json};

fn episode() -> Episode {
    Episode {
        id: Some(7),
        map_id: Some("m1".into()),
        instruction: Some("go to the sofa".into()),
        ..Episode::default()
    }
}

fn no_gold() -> Result<String, String> {
    Err("no gold".into())
}

#[test]
fn chat_and_embeddings_through_a_mock_server_and_the_cache() {
    let tmp = tempfile::tempdir().unwrap();
    let mut server = mockito::Server::new();
    let chat = server
        .mock("POST", "/v1/chat/completions")
        .with_body_from_request(|req| {
            let body: Value = serde_json::from_slice(req.body().unwrap()).unwrap();
            let user = body["messages"][1]["content"].as_str().unwrap().to_string();
            match user.as_str() {
                "refuse" => json!({"choices": [{"message": {"role": "assistant", "content": null, "refusal": "no"}, "finish_reason": "stop"}]}),
                "empty" => json!({"choices": []}),
                _ => completion(&format!("echo {user}")),
            }
            .to_string()
            .into_bytes()
        })
        .expect(3)
        .create();
    let embed = server
        .mock("POST", "/v1/embeddings")
        .with_body_from_request(|req| {
            let body: Value = serde_json::from_slice(req.body().unwrap()).unwrap();
            assert_eq!(body["model"], "mock-embed");
            let inputs = body["input"].as_array().unwrap();
            // Two dimensions for "short", three otherwise: the second request disagrees.
            let d = if inputs[0] == "short" { 2 } else { 3 };
            embeddings(&vec![vec![0.5; d]; inputs.len()])
                .to_string()
                .into_bytes()
        })
        .expect(2)
        .create();
    let setup = server_setup(&server.url(), &tmp.path().join("cache"), None);
    let ep = episode();
    let msgs = |u: &str| vec![Message::system("sys"), Message::user(u)];
    for round in 0..2 {
        let mut s = Session::new(&setup, "m", "m1", &ep);
        assert_eq!(
            s.chat("rer", msgs("hello"), &no_gold).unwrap(),
            "echo hello"
        );
        assert_eq!(
            s.chat("x", msgs("refuse"), &no_gold).unwrap_err().status,
            "llm_refused"
        );
        assert_eq!(
            s.chat("y", msgs("empty"), &no_gold).unwrap_err().status,
            "llm_empty"
        );
        let v = s.embed("aps", &["a".into(), "b".into()]).unwrap();
        assert_eq!((v.len(), v[0].len()), (2, 3));
        let e = s.embed("query", &["short".into()]).unwrap_err();
        assert_eq!(e.status, "embedding_failed", "round {round}");
        assert!(e.message.contains("2 dimensions"));
        assert_eq!(s.calls.len(), 5);
        assert_eq!(s.calls[0]["custom_id"], "m1/instruction_000007/m/rer");
    }
    // The second round was answered from the cache.
    chat.assert();
    embed.assert();
    assert_eq!(setup.store.stats().cache_hits, 5);
}

#[test]
fn a_reply_with_too_few_vectors_fails_the_request() {
    let tmp = tempfile::tempdir().unwrap();
    let mut server = mockito::Server::new();
    let _m = server
        .mock("POST", "/v1/embeddings")
        .with_body(embeddings(&[vec![1.0, 0.0]]).to_string())
        .create();
    let setup = server_setup(&server.url(), &tmp.path().join("cache"), None);
    let ep = episode();
    let mut s = Session::new(&setup, "m", "m1", &ep);
    let e = s.embed("aps", &["a".into(), "b".into()]).unwrap_err();
    assert_eq!(e.status, "embedding_failed");
    assert!(e.message.contains("1 embedding(s) for 2 input(s)"), "{e}");
}

#[test]
fn gold_replies_come_from_the_oracle_and_are_recorded() {
    let setup = gold_setup();
    let ep = episode();
    let mut s = Session::new(&setup, "m", "m1", &ep);
    let r = s.chat("rer", vec![Message::user("x")], &|| Ok("gold!".into()));
    assert_eq!(r.unwrap(), "gold!");
    assert_eq!(
        s.chat("t", vec![], &no_gold).unwrap_err().status,
        "gold_unavailable"
    );
    assert_eq!(s.calls[0]["gold"], true);
    assert!(setup.label().starts_with("[GOLD replies]"));
}

#[test]
fn gold_replies_go_through_the_cache_so_a_cache_only_run_repeats_them() {
    let tmp = tempfile::tempdir().unwrap();
    let cache = tmp.path().join("cache");
    let with_cache = |cache_only| ModelSetup {
        store: Store::new(Some(ResponseCache::new(&cache)), None, cache_only),
        ..gold_setup()
    };
    let ep = episode();
    let msgs = |u: &str| vec![Message::system("sys"), Message::user(u)];
    let first = with_cache(false);
    let mut s = Session::new(&first, "m", "m1", &ep);
    assert_eq!(
        s.chat("a", msgs("x"), &|| Ok("gold a".into())).unwrap(),
        "gold a"
    );
    // An oracle that cannot answer is not cached, and fails the same way each time.
    assert_eq!(
        s.chat("b", msgs("y"), &no_gold).unwrap_err().status,
        "gold_unavailable"
    );
    assert_eq!(first.store.stats().fetched, 1);
    let second = with_cache(true);
    let mut s2 = Session::new(&second, "m", "m1", &ep);
    // The cached reply answers, not the oracle (which now says something else).
    assert_eq!(
        s2.chat("a", msgs("x"), &|| Ok("changed".into())).unwrap(),
        "gold a"
    );
    assert_eq!(
        s2.chat("b", msgs("y"), &no_gold).unwrap_err().status,
        "gold_unavailable"
    );
    // A request the first run never made is a cache-only miss, not an oracle answer.
    let miss = s2
        .chat("c", msgs("z"), &|| Ok("gold c".into()))
        .unwrap_err();
    assert_eq!(miss.status, "gold_unavailable");
    assert!(miss.message.contains("--llm-cache-only"), "{miss}");
    assert_eq!(second.store.stats().cache_hits, 1);
    // The records are the same whether the reply came from the oracle or the cache.
    assert_eq!(s.calls[0], s2.calls[0]);
    // A server's model of the same messages is not answered by the oracle's entry.
    let http = server_setup("http://offline.invalid", &cache, None);
    let http = ModelSetup {
        store: Store::new(Some(ResponseCache::new(&cache)), None, true),
        ..http
    };
    let mut s3 = Session::new(&http, "m", "m1", &ep);
    assert_eq!(
        s3.chat("a", msgs("x"), &no_gold).unwrap_err().status,
        "llm_failed"
    );
}

#[test]
fn batch_round_trip_with_chat_and_embeddings() {
    let tmp = tempfile::tempdir().unwrap();
    let cache = tmp.path().join("cache");
    let batch = tmp.path().join("batch.jsonl");
    let setup = server_setup("http://offline.invalid", &cache, Some(&batch));
    let ep = episode();
    let mut s = Session::new(&setup, "m", "m1", &ep);
    assert_eq!(
        s.chat("rer", vec![Message::user("q")], &no_gold)
            .unwrap_err()
            .status,
        "pending"
    );
    assert_eq!(s.embed("aps", &["a".into()]).unwrap_err().status, "pending");
    setup.store.batch.as_ref().unwrap().finish().unwrap();
    let lines: Vec<Value> = std::fs::read_to_string(&batch)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 2);
    // The provider's answers, in the Batch output format.
    let mut out = String::new();
    for l in &lines {
        let body = if l["url"] == "/v1/embeddings" {
            embeddings(&[vec![0.1, 0.2]])
        } else {
            assert_eq!(l["url"], "/v1/chat/completions");
            completion("F a")
        };
        out.push_str(&json!({"custom_id": l["custom_id"], "response": {"status_code": 200, "body": body}, "error": null}).to_string());
        out.push('\n');
    }
    let replies = tmp.path().join("out.jsonl");
    std::fs::write(&replies, out).unwrap();
    let r = import_batch_files(&[replies], &ResponseCache::new(&cache)).unwrap();
    assert_eq!((r.imported, r.failed.len()), (2, 0), "{r:?}");
    let again = server_setup("http://offline.invalid", &cache, None);
    let mut s = Session::new(&again, "m", "m1", &ep);
    assert_eq!(
        s.chat("rer", vec![Message::user("q")], &no_gold).unwrap(),
        "F a"
    );
    assert_eq!(s.embed("aps", &["a".into()]).unwrap(), vec![vec![0.1, 0.2]]);
}

#[test]
fn only_the_methods_that_embed_text_name_their_embeddings() {
    let setup = gold_setup();
    assert_eq!(setup.chat_label(), "[GOLD replies]");
    assert!(setup.label().contains("LEXICAL"), "{}", setup.label());
    assert!(m2rc_baselines::uses_embeddings("lang2ltl"));
    assert!(m2rc_baselines::uses_embeddings("lang2ltl-2"));
    for name in ["sayplan", "osg-llm", "limp", "ltlcodegen", "iln"] {
        assert!(!m2rc_baselines::uses_embeddings(name), "{name}");
    }
}
