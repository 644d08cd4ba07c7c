//! The language server's stdio transport: `Content-Length` framing as `lsp_server`'s own, but
//! hardened against what a broken or hostile client sends.
//!
//! * A `Content-Length` above [`MAX_CONTENT_LENGTH`] is answered with an error and its body is
//!   skipped in small chunks, instead of allocating whatever the header asks for.
//! * A body that is not JSON gets a JSON-RPC parse error (-32700), and JSON that is not a
//!   JSON-RPC message an invalid-request error (-32600), and the server reads on.
//! * Reading stops after the `exit` notification, as the protocol ends there.
//! * A stream that cannot be framed any more (no `Content-Length`, a header that is not text, a
//!   message cut off by the end of the stream) gets a parse error, reading stops, and
//!   [`Transport::broken`] says why, so that the server exits non-zero saying so instead of
//!   looking like a clean end.

use lsp_server::{Connection, Message};
use serde_json::{Value, json};
use std::io::{BufRead, BufReader, Read, Write};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

/// The largest message body accepted, in bytes (a `.m2r` document is a few kilobytes).
pub const MAX_CONTENT_LENGTH: usize = 16 * 1024 * 1024;
/// The longest header line accepted, in bytes.
const MAX_HEADER_LINE: u64 = 8 * 1024;

/// The threads behind a [`stdio`] connection.
pub struct Transport {
    writer: JoinHandle<()>,
    broken: Arc<Mutex<Option<String>>>,
}

impl Transport {
    /// Why reading stopped before the client ended the stream or sent `exit`, if it did. Set
    /// before the reader lets go of the connection, so it is known once the server loop ends.
    pub fn broken(&self) -> Option<String> {
        self.broken
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .clone()
    }

    /// Waits until everything the server sent is written. The reader is not waited for: it may
    /// be blocked on a client that keeps its end open, and it dies with the process.
    pub fn join(self) {
        let _ = self.writer.join();
    }
}

/// A connection over standard input and output.
pub fn stdio() -> (Connection, Transport) {
    let (server, client) = Connection::memory();
    let out = Arc::new(Mutex::new(std::io::stdout()));
    let out_w = Arc::clone(&out);
    let rx = client.receiver;
    let writer = std::thread::spawn(move || {
        for msg in rx {
            let mut o = out_w.lock().unwrap_or_else(|p| p.into_inner());
            if msg.write(&mut *o).is_err() {
                break;
            }
        }
    });
    let tx = client.sender;
    let broken = Arc::new(Mutex::new(None));
    let broken_r = Arc::clone(&broken);
    std::thread::spawn(move || {
        let stop = |why: String| {
            *broken_r.lock().unwrap_or_else(|p| p.into_inner()) = Some(why);
        };
        let stdin = std::io::stdin();
        let mut input = BufReader::new(stdin.lock());
        let raw = |body: Value| {
            let mut o = out.lock().unwrap_or_else(|p| p.into_inner());
            let text = body.to_string();
            let _ = write!(o, "Content-Length: {}\r\n\r\n{text}", text.len());
            let _ = o.flush();
        };
        loop {
            match read_frame(&mut input) {
                Frame::End => break,
                Frame::Broken(why) => {
                    raw(error(Value::Null, -32700, &why));
                    stop(why);
                    break;
                }
                Frame::TooLarge(n) => {
                    raw(error(
                        Value::Null,
                        -32600,
                        &format!(
                            "message of {n} bytes is larger than the limit of {MAX_CONTENT_LENGTH} bytes; skipped"
                        ),
                    ));
                    let skipped = std::io::copy(&mut (&mut input).take(n), &mut std::io::sink());
                    if skipped.map_or(true, |k| k < n) {
                        stop(format!(
                            "the stream ended inside a message of {n} bytes (Content-Length)"
                        ));
                        break;
                    }
                }
                Frame::Body(bytes) => match parse(&bytes) {
                    Ok(msg) => {
                        let exit = matches!(&msg, Message::Notification(n) if n.method == "exit");
                        if tx.send(msg).is_err() || exit {
                            break;
                        }
                    }
                    Err(reply) => raw(reply),
                },
            }
        }
    });
    (server, Transport { writer, broken })
}

