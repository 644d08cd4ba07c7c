//! Planner semantics and call handling on small hand-made scene graphs.

use super::graph::{Node, SceneGraph};
use super::reply::parse_ltl;
use super::*;
use std::collections::BTreeMap;

/// A 10 x 10 house: room 1 left of a wall at column 5, room 2 right of it, one door at (5, 5)
/// (labelled room 1); `object_9` is the 3 x 3 block around (2, 8), `object_7` the block around
/// (8, 2).
fn two_rooms() -> SceneGraph {
    let n = 10;
    let trav: Vec<bool> = (0..n * n).map(|i| i % n != 5 || i / n == 5).collect();
    let cells = |f: &dyn Fn(usize, usize) -> bool| -> Vec<u32> {
        (0..n * n)
            .filter(|&i| trav[i] && f(i / n, i % n))
            .map(|i| i as u32)
            .collect()
    };
    let node = |id: &str, ap: &str, room: Option<u32>, cells: Vec<u32>| Node {
        id: id.into(),
        ap: ap.into(),
        category: id.split('_').next().unwrap_or("").into(),
        name: id.into(),
        room,
        cells,
    };
    let nodes = vec![
        node("floor_0", "enter(floor_0)", None, cells(&|_, _| true)),
        node("room_1", "enter(room_1)", Some(1), cells(&|_, c| c <= 5)),
        node("room_2", "enter(room_2)", Some(2), cells(&|_, c| c >= 6)),
        node(
            "object_9",
            "reach(object_9)",
            Some(2),
            cells(&|r, c| r.abs_diff(2) <= 1 && c.abs_diff(8) <= 1),
        ),
        node(
            "object_7",
            "reach(object_7)",
            Some(1),
            cells(&|r, c| r.abs_diff(8) <= 1 && c.abs_diff(2) <= 1),
        ),
    ];
    let adjacency = BTreeMap::from([(1, vec![2]), (2, vec![1])]);
    SceneGraph::from_parts(n, trav, nodes, adjacency)
}

fn s(x: &[&str]) -> Vec<String> {
    x.iter().map(|v| v.to_string()).collect()
}

fn plan_with(
    g: &SceneGraph,
    goals: &[&str],
    avoids: &[&str],
    preferred: &[u32],
    limit: u64,
) -> Planned {
    let (goals, avoids) = (s(goals), s(avoids));
    let allowed = allowed_aps(&goals, &avoids);
    let f = reply::built(&allowed, &goals, &avoids);
    plan(
        g,
        &f,
        &allowed,
        &goals,
        &avoids,
        preferred,
        Cell::new(8, 8),
        Some(2),
        limit,
    )
}

fn used(p: &Planned) -> Value {
    p.record["used"].clone()
}

#[test]
fn the_product_search_visits_goals_in_order_and_keeps_out_of_avoided_regions() {
    let g = two_rooms();
    let p = plan_with(
        &g,
        &["reach(object_7)", "reach(object_9)"],
        &[],
        &[],
        250_000,
    );
    assert_eq!(used(&p), json!("product"));
    let t = p.trajectory.unwrap();
    let in_node = |id: &str, c: &Cell| g.node(id).unwrap().cells.contains(&(c.row * 10 + c.col));
    let first7 = t.iter().position(|c| in_node("object_7", c)).unwrap();
    assert!(in_node("object_9", t.last().unwrap()));
    assert!(t[first7..].iter().any(|c| in_node("object_9", c)));
    assert!(
        t.iter().all(|c| c.col != 5 || c.row == 5),
        "through the door"
    );
    // Avoiding room 1 makes object 7 unreachable: no route, and no fallback with avoids.
    let p = plan_with(&g, &["reach(object_7)"], &["enter(room_1)"], &[], 250_000);
    assert_eq!(p.trajectory, None);
    assert_eq!(p.record["product"]["result"], json!("no_route"));
    assert_eq!(used(&p), json!(null));
}

