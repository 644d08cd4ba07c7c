//! Soft constraints: one raw value per constraint (no 0-1 score), measured on the waypoints of
//! the constraint's route stage that lie in its region, and gated to a worst case when a
//! stage-scoped constraint's hard segment did not succeed.

use super::context::{EvalError, HardContext};
use super::geometry::{EPSILON, Geom, Point, RegionSpec, compile};
use super::hcs::progress;
use super::map::EvalMap;
use super::ndtw::ndtw;
use super::path_shape::normalize_annotation;
use crate::episode::{CellRc, Episode, Scope, Shape, SoftConstraint};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeSet, HashMap, HashSet};

/// Evaluation switches.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct EvalOptions {
    /// Paper variant: count each region waypoint once (W_R as a set). The reference code keeps
    /// repeated waypoints, which is the default.
    pub dedup_region_waypoints: bool,
}

/// One soft constraint's result, with the reference's keys.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SoftDetail {
    pub constraint_id: String,
    /// Normalized type (`path_shape_preference` is reported as `geometric_path_preference`).
    pub preference_type: Option<String>,
    pub source_preference_type: Option<String>,
    pub scope: Option<Scope>,
    pub active_waypoint_count: usize,
    /// Always `null`: soft constraints get raw values only.
    pub score: Option<f64>,
    #[serde(default)]
    pub segment_gate_applied: bool,
    pub segment_succeeded: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub required_to_order: Option<Option<i64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ungated_active_waypoint_count: Option<usize>,
    pub status: String,
    pub raw_value: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub region_waypoint_count: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unit: Option<String>,
    #[serde(rename = "D_A", default, skip_serializing_if = "Option::is_none")]
    pub d_a: Option<f64>,
    #[serde(rename = "D_B", default, skip_serializing_if = "Option::is_none")]
    pub d_b: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub distance_unit: Option<String>,
    #[serde(rename = "nDTW", default, skip_serializing_if = "Option::is_none")]
    pub ndtw: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dtw_cost: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean_dtw_distance: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dtw_alignment_steps: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference_trajectory_source: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference_waypoint_count: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference_trajectory_file: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub waypoint_count: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub worst_case_measurement_status: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub evaluation_fallback: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fallback_error: Option<String>,
}

pub(crate) const NEAR: &str = "near_preference";
pub(crate) const FAR: &str = "far_preference";
pub(crate) const RELATIVE: &str = "relative_preference";
pub(crate) const PATH_SHAPE: &str = "path_shape_preference";
pub(crate) const GEOMETRIC_PATH: &str = "geometric_path_preference";
pub(crate) const CLEARANCE: &str = "clearance";

/// The soft detail skeleton the reference fills for every constraint.
pub(crate) fn base_detail(index: usize, c: &SoftConstraint) -> SoftDetail {
    let source = c.preference_type.clone();
    let normalized = match source.as_deref() {
        Some(PATH_SHAPE) => Some(GEOMETRIC_PATH.to_string()),
        _ => source.clone(),
    };
    SoftDetail {
        constraint_id: c
            .constraint_id
            .clone()
            .unwrap_or_else(|| format!("soft_{}", index + 1)),
        preference_type: normalized,
        source_preference_type: source,
        scope: c.scope.clone(),
        ..SoftDetail::default()
    }
}

/// A soft constraint's region, validated lazily (errors surface only when a point is tested).
pub(crate) struct SoftRegion<'c> {
    index: usize,
    c: &'c SoftConstraint,
    geom: Result<Geom, String>,
}

impl<'c> SoftRegion<'c> {
    pub fn new(index: usize, c: &'c SoftConstraint) -> Self {
        SoftRegion {
            index,
            c,
            geom: compile(RegionSpec::of_soft(c)),
        }
    }

    fn err(&self, message: impl Into<String>) -> EvalError {
        EvalError::Constraint {
            field: format!("soft_constraints[{}]", self.index),
            message: message.into(),
        }
    }

    fn geom(&self) -> Result<&Geom, EvalError> {
        self.geom.as_ref().map_err(|m| self.err(m.clone()))
    }

    /// Active waypoints inside the region, in order (optionally deduplicated).
    fn waypoints(&self, active: &[Point], dedup: bool) -> Result<Vec<Point>, EvalError> {
        if active.is_empty() {
            return Ok(Vec::new());
        }
        let g = self.geom()?;
        let mut out: Vec<Point> = active.iter().copied().filter(|&p| g.contains(p)).collect();
        if dedup {
            let mut seen = HashSet::new();
            out.retain(|p| seen.insert((p[0].to_bits(), p[1].to_bits())));
        }
        Ok(out)
    }

