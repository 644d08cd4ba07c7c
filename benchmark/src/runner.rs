//! Runs a method over a suite and writes one prediction record per episode, in the reference's
//! prediction layout (`<out>/<map_id>/instruction_<id:06>.json`).
//!
//! * Parallel across episodes (rayon); maps are loaded once each, on first use.
//! * Every record is written atomically, so a crash or kill leaves only whole records; a resumed
//!   run skips episodes whose record exists and parses, and since methods and the evaluator are
//!   deterministic the final directory is the same as an uninterrupted run's.
//! * `--shard k/N` takes the episodes whose position in the suite manifest is `k-1` modulo `N`,
//!   so a job array (Slurm `$SLURM_ARRAY_TASK_ID`, a Kubernetes indexed Job) can split a suite
//!   with no coordination; [`merge`] combines the shard directories.

use crate::episode::Episode;
use crate::methods::{Method, PreparedMap, start_cell};
use crate::rundir::record::{self, Expected, RecordFile};
use crate::rundir::{Fingerprint, RunLock};
use crate::suite::{EpisodeEntry, SuiteManifest};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// Name of the run manifest inside a run directory.
pub const RUN_MANIFEST: &str = "run.json";

#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error("{path}: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
    #[error("{0}")]
    Invalid(String),
}

fn io_err(path: &Path, source: std::io::Error) -> RunError {
    RunError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// `k/N`: this process runs shard k (1-based) of N.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl std::str::FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Shard, String> {
        let (k, n) = s
            .split_once('/')
            .ok_or_else(|| format!("shard `{s}` is not of the form k/N, e.g. 2/8"))?;
        let index: usize = k
            .trim()
            .parse()
            .map_err(|_| format!("shard `{s}`: `{k}` is not a number"))?;
        let count: usize = n
            .trim()
            .parse()
            .map_err(|_| format!("shard `{s}`: `{n}` is not a number"))?;
        if count == 0 || index == 0 || index > count {
            return Err(format!("shard `{s}`: need 1 <= k <= N"));
        }
        Ok(Shard { index, count })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

#[derive(Clone, Debug)]
pub struct RunOptions {
    pub suite: PathBuf,
    pub out: PathBuf,
    pub shard: Option<Shard>,
    /// `eval` (the default, the paper's evaluation scenes), `dev` or `all`.
    pub split: String,
    /// Show a progress bar (the caller decides: TTY and not CI).
    pub progress: bool,
}

/// What a run directory holds; written before any record so that mixing methods is refused.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunManifest {
    pub method: String,
    pub suite_name: String,
    pub split: String,
    pub shard: Option<Shard>,
    /// Episodes this run (or shard) covers.
    pub episodes: usize,
    /// What the records were made from (suite and method configuration); `None` only in
    /// directories written by an older m2rc, which are refused.
    #[serde(default)]
    pub fingerprint: Option<Fingerprint>,
    /// The episodes this run (or shard) covers, as `map_id/instruction_id`, in manifest order.
    #[serde(default)]
    pub expected: Vec<String>,
    /// Episodes of the split in the whole suite: what a complete run of the method holds.
    #[serde(default)]
    pub split_episodes: usize,
    /// The method's configuration (model methods), so a resumed run cannot mix configurations.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub method_config: Option<Value>,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct RunSummary {
    pub episodes: usize,
    /// Records already present and valid (resumed).
    pub skipped: usize,
    pub written: usize,
    /// Episodes where the method returned no route (scored with the start cell only).
    pub method_failures: usize,
    /// Records found invalid on resume and recomputed, with the reason (for a warning).
    pub recomputed: Vec<String>,
    /// Temporary files of an interrupted run that were removed.
    pub temps_removed: usize,
    /// Episodes waiting for a model reply (batch exchange); no record yet, run again after
    /// importing the replies.
    pub pending: usize,
}

