//! Direct ID and catalog-LTL (issue 31): gold ids rebuild the gold RouteIR, validation errors
//! point into the reply, the JSON Schemas accept generated replies, and a mock server's
//! conversation and a batch round trip run through the cache and the repair loop.

use crate::gold::{build, opts};
use crate::support::*;
use m2rc_baselines::grounding::directid::validate::validate;
use m2rc_baselines::grounding::directid::{
    CatalogIds, DIRECT_ID, build as ir_build, catalog, gold_reply, ltl, schema,
};
use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::methods::{PreparedMap, start_cell};
use m2rc_benchmark::pipeline::{PipelineOptions, compile_and_plan_with};
use m2rc_benchmark::runner::{self, read_records};
use m2rc_benchmark::suite::SuiteManifest;
use m2rc_compiler::intent::GraphDiagnostic;
use m2rc_compiler::ir::{RouteIr, SourceSpan};
use m2rc_llm::{Backend, ResponseCache, SimulatedSpec, Store, import_batch_files};
use m2rc_stdlib::query::MapQuery;
use serde_json::{Value, json};
use std::path::Path;
use std::sync::Arc;

/// Stages and constraints without source spans or route bindings (ids have no source).
fn normalised(mut ir: RouteIr) -> RouteIr {
    for s in &mut ir.stages {
        s.span = SourceSpan::default();
        for p in &mut s.passes {
            p.span = SourceSpan::default();
        }
    }
    for c in &mut ir.constraints {
        c.span = SourceSpan::default();
    }
    ir.route_bindings.clear();
    ir
}

/// Every episode of a suite: its prepared map, episode and gold program.
fn episodes(dir: &Path) -> Vec<(Arc<PreparedMap>, Episode, String)> {
    let m = SuiteManifest::read(dir).unwrap();
    let mut maps: std::collections::BTreeMap<String, Arc<PreparedMap>> = Default::default();
    m.episodes
        .iter()
        .map(|e| {
            let pm = maps
                .entry(e.map_id.clone())
                .or_insert_with(|| {
                    let path = m.map_path(dir, &e.map_id).unwrap();
                    let map = m2rc_stdlib::load::load_map(path.to_str().unwrap()).unwrap();
                    Arc::new(PreparedMap::new(map))
                })
                .clone();
            let ep = Episode::read(&dir.join(&e.file)).unwrap();
            let program = ep.m2rc_gold_program.clone().unwrap();
            (pm, ep, program)
        })
        .collect()
}

#[test]
fn gold_ids_rebuild_the_gold_route_ir() {
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("suite");
    build(&suite, 12);
    let (mut equal, mut lossy) = (0, 0);
    for (pm, ep, program) in episodes(&suite) {
        let q = MapQuery::new(&pm.map);
        let start = start_cell(&pm.map, &ep).unwrap();
        let gold = gold_reply(&program, &pm, &q, start).unwrap();
        if !gold.lossy.is_empty() {
            lossy += 1;
            continue;
        }
        let g = validate(&gold.reply, &q).unwrap_or_else(|d| panic!("{d:?}"));
        let rebuilt = ir_build::build(&g, &q, start).unwrap();
        let opts = PipelineOptions {
            start: Some(start),
            ..PipelineOptions::default()
        };
        let compiled = compile_and_plan_with(&program, &pm.map, pm.planning().unwrap(), &opts)
            .unwrap()
            .ir;
        assert_eq!(
            normalised(rebuilt),
            normalised(compiled),
            "{program}\n{}",
            gold.reply
        );
        // The catalog-LTL form of the same ids reads back to the same grounding.
        let (as_ltl, dropped) = ltl::from_direct_id(&gold.reply);
        if dropped.is_empty() {
            assert_eq!(ltl::read(&as_ltl, &q).unwrap(), g, "{as_ltl}");
        }
        equal += 1;
    }
    assert!(equal >= 6, "{equal} equal, {lossy} lossy");
}

