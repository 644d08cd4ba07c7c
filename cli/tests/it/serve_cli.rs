//! `m2rc serve` driven over loopback on an ephemeral port: good and bad programs, malformed and
//! oversized requests, concurrent requests, the bearer token, and a bounded load test.

use crate::common::{bin, m2rc, repo};
use serde_json::{Value, json};
use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};

/// A running service, stopped when dropped.
struct Server {
    child: Child,
    url: String,
}

impl Server {
    fn start(extra: &[&str], token: Option<&str>) -> Server {
        match token {
            Some(t) => Server::start_env(extra, &[("M2R_SERVE_TOKEN", t)]),
            None => Server::start_env(extra, &[]),
        }
    }

    /// A service with `extra` flags and `env` set; no model or token but those given.
    fn start_env(extra: &[&str], env: &[(&str, &str)]) -> Server {
        let mut cmd = Command::new(bin());
        cmd.args(["serve", "--map", "demo", "--listen", "127.0.0.1:0"])
            .args(extra)
            .env_remove("M2R_SERVE_TOKEN")
            .env_remove("M2R_LLM_BASE_URL")
            .env_remove("M2R_LLM_MODEL")
            .env_remove("M2R_LLM_API_KEY")
            .stdout(Stdio::piped())
            .stderr(Stdio::null());
        for (k, v) in env {
            cmd.env(k, v);
        }
        let mut child = cmd.spawn().expect("spawn m2rc serve");
        let mut line = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut line)
            .unwrap();
        let url = line
            .trim()
            .strip_prefix("m2rc serve: listening on ")
            .unwrap_or_else(|| panic!("unexpected first line: {line:?}"))
            .to_string();
        Server { child, url }
    }

    fn post(&self, body: impl Into<reqwest::blocking::Body>, token: Option<&str>) -> (u16, Value) {
        let mut req = reqwest::blocking::Client::new()
            .post(format!("{}/route", self.url))
            .header("content-type", "application/json")
            .body(body);
        if let Some(t) = token {
            req = req.bearer_auth(t);
        }
        let resp = req.send().expect("request");
        let status = resp.status().as_u16();
        let text = resp.text().unwrap();
        let v = serde_json::from_str(&text).unwrap_or_else(|e| panic!("{e}: {text}"));
        (status, v)
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn example(name: &str) -> String {
    std::fs::read_to_string(repo().join("examples").join(name)).unwrap()
}

fn program(name: &str) -> String {
    json!({ "program": example(name) }).to_string()
}

#[test]
fn good_program_returns_route_in_cells_metres_and_nav_path() {
    let s = Server::start(&[], None);
    let (status, v) = s.post(program("02_avoid_kitchen.m2r"), None);
    assert_eq!(status, 200, "{v}");
    let cells = v["route"]["cells"].as_array().unwrap();
    let points = v["route"]["map_frame"]["points_m"].as_array().unwrap();
    assert!(cells.len() > 2 && cells.len() == points.len(), "{v}");
    assert_eq!(v["program"], example("02_avoid_kitchen.m2r"));
    let nav = v["nav_path"].as_str().unwrap();
    assert_eq!(nav.matches("pose:").count(), cells.len(), "{nav}");
    // A start in metres: the route then begins at that point's cell.
    let k = cells.len() / 2;
    let body = json!({"program": example("02_avoid_kitchen.m2r"), "start": points[k]});
    let (status, w) = s.post(body.to_string(), None);
    assert_eq!(status, 200, "{w}");
    assert_eq!(w["route"]["cells"][0], cells[k]);
    // The map summary.
    let m: Value = serde_json::from_str(
        &reqwest::blocking::get(format!("{}/map", s.url))
            .unwrap()
            .text()
            .unwrap(),
    )
    .unwrap();
    assert_eq!(m["map_id"], "demo", "{m}");
    assert!(m["rooms"].as_array().is_some_and(|r| !r.is_empty()));
}

#[test]
fn bad_program_gets_422_with_its_diagnostic() {
    let s = Server::start(&[], None);
    let body = json!({"program": "route {\n  go rooms(kichen).only()\n}\n"}).to_string();
    let (status, v) = s.post(body, None);
    assert_eq!(status, 422, "{v}");
    let diags = v["diagnostics"].as_array().unwrap();
    assert!(!diags.is_empty(), "{v}");
    assert!(diags[0]["code"].as_str().is_some(), "{v}");
    assert!(v["program"].as_str().unwrap().contains("kichen"));
    // The service is still up.
    assert_eq!(s.post(program("01_smallest_bathroom.m2r"), None).0, 200);
}

#[test]
fn malformed_requests_get_400_with_a_message() {
    let s = Server::start(&[], None);
    for body in [
        "{not json",
        "[1, 2]",
        r#"{"program": 3}"#,
        r#"{"progrm": "route { go start }"}"#,
        r#"{"program": "route {}", "start": [1]}"#,
        "{}",
    ] {
        let (status, v) = s.post(body, None);
        assert_eq!(status, 400, "{body}: {v}");
        assert!(v["message"].as_str().is_some_and(|m| !m.is_empty()), "{v}");
    }
    let (status, v) = s.post(
        json!({"instruction": "go to the kitchen"}).to_string(),
        None,
    );
    assert_eq!(status, 400, "{v}");
    assert!(
        v["message"]
            .as_str()
            .unwrap()
            .contains("no model configured")
    );
    let (status, v) = s.post(
        json!({"program": example("01_smallest_bathroom.m2r"), "start": [1e9, 0.0]}).to_string(),
        None,
    );
    assert_eq!(status, 400, "{v}");
    assert!(v["message"].as_str().unwrap().contains("outside the map"));
}

#[test]
fn oversized_body_is_refused_with_413() {
    let s = Server::start(&["--max-body-bytes", "1000"], None);
    let big = json!({ "program": format!("// {}\nroute {{ go start }}", "x".repeat(5000)) });
    let (status, v) = s.post(big.to_string(), None);
    assert_eq!(status, 413, "{v}");
    assert!(v["help"].as_str().unwrap().contains("--max-body-bytes"));
    assert_eq!(s.post(program("01_smallest_bathroom.m2r"), None).0, 200);
}

#[test]
fn concurrent_requests_all_succeed_with_the_same_route() {
    let s = Server::start(&[], None);
    let bodies: Vec<Value> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..8)
            .map(|_| scope.spawn(|| s.post(program("05_closer_to_table.m2r"), None)))
            .collect();
        handles
            .into_iter()
            .map(|h| {
                let (status, v) = h.join().unwrap();
                assert_eq!(status, 200, "{v}");
                v
            })
            .collect()
    });
    assert!(bodies.windows(2).all(|w| w[0] == w[1]));
}