/// The episodes of a suite a run covers, in manifest order.
pub fn select_episodes<'a>(
    manifest: &'a SuiteManifest,
    split: &str,
    shard: Option<Shard>,
) -> Vec<&'a EpisodeEntry> {
    manifest
        .episodes
        .iter()
        .filter(|e| split == "all" || e.split == split)
        .enumerate()
        .filter(|(i, _)| shard.is_none_or(|s| i % s.count == s.index - 1))
        .map(|(_, e)| e)
        .collect()
}

pub fn record_path(out: &Path, map_id: &str, instruction_id: &str) -> PathBuf {
    out.join(map_id).join(format!("{instruction_id}.json"))
}

/// Whether a finished, well-formed record exists at `path`.
pub fn record_is_complete(path: &Path) -> bool {
    std::fs::read(path)
        .ok()
        .and_then(|b| serde_json::from_slice::<Value>(&b).ok())
        .is_some_and(|v| {
            v.get("metrics_summary").is_some_and(Value::is_object)
                && v.get("trajectory").is_some_and(Value::is_array)
        })
}

pub fn run(method: &dyn Method, opts: &RunOptions) -> Result<RunSummary, RunError> {
    if !["eval", "dev", "all"].contains(&opts.split.as_str()) {
        return Err(RunError::Invalid(format!(
            "split `{}` is not one of eval, dev, all",
            opts.split
        )));
    }
    let manifest =
        SuiteManifest::read(&opts.suite).map_err(|e| RunError::Invalid(e.to_string()))?;
    let episodes = select_episodes(&manifest, &opts.split, opts.shard);
    let fingerprint = Fingerprint::new(&opts.suite, &manifest, method.config())?;
    let run_manifest = RunManifest {
        method: method.name().to_string(),
        suite_name: manifest.config.name.clone(),
        split: opts.split.clone(),
        shard: opts.shard,
        episodes: episodes.len(),
        fingerprint: Some(fingerprint.clone()),
        expected: episodes
            .iter()
            .map(|e| format!("{}/{}", e.map_id, e.instruction_id))
            .collect(),
        split_episodes: select_episodes(&manifest, &opts.split, None).len(),
        method_config: Some(method.config()),
    };
    // Held until the run returns: no other process writes this directory meanwhile.
    let _lock = RunLock::acquire(&opts.out)?;
    let temps_removed = crate::rundir::remove_leftover_temps(&opts.out)?;
    check_or_write_run_manifest(&opts.out, &run_manifest)?;
    let recomputed: Mutex<Vec<String>> = Mutex::new(Vec::new());
    let ctx = RunCtx {
        fingerprint: &fingerprint,
        recomputed: &recomputed,
    };

    let mut maps: BTreeMap<&str, Mutex<MapSlot>> = manifest
        .scenes
        .iter()
        .map(|s| (s.map_id.as_str(), Mutex::new(MapSlot::default())))
        .collect();
    for e in &episodes {
        if let Some(slot) = maps.get_mut(e.map_id.as_str()) {
            slot.get_mut().expect("map slot").remaining += 1;
        }
    }
    let bar = progress_bar(episodes.len() as u64, opts.progress, method.name());
    let summary = Mutex::new(RunSummary {
        episodes: episodes.len(),
        temps_removed,
        ..RunSummary::default()
    });
    let first_error: Mutex<Option<RunError>> = Mutex::new(None);
    episodes.par_iter().for_each(|entry| {
        let result = run_one(method, opts, &ctx, &manifest, &maps, entry);
        let mut s = summary.lock().expect("summary lock");
        match result {
            Ok(Outcome::Skipped) => s.skipped += 1,
            Ok(Outcome::Written { method_failed }) => {
                s.written += 1;
                s.method_failures += method_failed as usize;
            }
            Ok(Outcome::Pending) => s.pending += 1,
            Err(e) => {
                let mut slot = first_error.lock().expect("error lock");
                if slot.is_none() {
                    *slot = Some(e);
                }
            }
        }
        bar.inc(1);
    });
    bar.finish_and_clear();
    if let Some(e) = first_error.into_inner().expect("error lock") {
        return Err(e);
    }
    let mut summary = summary.into_inner().expect("summary lock");
    summary.recomputed = recomputed.into_inner().unwrap_or_else(|p| p.into_inner());
    summary.recomputed.sort();
    Ok(summary)
}

