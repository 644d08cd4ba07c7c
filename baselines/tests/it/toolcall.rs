//! ToolCall (issue 31): the gold tool-call sequence plans the gold program's route; a scripted
//! conversation against a mock server (several calls in one turn, a blocked repeated failing
//! query, a text reply without `task`, the turn and tool budgets); the batch round trip of turns.

use crate::gold::{build, opts};
use crate::support::*;
use m2rc_baselines::grounding::toolcall::ToolCallMethod;
use m2rc_baselines::grounding::toolcall::conversation::Budgets;
use m2rc_benchmark::methods::method_by_name;
use m2rc_benchmark::runner::{self, read_records};
use m2rc_llm::{ResponseCache, import_batch_files};
use serde_json::{Value, json};
use std::path::Path;
use std::sync::Arc;

fn by_id(records: &[Value]) -> std::collections::BTreeMap<String, Value> {
    records
        .iter()
        .map(|r| {
            (
                format!("{}/{}", r["map_dir"], r["instruction_id"]),
                r.clone(),
            )
        })
        .collect()
}

#[test]
fn toolcall_gold_sequences_plan_the_gold_programs_routes() {
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("suite");
    let m = build(&suite, 6);
    let oracle = tmp.path().join("oracle");
    runner::run(
        method_by_name("oracle").unwrap().as_ref(),
        &opts(&suite, &oracle),
    )
    .unwrap();
    let method = ToolCallMethod::new(Arc::new(gold_setup()));
    let run = |dir: &str| {
        let out = tmp.path().join(dir);
        runner::run(&method, &opts(&suite, &out)).unwrap();
        read_records(&out).unwrap()
    };
    let (one, two) = (run("a"), run("b"));
    assert_eq!(one, two, "same inputs, same records");
    let (o, t) = (by_id(&read_records(&oracle).unwrap()), by_id(&one));
    assert_eq!(t.len(), m.episodes.len());
    let mut same = 0;
    for (k, r) in &t {
        let block = &r["toolcall"];
        assert_eq!(block["gold_replies"], true);
        if r["status"] == "ok" {
            assert_eq!(r["trajectory"], o[k]["trajectory"], "{k}");
            assert!(block["tool_calls"].as_u64().unwrap() <= 32);
            same += 1;
        } else {
            // Only the budget (or a loop the builders cannot say) may stop a gold sequence.
            let s = r["status"].as_str().unwrap();
            assert!(
                ["tool_budget_exhausted", "gold_unavailable"].contains(&s)
                    || o[k]["status"] != "ok",
                "{k}: {s}: {block}"
            );
        }
    }
    assert!(same >= 2, "{same}");
}

/// A tool-call reply.
fn calls(list: &[(&str, Value)]) -> Value {
    let calls: Vec<Value> = list
        .iter()
        .enumerate()
        .map(|(i, (name, args))| {
            json!({"id": format!("call_{i}"), "type": "function",
                   "function": {"name": name, "arguments": args.to_string()}})
        })
        .collect();
    json!({"choices": [{"message": {"role": "assistant", "content": null, "tool_calls": calls},
                        "finish_reason": "tool_calls"}],
           "usage": {"prompt_tokens": 100, "completion_tokens": 7}})
}

fn run_against(
    suite: &Path,
    out: &Path,
    cache: &Path,
    budgets: Budgets,
    reply: impl Fn(usize, &Value) -> Value + Send + Sync + 'static,
) -> Value {
    let mut server = mockito::Server::new();
    let _m = server
        .mock("POST", "/v1/chat/completions")
        .with_body_from_request(move |req| {
            let body: Value = serde_json::from_slice(req.body().unwrap()).unwrap();
            assert!(
                body["tools"].as_array().unwrap().len() > 50,
                "the tools are sent"
            );
            let msgs = body["messages"].as_array().unwrap();
            let turn = msgs.iter().filter(|m| m["role"] == "assistant").count();
            reply(turn, body.get("messages").unwrap())
                .to_string()
                .into_bytes()
        })
        .create();
    let mut setup = server_setup(&server.url(), cache, None);
    setup.embed_http = None;
    let mut method = ToolCallMethod::new(Arc::new(setup));
    method.budgets = budgets;
    runner::run(&method, &opts(suite, out)).unwrap();
    read_records(out).unwrap().remove(0)
}

