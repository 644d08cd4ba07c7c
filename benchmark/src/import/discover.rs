//! Finding the prediction files of a folder and the episode each one predicts.
//!
//! A file names its episode by its content (`map_id` and `instruction_id`, as the reference's
//! method output does) or by its place (`<map_id>/instruction_<id:06>.json`, the reference's and
//! m2rc's record layout, where `<map_id>` may be the last folder of a longer path such as
//! `procthor/001_valunseen`); when both name one, they must agree. Only `*.json` files are
//! predictions; hidden files and folders are skipped, symbolic links to folders are not
//! followed.

use serde_json::Value;
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// A prediction file larger than this is refused unread: at most 100 000 points, pretty-printed,
/// take well under 8 MiB.
pub const MAX_PREDICTION_BYTES: u64 = 16 << 20;
/// Folders deeper than this under the predictions folder are not searched.
pub const MAX_DEPTH: usize = 6;
/// More files than this in the predictions folder is refused (a wrong folder, such as `/`).
pub const MAX_FILES: usize = 1_000_000;

/// One prediction file, read.
#[derive(Debug)]
pub struct PredictionFile {
    /// Path relative to the predictions folder, with `/` separators (what records name).
    pub rel: String,
    /// The parsed JSON, or why it is not JSON (then the file is malformed).
    pub content: Result<Value, String>,
    /// The episode named by the file's place, as (map folder, instruction id).
    pub by_path: Option<(String, String)>,
    /// The episode named by the file's content: (map id, instruction id), each when present.
    pub by_content: (Option<String>, Option<String>),
}

impl PredictionFile {
    /// The episode the file predicts, as (map folder, instruction id): content first, place
    /// for what the content does not say. `Err` when the two disagree or nothing names it.
    pub fn episode(&self) -> Result<(String, String), String> {
        let (c_map, c_id) = &self.by_content;
        let c_map = c_map.as_deref().map(map_tail);
        let (p_map, p_id) = match &self.by_path {
            Some((m, i)) => (Some(m.as_str()), Some(i.as_str())),
            None => (None, None),
        };
        if let (Some(c), Some(p)) = (c_map, p_map)
            && c != p
        {
            return Err(format!(
                "its map_id names map `{c}` but it is stored under `{p}/`; move it or fix the field"
            ));
        }
        if let (Some(c), Some(p)) = (c_id.as_deref(), p_id)
            && c != p
        {
            return Err(format!(
                "its instruction_id is `{c}` but it is named `{p}.json`; rename it or fix the field"
            ));
        }
        match (c_map.or(p_map), c_id.as_deref().or(p_id)) {
            (Some(m), Some(i)) => Ok((m.to_string(), i.to_string())),
            _ => Err(
                "cannot tell which episode it predicts: store it as <map_id>/instruction_<id:06>.json, or give `map_id` and `instruction_id` in it"
                    .into(),
            ),
        }
    }
}

/// The last `/`-separated part of a map id (`procthor/001_valunseen` -> `001_valunseen`).
pub fn map_tail(id: &str) -> &str {
    id.rsplit('/').next().unwrap_or(id)
}

/// What a predictions folder holds.
#[derive(Debug, Default)]
pub struct Found {
    /// `*.json` files, sorted by relative path.
    pub files: Vec<PredictionFile>,
    /// Other files (not `*.json`, or hidden), which are not predictions.
    pub ignored: usize,
    /// SHA-256 over every prediction file's relative path and bytes, in path order: the
    /// imported method's fingerprint, so a changed prediction cannot be mixed into a run.
    pub sha256: String,
}

