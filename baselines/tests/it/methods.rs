//! Each method's call sequence against a mock server (replies scripted per call, including
//! malformed and refused replies and embeddings of the wrong dimension), and a batch round trip of
//! a multi-call method, on the demo house.

use crate::support::*;
use m2rc_baselines::calls::embed::lexical;
use m2rc_benchmark::episode::{Episode, StartPose};
use m2rc_benchmark::methods::{Prediction, PreparedMap};
use m2rc_llm::{ResponseCache, import_batch_files};
use serde_json::{Value, json};
use std::sync::{Arc, Mutex};

fn demo() -> PreparedMap {
    PreparedMap::new(m2rc_stdlib::demo::demo_map().unwrap())
}

fn episode(map: &PreparedMap, text: &str) -> Episode {
    let start = map.map.start.unwrap_or_else(|| {
        map.map
            .occupancy
            .iter_cells()
            .find(|(c, _)| map.map.is_free(*c))
            .unwrap()
            .0
    });
    Episode {
        id: Some(1),
        map_id: Some(map.map.map_id.clone()),
        instruction: Some(text.into()),
        start_pose: Some(StartPose {
            row: Some(start.row as i64),
            col: Some(start.col as i64),
            ..StartPose::default()
        }),
        ..Episode::default()
    }
}

/// The kind of a chat request, from its prompts.
fn kind(body: &Value) -> &'static str {
    let sys = body["messages"][0]["content"].as_str().unwrap_or("");
    let user = body["messages"][1]["content"].as_str().unwrap_or("");
    if user.contains("Your previous") {
        "repair"
    } else if sys.contains("referring-expression recogniser") {
        "rer"
    } else if sys.contains("into linear temporal logic. In each command") {
        "translate"
    } else if sys.contains("concise linear temporal logic") {
        "stage1"
    } else {
        "stage2"
    }
}

fn embed_body(body: &Value, dims: Option<usize>) -> Value {
    let vs: Vec<Vec<f32>> = body["input"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| {
            let v = lexical(t.as_str().unwrap());
            match dims {
                Some(d) => v[..d].to_vec(),
                None => v,
            }
        })
        .collect();
    embeddings(&vs)
}

fn block<'p>(p: &'p Prediction, name: &str) -> &'p Value {
    &p.extra[name]
}

fn steps(p: &Prediction, name: &str) -> Vec<String> {
    block(p, name)["calls"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["step"].as_str().unwrap().to_string())
        .collect()
}

/// Serves chat by `script(kind, nth call of that kind)` and embeddings by `dims(inputs)`.
fn serve(
    server: &mut mockito::Server,
    script: impl Fn(&str, usize, &Value) -> Value + Send + Sync + 'static,
    dims: impl Fn(usize) -> Option<usize> + Send + Sync + 'static,
) -> (mockito::Mock, mockito::Mock, Arc<Mutex<Vec<Value>>>) {
    let seen = Arc::new(Mutex::new(Vec::<Value>::new()));
    let s2 = seen.clone();
    let chat = server
        .mock("POST", "/v1/chat/completions")
        .with_body_from_request(move |req| {
            let body: Value = serde_json::from_slice(req.body().unwrap()).unwrap();
            let k = kind(&body);
            let mut seen = s2.lock().unwrap();
            let nth = seen.iter().filter(|b| kind(b) == k).count();
            seen.push(body.clone());
            script(k, nth, &body).to_string().into_bytes()
        })
        .create();
    let embed = server
        .mock("POST", "/v1/embeddings")
        .with_body_from_request(move |req| {
            let body: Value = serde_json::from_slice(req.body().unwrap()).unwrap();
            let n = body["input"].as_array().unwrap().len();
            embed_body(&body, dims(n)).to_string().into_bytes()
        })
        .create();
    (chat, embed, seen)
}

const TEXT: &str =
    "Go to the bed in the bedroom, then walk to the toilet. Never enter the kitchen.";

