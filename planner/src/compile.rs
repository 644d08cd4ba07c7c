//! Turns a [`PlanProblem`] into the padded arrays the searches run on: per segment the allowed mask
//! (traversable minus active avoid regions) and the cost field Φ; per stage the goal mask, its
//! heuristic and its smoothness mask. Shared by the sequential, global and shortest planners so
//! they all search exactly the same graph with exactly the same costs.

use crate::astar::{Heuristic, Smooth};
use crate::context::MapFields;
use crate::costfield::{self, FieldContext, FieldScratch, Run};
use crate::failure::PlanFailure;
use crate::goal;
use crate::layout::Layout;
use crate::problem::{Origin, PlanProblem, SegmentSpec, StageRole, StageSpec, WaypointMode};
use m2rc_stdlib::field::{self, LazySquaredDistances};
use std::cell::RefCell;
use std::collections::VecDeque;
use std::sync::Arc;

/// Per-problem arrays.
pub struct Prepared {
    pub layout: Layout,
    /// Row-major traversable mask.
    pub traversable_plain: Vec<bool>,
    /// Padded traversable mask.
    pub traversable: Vec<bool>,
    /// Row-major squared distance to the nearest clearance obstacle (empty when no term needs it).
    pub obstacle_sq: Arc<Vec<u32>>,
    /// Padded always-on clearance field (`None` when off).
    pub clearance: Option<Arc<Vec<f64>>>,
    /// Traversable cells by runs, for the cost fields.
    pub runs: Vec<Run>,
    /// Buffers reused by the transforms of every segment.
    scratch: RefCell<Scratch>,
    /// Arrays of finished segments, for the next ones; handed to `map_fields` when done.
    pub(crate) buffers: RefCell<Buffers>,
    map_fields: Option<Arc<MapFields>>,
}

/// Large per-segment arrays kept for reuse: a fresh 4 MB Φ or 2 MB heuristic table costs more in page
/// faults than filling it does.
#[derive(Debug, Default)]
pub struct Buffers {
    pub(crate) phi: Vec<Vec<f64>>,
    pub(crate) h: Vec<LazySquaredDistances>,
    pub(crate) field: FieldScratch,
}

impl Buffers {
    /// Keeps the arrays of a segment no search will read again.
    pub(crate) fn recycle(&mut self, seg: CompiledSegment) {
        if let Some(phi) = seg.phi.and_then(|a| Arc::try_unwrap(a).ok()) {
            self.phi.push(phi);
        }
        self.h.extend(seg.stages.into_iter().filter_map(|s| s.h));
    }
}

impl Drop for Prepared {
    fn drop(&mut self) {
        if let Some(f) = &self.map_fields {
            let mut buffers = std::mem::take(self.buffers.get_mut());
            buffers.field = std::mem::take(&mut self.scratch.get_mut().field);
            buffers.field.forget();
            f.stash(buffers);
        }
    }
}

#[derive(Default)]
struct Scratch {
    field: FieldScratch,
}

pub struct CompiledStage {
    pub role: StageRole,
    pub origin: Origin,
    /// Padded goal mask (target ∩ traversable ∩ ¬avoided).
    pub goal: Vec<bool>,
    /// Padded squared distance to the nearest goal cell, when the exact heuristic is on, computed
    /// row by row as the search reads it. Exact on every cell of the map; the padding border holds
    /// no meaningful value (never entered).
    pub h: Option<LazySquaredDistances>,
    /// Padded bounding box of the goal (rows, cols), for the cheap heuristic.
    pub bbox: (usize, usize, usize, usize),
    /// Padded smoothness mask.
    pub smooth: Option<Vec<bool>>,
}

impl CompiledStage {
    pub fn heuristic(&self) -> Heuristic<'_> {
        match &self.h {
            Some(t) => Heuristic::LazySquared(t),
            None => Heuristic::Box {
                r0: self.bbox.0,
                r1: self.bbox.1,
                c0: self.bbox.2,
                c1: self.bbox.3,
            },
        }
    }

    pub fn smooth(&self, weight: f64) -> Option<Smooth<'_>> {
        if weight == 0.0 {
            return None;
        }
        self.smooth.as_deref().map(|mask| Smooth { mask, weight })
    }
}

