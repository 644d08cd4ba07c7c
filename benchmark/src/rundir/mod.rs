//! What makes a run directory trustworthy: it names exactly the inputs its records were made
//! from, only one process writes it at a time, and every record read back is checked against it.
//!
//! * [`Fingerprint`]: a hash over the suite (its manifest and every episode file) and over the
//!   method's configuration ([`crate::methods::Method::config`], any JSON a method chooses, so a
//!   method with a model, an endpoint or repair rounds extends it without touching this code).
//!   `run.json` keeps it; a run, resume, report or merge over another fingerprint is refused with
//!   a message that says which part differs.
//! * [`RunLock`]: an exclusive OS file lock on `<out>/run.lock` for as long as a run or merge
//!   writes the directory, so two runs started together cannot interleave records.
//! * [`record`]: every record carries the run's fingerprint and a digest of its own content, and
//!   is validated (schema, episode id, map id, method, fingerprint, digest) wherever it is read.
//! * [`collect`]: the records of one or more run directories, deduplicated and checked for
//!   completeness, for `bench report` and `bench merge`.

pub mod collect;
pub mod merge;
pub mod record;

use crate::runner::RunError;
use crate::suite::SuiteManifest;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use sha2::{Digest, Sha256};
use std::fs::File;
use std::path::Path;

/// Name of the lock file inside a run directory.
pub const LOCK_FILE: &str = "run.lock";

/// Hex SHA-256 of `bytes`.
pub fn sha256_hex(bytes: &[u8]) -> String {
    let digest = Sha256::digest(bytes);
    digest.iter().map(|b| format!("{b:02x}")).collect()
}

/// The inputs a run was made from.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Fingerprint {
    /// SHA-256 over `suite.json` and every episode file it lists, in manifest order.
    pub suite: String,
    /// SHA-256 over the canonical JSON of [`Fingerprint::method_config`].
    pub method: String,
    /// The method's configuration itself, kept so that a refusal can say what differs.
    pub method_config: Value,
}

impl Fingerprint {
    /// Hashes the suite in `dir` (whose manifest is `manifest`) and the method configuration.
    pub fn new(
        dir: &Path,
        manifest: &SuiteManifest,
        method_config: Value,
    ) -> Result<Self, RunError> {
        Ok(Fingerprint {
            suite: suite_fingerprint(dir, manifest)?,
            method: sha256_hex(&serde_json::to_vec(&method_config).unwrap_or_default()),
            method_config,
        })
    }

    /// What differs between `self` (found in a run directory) and `other` (this run), in words;
    /// `None` when they are the same.
    pub fn differences(&self, other: &Fingerprint) -> Option<String> {
        let mut parts = Vec::new();
        if self.suite != other.suite {
            parts.push(format!(
                "the suite differs (suite fingerprint {} there, {} here: the manifest or an episode file changed, or it is another suite)",
                short(&self.suite),
                short(&other.suite)
            ));
        }
        if self.method != other.method {
            parts.push(format!(
                "the method configuration differs ({} there, {} here)",
                self.method_config, other.method_config
            ));
        }
        (!parts.is_empty()).then(|| parts.join("; "))
    }
}

/// The first 12 hex digits, enough to tell fingerprints apart in a message.
pub fn short(hex: &str) -> &str {
    &hex[..hex.len().min(12)]
}

/// SHA-256 over the manifest bytes and, for every episode in manifest order, its file name and
/// bytes (length-prefixed, so no two suites hash alike by shifting bytes between files).
pub fn suite_fingerprint(dir: &Path, manifest: &SuiteManifest) -> Result<String, RunError> {
    let mut h = Sha256::new();
    let manifest_path = dir.join(crate::suite::MANIFEST);
    let bytes = std::fs::read(&manifest_path).map_err(|e| io(&manifest_path, e))?;
    feed(&mut h, b"suite.json");
    feed(&mut h, &bytes);
    for e in &manifest.episodes {
        let path = dir.join(&e.file);
        let bytes = std::fs::read(&path).map_err(|err| io(&path, err))?;
        feed(&mut h, e.file.as_bytes());
        feed(&mut h, &bytes);
    }
    Ok(h.finalize().iter().map(|b| format!("{b:02x}")).collect())
}

fn feed(h: &mut Sha256, bytes: &[u8]) {
    h.update((bytes.len() as u64).to_le_bytes());
    h.update(bytes);
}

fn io(path: &Path, source: std::io::Error) -> RunError {
    RunError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// An exclusive lock on a run directory, released when dropped (or when the process dies: the
/// OS drops the lock with the file descriptor, so a killed run never leaves a stale lock).
#[derive(Debug)]
pub struct RunLock {
    _file: File,
}

impl RunLock {
    /// Creates `dir` if needed and takes its lock, or says that another process holds it.
    pub fn acquire(dir: &Path) -> Result<RunLock, RunError> {
        std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
        let path = dir.join(LOCK_FILE);
        let file = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .map_err(|e| io(&path, e))?;
        match file.try_lock() {
            Ok(()) => Ok(RunLock { _file: file }),
            Err(std::fs::TryLockError::WouldBlock) => Err(RunError::Invalid(format!(
                "{} is being written by another m2rc process (it holds {}); wait for it to finish or use another --out",
                dir.display(),
                path.display()
            ))),
            Err(std::fs::TryLockError::Error(e)) => Err(io(&path, e)),
        }
    }
}

/// Whether `name` is a temporary file left by an interrupted atomic write (`.<name>.tmp<pid>...`).
pub fn is_temp_name(name: &str) -> bool {
    name.starts_with('.') && name.contains(".tmp")
}

/// Removes the temporary files an interrupted run left in `dir` and its map folders; returns
/// how many. Call only while holding the directory's [`RunLock`].
pub fn remove_leftover_temps(dir: &Path) -> Result<usize, RunError> {
    let mut removed = 0;
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(0);
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name().to_string_lossy().to_string();
        let Ok(kind) = entry.file_type() else {
            continue;
        };
        if kind.is_dir() {
            removed += remove_leftover_temps(&path)?;
        } else if kind.is_file() && is_temp_name(&name) {
            std::fs::remove_file(&path).map_err(|e| io(&path, e))?;
            removed += 1;
        }
    }
    Ok(removed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn differences_name_the_part_that_changed() {
        let a = Fingerprint {
            suite: "aa".repeat(32),
            method: sha256_hex(b"1"),
            method_config: json!({"name": "oracle"}),
        };
        assert_eq!(a.differences(&a), None);
        let mut b = a.clone();
        b.suite = "bb".repeat(32);
        let d = a.differences(&b).unwrap();
        assert!(d.contains("suite differs") && !d.contains("method"), "{d}");
        b.method = sha256_hex(b"2");
        b.method_config = json!({"name": "oracle", "planner": "global"});
        let d = a.differences(&b).unwrap();
        assert!(
            d.contains("suite differs") && d.contains("\"global\""),
            "{d}"
        );
    }

    #[test]
    fn a_second_lock_on_the_same_directory_is_refused() {
        let tmp = tempfile::tempdir().unwrap();
        let first = RunLock::acquire(tmp.path()).unwrap();
        let err = RunLock::acquire(tmp.path()).unwrap_err().to_string();
        assert!(err.contains("another m2rc process"), "{err}");
        drop(first);
        RunLock::acquire(tmp.path()).unwrap();
    }

    #[test]
    fn temp_names() {
        assert!(is_temp_name(".instruction_000001.json.tmp123.ThreadId(2)"));
        assert!(!is_temp_name("instruction_000001.json"));
        assert!(!is_temp_name("run.json"));
    }
}