#[test]
fn lang2ltl_repairs_malformed_translations_in_order() {
    let tmp = tempfile::tempdir().unwrap();
    let mut server = mockito::Server::new();
    let (_c, _e, seen) = serve(
        &mut server,
        |k, nth, _| match (k, nth) {
            ("rer", _) => completion(
                "```json\n{\"referring_expressions\": [\"the bed\", \"the toilet\", \"the kitchen\"]}\n```",
            ),
            ("translate", _) => completion("F & a"),
            ("repair", 0) => completion("F ( a & b"),
            _ => completion("& F & a F b G ! c"),
        },
        |_| None,
    );
    let setup = Arc::new(server_setup(&server.url(), &tmp.path().join("c"), None));
    let m = m2rc_baselines::lang2ltl::make(setup);
    let map = demo();
    let p = m.predict(&map, &episode(&map, TEXT)).unwrap();
    assert_eq!(
        steps(&p, "lang2ltl"),
        [
            "rer",
            "ap_embeddings",
            "expression_embeddings",
            "translate",
            "repair1",
            "repair2"
        ]
    );
    let b = block(&p, "lang2ltl");
    assert_eq!(b["formula_source"], "repair 2");
    assert_eq!(b["formula_lifted"], "& F & a F b G ! c");
    assert_eq!(b["translation_errors"].as_array().unwrap().len(), 2);
    assert!(p.status.is_none(), "{:?} {b}", p.status);
    assert!(p.trajectory.len() > 1);
    // Every chat call went out at temperature 0 (the adaptation's), and no map data is in a prompt.
    for body in seen.lock().unwrap().iter() {
        assert_eq!(body["temperature"], 0.0);
        assert!(!body.to_string().contains("object_"));
    }
}