/// What every episode of one run shares.
struct RunCtx<'a> {
    fingerprint: &'a Fingerprint,
    recomputed: &'a Mutex<Vec<String>>,
}

enum Outcome {
    Skipped,
    Written { method_failed: bool },
    Pending,
}

/// Where an episode waiting for a model reply is marked (next to where its record will go).
pub fn pending_path(out: &Path, map_id: &str, instruction_id: &str) -> PathBuf {
    record_path(out, map_id, instruction_id).with_extension("pending")
}

/// A scene's prepared map, loaded by the first episode that needs it and dropped after the last
/// one, so a run holds only the maps being worked on (a prepared map with its distance fields is
/// tens of megabytes).
#[derive(Default)]
struct MapSlot {
    map: Option<Result<Arc<PreparedMap>, String>>,
    /// Selected episodes of this map not finished yet.
    remaining: usize,
}

fn run_one(
    method: &dyn Method,
    opts: &RunOptions,
    ctx: &RunCtx<'_>,
    manifest: &SuiteManifest,
    maps: &BTreeMap<&str, Mutex<MapSlot>>,
    entry: &EpisodeEntry,
) -> Result<Outcome, RunError> {
    let slot = maps.get(entry.map_id.as_str()).ok_or_else(|| {
        RunError::Invalid(format!(
            "episode {} names unknown map {}",
            entry.file, entry.map_id
        ))
    })?;
    let result = run_on_map(method, opts, ctx, manifest, slot, entry);
    let mut slot = slot.lock().unwrap_or_else(|p| p.into_inner());
    slot.remaining = slot.remaining.saturating_sub(1);
    if slot.remaining == 0 {
        slot.map = None;
    }
    result
}

fn run_on_map(
    method: &dyn Method,
    opts: &RunOptions,
    ctx: &RunCtx<'_>,
    manifest: &SuiteManifest,
    slot: &Mutex<MapSlot>,
    entry: &EpisodeEntry,
) -> Result<Outcome, RunError> {
    let out_path = record_path(&opts.out, &entry.map_id, &entry.instruction_id);
    let expected = Expected {
        method: method.name(),
        fingerprint: ctx.fingerprint,
        map_dir: &entry.map_id,
        instruction_id: &entry.instruction_id,
    };
    match record::check_file(&out_path, &expected) {
        RecordFile::Valid(_) => return Ok(Outcome::Skipped),
        RecordFile::Missing => {}
        RecordFile::Invalid(why) => {
            let mut r = ctx.recomputed.lock().unwrap_or_else(|p| p.into_inner());
            r.push(format!("{}: {why}", out_path.display()));
        }
    }
    let map = {
        let mut slot = slot.lock().unwrap_or_else(|p| p.into_inner());
        slot.map
            .get_or_insert_with(|| load_suite_map(manifest, &opts.suite, &entry.map_id))
            .clone()
    }
    .map_err(RunError::Invalid)?;
    let ep_path = opts.suite.join(&entry.file);
    let mut episode = Episode::read(&ep_path).map_err(|e| RunError::Invalid(e.to_string()))?;
    // Records name the episode by its place in the suite, never by the path the suite was
    // given as, so the same run gives the same bytes from any working directory.
    episode
        .check(Some(map.map.n()))
        .map_err(|e| RunError::Invalid(e.to_string()))?;
    episode.set_source_path(Some(PathBuf::from(&entry.file)));
    let mut record = predict_and_score(method, &map, &episode, &entry.map_id);
    let status = record
        .get("status")
        .and_then(Value::as_str)
        .map(str::to_string);
    let method_failed = status.as_deref() != Some("ok");
    if status.as_deref() != Some("pending") {
        record::seal(&mut record, ctx.fingerprint);
    }
    let status = status.as_deref();
    let bytes = serde_json::to_vec(&record).expect("record serializes");
    let marker = pending_path(&opts.out, &entry.map_id, &entry.instruction_id);
    if status == Some("pending") {
        write_atomic(&marker, &bytes).map_err(|e| io_err(&marker, e))?;
        return Ok(Outcome::Pending);
    }
    write_atomic(&out_path, &bytes).map_err(|e| io_err(&out_path, e))?;
    let _ = std::fs::remove_file(&marker);
    Ok(Outcome::Written { method_failed })
}