fn error(id: Value, code: i64, message: &str) -> Value {
    json!({"jsonrpc": "2.0", "id": id, "error": {"code": code, "message": message}})
}

/// A message, or the error response to send for a body that is not one.
fn parse(bytes: &[u8]) -> Result<Message, Value> {
    let value: Value = serde_json::from_slice(bytes)
        .map_err(|e| error(Value::Null, -32700, &format!("parse error: {e}")))?;
    let id = value.get("id").cloned().unwrap_or(Value::Null);
    serde_json::from_value(value).map_err(|e| {
        error(
            id,
            -32600,
            &format!("not a JSON-RPC request, response or notification: {e}"),
        )
    })
}

enum Frame {
    Body(Vec<u8>),
    TooLarge(u64),
    /// The stream cannot be framed any more (no length, a header that is not text).
    Broken(String),
    End,
}

fn read_frame(input: &mut impl BufRead) -> Frame {
    let mut length: Option<u64> = None;
    loop {
        let mut line = Vec::new();
        match input.take(MAX_HEADER_LINE).read_until(b'\n', &mut line) {
            Ok(0) => return Frame::End,
            Ok(_) => {}
            Err(_) => return Frame::End,
        }
        if !line.ends_with(b"\n") {
            return Frame::Broken("header line too long or cut off".into());
        }
        let Ok(text) = std::str::from_utf8(&line) else {
            return Frame::Broken("header is not UTF-8".into());
        };
        let text = text.trim_end_matches(['\r', '\n']);
        if text.is_empty() {
            break;
        }
        if let Some((name, value)) = text.split_once(':')
            && name.trim().eq_ignore_ascii_case("content-length")
        {
            match value.trim().parse::<u64>() {
                Ok(n) => length = Some(n),
                Err(_) => return Frame::Broken(format!("bad Content-Length `{}`", value.trim())),
            }
        }
    }
    let Some(n) = length else {
        return Frame::Broken("message without a Content-Length header".into());
    };
    if n > MAX_CONTENT_LENGTH as u64 {
        return Frame::TooLarge(n);
    }
    let mut body = Vec::with_capacity(n as usize);
    match input.take(n).read_to_end(&mut body) {
        Ok(k) if k as u64 == n => Frame::Body(body),
        Ok(k) => Frame::Broken(format!(
            "the stream ended inside a message: Content-Length {n}, {k} bytes followed"
        )),
        Err(e) => Frame::Broken(format!("cannot read a message body: {e}")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_bounded_and_bad_bodies_get_errors() {
        let mut input: &[u8] = b"Content-Length: 999999999999\r\n\r\n";
        assert!(matches!(
            read_frame(&mut input),
            Frame::TooLarge(999999999999)
        ));
        let mut input: &[u8] = b"Content-Length: 3\r\n\r\n{x}";
        let Frame::Body(b) = read_frame(&mut input) else {
            panic!("a body")
        };
        assert_eq!(parse(&b).unwrap_err()["error"]["code"], -32700);
        assert_eq!(
            parse(br#"{"method": 4}"#).unwrap_err()["error"]["code"],
            -32600
        );
        let mut input: &[u8] = b"Content-Type: x\r\n\r\n";
        assert!(matches!(read_frame(&mut input), Frame::Broken(_)));
        let mut input: &[u8] = b"Content-Length: 10\r\n\r\n{}";
        let Frame::Broken(why) = read_frame(&mut input) else {
            panic!("a cut-off body is a broken stream")
        };
        assert!(why.contains("Content-Length 10, 2 bytes"), "{why}");
        let mut input: &[u8] = b"";
        assert!(matches!(read_frame(&mut input), Frame::End));
    }
}
