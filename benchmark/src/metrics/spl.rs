//! Segment-wise SPL ("H-SPL"): for each target, the oracle length L* from the route's actual
//! segment start over the route's length L up to the first waypoint inside the target, zero once
//! any segment fails. Unlike HCS, completion here is waypoint-based.

use super::context::{EvalError, HardContext, active_for_spl};
use super::geometry::{EPSILON, Geom, Point, polyline_hits};
use super::map::EvalMap;
use super::oracle::shortest_legal_length;
use super::pl::path_length_cells;
use serde::{Deserialize, Serialize};

/// How the oracle is defined; reported per segment like the reference does.
pub const ORACLE_DEFINITION: &str = "precomputed_reverse_shortest_legal_distance_field_from_actual_segment_start_to_any_target_region_cell";

/// One SPL segment, with the reference's keys.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SegmentDetail {
    pub index: usize,
    pub from_order: Option<i64>,
    pub to_order: Option<i64>,
    pub start_anchor: Option<[i64; 2]>,
    pub goal_region_constraint_id: String,
    pub oracle_definition: String,
    pub active_must_avoid_ids: Vec<String>,
    #[serde(rename = "L_star")]
    pub l_star: Option<f64>,
    #[serde(rename = "L")]
    pub l: Option<f64>,
    pub length_unit: String,
    #[serde(rename = "S")]
    pub s: u8,
    #[serde(rename = "SPL")]
    pub spl: f64,
    pub status: String,
}

/// Returns the mean over targets and the per-segment details.
pub(crate) fn compute_spl(
    ctx: &HardContext<'_>,
    traj: &[[i64; 2]],
    points: &[Point],
    map: &EvalMap,
) -> Result<(f64, Vec<SegmentDetail>), EvalError> {
    ctx.require_targets("Segment-wise SPL")?;
    if map.traversable().is_none() {
        return Err(EvalError::Map(
            "the map has no `layers.occupancy`, so SPL cannot be computed".into(),
        ));
    }
    let res = map.resolution();
    let ordered = &ctx.ordered;
    let mut cursor = 0usize;
    let mut start_index = 0usize;
    let mut complete = true;
    let mut details = Vec::with_capacity(ordered.len() - 1);
    let mut sum = 0.0;
    for k in 1..ordered.len() {
        let (prev, goal) = (ordered[k - 1], ordered[k]);
        let from_order = Some(ctx.hard[prev].order.unwrap_or(k as i64));
        let to_order = Some(ctx.hard[goal].order.unwrap_or(k as i64 + 1));
        let avoid_idx: Vec<usize> = (0..ctx.hard.len())
            .filter(|&i| {
                ctx.is_avoid(i) && active_for_spl(&ctx.hard[i], &ctx.hard[prev], &ctx.hard[goal])
            })
            .collect();
        let active_ids: Vec<String> = avoid_idx
            .iter()
            .enumerate()
            .map(|(j, &i)| ctx.id_or(i, || format!("must_avoid_{}", j + 1)))
            .collect();
        let goal_geom = ctx.geom(goal)?;

        let mut oracle = None;
        let mut anchor = None;
        if complete && start_index < traj.len() {
            let s = traj[start_index];
            anchor = Some(s);
            let mut avoids: Vec<&Geom> = Vec::with_capacity(avoid_idx.len());
            for &i in &avoid_idx {
                avoids.push(ctx.geom(i)?);
            }
            oracle = shortest_legal_length(map, s, goal_geom, &avoids);
        }
        let mut hit = None;
        if complete {
            hit = (cursor..points.len()).find(|&i| goal_geom.contains(points[i]));
        }
        let actual: &[Point] = match hit {
            Some(h) if h >= start_index => &points[start_index..=h],
            _ => &[],
        };
        let actual_len = (!actual.is_empty()).then(|| path_length_cells(actual));
        let mut violation = false;
        if !actual.is_empty() {
            for &i in &avoid_idx {
                if polyline_hits(actual, ctx.geom(i)?) {
                    violation = true;
                    break;
                }
            }
        }
        let success = hit.is_some() && !violation && oracle.is_some();
        let (score, status) = if success {
            let l_star = oracle.unwrap_or(0.0);
            let denom = l_star.max(actual_len.unwrap_or(0.0));
            let score = if denom <= EPSILON {
                1.0
            } else {
                l_star / denom
            };
            if let Some(h) = hit {
                cursor = h;
                start_index = h;
            }
            (score, "completed")
        } else {
            complete = false;
            let status = if oracle.is_none() {
                "missing_or_invalid_oracle_segment"
            } else if hit.is_none() {
                "target_not_completed"
            } else {
                "active_must_avoid_violation"
            };
            (0.0, status)
        };
        sum += score;
        details.push(SegmentDetail {
            index: k,
            from_order,
            to_order,
            start_anchor: anchor,
            goal_region_constraint_id: ctx.id_or(goal, || format!("must_pass_{}", k + 1)),
            oracle_definition: ORACLE_DEFINITION.to_string(),
            active_must_avoid_ids: active_ids,
            l_star: oracle.map(|l| l * res),
            l: actual_len.map(|l| l * res),
            length_unit: "m".into(),
            s: u8::from(success),
            spl: score,
            status: status.into(),
        });
    }
    Ok((sum / details.len() as f64, details))
}
