//! SayPlan on the 20×20 two-room fixture: the scene graph against hand-checked counts, and the
//! multi-turn loop (expand, contract, a hidden node turned into feedback, a plan rejected by the
//! verifier then one accepted, the JSON re-asks running out).

use m2rc_baselines::Failure;
use m2rc_baselines::common::gold::GoldPlace;
use m2rc_baselines::common::grid::GridSearch;
use m2rc_baselines::iln::Gold;
use m2rc_baselines::sayplan::graph::{NodeKind, SceneGraph};
use m2rc_baselines::sayplan::{self, GoldScript};
use m2rc_compiler::lower::{Message, Role};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::fixture::two_rooms;
use serde_json::json;

fn graph() -> SceneGraph {
    SceneGraph::build(&two_rooms(), Cell::new(18, 2))
}

#[test]
fn scene_graph_of_the_fixture_matches_the_hand_count() {
    let g = graph();
    // scene, agent, 2 rooms, 10 objects.
    assert_eq!(g.nodes.len(), 14);
    let collapsed = g.collapsed();
    assert_eq!(collapsed.len(), 4);
    let view = g.view_json(&collapsed);
    // scene contains 2 rooms, rooms adjacent through the door, agent located in the bedroom.
    assert_eq!(
        view["edges"],
        json!([
            ["scene_0", "room_1", "contains"],
            ["scene_0", "room_2", "contains"],
            ["room_1", "room_2", "adjacent_to"],
            ["agent_0", "room_1", "located_at"]
        ])
    );
    let bedroom = &view["nodes"][2];
    assert_eq!(bedroom["id"], "room_1");
    assert_eq!(
        (
            bedroom["child_count"].as_u64(),
            bedroom["visible_children"].as_u64()
        ),
        (Some(7), Some(0))
    );
    let room_1 = g.index("room_1").unwrap();
    let mut all = collapsed.clone();
    all.extend(g.nodes[room_1].children.iter().copied());
    let edges = g.view_json(&all)["edges"].as_array().unwrap().len();
    assert_eq!(edges, 2 + 7 + 1 + 1);
    let lamp = &g.nodes[g.index("object_2").unwrap()];
    let NodeKind::Object {
        room,
        approach_cells,
    } = &lamp.kind
    else {
        panic!()
    };
    assert_eq!(*room, Some(1));
    // The lamp at (3, 7): its 4 side neighbours (L1 = 1) first, then the corners.
    let cell = |r, c| Cell::new(r, c);
    assert_eq!(
        approach_cells,
        &[
            cell(2, 7),
            cell(3, 6),
            cell(3, 8),
            cell(4, 7),
            cell(2, 6),
            cell(2, 8),
            cell(4, 6),
            cell(4, 8)
        ]
    );
    // The book (3, 3..=4) lies on the bed (2..=4 x 2..=5): its first ring is bed, so it is
    // approached from the second ring, the free cells around the bed.
    let book = &g.nodes[g.index("object_3").unwrap()];
    let NodeKind::Object { approach_cells, .. } = &book.kind else {
        panic!()
    };
    assert_eq!(approach_cells.first(), Some(&cell(1, 3)));
    assert!(
        approach_cells
            .iter()
            .all(|c| c.row == 1 || c.row == 5 || c.col == 1 || c.col == 6)
    );
}

fn search(mode: &str, cmd: &str, node: &str) -> String {
    json!({"reasoning": "", "mode": mode, "command": {"command_name": cmd, "node_name": node, "plan": null}}).to_string()
}

fn plan(steps: &[&str]) -> String {
    json!({"reasoning": "", "mode": "planning", "command": {"command_name": "none", "node_name": "", "plan": steps}}).to_string()
}

struct Call {
    step: String,
    messages: Vec<Message>,
}

fn run_script(replies: Vec<String>) -> (sayplan::SayPlanOutcome, Vec<Call>) {
    let map = two_rooms();
    let g = graph();
    let mut grid = GridSearch::new(&map);
    let mut replies = replies.into_iter();
    let mut calls = Vec::new();
    let mut ask = |step: &str, messages: Vec<Message>, _gold: Gold<'_>| {
        calls.push(Call {
            step: step.to_string(),
            messages,
        });
        Ok::<_, Failure>(replies.next().expect("an unexpected extra call"))
    };
    let script = GoldScript::default();
    let out = sayplan::run(&g, &mut grid, "go to the fridge", Ok(&script), &mut ask);
    (out, calls)
}