#[test]
fn token_is_required_off_loopback_and_checked() {
    let dir = tempfile::tempdir().unwrap();
    let r = m2rc(
        &["serve", "--map", "demo", "--listen", "0.0.0.0:0"],
        dir.path(),
    )
    .expect(2);
    assert!(r.stderr.contains("M2R_SERVE_TOKEN"), "{}", r.stderr);
    let s = Server::start(&[], Some("s3cret-token"));
    let (status, v) = s.post(program("01_smallest_bathroom.m2r"), None);
    assert_eq!(status, 401, "{v}");
    assert_eq!(
        s.post(program("01_smallest_bathroom.m2r"), Some("wrong")).0,
        401
    );
    let (status, v) = s.post(program("01_smallest_bathroom.m2r"), Some("s3cret-token"));
    assert_eq!(status, 200, "{v}");
    assert!(!v.to_string().contains("s3cret"));
}

/// Bounded load test (run with `--ignored --nocapture`): 200 requests of a cached `.m2r` program
/// from 4 clients; prints requests per second and the largest latency.
#[test]
#[ignore]
fn load_test_prints_throughput() {
    let s = Server::start(&[], None);
    let body = program("02_avoid_kitchen.m2r");
    let started = std::time::Instant::now();
    let worst = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..4)
            .map(|_| {
                scope.spawn(|| {
                    let mut worst = std::time::Duration::ZERO;
                    for _ in 0..50 {
                        let t = std::time::Instant::now();
                        assert_eq!(s.post(body.clone(), None).0, 200);
                        worst = worst.max(t.elapsed());
                    }
                    worst
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).max()
    })
    .unwrap();
    let secs = started.elapsed().as_secs_f64();
    println!(
        "serve load: 200 requests in {secs:.2} s = {:.1} requests/s, max latency {:.1} ms",
        200.0 / secs,
        worst.as_secs_f64() * 1e3
    );
}

