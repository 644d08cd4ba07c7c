//! End to end: spawn the real `m2rc lsp` binary and talk LSP to it over stdio, framing messages
//! with `Content-Length` headers as an editor does. Every read is bounded by a timeout so a hung
//! server fails the test instead of hanging CI.

use serde_json::{Value, json};
use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{Receiver, channel};
use std::time::Duration;

struct Server {
    child: Child,
    stdin: ChildStdin,
    messages: Receiver<Value>,
}

impl Server {
    fn spawn() -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_m2rc"))
            .arg("lsp")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("spawn m2rc lsp");
        let stdin = child.stdin.take().unwrap();
        let stdout = child.stdout.take().unwrap();
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let mut reader = BufReader::new(stdout);
            loop {
                let mut length = None;
                loop {
                    let mut line = String::new();
                    if reader.read_line(&mut line).unwrap_or(0) == 0 {
                        return;
                    }
                    let line = line.trim_end();
                    if line.is_empty() {
                        break;
                    }
                    if let Some(v) = line.strip_prefix("Content-Length: ") {
                        length = v.parse::<usize>().ok();
                    }
                }
                let Some(n) = length else { return };
                let mut body = vec![0u8; n];
                if reader.read_exact(&mut body).is_err() {
                    return;
                }
                if let Ok(v) = serde_json::from_slice::<Value>(&body)
                    && tx.send(v).is_err()
                {
                    return;
                }
            }
        });
        Server {
            child,
            stdin,
            messages: rx,
        }
    }

    fn send(&mut self, msg: Value) {
        let body = msg.to_string();
        write!(self.stdin, "Content-Length: {}\r\n\r\n{}", body.len(), body).unwrap();
        self.stdin.flush().unwrap();
    }

    fn next(&self) -> Value {
        self.messages
            .recv_timeout(Duration::from_secs(30))
            .expect("the server answered within 30 s")
    }

    fn response(&self, id: i64) -> Value {
        loop {
            let m = self.next();
            if m["id"] == id && m.get("method").is_none() {
                return m;
            }
        }
    }

    fn notification(&self, method: &str) -> Value {
        loop {
            let m = self.next();
            if m["method"] == method {
                return m;
            }
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[test]
fn lsp_over_stdio_diagnoses_edits_and_exits_cleanly() {
    let mut s = Server::spawn();
    s.send(
        json!({"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {"capabilities": {}}}),
    );
    let init = s.response(1);
    assert!(
        init["result"]["capabilities"]["hoverProvider"]
            .as_bool()
            .unwrap_or(false),
        "{init}"
    );
    s.send(json!({"jsonrpc": "2.0", "method": "initialized", "params": {}}));

    // Clients percent-encode non-ASCII path characters in URIs (RFC 3986).
    let uri = "file:///work/%C3%BCn%C3%AFcode/route.m2r";
    let text = "// “kitchen” → bedroom\nlet c = objects(chiar).nearest(start)\nroute { go c }\n";
    s.send(
        json!({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {
        "textDocument": {"uri": uri, "languageId": "m2r", "version": 1, "text": text}}}),
    );
    let d = s.notification("textDocument/publishDiagnostics");
    let diags = d["params"]["diagnostics"].as_array().unwrap();
    let chiar = diags
        .iter()
        .find(|x| x["message"].as_str().unwrap_or("").contains("chiar"))
        .unwrap_or_else(|| panic!("no diagnostic about `chiar`: {d}"));
    assert_eq!(chiar["range"]["start"], json!({"line": 1, "character": 16}));
    assert!(chiar["code"].as_str().unwrap().starts_with('E'), "{chiar}");

    let fixed = text.replace("chiar", "chair");
    s.send(
        json!({"jsonrpc": "2.0", "method": "textDocument/didChange", "params": {
        "textDocument": {"uri": uri, "version": 2}, "contentChanges": [{"text": fixed}]}}),
    );
    let d = s.notification("textDocument/publishDiagnostics");
    assert_eq!(d["params"]["version"], 2);
    let errors: Vec<&Value> = d["params"]["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|x| x["severity"] == 1)
        .collect();
    assert!(errors.is_empty(), "{d}");

    s.send(
        json!({"jsonrpc": "2.0", "id": 2, "method": "textDocument/hover", "params": {
        "textDocument": {"uri": uri}, "position": {"line": 1, "character": 25}}}),
    );
    let h = s.response(2);
    assert!(
        h["result"]["contents"]["value"]
            .as_str()
            .unwrap()
            .contains("nearest"),
        "{h}"
    );

    s.send(json!({"jsonrpc": "2.0", "id": 3, "method": "shutdown", "params": null}));
    let r = s.response(3);
    assert!(r.get("error").is_none(), "{r}");
    s.send(json!({"jsonrpc": "2.0", "method": "exit", "params": null}));
    let status = wait_with_timeout(&mut s.child, Duration::from_secs(20));
    assert_eq!(status, Some(0), "the server exits 0 after shutdown + exit");
}

fn wait_with_timeout(child: &mut Child, limit: Duration) -> Option<i32> {
    let start = std::time::Instant::now();
    while start.elapsed() < limit {
        if let Ok(Some(status)) = child.try_wait() {
            return status.code();
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    None
}
