//! The on-disk response cache: one JSON file per request, named by the SHA-256 of the request body
//! (model, messages, sampling parameters) plus the backend's extra key, written atomically.
//! Cache-first: a hit makes no request. A file that does not parse, or belongs to another key, is
//! ignored (and overwritten by the next fetch), never fatal.
//!
//! Layout: `<dir>/<k[0..2]>/<k>.json` holding `{"key", "custom_id", "latency_ms", "response"}`,
//! where `response` is the chat-completion body exactly as the server (or a batch output file)
//! gave it; and `<dir>/batch-pending/<h>.json` mapping a batch `custom_id` to its key until the
//! reply is imported.

use serde_json::{Value, json};
use sha2::{Digest, Sha256};
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(Clone, Debug)]
pub struct ResponseCache {
    dir: PathBuf,
}

/// Hex SHA-256.
pub fn sha256_hex(bytes: &[u8]) -> String {
    let d = Sha256::digest(bytes);
    d.iter().map(|b| format!("{b:02x}")).collect()
}

/// The cache key of a request body and the backend's extra key material.
pub fn cache_key(body: &Value, extra: &str) -> String {
    let material = json!({"body": body, "extra": extra});
    sha256_hex(&serde_json::to_vec(&material).unwrap_or_default())
}

impl ResponseCache {
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        ResponseCache { dir: dir.into() }
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    fn entry_path(&self, key: &str) -> PathBuf {
        self.dir
            .join(&key[..2.min(key.len())])
            .join(format!("{key}.json"))
    }

    fn pending_path(&self, custom_id: &str) -> PathBuf {
        self.dir
            .join("batch-pending")
            .join(format!("{}.json", &sha256_hex(custom_id.as_bytes())[..32]))
    }

    /// The cached response body and the latency it was fetched with; `None` on a miss or a
    /// corrupt entry.
    pub fn get(&self, key: &str) -> Option<(Value, f64)> {
        let bytes = std::fs::read(self.entry_path(key)).ok()?;
        let v: Value = serde_json::from_slice(&bytes).ok()?;
        if v.get("key").and_then(Value::as_str) != Some(key) {
            return None;
        }
        let response = v.get("response")?.clone();
        if !response.is_object() {
            return None;
        }
        let latency = v.get("latency_ms").and_then(Value::as_f64).unwrap_or(0.0);
        Some((response, latency))
    }

    pub fn put(
        &self,
        key: &str,
        custom_id: &str,
        response: &Value,
        latency_ms: f64,
    ) -> std::io::Result<()> {
        let entry = json!({
            "key": key,
            "custom_id": custom_id,
            "latency_ms": latency_ms,
            "response": response,
        });
        let bytes = serde_json::to_vec_pretty(&entry).unwrap_or_default();
        write_atomic(&self.entry_path(key), &bytes)
    }

    /// Remembers which key a batch `custom_id` stands for, and the model it was asked of.
    pub fn put_pending(&self, custom_id: &str, key: &str, model: &str) -> std::io::Result<()> {
        let bytes =
            serde_json::to_vec(&json!({"custom_id": custom_id, "key": key, "model": model}))
                .unwrap_or_default();
        write_atomic(&self.pending_path(custom_id), &bytes)
    }

    /// The key a batch `custom_id` was exported with.
    pub fn pending_key(&self, custom_id: &str) -> Option<String> {
        self.pending(custom_id).map(|(k, _)| k)
    }

    /// The key and the model a batch `custom_id` was exported with.
    pub fn pending(&self, custom_id: &str) -> Option<(String, Option<String>)> {
        let bytes = std::fs::read(self.pending_path(custom_id)).ok()?;
        let v: Value = serde_json::from_slice(&bytes).ok()?;
        if v.get("custom_id").and_then(Value::as_str) != Some(custom_id) {
            return None;
        }
        let key = v.get("key").and_then(Value::as_str)?.to_string();
        let model = v.get("model").and_then(Value::as_str).map(str::to_string);
        Some((key, model))
    }

    /// Whether an entry whose key starts with `prefix` (at least two hex digits) is cached.
    pub fn has_key_prefix(&self, prefix: &str) -> bool {
        if prefix.len() < 2 || !prefix.bytes().all(|b| b.is_ascii_hexdigit()) {
            return false;
        }
        std::fs::read_dir(self.dir.join(&prefix[..2])).is_ok_and(|entries| {
            entries
                .flatten()
                .any(|e| e.file_name().to_string_lossy().starts_with(prefix))
        })
    }

    pub fn clear_pending(&self, custom_id: &str) {
        let _ = std::fs::remove_file(self.pending_path(custom_id));
    }
}

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    std::fs::create_dir_all(dir)?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default();
    let tmp = dir.join(format!(
        ".{name}.tmp{}.{:?}",
        std::process::id(),
        std::thread::current().id()
    ));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_misses_and_corrupt_entries() {
        let dir = tempfile::tempdir().unwrap();
        let c = ResponseCache::new(dir.path());
        let body = json!({"model": "m", "messages": []});
        let k = cache_key(&body, "");
        assert_ne!(k, cache_key(&body, "x"));
        assert!(c.get(&k).is_none());
        c.put(&k, "a/round0", &json!({"choices": []}), 12.0)
            .unwrap();
        assert_eq!(c.get(&k), Some((json!({"choices": []}), 12.0)));
        std::fs::write(c.entry_path(&k), b"{not json").unwrap();
        assert!(c.get(&k).is_none());
        c.put_pending("a/round1", &k, "m").unwrap();
        assert_eq!(c.pending("a/round1"), Some((k.clone(), Some("m".into()))));
        assert!(c.has_key_prefix(&k[..16]) && !c.has_key_prefix("zz"));
        assert_eq!(c.pending_key("a/round1"), Some(k.clone()));
        c.clear_pending("a/round1");
        assert_eq!(c.pending_key("a/round1"), None);
    }
}
