//! One route against one episode: HCS, PL, segment-wise SPL and the soft raw values, plus the
//! worst-case record the benchmark uses when evaluation fails.

use super::context::{EvalError, HardContext};
use super::geometry::{Point, to_points};
use super::hcs::{HcsDetails, RecordRegion, compute_hcs};
use super::map::EvalMap;
use super::pl::path_length_cells;
use super::soft::{
    CLEARANCE, EvalOptions, FAR, GEOMETRIC_PATH, NEAR, PATH_SHAPE, RELATIVE, SoftDetail, SoftRegion,
};
use super::soft::{base_detail, compute_soft, near_or_far};
use super::spl::{SegmentDetail, compute_spl};
use crate::episode::Episode;
use serde::{Deserialize, Serialize};

/// What happened when evaluation failed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EvaluationFallback {
    pub policy: String,
    pub error: String,
}

/// Everything below the headline numbers, keyed like the reference's `details`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EvalDetails {
    pub hcs: HcsDetails,
    pub segments: Vec<SegmentDetail>,
    pub soft_constraints: Vec<SoftDetail>,
    pub scs_status: String,
    pub segment_reference_status: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub evaluation_fallback: Option<EvaluationFallback>,
    pub distance_unit: String,
    pub grid_resolution_m: f64,
}

/// One episode's metrics, keyed like the reference evaluator's output.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EpisodeMetrics {
    #[serde(rename = "HCS")]
    pub hcs: f64,
    /// Always `null`: soft constraints are reported as raw values, not scored.
    #[serde(rename = "SCS")]
    pub scs: Option<f64>,
    /// Path length, metres.
    #[serde(rename = "PL")]
    pub pl: f64,
    #[serde(rename = "segment_wise_SPL")]
    pub segment_wise_spl: f64,
    pub details: EvalDetails,
}

impl EpisodeMetrics {
    /// Whether these are the worst-case metrics of a failed evaluation.
    pub fn is_fallback(&self) -> bool {
        self.details.evaluation_fallback.is_some()
    }
}

/// Evaluates `trajectory` (integer `[row, col]` cells, already validated by
/// [`crate::route`]) on `episode` over `map`. Errors are what the reference raises on, e.g.
/// fewer than two must-pass regions or an invalid region; see [`evaluate_or_worst_case`].
pub fn evaluate(
    trajectory: &[[i64; 2]],
    episode: &Episode,
    map: &EvalMap,
    opts: &EvalOptions,
) -> Result<EpisodeMetrics, EvalError> {
    let points = to_points(trajectory);
    let ctx = HardContext::new(&episode.hard_constraints);
    let hcs = compute_hcs(&ctx, &points)?;
    let (spl, segments) = compute_spl(&ctx, trajectory, &points, map)?;
    let soft = compute_soft(&ctx, episode, &points, map, opts)?;
    let res = map.resolution();
    Ok(EpisodeMetrics {
        hcs: hcs.score,
        scs: None,
        pl: path_length_cells(&points) * res,
        segment_wise_spl: spl,
        details: EvalDetails {
            hcs,
            segments,
            soft_constraints: soft,
            scs_status: "pending_score_normalization".into(),
            segment_reference_status:
                "computed_on_demand_from_actual_segment_starts_to_target_regions".into(),
            evaluation_fallback: None,
            distance_unit: "m".into(),
            grid_resolution_m: res,
        },
    })
}

/// [`evaluate`], falling back to [`worst_case_metrics`] on error, as the benchmark does.
pub fn evaluate_or_worst_case(
    trajectory: &[[i64; 2]],
    episode: &Episode,
    map: &EvalMap,
    opts: &EvalOptions,
) -> EpisodeMetrics {
    evaluate(trajectory, episode, map, opts)
        .unwrap_or_else(|e| worst_case_metrics(Some(trajectory), episode, map, &e.to_string()))
}