fn demo() -> (m2rc_stdlib::map::SemanticMap, m2rc_stdlib::grid::Cell) {
    let map = m2rc_stdlib::demo::demo_map().unwrap();
    let start = map.start.unwrap();
    (map, start)
}

fn errors(reply: Value, q: &MapQuery) -> Vec<GraphDiagnostic> {
    validate(&reply, q).unwrap_err()
}

fn find<'a>(ds: &'a [GraphDiagnostic], pointer: &str) -> &'a GraphDiagnostic {
    ds.iter()
        .find(|d| d.pointer == pointer)
        .unwrap_or_else(|| panic!("no diagnostic at {pointer}: {ds:?}"))
}

#[test]
fn validation_errors_name_the_json_pointer_code_and_fix() {
    let (map, _) = demo();
    let q = MapQuery::new(&map);
    let obj = map.objects[0].id;
    let room = map.rooms[0].id;
    let ds = errors(
        json!({"segments": [
            {"id": "s1", "target_id": format!("obejct_{obj}")},
            {"id": "s2", "target_id": "object_999999"},
            {"id": "s3", "target_id": "task_start"},
            {"id": "s4", "target_id": format!("room_{room}")},
        ], "constraints": [
            {"kind": "prefer_near", "ref_ids": [format!("object_{obj}"), format!("room_{room}")]},
            {"kind": "prefer_path_shape", "ref_ids": [format!("object_{obj}")], "path_shape": {"type": "follow_wall"}},
            {"kind": "prefer_relative", "ref_ids": [format!("object_{obj}"), format!("room_{room}")]},
            {"kind": "forbid", "ref_ids": [format!("room_{room}")], "segment_ids": ["s9"]},
            {"kind": "hover", "ref_ids": []},
            {"kind": "forbid", "ref_ids": ["task_start"]},
        ]}),
        &q,
    );
    let misspelt = find(&ds, "/segments/0/target_id");
    assert_eq!(misspelt.diagnostic.code.id(), "E0904");
    assert_eq!(
        misspelt.diagnostic.help.as_deref(),
        Some(format!("write `object_{obj}`").as_str())
    );
    let unknown = find(&ds, "/segments/1/target_id");
    assert_eq!(unknown.diagnostic.code.id(), "E0904");
    assert!(
        !unknown
            .diagnostic
            .help
            .as_deref()
            .unwrap()
            .contains("write `")
    );
    // Going back to the start is a destination; avoiding it is not a place.
    assert!(
        ds.iter().all(|d| d.pointer != "/segments/2/target_id"),
        "{ds:?}"
    );
    let kind = find(&ds, "/constraints/5/ref_ids/0");
    assert_eq!(kind.diagnostic.code.id(), "E0902");
    assert!(kind.diagnostic.message.contains("the start"), "{kind:?}");
    let arity = find(&ds, "/constraints/0/ref_ids");
    assert_eq!(arity.diagnostic.code.id(), "E0905");
    assert!(arity.diagnostic.message.contains("exactly 1"), "{arity:?}");
    let wall = find(&ds, "/constraints/1/ref_ids/0");
    assert!(wall.diagnostic.message.contains("an object"), "{wall:?}");
    find(&ds, "/constraints/2/relation");
    let seg = find(&ds, "/constraints/3/segment_ids/0");
    assert!(
        seg.diagnostic.help.as_deref().unwrap().contains("s1, s3") || seg.diagnostic.help.is_some()
    );
    find(&ds, "/constraints/4/kind");
    // A neighbouring number is another object: never suggested.
    let ds = errors(
        json!({"segments": [{"id": "s1", "target_id": "objekt_999999"}]}),
        &q,
    );
    assert!(
        !find(&ds, "/segments/0/target_id")
            .diagnostic
            .help
            .as_deref()
            .unwrap()
            .contains("write `")
    );
    // A reply without segments.
    find(&errors(json!({"constraints": []}), &q), "/segments");
}

