//! ILN on the 20×20 two-room fixture (bedroom columns 0..=8, kitchen 10..=19, one door cell at
//! (8, 9)): the area–passage graph against hand-checked values, and the two calls' failures.

use m2rc_baselines::Failure;
use m2rc_baselines::common::grid::GridSearch;
use m2rc_baselines::iln::graph::AreaGraph;
use m2rc_baselines::iln::{self, prompts};
use m2rc_compiler::lower::Message;
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::fixture::two_rooms;
use std::collections::BTreeMap;

#[test]
fn area_passage_graph_of_the_fixture_matches_the_hand_count() {
    let map = two_rooms();
    let g = AreaGraph::build(&map);
    assert_eq!(g.areas.len(), 2);
    assert_eq!(g.passages.len(), 1);
    let bedroom = &g.areas[0];
    assert_eq!(bedroom.id, "room_1");
    assert_eq!(bedroom.centroid, [9.5, 4.0]);
    // (10, 4) is as near the centroid but is the chair.
    assert_eq!(bedroom.medoid, Cell::new(9, 4));
    assert_eq!(
        bedroom.landmarks,
        [
            "bed",
            "book",
            "chair",
            "house_plant",
            "lamp",
            "rug",
            "shelf"
        ]
    );
    let kitchen = &g.areas[1];
    assert_eq!(kitchen.centroid, [9.5, 14.5]);
    assert_eq!(kitchen.medoid, Cell::new(9, 14));
    assert_eq!(kitchen.landmarks, ["cup", "dining_table", "fridge"]);
    let p = &g.passages[0];
    assert_eq!((p.id.as_str(), p.areas), ("passage_0", (0, 1)));
    // The door cell and the room cell on each side of it.
    assert_eq!((p.anchor, p.width), (Cell::new(8, 9), 3));
    let text = g.serialise();
    assert!(text.contains("room_1: category=bedroom, name=bedroom_1, passages=[passage_0]"));
    assert!(text.contains("passage_0: rooms=room_1<->room_2, anchor=[8,9], width=3"));
    assert!(text.contains("room_2: [cup, dining_table, fridge]"));
}

#[test]
fn start_area_falls_back_to_the_nearest_labelled_free_cell() {
    let map = two_rooms();
    let g = AreaGraph::build(&map);
    assert_eq!(g.start_area(&map, Cell::new(18, 2)), Some(0));
    // The door cell is unlabelled; (8, 8) and (8, 10) are equally near, (8, 8) comes first.
    assert_eq!(g.start_area(&map, Cell::new(8, 9)), Some(0));
}

type Script = Vec<(&'static str, String)>;

/// A scripted model: answers the calls in order, and records the step names it was asked.
fn scripted(
    replies: Script,
) -> impl FnMut(&str, Vec<Message>, iln::Gold<'_>) -> Result<String, Failure> {
    let mut replies = replies.into_iter();
    move |step: &str, _m: Vec<Message>, _gold: iln::Gold<'_>| {
        let (want, reply) = replies.next().expect("an unexpected extra call");
        assert_eq!(step, want);
        Ok(reply)
    }
}

fn run_with(replies: Script) -> iln::IlnOutcome {
    let map = two_rooms();
    let g = AreaGraph::build(&map);
    let mut grid = GridSearch::new(&map);
    let mut ask = scripted(replies);
    iln::run(
        &map,
        &g,
        &mut grid,
        "go to the fridge",
        Cell::new(18, 2),
        Some("room_2"),
        &mut ask,
    )
}

#[test]
fn two_calls_then_a_route_through_the_door_to_the_kitchen_medoid() {
    let out = run_with(vec![
        (
            "destination",
            r#"{"destination_area": "room_2", "reason": "fridge"}"#.into(),
        ),
        (
            "passage_costs",
            r#"```json
{"door_costs": {"passage_0": {"cost": 3}}, "navigation_task": ["room_1", "room_2"], "notes": ""}
```"#
                .into(),
        ),
    ]);
    assert_eq!(out.status, "ok");
    assert_eq!(out.trajectory.first(), Some(&Cell::new(18, 2)));
    assert_eq!(out.trajectory.last(), Some(&Cell::new(9, 14)));
    assert!(out.trajectory.contains(&Cell::new(8, 9)));
    assert_eq!(out.info["graph_planner"]["passages"][0], "passage_0");
    assert_eq!(
        out.info["passage_cost_evaluator"]["costs"]["passage_0"],
        3.0
    );
}

#[test]
fn an_unknown_area_is_a_grounding_failure_with_the_start_only() {
    let out = run_with(vec![(
        "destination",
        r#"{"destination_area": "room_9", "reason": "?"}"#.into(),
    )]);
    assert_eq!(out.status, "grounding_failed");
    assert_eq!(out.trajectory, vec![Cell::new(18, 2)]);
    assert!(
        out.info["failure_reason"]
            .as_str()
            .unwrap()
            .contains("room_9")
    );
}

#[test]
fn malformed_cost_json_is_invalid_output() {
    for bad in [
        r#"{"door_costs": {"passage_0": {"cost": "high"}}}"#,
        r#"{"door_costs": [1, 2]}"#,
        r#"{"door_costs": {"passage_0": {"cost": -1}}"#,
        "no json here",
    ] {
        let out = run_with(vec![
            ("destination", r#"{"destination_area": "room_2"}"#.into()),
            ("passage_costs", bad.into()),
        ]);
        assert_eq!(out.status, "llm_output_invalid", "{bad}");
        assert_eq!(out.trajectory, vec![Cell::new(18, 2)]);
    }
}

#[test]
fn gold_replies_pick_the_target_area_and_neutral_costs() {
    let map = two_rooms();
    let g = AreaGraph::build(&map);
    assert_eq!(
        prompts::read_destination(&g, &prompts::gold_destination_reply("room_2")),
        Ok(1)
    );
    let (costs, notes) =
        prompts::read_costs(&g, &prompts::gold_cost_reply("room_1", "room_2")).unwrap();
    assert_eq!((costs, notes), (BTreeMap::new(), vec![]));
    let mut grid = GridSearch::new(&map);
    let mut gold = |_: &str, _: Vec<Message>, gold: iln::Gold<'_>| {
        gold().map_err(|e| Failure::new("gold_unavailable", e))
    };
    let out = iln::run(
        &map,
        &g,
        &mut grid,
        "x",
        Cell::new(18, 2),
        Some("room_2"),
        &mut gold,
    );
    assert_eq!(out.status, "ok");
    // Without a destination room in the annotations the oracle has no reply.
    let out = iln::run(&map, &g, &mut grid, "x", Cell::new(18, 2), None, &mut gold);
    assert_eq!(out.status, "gold_unavailable");
}

#[test]
fn a_pending_call_makes_the_episode_pending() {
    let map = two_rooms();
    let g = AreaGraph::build(&map);
    let mut grid = GridSearch::new(&map);
    let mut ask = |s: &str, _: Vec<Message>, _: iln::Gold<'_>| Err(Failure::new("pending", s));
    let out = iln::run(
        &map,
        &g,
        &mut grid,
        "x",
        Cell::new(18, 2),
        Some("room_2"),
        &mut ask,
    );
    assert!(out.pending);
}
