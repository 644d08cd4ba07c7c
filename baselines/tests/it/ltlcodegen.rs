//! LTLCodeGen end to end on the demo house: the gold program of a fixture episode, and a mock
//! server's attempts (bad code retried with its error, a refusal).

use crate::osgllm::{block, demo, fixture, object};
use crate::support::*;
use m2rc_baselines::ltlcodegen::method::LtlCodeGen;
use m2rc_benchmark::methods::Method;
use m2rc_stdlib::grid::Cell;
use serde_json::{Value, json};
use std::sync::{Arc, Mutex};

#[test]
fn the_gold_program_of_the_fixture_episode_gives_the_annotated_route() {
    let map = demo();
    let ep = fixture(&map.map);
    let m = LtlCodeGen::new(Arc::new(gold_setup()));
    let p = m.predict(&map, &ep).unwrap();
    let b = block(&p, "ltlcodegen");
    assert_eq!(p.status, None, "{b}");
    let fridge = object(&map.map, "fridge");
    let code = b["attempts"][0]["code"].as_str().unwrap();
    assert_eq!(
        code,
        format!(
            "def question():\n    return ltl_and(ltl_eventually(ltl_and(ap(\"object_{fridge}\"), \
             ltl_eventually(ap(\"room_6\")))), ltl_always(ltl_not(ap(\"room_4\"))))\n"
        )
    );
    let centre = map.map.object(fridge).unwrap().center;
    let t = &p.trajectory;
    let near = |c: &Cell| (c.row as f64 - centre[0]).hypot(c.col as f64 - centre[1]) <= 20.0;
    let reached = t.iter().position(near).unwrap();
    assert!(t[reached..].iter().any(|c| map.map.room_at(*c) == 6));
    assert_eq!(map.map.room_at(*t.last().unwrap()), 6);
    assert!(t.iter().all(|c| map.map.room_at(*c) != 4));
    assert_eq!(b["removed_initial_aps"], json!([]));
}

#[test]
fn bad_code_is_retried_with_its_error_and_a_refusal_ends_the_episode() {
    let map = demo();
    let ep = fixture(&map.map);
    let fridge = object(&map.map, "fridge");
    let tmp = tempfile::tempdir().unwrap();
    let seen: Arc<Mutex<Vec<String>>> = Arc::default();
    let mut server = mockito::Server::new();
    let log = seen.clone();
    let _m = server
        .mock("POST", "/v1/chat/completions")
        .with_body_from_request(move |req| {
            let body: Value = serde_json::from_slice(req.body().unwrap()).unwrap();
            let user = body["messages"][1]["content"].as_str().unwrap().to_string();
            log.lock().unwrap().push(user.clone());
            let reply = if user.contains("Previous code") {
                format!("```python\ndef question():\n    return ltl_eventually(ap(\"object_{fridge}\"))\n```")
            } else {
                "def question():\n    import os\n    return ap(\"room_1\")\n".to_string()
            };
            completion(&reply).to_string().into_bytes()
        })
        .create();
    let setup = Arc::new(server_setup(&server.url(), &tmp.path().join("c"), None));
    let p = LtlCodeGen::new(setup).predict(&map, &ep).unwrap();
    let b = block(&p, "ltlcodegen");
    assert_eq!(p.status, None, "{b}");
    let seen = seen.lock().unwrap();
    assert_eq!(seen.len(), 2);
    assert!(
        seen[1].contains("import os") && seen[1].contains("`import` is not part of the sandbox")
    );
    assert_eq!(b["attempts"].as_array().unwrap().len(), 2);
    assert_eq!(b["formula"], json!(format!("F object_{fridge}")));
    // A refusal: no retry, the start-only route.
    let mut refusing = mockito::Server::new();
    let _r = refusing
        .mock("POST", "/v1/chat/completions")
        .with_body(json!({"choices": [{"message": {"role": "assistant", "content": null, "refusal": "no"}, "finish_reason": "stop"}]}).to_string())
        .expect(1)
        .create();
    let setup = Arc::new(server_setup(&refusing.url(), &tmp.path().join("r"), None));
    let p = LtlCodeGen::new(setup).predict(&map, &ep).unwrap();
    assert_eq!(p.status.as_deref(), Some("codegen_failed"));
    assert!(p.trajectory.is_empty());
    assert!(block(&p, "ltlcodegen").to_string().contains("llm_refused"));
}