/// Reads every prediction file under `dir`.
pub fn discover(dir: &Path) -> Result<Found, String> {
    let meta = std::fs::metadata(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    if !meta.is_dir() {
        return Err(format!(
            "{}: not a folder (--predictions takes the folder of prediction files)",
            dir.display()
        ));
    }
    let mut paths = Vec::new();
    let mut ignored = 0;
    walk(dir, dir, 0, &mut paths, &mut ignored)?;
    paths.sort();
    let mut hasher = Sha256::new();
    let mut files = Vec::with_capacity(paths.len());
    for (rel, path) in paths {
        let content = read_json(&path);
        let bytes_for_hash = match &content {
            Ok((_, bytes)) => bytes.as_slice(),
            Err(_) => &[],
        };
        for part in [rel.as_bytes(), bytes_for_hash] {
            hasher.update((part.len() as u64).to_le_bytes());
            hasher.update(part);
        }
        let content = content.map(|(v, _)| v);
        let by_content = match &content {
            Ok(Value::Object(o)) => (
                o.get("map_id").and_then(Value::as_str).map(str::to_string),
                o.get("instruction_id")
                    .and_then(Value::as_str)
                    .map(str::to_string),
            ),
            _ => (None, None),
        };
        files.push(PredictionFile {
            by_path: episode_by_path(&rel),
            rel,
            content,
            by_content,
        });
    }
    Ok(Found {
        files,
        ignored,
        sha256: hasher
            .finalize()
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect(),
    })
}

/// The file's JSON and bytes, or why it cannot be used.
fn read_json(path: &Path) -> Result<(Value, Vec<u8>), String> {
    let len = std::fs::metadata(path)
        .map_err(|e| format!("cannot read it: {e}"))?
        .len();
    if len > MAX_PREDICTION_BYTES {
        return Err(format!(
            "it is {len} bytes, more than the limit of {MAX_PREDICTION_BYTES}"
        ));
    }
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read it: {e}"))?;
    let value = serde_json::from_slice(&bytes).map_err(|e| format!("not valid JSON: {e}"))?;
    Ok((value, bytes))
}

/// `(map folder, instruction id)` from `.../<map>/instruction_<id>.json`.
fn episode_by_path(rel: &str) -> Option<(String, String)> {
    let mut parts = rel.rsplit('/');
    let stem = parts.next()?.strip_suffix(".json")?;
    let map = parts.next()?;
    stem.starts_with("instruction_")
        .then(|| (map.to_string(), stem.to_string()))
}

fn walk(
    root: &Path,
    dir: &Path,
    depth: usize,
    out: &mut Vec<(String, PathBuf)>,
    ignored: &mut usize,
) -> Result<(), String> {
    let entries = std::fs::read_dir(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for entry in entries {
        let entry = entry.map_err(|e| format!("{}: {e}", dir.display()))?;
        let name = entry.file_name().to_string_lossy().to_string();
        let path = entry.path();
        // `file_type` does not follow links: a linked folder is not entered (no cycles), a
        // linked file is read.
        let kind = entry
            .file_type()
            .map_err(|e| format!("{}: {e}", path.display()))?;
        let is_file = kind.is_file() || (kind.is_symlink() && path.is_file());
        if name.starts_with('.') {
            *ignored += 1;
        } else if kind.is_dir() {
            if depth < MAX_DEPTH {
                walk(root, &path, depth + 1, out, ignored)?;
            }
        } else if is_file && name.ends_with(".json") {
            let rel = path
                .strip_prefix(root)
                .unwrap_or(&path)
                .components()
                .map(|c| c.as_os_str().to_string_lossy().to_string())
                .collect::<Vec<_>>()
                .join("/");
            out.push((rel, path));
        } else {
            *ignored += 1;
        }
        if out.len() + *ignored > MAX_FILES {
            return Err(format!(
                "{}: more than {MAX_FILES} files; is this the predictions folder?",
                root.display()
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(rel: &str, content: Value) -> PredictionFile {
        let by_content = match &content {
            Value::Object(o) => (
                o.get("map_id").and_then(Value::as_str).map(str::to_string),
                o.get("instruction_id")
                    .and_then(Value::as_str)
                    .map(str::to_string),
            ),
            _ => (None, None),
        };
        PredictionFile {
            rel: rel.into(),
            by_path: episode_by_path(rel),
            content: Ok(content),
            by_content,
        }
    }

    #[test]
    fn episodes_are_named_by_content_or_by_place_and_both_must_agree() {
        use serde_json::json;
        let ep = |m: &str, i: &str| Ok((m.to_string(), i.to_string()));
        let f = file("001_a/instruction_000002.json", json!([[0, 0]]));
        assert_eq!(f.episode(), ep("001_a", "instruction_000002"));
        let f = file(
            "procthor/001_a/instruction_000002.json",
            json!({"trajectory": []}),
        );
        assert_eq!(f.episode(), ep("001_a", "instruction_000002"));
        let f = file(
            "anything.json",
            json!({"map_id": "procthor/001_a", "instruction_id": "instruction_000003"}),
        );
        assert_eq!(f.episode(), ep("001_a", "instruction_000003"));
        let f = file(
            "002_b/instruction_000003.json",
            json!({"map_id": "procthor/001_a", "instruction_id": "instruction_000003"}),
        );
        assert!(f.episode().unwrap_err().contains("stored under `002_b/`"));
        let f = file(
            "001_a/instruction_000004.json",
            json!({"instruction_id": "instruction_000003"}),
        );
        assert!(
            f.episode()
                .unwrap_err()
                .contains("named `instruction_000004.json`")
        );
        let f = file("route.json", json!([[0, 0]]));
        assert!(
            f.episode()
                .unwrap_err()
                .contains("cannot tell which episode")
        );
    }
}
