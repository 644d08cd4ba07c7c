//! `bench import`: scores the routes another program wrote, one file per episode, into a run
//! directory that `bench report` reads beside m2rc's own runs.
//!
//! The import is a [`Method`] whose answers are the prediction files, run by the same
//! [`runner`] as every other method: the same records (scored by the same evaluator, with the
//! route's validity), the same fingerprint (the suite, and a hash of every prediction file, so a
//! changed prediction is never mixed into an earlier import), the same lock, resume and
//! validation. What is particular to an import is refused before anything is written: a
//! prediction for a map or episode the suite does not have, two predictions for one episode, a
//! file that names no episode (and, by the command, an output folder that is, holds or lies in
//! an input: `cli::outputs`). An
//! episode without a prediction, or with one that cannot be read as a route, is scored on its
//! start cell alone and its record says why (`status` `missing_prediction` or
//! `malformed_prediction`, and `prediction.problem`), so it costs points instead of vanishing.

pub mod discover;

use crate::episode::Episode;
use crate::methods::{
    METHOD_NAMES, MODEL_METHOD_NAMES, Method, MethodError, Prediction, PreparedMap,
};
use crate::route::parse_route;
use crate::rundir::collect::read_run_dir;
use crate::rundir::record;
use crate::runner::{self, RunError, RunOptions, RunSummary};
use crate::suite::SuiteManifest;
use discover::{discover, map_tail};
use m2rc_stdlib::grid::Cell;
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// Status of the record of an episode with no prediction file.
pub const MISSING: &str = "missing_prediction";
/// Status of the record of an episode whose prediction file is not a usable route.
pub const MALFORMED: &str = "malformed_prediction";

#[derive(Clone, Debug)]
pub struct ImportOptions {
    pub suite: PathBuf,
    /// The folder of prediction files.
    pub predictions: PathBuf,
    /// The name the method's records and report row carry.
    pub method: String,
    pub out: PathBuf,
    /// `eval`, `dev` or `all`, as for `bench run`.
    pub split: String,
    pub progress: bool,
}

/// What an import did.
#[derive(Clone, Debug, Default)]
pub struct ImportSummary {
    pub run: RunSummary,
    /// Episodes scored from their prediction.
    pub ok: usize,
    /// Episodes without a prediction file (scored on the start cell), by key.
    pub missing: Vec<String>,
    /// Episodes whose prediction could not be used (scored on the start cell): key, file, why.
    pub malformed: Vec<(String, String)>,
    /// Episodes whose route is not drivable: key and the first problem.
    pub invalid_routes: Vec<(String, String)>,
    /// Files of the predictions folder that are not predictions (not `*.json`, or hidden).
    pub ignored_files: usize,
}

/// The most refusals listed in one message (the count says how many there are).
const MAX_LISTED: usize = 20;

pub fn import(opts: &ImportOptions) -> Result<ImportSummary, RunError> {
    check_method_name(&opts.method)?;
    let manifest =
        SuiteManifest::read(&opts.suite).map_err(|e| RunError::Invalid(e.to_string()))?;
    let found = discover(&opts.predictions).map_err(RunError::Invalid)?;
    let files = match_files(&manifest, &opts.split, found.files)?;
    let method = Imported {
        name: opts.method.clone(),
        sha256: found.sha256,
        count: files.len(),
        files,
    };
    let run = runner::run(
        &method,
        &RunOptions {
            suite: opts.suite.clone(),
            out: opts.out.clone(),
            shard: None,
            split: opts.split.clone(),
            progress: opts.progress,
        },
    )?;
    let mut summary = ImportSummary {
        run,
        ignored_files: found.ignored,
        ..ImportSummary::default()
    };
    let dir = read_run_dir(&opts.out)?;
    for (key, r) in &dir.records {
        let problem = || {
            r.pointer("/prediction/problem")
                .and_then(Value::as_str)
                .unwrap_or("")
                .to_string()
        };
        match r.get("status").and_then(Value::as_str) {
            Some(MISSING) => summary.missing.push(key.clone()),
            Some(MALFORMED) => summary.malformed.push((key.clone(), problem())),
            _ => summary.ok += 1,
        }
        if let Ok(v) = record::route_validity(r)
            && !v.valid
        {
            summary.invalid_routes.push((key.clone(), v.summary()));
        }
    }
    Ok(summary)
}

/// An imported method's name is a record field and a report row: a plain word, and none of
/// m2rc's own methods (whose rows it would be taken for).
fn check_method_name(name: &str) -> Result<(), RunError> {
    let plain = !name.is_empty()
        && name.len() <= 64
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_.+".contains(c));
    if !plain {
        return Err(RunError::Invalid(format!(
            "--method `{name}`: name the imported method with 1 to 64 letters, digits, `-`, `_`, `.` or `+`"
        )));
    }
    if METHOD_NAMES.contains(&name) || MODEL_METHOD_NAMES.contains(&name) {
        return Err(RunError::Invalid(format!(
            "--method `{name}` is one of m2rc's own methods; give the imported routes a name of their own"
        )));
    }
    Ok(())
}

/// By `map_id/instruction_id`: the file's path under the predictions folder, and its JSON or why
/// it is not JSON.
type Predictions = BTreeMap<String, (String, Result<Value, String>)>;

