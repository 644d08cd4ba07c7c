//! Scoring glue between the runner and the evaluator: the evaluator's full metrics for the
//! record, the headline summary, and the episode's value per soft category (what C.7 averages,
//! computed by [`crate::metrics::aggregate`]) for readers of single records; and the route's
//! validity ([`crate::route::validity`]), which every scored record carries beside its scores.

use crate::episode::Episode;
use crate::metrics::aggregate::episode_soft_values;
use crate::metrics::evaluate::evaluate_or_worst_case;
use crate::metrics::map::EvalMap;
use crate::metrics::soft::EvalOptions;
use crate::route::validity::{RouteValidity, route_validity};
use serde_json::{Value, json};

pub struct Scored {
    pub metrics: Value,
    pub summary: Value,
    pub soft_values: Value,
    pub validity: RouteValidity,
}

pub fn score(trajectory: &[[i64; 2]], episode: &Episode, map: &EvalMap) -> Scored {
    let m = evaluate_or_worst_case(trajectory, episode, map, &EvalOptions::default());
    let summary =
        json!({"HCS": m.hcs, "SCS": m.scs, "PL": m.pl, "segment_wise_SPL": m.segment_wise_spl});
    let soft = episode_soft_values(&m);
    Scored {
        validity: route_validity(trajectory, map),
        metrics: serde_json::to_value(&m).expect("metrics serialize"),
        summary,
        soft_values: json!({
            "near": soft.near,
            "far": soft.far,
            "relative": soft.relative,
            "path_shape": soft.path_shape,
            "clearance": soft.clearance,
        }),
    }
}