#[test]
fn past_the_expansion_limit_the_room_skeleton_is_tried_before_plain_sequential_search() {
    let g = two_rooms();
    // One expansion is not enough for the product search.
    let p = plan_with(&g, &["reach(object_7)"], &[], &[], 1);
    assert_eq!(p.record["product"]["result"], json!("expansion_limit"));
    assert_eq!(p.record["product"]["expansions"], json!(1));
    assert_eq!(used(&p), json!("room_skeleton"));
    assert_eq!(
        p.record["skeleton_goals"],
        json!(["enter(room_1)", "reach(object_7)"])
    );
    let t = p.trajectory.unwrap();
    assert_eq!(t[0], Cell::new(8, 8));
    assert!(g.node("object_7").unwrap().cells.contains(&{
        let c = t.last().unwrap();
        c.row * 10 + c.col
    }));
    // Each step of the route is one 8-connected move.
    assert!(t.windows(2).all(|w| w[0].row.abs_diff(w[1].row) <= 1
        && w[0].col.abs_diff(w[1].col) <= 1
        && w[0] != w[1]));
}

#[test]
fn without_a_room_path_the_plain_sequential_search_is_the_last_resort() {
    let mut g = two_rooms();
    g.adjacency.clear();
    let p = plan_with(&g, &["reach(object_7)"], &[], &[], 1);
    assert_eq!(p.record["skeleton_goals"], json!(null));
    assert_eq!(used(&p), json!("sequential"));
    // With an avoid, the limit ends the episode: the fallbacks would ignore the avoid.
    let p = plan_with(&g, &["reach(object_7)"], &["reach(object_9)"], &[], 1);
    assert_eq!(p.trajectory, None);
    assert_eq!(p.record["product"]["result"], json!("expansion_limit"));
    assert_eq!(used(&p), json!(null));
}

#[test]
fn the_skeleton_search_tries_the_models_preferred_rooms_first() {
    let mut g = two_rooms();
    g.nodes.push(Node {
        id: "object_5".into(),
        ap: "reach(object_5)".into(),
        category: "x".into(),
        name: "x".into(),
        room: Some(4),
        cells: vec![0],
    });
    let g = SceneGraph::from_parts(
        g.n,
        g.traversable.clone(),
        g.nodes.clone(),
        BTreeMap::from([
            (1, vec![2, 3]),
            (2, vec![1, 4]),
            (3, vec![1, 4]),
            (4, vec![2, 3]),
        ]),
    );
    let goals = s(&["reach(object_5)"]);
    assert_eq!(
        fallback::skeleton_goals(&g, Some(1), &goals, &[]).unwrap(),
        s(&["enter(room_2)", "enter(room_4)", "reach(object_5)"])
    );
    assert_eq!(
        fallback::skeleton_goals(&g, Some(1), &goals, &[3]).unwrap(),
        s(&["enter(room_3)", "enter(room_4)", "reach(object_5)"])
    );
    assert_eq!(fallback::skeleton_goals(&g, None, &goals, &[]), None);
}

/// Replies scripted per call.
struct Script(Vec<Result<String, CallError>>, Vec<String>);

impl Ask for Script {
    fn ask(&mut self, call: &str, _system: &str, user: &str) -> Result<String, CallError> {
        self.1.push(format!("{call}: {user}"));
        if self.0.is_empty() {
            return Err(CallError::Failed("no more replies".into()));
        }
        self.0.remove(0)
    }
}

fn demo() -> SemanticMap {
    m2rc_stdlib::demo::demo_map().unwrap()
}

fn start_of(map: &SemanticMap, g: &SceneGraph) -> Cell {
    let n = map.n();
    let i = g.nodes[0].cells[g.nodes[0].cells.len() / 2] as usize;
    Cell::new((i / n) as u32, (i % n) as u32)
}

