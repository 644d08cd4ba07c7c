//! Fault injection on model replies and batch files, end to end through the binary: replies and
//! bodies past their limits, batch replies made for another request, a batch export over its own
//! input or over an existing file, empty instructions, and route files past their byte limit.

use crate::common;
use common::*;
use serde_json::{Value, json};
use std::path::Path;
use std::process::Command;

const GO: &str = "Go to the bed nearest to you.";
const PROGRAM: &str = "route {\n  go objects(bed).nearest(start)\n}\n";

fn m2rc_env(args: &[&str], cwd: &Path, base_url: &str) -> Run {
    let out = Command::new(bin())
        .args(args)
        .current_dir(cwd)
        .env_remove("M2R_LLM_MODEL")
        .env_remove("M2R_LLM_API_KEY")
        .env("M2R_LLM_BASE_URL", base_url)
        .env("CI", "1")
        .output()
        .unwrap();
    Run {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

fn completion(content: &str) -> Value {
    json!({"choices": [{"message": {"role": "assistant", "content": content}, "finish_reason": "stop"}],
           "usage": {"prompt_tokens": 10, "completion_tokens": 5}})
}

#[test]
fn replies_and_bodies_past_their_limits_end_the_run_as_model_failed() {
    let tmp = tempfile::tempdir().unwrap();
    let mut server = mockito::Server::new();
    // A program of 300 KB: refused before it is compiled.
    let long = format!("```m2r\n{PROGRAM}// {}\n```", "x".repeat(300 * 1024));
    let m = server
        .mock("POST", "/v1/chat/completions")
        .with_body(completion(&long).to_string())
        .expect(1)
        .create();
    let url = format!("{}/v1", server.url());
    let r = m2rc_env(
        &["run", GO, "--map", "demo", "--llm-no-cache"],
        tmp.path(),
        &url,
    )
    .expect(1);
    m.assert();
    assert!(
        r.stderr.contains("262144 bytes of a program"),
        "{}",
        r.stderr
    );
    assert!(r.stderr.contains("no route: model_failed"), "{}", r.stderr);
    assert!(!r.stderr.contains("xxxxxxxx"), "the reply was printed");
    // A body of 2 MiB against a limit of 1 MiB: not read, not retried.
    let mut server = mockito::Server::new();
    let m = server
        .mock("POST", "/v1/chat/completions")
        .with_body(vec![b' '; 2 << 20])
        .expect(1)
        .create();
    let url = format!("{}/v1", server.url());
    let r = m2rc_env(
        &[
            "run",
            GO,
            "--map",
            "demo",
            "--llm-no-cache",
            "--llm-max-response-mb",
            "1",
        ],
        tmp.path(),
        &url,
    )
    .expect(1);
    m.assert();
    assert!(
        r.stderr.contains("more than the limit of 1048576 bytes"),
        "{}",
        r.stderr
    );
}

#[test]
fn empty_instructions_and_pointless_repair_requests_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("p.m2r"), PROGRAM).unwrap();
    for args in [
        vec!["prompt", "  ", "--map", "demo"],
        vec!["run", "", "--map", "demo"],
    ] {
        let r = m2rc_env(&args, tmp.path(), "http://127.0.0.1:9/v1").expect(2);
        assert!(
            r.stderr.contains("the instruction is empty"),
            "{}",
            r.stderr
        );
        assert!(r.stdout.is_empty());
    }
    let r = m2rc(
        &[
            "prompt",
            GO,
            "--map",
            "demo",
            "--repair-rounds",
            "0",
            "--repair-of",
            "p.m2r",
        ],
        tmp.path(),
    )
    .expect(2);
    assert!(
        r.stderr.contains("never sends a repair request"),
        "{}",
        r.stderr
    );
    assert!(r.stdout.is_empty());
    // A program past the 256 KiB limit is not compiled for a repair request.
    let big = format!("{PROGRAM}{}", "// x\n".repeat(60_000));
    std::fs::write(tmp.path().join("big.m2r"), big).unwrap();
    let r = m2rc(
        &["prompt", GO, "--map", "demo", "--repair-of", "big.m2r"],
        tmp.path(),
    )
    .expect(1);
    assert!(r.stderr.contains("limit"), "{}", r.stderr);
    assert!(r.stdout.is_empty());
}

/// Answers every request of a batch input file with `PROGRAM` (the body's `model` as given).
fn answer(batch: &Path, out: &Path, model: Option<&str>) {
    let mut lines = String::new();
    for l in std::fs::read_to_string(batch).unwrap().lines() {
        let req: Value = serde_json::from_str(l).unwrap();
        let mut body = completion(&format!("```m2r\n{PROGRAM}```"));
        if let Some(m) = model {
            body["model"] = json!(m);
        }
        lines.push_str(
            &json!({"custom_id": req["custom_id"], "response": {"status_code": 200, "body": body}})
                .to_string(),
        );
        lines.push('\n');
    }
    std::fs::write(out, lines).unwrap();
}