pub struct CompiledSegment {
    /// Padded: traversable and not avoided.
    pub allowed: Vec<bool>,
    /// Padded Φ, exact on traversable cells (a search reads nothing else); `None` when it is zero
    /// on all of them. Shared with the problem's clearance field when the segment adds no term.
    pub phi: Option<Arc<Vec<f64>>>,
    /// The avoid regions' origins, in the order of the segment's `forbidden` (whose cells
    /// failure diagnosis reads again: a mask of each would be built for every segment and used
    /// only when one fails).
    pub forbids: Vec<Origin>,
    pub stages: Vec<CompiledStage>,
}

pub fn prepare(p: &PlanProblem) -> Result<Prepared, PlanFailure> {
    let n = p.traversable.n();
    let invalid = |message: String| PlanFailure::InvalidProblem { message };
    if n == 0 {
        return Err(invalid("the map grid is empty".into()));
    }
    if !(p.resolution.is_finite() && p.resolution > 0.0) {
        return Err(invalid(format!(
            "resolution must be a positive number of metres, got {}",
            p.resolution
        )));
    }
    p.profile.validate().map_err(invalid)?;
    if let Some(o) = &p.obstacles
        && o.n() != n
    {
        return Err(invalid(format!(
            "obstacle mask is {0}×{0}, the map is {n}×{n}",
            o.n()
        )));
    }
    if n > 40_000 {
        return Err(invalid(format!("a {n}×{n} grid is too large to plan on")));
    }
    let layout = Layout::new(n);
    let traversable_plain = p.traversable.data().to_vec();
    let traversable = layout.pad(&traversable_plain, false);
    let runs = costfield::traversable_runs(&traversable_plain, n);
    let needs_obstacles = (p.profile.clearance && p.profile.clearance_weight > 0.0)
        || (p.profile.soft_scale > 0.0
            && p.segments
                .iter()
                .flat_map(|s| &s.soft)
                .any(|t| matches!(t.kind, crate::problem::SoftKind::Clearance { .. })));
    let (obstacle_sq, clearance) = if needs_obstacles {
        let shared = p.map_fields.as_ref().filter(|f| f.n() == n);
        let d = match shared {
            Some(f) => f.obstacle_sq(),
            None => {
                let mut obs: Vec<bool> = match &p.obstacles {
                    Some(o) => o.data().to_vec(),
                    None => traversable_plain.iter().map(|t| !t).collect(),
                };
                if !obs.iter().any(|v| *v) {
                    obs = traversable_plain.iter().map(|t| !t).collect();
                }
                Arc::new(field::squared_distances(&obs, n))
            }
        };
        let c = p.profile.clearance.then(|| {
            let make = || {
                let ctx = FieldContext {
                    n,
                    resolution: p.resolution,
                    profile: &p.profile,
                    obstacle_sq: &d,
                    runs: &[],
                };
                costfield::clearance_field_padded(&ctx, &layout)
            };
            let radius = p.profile.cells(p.profile.clearance_radius_m, p.resolution);
            match shared {
                Some(f) => f.clearance(
                    (radius.to_bits(), p.profile.clearance_weight.to_bits()),
                    make,
                ),
                None => Arc::new(make()),
            }
        });
        (d, c)
    } else {
        (Arc::new(Vec::new()), None)
    };
    let mut buffers = p
        .map_fields
        .as_ref()
        .map(|f| f.take_buffers())
        .unwrap_or_default();
    Ok(Prepared {
        layout,
        traversable_plain,
        traversable,
        obstacle_sq,
        clearance,
        runs,
        scratch: RefCell::new(Scratch {
            field: std::mem::take(&mut buffers.field),
        }),
        buffers: RefCell::new(buffers),
        map_fields: p.map_fields.clone(),
    })
}

/// The stages actually planned, after the profile's waypoint mode.
fn effective_stages(spec: &SegmentSpec, mode: WaypointMode) -> Vec<StageSpec> {
    match mode {
        WaypointMode::Stages => spec.stages.clone(),
        WaypointMode::Drop => spec
            .stages
            .iter()
            .filter(|s| s.role != StageRole::Waypoint)
            .cloned()
            .collect(),
        WaypointMode::Collapse => {
            let mut out: Vec<StageSpec> = Vec::new();
            let mut run: Vec<StageSpec> = Vec::new();
            let flush = |run: &mut Vec<StageSpec>, out: &mut Vec<StageSpec>| {
                if let Some(first) = run.first() {
                    let cells: Vec<_> = run.iter().flat_map(|s| target_cells(&s.target)).collect();
                    out.push(StageSpec {
                        target: crate::problem::Target::Region {
                            cells: crate::problem::Area::Cells(cells),
                            fallback: None,
                        },
                        role: StageRole::Waypoint,
                        smoothness: None,
                        origin: first.origin,
                    });
                }
                run.clear();
            };
            for s in &spec.stages {
                if s.role == StageRole::Waypoint {
                    run.push(s.clone());
                } else {
                    flush(&mut run, &mut out);
                    out.push(s.clone());
                }
            }
            flush(&mut run, &mut out);
            out
        }
    }
}

