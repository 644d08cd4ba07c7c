//! `go S` and `pass S` on a set: "proceed to a box in the bedroom" names no box, so the stage's
//! goal is every member at once (`PlaceKind::AnyOf`) and the planner reaches whichever member
//! makes the route cheapest, in one search with the stage's constraints. Grounding never picks the
//! member for the plan; it only needs one for what comes after the stage (`here`, `visited()`,
//! the next stage's loops): before planning the member nearest by travel (a nominal binding, as
//! for the other route-dependent places), then the member the planned route reached.

use super::codes;
use super::value::PlaceVal;
use super::{Grounder, Problem};
use crate::ir::{Place, PlaceKind};
use m2rc_grammar::ast::Span;

/// The member of a set destination (`pass: None`) or must-pass (`pass: Some(i)`, the index among
/// the stage's passes) that a planned route reached; the pipeline hands these back to grounding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Chosen {
    pub stage: usize,
    pub pass: Option<usize>,
    pub member: usize,
}

/// A grounded `go`/`pass` operand: the IR place and the value standing for it afterwards.
pub(super) struct Goal {
    pub ir: Place,
    pub value: PlaceVal,
}

impl Grounder<'_, '_> {
    /// The goal of `go`/`pass` (`word`) over `places`: the place itself when there is one, every
    /// member as one `AnyOf` goal when there are several, and an error naming the span when the
    /// set is empty.
    pub(super) fn set_goal(
        &mut self,
        word: &str,
        span: Span,
        places: Vec<PlaceVal>,
        stage: usize,
        pass: Option<usize>,
    ) -> Option<Goal> {
        match places.len() {
            0 => {
                self.problems.push(
                    Problem::error(
                        codes::EMPTY_REFERENCE,
                        span,
                        format!("`{word}` has no place to reach: the set is empty on this map"),
                    )
                    .help("check the set's filters against the map (`m2rc map info`), or name another place"),
                );
                None
            }
            1 => {
                let value = places.into_iter().next()?;
                Some(Goal {
                    ir: self.ir_place(&value),
                    value,
                })
            }
            _ => {
                let members: Vec<Place> = places.iter().map(|p| self.ir_place(p)).collect();
                let chosen = self
                    .chosen
                    .iter()
                    .find(|c| c.stage == stage && c.pass == pass)
                    .map(|c| c.member)
                    .filter(|&m| m < places.len());
                let member = match chosen {
                    Some(m) => m,
                    None => self.nearest_by_travel(&places),
                };
                let against_route = chosen.is_some();
                self.bindings.push(crate::ir::RouteBinding {
                    function: word.into(),
                    resolved: members[member].label.clone(),
                    against: if against_route {
                        crate::ir::BoundAgainst::Planned
                    } else {
                        crate::ir::BoundAgainst::Nominal
                    },
                    span: crate::ir::SourceSpan::new(self.source, span),
                });
                let labels: Vec<&str> = members.iter().map(|m| m.label.as_str()).collect();
                let label = if labels.len() <= 3 {
                    format!("any of {}", labels.join(", "))
                } else {
                    format!(
                        "any of {}, {}, {} and {} more",
                        labels[0],
                        labels[1],
                        labels[2],
                        labels.len() - 3
                    )
                };
                let cells: Vec<_> = members
                    .iter()
                    .flat_map(|m| m.cells.cells().iter().copied())
                    .collect();
                Some(Goal {
                    ir: Place {
                        kind: PlaceKind::AnyOf { members },
                        label,
                        cells: crate::ir::CellSet::new(cells),
                    },
                    value: places[member].clone(),
                })
            }
        }
    }

    /// The member nearest by travel from where the stage starts (the first among equals, and the
    /// first when none can be reached): what the stage stands for until a route is planned.
    fn nearest_by_travel(&mut self, places: &[PlaceVal]) -> usize {
        let here = self.here.clone();
        let field = self.travel_from(&here);
        let mut best = (f64::INFINITY, 0);
        for (i, p) in places.iter().enumerate() {
            let d = field
                .to(&self.q.band(p.target(self.q)))
                .unwrap_or(f64::INFINITY);
            if d < best.0 {
                best = (d, i);
            }
        }
        best.1
    }
}
