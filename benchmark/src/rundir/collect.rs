//! Reading run directories back: every record validated against its directory's `run.json`,
//! directories named twice read once, directories of one method combined (shards, or shards
//! beside their merge) with each episode counted once, and completeness measured against the
//! episodes the run was meant to cover.

use super::Fingerprint;
use super::record::{self, Expected, RecordFile};
use crate::runner::{RUN_MANIFEST, RunError, RunManifest, read_run_manifest, record_path};
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One run directory, read and validated.
#[derive(Clone, Debug)]
pub struct RunDir {
    pub path: PathBuf,
    pub manifest: RunManifest,
    pub fingerprint: Fingerprint,
    /// Scored records by `map_id/instruction_id`, in the order `run.json` lists them.
    pub records: Vec<(String, Value)>,
    /// Expected episodes with no record yet (or a `pending` one).
    pub missing: Vec<String>,
}

impl RunDir {
    pub fn is_complete(&self) -> bool {
        self.missing.is_empty()
    }
}

/// The fingerprint of a run directory's manifest, or the refusal for a directory written before
/// run directories had fingerprints.
pub fn manifest_fingerprint(dir: &Path, m: &RunManifest) -> Result<Fingerprint, RunError> {
    m.fingerprint.clone().ok_or_else(|| {
        RunError::Invalid(format!(
            "{}: has no suite and method fingerprint (written by an older m2rc); its records cannot be checked, run the method again into a new directory",
            dir.join(RUN_MANIFEST).display()
        ))
    })
}

/// Reads a run directory and validates every record in it. A record that fails validation, or
/// a record file of an episode the run does not cover, is an error naming the file.
pub fn read_run_dir(dir: &Path) -> Result<RunDir, RunError> {
    let manifest = read_run_manifest(dir)?;
    let fingerprint = manifest_fingerprint(dir, &manifest)?;
    let expected: BTreeMap<&str, usize> = manifest
        .expected
        .iter()
        .enumerate()
        .map(|(i, k)| (k.as_str(), i))
        .collect();
    // Every record file present must be one this run covers.
    for file in record_files(dir)? {
        let key = key_of(dir, &file);
        if !expected.contains_key(key.as_str()) {
            return Err(RunError::Invalid(format!(
                "{}: not an episode of this run ({} covers {} episodes of suite `{}`); remove it or report the directory it belongs to",
                file.display(),
                dir.display(),
                manifest.expected.len(),
                manifest.suite_name
            )));
        }
    }
    let mut records = Vec::new();
    let mut missing = Vec::new();
    for key in &manifest.expected {
        let (map_dir, instruction_id) = split_key(key)?;
        let path = record_path(dir, map_dir, instruction_id);
        let e = Expected {
            method: &manifest.method,
            fingerprint: &fingerprint,
            map_dir,
            instruction_id,
        };
        match record::check_file(&path, &e) {
            RecordFile::Missing => missing.push(key.clone()),
            RecordFile::Valid(v) if record::is_pending(&v) => missing.push(key.clone()),
            RecordFile::Valid(v) => records.push((key.clone(), v)),
            RecordFile::Invalid(why) => {
                return Err(RunError::Invalid(format!(
                    "{}: invalid record: {why}; resume the run (`bench run` with the same arguments) to recompute it",
                    path.display()
                )));
            }
        }
    }
    Ok(RunDir {
        path: dir.to_path_buf(),
        manifest,
        fingerprint,
        records,
        missing,
    })
}

/// `map_id/instruction_id` of a record file under `dir`.
fn key_of(dir: &Path, file: &Path) -> String {
    let rel = file.strip_prefix(dir).unwrap_or(file);
    let map = rel
        .parent()
        .map(|p| p.to_string_lossy().to_string())
        .unwrap_or_default();
    let stem = rel
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_default();
    format!("{map}/{stem}")
}

