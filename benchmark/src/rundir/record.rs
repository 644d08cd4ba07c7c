//! Prediction records as the run directory's evidence: sealed with the run's fingerprint and a
//! digest of their own content when written, validated whenever they are read.
//!
//! Validation is strict about what the report relies on (whose episode, which method, which
//! inputs, the scored metrics, the route and its validity) and tolerant of everything else: keys a method adds
//! (a model's reply, repair rounds, a `pending` outcome of a batch job) pass as they are, as long
//! as the digest, computed over the whole record, still matches.

use super::Fingerprint;
use crate::metrics::evaluate::EpisodeMetrics;
use crate::route::validity::RouteValidity;
use serde_json::{Value, json};
use std::path::Path;

/// Key of the run fingerprint inside a record: `{"suite": hex, "method": hex}`.
pub const FINGERPRINT_KEY: &str = "run_fingerprint";
/// Key of the record's own SHA-256 digest (over the record without this key).
pub const DIGEST_KEY: &str = "record_digest";
/// The `status` of a record whose method has not answered yet (for example a batch job); it is
/// valid but not scored, so a report counts it as missing.
pub const PENDING: &str = "pending";
/// Key of the route's validity inside a scored record.
pub const VALIDITY_KEY: &str = "route_validity";

/// What a record at a given place of a given run must say about itself.
#[derive(Clone, Copy, Debug)]
pub struct Expected<'a> {
    pub method: &'a str,
    pub fingerprint: &'a Fingerprint,
    /// The map folder the record lives in (`<out>/<map_dir>/...`).
    pub map_dir: &'a str,
    /// `instruction_<id:06>`, the file's stem.
    pub instruction_id: &'a str,
}

/// Adds the run fingerprint and the digest to a freshly computed record.
pub fn seal(record: &mut Value, fingerprint: &Fingerprint) {
    if let Some(obj) = record.as_object_mut() {
        obj.shift_remove(DIGEST_KEY);
        obj.insert(
            FINGERPRINT_KEY.into(),
            json!({"suite": fingerprint.suite, "method": fingerprint.method}),
        );
    }
    let digest = digest(record);
    if let Some(obj) = record.as_object_mut() {
        obj.insert(DIGEST_KEY.into(), Value::String(digest));
    }
}

/// SHA-256 over the record's compact JSON without [`DIGEST_KEY`] (key order kept), so an edit of
/// any value (an HCS, a trajectory point) no longer matches, while re-indenting the file does.
pub fn digest(record: &Value) -> String {
    let mut copy = record.clone();
    if let Some(obj) = copy.as_object_mut() {
        obj.shift_remove(DIGEST_KEY);
    }
    super::sha256_hex(&serde_json::to_vec(&copy).unwrap_or_default())
}

/// Whether a (valid) record is a `pending` placeholder rather than a scored prediction.
pub fn is_pending(record: &Value) -> bool {
    record.get("status").and_then(Value::as_str) == Some(PENDING)
}

