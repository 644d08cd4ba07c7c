//! Batch exchange in the OpenAI Batch formats, for hosted batch APIs and for machines without
//! network access.
//!
//! * Export (`--llm-batch-out FILE`): every request the run needs that the cache cannot answer,
//!   one JSON object a line, `{"custom_id", "method": "POST", "url": "/v1/chat/completions",
//!   "body"}`, sorted by `custom_id`. The `custom_id` is the request's name and a digest of the
//!   request itself, `<map>/<instruction>/round<k>#<16 hex digits>` (the first digits of its
//!   cache key: model, messages, sampling parameters), so a reply names the exact request it
//!   answers. The file is rewritten atomically as requests are added, so it is whole even if the
//!   run is killed.
//! * Import (`--llm-batch-in FILE`, repeatable): lines of the Batch output format,
//!   `{"custom_id", "response": {"status_code", "body"}, "error"}`, go into the cache under the key
//!   the request was exported with; the next run continues each episode where it stopped. A reply
//!   is imported only when its digest is that of the request this run exported under its name:
//!   a reply made for another model, another prompt configuration or another episode is refused,
//!   never scored.

use crate::cache::{ResponseCache, sha256_hex, write_atomic};
use crate::wire::{check_reply_size, parse_completion};
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Hex digits of the request digest in an exported `custom_id`.
pub const DIGEST_HEX: usize = 16;

/// The longest line of a batch output file read, in bytes: a reply body within the client's
/// default response limit, with room for the envelope. A longer line is reported and skipped
/// without being held in memory.
pub const MAX_LINE_BYTES: usize = 8 * 1024 * 1024;

/// The `custom_id` a request is exported under: its name and the first digits of its key.
pub fn export_id(custom_id: &str, key: &str) -> String {
    format!("{custom_id}#{}", &key[..DIGEST_HEX.min(key.len())])
}