    /// In-grid cells of the region (the set a near preference's worst case ranges over).
    pub fn cells(&self, n: usize) -> Result<Vec<CellRc>, EvalError> {
        let c = self.c;
        if c.shape == Some(Shape::Freeform) {
            let set: BTreeSet<CellRc> = c
                .cells
                .iter()
                .flatten()
                .copied()
                .filter(|p| p[0] >= 0 && p[1] >= 0 && (p[0] as usize) < n && (p[1] as usize) < n)
                .collect();
            return Ok(set.into_iter().collect());
        }
        let center = c
            .center
            .ok_or_else(|| self.err("constraint center must be [row, col]"))?;
        let (hr, hc) = match c.shape {
            Some(Shape::Circle) => {
                let r = c.radius.unwrap_or(0.0);
                (r, r)
            }
            Some(Shape::Rectangle) => (c.height.unwrap_or(0.0) / 2.0, c.width.unwrap_or(0.0) / 2.0),
            _ => return Ok(Vec::new()),
        };
        let last = n as f64 - 1.0;
        let r0 = (center[0] - hr).floor().max(0.0);
        let r1 = (center[0] + hr).ceil().min(last);
        let c0 = (center[1] - hc).floor().max(0.0);
        let c1 = (center[1] + hc).ceil().min(last);
        let mut out = Vec::new();
        if !(r0 <= r1 && c0 <= c1) {
            return Ok(out);
        }
        let g = self.geom()?;
        for r in r0 as i64..=r1 as i64 {
            for col in c0 as i64..=c1 as i64 {
                if g.contains([r as f64, col as f64]) {
                    out.push([r, col]);
                }
            }
        }
        Ok(out)
    }
}

fn dist_to_cells(p: Point, cells: &[CellRc]) -> f64 {
    cells
        .iter()
        .map(|c| (p[0] - c[0] as f64).hypot(p[1] - c[1] as f64))
        .fold(f64::INFINITY, f64::min)
}

fn mean_dist(points: &[Point], cells: &[CellRc]) -> f64 {
    points.iter().map(|&p| dist_to_cells(p, cells)).sum::<f64>() / points.len() as f64
}

fn ref_cells(r: Option<&crate::episode::ReferenceRegion>) -> &[CellRc] {
    r.and_then(|r| r.cells.as_deref()).unwrap_or(&[])
}

/// Near / far. An empty region gives the farthest region cell (near) or 0 (far).
pub(crate) fn near_or_far(
    region: &SoftRegion<'_>,
    active: &[Point],
    map: &EvalMap,
    opts: &EvalOptions,
    d: &mut SoftDetail,
) -> Result<(), EvalError> {
    let c = region.c;
    let footprint = ref_cells(c.reference_region.as_ref());
    let wr = region.waypoints(active, opts.dedup_region_waypoints)?;
    d.region_waypoint_count = Some(wr.len());
    if footprint.is_empty() {
        d.status = "missing_object_footprint_cells".into();
        d.raw_value = None;
        return Ok(());
    }
    let near = c.preference_type.as_deref() == Some(NEAR);
    let distance = if !wr.is_empty() {
        d.status = "computed".into();
        Some(mean_dist(&wr, footprint))
    } else if near {
        let cells = region.cells(map.n())?;
        let worst = cells
            .iter()
            .map(|&[r, col]| dist_to_cells([r as f64, col as f64], footprint))
            .fold(None, |acc: Option<f64>, x| {
                Some(acc.map_or(x, |a| a.max(x)))
            });
        d.status = if worst.is_some() {
            "empty_region_max_distance"
        } else {
            "empty_region_without_cells"
        }
        .into();
        worst
    } else {
        d.status = "empty_region_zero_distance".into();
        Some(0.0)
    };
    d.raw_value = distance.map(|x| x * map.resolution());
    d.direction = Some(
        if near {
            "smaller_is_better"
        } else {
            "larger_is_better"
        }
        .into(),
    );
    d.unit = Some("m".into());
    Ok(())
}