/// Checks a parsed record against what its place in the run says it must be. The error says
/// what is wrong in words.
pub fn validate(record: &Value, e: &Expected<'_>) -> Result<(), String> {
    let obj = record
        .as_object()
        .ok_or("not a JSON object (a prediction record is an object)")?;
    let text = |k: &str| obj.get(k).and_then(Value::as_str);
    match text("method") {
        Some(m) if m == e.method => {}
        Some(m) => {
            return Err(format!(
                "it is a record of method `{m}`, but the run is `{}`",
                e.method
            ));
        }
        None => return Err("field `method` is missing or not a string".into()),
    }
    match text("instruction_id") {
        Some(id) if id == e.instruction_id => {}
        Some(id) => {
            return Err(format!(
                "it is the record of {id}, but it is stored as {}",
                e.instruction_id
            ));
        }
        None => return Err("field `instruction_id` is missing or not a string".into()),
    }
    match text("map_dir") {
        Some(d) if d == e.map_dir => {}
        Some(d) => {
            return Err(format!(
                "it is a record of map {d}, but it is stored under {}",
                e.map_dir
            ));
        }
        None => return Err("field `map_dir` is missing or not a string".into()),
    }
    match text("map_id") {
        Some(id) if id == e.map_dir || id.rsplit('/').next() == Some(e.map_dir) => {}
        Some(id) => return Err(format!("its episode is on map `{id}`, not {}", e.map_dir)),
        None => return Err("field `map_id` is missing or not a string".into()),
    }
    match obj.get(FINGERPRINT_KEY) {
        Some(fp) => {
            if fp.get("suite").and_then(Value::as_str) != Some(e.fingerprint.suite.as_str()) {
                return Err(
                    "it was made from another suite (its suite fingerprint differs from run.json)"
                        .into(),
                );
            }
            if fp.get("method").and_then(Value::as_str) != Some(e.fingerprint.method.as_str()) {
                return Err("it was made with another method configuration (its method fingerprint differs from run.json)".into());
            }
        }
        None => {
            return Err(format!(
                "field `{FINGERPRINT_KEY}` is missing (not written by this run)"
            ));
        }
    }
    if text("status").is_none() {
        return Err("field `status` is missing or not a string".into());
    }
    if is_pending(record) {
        return check_digest(record);
    }
    let traj = obj
        .get("trajectory")
        .and_then(Value::as_array)
        .ok_or("field `trajectory` is missing or not a list")?;
    if traj.is_empty() {
        return Err("field `trajectory` is empty".into());
    }
    for (i, p) in traj.iter().enumerate() {
        let ok = p
            .as_array()
            .is_some_and(|a| a.len() == 2 && a.iter().all(|x| x.as_u64().is_some()));
        if !ok {
            return Err(format!(
                "trajectory[{i}] is not a [row, col] pair of non-negative integers"
            ));
        }
    }
    let metrics: EpisodeMetrics = obj
        .get("metrics")
        .cloned()
        .ok_or_else(|| "field `metrics` is missing".to_string())
        .and_then(|m| serde_json::from_value(m).map_err(|err| format!("field `metrics`: {err}")))?;
    let summary_hcs = obj
        .get("metrics_summary")
        .and_then(|s| s.get("HCS"))
        .and_then(Value::as_f64)
        .ok_or("field `metrics_summary.HCS` is missing or not a number")?;
    if summary_hcs != metrics.hcs {
        return Err(format!(
            "metrics_summary.HCS {summary_hcs} disagrees with metrics.HCS {}",
            metrics.hcs
        ));
    }
    route_validity(record)?;
    check_digest(record)
}

/// The record's `route_validity` ([`crate::route::validity`]): what `bench report` counts and
/// refuses on. A record without it was written before routes were checked.
pub fn route_validity(record: &Value) -> Result<RouteValidity, String> {
    let v = record.get(VALIDITY_KEY).ok_or(
        "field `route_validity` is missing (written by an m2rc that did not check routes)",
    )?;
    serde_json::from_value(v.clone()).map_err(|err| format!("field `{VALIDITY_KEY}`: {err}"))
}

/// Checked last, so that a record broken in a way the schema sees is reported as such.
fn check_digest(record: &Value) -> Result<(), String> {
    match record.get(DIGEST_KEY).and_then(Value::as_str) {
        Some(d) if d == digest(record) => Ok(()),
        Some(_) => Err(
            "its content was changed after it was written (the record digest does not match)"
                .into(),
        ),
        None => Err(format!("field `{DIGEST_KEY}` is missing")),
    }
}

/// The state of the record file at `path`.
#[derive(Debug)]
pub enum RecordFile {
    Missing,
    Valid(Value),
    Invalid(String),
}

/// Reads and validates the record at `path`.
pub fn check_file(path: &Path, e: &Expected<'_>) -> RecordFile {
    let bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(err) if err.kind() == std::io::ErrorKind::NotFound => return RecordFile::Missing,
        Err(err) => return RecordFile::Invalid(format!("cannot read it: {err}")),
    };
    let value: Value = match serde_json::from_slice(&bytes) {
        Ok(v) => v,
        Err(err) => return RecordFile::Invalid(format!("not valid JSON (truncated?): {err}")),
    };
    match validate(&value, e) {
        Ok(()) => RecordFile::Valid(value),
        Err(why) => RecordFile::Invalid(why),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fp() -> Fingerprint {
        Fingerprint {
            suite: "s".repeat(64),
            method: "m".repeat(64),
            method_config: json!({"name": "x"}),
        }
    }

    #[test]
    fn a_sealed_pending_record_with_extra_keys_is_valid_and_an_edit_is_not() {
        let mut r = json!({"method": "x", "map_id": "procthor/001_a", "map_dir": "001_a",
            "instruction_id": "instruction_000001", "status": "pending", "llm": {"model": "m"}});
        let f = fp();
        seal(&mut r, &f);
        let e = Expected {
            method: "x",
            fingerprint: &f,
            map_dir: "001_a",
            instruction_id: "instruction_000001",
        };
        validate(&r, &e).unwrap();
        r["llm"]["model"] = json!("other");
        assert!(validate(&r, &e).unwrap_err().contains("changed"));
    }
}
