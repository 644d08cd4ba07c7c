use super::feedback::apply_fixes;
use super::ops::{LANGUAGE_OPS, json_schema, operator_names, operators};
use super::*;
use crate::diagnostic::Code;
use crate::lower::examples;
use m2rc_grammar::{parse, print};
use serde_json::json;

/// Every program the prompt's examples and the repository's examples hold.
fn programs() -> Vec<(String, String)> {
    let mut v: Vec<(String, String)> = examples::all()
        .into_iter()
        .map(|e| (e.name.to_string(), e.program))
        .collect();
    let root = env!("CARGO_MANIFEST_DIR");
    let mut files: Vec<_> = [
        "/../examples",
        "/../tests/ui/real",
        "/../tests/ui/real/real",
    ]
    .iter()
    .filter_map(|d| std::fs::read_dir(format!("{root}{d}")).ok())
    .flatten()
    .filter_map(|e| e.ok().map(|e| e.path()))
    .filter(|p| p.extension().is_some_and(|x| x == "m2r"))
    .collect();
    files.sort();
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        v.push((f.display().to_string(), text));
    }
    assert!(v.len() > 30);
    v
}

fn validator() -> (boon::Schemas, boon::SchemaIndex) {
    let mut schemas = boon::Schemas::new();
    let mut compiler = boon::Compiler::new();
    compiler
        .add_resource("urn:m2rc:intent", json_schema())
        .expect("schema resource");
    let idx = compiler
        .compile("urn:m2rc:intent", &mut schemas)
        .expect("the generated schema compiles");
    (schemas, idx)
}

#[test]
fn program_graph_program_is_the_canonical_program() {
    for (name, src) in programs() {
        let graph = program_to_graph(&src).unwrap_or_else(|e| panic!("{name}: {e}"));
        let compiled = graph_to_program(&graph).unwrap_or_else(|e| panic!("{name}: {e:?}"));
        let canonical = print(&parse(&src).program);
        assert_eq!(compiled.program, canonical, "{name}");
        assert!(!compiled.map.is_empty(), "{name}: no source map");
        assert_eq!(
            program_to_graph(&compiled.program).unwrap(),
            graph,
            "{name}"
        );
    }
}

#[test]
fn generated_graphs_validate_against_the_generated_schema() {
    let (schemas, idx) = validator();
    for (name, src) in programs() {
        let graph = program_to_graph(&src).unwrap();
        if let Err(e) = schemas.validate(&graph, idx) {
            panic!("{name}: {e}\n{graph}");
        }
    }
    // The schema rejects what the compiler would: an operator the language lacks, a stray field.
    let bad = json!({"segments": [{"to": {"op": "nearest_to", "of": "bed"}}]});
    assert!(schemas.validate(&bad, idx).is_err());
    let bad = json!({"segments": [{"to": "bed", "speed": 2}]});
    assert!(schemas.validate(&bad, idx).is_err());
}

#[test]
fn the_operator_list_is_the_built_in_table() {
    let names = operator_names();
    for b in m2rc_stdlib::builtins::BUILTINS {
        assert!(names.contains(&b.name), "{} missing", b.name);
    }
    let distinct: std::collections::BTreeSet<&str> = m2rc_stdlib::builtins::BUILTINS
        .iter()
        .map(|b| b.name)
        .collect();
    assert_eq!(operators().len(), distinct.len());
    // The language's own operators cover every binary operator of the grammar.
    use m2rc_grammar::ast::BinOp::*;
    for op in [Or, And, Eq, Ne, Lt, Le, Gt, Ge, Union, Add, Sub, Mul] {
        assert!(
            LANGUAGE_OPS.iter().any(|(_, _, b, _)| *b == Some(op)),
            "{op:?}"
        );
    }
    let reference = ops::operator_reference();
    let nearest = reference
        .lines()
        .find(|l| l.starts_with("{op: nearest, of: Set<T>, args: [to: Place"))
        .expect("nearest is in the reference");
    assert!(nearest.contains(" = here"), "{nearest}");
}

#[test]
fn shape_errors_point_into_the_graph() {
    let g = json!({
        "segments": [
            {"to": {"op": "nearset", "of": {"op": "objects", "args": ["bed"]}}},
            {"to": "bed", "constraints": [{"kind": "avoid", "place": "kitchen"}]}
        ]
    });
    let errs = graph_to_program(&g).unwrap_err();
    let at: Vec<(&str, &str)> = errs
        .iter()
        .map(|d| (d.pointer.as_str(), d.diagnostic.code.id()))
        .collect();
    assert!(at.contains(&("/segments/0/to/op", "E0903")), "{at:?}");
    assert!(
        at.contains(&("/segments/1/constraints/0/kind", "E0902")),
        "{at:?}"
    );
    let op = errs
        .iter()
        .find(|d| d.pointer == "/segments/0/to/op")
        .unwrap();
    assert_eq!(op.diagnostic.help.as_deref(), Some("write `nearest`"));
    let kind = errs
        .iter()
        .find(|d| d.diagnostic.code == Code::GraphShape)
        .unwrap();
    assert!(kind.to_json()["pointer"].is_string());
}