/// Worst-case metrics after an evaluation error or an unusable prediction (`trajectory` is
/// `None` when it could not be read): HCS and SPL 0, PL of whatever route there is, near at its
/// farthest region cell (else the map diagonal), every other soft raw value 0.
pub fn worst_case_metrics(
    trajectory: Option<&[[i64; 2]]>,
    episode: &Episode,
    map: &EvalMap,
    error: &str,
) -> EpisodeMetrics {
    let res = map.resolution();
    let n = map.n();
    let mut soft = Vec::with_capacity(episode.soft_constraints.len());
    for (index, c) in episode.soft_constraints.iter().enumerate() {
        let mut d = base_detail(index, c);
        d.evaluation_fallback = Some("worst_case".into());
        match c.preference_type.as_deref() {
            Some(NEAR) => {
                let region = SoftRegion::new(index, c);
                if let Err(e) = near_or_far(&region, &[], map, &EvalOptions::default(), &mut d) {
                    d.raw_value = None;
                    d.region_waypoint_count = Some(0);
                    d.fallback_error = Some(e.to_string());
                }
                if d.raw_value.is_none() {
                    d.status = "evaluation_error_worst_case_map_diagonal".into();
                    d.raw_value = Some(std::f64::consts::SQRT_2 * n.saturating_sub(1) as f64 * res);
                    d.direction = Some("smaller_is_better".into());
                    d.unit = Some("m".into());
                } else {
                    d.status = "evaluation_error_worst_case_max_distance".into();
                }
            }
            Some(t @ (FAR | RELATIVE | PATH_SHAPE | GEOMETRIC_PATH | CLEARANCE)) => {
                d.status = "evaluation_error_worst_case_zero".into();
                d.raw_value = Some(0.0);
                d.direction = Some("larger_is_better".into());
                match t {
                    FAR => {
                        d.region_waypoint_count = Some(0);
                        d.unit = Some("m".into());
                    }
                    RELATIVE => {
                        d.region_waypoint_count = Some(0);
                        d.unit = Some("ratio".into());
                    }
                    CLEARANCE => {
                        d.waypoint_count = Some(0);
                        d.unit = Some("m".into());
                    }
                    _ => {
                        d.ndtw = Some(0.0);
                        d.region_waypoint_count = Some(0);
                    }
                }
            }
            _ => {
                d.status = "evaluation_error_unsupported_preference".into();
                d.raw_value = Some(0.0);
            }
        }
        soft.push(d);
    }
    let ctx = HardContext::new(&episode.hard_constraints);
    let targets = ctx.ordered.len().saturating_sub(1);
    let record = ctx.ordered.first().map(|&i| RecordRegion {
        constraint_id: ctx.hard[i].constraint_id.clone(),
        order: ctx.hard[i].order,
    });
    let pl = trajectory.map_or(0.0, |t| {
        let pts: Vec<Point> = to_points(t);
        path_length_cells(&pts) * res
    });
    EpisodeMetrics {
        hcs: 0.0,
        scs: None,
        pl,
        segment_wise_spl: 0.0,
        details: EvalDetails {
            hcs: HcsDetails {
                score: 0.0,
                valid_completed_count: 0,
                must_pass_count: targets,
                ignored_record_must_pass: record,
                failed: true,
                first_failed_transition: (targets > 0).then_some(1),
                failure_type: Some("metric_evaluation_error_worst_case".into()),
                first_must_avoid_violation: None,
                must_avoid_violations: Vec::new(),
                global_must_avoid_violations: Vec::new(),
            },
            segments: Vec::new(),
            soft_constraints: soft,
            scs_status: "evaluation_error_worst_case_raw_values".into(),
            segment_reference_status: "evaluation_error_worst_case_zero".into(),
            evaluation_fallback: Some(EvaluationFallback {
                policy: "worst_case".into(),
                error: error.to_string(),
            }),
            distance_unit: "m".into(),
            grid_resolution_m: res,
        },
    }
}
