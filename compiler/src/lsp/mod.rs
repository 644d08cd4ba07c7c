//! The `.m2r` language server engine: diagnostics on open and change, hover, completion.
//!
//! The engine runs over any `lsp_server::Connection`, so the compiler itself does no I/O: the CLI
//! hands it stdio (`m2rc lsp`), tests hand it an in-memory pair. Positions are UTF-16 code units,
//! the protocol's default encoding, converted from the compiler's byte spans by
//! `diagnostic::LineIndex`, so non-ASCII text (names in comments, `→`, `—`) lands on the right
//! column.

mod complete;
mod hover;
mod locate;
mod worker;

use crate::diagnostic::{self, LineIndex};
use lsp_server::{
    Connection, ExtractError, Message, Notification, ProtocolError, Request, Response,
};
use lsp_types as lsp;
use lsp_types::notification::{
    DidChangeTextDocument, DidCloseTextDocument, DidOpenTextDocument, Notification as _,
    PublishDiagnostics,
};
use lsp_types::request::{Completion, HoverRequest, Request as _};
use m2rc_stdlib::vocab::Vocabulary;
use std::collections::BTreeMap;

/// What the server advertises: full-text sync, hover, and completion triggered by `.`.
pub fn capabilities() -> lsp::ServerCapabilities {
    lsp::ServerCapabilities {
        text_document_sync: Some(lsp::TextDocumentSyncCapability::Kind(
            lsp::TextDocumentSyncKind::FULL,
        )),
        hover_provider: Some(lsp::HoverProviderCapability::Simple(true)),
        completion_provider: Some(lsp::CompletionOptions {
            trigger_characters: Some(vec![".".to_string()]),
            ..Default::default()
        }),
        ..Default::default()
    }
}

/// Why the server stopped other than by a clean `shutdown` + `exit`.
#[derive(Debug)]
pub enum LspError {
    /// The client broke the protocol (for example, no `initialize` first).
    Protocol(ProtocolError),
    /// The client went away while the server was still sending.
    Disconnected,
    /// The client sent `exit` without `shutdown` first (the server then exits with status 1).
    ExitWithoutShutdown,
}

impl std::fmt::Display for LspError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LspError::Protocol(e) => write!(f, "protocol error: {e}"),
            LspError::Disconnected => f.write_str("the client disconnected"),
            LspError::ExitWithoutShutdown => f.write_str("`exit` without `shutdown`"),
        }
    }
}

impl std::error::Error for LspError {}

impl From<ProtocolError> for LspError {
    fn from(e: ProtocolError) -> Self {
        LspError::Protocol(e)
    }
}

/// The documents the client has open, by URI string.
struct Documents {
    texts: BTreeMap<String, (i32, String)>,
}

/// Runs the initialize handshake and then serves until `shutdown`/`exit`.
pub fn serve(connection: &Connection, vocab: &Vocabulary) -> Result<(), LspError> {
    let caps = serde_json::to_value(capabilities()).unwrap_or_default();
    let (id, _params) = connection.initialize_start()?;
    connection.initialize_finish(
        id,
        serde_json::json!({
            "capabilities": caps,
            "serverInfo": { "name": "m2rc", "version": env!("CARGO_PKG_VERSION") },
        }),
    )?;
    main_loop(connection, vocab)
}

/// The message loop after initialization. Requests the server does not know get a
/// `MethodNotFound` error, so a client never waits forever.
pub fn main_loop(connection: &Connection, vocab: &Vocabulary) -> Result<(), LspError> {
    let (jobs, queue) = std::sync::mpsc::channel();
    let out = connection.sender.clone();
    std::thread::scope(|s| {
        s.spawn(move || worker::run(queue, |m| out.send(m).is_ok(), vocab));
        // `jobs` is dropped when the loop returns, which ends the checker thread.
        serve_messages(connection, vocab, jobs)
    })
}

fn serve_messages(
    connection: &Connection,
    vocab: &Vocabulary,
    jobs: std::sync::mpsc::Sender<worker::Job>,
) -> Result<(), LspError> {
    let mut docs = Documents {
        texts: BTreeMap::new(),
    };
    for msg in &connection.receiver {
        match msg {
            Message::Request(req) => {
                if connection.handle_shutdown(&req)? {
                    return Ok(());
                }
                let response = handle_request(req, &docs, vocab);
                send(connection, Message::Response(response))?;
            }
            Message::Notification(note) if note.method == "exit" => {
                return Err(LspError::ExitWithoutShutdown);
            }
            Message::Notification(note) => {
                if let Some(job) = handle_notification(note, &mut docs)
                    && jobs.send(job).is_err()
                {
                    return Err(LspError::Disconnected);
                }
            }
            Message::Response(_) => {}
        }
    }
    Ok(())
}