#[test]
fn a_scripted_conversation_blocks_a_repeated_failing_query_and_submits() {
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("suite");
    build(&suite, 1);
    let bad = json!({"category": "unicorn"});
    let script = move |turn: usize, msgs: &Value| match turn {
        // Several calls in one turn: one fails, one makes `set#1`.
        0 => calls(&[("objects", bad.clone()), ("rooms", json!({}))]),
        // The failing query again: tries 2 and 3 run, the 4th is blocked without running.
        1 => calls(&[
            ("objects", bad.clone()),
            ("objects", bad.clone()),
            ("objects", bad.clone()),
        ]),
        2 => {
            let last = msgs.as_array().unwrap().last().unwrap();
            assert_eq!(last["role"], "tool");
            assert_eq!(last["tool_call_id"], "call_2");
            assert!(
                last["content"]
                    .as_str()
                    .unwrap()
                    .contains("QUERY_RETRY_LIMIT_REACHED")
            );
            calls(&[
                ("nearest", json!({"of": "set#1"})),
                ("segment", json!({"target": "room#2"})),
            ])
        }
        _ => calls(&[("task", json!({"segments": ["segment#3"]}))]),
    };
    let rec = run_against(
        &suite,
        &tmp.path().join("run"),
        &tmp.path().join("cache"),
        Budgets::default(),
        script,
    );
    let b = &rec["toolcall"];
    assert_eq!(rec["status"], "ok", "{b}");
    assert_eq!(b["turns"], 4);
    assert_eq!(b["tool_calls"], 8);
    assert_eq!(b["blocked_calls"], 1);
    assert_eq!(b["failed_calls"], 3);
    assert_eq!(b["prompt_tokens"], 400);
    assert!(!rec["trajectory"].as_array().unwrap().is_empty());
    assert!(
        rec["program"]
            .as_str()
            .unwrap()
            .contains("go rooms().nearest()")
    );
}

#[test]
fn text_without_task_and_the_budgets_end_the_conversation() {
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("suite");
    build(&suite, 1);
    let text = run_against(
        &suite,
        &tmp.path().join("text"),
        &tmp.path().join("c1"),
        Budgets::default(),
        |_, _| completion("I think the robot should go to the kitchen."),
    );
    assert_eq!(text["status"], "text_without_task");
    assert_eq!(
        text["toolcall"]["reference_status"],
        "MODEL_RETURNED_TEXT_WITHOUT_TASK"
    );
    assert!(
        text["trajectory"].as_array().unwrap().len() <= 1,
        "start only"
    );
    let small = Budgets {
        tool_calls: 32,
        turns: 3,
        retries: 3,
    };
    let turns = run_against(
        &suite,
        &tmp.path().join("turns"),
        &tmp.path().join("c2"),
        small,
        |_, _| calls(&[("rooms", json!({}))]),
    );
    assert_eq!(turns["status"], "turn_budget_exhausted");
    assert_eq!(turns["toolcall"]["turns"], 3);
    let few = Budgets {
        tool_calls: 4,
        turns: 40,
        retries: 3,
    };
    let tools = run_against(
        &suite,
        &tmp.path().join("tools"),
        &tmp.path().join("c3"),
        few,
        |_, _| {
            calls(&[
                ("rooms", json!({})),
                ("rooms", json!({"category": "kitchen"})),
                ("count", json!({"of": "set#1"})),
            ])
        },
    );
    assert_eq!(tools["status"], "tool_budget_exhausted");
    assert_eq!(tools["toolcall"]["tool_calls"], 4);
    // A submitted route that does not compile ends it (the reference runs ToolCall without repair).
    let bad = run_against(
        &suite,
        &tmp.path().join("bad"),
        &tmp.path().join("c4"),
        Budgets::default(),
        |turn, _| match turn {
            // A number where a place belongs: the builder takes the handle, the compiler refuses
            // it (a set of rooms would not do since a set is a destination: any member).
            0 => calls(&[("rooms", json!({}))]),
            1 => calls(&[("count", json!({"of": "set#1"}))]),
            2 => calls(&[("segment", json!({"target": "number#2"}))]),
            _ => calls(&[("task", json!({"segments": ["segment#3"]}))]),
        },
    );
    assert_eq!(
        bad["status"], "route_ir_verification_failed",
        "{}",
        bad["toolcall"]
    );
}

