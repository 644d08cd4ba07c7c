//! Fault injection on `m2rc lsp`: an absurd Content-Length, malformed JSON-RPC, and `exit`
//! without `shutdown`. Each session is written in one go and the output read after the server
//! ends, bounded by a timeout so a hung server fails instead of hanging CI.

use serde_json::{Value, json};
use std::io::{Read, Write};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn frame(v: &Value) -> Vec<u8> {
    let body = v.to_string();
    format!("Content-Length: {}\r\n\r\n{body}", body.len()).into_bytes()
}

fn raw_frame(body: &str) -> Vec<u8> {
    format!("Content-Length: {}\r\n\r\n{body}", body.len()).into_bytes()
}

/// Runs a session; returns the exit status and the messages the server wrote.
fn session(input: &[u8]) -> (Option<i32>, Vec<Value>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_m2rc"))
        .arg("lsp")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    stdin.write_all(input).unwrap();
    drop(stdin);
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("the language server did not finish within 60 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut out = Vec::new();
    child.stdout.take().unwrap().read_to_end(&mut out).unwrap();
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    (status.code(), parse_frames(&out), err)
}

fn parse_frames(mut bytes: &[u8]) -> Vec<Value> {
    let mut out = Vec::new();
    while let Some(pos) = bytes.windows(4).position(|w| w == b"\r\n\r\n") {
        let head = std::str::from_utf8(&bytes[..pos]).unwrap();
        let n: usize = head
            .lines()
            .find_map(|l| l.strip_prefix("Content-Length: "))
            .unwrap()
            .trim()
            .parse()
            .unwrap();
        let body = &bytes[pos + 4..pos + 4 + n];
        out.push(serde_json::from_slice(body).unwrap());
        bytes = &bytes[pos + 4 + n..];
    }
    out
}

fn init() -> Vec<u8> {
    let mut v = frame(
        &json!({"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {"capabilities": {}}}),
    );
    v.extend(frame(
        &json!({"jsonrpc": "2.0", "method": "initialized", "params": {}}),
    ));
    v
}

fn shutdown_exit() -> Vec<u8> {
    let mut v = frame(&json!({"jsonrpc": "2.0", "id": 99, "method": "shutdown", "params": null}));
    v.extend(frame(
        &json!({"jsonrpc": "2.0", "method": "exit", "params": null}),
    ));
    v
}

#[test]
fn a_huge_content_length_is_answered_not_allocated() {
    let mut input = init();
    input.extend(b"Content-Length: 999999999999\r\n\r\n{}");
    let (code, msgs, err) = session(&input);
    assert!(code.is_some(), "killed by a signal; stderr: {err}");
    assert!(!err.contains("memory allocation"), "{err}");
    let e = msgs
        .iter()
        .find(|m| m["error"]["code"] == -32600)
        .unwrap_or_else(|| panic!("{msgs:?}"));
    assert!(
        e["error"]["message"]
            .as_str()
            .unwrap()
            .contains("larger than the limit"),
        "{e}"
    );
}

#[test]
fn malformed_json_rpc_gets_a_parse_error_and_the_server_goes_on() {
    let mut input = init();
    input.extend(raw_frame("{this is not json"));
    input.extend(raw_frame(r#"{"jsonrpc": "2.0", "method": 5}"#));
    input.extend(frame(
        &json!({"jsonrpc": "2.0", "id": 2, "method": "textDocument/hover", "params": {
        "textDocument": {"uri": "file:///x.m2r"}, "position": {"line": 0, "character": 0}}}),
    ));
    input.extend(shutdown_exit());
    let (code, msgs, err) = session(&input);
    let parse = msgs
        .iter()
        .find(|m| m["error"]["code"] == -32700)
        .unwrap_or_else(|| panic!("{msgs:?}"));
    assert_eq!(parse["id"], Value::Null);
    let invalid = msgs
        .iter()
        .find(|m| m["error"]["code"] == -32600)
        .unwrap_or_else(|| panic!("{msgs:?}"));
    assert_eq!(invalid["id"], Value::Null);
    assert!(
        msgs.iter()
            .any(|m| m["id"] == 2 && m.get("error").is_none()),
        "{msgs:?}"
    );
    assert!(msgs.iter().any(|m| m["id"] == 99), "{msgs:?}");
    assert_eq!(code, Some(0), "{err}");
}

#[test]
fn exit_without_shutdown_exits_1_and_after_shutdown_0() {
    let mut input = init();
    input.extend(frame(
        &json!({"jsonrpc": "2.0", "method": "exit", "params": null}),
    ));
    let (code, _, err) = session(&input);
    assert_eq!(code, Some(1), "{err}");
    let mut input = init();
    input.extend(shutdown_exit());
    let (code, _, err) = session(&input);
    assert_eq!(code, Some(0), "{err}");
}

#[test]
fn a_malformed_frame_is_said_on_stderr_and_exits_non_zero() {
    // A header without Content-Length, and a body cut off by the end of the stream.
    for tail in [
        &b"Content-Type: x\r\n\r\n"[..],
        &b"Content-Length: 50\r\n\r\n{\"jsonrpc\": \"2.0\""[..],
    ] {
        let mut input = init();
        input.extend(tail);
        let (code, msgs, err) = session(&input);
        assert_eq!(code, Some(2), "{err}");
        assert!(err.contains("malformed message"), "{err}");
        assert!(
            msgs.iter().any(|m| m["error"]["code"] == -32700),
            "{msgs:?}"
        );
    }
    // A stream closed between messages is still a clean end.
    let (code, _, err) = session(&init());
    assert_eq!(code, Some(0), "{err}");
}

#[test]
fn a_second_initialize_gets_an_invalid_request_error() {
    let mut input = init();
    input.extend(frame(
        &json!({"jsonrpc": "2.0", "id": 7, "method": "initialize", "params": {"capabilities": {}}}),
    ));
    input.extend(shutdown_exit());
    let (code, msgs, err) = session(&input);
    let again = msgs
        .iter()
        .find(|m| m["id"] == 7)
        .unwrap_or_else(|| panic!("{msgs:?}"));
    assert_eq!(again["error"]["code"], -32600, "{again}");
    assert_eq!(code, Some(0), "{err}");
}