#[test]
fn catalog_ltl_refuses_formulas_outside_the_skeleton_with_pointers() {
    let (map, _) = demo();
    let q = MapQuery::new(&map);
    let (a, b) = (
        format!("object_{}", map.objects[0].id),
        format!("object_{}", map.objects[1].id),
    );
    let room = format!("room_{}", map.rooms[0].id);
    let props = json!([
        {"name": "a", "kind": "visit", "ref_ids": [a]},
        {"name": "b", "kind": "visit", "ref_ids": [b]},
        {"name": "k", "kind": "avoid", "ref_ids": [room]},
    ]);
    let ok = ltl::read(
        &json!({"formula": "F(a & F(b)) & G(!k)", "propositions": props}),
        &q,
    )
    .unwrap();
    assert_eq!(ok.segments.len(), 2);
    assert_eq!(ok.constraints.len(), 1);
    assert_eq!(ok.constraints[0].segments, None);
    // Unicode operators are the same formula.
    let uni = ltl::read(
        &json!({"formula": "◇(a ∧ ◇(b)) ∧ □(¬k)", "propositions": props}),
        &q,
    )
    .unwrap();
    assert_eq!(uni, ok);
    for bad in [
        "F(a) & F(b) & G(!k)",
        "F(a & X(b)) & G(!k)",
        "F(a | F(b)) & G(!k)",
        "F(a & F(b)",
        "F(a & F(a)) & G(!k)",
        "F(a & F(c)) & G(!k)",
    ] {
        let ds = ltl::read(&json!({"formula": bad, "propositions": props}), &q).unwrap_err();
        assert!(ds.iter().any(|d| d.pointer == "/formula"), "{bad}: {ds:?}");
    }
    // An avoid neither in G(!k) nor scoped by `during`.
    let ds = ltl::read(
        &json!({"formula": "F(a & F(b))", "propositions": props}),
        &q,
    )
    .unwrap_err();
    find(&ds, "/propositions/2");
    // A catalog error in a visit points at the proposition, not at the Direct ID form.
    let mut wrong = props.clone();
    wrong[1]["ref_ids"] = json!(["object_999999"]);
    let ds = ltl::read(
        &json!({"formula": "F(a & F(b)) & G(!k)", "propositions": wrong}),
        &q,
    )
    .unwrap_err();
    find(&ds, "/propositions/1/ref_ids/0");
    // Nesting past the limit is refused, not recursed into.
    let deep = format!("{}a{}", "F(".repeat(200), ")".repeat(200));
    let ds = ltl::read(&json!({"formula": deep, "propositions": props}), &q).unwrap_err();
    assert!(ds[0].diagnostic.message.contains("deeper"), "{ds:?}");
}

fn validator(schema: Value) -> (boon::Schemas, boon::SchemaIndex) {
    let mut schemas = boon::Schemas::new();
    let mut compiler = boon::Compiler::new();
    compiler.add_resource("urn:m2rc:ids", schema).unwrap();
    let idx = compiler.compile("urn:m2rc:ids", &mut schemas).unwrap();
    (schemas, idx)
}

#[test]
fn json_schemas_accept_generated_replies_and_refuse_bad_ones() {
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("suite");
    build(&suite, 8);
    let (ds, di) = validator(schema::direct_id_schema());
    let (ls, li) = validator(schema::catalog_ltl_schema());
    let mut n = 0;
    for (pm, ep, program) in episodes(&suite) {
        let q = MapQuery::new(&pm.map);
        let start = start_cell(&pm.map, &ep).unwrap();
        let gold = gold_reply(&program, &pm, &q, start).unwrap();
        ds.validate(&gold.reply, di)
            .unwrap_or_else(|e| panic!("{e}: {}", gold.reply));
        let (as_ltl, _) = ltl::from_direct_id(&gold.reply);
        ls.validate(&as_ltl, li)
            .unwrap_or_else(|e| panic!("{e}: {as_ltl}"));
        n += 1;
    }
    assert!(n >= 6);
    assert!(
        ds.validate(&json!({"segments": [{"id": "s1", "target_id": "bed"}]}), di)
            .is_err()
    );
    assert!(
        ds.validate(
            &json!({"segments": [], "constraints": [{"kind": "hover", "ref_ids": ["room_1"]}]}),
            di
        )
        .is_err()
    );
    assert!(
        ls.validate(&json!({"formula": "F a; rm", "propositions": []}), li)
            .is_err()
    );
}

