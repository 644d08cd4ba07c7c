//! The language server's diagnostics round trip on an edit: a `didChange` notification in, a
//! `publishDiagnostics` notification out, over an in-memory connection (the transport the CLI
//! swaps for stdio). Target: under 10 ms for the longest real program.
//! Also the first diagnostics of a 5 MB document (`didOpen` to `publishDiagnostics`): under 2 s,
//! and a hover sent right after that `didOpen` is answered before the check finishes.

use criterion::{Criterion, criterion_group, criterion_main};
use lsp_server::{Connection, Message, Notification, Request, RequestId};
use m2rc_stdlib::vocab::Vocabulary;
use std::time::Duration;

const PROGRAM: &str = include_str!("scene108_018.m2r");

fn bench(c: &mut Criterion) {
    let (server, client) = Connection::memory();
    let thread = std::thread::spawn(move || {
        let vocab = Vocabulary::benchmark();
        m2rc_compiler::lsp::serve(&server, &vocab).expect("server");
    });
    let send = |m: Message| client.sender.send(m).expect("send");
    send(Message::Request(Request::new(
        RequestId::from(1),
        "initialize".into(),
        serde_json::json!({"capabilities": {}}),
    )));
    let _ = client
        .receiver
        .recv_timeout(Duration::from_secs(10))
        .expect("initialize response");
    send(Message::Notification(Notification::new(
        "initialized".into(),
        serde_json::json!({}),
    )));
    let uri = "file:///bench/route.m2r";
    send(Message::Notification(Notification::new(
        "textDocument/didOpen".into(),
        serde_json::json!({"textDocument": {"uri": uri, "languageId": "m2r", "version": 1, "text": PROGRAM}}),
    )));
    let _ = client
        .receiver
        .recv_timeout(Duration::from_secs(10))
        .expect("diagnostics");
    let mut version = 1;
    c.bench_function("lsp_did_change_to_publish_diagnostics", |b| {
        b.iter(|| {
            version += 1;
            // Alternate between a clean text and one with a typo, as an editor would send.
            let text = if version % 2 == 0 {
                PROGRAM.replace("dresser", "dreser")
            } else {
                PROGRAM.to_string()
            };
            send(Message::Notification(Notification::new(
                "textDocument/didChange".into(),
                serde_json::json!({"textDocument": {"uri": uri, "version": version},
                                   "contentChanges": [{"text": text}]}),
            )));
            loop {
                match client
                    .receiver
                    .recv_timeout(Duration::from_secs(10))
                    .expect("publish")
                {
                    Message::Notification(n) if n.method == "textDocument/publishDiagnostics" => {
                        break n;
                    }
                    _ => continue,
                }
            }
        })
    });
    send(Message::Request(Request::new(
        RequestId::from(2),
        "shutdown".into(),
        serde_json::Value::Null,
    )));
    let _ = client.receiver.recv_timeout(Duration::from_secs(10));
    send(Message::Notification(Notification::new(
        "exit".into(),
        serde_json::Value::Null,
    )));
    let _ = thread.join();
}

/// A generated document of at least `bytes` bytes: a chain of bindings and a route.
fn large_document(bytes: usize) -> String {
    let mut s = String::from("let p0 = objects(chair).nearest()\n");
    let mut i = 1;
    while s.len() < bytes {
        s.push_str(&format!(
            "let p{i} = objects(chair).nearest(to: p{})\n",
            i - 1
        ));
        i += 1;
    }
    s.push_str(&format!("route {{\n  go p{}\n}}\n", i - 1));
    s
}

fn bench_large(c: &mut Criterion) {
    let (server, client) = Connection::memory();
    let thread = std::thread::spawn(move || {
        let vocab = Vocabulary::benchmark();
        m2rc_compiler::lsp::serve(&server, &vocab).expect("server");
    });
    let send = |m: Message| client.sender.send(m).expect("send");
    send(Message::Request(Request::new(
        RequestId::from(1),
        "initialize".into(),
        serde_json::json!({"capabilities": {}}),
    )));
    let _ = client.receiver.recv_timeout(Duration::from_secs(10));
    send(Message::Notification(Notification::new(
        "initialized".into(),
        serde_json::json!({}),
    )));
    let text = large_document(5_000_000);
    let mut n = 0;
    let mut group = c.benchmark_group("lsp_large");
    group.sample_size(10);
    group.bench_function("lsp_first_diagnostics_5mb", |b| {
        b.iter(|| {
            n += 1;
            let uri = format!("file:///bench/large{n}.m2r");
            send(Message::Notification(Notification::new(
                "textDocument/didOpen".into(),
                serde_json::json!({"textDocument": {"uri": uri, "languageId": "m2r", "version": 1, "text": text}}),
            )));
            loop {
                match client.receiver.recv_timeout(Duration::from_secs(60)).expect("publish") {
                    Message::Notification(n) if n.method == "textDocument/publishDiagnostics" => break n,
                    _ => continue,
                }
            }
        })
    });
    group.finish();
    send(Message::Request(Request::new(
        RequestId::from(2),
        "shutdown".into(),
        serde_json::Value::Null,
    )));
    let _ = client.receiver.recv_timeout(Duration::from_secs(60));
    send(Message::Notification(Notification::new(
        "exit".into(),
        serde_json::Value::Null,
    )));
    let _ = thread.join();
}

criterion_group!(benches, bench, bench_large);
criterion_main!(benches);