/// A prediction file's episode, checked against the suite: `Ok((key, file))` for each usable
/// one, or every refusal together.
fn match_files(
    manifest: &SuiteManifest,
    split: &str,
    files: Vec<discover::PredictionFile>,
) -> Result<Predictions, RunError> {
    let episodes: BTreeMap<String, &str> = manifest
        .episodes
        .iter()
        .map(|e| {
            (
                format!("{}/{}", e.map_id, e.instruction_id),
                e.split.as_str(),
            )
        })
        .collect();
    let maps: Vec<&str> = manifest.scenes.iter().map(|s| s.map_id.as_str()).collect();
    let mut refusals: Vec<String> = Vec::new();
    let mut by_key: BTreeMap<String, Vec<discover::PredictionFile>> = BTreeMap::new();
    for f in files {
        let (map, id) = match f.episode() {
            Ok(e) => e,
            Err(why) => {
                refusals.push(format!("{}: {why}", f.rel));
                continue;
            }
        };
        let key = format!("{map}/{id}");
        match episodes.get(&key) {
            _ if !maps.contains(&map.as_str()) => refusals.push(format!(
                "{}: predicts an episode of map `{map}`, which is not in suite `{}` (its maps: {})",
                f.rel,
                manifest.config.name,
                maps.join(", ")
            )),
            None => refusals.push(format!(
                "{}: map `{map}` of suite `{}` has no episode {id}",
                f.rel, manifest.config.name
            )),
            Some(s) if split != "all" && *s != split => refusals.push(format!(
                "{}: episode {key} is in the suite's `{s}` split, and the import covers `{split}` (--split {s} or --split all imports it)",
                f.rel
            )),
            Some(_) => by_key.entry(key).or_default().push(f),
        }
    }
    let mut out = BTreeMap::new();
    for (key, mut fs) in by_key {
        if fs.len() > 1 {
            let names: Vec<&str> = fs.iter().map(|f| f.rel.as_str()).collect();
            refusals.push(format!(
                "episode {key} has {} predictions ({}); keep one",
                fs.len(),
                names.join(", ")
            ));
            continue;
        }
        let f = fs.remove(0);
        out.insert(key, (f.rel, f.content));
    }
    if refusals.is_empty() {
        return Ok(out);
    }
    let n = refusals.len();
    let mut text = format!(
        "{n} prediction file(s) refused, nothing imported (prediction files are named <map_id>/instruction_<id:06>.json or hold `map_id` and `instruction_id`):"
    );
    for r in refusals.iter().take(MAX_LISTED) {
        text.push_str("\n  ");
        text.push_str(r);
    }
    if n > MAX_LISTED {
        text.push_str(&format!("\n  ... and {} more", n - MAX_LISTED));
    }
    Err(RunError::Invalid(text))
}

/// The prediction files as a method.
struct Imported {
    name: String,
    sha256: String,
    count: usize,
    files: Predictions,
}

impl Imported {
    fn unusable(status: &str, file: Option<&str>, problem: String) -> Prediction {
        let mut extra = serde_json::Map::new();
        extra.insert(
            "prediction".into(),
            json!({"file": file, "problem": problem}),
        );
        Prediction {
            trajectory: vec![],
            program: None,
            notes: vec![format!("{problem}; scored on the start cell alone")],
            status: Some(status.to_string()),
            extra,
        }
    }
}

impl Method for Imported {
    fn name(&self) -> &str {
        &self.name
    }

    fn config(&self) -> Value {
        json!({
            "method": self.name,
            "m2rc": env!("CARGO_PKG_VERSION"),
            "imported": {"prediction_files": self.count, "sha256": self.sha256},
        })
    }

    fn predict(&self, map: &PreparedMap, episode: &Episode) -> Result<Prediction, MethodError> {
        let key = format!(
            "{}/{}",
            map_tail(episode.map_id.as_deref().unwrap_or("")),
            episode.instruction_id().unwrap_or_default()
        );
        let Some((rel, content)) = self.files.get(&key) else {
            return Ok(Imported::unusable(
                MISSING,
                None,
                "no prediction file for this episode".into(),
            ));
        };
        let route = content
            .as_ref()
            .map_err(String::clone)
            .and_then(|v| parse_route(v, map.map.n(), rel).map_err(|e| e.to_string()));
        match route {
            Ok(points) if !points.is_empty() => {
                let mut extra = serde_json::Map::new();
                extra.insert("prediction".into(), json!({"file": rel}));
                Ok(Prediction {
                    // In the grid (checked by `parse_route`), so the casts are exact.
                    trajectory: points
                        .iter()
                        .map(|p| Cell::new(p[0] as u32, p[1] as u32))
                        .collect(),
                    extra,
                    ..Prediction::default()
                })
            }
            Ok(_) => Ok(Imported::unusable(
                MALFORMED,
                Some(rel),
                format!("{rel}: the trajectory is empty"),
            )),
            Err(why) if why.starts_with(rel.as_str()) => {
                Ok(Imported::unusable(MALFORMED, Some(rel), why))
            }
            Err(why) => Ok(Imported::unusable(
                MALFORMED,
                Some(rel),
                format!("{rel}: {why}"),
            )),
        }
    }
}
