//! SayPlan's verifier and classical planner in one pass: each `goto` of the plan is checked
//! against the scene graph and the visible nodes, then driven with grid A* from where the last
//! one ended (an object through its nearest reachable approach cell, a room to its navigation
//! target). The first problem rejects the plan with feedback the next planning round reads.

use super::graph::{NodeKind, SceneGraph};
use crate::common::grid::{GridSearch, append_path};
use m2rc_stdlib::grid::Cell;
use std::collections::BTreeSet;

#[derive(Clone, Debug, PartialEq)]
pub struct Verdict {
    /// The route driven (the whole plan when accepted, up to the failing step when not).
    pub route: Vec<Cell>,
    /// `None` when the plan is accepted; else the feedback.
    pub rejection: Option<String>,
}

/// The node id of a `goto(<id>)` action, `None` for `done()`, or why the action is not one.
fn parse_action(a: &str) -> Result<Option<&str>, String> {
    let a = a.trim();
    if a == "done()" {
        return Ok(None);
    }
    a.strip_prefix("goto(")
        .and_then(|r| r.strip_suffix(')'))
        .map(str::trim)
        .filter(|id| !id.is_empty())
        .map(Some)
        .ok_or_else(|| format!("`{a}` is not a valid action; use goto(<node id>) or done()"))
}

pub fn verify(
    g: &SceneGraph,
    visible: &BTreeSet<usize>,
    grid: &mut GridSearch<'_>,
    plan: &[String],
) -> Verdict {
    let mut route = vec![g.start];
    let reject = |route: Vec<Cell>, why: String| Verdict {
        route,
        rejection: Some(why),
    };
    for (step, action) in plan.iter().enumerate() {
        let id = match parse_action(action) {
            Ok(Some(id)) => id,
            Ok(None) => break,
            Err(e) => return reject(route, format!("step {}: {e}", step + 1)),
        };
        let Some(i) = g.index(id) else {
            return reject(
                route,
                format!("step {}: `{id}` is not a node of the scene graph", step + 1),
            );
        };
        if !visible.contains(&i) {
            return reject(
                route,
                format!(
                    "step {}: `{id}` is not visible; expand its room before using it",
                    step + 1
                ),
            );
        }
        let goals: Vec<Cell> = match &g.nodes[i].kind {
            NodeKind::Scene => {
                return reject(
                    route,
                    format!(
                        "step {}: `{id}` is the whole scene, not a place to go",
                        step + 1
                    ),
                );
            }
            NodeKind::Agent => vec![g.start],
            NodeKind::Room { navigation_target } => match navigation_target {
                Some(t) => vec![*t],
                None => {
                    return reject(
                        route,
                        format!("step {}: room `{id}` has no free cell to go to", step + 1),
                    );
                }
            },
            NodeKind::Object { approach_cells, .. } => {
                if approach_cells.is_empty() {
                    return reject(
                        route,
                        format!(
                            "step {}: object `{id}` has no free cell beside it to approach",
                            step + 1
                        ),
                    );
                }
                approach_cells.clone()
            }
        };
        let at = *route.last().expect("non-empty");
        match grid.path_to_any(at, &goals, None) {
            Ok(leg) => append_path(&mut route, &leg.cells),
            Err(_) => {
                return reject(
                    route,
                    format!(
                        "step {}: no path to `{id}` from the previous position",
                        step + 1
                    ),
                );
            }
        }
    }
    Verdict {
        route,
        rejection: None,
    }
}