#[test]
fn malformed_refused_and_unknown_replies_end_the_episode_at_the_start_with_the_call_named() {
    let map = demo();
    let g = SceneGraph::build(&map);
    let start = start_of(&map, &g);
    let room = g
        .nodes
        .iter()
        .find(|x| x.id.starts_with("room_"))
        .unwrap()
        .id
        .clone();
    type Case = (Vec<Result<String, CallError>>, &'static str, &'static str);
    let cases: Vec<Case> = vec![
        (
            vec![Ok("I cannot help with that.".into())],
            "grounding",
            "no JSON object",
        ),
        (
            vec![Err(CallError::Failed("HTTP 400: refused".into()))],
            "grounding",
            "refused",
        ),
        (
            vec![Ok(r#"{"ordered_goal_entities": ["room_999"]}"#.into())],
            "grounding",
            "not an id",
        ),
        (
            vec![Ok(r#"{"ordered_goal_entities": []}"#.into())],
            "grounding",
            "no goal",
        ),
        (
            vec![
                Ok(format!(
                    r#"```json
{{"ordered_goal_entities": ["{room}"]}}
```"#
                )),
                Ok(r#"{"ltl_prefix": "F &"}"#.into()),
            ],
            "ltl",
            "ends early",
        ),
        (
            vec![
                Ok(format!(r#"{{"ordered_goal_entities": ["{room}"]}}"#)),
                Ok(r#"{"ltl_prefix": null}"#.into()),
                Ok("no".into()),
            ],
            "heuristic",
            "no JSON object",
        ),
    ];
    for (replies, call, why) in cases {
        let mut script = Script(replies, vec![]);
        let out = run_episode(&map, &g, "go to the room", start, &mut script);
        assert_eq!(out.status, "ltl_translation_failed", "{why}");
        assert_eq!(out.trajectory, vec![start]);
        assert_eq!(out.record["failed_call"], json!(call));
        assert!(
            out.record["error"].as_str().unwrap().contains(why),
            "{}",
            out.record
        );
    }
    let mut script = Script(vec![Err(CallError::Pending("ep-1".into()))], vec![]);
    let out = run_episode(&map, &g, "go", start, &mut script);
    assert_eq!(out.status, "pending");
}

#[test]
fn a_missing_formula_is_built_from_the_grounding_and_the_route_reaches_the_goal() {
    let map = demo();
    let g = SceneGraph::build(&map);
    let start = start_of(&map, &g);
    let target = g
        .nodes
        .iter()
        .rfind(|x| x.id.starts_with("room_") && !x.cells.is_empty())
        .unwrap()
        .clone();
    let mut script = Script(
        vec![
            Ok(format!(
                r#"{{"ordered_goal_entities": ["{}"], "avoid_entities": []}}"#,
                target.id
            )),
            Ok(r#"{"notes": "no formula"}"#.into()),
            Ok(r#"{"preferred_nodes": ["room_424242"]}"#.into()),
        ],
        vec![],
    );
    let out = run_episode(&map, &g, "go to that room", start, &mut script);
    assert_eq!(out.status, "ok", "{}", out.record);
    assert_eq!(out.record["ltl"]["source"], json!("built_from_grounding"));
    assert_eq!(
        out.record["ltl"]["prefix"],
        json!(format!("F {}", target.ap))
    );
    assert_eq!(
        out.record["heuristic"]["ignored_ids"],
        json!(["room_424242"])
    );
    let last = out.trajectory.last().unwrap();
    assert!(
        target
            .cells
            .contains(&(last.row * map.n() as u32 + last.col))
    );
    // The three calls, in order; the grounding call shows the graph without coordinates.
    let calls: Vec<&str> = script
        .1
        .iter()
        .map(|c| c.split(':').next().unwrap())
        .collect();
    assert_eq!(calls, CALLS);
    assert!(!script.1[0].contains("center") && script.1[0].contains("connected_rooms"));
}

#[test]
fn an_ast_reply_is_read_and_a_bad_one_is_refused() {
    let allowed = s(&["enter(room_1)", "reach(object_9)"]);
    let ast = r#"{"ltl_ast": {"op": "&", "args": [{"op": "F", "args": [{"ap": "reach(object_9)"}]},
        {"op": "G", "args": [{"op": "!", "args": [{"ap": "enter(room_1)"}]}]}]}}"#;
    let (f, src) = parse_ltl(ast, &allowed, &[], &[]).unwrap();
    assert_eq!(src, reply::FormulaSource::Ast);
    assert_eq!(
        prefix::to_prefix(&f, &allowed),
        "& F reach(object_9) G ! enter(room_1)"
    );
    let bad = r#"{"ltl_ast": {"op": "F", "args": []}}"#;
    assert!(
        parse_ltl(bad, &allowed, &[], &[])
            .unwrap_err()
            .contains("takes 1")
    );
}
