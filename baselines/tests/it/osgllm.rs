//! OSG-LLM end to end on the demo house: gold replies on fixture episodes, a mock server's call
//! sequence (good, malformed and refused replies), and the batch round trip of its three calls.

use crate::support::*;
use m2rc_baselines::osgllm::graph::SceneGraph;
use m2rc_baselines::osgllm::method::OsgLlm;
use m2rc_benchmark::episode::{ConstraintKind, Episode, HardConstraint, Scope, StartPose};
use m2rc_benchmark::methods::{Method, Prediction, PreparedMap};
use m2rc_llm::{ResponseCache, import_batch_files};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use serde_json::{Value, json};
use std::sync::Arc;

pub fn demo() -> PreparedMap {
    PreparedMap::new(m2rc_stdlib::demo::demo_map().unwrap())
}

pub fn object(map: &SemanticMap, category: &str) -> u32 {
    map.objects
        .iter()
        .find(|o| o.category == category)
        .unwrap()
        .id
}

fn constraint(
    id: &str,
    kind: ConstraintKind,
    cells: Vec<[i64; 2]>,
    object: Option<u32>,
    order: Option<i64>,
) -> HardConstraint {
    let mut h = HardConstraint::freeform(id, kind, cells);
    h.object_id = object.map(i64::from);
    h.order = order;
    h.label = Some(id.to_string());
    h.scope = Some(Scope::global());
    h
}

/// An episode on the demo house: to the fridge, then into bedroom 3 (room 6, behind the
/// kitchen), never into bathroom 1 (room 4).
pub fn fixture(map: &SemanticMap) -> Episode {
    let fridge = map.object(object(map, "fridge")).unwrap();
    let cells = |v: Vec<Cell>| v.iter().map(|c| [c.row as i64, c.col as i64]).collect();
    Episode {
        id: Some(1),
        map_id: Some("demo".into()),
        instruction: Some(
            "Go to the fridge, then into the small bedroom behind the kitchen. Never enter the big bathroom."
                .into(),
        ),
        start_pose: Some(StartPose {
            row: Some(40),
            col: Some(112),
            ..StartPose::default()
        }),
        hard_constraints: vec![
            constraint("start", ConstraintKind::MustPass, vec![[40, 112]], None, Some(1)),
            constraint(
                "target_1",
                ConstraintKind::MustPass,
                cells(fridge.footprint.clone()),
                Some(fridge.id),
                Some(2),
            ),
            constraint("target_2", ConstraintKind::MustPass, cells(map.room_cells(6)), None, Some(3)),
            constraint("avoid_1", ConstraintKind::MustAvoid, cells(map.room_cells(4)), None, None),
        ],
        ..Episode::default()
    }
}

pub fn block<'a>(p: &'a Prediction, key: &str) -> &'a Value {
    p.extra.get(key).unwrap()
}

#[test]
fn gold_replies_on_the_fixture_episode_give_the_annotated_route() {
    let map = demo();
    let ep = fixture(&map.map);
    let m = OsgLlm::new(Arc::new(gold_setup()));
    let p = m.predict(&map, &ep).unwrap();
    let b = block(&p, "osg-llm");
    assert_eq!(p.status, None, "{b}");
    let g = SceneGraph::build(&map.map);
    let fridge = g
        .node(&format!("object_{}", object(&map.map, "fridge")))
        .unwrap();
    let n = map.map.n() as u32;
    let at = |c: &Cell| c.row * n + c.col;
    let t = &p.trajectory;
    assert_eq!(t[0], Cell::new(40, 112));
    let reached = t
        .iter()
        .position(|c| fridge.cells.contains(&at(c)))
        .unwrap();
    assert!(t[reached..].iter().any(|c| map.map.room_at(*c) == 6));
    assert_eq!(map.map.room_at(*t.last().unwrap()), 6);
    assert!(t.iter().all(|c| map.map.room_at(*c) != 4));
    assert_eq!(b["planner"]["used"], json!("product"));
    assert_eq!(
        b["ltl"]["prefix"],
        json!(format!(
            "& F & {} F enter(room_6) G ! enter(room_4)",
            fridge.ap
        ))
    );
    let calls: Vec<&Value> = b["calls"].as_array().unwrap().iter().collect();
    assert_eq!(calls.len(), 3);
    assert!(calls.iter().all(|c| c["gold"] == json!(true)));
    // Same inputs, same bytes.
    let again = m.predict(&map, &ep).unwrap();
    assert_eq!(again, p);
}