/// Relative: D_B / D_A, A being the preferred object.
pub(crate) fn relative(
    region: &SoftRegion<'_>,
    active: &[Point],
    map: &EvalMap,
    opts: &EvalOptions,
    d: &mut SoftDetail,
) -> Result<(), EvalError> {
    let regions = match region.c.reference_regions.as_deref() {
        Some(r) if r.len() == 2 => r,
        _ => {
            d.status = "missing_relative_object_footprints".into();
            d.raw_value = None;
            d.region_waypoint_count = Some(0);
            return Ok(());
        }
    };
    let (a, b) = (ref_cells(Some(&regions[0])), ref_cells(Some(&regions[1])));
    let wr = region.waypoints(active, opts.dedup_region_waypoints)?;
    d.region_waypoint_count = Some(wr.len());
    if a.is_empty() || b.is_empty() {
        d.status = "missing_relative_object_footprints".into();
        d.raw_value = None;
        return Ok(());
    }
    d.direction = Some("larger_is_better".into());
    if wr.is_empty() {
        d.status = "empty_region_zero_score".into();
        d.raw_value = Some(0.0);
        d.unit = Some("ratio".into());
        return Ok(());
    }
    let (da, db) = (mean_dist(&wr, a), mean_dist(&wr, b));
    d.d_a = Some(da * map.resolution());
    d.d_b = Some(db * map.resolution());
    d.distance_unit = Some("m".into());
    if da <= EPSILON {
        d.status = "zero_distance_to_preferred_object_pending_policy".into();
        d.raw_value = None;
    } else {
        d.status = "computed".into();
        d.raw_value = Some(db / da);
    }
    Ok(())
}

/// Path shape: nDTW between the region waypoints and the reference polyline.
pub(crate) fn path_shape(
    region: &SoftRegion<'_>,
    active: &[Point],
    reference: &PathReference,
    opts: &EvalOptions,
    d: &mut SoftDetail,
) -> Result<(), EvalError> {
    d.reference_trajectory_source = Some(reference.source.clone());
    let Some(points) = &reference.points else {
        d.status = "missing_reference_trajectory".into();
        d.raw_value = None;
        d.reference_waypoint_count = Some(0);
        return Ok(());
    };
    d.reference_waypoint_count = Some(points.len());
    d.reference_trajectory_file = reference.file.clone();
    let local = region.waypoints(active, opts.dedup_region_waypoints)?;
    d.region_waypoint_count = Some(local.len());
    d.direction = Some("larger_is_better".into());
    if local.is_empty() {
        d.status = "empty_region_zero_score".into();
        d.raw_value = Some(0.0);
        d.ndtw = Some(0.0);
        return Ok(());
    }
    let r = ndtw(&local, points);
    d.status = "computed".into();
    d.raw_value = Some(r.score);
    d.ndtw = Some(r.score);
    d.dtw_cost = Some(r.cost);
    d.mean_dtw_distance = Some(r.mean);
    d.dtw_alignment_steps = Some(r.steps);
    Ok(())
}

/// Clearance: mean distance from the active waypoints to the nearest obstacle cell, in metres.
pub(crate) fn clearance(active: &[Point], map: &EvalMap, d: &mut SoftDetail) {
    if active.is_empty() {
        d.status = "empty_trajectory".into();
        d.raw_value = None;
        d.waypoint_count = Some(0);
        return;
    }
    d.waypoint_count = Some(active.len());
    let Some(field) = map.clearance_field() else {
        d.status = "no_nontraversable_cells".into();
        d.raw_value = None;
        return;
    };
    let n = map.n();
    let total: f64 = active
        .iter()
        .map(|p| {
            let (r, c) = (p[0] as i64, p[1] as i64);
            if map.in_grid(r, c) {
                field.at(r as usize * n + c as usize)
            } else {
                map.nearest_obstacle_distance(*p)
            }
        })
        .sum();
    d.status = "computed".into();
    d.raw_value = Some(total / active.len() as f64 * map.resolution());
    d.direction = Some("larger_is_better".into());
    d.unit = Some("m".into());
}

/// The polyline a path-shape preference is compared with, and where it came from.
pub(crate) struct PathReference {
    pub points: Option<Vec<Point>>,
    pub source: String,
    pub file: Option<String>,
}

pub(crate) fn path_reference(
    index: usize,
    c: &SoftConstraint,
    episode: &Episode,
    n: usize,
) -> Result<PathReference, EvalError> {
    let is_path = matches!(
        c.preference_type.as_deref(),
        Some(PATH_SHAPE | GEOMETRIC_PATH)
    );
    let has_id = c
        .constraint_id
        .as_deref()
        .is_some_and(|s| !s.trim().is_empty());
    if is_path
        && has_id
        && let Some(annotation) = &c.path_shape_annotation
    {
        let label = format!("soft_constraints[{index}].path_shape_annotation");
        let (traj, source) =
            normalize_annotation(annotation, n, &label).map_err(|m| EvalError::Constraint {
                field: label.clone(),
                message: m,
            })?;
        return Ok(PathReference {
            points: Some(traj.iter().map(|p| [p[0] as f64, p[1] as f64]).collect()),
            source,
            file: episode.source_path().map(|p| p.display().to_string()),
        });
    }
    Ok(PathReference {
        points: c
            .reference_trajectory
            .as_ref()
            .map(|t| t.iter().map(|p| [p[0] as f64, p[1] as f64]).collect()),
        source: "instruction_reference_trajectory".into(),
        file: None,
    })
}