fn load_suite_map(
    manifest: &SuiteManifest,
    suite: &Path,
    map_id: &str,
) -> Result<Arc<PreparedMap>, String> {
    let path = manifest
        .map_path(suite, map_id)
        .ok_or_else(|| format!("suite has no map {map_id}"))?;
    let name = path.display().to_string();
    let loaded = crate::map_cache::load_map_file(
        crate::map_cache::dir_for_runs(),
        &path,
        |bytes| m2rc_stdlib::map::read_map_document_json(bytes, &name).map_err(|e| e.to_string()),
        |e| format!("{name}: {e}"),
    )?;
    Ok(Arc::new(PreparedMap::with_obstacle_sq(
        loaded.doc.map,
        loaded.obstacle_sq,
    )))
}

/// Runs the method on one episode and scores its route: the full prediction record.
pub fn predict_and_score(
    method: &dyn Method,
    prepared: &PreparedMap,
    episode: &Episode,
    map_dir: &str,
) -> Value {
    let (map, eval) = (&prepared.map, &prepared.eval);
    let mut extra = serde_json::Map::new();
    let (trajectory, status, error, program, notes) = match method.predict(prepared, episode) {
        Ok(mut p) if p.status.is_some() => {
            extra = std::mem::take(&mut p.extra);
            let route = if p.trajectory.is_empty() {
                fallback_route(map, episode)
            } else {
                p.trajectory
            };
            (
                route,
                p.status.unwrap_or_default(),
                None,
                p.program,
                p.notes,
            )
        }
        Ok(mut p) if !p.trajectory.is_empty() => {
            extra = std::mem::take(&mut p.extra);
            (p.trajectory, "ok".to_string(), None, p.program, p.notes)
        }
        Ok(mut p) => {
            extra = std::mem::take(&mut p.extra);
            (
                fallback_route(map, episode),
                "empty_route".to_string(),
                None,
                p.program,
                p.notes,
            )
        }
        Err(e) => (
            fallback_route(map, episode),
            "method_error".to_string(),
            Some(e.0),
            None,
            vec![],
        ),
    };
    let traj: Vec<[i64; 2]> = trajectory
        .iter()
        .map(|c| [c.row as i64, c.col as i64])
        .collect();
    let scored = crate::report::score::score(&traj, episode, eval);
    let generation = episode.m2rc_generation.as_ref();
    let meta = |k: &str| {
        generation
            .and_then(|g| g.extra.get(k))
            .cloned()
            .unwrap_or(Value::Null)
    };
    let mut record = json!({
        "method": method.name(),
        "map_id": episode.map_id,
        "map_dir": map_dir,
        "instruction_id": episode.instruction_id(),
        "difficulty_level": episode.difficulty_level,
        "status": status,
        "error": error,
        "notes": notes,
        "program": program,
        "episode_factors": {
            "max_depth": meta("max_depth"),
            "max_candidates": meta("max_candidates"),
            "hard_constraints": episode.hard_constraints.len().saturating_sub(1),
        },
        "metrics": scored.metrics,
        "metrics_summary": scored.summary,
        "soft_episode_values": scored.soft_values,
        "route_validity": scored.validity,
        "trajectory": traj,
    });
    if let Value::Object(m) = &mut record {
        for (k, v) in extra {
            m.entry(k).or_insert(v);
        }
    }
    record
}