/// A mock server answering each of OSG-LLM's calls by its system prompt.
fn server(grounding: &str, ltl: &str) -> (mockito::ServerGuard, mockito::Mock) {
    let mut server = mockito::Server::new();
    let (grounding, ltl) = (grounding.to_string(), ltl.to_string());
    let mock = server
        .mock("POST", "/v1/chat/completions")
        .with_body_from_request(move |req| {
            let body: Value = serde_json::from_slice(req.body().unwrap()).unwrap();
            let system = body["messages"][0]["content"].as_str().unwrap();
            let reply = if system.contains("scene graph (a floor") {
                grounding.clone()
            } else if system.contains("prefix notation") {
                ltl.clone()
            } else {
                r#"{"preferred_nodes": ["room_2"], "reason": "the kitchen"}"#.to_string()
            };
            if reply == "REFUSE" {
                return json!({"choices": [{"message": {"role": "assistant", "content": null, "refusal": "I cannot"}, "finish_reason": "stop"}]}).to_string().into_bytes();
            }
            completion(&reply).to_string().into_bytes()
        })
        .create();
    (server, mock)
}

#[test]
fn a_mock_servers_replies_are_called_in_order_and_bad_ones_fail_the_episode() {
    let map = demo();
    let ep = fixture(&map.map);
    let fridge = object(&map.map, "fridge");
    let good_grounding = format!(
        r#"{{"ordered_goal_entities": ["object_{fridge}"], "avoid_entities": ["room_4"]}}"#
    );
    let good_ltl = format!(r#"{{"ltl_prefix": "& F reach(object_{fridge}) G ! enter(room_4)"}}"#);
    let tmp = tempfile::tempdir().unwrap();
    // Good replies: three calls, named by step, and a route to the fridge.
    let (s, mock) = server(&good_grounding, &good_ltl);
    let setup = Arc::new(server_setup(&s.url(), &tmp.path().join("c1"), None));
    let p = OsgLlm::new(setup).predict(&map, &ep).unwrap();
    let b = block(&p, "osg-llm");
    assert_eq!(p.status, None, "{b}");
    let ids: Vec<&str> = b["calls"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["custom_id"].as_str().unwrap())
        .collect();
    assert_eq!(
        ids,
        [
            "demo/instruction_000001/osg-llm/grounding",
            "demo/instruction_000001/osg-llm/ltl",
            "demo/instruction_000001/osg-llm/heuristic"
        ]
    );
    assert_eq!(b["heuristic"]["preferred_rooms"], json!([2]));
    mock.expect(3).assert();
    // Malformed, unknown and refused replies: the episode fails at the call that went wrong.
    let cases = [
        (
            "Sure, happy to help!".to_string(),
            good_ltl.clone(),
            "grounding",
            "no JSON object",
        ),
        (
            r#"{"ordered_goal_entities": ["object_999999"]}"#.to_string(),
            good_ltl.clone(),
            "grounding",
            "not an id",
        ),
        (
            "REFUSE".to_string(),
            good_ltl.clone(),
            "grounding",
            "llm_refused",
        ),
        (
            good_grounding.clone(),
            r#"{"ltl_prefix": "& F"}"#.to_string(),
            "ltl",
            "ends early",
        ),
        (
            good_grounding.clone(),
            "REFUSE".to_string(),
            "ltl",
            "llm_refused",
        ),
    ];
    for (k, (g, l, call, why)) in cases.into_iter().enumerate() {
        let (s, _m) = server(&g, &l);
        let setup = Arc::new(server_setup(
            &s.url(),
            &tmp.path().join(format!("c{k}x")),
            None,
        ));
        let p = OsgLlm::new(setup).predict(&map, &ep).unwrap();
        let b = block(&p, "osg-llm");
        assert_eq!(p.status.as_deref(), Some("ltl_translation_failed"), "{b}");
        assert!(
            p.trajectory.is_empty(),
            "scored as the start-only route by the runner"
        );
        assert_eq!(b["failed_call"], json!(call));
        assert!(b.to_string().contains(why), "{why}: {b}");
    }
}

#[test]
fn three_calls_are_three_batch_rounds() {
    let map = demo();
    let ep = fixture(&map.map);
    let fridge = object(&map.map, "fridge");
    let tmp = tempfile::tempdir().unwrap();
    let cache = tmp.path().join("cache");
    let replies = [
        format!(r#"{{"ordered_goal_entities": ["object_{fridge}"]}}"#),
        format!(r#"{{"ltl_prefix": "F reach(object_{fridge})"}}"#),
        r#"{"preferred_nodes": []}"#.to_string(),
    ];
    for (round, reply) in replies.iter().enumerate() {
        let batch = tmp.path().join(format!("batch{round}.jsonl"));
        let setup = Arc::new(server_setup("http://offline.invalid", &cache, Some(&batch)));
        let p = OsgLlm::new(setup.clone()).predict(&map, &ep).unwrap();
        assert_eq!(p.status.as_deref(), Some("pending"), "round {round}");
        setup.store.batch.as_ref().unwrap().finish().unwrap();
        let lines: Vec<Value> = std::fs::read_to_string(&batch)
            .unwrap()
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(lines.len(), 1, "one new request per round");
        let out = json!({"custom_id": lines[0]["custom_id"], "response": {"status_code": 200, "body": completion(reply)}, "error": null});
        let file = tmp.path().join(format!("out{round}.jsonl"));
        std::fs::write(&file, out.to_string() + "\n").unwrap();
        let r = import_batch_files(&[file], &ResponseCache::new(&cache)).unwrap();
        assert_eq!(r.imported, 1);
    }
    let setup = Arc::new(server_setup("http://offline.invalid", &cache, None));
    let p = OsgLlm::new(setup).predict(&map, &ep).unwrap();
    assert_eq!(p.status, None, "{}", block(&p, "osg-llm"));
}

#[test]
fn an_avoided_region_is_said_as_its_room_its_object_or_not_at_all() {
    use m2rc_baselines::osgllm::gold::avoid_nodes;
    let map = demo();
    let m = &map.map;
    let cells = |v: &[Cell]| {
        v.iter()
            .map(|c| [c.row as i64, c.col as i64])
            .collect::<Vec<_>>()
    };
    let avoid = |c: Vec<[i64; 2]>| constraint("a", ConstraintKind::MustAvoid, c, None, None);
    assert_eq!(avoid_nodes(m, &avoid(cells(&m.room_cells(4)))), ["room_4"]);
    // The area around the fridge: its footprint and a ring of cells.
    let fridge = m.object(object(m, "fridge")).unwrap();
    let mut around: Vec<Cell> = Vec::new();
    for c in &fridge.footprint {
        for (dr, dc) in [(0i64, 0i64), (-2, 0), (2, 0), (0, -2), (0, 2)] {
            let (r, k) = (c.row as i64 + dr, c.col as i64 + dc);
            if r >= 0 && k >= 0 {
                around.push(Cell::new(r as u32, k as u32));
            }
        }
    }
    let said = avoid_nodes(m, &avoid(cells(&around)));
    assert!(said.contains(&format!("object_{}", fridge.id)), "{said:?}");
    // A few free cells of the living room with no object in them: nothing the graph can say.
    let free: Vec<Cell> = m
        .room_cells(1)
        .into_iter()
        .filter(|c| m.is_free(*c))
        .take(3)
        .collect();
    assert_eq!(avoid_nodes(m, &avoid(cells(&free))), Vec::<String>::new());
}