/// All soft details of an episode.
pub(crate) fn compute_soft(
    ctx: &HardContext<'_>,
    episode: &Episode,
    points: &[Point],
    map: &EvalMap,
    opts: &EvalOptions,
) -> Result<Vec<SoftDetail>, EvalError> {
    // First waypoint hit of each must-pass in order; the cursor stays on the hit.
    let mut hits: HashMap<i64, usize> = HashMap::new();
    let mut cursor = 0usize;
    for (pos, &i) in ctx.ordered.iter().enumerate() {
        let key = ctx.hard[i].order.unwrap_or(pos as i64 + 1);
        if cursor < points.len() {
            let g = ctx.geom(i)?;
            if let Some(h) = (cursor..points.len()).find(|&k| g.contains(points[k])) {
                hits.insert(key, h);
                cursor = h;
            }
        }
    }
    // Stages completed under all hard constraints (global avoids stop progress here too).
    let mut completed_to: HashSet<i64> = HashSet::new();
    if ctx.ordered.len() >= 2 {
        let p = progress(ctx, points, &|_| true)?;
        for (k, &i) in ctx.ordered[1..=p.valid_completed_count].iter().enumerate() {
            completed_to.insert(ctx.hard[i].order.unwrap_or(k as i64 + 2));
        }
    }

    let mut out = Vec::with_capacity(episode.soft_constraints.len());
    for (index, c) in episode.soft_constraints.iter().enumerate() {
        let mut d = base_detail(index, c);
        let scope = c.scope.as_ref().filter(|s| s.is_between());
        let candidate: &[Point] = match scope {
            Some(s) => match (s.from_order, s.to_order) {
                (Some(f), Some(t)) => match (hits.get(&f), hits.get(&t)) {
                    (Some(&fi), Some(&ti)) if ti >= fi => &points[fi..=ti],
                    (Some(&fi), _) => &points[fi..],
                    (None, Some(&ti)) => &points[..=ti],
                    (None, None) => points,
                },
                _ => points,
            },
            None => points,
        };
        let succeeded = match scope {
            None => true,
            Some(s) => s.to_order.is_some_and(|t| completed_to.contains(&t)),
        };
        let active: &[Point] = if succeeded { candidate } else { &[] };
        d.active_waypoint_count = active.len();
        d.segment_gate_applied = scope.is_some();
        d.segment_succeeded = scope.map(|_| succeeded);
        if let Some(s) = scope {
            d.required_to_order = Some(s.to_order);
            if !succeeded {
                d.ungated_active_waypoint_count = Some(candidate.len());
            }
        }
        let region = SoftRegion::new(index, c);
        match c.preference_type.as_deref() {
            Some(NEAR | FAR) => near_or_far(&region, active, map, opts, &mut d)?,
            Some(RELATIVE) => relative(&region, active, map, opts, &mut d)?,
            Some(PATH_SHAPE | GEOMETRIC_PATH) => {
                let reference = path_reference(index, c, episode, map.n())?;
                path_shape(&region, active, &reference, opts, &mut d)?
            }
            Some(CLEARANCE) => clearance(active, map, &mut d),
            _ => {
                d.status = "unsupported_preference".into();
                d.raw_value = None;
            }
        }
        if scope.is_some() && !succeeded {
            if c.preference_type.as_deref() == Some(CLEARANCE) {
                d.raw_value = Some(0.0);
                d.waypoint_count = Some(0);
                d.direction = Some("larger_is_better".into());
                d.unit = Some("m".into());
            }
            d.worst_case_measurement_status = Some(std::mem::replace(
                &mut d.status,
                "segment_not_completed_worst_case".into(),
            ));
        }
        out.push(d);
    }
    Ok(out)
}

/// Soft details alone (no HCS / SPL), e.g. for episodes without must-pass regions.
pub fn soft_details(
    trajectory: &[[i64; 2]],
    episode: &Episode,
    map: &EvalMap,
    opts: &EvalOptions,
) -> Result<Vec<SoftDetail>, EvalError> {
    let ctx = HardContext::new(&episode.hard_constraints);
    compute_soft(
        &ctx,
        episode,
        &super::geometry::to_points(trajectory),
        map,
        opts,
    )
}