/// An exported `custom_id` split into the request's name and its digest.
pub fn split_export_id(id: &str) -> Option<(&str, &str)> {
    let (name, digest) = id.rsplit_once('#')?;
    (digest.len() == DIGEST_HEX
        && digest
            .bytes()
            .all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f')))
    .then_some((name, digest))
}

/// The batch input file being written by a run.
#[derive(Debug)]
pub struct BatchOut {
    path: PathBuf,
    lines: Mutex<BTreeMap<String, String>>,
}

impl BatchOut {
    pub fn new(path: impl Into<PathBuf>) -> Self {
        BatchOut {
            path: path.into(),
            lines: Mutex::new(BTreeMap::new()),
        }
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Adds a request under its exported `custom_id` (see [`export_id`]).
    pub fn add(&self, custom_id: &str, body: &Value) -> std::io::Result<()> {
        self.add_to(custom_id, "/v1/chat/completions", body)
    }

    /// Adds a request to another endpoint of the Batch API (`/v1/embeddings`).
    pub fn add_to(&self, custom_id: &str, url: &str, body: &Value) -> std::io::Result<()> {
        let line = json!({
            "custom_id": custom_id,
            "method": "POST",
            "url": url,
            "body": body,
        });
        let mut lines = self.lines.lock().unwrap_or_else(|p| p.into_inner());
        lines.insert(custom_id.to_string(), line.to_string());
        write_lines(&self.path, &lines)
    }

    /// Writes the file (also when no request was needed, so a stale file never lingers).
    pub fn finish(&self) -> std::io::Result<usize> {
        let lines = self.lines.lock().unwrap_or_else(|p| p.into_inner());
        write_lines(&self.path, &lines)?;
        Ok(lines.len())
    }

    pub fn len(&self) -> usize {
        self.lines.lock().map(|l| l.len()).unwrap_or(0)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

fn write_lines(path: &Path, lines: &BTreeMap<String, String>) -> std::io::Result<()> {
    let mut text = String::new();
    for l in lines.values() {
        text.push_str(l);
        text.push('\n');
    }
    write_atomic(path, text.as_bytes())
}

/// What an import did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct BatchImport {
    pub imported: usize,
    /// Lines whose `custom_id` this cache never exported (another run's, or one without a
    /// request digest).
    pub unknown: Vec<String>,
    /// Lines whose reply is already in the cache (imported before, or a repeated line with the
    /// same reply).
    pub already: Vec<String>,
    /// Lines that were refused (`file:line: why`): an error or a non-200 status, not JSON, not
    /// UTF-8, not a chat completion, too long, a reply to another request than the one exported
    /// under that name, or a `custom_id` given twice with different replies. Those requests stay
    /// pending and are exported again by the next run.
    pub failed: Vec<String>,
    /// Replies that were imported but whose body names another model than the one asked.
    pub warnings: Vec<String>,
}

/// One reply line that passed the checks of the first pass.
struct Candidate {
    /// `file:line` of its first occurrence.
    at: String,
    /// Digest of its `response` (to tell repeated lines from conflicting ones).
    digest: String,
    /// Every place it occurs with a different reply.
    conflicts: Vec<String>,
    /// Every place it occurs again with the same reply.
    repeats: Vec<String>,
}

/// Reads Batch output files into the cache. A bad line is reported, never fatal; a file that
/// cannot be read at all (missing, compressed) is an error naming it.
pub fn import_batch_files(files: &[PathBuf], cache: &ResponseCache) -> Result<BatchImport, String> {
    let mut out = BatchImport::default();
    // First pass: every line checked, each `custom_id` with its replies, so that a request
    // answered twice differently is refused as a whole rather than first-come.
    let mut seen: BTreeMap<String, Candidate> = BTreeMap::new();
    for file in files {
        let unreadable = for_each_line(file, |at, v| {
            let Some((id, _, _)) = check_line(at, v, cache, &mut out) else {
                return;
            };
            let digest = sha256_hex(v["response"]["body"].to_string().as_bytes());
            match seen.get_mut(&id) {
                None => {
                    seen.insert(
                        id,
                        Candidate {
                            at: at.to_string(),
                            digest,
                            conflicts: Vec::new(),
                            repeats: Vec::new(),
                        },
                    );
                }
                Some(c) if c.digest == digest => c.repeats.push(at.to_string()),
                Some(c) => c.conflicts.push(at.to_string()),
            }
        })?;
        out.failed.extend(unreadable);
    }
    for (id, c) in &seen {
        if !c.conflicts.is_empty() {
            out.failed.push(format!(
                "{}: `{id}` is answered again with a different reply at {}; none of them imported",
                c.at,
                c.conflicts.join(", ")
            ));
        }
        for r in &c.repeats {
            out.already
                .push(format!("{r}: `{id}` repeats the reply of {}", c.at));
        }
    }
    // Second pass: the first line of every unambiguous `custom_id` goes into the cache.
    for file in files {
        let mut quiet = BatchImport::default();
        let mut result = Ok(());
        for_each_line(file, |at, v| {
            if result.is_err() {
                return;
            }
            let Some((id, key, model)) = check_line(at, v, cache, &mut quiet) else {
                return;
            };
            let Some(c) = seen.get(&id) else { return };
            if c.at != at || !c.conflicts.is_empty() {
                return;
            }
            let body = &v["response"]["body"];
            if let (Some(asked), Some(got)) = (model, body.get("model").and_then(Value::as_str))
                && !got.starts_with(asked.as_str())
            {
                out.warnings.push(format!(
                    "{at}: `{id}` was asked of model `{asked}`, but the reply says `{got}`"
                ));
            }
            let (name, _) = split_export_id(&id).unwrap_or((&id, ""));
            result = cache
                .put(&key, name, body, 0.0)
                .map_err(|e| format!("{}: cannot write: {e}", cache.dir().display()));
            if result.is_ok() {
                cache.clear_pending(name);
                out.imported += 1;
            }
        })?;
        result?;
    }
    Ok(out)
}

/// Checks one parsed line: its `custom_id` names a request this cache exported and is waiting
/// for, its digest is that request's, and it carries a 200 chat completion of a usable size.
/// Returns the exported id, the cache key and the model asked; otherwise records why not.
fn check_line(
    at: &str,
    v: &Value,
    cache: &ResponseCache,
    out: &mut BatchImport,
) -> Option<(String, String, Option<String>)> {
    let Some(id) = v.get("custom_id").and_then(Value::as_str) else {
        out.failed.push(format!("{at}: no `custom_id`"));
        return None;
    };
    let Some((name, digest)) = split_export_id(id) else {
        out.unknown.push(format!(
            "{at}: `{id}` carries no request digest (`<name>#<16 hex digits>`), so it was not \
             exported by this version of m2rc"
        ));
        return None;
    };
    let Some((key, model)) = cache.pending(name) else {
        if cache.has_key_prefix(digest) {
            out.already
                .push(format!("{at}: `{id}` is already in the cache"));
        } else {
            out.unknown.push(format!(
                "{at}: `{id}`: no request of this name is waiting in {}",
                cache.dir().display()
            ));
        }
        return None;
    };
    if !key.starts_with(digest) {
        if cache.has_key_prefix(digest) {
            out.already
                .push(format!("{at}: `{id}` is already in the cache"));
        } else {
            out.failed.push(format!(
                "{at}: `{id}` answers another request than the one exported as `{name}` \
                 (another model, prompt configuration or episode); not imported"
            ));
        }
        return None;
    }
    if let Some(err) = v.get("error").filter(|e| !e.is_null()) {
        let err: String = err.to_string().chars().take(300).collect();
        out.failed.push(format!("{at}: `{id}` failed: {err}"));
        return None;
    }
    let status = v.pointer("/response/status_code").and_then(Value::as_u64);
    let Some(body) = v.pointer("/response/body").filter(|b| b.is_object()) else {
        out.failed.push(format!(
            "{at}: `{id}` has status {} and no body",
            status.map_or("none".to_string(), |s| s.to_string())
        ));
        return None;
    };
    if status != Some(200) {
        out.failed.push(format!(
            "{at}: `{id}` has status {}",
            status.map_or("none".to_string(), |s| s.to_string())
        ));
        return None;
    }
    // An embeddings reply (`data`, no `choices`) is checked as one; anything else as a chat
    // completion.
    if body.get("data").is_some() && body.get("choices").is_none() {
        if let Err(e) = crate::wire::parse_embeddings(body) {
            out.failed.push(format!(
                "{at}: `{id}`: the body is not a list of embeddings: {e}"
            ));
            return None;
        }
        return Some((id.to_string(), key, model));
    }
    let reply = match parse_completion(body, 0.0) {
        Ok(r) => r,
        Err(e) => {
            out.failed.push(format!(
                "{at}: `{id}`: the body is not a chat completion: {e}"
            ));
            return None;
        }
    };
    if let Err(e) = check_reply_size(&reply) {
        out.failed.push(format!("{at}: `{id}`: {e}"));
        return None;
    }
    Some((id.to_string(), key, model))
}

/// Calls `f` with `file:line` and the JSON of every non-blank line of `file`; returns the lines
/// that are too long, not UTF-8 or not JSON, by line number.
fn for_each_line(file: &Path, mut f: impl FnMut(&str, &Value)) -> Result<Vec<String>, String> {
    let mut failed = Vec::new();
    let name = file.display();
    let opened = std::fs::File::open(file).map_err(|e| format!("--llm-batch-in {name}: {e}"))?;
    let mut reader = BufReader::new(opened);
    let head = reader
        .fill_buf()
        .map_err(|e| format!("--llm-batch-in {name}: {e}"))?;
    if head.starts_with(&[0x1f, 0x8b]) {
        return Err(format!(
            "--llm-batch-in {name}: the file is gzip-compressed; decompress it first \
             (`gunzip -k {name}`) and import the .jsonl"
        ));
    }
    let mut line = Vec::new();
    for n in 1.. {
        line.clear();
        let at = format!("{name}:{n}");
        let (read, whole) = read_line_capped(&mut reader, &mut line, MAX_LINE_BYTES)
            .map_err(|e| format!("--llm-batch-in {at}: {e}"))?;
        if read == 0 {
            break;
        }
        if !whole {
            failed.push(format!("{at}: longer than {MAX_LINE_BYTES} bytes; skipped"));
            continue;
        }
        let Ok(text) = std::str::from_utf8(&line) else {
            failed.push(format!("{at}: not UTF-8 text"));
            continue;
        };
        if text.trim().is_empty() {
            continue;
        }
        match serde_json::from_str::<Value>(text) {
            Ok(v) => f(&at, &v),
            Err(e) => failed.push(format!("{at}: not JSON: {e}")),
        }
    }
    Ok(failed)
}

/// Reads one line (without its newline) into `buf`, keeping at most `cap` bytes; the rest of a
/// longer line is read and dropped. Returns the bytes consumed (0 at the end) and whether the
/// line fit.
fn read_line_capped(
    reader: &mut impl BufRead,
    buf: &mut Vec<u8>,
    cap: usize,
) -> std::io::Result<(usize, bool)> {
    let mut consumed = 0;
    let mut whole = true;
    loop {
        let chunk = reader.fill_buf()?;
        if chunk.is_empty() {
            return Ok((consumed, whole));
        }
        let (part, done) = match chunk.iter().position(|b| *b == b'\n') {
            Some(i) => (&chunk[..i], Some(i + 1)),
            None => (chunk, None),
        };
        if whole && buf.len() + part.len() <= cap {
            buf.extend_from_slice(part);
        } else {
            whole = false;
            buf.clear();
        }
        let used = done.unwrap_or(part.len());
        reader.consume(used);
        consumed += used;
        if done.is_some() {
            return Ok((consumed, whole));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn export_ids_carry_the_digest() {
        let id = export_id("demo/e1/round0", &"ab".repeat(32));
        assert_eq!(id, format!("demo/e1/round0#{}", "ab".repeat(8)));
        assert_eq!(
            split_export_id(&id),
            Some(("demo/e1/round0", "abababababababab"))
        );
        assert_eq!(split_export_id("demo/e1/round0"), None);
        assert_eq!(split_export_id("demo/e1/round0#XYZ"), None);
    }

    #[test]
    fn long_lines_are_skipped_without_being_held() {
        let text = format!("ab\n{}\ncd", "x".repeat(50));
        let mut r = BufReader::with_capacity(8, text.as_bytes());
        let mut buf = Vec::new();
        let mut got = Vec::new();
        loop {
            buf.clear();
            let (n, whole) = read_line_capped(&mut r, &mut buf, 10).unwrap();
            if n == 0 {
                break;
            }
            got.push((String::from_utf8(buf.clone()).unwrap(), whole));
        }
        assert_eq!(
            got,
            vec![
                ("ab".to_string(), true),
                (String::new(), false),
                ("cd".to_string(), true)
            ]
        );
    }
}
