//! The engine driven in process over `Connection::memory()`, as a client would drive it.

use super::*;
use lsp_server::{Connection, Message, Notification, Request, RequestId};
use std::str::FromStr;
use std::time::Duration;

struct Client {
    conn: Connection,
    thread: Option<std::thread::JoinHandle<()>>,
    next_id: i32,
}

impl Client {
    fn start() -> Client {
        let (server, client) = Connection::memory();
        let thread = std::thread::spawn(move || {
            let vocab = Vocabulary::benchmark();
            serve(&server, &vocab).expect("server loop");
        });
        let mut c = Client {
            conn: client,
            thread: Some(thread),
            next_id: 1,
        };
        let init = c.request("initialize", serde_json::json!({ "capabilities": {} }));
        assert_eq!(init["capabilities"]["hoverProvider"], true, "{init}");
        c.notify("initialized", serde_json::json!({}));
        c
    }

    fn recv(&self) -> Message {
        self.conn
            .receiver
            .recv_timeout(Duration::from_secs(20))
            .expect("server answered in time")
    }

    fn request(&mut self, method: &str, params: serde_json::Value) -> serde_json::Value {
        let id = RequestId::from(self.next_id);
        self.next_id += 1;
        self.conn
            .sender
            .send(Message::Request(Request::new(
                id.clone(),
                method.into(),
                params,
            )))
            .unwrap();
        loop {
            if let Message::Response(r) = self.recv() {
                assert_eq!(r.id, id);
                return r
                    .response_result
                    .unwrap_or_else(|e| panic!("error response: {e:?}"));
            }
        }
    }

    fn notify(&self, method: &str, params: serde_json::Value) {
        self.conn
            .sender
            .send(Message::Notification(Notification::new(
                method.into(),
                params,
            )))
            .unwrap();
    }

    fn diagnostics(&self) -> serde_json::Value {
        loop {
            if let Message::Notification(n) = self.recv()
                && n.method == "textDocument/publishDiagnostics"
            {
                return n.params;
            }
        }
    }
}