#[test]
fn compile_errors_become_pointers_and_patches() {
    let g =
        json!({"segments": [{"to": {"op": "only", "of": {"op": "objects", "args": ["chiar"]}}}]});
    let compiled = graph_to_program(&g).unwrap();
    let vocab = m2rc_stdlib::vocab::Vocabulary::benchmark();
    let checked = crate::check(&compiled.program, &vocab);
    assert!(checked.has_errors());
    let fb = graph_feedback(&compiled, &checked.diagnostics);
    let d = fb
        .iter()
        .find(|d| d.diagnostic.code == Code::UnknownCategory)
        .expect("unknown category");
    assert_eq!(d.pointer, "/segments/0/to/of/args/0");
    assert_eq!(
        d.patch,
        Some(json!({"op": "replace", "path": "/segments/0/to/of/args/0", "value": "chair"}))
    );
    // The certain fix, applied to the reply, gives a graph that checks.
    let fixed = apply_fixes(&g.to_string(), &fb).expect("a fix applies");
    let again = graph_to_program(&reply_json(&fixed).unwrap()).unwrap();
    assert!(
        !crate::check(&again.program, &vocab).has_errors(),
        "{}",
        again.program
    );
}

#[test]
fn a_set_where_one_place_is_needed_is_patched_by_wrapping_the_node() {
    // `go` takes a set (any one member); `area_near` needs one place.
    let g = json!({"segments": [{"to": {"op": "area_near", "args": [{"op": "objects", "args": ["bed"]}]}}]});
    let compiled = graph_to_program(&g).unwrap();
    let vocab = m2rc_stdlib::vocab::Vocabulary::benchmark();
    let checked = crate::check(&compiled.program, &vocab);
    let fb = graph_feedback(&compiled, &checked.diagnostics);
    let patched: Vec<_> = fb.iter().filter_map(|d| d.patch.clone()).collect();
    assert!(
        patched.iter().any(|p| p["path"] == "/segments/0/to/args/0"
            && p["value"]["of"] == json!({"op": "objects", "args": ["bed"]})),
        "{fb:?}"
    );
}

#[test]
fn replies_cut_short_get_their_closing_brackets() {
    let full = r#"{"segments": [{"to": "bed"}]}"#;
    let cut = &full[..full.len() - 2];
    let err = reply_json(cut).unwrap_err();
    assert_eq!(err.diagnostic.code, Code::GraphNotJson);
    assert_eq!(err.patch, Some(json!({"op": "append_text", "text": "]}"})));
    let fixed = apply_fixes(cut, &[*err]).unwrap();
    assert_eq!(reply_json(&fixed).unwrap(), reply_json(full).unwrap());
    assert!(reply_json("no json here").is_err());
    let fenced = format!("Here it is:\n```json\n{full}\n```\n");
    assert_eq!(reply_json(&fenced).unwrap(), reply_json(full).unwrap());
}

#[test]
fn deep_graphs_are_refused_not_recursed() {
    let mut v = json!("bed");
    for _ in 0..100 {
        v = json!({"op": "only", "of": v});
    }
    let g = json!({"segments": [{"to": v}]});
    let errs = graph_to_program(&g).unwrap_err();
    assert!(
        errs.iter()
            .any(|d| d.diagnostic.message.contains("nests deeper"))
    );
}

#[test]
fn a_deleted_argument_is_patched_on_the_whole_call() {
    let g = json!({"segments": [{"to": {"op": "only", "of": {"op": "objects", "args": ["bed"]}, "args": [1]}}]});
    let compiled = graph_to_program(&g).unwrap();
    let vocab = m2rc_stdlib::vocab::Vocabulary::benchmark();
    let checked = crate::check(&compiled.program, &vocab);
    let fb = graph_feedback(&compiled, &checked.diagnostics);
    let fixed = apply_fixes(&g.to_string(), &fb).expect("a fix applies");
    assert_eq!(
        reply_json(&fixed).unwrap(),
        json!({"segments": [{"to": {"op": "only", "of": {"op": "objects", "args": ["bed"]}}}]})
    );
}