#[test]
fn the_catalog_lists_every_room_and_object_with_geometry() {
    let (map, start) = demo();
    let q = MapQuery::new(&map);
    let c = catalog::compact_catalog(&q, start);
    assert_eq!(c["schema_version"], 1);
    assert_eq!(c["start"]["id"], "task_start");
    assert_eq!(c["rooms"].as_array().unwrap().len(), map.rooms.len());
    assert_eq!(c["objects"].as_array().unwrap().len(), map.objects.len());
    let o = &c["objects"][0];
    for k in [
        "id",
        "category",
        "room_id",
        "center_grid",
        "bbox_grid",
        "footprint_cell_count",
    ] {
        assert!(!o[k].is_null(), "{k}: {o}");
    }
    let r = &c["rooms"][0];
    for k in ["id", "category", "center_grid", "bbox_grid", "area_cells"] {
        assert!(!r[k].is_null(), "{k}: {r}");
    }
    assert!(!c["room_adjacency"].as_array().unwrap().is_empty());
    assert_eq!(catalog::compact_catalog(&q, start), c, "deterministic");
}

fn simulated(rate: f64, seed: u64) -> m2rc_baselines::ModelSetup {
    let mut s = gold_setup();
    s.backend = Backend::Simulated(SimulatedSpec {
        fault_rate: rate,
        seed,
    });
    s.model = format!("simulated:{rate}:{seed}");
    s
}

#[test]
fn gold_and_simulated_runs_and_repairs() {
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("suite");
    let m = build(&suite, 8);
    let run = |setup: m2rc_baselines::ModelSetup,
               rounds: usize,
               form: &'static m2rc_baselines::grounding::directid::Form,
               dir: &str| {
        let out = tmp.path().join(dir);
        let mut method = CatalogIds::new(Arc::new(setup), rounds, form);
        method.repair.local_fixes = false;
        runner::run(&method, &opts(&suite, &out)).unwrap();
        read_records(&out).unwrap()
    };
    let ok = |rs: &[Value]| rs.iter().filter(|r| r["status"] == "ok").count();
    for form in [&DIRECT_ID, &ltl::FORM] {
        let gold = run(gold_setup(), 0, form, &format!("{}-gold", form.name));
        assert_eq!(gold.len(), m.episodes.len());
        assert!(ok(&gold) >= m.episodes.len() - 1, "{}", ok(&gold));
        assert_eq!(gold[0][form.name]["gold_replies"], true);
    }
    let r0 = run(simulated(0.9, 1), 0, &DIRECT_ID, "r0");
    let r3 = run(simulated(0.9, 1), 3, &DIRECT_ID, "r3");
    assert_eq!(
        r3,
        run(simulated(0.9, 1), 3, &DIRECT_ID, "r3b"),
        "same inputs, same records"
    );
    assert!(ok(&r3) > ok(&r0), "{} vs {}", ok(&r3), ok(&r0));
    // Some rejection spoke JSON pointers into the reply.
    let pointed = |r: &Value| {
        r["directid"]["calls"].as_array().unwrap().iter().any(|c| {
            c["diagnostics"]
                .as_array()
                .unwrap()
                .iter()
                .any(|d| d["message"].as_str().unwrap().contains("(at `/"))
        })
    };
    assert!(r3.iter().any(pointed), "no pointer diagnostics");
}

/// The first reply of the mock server: the gold ids of the one-episode suite with one id's kind
/// word misspelt; the repair request must carry its pointer.
#[test]
fn direct_id_against_a_mock_server_and_through_a_batch_round_trip() {
    mock_server_and_batch_round_trip(&DIRECT_ID);
}

#[test]
fn catalog_ltl_against_a_mock_server_and_through_a_batch_round_trip() {
    mock_server_and_batch_round_trip(&ltl::FORM);
}