impl Drop for Client {
    fn drop(&mut self) {
        let id = RequestId::from(9999);
        let _ = self.conn.sender.send(Message::Request(Request::new(
            id,
            "shutdown".into(),
            serde_json::Value::Null,
        )));
        let _ = self
            .conn
            .sender
            .send(Message::Notification(Notification::new(
                "exit".into(),
                serde_json::Value::Null,
            )));
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

const URI: &str = "file:///tmp/route.m2r";

fn open(c: &Client, text: &str) -> serde_json::Value {
    c.notify(
        "textDocument/didOpen",
        serde_json::json!({ "textDocument": { "uri": URI, "languageId": "m2r", "version": 1, "text": text } }),
    );
    c.diagnostics()
}

#[test]
fn publishes_diagnostics_on_open_and_change() {
    let mut c = Client::start();
    let bad = "let c = objects(chiar).nearest(start)\nroute { go c }\n";
    let d = open(&c, bad);
    let diags = d["diagnostics"].as_array().unwrap();
    assert!(!diags.is_empty(), "{d}");
    assert_eq!(diags[0]["range"]["start"]["line"], 0);
    assert_eq!(diags[0]["range"]["start"]["character"], 16);
    assert_eq!(diags[0]["source"], "m2rc");

    let good = "let c = objects(chair).nearest(start)\nroute { go c }\n";
    c.notify(
        "textDocument/didChange",
        serde_json::json!({ "textDocument": { "uri": URI, "version": 2 }, "contentChanges": [{ "text": good }] }),
    );
    let d = c.diagnostics();
    assert_eq!(d["version"], 2);
    let errors: Vec<_> = d["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|x| x["severity"] == 1)
        .collect();
    assert!(errors.is_empty(), "{d}");
    let _ = c.request("shutdown", serde_json::Value::Null);
}

#[test]
fn positions_are_utf16_after_non_ascii_text() {
    let c = Client::start();
    // `→` is 3 bytes in UTF-8 and 1 UTF-16 unit; `𝄞` is 4 bytes and 2 units.
    let text = "// kitchen → living room 𝄞\nlet c = objects(chiar).nearest(start) // → 𝄞\nroute { go c }\n";
    let d = open(&c, text);
    let first = &d["diagnostics"][0];
    assert_eq!(first["range"]["start"]["line"], 1, "{d}");
    assert_eq!(first["range"]["start"]["character"], 16, "{d}");

    let text = "let a = \"→𝄞\" let c = objects(chiar).nearest(start)\nroute { go c }\n";
    let d = open(&c, text);
    let diags = d["diagnostics"].as_array().unwrap();
    let chiar = diags
        .iter()
        .find(|x| x["message"].as_str().unwrap_or("").contains("chiar"))
        .expect("chiar diagnostic");
    // `let a = "→𝄞" ` is 14 UTF-16 units; `let c = objects(` is 16 more.
    assert_eq!(chiar["range"]["start"]["character"], 30, "{d}");
}

#[test]
fn hover_shows_builtin_signatures_and_binding_types() {
    let mut c = Client::start();
    let text = "let c = objects(chair).nearest(start)\nroute { go c }\n";
    open(&c, text);
    let h = c.request(
        "textDocument/hover",
        serde_json::json!({ "textDocument": { "uri": URI }, "position": { "line": 0, "character": 25 } }),
    );
    let value = h["contents"]["value"].as_str().unwrap();
    assert!(value.contains("nearest"), "{value}");
    let h = c.request(
        "textDocument/hover",
        serde_json::json!({ "textDocument": { "uri": URI }, "position": { "line": 1, "character": 11 } }),
    );
    let value = h["contents"]["value"].as_str().unwrap();
    assert!(value.contains("let c: Object"), "{value}");
    let h = c.request(
        "textDocument/hover",
        serde_json::json!({ "textDocument": { "uri": URI }, "position": { "line": 0, "character": 18 } }),
    );
    assert!(
        h["contents"]["value"]
            .as_str()
            .unwrap()
            .contains("object category"),
        "{h}"
    );
}

#[test]
fn completion_offers_methods_after_dot_and_names_elsewhere() {
    let mut c = Client::start();
    let text = "let chairs = objects(chair)\nlet c = chairs.ne\nroute { go c }\n";
    open(&c, text);
    let r = c.request(
        "textDocument/completion",
        serde_json::json!({ "textDocument": { "uri": URI }, "position": { "line": 1, "character": 17 } }),
    );
    let labels: Vec<&str> = r
        .as_array()
        .unwrap()
        .iter()
        .map(|i| i["label"].as_str().unwrap())
        .collect();
    assert!(
        labels.contains(&"nearest") && labels.contains(&"near") && labels.contains(&"next_to"),
        "{labels:?}"
    );
    assert!(!labels.contains(&"objects"), "{labels:?}");

    let r = c.request(
        "textDocument/completion",
        serde_json::json!({ "textDocument": { "uri": URI }, "position": { "line": 1, "character": 10 } }),
    );
    let labels: Vec<&str> = r
        .as_array()
        .unwrap()
        .iter()
        .map(|i| i["label"].as_str().unwrap())
        .collect();
    assert!(labels.contains(&"chairs"), "{labels:?}");
}

#[test]
fn unknown_requests_get_an_error_not_silence() {
    let mut c = Client::start();
    let id = RequestId::from(77);
    c.conn
        .sender
        .send(Message::Request(Request::new(
            id.clone(),
            "textDocument/definition".into(),
            serde_json::json!({}),
        )))
        .unwrap();
    loop {
        if let Message::Response(r) = c.recv() {
            assert_eq!(r.id, id);
            assert!(r.response_result.is_err());
            break;
        }
    }
    let _ = c.request("shutdown", serde_json::Value::Null);
    let _ = lsp::Uri::from_str(URI).unwrap();
}
