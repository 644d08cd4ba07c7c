//! SayPlan and ILN as benchmark methods over the LLM-call helper: a mock server answering a
//! scripted multi-turn conversation (then the cache answering it again without the server), and
//! ILN's two calls as two batch rounds.

use crate::support::*;
use m2rc_baselines::iln::method::Iln;
use m2rc_baselines::sayplan::method::SayPlan;
use m2rc_benchmark::episode::{Episode, StartPose};
use m2rc_benchmark::methods::{Method, PreparedMap};
use m2rc_llm::{ResponseCache, import_batch_files};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::fixture::two_rooms;
use serde_json::{Value, json};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

fn episode() -> Episode {
    Episode {
        id: Some(3),
        map_id: Some("test/two_rooms".into()),
        instruction: Some("go to the fridge in the kitchen".into()),
        start_pose: Some(StartPose {
            row: Some(18),
            col: Some(2),
            ..StartPose::default()
        }),
        ..Episode::default()
    }
}

/// A mock chat server answering the `replies` in order.
fn scripted_server(server: &mut mockito::Server, replies: Vec<String>) -> mockito::Mock {
    let n = replies.len();
    let next = Arc::new(AtomicUsize::new(0));
    server
        .mock("POST", "/v1/chat/completions")
        .with_body_from_request(move |_| {
            let i = next.fetch_add(1, Ordering::SeqCst);
            completion(&replies[i]).to_string().into_bytes()
        })
        .expect(n)
        .create()
}

fn search(mode: &str, cmd: &str, node: &str) -> String {
    json!({"reasoning": "r", "mode": mode, "command": {"command_name": cmd, "node_name": node, "plan": null}}).to_string()
}

fn plan(steps: &[&str]) -> String {
    json!({"reasoning": "r", "mode": "planning", "command": {"command_name": "none", "node_name": "", "plan": steps}}).to_string()
}

#[test]
fn sayplan_over_a_mock_server_then_from_the_cache() {
    let tmp = tempfile::tempdir().unwrap();
    let cache = tmp.path().join("cache");
    let mut server = mockito::Server::new();
    let mock = scripted_server(
        &mut server,
        vec![
            search("exploring", "expand_node", "room_2"),
            "Sure! Here it is: not json".into(),
            search("planning", "none", ""),
            plan(&["goto(object_3)"]),
            plan(&["goto(object_8)", "done()"]),
        ],
    );
    let map = PreparedMap::new(two_rooms());
    let method = SayPlan {
        setup: Arc::new(server_setup(&server.url(), &cache, None)),
    };
    let p = method.predict(&map, &episode()).unwrap();
    mock.assert();
    assert_eq!(p.status, None, "{:?}", p.extra);
    let block = &p.extra["sayplan"];
    assert_eq!(block["status"], "ok");
    let steps: Vec<&str> = block["calls"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["step"].as_str().unwrap())
        .collect();
    assert_eq!(
        steps,
        ["search1", "search2", "search2-reask1", "plan1", "plan2"]
    );
    assert_eq!(block["planning_attempts"][0]["accepted"], false);
    let end = *p.trajectory.last().unwrap();
    assert!(
        (1..=4).contains(&end.row) && (15..=18).contains(&end.col),
        "{end:?}"
    );
    // Again, offline: every call answered from the cache, the same route.
    let again = SayPlan {
        setup: Arc::new(server_setup("http://offline.invalid", &cache, None)),
    };
    let q = again.predict(&map, &episode()).unwrap();
    assert_eq!(q.trajectory, p.trajectory);
    assert_eq!(again.setup.store.stats().cache_hits, 5);
}

#[test]
fn iln_two_calls_as_two_batch_rounds() {
    let tmp = tempfile::tempdir().unwrap();
    let cache = tmp.path().join("cache");
    let map = PreparedMap::new(two_rooms());
    let replies = [
        r#"{"destination_area": "room_2", "reason": "the fridge"}"#,
        r#"{"door_costs": {"passage_0": {"cost": 10}}, "navigation_task": ["room_1", "room_2"], "notes": ""}"#,
    ];
    for (round, reply) in replies.iter().enumerate() {
        let batch = tmp.path().join(format!("batch{round}.jsonl"));
        let method = Iln {
            setup: Arc::new(server_setup("http://offline.invalid", &cache, Some(&batch))),
        };
        let p = method.predict(&map, &episode()).unwrap();
        assert_eq!(p.status.as_deref(), Some("pending"), "round {round}");
        method.setup.store.batch.as_ref().unwrap().finish().unwrap();
        let lines: Vec<Value> = std::fs::read_to_string(&batch)
            .unwrap()
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(lines.len(), 1, "one new request per round");
        let out = json!({"custom_id": lines[0]["custom_id"], "response": {"status_code": 200, "body": completion(reply)}, "error": null});
        let answers = tmp.path().join(format!("answers{round}.jsonl"));
        std::fs::write(&answers, format!("{out}\n")).unwrap();
        let r = import_batch_files(&[answers], &ResponseCache::new(&cache)).unwrap();
        assert_eq!(r.imported, 1);
    }
    let method = Iln {
        setup: Arc::new(server_setup("http://offline.invalid", &cache, None)),
    };
    let p = method.predict(&map, &episode()).unwrap();
    assert_eq!(p.status, None, "{:?}", p.extra);
    assert_eq!(p.trajectory.first(), Some(&Cell::new(18, 2)));
    assert_eq!(p.trajectory.last(), Some(&Cell::new(9, 14)));
    assert_eq!(p.extra["iln"]["calls"].as_array().unwrap().len(), 2);
}

#[test]
fn iln_unknown_area_from_a_server_keeps_the_start_and_says_why() {
    let tmp = tempfile::tempdir().unwrap();
    let mut server = mockito::Server::new();
    let mock = scripted_server(
        &mut server,
        vec![r#"{"destination_area": "garage", "reason": "?"}"#.into()],
    );
    let map = PreparedMap::new(two_rooms());
    let method = Iln {
        setup: Arc::new(server_setup(&server.url(), &tmp.path().join("c"), None)),
    };
    let p = method.predict(&map, &episode()).unwrap();
    mock.assert();
    assert_eq!(p.status.as_deref(), Some("grounding_failed"));
    assert_eq!(p.trajectory, vec![Cell::new(18, 2)]);
    assert!(
        p.extra["iln"]["failure_reason"]
            .as_str()
            .unwrap()
            .contains("garage")
    );
}