/// A misspelt id repaired from its pointer diagnostic, the same record from the cache alone, and
/// the batch round trip, for a catalog-id form.
fn mock_server_and_batch_round_trip(form: &'static m2rc_baselines::grounding::directid::Form) {
    let tmp = tempfile::tempdir().unwrap();
    let suite = tmp.path().join("suite");
    build(&suite, 1);
    let (pm, ep, program) = episodes(&suite).remove(0);
    let q = MapQuery::new(&pm.map);
    let start = start_cell(&pm.map, &ep).unwrap();
    let good = (form.write)(&gold_reply(&program, &pm, &q, start).unwrap().reply)
        .0
        .to_string();
    let bad = good.replacen("\"object_", "\"obejct_", 1).replacen(
        "\"room_",
        "\"roon_",
        usize::from(!good.contains("\"object_")),
    );
    assert_ne!(bad, good);
    let mut server = mockito::Server::new();
    let (g2, b2) = (good.clone(), bad.clone());
    let calls = server
        .mock("POST", "/v1/chat/completions")
        .with_body_from_request(move |req| {
            let body: Value = serde_json::from_slice(req.body().unwrap()).unwrap();
            let n = body["messages"].as_array().unwrap().len();
            let text = if n <= 2 {
                assert!(
                    body["messages"][1]["content"]
                        .as_str()
                        .unwrap()
                        .contains("\"schema_version\":1")
                );
                b2.clone()
            } else {
                let last = body["messages"][n - 1]["content"].as_str().unwrap();
                assert!(last.contains("\"pointer\": \"/"), "{last}");
                g2.clone()
            };
            completion(&text).to_string().into_bytes()
        })
        .expect(2)
        .create();
    let cache = tmp.path().join("cache");
    let setup = |url: &str, batch: Option<&Path>| {
        let mut s = server_setup(url, &cache, batch);
        s.embed_http = None;
        s
    };
    let method = CatalogIds::new(Arc::new(setup(&server.url(), None)), 3, form);
    let out = tmp.path().join("run");
    runner::run(&method, &opts(&suite, &out)).unwrap();
    let recs = read_records(&out).unwrap();
    assert_eq!(
        recs[0][form.name]["success_round"], 1,
        "{}",
        recs[0][form.name]
    );
    assert_eq!(recs[0]["status"], "ok");
    calls.assert();
    // Offline from the cache: the same record, no request.
    let mut offline = setup("http://127.0.0.1:9", None);
    offline.store = Store::new(Some(ResponseCache::new(&cache)), None, true);
    let out2 = tmp.path().join("run2");
    runner::run(
        &CatalogIds::new(Arc::new(offline), 3, form),
        &opts(&suite, &out2),
    )
    .unwrap();
    let strip = |mut v: Value| {
        v["model"] = Value::Null;
        v
    };
    assert_eq!(
        strip(read_records(&out2).unwrap()[0][form.name].clone()),
        strip(recs[0][form.name].clone())
    );

    // Batch: export the request, answer it as a provider would, import, run again.
    let cache_b = tmp.path().join("cache-b");
    let batch = tmp.path().join("batch.jsonl");
    let exporting = {
        let mut s = server_setup("http://offline.invalid", &cache_b, Some(&batch));
        s.embed_http = None;
        s
    };
    let exporting = Arc::new(exporting);
    let out3 = tmp.path().join("run3");
    runner::run(
        &CatalogIds::new(exporting.clone(), 0, form),
        &opts(&suite, &out3),
    )
    .unwrap();
    exporting.store.batch.as_ref().unwrap().finish().unwrap();
    assert!(
        read_records(&out3).unwrap().is_empty(),
        "a pending episode writes no record"
    );
    let lines: Vec<Value> = std::fs::read_to_string(&batch)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 1);
    let answer = json!({"custom_id": lines[0]["custom_id"], "response": {"status_code": 200, "body": completion(&good)}, "error": null});
    let replies = tmp.path().join("out.jsonl");
    std::fs::write(&replies, format!("{answer}\n")).unwrap();
    let r = import_batch_files(&[replies], &ResponseCache::new(&cache_b)).unwrap();
    assert_eq!((r.imported, r.failed.len()), (1, 0), "{r:?}");
    let mut again = server_setup("http://offline.invalid", &cache_b, None);
    again.embed_http = None;
    again.store = Store::new(Some(ResponseCache::new(&cache_b)), None, true);
    runner::run(
        &CatalogIds::new(Arc::new(again), 0, form),
        &opts(&suite, &out3),
    )
    .unwrap();
    let recs = read_records(&out3).unwrap();
    assert_eq!(recs[0]["status"], "ok", "{}", recs[0]);
}

