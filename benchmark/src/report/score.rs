//! Scoring glue between the runner and the evaluator: the evaluator's full metrics for the
//! record, the headline summary, and the per-episode soft values that Table I aggregates (C.7:
//! for each soft type, the mean of the episode's finite raw values).

use crate::episode::Episode;
use crate::metrics::evaluate::evaluate_or_worst_case;
use crate::metrics::map::EvalMap;
use crate::metrics::soft::EvalOptions;
use serde_json::{Map, Value, json};

pub struct Scored {
    pub metrics: Value,
    pub summary: Value,
    pub soft_values: Value,
}

/// Which soft-type key of Table I a detail's `preference_type` belongs to.
fn soft_key(t: &str) -> Option<&'static str> {
    match t {
        "near_preference" => Some("near"),
        "far_preference" => Some("far"),
        "relative_preference" => Some("relative"),
        "path_shape_preference" | "geometric_path_preference" => Some("path_shape"),
        "clearance" => Some("clearance"),
        _ => None,
    }
}

pub fn score(trajectory: &[[i64; 2]], episode: &Episode, map: &EvalMap) -> Scored {
    let m = evaluate_or_worst_case(trajectory, episode, map, &EvalOptions::default());
    let summary =
        json!({"HCS": m.hcs, "SCS": m.scs, "PL": m.pl, "segment_wise_SPL": m.segment_wise_spl});
    let mut sums: [(f64, usize); 5] = Default::default();
    const KEYS: [&str; 5] = ["near", "far", "relative", "path_shape", "clearance"];
    for d in &m.details.soft_constraints {
        let key = d
            .preference_type
            .as_deref()
            .and_then(soft_key)
            .or_else(|| d.source_preference_type.as_deref().and_then(soft_key));
        if let (Some(key), Some(raw)) = (key, d.raw_value.filter(|x| x.is_finite())) {
            let k = KEYS.iter().position(|x| *x == key).expect("known key");
            sums[k].0 += raw;
            sums[k].1 += 1;
        }
    }
    let mut soft = Map::new();
    for (k, key) in KEYS.iter().enumerate() {
        let (s, n) = sums[k];
        soft.insert(
            key.to_string(),
            if n > 0 {
                json!(s / n as f64)
            } else {
                Value::Null
            },
        );
    }
    Scored {
        metrics: serde_json::to_value(&m).expect("metrics serialize"),
        summary,
        soft_values: Value::Object(soft),
    }
}
