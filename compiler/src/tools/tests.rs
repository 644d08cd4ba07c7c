use super::spec::{LANGUAGE_TOOLS, tool_specs};
use super::*;
use crate::check::check;
use crate::eval::{GroundOptions, ground_checked};
use crate::intent::ops::{LANGUAGE_OPS, operators};
use m2rc_stdlib::map::SemanticMap;
use m2rc_stdlib::query::MapQuery;
use m2rc_stdlib::vocab::Vocabulary;
use serde_json::{Value, json};

fn demo() -> SemanticMap {
    m2rc_stdlib::demo::demo_map().expect("demo map")
}

fn examples() -> Vec<(String, String)> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples");
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "m2r"))
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|f| {
            let text = std::fs::read_to_string(&f).unwrap();
            (f.display().to_string(), text)
        })
        .filter(|(_, t)| t.contains("// map: demo"))
        .collect()
}

/// The RouteIR a program grounds to on the demo map (spans aside).
fn route_ir(map: &SemanticMap, src: &str) -> Value {
    let vocab = Vocabulary::from_map(map);
    let checked = check(src, &vocab);
    assert!(!checked.has_errors(), "{src}\n{:?}", checked.diagnostics);
    let q = MapQuery::new(map);
    let g = ground_checked(&checked, src, &q, &GroundOptions::default());
    let mut v = serde_json::to_value(g.ir.expect("grounds")).unwrap();
    strip_spans(&mut v);
    // A binding written out twice records its route-dependent place twice; the places are equal.
    if let Some(Value::Array(b)) = v.get_mut("route_bindings") {
        b.dedup();
    }
    v
}

fn strip_spans(v: &mut Value) {
    match v {
        Value::Object(o) => {
            o.remove("span");
            o.values_mut().for_each(strip_spans);
        }
        Value::Array(a) => a.iter_mut().for_each(strip_spans),
        _ => {}
    }
}

#[test]
fn one_tool_per_builtin_name_and_every_language_operator() {
    let specs = tool_specs();
    let mut names: Vec<&str> = specs.iter().map(|s| s.name).collect();
    let n = names.len();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), n, "tool names are unique");
    for o in operators() {
        assert!(
            specs.iter().any(|s| s.kind == ToolKind::Builtin(o.name)),
            "built-in `{}` has no tool",
            o.name
        );
    }
    let builtin_tools = specs
        .iter()
        .filter(|s| matches!(s.kind, ToolKind::Builtin(_)))
        .count();
    assert_eq!(builtin_tools, operators().len(), "no tool beyond the table");
    let mut covered = super::spec::language_ops_covered();
    let mut ops: Vec<&str> = LANGUAGE_OPS.iter().map(|(n, ..)| *n).collect();
    covered.sort_unstable();
    ops.sort_unstable();
    assert_eq!(
        covered, ops,
        "the language tools cover the grammar's operators"
    );
    assert_eq!(LANGUAGE_TOOLS.len(), 8);
    for b in ["set_segment_context", "constraint", "segment", "task"] {
        assert!(
            specs
                .iter()
                .any(|s| s.name == b && s.kind == ToolKind::Builder)
        );
    }
    // OpenAI's function-name rule.
    for s in &specs {
        assert!(
            s.name.len() <= 64
                && s.name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-'),
            "{}",
            s.name
        );
    }
}

fn validator(schema: &Value) -> (boon::Schemas, boon::SchemaIndex) {
    let mut schemas = boon::Schemas::new();
    let mut compiler = boon::Compiler::new();
    compiler
        .add_resource("urn:m2rc:tool", schema.clone())
        .expect("schema resource");
    let idx = compiler
        .compile("urn:m2rc:tool", &mut schemas)
        .expect("the generated parameter schema compiles");
    (schemas, idx)
}