#[test]
fn each_turn_is_a_batch_round_and_the_lines_carry_the_tools() {
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("suite");
    build(&suite, 1);
    let cache = tmp.path().join("cache");
    let script = [
        calls(&[("rooms", json!({}))]),
        calls(&[
            ("nearest", json!({"of": "set#1"})),
            ("segment", json!({"target": "room#2"})),
        ]),
        calls(&[("task", json!({"segments": ["segment#3"]}))]),
    ];
    let mut status = String::new();
    for round in 0..=script.len() {
        let batch = tmp.path().join(format!("batch{round}.jsonl"));
        let setup = server_setup("http://offline.invalid", &cache, Some(&batch));
        let setup = Arc::new(setup);
        let method = ToolCallMethod::new(setup.clone());
        let out = tmp.path().join(format!("run{round}"));
        runner::run(&method, &opts(&suite, &out)).unwrap();
        setup.store.batch.as_ref().unwrap().finish().unwrap();
        let recs = read_records(&out).unwrap();
        if let Some(r) = recs.first() {
            status = r["status"].as_str().unwrap().to_string();
            break;
        }
        let lines: Vec<Value> = std::fs::read_to_string(&batch)
            .unwrap()
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(lines.len(), 1, "round {round}: one turn per round");
        let body = &lines[0]["body"];
        assert!(body["tools"].as_array().unwrap().len() > 50);
        assert_eq!(
            body["messages"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|m| m["role"] == "tool")
                .count(),
            [0, 1, 3][round]
        );
        let answer = json!({"custom_id": lines[0]["custom_id"],
                            "response": {"status_code": 200, "body": script[round]}, "error": null});
        let replies = tmp.path().join(format!("out{round}.jsonl"));
        std::fs::write(&replies, format!("{answer}\n")).unwrap();
        let r = import_batch_files(&[replies], &ResponseCache::new(&cache)).unwrap();
        assert_eq!((r.imported, r.failed.len()), (1, 0), "{r:?}");
    }
    assert_eq!(status, "ok");
}

