//! Batch exchange in the OpenAI Batch formats, for hosted batch APIs and for machines without
//! network access.
//!
//! * Export (`--llm-batch-out FILE`): every request the run needs that the cache cannot answer,
//!   one JSON object a line, `{"custom_id", "method": "POST", "url": "/v1/chat/completions",
//!   "body"}`, sorted by `custom_id` (`<map>/<instruction>/round<k>`). The file is rewritten
//!   atomically as requests are added, so it is whole even if the run is killed.
//! * Import (`--llm-batch-in FILE`, repeatable): lines of the Batch output format,
//!   `{"custom_id", "response": {"status_code", "body"}, "error"}`, go into the cache under the key
//!   the request was exported with; the next run continues each episode where it stopped.

use crate::cache::{ResponseCache, write_atomic};
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

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

    pub fn add(&self, custom_id: &str, body: &Value) -> std::io::Result<()> {
        let line = json!({
            "custom_id": custom_id,
            "method": "POST",
            "url": "/v1/chat/completions",
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
    /// Lines whose `custom_id` this cache never exported (another run's, or already imported).
    pub unknown: Vec<String>,
    /// Lines that carried an error or a non-200 status, or did not parse (`file:line: why`);
    /// those requests stay pending and are exported again by the next run.
    pub failed: Vec<String>,
}

/// Reads Batch output files into the cache. A bad line is reported, never fatal; an unreadable
/// file is an error naming it.
pub fn import_batch_files(files: &[PathBuf], cache: &ResponseCache) -> Result<BatchImport, String> {
    let mut out = BatchImport::default();
    for file in files {
        let text = std::fs::read_to_string(file)
            .map_err(|e| format!("--llm-batch-in {}: {e}", file.display()))?;
        for (i, line) in text.lines().enumerate() {
            if line.trim().is_empty() {
                continue;
            }
            let at = format!("{}:{}", file.display(), i + 1);
            let v: Value = match serde_json::from_str(line) {
                Ok(v) => v,
                Err(e) => {
                    out.failed.push(format!("{at}: not JSON: {e}"));
                    continue;
                }
            };
            let Some(id) = v.get("custom_id").and_then(Value::as_str) else {
                out.failed.push(format!("{at}: no `custom_id`"));
                continue;
            };
            let Some(key) = cache.pending_key(id) else {
                out.unknown.push(id.to_string());
                continue;
            };
            if let Some(err) = v.get("error").filter(|e| !e.is_null()) {
                out.failed.push(format!("{at}: `{id}` failed: {err}"));
                continue;
            }
            let status = v.pointer("/response/status_code").and_then(Value::as_u64);
            let body = v.pointer("/response/body").filter(|b| b.is_object());
            match (status, body) {
                (Some(200), Some(body)) => {
                    cache
                        .put(&key, id, body, 0.0)
                        .map_err(|e| format!("{}: cannot write: {e}", cache.dir().display()))?;
                    cache.clear_pending(id);
                    out.imported += 1;
                }
                (s, _) => out.failed.push(format!(
                    "{at}: `{id}` has status {} or no body",
                    s.map_or("none".to_string(), |s| s.to_string())
                )),
            }
        }
    }
    Ok(out)
}