/// Every gold call's arguments (after binding) validate against the tool's generated schema,
/// and the schemas refuse what the session would: a stray argument, a missing required one.
#[test]
fn tool_schemas_accept_generated_arguments_and_refuse_stray_ones() {
    let specs = tool_specs();
    let mut checked = 0;
    for (name, src) in examples() {
        let Ok(calls) = gold_calls(&src) else {
            continue;
        };
        let handles: Vec<Option<String>> =
            (0..calls.len()).map(|k| Some(format!("set#{k}"))).collect();
        for c in &calls {
            let spec = specs.iter().find(|s| s.name == c.name).unwrap();
            let (schemas, idx) = validator(&spec.parameters);
            let args = c.bind(&handles).unwrap();
            if let Err(e) = schemas.validate(&args, idx) {
                panic!("{name}: {}: {e}\n{args}", c.name);
            }
            checked += 1;
        }
    }
    assert!(checked > 40, "{checked}");
    let spec = specs.iter().find(|s| s.name == "nearest").unwrap();
    let (schemas, idx) = validator(&spec.parameters);
    assert!(schemas.validate(&json!({"of": "set#1"}), idx).is_ok());
    assert!(
        schemas
            .validate(&json!({"of": "set#1", "speed": 2}), idx)
            .is_err()
    );
    let spec = specs.iter().find(|s| s.name == "task").unwrap();
    let (schemas, idx) = validator(&spec.parameters);
    assert!(schemas.validate(&json!({}), idx).is_err());
}

#[test]
fn gold_calls_rebuild_the_gold_route_exactly() {
    let map = demo();
    let mut replayed = 0;
    for (name, src) in examples() {
        let Ok(calls) = gold_calls(&src) else {
            continue;
        };
        let mut s = ToolSession::new(&map, None, Limits::default());
        let mut handles: Vec<Option<String>> = Vec::new();
        for c in &calls {
            let args = c
                .bind(&handles)
                .unwrap_or_else(|| panic!("{name}: unbound {c:?}"));
            let out = s.call(&c.name, &args);
            assert!(out.ok, "{name}: {} {args} -> {}", c.name, out.content);
            handles.push(out.content["handle"].as_str().map(str::to_string));
        }
        let done = s
            .finished
            .as_ref()
            .unwrap_or_else(|| panic!("{name}: no task"));
        assert_eq!(
            route_ir(&map, &done.program),
            route_ir(&map, &src),
            "{name}\n{}",
            done.program
        );
        replayed += 1;
    }
    assert!(replayed >= 8, "{replayed}");
}

#[test]
fn results_are_handles_with_previews_and_compose() {
    let map = demo();
    let mut s = ToolSession::new(&map, None, Limits::default());
    let beds = s.call("objects", &json!({"category": "bed"}));
    assert!(beds.ok, "{}", beds.content);
    let h = beds.content["handle"].as_str().unwrap().to_string();
    assert!(h.starts_with("set#"), "{h}");
    let value = beds.content["value"].as_str().unwrap();
    assert!(value.contains("bed #"), "{value}");
    let nearest = s.call("nearest", &json!({"of": h}));
    assert!(nearest.ok, "{}", nearest.content);
    assert!(
        nearest.content["handle"]
            .as_str()
            .unwrap()
            .starts_with("object#")
    );
    let count = s.call("count", &json!({"of": h}));
    assert!(
        count.content["value"]
            .as_str()
            .unwrap()
            .starts_with("number#")
    );
    // A lambda with a handle in its body.
    let rooms = s.call(
        "where",
        &json!({"of": "set#9", "pred": {"lambda": "r", "body": "x"}}),
    );
    assert!(!rooms.ok);
    assert!(
        rooms.content["error"]
            .as_str()
            .unwrap()
            .contains("no handle `set#9`")
    );
    let all = s.call("rooms", &json!({}));
    let with_beds = s.call(
        "where",
        &json!({"of": all.content["handle"], "pred": {"lambda": "r", "body":
            {"op": ">", "args": [{"op": "count", "of": {"op": "in", "of": h, "args": ["r"]}}, 0]}}}),
    );
    assert!(with_beds.ok, "{}", with_beds.content);
    let text = with_beds.content["value"].as_str().unwrap();
    assert!(text.contains("bedroom"), "{text}");
}