#[test]
fn batch_replies_belong_to_their_requests_and_never_overwrite_inputs() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let offline = "http://127.0.0.1:9/v1";
    let run = |extra: &[&str]| {
        let mut args = vec!["run", GO, "--map", "demo", "--llm-cache", "cache"];
        args.extend_from_slice(extra);
        m2rc_env(&args, dir, offline)
    };
    // Export: the request's custom_id carries its digest.
    let r = run(&["--llm-batch-out", "b1.jsonl"]).expect(1);
    assert!(r.stderr.contains("wrote 1 batch request"), "{}", r.stderr);
    let req: Value = serde_json::from_str(
        std::fs::read_to_string(dir.join("b1.jsonl"))
            .unwrap()
            .trim(),
    )
    .unwrap();
    let id = req["custom_id"].as_str().unwrap();
    assert!(
        id.starts_with("demo/run/round0#") && id.len() == "demo/run/round0#".len() + 16,
        "{id}"
    );
    // The export never replaces its own input, nor, without --force, any non-empty file.
    answer(&dir.join("b1.jsonl"), &dir.join("o1.jsonl"), None);
    let before = std::fs::read(dir.join("o1.jsonl")).unwrap();
    let r = run(&[
        "--llm-batch-in",
        "o1.jsonl",
        "--llm-batch-out",
        "./o1.jsonl",
    ]);
    assert_ne!(r.code, Some(0));
    assert!(
        r.stderr.contains("is the file --llm-batch-in"),
        "{}",
        r.stderr
    );
    assert_eq!(std::fs::read(dir.join("o1.jsonl")).unwrap(), before);
    let r = run(&["--llm-batch-out", "b1.jsonl"]);
    assert_ne!(r.code, Some(0));
    assert!(r.stderr.contains("--force"), "{}", r.stderr);
    // Replies made for another model's request under the same name are refused.
    let r = m2rc_env(
        &[
            "run",
            GO,
            "--map",
            "demo",
            "--llm-cache",
            "other-cache",
            "--llm-model",
            "other",
            "--llm-batch-out",
            "other.jsonl",
        ],
        dir,
        offline,
    )
    .expect(1);
    assert!(r.stderr.contains("wrote 1 batch request"), "{}", r.stderr);
    answer(&dir.join("other.jsonl"), &dir.join("other-out.jsonl"), None);
    let r = run(&["--llm-batch-in", "other-out.jsonl", "--llm-cache-only"]).expect(1);
    assert!(
        r.stderr.contains("imported 0 batch replies"),
        "{}",
        r.stderr
    );
    assert!(r.stderr.contains("answers another request"), "{}", r.stderr);
    // Our own replies are imported (a differing model name is warned about) and used.
    answer(
        &dir.join("b1.jsonl"),
        &dir.join("o1.jsonl"),
        Some("somebody-else"),
    );
    let r = run(&["--llm-batch-in", "o1.jsonl", "--llm-cache-only"]).expect(0);
    assert!(
        r.stderr.contains("imported 1 batch replies"),
        "{}",
        r.stderr
    );
    assert!(r.stderr.contains("somebody-else"), "{}", r.stderr);
    assert!(r.stderr.contains("accepted in round 0"), "{}", r.stderr);
    // With --force, an existing export may be replaced.
    run(&["--llm-batch-out", "b1.jsonl", "--force"]).expect(0);
}

#[test]
fn route_files_past_the_byte_limit_are_refused_before_they_are_parsed() {
    let tmp = tempfile::tempdir().unwrap();
    let (m, _, ep, _) = &episodes(suite(3))[0];
    let map = suite(3).join("maps").join(m).join(format!("{m}.json"));
    // 65 MiB of one list: refused by its size, before any of it is parsed.
    let mut text = Vec::with_capacity(65 << 20);
    text.push(b'[');
    while text.len() < 65 << 20 {
        text.extend_from_slice(b"[1, 1], ");
    }
    text.extend_from_slice(b"[1, 1]]");
    std::fs::write(tmp.path().join("r.json"), text).unwrap();
    let r = m2rc(
        &[
            "eval",
            "--map",
            map.to_str().unwrap(),
            "--episode",
            ep.to_str().unwrap(),
            "--route",
            "r.json",
        ],
        tmp.path(),
    )
    .expect(2);
    assert!(
        r.stderr.contains("the limit of a route file"),
        "{}",
        r.stderr
    );
}

#[test]
fn run_stops_a_program_at_the_episode_budget_and_says_why() {
    let tmp = tempfile::tempdir().unwrap();
    let mut server = mockito::Server::new();
    let ltl = "```m2r\nlet bed = objects(bed).nearest(start)\nlet kitchen = rooms(kitchen).only()\nroute ltl \"F(kitchen & F bed)\"\n```";
    let m = server
        .mock("POST", "/v1/chat/completions")
        .with_body(completion(ltl).to_string())
        .expect(1)
        .create();
    let url = format!("{}/v1", server.url());
    let r = m2rc_env(
        &[
            "run",
            GO,
            "--map",
            "demo",
            "--llm-no-cache",
            "--episode-max-product-mb",
            "1",
        ],
        tmp.path(),
        &url,
    )
    .expect(1);
    m.assert();
    assert!(
        r.stderr.contains("no route: budget_exceeded")
            && r.stderr.contains("memory budget of 1 MiB"),
        "{}",
        r.stderr
    );
    let r = m2rc_env(
        &["run", GO, "--map", "demo", "--episode-max-seconds", "0"],
        tmp.path(),
        &url,
    )
    .expect(2);
    assert!(r.stderr.contains("--episode-max-seconds"), "{}", r.stderr);
}