#[test]
fn expand_contract_hidden_node_rejected_plan_then_accepted_plan() {
    let (out, calls) = run_script(vec![
        search("exploring", "expand_node", "room_1"),
        search("exploring", "contract_node", "room_1"),
        // Hidden now: becomes feedback, not a failure.
        search("exploring", "expand_node", "object_8"),
        search("exploring", "expand_node", "room_2"),
        search("planning", "none", ""),
        // object_3 (the book) is not visible (room_1 was contracted).
        plan(&["goto(object_3)"]),
        plan(&["goto(object_8)", "done()"]),
    ]);
    assert_eq!(out.status, "ok");
    let steps: Vec<&str> = calls.iter().map(|c| c.step.as_str()).collect();
    assert_eq!(
        steps,
        [
            "search1", "search2", "search3", "search4", "search5", "plan1", "plan2"
        ]
    );
    // The hidden-node feedback reaches the next search prompt.
    let fourth = &calls[3].messages[1].content;
    assert!(fourth.contains("`object_8` is hidden"), "{fourth}");
    // The verifier's rejection reaches the second planning round, with the previous plan.
    let second = &calls[6].messages[1].content;
    assert!(second.contains("`object_3` is not visible"), "{second}");
    assert!(second.contains("goto(object_3)"));
    assert_eq!(out.info["planning_attempts"][0]["accepted"], false);
    assert_eq!(
        out.info["final_high_level_plan"],
        json!(["goto(object_8)", "done()"])
    );
    // The fridge at rows 2..=3, cols 16..=17: the route ends beside it.
    let end = *out.trajectory.last().unwrap();
    assert!(
        (1..=4).contains(&end.row) && (15..=18).contains(&end.col),
        "{end:?}"
    );
    assert_eq!(out.info["task_subgraph"].as_array().unwrap().len(), 4 + 3);
}

#[test]
fn json_reasks_then_exhausted() {
    let (out, calls) = run_script(vec!["not json".into(), "{\"mode\": 3}".into(), "{}".into()]);
    assert_eq!(out.status, "llm_output_invalid");
    assert_eq!(out.trajectory, vec![Cell::new(18, 2)]);
    let steps: Vec<&str> = calls.iter().map(|c| c.step.as_str()).collect();
    assert_eq!(steps, ["search1", "search1-reask1", "search1-reask2"]);
    // A re-ask carries the bad reply and the reason as the next turns.
    let last = &calls[2].messages;
    assert_eq!(last.len(), 6);
    assert_eq!(last[4].role, Role::Assistant);
    assert!(
        last[5].content.contains("field `mode` is not a string"),
        "{}",
        last[5].content
    );
}

#[test]
fn every_plan_rejected_keeps_the_longest_attempt() {
    let mut replies = vec![search("planning", "none", "")];
    // The first plan reaches room_2 then fails; the others fail at once.
    replies.push(plan(&["goto(room_2)", "goto(scene_0)"]));
    for _ in 0..4 {
        replies.push(plan(&["fly()"]));
    }
    let (out, calls) = run_script(replies);
    assert_eq!(calls.len(), 1 + 5);
    assert_eq!(out.status, "planning_failed");
    assert!(out.trajectory.len() > 1);
    assert!(
        out.info["failure_reason"]
            .as_str()
            .unwrap()
            .contains("not a valid action")
    );
}

#[test]
fn gold_script_expands_the_target_rooms_and_plans_the_targets() {
    let map = two_rooms();
    let g = graph();
    let place = |object: u32, room: u32| GoldPlace {
        expression: None,
        object_id: Some(object),
        room_id: Some(room),
        is_room: false,
        order: None,
        scope: None,
    };
    // An object the map does not have is left to its annotated room.
    let targets = [place(2, 1), place(99, 1), place(8, 2)];
    let script = sayplan::gold_script(&g, &targets);
    assert_eq!(script.expand, ["room_1", "room_2"]);
    assert_eq!(script.targets, ["object_2", "room_1", "object_8"]);
    let mut grid = GridSearch::new(&map);
    let mut gold = |_: &str, _: Vec<Message>, gold: Gold<'_>| {
        gold().map_err(|e| Failure::new("gold_unavailable", e))
    };
    let out = sayplan::run(&g, &mut grid, "x", Ok(&script), &mut gold);
    assert_eq!(out.status, "ok");
    // Two expansions, the switch to planning, one plan.
    assert_eq!(out.info["call_count"], 3 + 1);
    let out = sayplan::run(&g, &mut grid, "x", Err("no destination"), &mut gold);
    assert_eq!(out.status, "gold_unavailable");
}
