//! End to end: spawn `m2rc tools --map demo` and talk MCP to it over stdio (newline-delimited
//! JSON-RPC 2.0), as an agent would: initialize, list, call, build and submit a route, and
//! malformed frames, each answered without the server going away. Every read has a timeout so a
//! hung server fails the test instead of hanging CI.

use serde_json::{Value, json};
use std::io::{BufRead, BufReader, Write};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{Receiver, channel};
use std::time::Duration;

struct Server {
    child: Child,
    stdin: ChildStdin,
    lines: Receiver<Value>,
}

impl Server {
    fn spawn(extra: &[&str]) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_m2rc"))
            .args(["tools", "--map", "demo"])
            .args(extra)
            .env("M2RC_MAP_CACHE", "off")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("spawn m2rc tools");
        let stdin = child.stdin.take().unwrap();
        let stdout = child.stdout.take().unwrap();
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { return };
                let v: Value = serde_json::from_str(&line).expect("every answer is one JSON line");
                if tx.send(v).is_err() {
                    return;
                }
            }
        });
        Server {
            child,
            stdin,
            lines: rx,
        }
    }

    fn send_raw(&mut self, text: &str) {
        self.stdin.write_all(text.as_bytes()).unwrap();
        self.stdin.write_all(b"\n").unwrap();
        self.stdin.flush().unwrap();
    }

    fn recv(&mut self) -> Value {
        self.lines
            .recv_timeout(Duration::from_secs(120))
            .expect("an answer")
    }

    fn request(&mut self, id: u64, method: &str, params: Value) -> Value {
        self.send_raw(
            &json!({"jsonrpc": "2.0", "id": id, "method": method, "params": params}).to_string(),
        );
        let r = self.recv();
        assert_eq!(r["id"], id, "{r}");
        r
    }

    fn call(&mut self, id: u64, name: &str, args: Value) -> Value {
        let r = self.request(id, "tools/call", json!({"name": name, "arguments": args}));
        r["result"].clone()
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[test]
fn an_agent_initializes_lists_calls_and_gets_a_route() {
    let mut s = Server::spawn(&["--max-line-bytes", "4096"]);
    let init = s.request(
        1,
        "initialize",
        json!({"protocolVersion": "2025-06-18",
        "capabilities": {}, "clientInfo": {"name": "test", "version": "0"}}),
    );
    assert_eq!(init["result"]["protocolVersion"], "2025-06-18");
    assert!(init["result"]["capabilities"]["tools"].is_object());
    // An older revision it speaks is kept; one it does not know gets its latest.
    let older = s.request(9, "initialize", json!({"protocolVersion": "2024-11-05"}));
    assert_eq!(older["result"]["protocolVersion"], "2024-11-05");
    let unknown = s.request(10, "initialize", json!({"protocolVersion": "1999-01-01"}));
    assert_eq!(unknown["result"]["protocolVersion"], "2025-06-18");
    // A notification gets no answer: the next line answers the next request.
    s.send_raw(r#"{"jsonrpc":"2.0","method":"notifications/initialized"}"#);
    let list = s.request(2, "tools/list", json!({}));
    let tools = list["result"]["tools"].as_array().unwrap();
    let names: Vec<&str> = tools.iter().map(|t| t["name"].as_str().unwrap()).collect();
    for n in [
        "objects",
        "rooms",
        "nearest",
        "where",
        "compare",
        "constraint",
        "segment",
        "task",
    ] {
        assert!(names.contains(&n), "{n}");
    }
    assert!(tools.iter().all(|t| t["inputSchema"]["type"] == "object"));
    // Malformed frames: each answered with a JSON-RPC error, the server stays.
    s.send_raw("{not json");
    assert_eq!(s.recv()["error"]["code"], -32700);
    s.send_raw("[1, 2]");
    assert_eq!(s.recv()["error"]["code"], -32600);
    s.send_raw(&format!(
        "{{\"jsonrpc\":\"2.0\",\"id\":9,\"method\":\"x\",\"pad\":\"{}\"}}",
        "a".repeat(5000)
    ));
    let long = s.recv();
    assert_eq!(long["error"]["code"], -32600);
    assert!(
        long["error"]["message"]
            .as_str()
            .unwrap()
            .contains("--max-line-bytes")
    );
    let unknown = s.request(3, "resources/list", json!({}));
    assert_eq!(unknown["error"]["code"], -32601);
    // Tool calls: results are handles; a bad call is a result with isError.
    let beds = s.call(4, "objects", json!({"category": "bed"}));
    assert_eq!(beds["isError"], false, "{beds}");
    let h = beds["structuredContent"]["handle"]
        .as_str()
        .unwrap()
        .to_string();
    let bad = s.call(5, "objects", json!({"category": "unicorn"}));
    assert_eq!(bad["isError"], true);
    assert!(
        bad["content"][0]["text"]
            .as_str()
            .unwrap()
            .contains("unicorn")
    );
    let bed = s.call(6, "nearest", json!({"of": h}));
    let bed = bed["structuredContent"]["handle"]
        .as_str()
        .unwrap()
        .to_string();
    let seg = s.call(7, "segment", json!({"target": bed}));
    let seg = seg["structuredContent"]["handle"]
        .as_str()
        .unwrap()
        .to_string();
    let done = s.call(8, "task", json!({"segments": [seg]}));
    assert_eq!(done["isError"], false, "{done}");
    let route = &done["structuredContent"]["route"];
    assert!(route["length_m"].as_f64().unwrap() > 0.0, "{done}");
    assert!(route["geojson"].is_object());
    assert!(
        done["structuredContent"]["program"]
            .as_str()
            .unwrap()
            .contains("nearest()")
    );
    // A fresh session follows: the old handles are gone.
    let after = s.call(10, "count", json!({"of": h}));
    assert_eq!(after["isError"], true);
}