fn target_cells(t: &crate::problem::Target) -> Vec<m2rc_stdlib::grid::Cell> {
    use crate::problem::Target;
    match t {
        Target::Position(c) => vec![*c],
        Target::Room(a) | Target::Region { cells: a, .. } => a.cells(),
        Target::Object { footprint, .. } => footprint.clone(),
        Target::AnyOf(members) => members.iter().flat_map(target_cells).collect(),
    }
}

pub fn compile_segment(
    p: &PlanProblem,
    prep: &Prepared,
    index: usize,
    spec: &SegmentSpec,
) -> Result<CompiledSegment, PlanFailure> {
    let n = prep.layout.n;
    let l = prep.layout;
    let forbids: Vec<Origin> = spec.forbidden.iter().map(|f| f.origin).collect();
    // Built as the forbidden mask, then turned in place into "traversable and not forbidden".
    let mut allowed_plain = vec![false; n * n];
    for f in &spec.forbidden {
        f.cells.or_into(&mut allowed_plain, n);
    }
    allowed_plain
        .iter_mut()
        .zip(&prep.traversable_plain)
        .for_each(|(a, t)| *a = *t && !*a);

    // Φ.
    let mut scratch = prep.scratch.borrow_mut();
    let adds_terms = p.profile.soft_scale > 0.0 && !spec.soft.is_empty();
    let phi = if adds_terms {
        let reused = prep.buffers.borrow_mut().phi.pop();
        let mut phi = match (reused, &prep.clearance) {
            (Some(mut b), Some(c)) if b.len() == c.len() => {
                b.copy_from_slice(c);
                b
            }
            (Some(mut b), None) if b.len() == l.len() => {
                b.fill(0.0);
                b
            }
            (_, Some(c)) => c.to_vec(),
            (_, None) => vec![0.0; l.len()],
        };
        let ctx = FieldContext {
            n,
            resolution: p.resolution,
            profile: &p.profile,
            obstacle_sq: &prep.obstacle_sq,
            runs: &prep.runs,
        };
        for t in &spec.soft {
            costfield::add_term(&mut phi, &ctx, &mut scratch.field, t);
        }
        nonzero_on(&phi, &prep.runs, l).then(|| Arc::new(phi))
    } else {
        prep.clearance
            .as_ref()
            .filter(|c| nonzero_on(c, &prep.runs, l))
            .map(Arc::clone)
    };

    let radius = goal::goal_radius_cells(p.profile.goal_radius_m, p.resolution);
    let mut stages = Vec::new();
    for (si, st) in effective_stages(spec, p.profile.waypoints)
        .iter()
        .enumerate()
    {
        let mut goal_plain = goal::goal_mask(&st.target, &prep.traversable_plain, n, radius);
        if !goal_plain.iter().any(|v| *v) {
            return Err(PlanFailure::TargetEmpty {
                segment: index,
                stage: si,
                origin: st.origin,
            });
        }
        goal_plain
            .iter_mut()
            .zip(&allowed_plain)
            .for_each(|(g, a)| *g &= *a);
        if !goal_plain.iter().any(|v| *v) {
            let raw = goal::goal_mask(&st.target, &prep.traversable_plain, n, radius);
            let culprits = spec
                .forbidden
                .iter()
                .filter(|f| {
                    let m = f.cells.to_mask(n);
                    raw.iter().zip(&m).any(|(g, f)| *g && *f)
                })
                .map(|f| f.origin)
                .collect();
            return Err(PlanFailure::GoalBlocked {
                segment: index,
                stage: si,
                origin: st.origin,
                forbids: culprits,
            });
        }
        let goal = l.pad(&goal_plain, false);
        // On the padded grid directly: distances are translation invariant and the border holds
        // no goal, so every map cell gets its exact value without a copy.
        let h = p.profile.edt_heuristic.then(|| {
            let mut h = prep.buffers.borrow_mut().h.pop().unwrap_or_default();
            h.reset(&goal, l.w);
            h
        });
        let (mut r0, mut r1, mut c0, mut c1) = (usize::MAX, 0, usize::MAX, 0);
        for (i, _) in goal_plain.iter().enumerate().filter(|(_, g)| **g) {
            let (r, c) = (i / n + 1, i % n + 1);
            r0 = r0.min(r);
            r1 = r1.max(r);
            c0 = c0.min(c);
            c1 = c1.max(c);
        }
        let smooth = st.smoothness.as_ref().map(|a| {
            let m: Vec<bool> = a
                .to_mask(n)
                .iter()
                .zip(&prep.traversable_plain)
                .map(|(a, t)| *a && *t)
                .collect();
            l.pad(&m, false)
        });
        stages.push(CompiledStage {
            role: st.role,
            origin: st.origin,
            goal,
            h,
            bbox: (r0, r1, c0, c1),
            smooth,
        });
    }
    Ok(CompiledSegment {
        allowed: l.pad(&allowed_plain, false),
        phi,
        forbids,
        stages,
    })
}