fn send(connection: &Connection, msg: Message) -> Result<(), LspError> {
    connection
        .sender
        .send(msg)
        .map_err(|_| LspError::Disconnected)
}

fn handle_request(req: Request, docs: &Documents, vocab: &Vocabulary) -> Response {
    let id = req.id.clone();
    match req.method.as_str() {
        HoverRequest::METHOD => match cast::<HoverRequest>(req) {
            Ok(params) => {
                let pos = params.text_document_position_params;
                let hover = docs
                    .texts
                    .get(pos.text_document.uri.as_str())
                    .and_then(|(_, text)| hover::hover(text, pos.position, vocab));
                Response::new_ok(id, hover)
            }
            Err(msg) => Response::new_err(id, lsp_server::ErrorCode::InvalidParams as i32, msg),
        },
        Completion::METHOD => match cast::<Completion>(req) {
            Ok(params) => {
                let pos = params.text_document_position;
                let items = docs
                    .texts
                    .get(pos.text_document.uri.as_str())
                    .map(|(_, text)| complete::complete(text, pos.position, vocab))
                    .unwrap_or_default();
                Response::new_ok(id, lsp::CompletionResponse::Array(items))
            }
            Err(msg) => Response::new_err(id, lsp_server::ErrorCode::InvalidParams as i32, msg),
        },
        // The handshake is done once, in `serve`; a second one is a client error.
        "initialize" => Response::new_err(
            id,
            lsp_server::ErrorCode::InvalidRequest as i32,
            "the server is already initialized: `initialize` is sent once per session".into(),
        ),
        other => Response::new_err(
            id,
            lsp_server::ErrorCode::MethodNotFound as i32,
            format!("m2rc does not handle `{other}`"),
        ),
    }
}

fn cast<R: lsp_types::request::Request>(req: Request) -> Result<R::Params, String> {
    req.extract::<R::Params>(R::METHOD)
        .map(|(_, p)| p)
        .map_err(|e| match e {
            ExtractError::MethodMismatch(r) => format!("unexpected method {}", r.method),
            ExtractError::JsonError { method, error } => {
                format!("bad params for {method}: {error}")
            }
        })
}

/// Updates the open documents; the check to run, if any.
fn handle_notification(note: Notification, docs: &mut Documents) -> Option<worker::Job> {
    match note.method.as_str() {
        DidOpenTextDocument::METHOD => {
            let p: lsp::DidOpenTextDocumentParams = serde_json::from_value(note.params).ok()?;
            let doc = p.text_document;
            docs.texts.insert(
                doc.uri.as_str().to_string(),
                (doc.version, doc.text.clone()),
            );
            Some(worker::Job::Check {
                uri: doc.uri,
                version: doc.version,
                text: doc.text,
            })
        }
        DidChangeTextDocument::METHOD => {
            let p: lsp::DidChangeTextDocumentParams = serde_json::from_value(note.params).ok()?;
            // Full sync: the last change carries the whole text.
            let text = p.content_changes.into_iter().last()?.text;
            docs.texts.insert(
                p.text_document.uri.as_str().to_string(),
                (p.text_document.version, text.clone()),
            );
            Some(worker::Job::Check {
                uri: p.text_document.uri,
                version: p.text_document.version,
                text,
            })
        }
        DidCloseTextDocument::METHOD => {
            let p: lsp::DidCloseTextDocumentParams = serde_json::from_value(note.params).ok()?;
            docs.texts.remove(p.text_document.uri.as_str());
            Some(worker::Job::Close(p.text_document.uri))
        }
        _ => None,
    }
}

/// Checks one document and converts its diagnostics to LSP form.
pub fn diagnostics_for(text: &str, uri: &lsp::Uri, vocab: &Vocabulary) -> Vec<lsp::Diagnostic> {
    let result = crate::check::check(text, vocab);
    diagnostic::lsp::to_lsp(&result.diagnostics, text, uri)
}

/// The byte offset of an LSP position in `text`.
fn offset(text: &str, pos: lsp::Position) -> usize {
    LineIndex::new(text).offset_of_utf16(pos.line, pos.character)
}

#[cfg(test)]
mod tests;