/// The token benchmark (not a test): the first prompt's estimated tokens per episode for
/// CaG, Schema, Direct ID and catalog-LTL on a suite, mean and largest with its map. Run with
/// `M2RC_TOKENS_SUITE=DIR cargo test -p m2rc-baselines --test it prompt_tokens -- --ignored
/// --nocapture` (`M2RC_TOKENS_EVERY=N` takes every N-th episode).
#[test]
#[ignore = "a measurement on a built suite, not a test"]
fn prompt_tokens_per_episode() {
    use m2rc_baselines::grounding::directid::prompt::direct_id_prompt;
    use m2rc_compiler::intent::schema_prompt;
    use m2rc_compiler::lower::{CatalogMode, Prompt, PromptOptions, SceneCatalog};
    let dir =
        std::path::PathBuf::from(std::env::var("M2RC_TOKENS_SUITE").expect("M2RC_TOKENS_SUITE"));
    let every: usize = std::env::var("M2RC_TOKENS_EVERY")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let m = SuiteManifest::read(&dir).unwrap();
    let names = ["cag", "schema", "directid", "catalog-ltl"];
    let mut stats: Vec<(usize, usize, usize, String)> = vec![(0, 0, 0, String::new()); names.len()];
    let mut maps: std::collections::BTreeMap<String, m2rc_stdlib::map::SemanticMap> =
        Default::default();
    for e in m
        .episodes
        .iter()
        .filter(|e| e.split == "eval")
        .step_by(every.max(1))
    {
        let map = maps.entry(e.map_id.clone()).or_insert_with(|| {
            let path = m.map_path(&dir, &e.map_id).unwrap();
            m2rc_stdlib::load::load_map(path.to_str().unwrap()).unwrap()
        });
        let ep = Episode::read(&dir.join(&e.file)).unwrap();
        let instruction = ep.instruction.clone().unwrap_or_default();
        let q = MapQuery::new(map);
        let start = start_cell(map, &ep).unwrap();
        let counts = SceneCatalog::from_map(map, CatalogMode::Counts);
        let catalog = catalog::compact_catalog(&q, start);
        let prompts: [Prompt; 4] = [
            Prompt::new(
                &map.map_id,
                &counts,
                &instruction,
                &PromptOptions::default(),
            ),
            schema_prompt(
                &map.map_id,
                &counts,
                &instruction,
                m2rc_baselines::grounding::schema::EXAMPLES,
            ),
            direct_id_prompt(&catalog, &instruction),
            ltl::ltl_prompt(&catalog, &instruction),
        ];
        for (s, p) in stats.iter_mut().zip(&prompts) {
            let t = p.estimated_tokens();
            s.0 += 1;
            s.1 += t;
            if t > s.2 {
                s.2 = t;
                s.3 = format!("{} ({} objects)", map.map_id, map.objects.len());
            }
        }
    }
    println!("| variant | episodes | mean tokens | largest | largest on |");
    println!("| --- | ---: | ---: | ---: | --- |");
    for (n, s) in names.iter().zip(&stats) {
        println!(
            "| {n} | {} | {:.0} | {} | {} |",
            s.0,
            s.1 as f64 / s.0.max(1) as f64,
            s.2,
            s.3
        );
    }
}