/// Whether the padded field is non-zero on some traversable cell (given by its runs).
fn nonzero_on(phi: &[f64], runs: &[Run], layout: Layout) -> bool {
    runs.iter().any(|run| {
        let at = layout.idx(m2rc_stdlib::grid::Cell::new(run.row, run.c0));
        phi[at..=at + (run.c1 - run.c0) as usize]
            .iter()
            .any(|v| *v != 0.0)
    })
}

/// Whether any goal cell is reachable from `start` over `allowed` (8-connected, no corner cutting
/// on `traversable`: [`crate::layout::corners_free`]). Used only to explain failures.
pub fn reachable(
    layout: Layout,
    traversable: &[bool],
    allowed: &[bool],
    goal: &[bool],
    start: usize,
) -> bool {
    let offs = layout.offsets();
    let w = layout.w as isize;
    let mut seen = vec![false; layout.len()];
    let mut queue = VecDeque::from([start]);
    seen[start] = true;
    while let Some(u) = queue.pop_front() {
        if goal[u] {
            return true;
        }
        for (k, off) in offs.iter().enumerate() {
            let v = (u as isize + off) as usize;
            if seen[v] || !allowed[v] {
                continue;
            }
            if !crate::layout::corners_free(traversable, u, k, w as usize) {
                continue;
            }
            seen[v] = true;
            queue.push_back(v);
        }
    }
    false
}

/// Explains why stage `stage` of `seg` cannot be reached from `start` (padded index).
pub fn explain_unreachable(
    p: &PlanProblem,
    prep: &Prepared,
    seg: &CompiledSegment,
    segment: usize,
    stage: usize,
    start: usize,
) -> PlanFailure {
    let l = prep.layout;
    let n = l.n;
    let st = &seg.stages[stage];
    let from = l.cell(start);
    // The stage's goal without any avoid region.
    let radius = goal::goal_radius_cells(p.profile.goal_radius_m, p.resolution);
    let spec_stages = effective_stages(&p.segments[segment], p.profile.waypoints);
    let raw = l.pad(
        &goal::goal_mask(
            &spec_stages[stage].target,
            &prep.traversable_plain,
            n,
            radius,
        ),
        false,
    );
    if seg.forbids.is_empty() || !reachable(l, &prep.traversable, &prep.traversable, &raw, start) {
        return PlanFailure::Unreachable {
            segment,
            stage,
            origin: st.origin,
            from,
        };
    }
    // Which avoid region, removed on its own, reconnects the target? (Bounded: each test is a BFS.)
    let mut culprits = Vec::new();
    let forbidden = &p.segments[segment].forbidden;
    if forbidden.len() <= 16 {
        for skip in 0..forbidden.len() {
            let mut others = vec![false; n * n];
            for (j, f) in forbidden.iter().enumerate() {
                if j != skip {
                    f.cells.or_into(&mut others, n);
                }
            }
            let others = l.pad(&others, false);
            let allowed: Vec<bool> = prep
                .traversable
                .iter()
                .zip(&others)
                .map(|(t, f)| *t && !*f)
                .collect();
            let goal: Vec<bool> = raw.iter().zip(&allowed).map(|(g, a)| *g && *a).collect();
            let corners = if p.profile.avoid_corners {
                &allowed
            } else {
                &prep.traversable
            };
            if allowed[start] && reachable(l, corners, &allowed, &goal, start) {
                culprits.push(forbidden[skip].origin);
            }
        }
    }
    if culprits.is_empty() {
        culprits = seg.forbids.clone();
    }
    PlanFailure::UnreachableUnderAvoids {
        segment,
        stage,
        origin: st.origin,
        from,
        forbids: culprits,
    }
}