#[test]
fn failing_queries_are_blocked_after_three_tries_and_errors_name_the_fault() {
    let map = demo();
    let mut s = ToolSession::new(&map, None, Limits::default());
    let bad = json!({"category": "unicorn"});
    for i in 1..=3 {
        let out = s.call("objects", &bad);
        assert!(!out.ok && !out.blocked, "try {i}");
        let e = out.content["error"].as_str().unwrap();
        assert!(e.contains("unicorn"), "{e}");
        assert_eq!(out.content.get("blocked").is_some(), i == 3);
    }
    let out = s.call("objects", &bad);
    assert!(out.blocked);
    assert_eq!(out.content["error"], "QUERY_RETRY_LIMIT_REACHED");
    assert_eq!((s.executed, s.failed, s.blocked), (3, 3, 1));
    // Another spelling of a different query still runs.
    assert!(s.call("objects", &json!({"category": "bed"})).ok);
    for (tool, args, says) in [
        ("teleport", json!({}), "no tool `teleport`"),
        ("nearest", json!({"speed": 1}), "no argument `speed`"),
        ("nearest", json!([1]), "JSON object"),
        ("segment", json!({}), "needs the argument `target`"),
        ("objects", json!({"category": ["bed"]}), "not a list"),
        ("task", json!({"segments": []}), "at least one segment"),
    ] {
        let out = s.call(tool, &args);
        let e = out.content["error"].as_str().unwrap_or("");
        assert!(!out.ok && e.contains(says), "{tool}: {e}");
    }
}

#[test]
fn the_builders_place_context_constraints_and_the_task_compiles() {
    let map = demo();
    let mut s = ToolSession::new(&map, None, Limits::default());
    let beds = s.call("objects", &json!({"category": "bed"}));
    let bed = s.call("nearest", &json!({"of": beds.content["handle"]}));
    assert!(bed.ok, "{}", bed.content);
    let kitchens = s.call("rooms", &json!({"category": "kitchen"}));
    let kitchen = s.call("only", &json!({"of": kitchens.content["handle"]}));
    assert!(
        s.call("set_segment_context", &json!({"segment_id": "s1"}))
            .ok
    );
    let avoid = s.call(
        "constraint",
        &json!({"kind": "forbid", "value": kitchen.content["handle"]}),
    );
    assert!(avoid.ok, "{}", avoid.content);
    let seg = s.call(
        "segment",
        &json!({"segment_id": "s1", "target": bed.content["handle"]}),
    );
    let task = s.call("task", &json!({"segments": [seg.content["handle"]]}));
    assert!(task.ok, "{}", task.content);
    let done = s.finished.clone().unwrap();
    assert!(
        done.program.contains("avoid rooms(kitchen).only()"),
        "{}",
        done.program
    );
    assert!(
        done.program.contains("go objects(bed).nearest() as s1 {"),
        "{}",
        done.program
    );
    assert!(!s.call("count", &json!({"of": beds.content["handle"]})).ok);
}

#[test]
fn handle_and_query_limits_hold() {
    let map = demo();
    let limits = Limits {
        max_handles: 3,
        max_query_bytes: 200,
        retry_limit: 3,
    };
    let mut s = ToolSession::new(&map, None, limits);
    let mut h = s.call("rooms", &json!({})).content["handle"].clone();
    // Doubling a set through `union` grows the written-out query until the limit stops it.
    let mut stopped = None;
    for _ in 0..10 {
        let out = s.call("union", &json!({"left": h, "right": h}));
        if !out.ok {
            stopped = Some(out.content["error"].as_str().unwrap().to_string());
            break;
        }
        h = out.content["handle"].clone();
    }
    let e = stopped.expect("a limit stops the growth");
    assert!(e.contains("limit"), "{e}");
}

#[test]
fn the_docs_tool_list_is_the_generated_one() {
    let page = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/tools.md"))
        .expect("docs/tools.md");
    let begin = "<!-- tool list: generated, checked by a test -->\n";
    let end = "<!-- end of tool list -->";
    let from = page.find(begin).expect("start marker") + begin.len();
    let to = page[from..].find(end).expect("end marker") + from;
    let generated = super::spec::tool_list_markdown();
    assert!(
        page[from..to] == generated,
        "docs/tools.md's tool list differs from the generated one; it should read:\n{begin}{generated}{end}"
    );
}
