//! Why a plan failed, precisely enough for the compiler to point at the `.m2r` span responsible:
//! every reason names the segment and stage it happened in and the [`Origin`]s of the stage target
//! and of the avoid regions that made it so. Codes are the `E07xx` planning range of the diagnostic
//! registry.
//!
//! The planner numbers segments and their planned parts from 0; the messages speak the user's
//! language instead: stages count from 1, as `m2rc compile` lists them, and a stage's planned part
//! is named by what it is (its destination, a must-pass place, a waypoint of its path shape).

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
    #[error("stage {} starts at [{}, {}], inside a region it must avoid", segment + 1, start.row, start.col)]
    StartInForbidden {
        segment: usize,
        start: Cell,
        forbids: Vec<Origin>,
    },
    /// The stage target has no traversable cell (and no usable fallback).
    #[error("{} has no traversable cell", part(*segment, origin))]
    TargetEmpty {
        segment: usize,
        stage: usize,
        origin: Origin,
    },
    /// Every traversable target cell is inside an active avoid region.
    #[error("every reachable cell of {} is inside a region to avoid", part(*segment, origin))]
    GoalBlocked {
        segment: usize,
        stage: usize,
        origin: Origin,
        forbids: Vec<Origin>,
    },
    /// No path exists even ignoring the avoid regions (the target is in a disconnected part).
    #[error("{} cannot be reached from [{}, {}]", part(*segment, origin), from.row, from.col)]
    Unreachable {
        segment: usize,
        stage: usize,
        origin: Origin,
        from: Cell,
    },
    /// A path exists, but every one crosses an active avoid region. `forbids` lists the avoid
    /// regions whose removal alone reconnects the target, or all active ones when no single one does.
    #[error("{} is unreachable without entering a region to avoid", part(*segment, origin))]
    UnreachableUnderAvoids {
        segment: usize,
        stage: usize,
        origin: Origin,
        from: Cell,
        forbids: Vec<Origin>,
    },
    /// The expansion budget ran out before the target was reached.
    #[error("search budget of {budget} expansions exhausted on the way to {}", part(*segment, origin))]
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

/// The planned part of segment `segment` that `origin` names, as the summary counts stages.
fn part(segment: usize, origin: &Origin) -> String {
    let n = segment + 1;
    match origin {
        Origin::Pass { index, .. } => format!("must-pass place {} of stage {n}", index + 1),
        Origin::Constraint { part, .. } => {
            format!("waypoint {} of stage {n}'s path shape", part + 1)
        }
        Origin::Target { .. } | Origin::Unknown => format!("the destination of stage {n}"),
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Stages count from 1 as the summary lists them; the planner's own part numbers stay inside.
    #[test]
    fn messages_count_stages_as_the_summary_does() {
        let f = PlanFailure::UnreachableUnderAvoids {
            segment: 0,
            stage: 0,
            origin: Origin::Target { stage: 0 },
            from: Cell::new(3, 4),
            forbids: vec![],
        };
        assert_eq!(
            f.to_string(),
            "the destination of stage 1 is unreachable without entering a region to avoid"
        );
        let f = PlanFailure::TargetEmpty {
            segment: 1,
            stage: 0,
            origin: Origin::Pass { stage: 1, index: 0 },
        };
        assert_eq!(
            f.to_string(),
            "must-pass place 1 of stage 2 has no traversable cell"
        );
        let f = PlanFailure::StartInForbidden {
            segment: 2,
            start: Cell::new(1, 1),
            forbids: vec![],
        };
        assert!(f.to_string().starts_with("stage 3 starts at"), "{f}");
    }
}
