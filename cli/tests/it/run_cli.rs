//! `m2rc run` and `m2rc prompt` end to end, against a mock OpenAI-compatible server on loopback.

use serde_json::{Value, json};
use std::path::Path;
use std::process::Command;

const KEY: &str = "sk-cli-SECRET-9191";

/// The binary with no model configured and its user cache directory under `home` (never the
/// real user's).
fn m2rc(home: &Path) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_m2rc"));
    c.env_remove("M2R_LLM_BASE_URL")
        .env_remove("M2R_LLM_MODEL")
        .env_remove("M2R_LLM_API_KEY")
        .env("XDG_CACHE_HOME", home.join("cache"))
        .env("HOME", home);
    c
}

fn reply(program: &str) -> String {
    json!({"choices": [{"message": {"role": "assistant", "content": format!("Here you go:\n```m2r\n{program}```")}, "finish_reason": "stop"}],
           "usage": {"prompt_tokens": 2500, "completion_tokens": 40}})
    .to_string()
}

#[test]
fn run_lowers_repairs_and_plans_against_a_mock_server() {
    let tmp = tempfile::tempdir().unwrap();
    let mut server = mockito::Server::new();
    // The first reply misspells a category (fixed locally) and uses a set as one place (sent back).
    let first = server
        .mock("POST", "/v1/chat/completions")
        .match_header("authorization", format!("Bearer {KEY}").as_str())
        .with_body(reply("route {\n  go area_near(objects(bedd))\n}\n"))
        .expect(1)
        .create();
    let second = server
        .mock("POST", "/v1/chat/completions")
        .match_body(mockito::Matcher::Regex("E02|E01|E04".into()))
        .with_body(reply(
            "route {\n  go area_near(objects(bed).nearest(start))\n}\n",
        ))
        .expect(1)
        .create();
    let route = tmp.path().join("route.json");
    let png = tmp.path().join("route.png");
    let out = m2rc(tmp.path())
        .current_dir(tmp.path())
        .env("M2R_LLM_BASE_URL", format!("{}/v1", server.url()))
        .env("M2R_LLM_API_KEY", KEY)
        .args([
            "run",
            "Go to the bed nearest to you.",
            "--map",
            "demo",
            "-o",
        ])
        .arg(&route)
        .arg("--png")
        .arg(&png)
        .args(["--llm-backoff-ms", "1"])
        .output()
        .unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "{stdout}\n{stderr}");
    first.assert();
    second.assert();
    assert!(stderr.contains("local fix"), "{stderr}");
    assert!(stderr.contains("accepted in round 1"), "{stderr}");
    assert!(stdout.contains("objects(bed).nearest(start)"), "{stdout}");
    let doc: Value = serde_json::from_slice(&std::fs::read(&route).unwrap()).unwrap();
    assert!(doc["trajectory"].as_array().unwrap().len() > 1);
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    // The cache is the user's ($XDG_CACHE_HOME/m2rc/llm-cache), said on stderr; nothing is left
    // in the working directory.
    let cache = tmp.path().join("cache/m2rc/llm-cache");
    assert!(
        stderr.contains(&format!("replies cached in {}", cache.display())),
        "{stderr}"
    );
    assert!(std::fs::read_dir(&cache).unwrap().count() > 0);
    assert!(!tmp.path().join(".m2rc").exists());
    // Cached: the same command makes no request (the mocks' expectations are already met) ...
    let again = m2rc(tmp.path())
        .current_dir(tmp.path())
        .env("M2R_LLM_BASE_URL", "http://127.0.0.1:9/v1")
        .args([
            "run",
            "Go to the bed nearest to you.",
            "--map",
            "demo",
            "--llm-cache-only",
            "--emit",
            "m2r",
        ])
        .output()
        .unwrap();
    assert!(
        again.status.success(),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
    assert_eq!(
        String::from_utf8_lossy(&again.stdout),
        "route {\n  go area_near(objects(bed).nearest(start))\n}\n"
    );
    // ... and nothing written holds the key, nor does anything printed.
    let mut stack = vec![tmp.path().to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            if e.path().is_dir() {
                stack.push(e.path());
            } else {
                let b = std::fs::read(e.path()).unwrap();
                assert!(
                    !String::from_utf8_lossy(&b).contains(KEY),
                    "{}",
                    e.path().display()
                );
            }
        }
    }
    assert!(!stdout.contains(KEY) && !stderr.contains(KEY));
}

#[test]
fn run_without_a_server_fails_cleanly_and_prompt_prints_the_messages() {
    let tmp = tempfile::tempdir().unwrap();
    let out = m2rc(tmp.path())
        .args(["run", "Go to the bed.", "--map", "demo", "--llm-no-cache"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("M2R_LLM_BASE_URL"), "{err}");
    // It says what works without a server, with this command's own map and instruction.
    assert!(
        err.contains("m2rc prompt --map demo \"Go to the bed.\"")
            && err.contains("--llm-batch-out"),
        "{err}"
    );
    // A server that does not answer: the URL tried is named, and the same ways out are shown.
    let port = {
        let l = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        l.local_addr().unwrap().port()
    };
    let out = m2rc(tmp.path())
        .args(["run", "Go to the bed.", "--map", "demo", "--llm-no-cache"])
        .args(["--llm-max-attempts", "1", "--llm-base-url"])
        .arg(format!("http://127.0.0.1:{port}/v1"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(&format!(
            "cannot connect to http://127.0.0.1:{port}/v1/chat/completions"
        )) && err.contains("m2rc prompt --map demo"),
        "{err}"
    );
    // `--llm simulated` is not offered by `run --help`, and refused naming where it works.
    let help = m2rc(tmp.path()).args(["run", "--help"]).output().unwrap();
    let help = String::from_utf8_lossy(&help.stdout);
    assert!(
        help.contains("--llm-base-url") && !help.contains("simulated"),
        "{help}"
    );
    let out = m2rc(tmp.path())
        .args([
            "run",
            "Go to the bed.",
            "--map",
            "demo",
            "--llm",
            "simulated",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("m2rc bench run"));
    let out = m2rc(tmp.path())
        .args([
            "prompt",
            "--map",
            "demo",
            "Go to the bed.",
            "--format",
            "json",
        ])
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["messages"].as_array().unwrap().len(), 2);
    assert!(v["estimated_tokens"].as_u64().unwrap() > 1000);
    let prog = tmp.path().join("p.m2r");
    std::fs::write(&prog, "route {\n  go area_near(objects(bed))\n}\n").unwrap();
    let out = m2rc(tmp.path())
        .args(["prompt", "--map", "demo", "Go to the bed.", "--repair-of"])
        .arg(&prog)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success());
    assert!(
        text.contains("===== assistant =====") && text.contains("## Diagnostics as JSON"),
        "{text}"
    );
}
