//! Checking off the message loop: the loop hands each new text to a checker thread and goes
//! straight back to answering hover and completion (which read the text, not the check result),
//! so a large document never blocks them. Texts that arrive while a check runs replace older
//! ones of the same document: only the newest version of each document is checked and published.

use super::{Notification, PublishDiagnostics, diagnostics_for};
use lsp_server::Message;
use lsp_types as lsp;
use lsp_types::notification::Notification as _;
use m2rc_stdlib::vocab::Vocabulary;
use std::collections::BTreeMap;
use std::sync::mpsc::Receiver;

/// Work for the checker thread.
pub(super) enum Job {
    /// Check this version of a document and publish its diagnostics.
    Check {
        uri: lsp::Uri,
        version: i32,
        text: String,
    },
    /// The document was closed: publish an empty list (after any pending check of it).
    Close(lsp::Uri),
}

impl Job {
    fn uri(&self) -> &lsp::Uri {
        match self {
            Job::Check { uri, .. } | Job::Close(uri) => uri,
        }
    }
}

/// Runs until `jobs` is closed, publishing through `out` (false once the client is gone).
pub(super) fn run(jobs: Receiver<Job>, out: impl Fn(Message) -> bool, vocab: &Vocabulary) {
    while let Ok(first) = jobs.recv() {
        // Coalesce: newest job per document, in order of first arrival.
        let mut pending: BTreeMap<String, (usize, Job)> = BTreeMap::new();
        let mut n = 0;
        let mut add = |pending: &mut BTreeMap<String, (usize, Job)>, j: Job| {
            let key = j.uri().as_str().to_string();
            let order = pending.get(&key).map_or(n, |(o, _)| *o);
            pending.insert(key, (order, j));
            n += 1;
        };
        add(&mut pending, first);
        while let Ok(j) = jobs.try_recv() {
            add(&mut pending, j);
        }
        let mut batch: Vec<(usize, Job)> = pending.into_values().collect();
        batch.sort_by_key(|(o, _)| *o);
        for (_, job) in batch {
            let params = match job {
                Job::Check { uri, version, text } => {
                    let diags = diagnostics_for(&text, &uri, vocab);
                    lsp::PublishDiagnosticsParams::new(uri, diags, Some(version))
                }
                Job::Close(uri) => lsp::PublishDiagnosticsParams::new(uri, Vec::new(), None),
            };
            let note = Notification::new(PublishDiagnostics::METHOD.to_string(), params);
            if !out(Message::Notification(note)) {
                return;
            }
        }
    }
}
