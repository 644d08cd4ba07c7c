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

/// The message loop hands checks to the checker thread and never waits for one: with no checker
/// draining the queue at all (a check that never finishes), hover and completion on the open
/// document are still answered, and the check waits in the queue for the newest text.
#[test]
fn hover_and_completion_are_answered_while_a_check_is_still_running() {
    let (server, client) = Connection::memory();
    let (jobs, queue) = std::sync::mpsc::channel();
    let thread = std::thread::spawn(move || {
        let vocab = Vocabulary::benchmark();
        let _ = serve_messages(&server, &vocab, jobs);
    });
    // A large document (about 1 MB) whose check would take a while even if it ran.
    let mut text = String::from("let c = objects(chair).nearest(start)\n");
    for i in 0..20_000 {
        text.push_str(&format!("let b{i} = rooms(bedroom).nearest()\n"));
    }
    text.push_str("route { go c }\n");
    let send = |m: Message| client.sender.send(m).unwrap();
    send(Message::Notification(Notification::new(
        "textDocument/didOpen".into(),
        serde_json::json!({ "textDocument": { "uri": URI, "languageId": "m2r", "version": 1, "text": text } }),
    )));
    send(Message::Request(Request::new(
        RequestId::from(1),
        "textDocument/hover".into(),
        serde_json::json!({ "textDocument": { "uri": URI }, "position": { "line": 0, "character": 10 } }),
    )));
    send(Message::Request(Request::new(
        RequestId::from(2),
        "textDocument/completion".into(),
        serde_json::json!({ "textDocument": { "uri": URI }, "position": { "line": 0, "character": 23 } }),
    )));
    let mut answered = Vec::new();
    while answered.len() < 2 {
        match client.receiver.recv_timeout(Duration::from_secs(60)) {
            Ok(Message::Response(r)) => answered.push(r),
            Ok(other) => panic!("only responses can come while no check runs: {other:?}"),
            Err(e) => panic!("no answer while the check is pending: {e}"),
        }
    }
    let hover = answered[0].response_result.clone().expect("hover result");
    assert!(
        hover["contents"]["value"]
            .as_str()
            .is_some_and(|s| s.contains("objects")),
        "{hover}"
    );
    let items = answered[1]
        .response_result
        .clone()
        .expect("completion result");
    assert!(
        items
            .as_array()
            .is_some_and(|a| a.iter().any(|i| i["label"] == "nearest")),
        "{items}"
    );
    // The check is queued, not lost: one job, for version 1 of the document.
    match queue.try_recv() {
        Ok(worker::Job::Check { version, .. }) => assert_eq!(version, 1),
        Ok(_) => panic!("expected a check job"),
        Err(e) => panic!("the check was not queued: {e}"),
    }
    send(Message::Request(Request::new(
        RequestId::from(3),
        "shutdown".into(),
        serde_json::Value::Null,
    )));
    send(Message::Notification(Notification::new(
        "exit".into(),
        serde_json::Value::Null,
    )));
    thread.join().unwrap();
}

/// A formula whose automaton is exponential (thirty unordered visits) gets E0810 on opening the
/// document: the engine neither hangs nor runs out of memory on it, and answers afterwards.
#[test]
fn exponential_ltl_formula_is_a_diagnostic_not_a_crash() {
    let mut c = Client::start();
    let mut text = String::new();
    for i in 0..30 {
        text.push_str(&format!("let a{i} = rooms(kitchen).only()\n"));
    }
    let formula: Vec<String> = (0..30).map(|i| format!("F a{i}")).collect();
    text.push_str(&format!("route ltl \"{}\"\n", formula.join(" & ")));
    let d = open(&c, &text);
    let diags = d["diagnostics"].as_array().unwrap();
    assert!(diags.iter().any(|x| x["code"] == "E0810"), "{d}");
    let hover = c.request(
        "textDocument/hover",
        serde_json::json!({ "textDocument": { "uri": URI }, "position": { "line": 0, "character": 11 } }),
    );
    assert!(hover["contents"]["value"].as_str().is_some(), "{hover}");
}
