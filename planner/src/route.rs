//! The planner's output, as written to JSON by `m2rc plan` and read by the benchmark.

use crate::failure::PlanFailure;
use crate::problem::{Origin, StageRole};
use m2rc_stdlib::grid::Cell;
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PlanStatus {
    Success,
    Failed,
    /// Not planned because an earlier segment failed.
    Skipped,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlannedStage {
    pub role: StageRole,
    pub origin: Origin,
    /// Where the stage ended (its first goal cell reached).
    pub endpoint: Cell,
    /// Cost of the stage path, including Φ and turn penalties.
    pub cost: f64,
    pub expansions: u64,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlannedSegment {
    pub index: usize,
    pub status: PlanStatus,
    /// From the segment start to its endpoint, both included (the completed stages only when the
    /// segment failed).
    pub path: Vec<Cell>,
    pub length_m: f64,
    pub cost: f64,
    pub expansions: u64,
    pub stages: Vec<PlannedStage>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlannedRoute {
    /// `sequential`, `global` or `shortest`.
    pub planner: String,
    /// Name of the cost profile.
    pub profile: String,
    pub status: PlanStatus,
    /// The whole route, joints not repeated. On failure: the route up to the failing segment, or
    /// just the start when that is empty (as the reference evaluator expects).
    pub trajectory: Vec<Cell>,
    pub length_m: f64,
    pub cost: f64,
    pub expansions: u64,
    pub segments: Vec<PlannedSegment>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub failure: Option<PlanFailure>,
}

impl PlannedRoute {
    pub fn is_success(&self) -> bool {
        self.status == PlanStatus::Success
    }

    pub(crate) fn failed(planner: &str, profile: &str, start: Cell, failure: PlanFailure) -> Self {
        PlannedRoute {
            planner: planner.into(),
            profile: profile.into(),
            status: PlanStatus::Failed,
            trajectory: vec![start],
            length_m: 0.0,
            cost: 0.0,
            expansions: 0,
            segments: Vec::new(),
            failure: Some(failure),
        }
    }
}

/// Length of a cell path in metres (1 or √2 cells per step).
pub fn path_length_m(path: &[Cell], resolution: f64) -> f64 {
    path.windows(2).map(|w| w[0].dist(w[1])).sum::<f64>() * resolution
}

/// Appends `next` to `acc`, dropping `next`'s first cell when it repeats `acc`'s last.
pub(crate) fn append_path(acc: &mut Vec<Cell>, next: &[Cell]) {
    let skip = usize::from(!acc.is_empty() && next.first() == acc.last());
    acc.extend_from_slice(&next[skip.min(next.len())..]);
}