fn fallback_route(map: &SemanticMap, episode: &Episode) -> Vec<Cell> {
    start_cell(map, episode)
        .map(|c| vec![c])
        .unwrap_or_else(|_| vec![Cell::new(0, 0)])
}

fn check_or_write_run_manifest(out: &Path, m: &RunManifest) -> Result<(), RunError> {
    let path = out.join(RUN_MANIFEST);
    if let Ok(bytes) = std::fs::read(&path) {
        let old: RunManifest = serde_json::from_slice(&bytes).map_err(|e| {
            RunError::Invalid(format!("{}: not a run manifest: {e}", path.display()))
        })?;
        let old_fp = crate::rundir::collect::manifest_fingerprint(out, &old)?;
        if let Some(fp) = &m.fingerprint
            && let Some(diff) = old_fp.differences(fp)
        {
            return Err(RunError::Invalid(format!(
                "{} holds a run of method `{}` on suite `{}`, and {diff}; resume it with the same suite and method, or use another --out",
                out.display(),
                old.method,
                old.suite_name
            )));
        }
        if old.method != m.method
            || old.method_config != m.method_config
            || old.suite_name != m.suite_name
            || old.shard != m.shard
            || old.split != m.split
            || old.expected != m.expected
        {
            return Err(RunError::Invalid(format!(
                "{} already holds a run of method `{}` on suite `{}` (split {}, shard {:?}), or one with another method configuration; use another --out",
                out.display(),
                old.method,
                old.suite_name,
                old.split,
                old.shard.map(|s| s.to_string())
            )));
        }
        return Ok(());
    }
    let bytes = serde_json::to_vec_pretty(m).expect("manifest serializes");
    write_atomic(&path, &bytes).map_err(|e| io_err(&path, e))
}

pub fn read_run_manifest(dir: &Path) -> Result<RunManifest, RunError> {
    let path = dir.join(RUN_MANIFEST);
    let bytes = std::fs::read(&path).map_err(|e| io_err(&path, e))?;
    serde_json::from_slice(&bytes)
        .map_err(|e| RunError::Invalid(format!("{}: not a run manifest: {e}", path.display())))
}

/// Every prediction record of a run directory, sorted by (map directory, instruction id).
pub fn read_records(dir: &Path) -> Result<Vec<Value>, RunError> {
    let mut files: Vec<PathBuf> = Vec::new();
    let entries = std::fs::read_dir(dir).map_err(|e| io_err(dir, e))?;
    for entry in entries.flatten() {
        let p = entry.path();
        if p.is_dir() {
            for f in std::fs::read_dir(&p).map_err(|e| io_err(&p, e))?.flatten() {
                let name = f.file_name().to_string_lossy().to_string();
                if name.starts_with("instruction_") && name.ends_with(".json") {
                    files.push(f.path());
                }
            }
        }
    }
    files.sort();
    files
        .iter()
        .map(|f| {
            let bytes = std::fs::read(f).map_err(|e| io_err(f, e))?;
            serde_json::from_slice(&bytes).map_err(|e| {
                RunError::Invalid(format!("{}: not a prediction record: {e}", f.display()))
            })
        })
        .collect()
}

pub use crate::rundir::merge::{MergeSummary, merge};

fn progress_bar(len: u64, show: bool, label: &str) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(
        Some(len),
        if show {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        },
    );
    if let Ok(style) =
        ProgressStyle::with_template("{prefix:>10} [{bar:30}] {pos}/{len} episodes ({eta} left)")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_prefix(label.to_string());
    bar
}

/// Writes `bytes` to `path` atomically (temporary file in the same directory, fsync, rename), so
/// an interrupted run never leaves a half-written file that a resumed run would trust; see
/// [`crate::atomic`] for what happens with links and special files.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    crate::atomic::write_atomic(path, bytes)
}