#[test]
fn lang2ltl_falls_back_to_the_sequential_formula_after_two_failed_repairs() {
    let tmp = tempfile::tempdir().unwrap();
    let mut server = mockito::Server::new();
    let (_c, _e, _) = serve(
        &mut server,
        |k, _, _| match k {
            "rer" => completion("{\"referring_expressions\": [\"the bed\", \"the toilet\"]}"),
            _ => completion("I cannot write that formula."),
        },
        |_| None,
    );
    let setup = Arc::new(server_setup(&server.url(), &tmp.path().join("c"), None));
    let map = demo();
    let p = m2rc_baselines::lang2ltl::make(setup)
        .predict(&map, &episode(&map, TEXT))
        .unwrap();
    let b = block(&p, "lang2ltl");
    assert_eq!(b["formula_source"], "sequential fallback");
    // F (ap1 & F ap2) over the two grounded APs, in expression order.
    let f = b["formula"].as_str().unwrap();
    let aps: Vec<&str> = b["groundings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|g| g["ap"].as_str().unwrap())
        .collect();
    assert_eq!(f, format!("F & {} F {}", aps[0], aps[1]), "{b}");
    assert_eq!(steps(&p, "lang2ltl").len(), 6);
}

#[test]
fn lang2ltl_failures_refused_rer_and_wrong_dimensions() {
    let tmp = tempfile::tempdir().unwrap();
    let mut server = mockito::Server::new();
    let (_c, _e, _) = serve(
        &mut server,
        |_, _, _| json!({"choices": [{"message": {"role": "assistant", "content": null, "refusal": "I can't help"}, "finish_reason": "stop"}]}),
        |_| None,
    );
    let setup = Arc::new(server_setup(&server.url(), &tmp.path().join("c"), None));
    let map = demo();
    let p = m2rc_baselines::lang2ltl::make(setup)
        .predict(&map, &episode(&map, TEXT))
        .unwrap();
    assert_eq!(p.status.as_deref(), Some("llm_refused"));
    assert!(
        p.trajectory.is_empty(),
        "the runner scores the start-only route"
    );

    let mut server = mockito::Server::new();
    let (_c, _e, _) = serve(
        &mut server,
        |_, _, _| completion("{\"referring_expressions\": [\"the bed\"]}"),
        // The landmarks' vectors and the expression's disagree in length.
        |n| if n == 1 { Some(8) } else { None },
    );
    let setup = Arc::new(server_setup(&server.url(), &tmp.path().join("d"), None));
    let p = m2rc_baselines::lang2ltl::make(setup)
        .predict(&map, &episode(&map, TEXT))
        .unwrap();
    assert_eq!(p.status.as_deref(), Some("embedding_failed"));
    assert!(
        block(&p, "lang2ltl")["failure"]
            .as_str()
            .unwrap()
            .contains("8 dimensions")
    );
}

#[test]
fn limp_two_stages_one_repair_at_its_own_temperature() {
    let tmp = tempfile::tempdir().unwrap();
    let mut server = mockito::Server::new();
    let (_c, _e, seen) = serve(
        &mut server,
        |k, _, _| match k {
            "stage1" => completion("F ( bed & F toilet ) & G ( !kitchen )"),
            "stage2" => completion("F ( near[bed] & F toilet ) & G ( !near[kitchen] )"),
            _ => completion(
                "Output: F ( near[bed::isinside(bedroom)] & F near[toilet] ) & G ( !near[kitchen] )",
            ),
        },
        |_| None,
    );
    let setup = Arc::new(server_setup(&server.url(), &tmp.path().join("c"), None));
    let map = demo();
    let p = m2rc_baselines::limp::make(setup)
        .predict(&map, &episode(&map, TEXT))
        .unwrap();
    assert_eq!(steps(&p, "limp"), ["stage1", "stage2", "repair"]);
    let b = block(&p, "limp");
    assert!(b["stage2_error"].as_str().unwrap().contains("bare"));
    assert_eq!(b["groundings"].as_object().unwrap().len(), 3, "{b}");
    for body in seen.lock().unwrap().iter() {
        assert_eq!(body["temperature"], 0.2);
    }
    // An unsupported comparator ends the episode with LIMP's own status.
    let mut server = mockito::Server::new();
    let (_c, _e, _) = serve(
        &mut server,
        |k, _, _| match k {
            "stage1" => completion("F bed"),
            _ => completion("F near[bed::isbehind(sofa)]"),
        },
        |_| None,
    );
    let setup = Arc::new(server_setup(&server.url(), &tmp.path().join("d"), None));
    let p = m2rc_baselines::limp::make(setup)
        .predict(&map, &episode(&map, TEXT))
        .unwrap();
    assert_eq!(p.status.as_deref(), Some("unsupported_comparator"));
}

/// Lang2LTL in a batch run: each layer of calls the cache cannot answer is one round (the
/// recogniser, the landmarks' embeddings, the expressions' embeddings, the translation), and the
/// last round's answer is the live run's.
#[test]
fn lang2ltl_batch_round_trip() {
    let tmp = tempfile::tempdir().unwrap();
    let cache = tmp.path().join("cache");
    let map = demo();
    let ep = episode(&map, TEXT);
    let answer = |l: &Value| -> Value {
        let body = &l["body"];
        if l["url"] == "/v1/embeddings" {
            return embed_body(body, None);
        }
        match kind(body) {
            "rer" => completion(
                "{\"referring_expressions\": [\"the bed\", \"the toilet\", \"the kitchen\"]}",
            ),
            _ => completion("& F & a F b G ! c"),
        }
    };
    let mut rounds = 0;
    let p = loop {
        let batch = tmp.path().join(format!("batch{rounds}.jsonl"));
        let setup = Arc::new(server_setup("http://offline.invalid", &cache, Some(&batch)));
        let p = m2rc_baselines::lang2ltl::make(setup.clone())
            .predict(&map, &ep)
            .unwrap();
        if p.status.as_deref() != Some("pending") {
            break p;
        }
        rounds += 1;
        assert!(rounds <= 6);
        setup.store.batch.as_ref().unwrap().finish().unwrap();
        let mut out = String::new();
        for line in std::fs::read_to_string(&batch).unwrap().lines() {
            let l: Value = serde_json::from_str(line).unwrap();
            out += &json!({"custom_id": l["custom_id"], "response": {"status_code": 200, "body": answer(&l)}, "error": null}).to_string();
            out.push('\n');
        }
        let replies = tmp.path().join(format!("out{rounds}.jsonl"));
        std::fs::write(&replies, out).unwrap();
        let r = import_batch_files(&[replies], &ResponseCache::new(&cache)).unwrap();
        assert_eq!(
            (r.imported, r.failed.len()),
            (1, 0),
            "one request per round: {r:?}"
        );
    };
    assert_eq!(rounds, 4);
    assert!(p.status.is_none(), "{:?}", p.status);
    // The same episode against a live server with the same replies gives the same route.
    let mut server = mockito::Server::new();
    let (_c, _e, _) = serve(
        &mut server,
        |k, _, _| match k {
            "rer" => completion(
                "{\"referring_expressions\": [\"the bed\", \"the toilet\", \"the kitchen\"]}",
            ),
            _ => completion("& F & a F b G ! c"),
        },
        |_| None,
    );
    let setup = Arc::new(server_setup(&server.url(), &tmp.path().join("live"), None));
    let live = m2rc_baselines::lang2ltl::make(setup)
        .predict(&map, &ep)
        .unwrap();
    assert_eq!(live.trajectory, p.trajectory);
}
