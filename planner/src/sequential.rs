//! The reference planner (`sequential_greedy_astar`, method notes §4.5): one A* per stage, from the
//! current cell to any cell of the stage's goal; the first goal cell popped becomes the next start.
//! Greedy: an endpoint that is cheap now but expensive for later stages is never revisited (the
//! global planner fixes that).

use crate::astar::{AStar, Outcome, Query, Space};
use crate::compile::{self, CompiledSegment, Prepared};
use crate::failure::PlanFailure;
use crate::layout::NO_HEADING;
use crate::problem::PlanProblem;
use crate::route::{
    PlanStatus, PlannedRoute, PlannedSegment, PlannedStage, append_path, path_length_m,
};

/// Segments compiled on first use, so a failure in segment 1 is reported before segment 2's
/// targets are even looked at (as in the reference).
pub(crate) struct SegmentCache {
    slots: Vec<Option<Result<CompiledSegment, PlanFailure>>>,
}

impl SegmentCache {
    pub(crate) fn new(count: usize) -> Self {
        SegmentCache {
            slots: (0..count).map(|_| None).collect(),
        }
    }

    /// Hands segment `i`'s arrays to `prep` for the segments after it (sequential planning never
    /// reads a finished segment again).
    pub(crate) fn release(&mut self, i: usize, prep: &Prepared) {
        if let Some(Some(Ok(seg))) = self.slots.get_mut(i).map(Option::take) {
            prep.buffers.borrow_mut().recycle(seg);
        }
    }

    /// A segment compiled earlier by [`SegmentCache::get`].
    pub(crate) fn peek(&self, i: usize) -> Option<&CompiledSegment> {
        self.slots.get(i)?.as_ref()?.as_ref().ok()
    }

    pub(crate) fn get(
        &mut self,
        p: &PlanProblem,
        prep: &Prepared,
        i: usize,
    ) -> Result<&CompiledSegment, PlanFailure> {
        if self.slots[i].is_none() {
            self.slots[i] = Some(compile::compile_segment(p, prep, i, &p.segments[i]));
        }
        match self.slots[i].as_ref() {
            Some(Ok(s)) => Ok(s),
            Some(Err(e)) => Err(e.clone()),
            None => Err(PlanFailure::InvalidProblem {
                message: "segment cache slot empty".into(),
            }),
        }
    }
}

/// Plans `p` with the reference sequential planner.
pub fn plan_sequential(p: &PlanProblem) -> PlannedRoute {
    let prep = match compile::prepare(p) {
        Ok(prep) => prep,
        Err(f) => return PlannedRoute::failed("sequential", &p.profile.name, p.start, f),
    };
    let mut cache = SegmentCache::new(p.segments.len());
    run(p, &prep, &mut cache, &mut AStar::new(), "sequential", true)
}

pub(crate) fn run(
    p: &PlanProblem,
    prep: &Prepared,
    cache: &mut SegmentCache,
    astar: &mut AStar,
    name: &str,
    release: bool,
) -> PlannedRoute {
    let l = prep.layout;
    let profile = &p.profile.name;
    if !l.contains(p.start) || !prep.traversable[l.idx(p.start)] {
        return PlannedRoute::failed(
            name,
            profile,
            p.start,
            PlanFailure::StartBlocked { start: p.start },
        );
    }
    let mut cur = l.idx(p.start);
    let mut heading = NO_HEADING;
    let mut trajectory = vec![p.start];
    let mut segments = Vec::new();
    let mut total_cost = 0.0;
    let mut total_exp = 0;
    let mut failure = None;
    'segments: for si in 0..p.segments.len() {
        let seg = match cache.get(p, prep, si) {
            Ok(s) => s,
            Err(f) => {
                failure = Some(f);
                break;
            }
        };
        let mut planned = PlannedSegment {
            index: si,
            status: PlanStatus::Success,
            path: vec![l.cell(cur)],
            length_m: 0.0,
            cost: 0.0,
            expansions: 0,
            stages: Vec::new(),
        };
        if !seg.allowed[cur] {
            let i = l.n * l.cell(cur).row as usize + l.cell(cur).col as usize;
            let forbids = p.segments[si]
                .forbidden
                .iter()
                .filter(|f| f.cells.to_mask(l.n)[i])
                .map(|f| f.origin)
                .collect();
            failure = Some(PlanFailure::StartInForbidden {
                segment: si,
                start: l.cell(cur),
                forbids,
            });
            planned.status = PlanStatus::Failed;
            segments.push(planned);
            break;
        }
        let budget = p.profile.max_expansions;
        let mut used = 0u64;
        for (ti, st) in seg.stages.iter().enumerate() {
            if st.goal[cur] {
                planned.stages.push(PlannedStage {
                    role: st.role,
                    origin: st.origin,
                    endpoint: l.cell(cur),
                    cost: 0.0,
                    expansions: 0,
                });
                continue;
            }
            let space = Space {
                layout: l,
                traversable: if p.profile.avoid_corners {
                    &seg.allowed
                } else {
                    &prep.traversable
                },
                allowed: &seg.allowed,
                phi: seg.phi.as_deref().map(Vec::as_slice),
            };
            let q = Query {
                start: cur,
                goal: &st.goal,
                heuristic: st.heuristic(),
                smooth: st.smooth(p.profile.smoothness_weight),
                initial_heading: heading,
                budget: if budget == 0 {
                    0
                } else {
                    budget.saturating_sub(used).max(1)
                },
            };
            match astar.search(space, q) {
                Outcome::Found(f) => {
                    used += f.expansions;
                    planned.expansions += f.expansions;
                    planned.cost += f.cost;
                    let cells: Vec<_> = f.path.iter().map(|&i| l.cell(i)).collect();
                    append_path(&mut planned.path, &cells);
                    cur = *f.path.last().unwrap_or(&cur);
                    heading = f.final_heading;
                    planned.stages.push(PlannedStage {
                        role: st.role,
                        origin: st.origin,
                        endpoint: l.cell(cur),
                        cost: f.cost,
                        expansions: f.expansions,
                    });
                }
                Outcome::Exhausted { expansions } => {
                    planned.expansions += expansions;
                    failure = Some(compile::explain_unreachable(p, prep, seg, si, ti, cur));
                }
                Outcome::OverBudget { expansions } => {
                    planned.expansions += expansions;
                    failure = Some(PlanFailure::BudgetExceeded {
                        segment: si,
                        stage: ti,
                        origin: st.origin,
                        budget,
                    });
                }
            }
            if failure.is_some() {
                planned.status = PlanStatus::Failed;
                planned.length_m = path_length_m(&planned.path, p.resolution);
                total_exp += planned.expansions;
                segments.push(planned);
                break 'segments;
            }
        }
        planned.length_m = path_length_m(&planned.path, p.resolution);
        total_cost += planned.cost;
        total_exp += planned.expansions;
        append_path(&mut trajectory, &planned.path);
        segments.push(planned);
        if release {
            cache.release(si, prep);
        }
    }
    let status = if failure.is_some() {
        PlanStatus::Failed
    } else {
        PlanStatus::Success
    };
    PlannedRoute {
        planner: name.into(),
        profile: profile.clone(),
        status,
        length_m: path_length_m(&trajectory, p.resolution),
        trajectory,
        cost: total_cost,
        expansions: total_exp,
        segments,
        failure,
    }
}