/// The figure of issue 31's benchmark (not a test; `cargo test -p m2rc-baselines --test it
/// toolcall_overhead -- --ignored --nocapture`): the gold conversations replayed by a mock
/// server into a cache, then re-run from the cache alone; m2rc's own cost per turn (cache look-up,
/// reply parsing, the tool calls' evaluation), and the tool list's estimated prompt tokens.
#[test]
#[ignore]
fn toolcall_overhead_per_turn_with_cached_replies() {
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("suite");
    let m = build(&suite, 12);
    let gold = tmp.path().join("gold");
    let started = std::time::Instant::now();
    runner::run(
        &ToolCallMethod::new(Arc::new(gold_setup())),
        &opts(&suite, &gold),
    )
    .unwrap();
    let gold_s = started.elapsed().as_secs_f64();
    // Each episode's gold turns, by the instruction the user message carries.
    let episodes: Vec<Value> = read_records(&gold).unwrap();
    let mut script: std::collections::BTreeMap<String, Vec<Value>> = Default::default();
    let text: std::collections::BTreeMap<String, String> = m
        .episodes
        .iter()
        .map(|e| {
            let ep: Value =
                serde_json::from_str(&std::fs::read_to_string(suite.join(&e.file)).unwrap())
                    .unwrap();
            (
                e.instruction_id.clone(),
                ep["instruction"].as_str().unwrap_or_default().to_string(),
            )
        })
        .collect();
    for r in &episodes {
        let calls = r["toolcall"]["calls"].as_array().unwrap();
        let mut turns: Vec<Vec<(String, Value)>> = Vec::new();
        for c in calls {
            let t = c["turn"].as_u64().unwrap() as usize;
            if turns.len() <= t {
                turns.resize(t + 1, Vec::new());
            }
            let args: Value = serde_json::from_str(c["arguments"].as_str().unwrap()).unwrap();
            turns[t].push((c["name"].as_str().unwrap().to_string(), args));
        }
        let replies = turns
            .iter()
            .map(|t| {
                let list: Vec<(&str, Value)> =
                    t.iter().map(|(n, a)| (n.as_str(), a.clone())).collect();
                calls_reply(&list)
            })
            .collect();
        script.insert(r["instruction_id"].as_str().unwrap().to_string(), replies);
    }
    let by_instruction: std::collections::BTreeMap<String, Vec<Value>> = episodes
        .iter()
        .map(|r| {
            let id = r["instruction_id"].as_str().unwrap();
            (text[id].clone(), script[id].clone())
        })
        .collect();
    let mut server = mockito::Server::new();
    let _m = server
        .mock("POST", "/v1/chat/completions")
        .with_body_from_request(move |req| {
            let body: Value = serde_json::from_slice(req.body().unwrap()).unwrap();
            let msgs = body["messages"].as_array().unwrap();
            let user = msgs[1]["content"].as_str().unwrap();
            let turn = msgs.iter().filter(|m| m["role"] == "assistant").count();
            let replies = by_instruction
                .iter()
                .find(|(k, _)| user.contains(k.as_str()))
                .map(|(_, v)| v)
                .unwrap();
            replies
                .get(turn)
                .cloned()
                .unwrap_or_else(|| completion("done"))
                .to_string()
                .into_bytes()
        })
        .create();
    let cache = tmp.path().join("cache");
    let mut setup = server_setup(&server.url(), &cache, None);
    setup.embed_http = None;
    runner::run(
        &ToolCallMethod::new(Arc::new(setup)),
        &opts(&suite, &tmp.path().join("fill")),
    )
    .unwrap();
    let mut offline = server_setup("http://127.0.0.1:9", &cache, None);
    offline.embed_http = None;
    offline.store = m2rc_llm::Store::new(Some(ResponseCache::new(&cache)), None, true);
    let out = tmp.path().join("cached");
    let started = std::time::Instant::now();
    runner::run(&ToolCallMethod::new(Arc::new(offline)), &opts(&suite, &out)).unwrap();
    let cached_s = started.elapsed().as_secs_f64();
    let recs = read_records(&out).unwrap();
    let turns: u64 = recs
        .iter()
        .map(|r| r["toolcall"]["turns"].as_u64().unwrap_or(0))
        .sum();
    let calls: u64 = recs
        .iter()
        .map(|r| r["toolcall"]["tool_calls"].as_u64().unwrap_or(0))
        .sum();
    let ok = recs.iter().filter(|r| r["status"] == "ok").count();
    println!(
        "episodes {} (ok {ok}), turns {turns}, tool calls {calls}; gold run {:.2} s; cached run {:.2} s \
         = {:.1} ms per turn, {:.1} ms per episode (planning included); tool list ~{} tokens",
        recs.len(),
        gold_s,
        cached_s,
        cached_s * 1e3 / turns.max(1) as f64,
        cached_s * 1e3 / recs.len().max(1) as f64,
        m2rc_baselines::grounding::toolcall::tools_estimated_tokens()
    );
    assert_eq!(recs.len(), episodes.len());
}

fn calls_reply(list: &[(&str, Value)]) -> Value {
    calls(list)
}