const KEY: &str = "sk-serve-SECRET-4242";

fn reply(program: &str) -> String {
    json!({"choices": [{"message": {"role": "assistant", "content": format!("Here you go:\n```m2r\n{program}```")}, "finish_reason": "stop"}],
           "usage": {"prompt_tokens": 2500, "completion_tokens": 40}})
    .to_string()
}

/// A service whose model is the mock server at `url`, with its reply cache in `home`.
fn start_with_model(url: &str, home: &std::path::Path) -> Server {
    let cache = home.join("llm-cache");
    Server::start_env(
        &[
            "--llm-base-url",
            url,
            "--llm-backoff-ms",
            "1",
            "--llm-cache",
            cache.to_str().unwrap(),
        ],
        &[("M2R_LLM_API_KEY", KEY)],
    )
}

#[test]
fn an_instruction_goes_through_the_model_and_comes_back_with_its_program_and_route() {
    let home = tempfile::tempdir().unwrap();
    let mut llm = mockito::Server::new();
    // The reply quotes the key (a server that echoes its request): the service must not.
    let written = format!("route {{\n  go objects(bed).nearest(start)\n}}\n// {KEY}\n");
    let mock = llm
        .mock("POST", "/v1/chat/completions")
        .match_header("authorization", format!("Bearer {KEY}").as_str())
        .with_body(reply(&written))
        .expect(1)
        .create();
    let s = start_with_model(&format!("{}/v1", llm.url()), home.path());
    let body = json!({"instruction": "Go to the bed nearest to you."}).to_string();
    let (status, v) = s.post(body, None);
    mock.assert();
    assert_eq!(status, 200, "{v}");
    let text = v.to_string();
    assert!(!text.contains(KEY), "the key was echoed: {text}");
    assert!(
        v["program"]
            .as_str()
            .unwrap()
            .contains("objects(bed).nearest(start)"),
        "{v}"
    );
    assert!(v["program"].as_str().unwrap().contains("***"), "{v}");
    assert_eq!(v["instruction"], "Go to the bed nearest to you.");
    let rounds = v["rounds"].as_array().unwrap();
    assert_eq!(rounds.len(), 1, "{v}");
    assert_eq!(rounds[0]["outcome"], "accepted", "{v}");
    assert!(v["route"]["cells"].as_array().unwrap().len() > 1, "{v}");
    assert!(v["nav_path"].as_str().unwrap().contains("pose:"));
    // A program request on the same service is unchanged.
    assert_eq!(s.post(program("01_smallest_bathroom.m2r"), None).0, 200);
}

#[test]
fn a_bad_program_is_repaired_from_its_diagnostics_and_each_round_is_returned() {
    let home = tempfile::tempdir().unwrap();
    let mut llm = mockito::Server::new();
    // A set in a one-place argument: rejected by the checker, sent back with its diagnostic.
    let first = llm
        .mock("POST", "/v1/chat/completions")
        .match_body(mockito::Matcher::Regex("Go to a bed".into()))
        .with_body(reply("route {\n  go area_near(objects(bed))\n}\n"))
        .expect(1)
        .create();
    let second = llm
        .mock("POST", "/v1/chat/completions")
        .match_body(mockito::Matcher::Regex("E02|E01|E04".into()))
        .with_body(reply("route {\n  go objects(bed).nearest(start)\n}\n"))
        .expect(1)
        .create();
    let s = start_with_model(&format!("{}/v1", llm.url()), home.path());
    let (status, v) = s.post(json!({"instruction": "Go to a bed."}).to_string(), None);
    first.assert();
    second.assert();
    assert_eq!(status, 200, "{v}");
    let rounds = v["rounds"].as_array().unwrap();
    assert_eq!(rounds.len(), 2, "{v}");
    assert_ne!(rounds[0]["outcome"], "accepted", "{v}");
    assert!(
        !rounds[0]["diagnostics"].as_array().unwrap().is_empty(),
        "{v}"
    );
    assert_eq!(rounds[1]["outcome"], "accepted", "{v}");
    assert_eq!(
        v["program"],
        "route {\n  go objects(bed).nearest(start)\n}\n"
    );
}
