//! Per-episode preparation shared by the metrics: validated regions, the ordered must-pass
//! list, and which must-avoids are active on which route stage.
//!
//! Region errors are kept per constraint and raised only when a metric actually tests a point
//! against that region, because that is when the reference raises.

use super::geometry::{Geom, RegionSpec, compile};
use crate::episode::{ConstraintKind, HardConstraint};

/// An error that stops evaluation (the reference raises); the runner then applies the
/// worst-case policy ([`super::evaluate::worst_case_metrics`]).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EvalError {
    /// A constraint whose region or fields the metrics cannot use.
    #[error("{field}: {message}")]
    Constraint { field: String, message: String },
    /// An episode-level problem (too few must-pass regions, ...).
    #[error("{0}")]
    Episode(String),
    /// The map lacks something a metric needs.
    #[error("map: {0}")]
    Map(String),
}

pub(crate) struct HardContext<'e> {
    pub hard: &'e [HardConstraint],
    geoms: Vec<Result<Geom, String>>,
    /// Must-pass indices sorted by `(order, index)`, a missing order counting as index + 1.
    pub ordered: Vec<usize>,
}

impl<'e> HardContext<'e> {
    pub fn new(hard: &'e [HardConstraint]) -> Self {
        let geoms = hard
            .iter()
            .map(|c| compile(RegionSpec::of_hard(c)))
            .collect();
        let mut ordered: Vec<(f64, usize)> = hard
            .iter()
            .enumerate()
            .filter(|(_, c)| c.kind == ConstraintKind::MustPass)
            .map(|(i, c)| (c.order.map_or((i + 1) as f64, |o| o as f64), i))
            .collect();
        ordered.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        HardContext {
            hard,
            geoms,
            ordered: ordered.into_iter().map(|(_, i)| i).collect(),
        }
    }

    /// The validated region of hard constraint `i`.
    pub fn geom(&self, i: usize) -> Result<&Geom, EvalError> {
        self.geoms[i].as_ref().map_err(|m| EvalError::Constraint {
            field: format!("hard_constraints[{i}]"),
            message: m.clone(),
        })
    }

    pub fn is_avoid(&self, i: usize) -> bool {
        self.hard[i].kind == ConstraintKind::MustAvoid
    }

    /// Must-avoid whose scope is not stage-restricted.
    pub fn is_global_avoid(&self, i: usize) -> bool {
        self.is_avoid(i) && !self.hard[i].is_scoped()
    }

    /// The identifier the reference reports: `constraint_id`, else a positional fallback.
    pub fn id_or(&self, i: usize, fallback: impl FnOnce() -> String) -> String {
        self.hard[i].constraint_id.clone().unwrap_or_else(fallback)
    }

    /// Fails unless there is a record region plus at least one target.
    pub fn require_targets(&self, what: &str) -> Result<(), EvalError> {
        if self.ordered.len() < 2 {
            return Err(EvalError::Episode(format!(
                "{what} requires at least one scored must-pass region after the first record region \
                 (found {} must-pass constraints)",
                self.ordered.len()
            )));
        }
        Ok(())
    }
}

/// Stage activity as HCS progress decides it: a numeric `to_order` must match the goal's order,
/// and `from_order` the previous goal's (a missing `from_order` never matches, since the record
/// region always precedes).
pub(crate) fn active_for_hcs(
    avoid: &HardConstraint,
    prev: &HardConstraint,
    goal: &HardConstraint,
) -> bool {
    let Some(scope) = avoid.scope.as_ref().filter(|s| s.is_between()) else {
        return true;
    };
    if let Some(to) = scope.to_order
        && goal.order != Some(to)
    {
        return false;
    }
    match scope.from_order {
        None => false,
        Some(from) => prev.order == Some(from),
    }
}

/// Stage activity as segment-wise SPL decides it: `to_order` must equal the goal's order even
/// when both are missing, and `from_order` the previous goal's.
pub(crate) fn active_for_spl(
    avoid: &HardConstraint,
    prev: &HardConstraint,
    goal: &HardConstraint,
) -> bool {
    let Some(scope) = avoid.scope.as_ref().filter(|s| s.is_between()) else {
        return true;
    };
    if scope.to_order != goal.order {
        return false;
    }
    match scope.from_order {
        None => false,
        Some(from) => prev.order == Some(from),
    }
}
