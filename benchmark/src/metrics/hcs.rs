//! HCS, the Hard Constraint Score: the fraction of ordered must-pass targets reached before any
//! active must-avoid is touched, with any touch of a global must-avoid zeroing the score.
//!
//! Goals are entered geometrically (a segment crossing a goal counts), several goals may be
//! completed on one segment, and an avoid touched at the same parameter as the goal (within
//! 1e-6) is a failure.

use super::context::{EvalError, HardContext, active_for_hcs};
use super::geometry::{EPSILON, Point, polyline_hits};
use serde::{Deserialize, Serialize};

/// The record (start-anchor) region, reported but never scored.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RecordRegion {
    pub constraint_id: Option<String>,
    pub order: Option<i64>,
}

/// HCS details, with the reference's keys.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct HcsDetails {
    pub score: f64,
    pub valid_completed_count: usize,
    pub must_pass_count: usize,
    pub ignored_record_must_pass: Option<RecordRegion>,
    pub failed: bool,
    pub first_failed_transition: Option<usize>,
    pub failure_type: Option<String>,
    pub first_must_avoid_violation: Option<String>,
    pub must_avoid_violations: Vec<String>,
    pub global_must_avoid_violations: Vec<String>,
}

/// Ordered progress over the hard constraints selected by `include` (indices into the episode's
/// hard list). Global avoids among them are active on every stage.
pub(crate) fn progress(
    ctx: &HardContext<'_>,
    points: &[Point],
    include: &dyn Fn(usize) -> bool,
) -> Result<HcsDetails, EvalError> {
    ctx.require_targets("HCS")?;
    let ordered: Vec<usize> = ctx
        .ordered
        .iter()
        .copied()
        .filter(|&i| include(i))
        .collect();
    // Must-pass constraints are always included by the callers; keep the check honest anyway.
    if ordered.len() < 2 {
        return Err(EvalError::Episode(
            "HCS requires at least two must-pass regions".into(),
        ));
    }
    let record = ordered[0];
    let targets = &ordered[1..];
    let avoids: Vec<usize> = (0..ctx.hard.len())
        .filter(|&i| include(i) && ctx.is_avoid(i))
        .collect();
    let m = targets.len();
    let mut completed = 0usize;
    let mut failed = false;
    let mut failure_type = None;
    let mut failed_transition = None;
    let mut first_violation = None;
    let mut violations = Vec::new();

    if let Some(&p0) = points.first() {
        while completed < m && ctx.geom(targets[completed])?.contains(p0) {
            completed += 1;
        }
    }

    'segments: for w in points.windows(2) {
        if failed || completed == m {
            break;
        }
        let (a, b) = (w[0], w[1]);
        let mut t = 0.0f64;
        while completed < m {
            let goal = targets[completed];
            let prev = ordered[completed];
            // Earliest active avoid hit at or after t (first in list order on ties).
            let mut avoid_hit: Option<(f64, usize)> = None;
            for &v in &avoids {
                if !active_for_hcs(&ctx.hard[v], &ctx.hard[prev], &ctx.hard[goal]) {
                    continue;
                }
                if let Some((enter, exit)) = ctx.geom(v)?.segment_interval(a, b)
                    && exit >= t - EPSILON
                {
                    let at = enter.max(t);
                    if avoid_hit.is_none_or(|(best, _)| at < best) {
                        avoid_hit = Some((at, v));
                    }
                }
            }
            let goal_hit = match ctx.geom(goal)?.segment_interval(a, b) {
                Some((enter, exit)) if exit >= t - EPSILON => Some(enter.max(t)),
                _ => None,
            };
            if let Some((at, v)) = avoid_hit
                && goal_hit.is_none_or(|g| at <= g + EPSILON)
            {
                failed = true;
                failure_type = Some("must_avoid_violation".to_string());
                failed_transition = Some(completed + 1);
                let id = ctx.id_or(v, || format!("must_avoid_{}", violations.len() + 1));
                first_violation = Some(id.clone());
                violations.push(id);
                break 'segments;
            }
            let Some(g) = goal_hit else { break };
            completed += 1;
            t = g;
        }
    }

    Ok(HcsDetails {
        score: completed as f64 / m as f64,
        valid_completed_count: completed,
        must_pass_count: m,
        ignored_record_must_pass: Some(RecordRegion {
            constraint_id: ctx.hard[record].constraint_id.clone(),
            order: ctx.hard[record].order,
        }),
        failed,
        first_failed_transition: failed_transition,
        failure_type,
        first_must_avoid_violation: first_violation,
        must_avoid_violations: violations,
        global_must_avoid_violations: Vec::new(),
    })
}

/// HCS: zero when any global must-avoid is touched, else ordered progress over the must-passes
/// and the stage-scoped avoids.
pub(crate) fn compute_hcs(
    ctx: &HardContext<'_>,
    points: &[Point],
) -> Result<HcsDetails, EvalError> {
    let mut violated = Vec::new();
    let mut k = 0usize;
    for i in 0..ctx.hard.len() {
        if !ctx.is_global_avoid(i) {
            continue;
        }
        k += 1;
        if !points.is_empty() && polyline_hits(points, ctx.geom(i)?) {
            violated.push(ctx.id_or(i, || format!("global_must_avoid_{k}")));
        }
    }
    let mut details = progress(ctx, points, &|i| !ctx.is_global_avoid(i))?;
    if !violated.is_empty() {
        details.score = 0.0;
        details.failed = true;
        details.failure_type = Some("global_must_avoid_violation".into());
        details.first_must_avoid_violation = Some(violated[0].clone());
        details
            .must_avoid_violations
            .extend(violated.iter().cloned());
        details.global_must_avoid_violations = violated;
    }
    Ok(details)
}
