//! Why a plan failed, precisely enough for the compiler to point at the `.m2r` span responsible:
//! every reason names the segment and stage it happened in and the [`Origin`]s of the stage target
//! and of the avoid regions that made it so. Codes are the `E07xx` planning range of the diagnostic
//! registry.

use crate::problem::Origin;
use m2rc_stdlib::grid::Cell;
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, thiserror::Error)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum PlanFailure {
    /// The start cell is outside the grid or not traversable.
    #[error("the start cell [{}, {}] is not traversable", start.row, start.col)]
    StartBlocked { start: Cell },
    /// The route is inside an avoid region when a segment begins.
    #[error("segment {segment} starts at [{}, {}], inside a region it must avoid", start.row, start.col)]
    StartInForbidden {
        segment: usize,
        start: Cell,
        forbids: Vec<Origin>,
    },
    /// The stage target has no traversable cell (and no usable fallback).
    #[error("stage {stage} of segment {segment}: the target has no traversable cell")]
    TargetEmpty {
        segment: usize,
        stage: usize,
        origin: Origin,
    },
    /// Every traversable target cell is inside an active avoid region.
    #[error(
        "stage {stage} of segment {segment}: every reachable cell of the target is inside a region to avoid"
    )]
    GoalBlocked {
        segment: usize,
        stage: usize,
        origin: Origin,
        forbids: Vec<Origin>,
    },
    /// No path exists even ignoring the avoid regions (the target is in a disconnected part).
    #[error("stage {stage} of segment {segment}: the target cannot be reached from [{}, {}]", from.row, from.col)]
    Unreachable {
        segment: usize,
        stage: usize,
        origin: Origin,
        from: Cell,
    },
    /// A path exists, but every one crosses an active avoid region. `forbids` lists the avoid
    /// regions whose removal alone reconnects the target, or all active ones when no single one does.
    #[error(
        "stage {stage} of segment {segment}: the target is unreachable without entering a region to avoid"
    )]
    UnreachableUnderAvoids {
        segment: usize,
        stage: usize,
        origin: Origin,
        from: Cell,
        forbids: Vec<Origin>,
    },
    /// The expansion budget ran out before the target was reached.
    #[error("stage {stage} of segment {segment}: search budget of {budget} expansions exhausted")]
    BudgetExceeded {
        segment: usize,
        stage: usize,
        origin: Origin,
        budget: u64,
    },
    /// The problem itself is malformed (mask sizes, weights); a caller bug or a bad input file.
    #[error("invalid planning problem: {message}")]
    InvalidProblem { message: String },
}

impl PlanFailure {
    /// The stable diagnostic code.
    pub fn code(&self) -> &'static str {
        match self {
            PlanFailure::StartBlocked { .. } => "E0701",
            PlanFailure::StartInForbidden { .. } => "E0702",
            PlanFailure::TargetEmpty { .. } => "E0703",
            PlanFailure::GoalBlocked { .. } => "E0704",
            PlanFailure::Unreachable { .. } => "E0705",
            PlanFailure::UnreachableUnderAvoids { .. } => "E0706",
            PlanFailure::BudgetExceeded { .. } => "E0707",
            PlanFailure::InvalidProblem { .. } => "E0708",
        }
    }

    /// The reference planner's name for the same failure, for reports that compare the two.
    pub fn reference_code(&self) -> &'static str {
        match self {
            PlanFailure::StartBlocked { .. } => "START_UNRESOLVED",
            PlanFailure::StartInForbidden { .. } => "START_IN_FORBIDDEN_REGION",
            PlanFailure::TargetEmpty { .. } => "EMPTY_TARGET_REGION",
            PlanFailure::GoalBlocked { .. } => "GOAL_BLOCKED_BY_HARD_CONSTRAINT",
            PlanFailure::Unreachable { .. }
            | PlanFailure::UnreachableUnderAvoids { .. }
            | PlanFailure::BudgetExceeded { .. }
            | PlanFailure::InvalidProblem { .. } => "NO_FEASIBLE_PATH",
        }
    }

    /// The segment the failure happened in, when it belongs to one.
    pub fn segment(&self) -> Option<usize> {
        match self {
            PlanFailure::StartInForbidden { segment, .. }
            | PlanFailure::TargetEmpty { segment, .. }
            | PlanFailure::GoalBlocked { segment, .. }
            | PlanFailure::Unreachable { segment, .. }
            | PlanFailure::UnreachableUnderAvoids { segment, .. }
            | PlanFailure::BudgetExceeded { segment, .. } => Some(*segment),
            PlanFailure::StartBlocked { .. } | PlanFailure::InvalidProblem { .. } => None,
        }
    }

    /// The origin of the stage target involved (the primary span of a diagnostic).
    pub fn target(&self) -> Option<Origin> {
        match self {
            PlanFailure::TargetEmpty { origin, .. }
            | PlanFailure::GoalBlocked { origin, .. }
            | PlanFailure::Unreachable { origin, .. }
            | PlanFailure::UnreachableUnderAvoids { origin, .. }
            | PlanFailure::BudgetExceeded { origin, .. } => Some(*origin),
            _ => None,
        }
    }

    /// The avoid regions responsible (secondary spans of a diagnostic).
    pub fn forbids(&self) -> &[Origin] {
        match self {
            PlanFailure::StartInForbidden { forbids, .. }
            | PlanFailure::GoalBlocked { forbids, .. }
            | PlanFailure::UnreachableUnderAvoids { forbids, .. } => forbids,
            _ => &[],
        }
    }
}
