//! How a baseline's episode ends when it has no route. Every failure is scored one way, for every
//! method: the start-only route (the runner's fallback, as for `grounding2route`); the method's own
//! status string (`translation_failed`, `grounding_failed`, `planner_limit`, ...) goes into the
//! record, so the reasons can be counted per method. The reference's per-runner quirks (zero-score
//! records without soft details, episodes left out) are not copied (`docs/baselines.md`).

use m2rc_benchmark::methods::Prediction;
use serde_json::{Map, Value, json};

/// A method's failure: its own status string and what went wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    pub status: String,
    pub message: String,
}

impl Failure {
    pub fn new(status: &str, message: impl Into<String>) -> Self {
        Failure {
            status: status.to_string(),
            message: message.into(),
        }
    }
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.status, self.message)
    }
}

/// The status of an episode waiting for a batch reply; the runner writes no record for it.
pub const PENDING: &str = "pending";

/// The prediction of an episode: its route (empty on failure, which the runner scores as the
/// start-only route), the status, and the method's block under `key` in the record.
pub fn prediction(
    key: &str,
    route: Result<Vec<m2rc_stdlib::grid::Cell>, Failure>,
    mut block: Map<String, Value>,
    notes: Vec<String>,
) -> Prediction {
    let (trajectory, status) = match route {
        Ok(r) if !r.is_empty() => (r, None),
        Ok(_) => (vec![], Some("empty_route".to_string())),
        Err(f) => {
            block.insert("status".into(), json!(f.status));
            block.insert("failure".into(), json!(f.message));
            (vec![], Some(f.status))
        }
    };
    block.entry("status").or_insert(json!("ok"));
    let mut extra = Map::new();
    extra.insert(key.to_string(), Value::Object(block));
    Prediction {
        trajectory,
        program: None,
        notes,
        status,
        extra,
    }
}