pub fn split_key(key: &str) -> Result<(&str, &str), RunError> {
    key.split_once('/').ok_or_else(|| {
        RunError::Invalid(format!(
            "run.json: episode key `{key}` is not map_id/instruction_id"
        ))
    })
}

/// The record files (`<dir>/<map>/instruction_*.json`) of a run directory, sorted.
pub fn record_files(dir: &Path) -> Result<Vec<PathBuf>, RunError> {
    let io = |p: &Path, e| RunError::Io {
        path: p.display().to_string(),
        source: e,
    };
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(|e| io(dir, e))?.flatten() {
        let p = entry.path();
        if entry.file_type().is_ok_and(|t| t.is_dir()) {
            for f in std::fs::read_dir(&p).map_err(|e| io(&p, e))?.flatten() {
                let name = f.file_name().to_string_lossy().to_string();
                if name.starts_with("instruction_") && name.ends_with(".json") {
                    files.push(f.path());
                }
            }
        }
    }
    files.sort();
    Ok(files)
}

/// The runs of one method, combined from one or more directories.
#[derive(Clone, Debug)]
pub struct MethodRecords {
    pub method: String,
    pub fingerprint: Fingerprint,
    pub split: String,
    /// Episodes of the split: what a complete run of the method holds.
    pub expected: usize,
    /// Scored records, each episode once, in key order.
    pub records: BTreeMap<String, Value>,
    pub dirs: Vec<PathBuf>,
}

impl MethodRecords {
    pub fn present(&self) -> usize {
        self.records.len()
    }
    pub fn is_complete(&self) -> bool {
        self.present() >= self.expected
    }
}

/// Reads run directories, keeping the order methods first appear in. A directory named twice
/// (by any path) is read once; directories of the same method must come from the same suite,
/// split and method configuration; an episode in two of them must have the same record.
pub fn collect(dirs: &[impl AsRef<Path>]) -> Result<Vec<MethodRecords>, RunError> {
    let mut seen: Vec<PathBuf> = Vec::new();
    let mut out: Vec<MethodRecords> = Vec::new();
    for d in dirs {
        let d = d.as_ref();
        let canonical = std::fs::canonicalize(d).map_err(|e| RunError::Io {
            path: d.display().to_string(),
            source: e,
        })?;
        if seen.contains(&canonical) {
            continue;
        }
        seen.push(canonical);
        let run = read_run_dir(d)?;
        let m = &run.manifest;
        let slot = match out.iter_mut().position(|r| r.method == m.method) {
            Some(i) => {
                let r = &out[i];
                if let Some(diff) = r.fingerprint.differences(&run.fingerprint) {
                    return Err(RunError::Invalid(format!(
                        "{} and {} are both runs of `{}` but {diff}; report them separately",
                        r.dirs[0].display(),
                        d.display(),
                        m.method
                    )));
                }
                if r.split != m.split {
                    return Err(RunError::Invalid(format!(
                        "{} covers split {} but {} covers {}",
                        r.dirs[0].display(),
                        r.split,
                        d.display(),
                        m.split
                    )));
                }
                i
            }
            None => {
                out.push(MethodRecords {
                    method: m.method.clone(),
                    fingerprint: run.fingerprint.clone(),
                    split: m.split.clone(),
                    expected: m.split_episodes,
                    records: BTreeMap::new(),
                    dirs: Vec::new(),
                });
                out.len() - 1
            }
        };
        let target = &mut out[slot];
        target.dirs.push(d.to_path_buf());
        for (key, value) in run.records {
            match target.records.get(&key) {
                Some(old) if old.get(record::DIGEST_KEY) == value.get(record::DIGEST_KEY) => {}
                Some(_) => {
                    return Err(RunError::Invalid(format!(
                        "{key}: {} holds a record that differs from the one already read from {}",
                        d.display(),
                        target.dirs[0].display()
                    )));
                }
                None => {
                    target.records.insert(key, value);
                }
            }
        }
    }
    Ok(out)
}
