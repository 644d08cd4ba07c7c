//! Whether a route could be driven on its map. The reference evaluator scores any list of cells
//! (a two-point route straight through the walls can score HCS 1 and SPL 1), and m2rc keeps
//! those scores so that its numbers stay the reference's; but every path that scores a route
//! (`eval`, `bench run`, `bench import`) also records this check, and `bench report` refuses to
//! rank a method with invalid routes unless told to.
//!
//! A route is valid when every step moves to one of the 8 neighbouring cells (or stays), every
//! point is a free cell, and no diagonal step cuts a corner. The corner rule is the one the
//! planners and the evaluator's oracle (SPL's L*) move by: [`diagonal_corners`].

use crate::metrics::map::EvalMap;
use serde::{Deserialize, Serialize};
use std::fmt;

/// The two cells a diagonal step from `from` to `to` passes between, or `None` when the step is
/// not a diagonal move to a neighbour. A diagonal step is legal only when both are free: the
/// rule of the planners (`planner::astar`), the evaluator's legal moves (SPL's L*) and the suite
/// generator's paths, and the one [`route_validity`] checks.
pub fn diagonal_corners(from: [i64; 2], to: [i64; 2]) -> Option<[[i64; 2]; 2]> {
    let (dr, dc) = (to[0] - from[0], to[1] - from[1]);
    (dr.abs() == 1 && dc.abs() == 1).then_some([[from[0] + dr, from[1]], [from[0], from[1] + dc]])
}

/// The first thing wrong with a route, for a message a user can find the place with. Steps are
/// numbered from 0: step `i` goes from point `i` to point `i + 1`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum RouteProblem {
    /// A step to a cell that is not one of the 8 neighbours: the route jumps.
    NonAdjacentStep {
        step: usize,
        from: [i64; 2],
        to: [i64; 2],
    },
    /// A point on a cell that is not free (a wall, furniture, outside the house).
    BlockedCell { point: usize, cell: [i64; 2] },
    /// A diagonal step between two cells where one of the two corner cells is not free.
    CornerCut {
        step: usize,
        from: [i64; 2],
        to: [i64; 2],
        corner: [i64; 2],
    },
}

impl fmt::Display for RouteProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let rc = |c: &[i64; 2]| format!("[{}, {}]", c[0], c[1]);
        match self {
            RouteProblem::NonAdjacentStep { step, from, to } => write!(
                f,
                "step {step} jumps from {} to {} ({} rows, {} columns), not to one of the 8 neighbouring cells",
                rc(from),
                rc(to),
                (to[0] - from[0]).abs(),
                (to[1] - from[1]).abs()
            ),
            RouteProblem::BlockedCell { point, cell } => {
                write!(f, "point {point} {} is not a free cell", rc(cell))
            }
            RouteProblem::CornerCut {
                step,
                from,
                to,
                corner,
            } => write!(
                f,
                "step {step} from {} to {} cuts the corner of the blocked cell {}",
                rc(from),
                rc(to),
                rc(corner)
            ),
        }
    }
}

/// The validity of one route: counts of each kind of problem and the first one.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RouteValidity {
    pub valid: bool,
    /// Steps (points - 1) of the route.
    pub steps: usize,
    pub non_adjacent_steps: usize,
    /// Points on cells that are not free.
    pub blocked_cells: usize,
    pub corner_cuts: usize,
    /// Whether the map has an occupancy layer; without one (a minimal map of `grid_size` and
    /// objects) free cells and corners cannot be checked, only adjacency.
    pub occupancy_checked: bool,
    /// The first problem along the route (`null` when valid).
    pub first_problem: Option<RouteProblem>,
}

impl RouteValidity {
    /// One line for a warning: the counts and the first problem ("1 corner cut; first: step
    /// 4 from [3, 4] to [4, 5] cuts the corner of the blocked cell [3, 5]").
    pub fn summary(&self) -> String {
        if self.valid {
            return "no problem".into();
        }
        let mut parts = Vec::new();
        let mut count = |n: usize, one: &str, many: &str| {
            if n > 0 {
                parts.push(format!("{n} {}", if n == 1 { one } else { many }));
            }
        };
        count(
            self.non_adjacent_steps,
            "step that is not to a neighbouring cell",
            "steps that are not to a neighbouring cell",
        );
        count(
            self.blocked_cells,
            "point on a blocked cell",
            "points on blocked cells",
        );
        count(self.corner_cuts, "corner cut", "corner cuts");
        let first = self
            .first_problem
            .as_ref()
            .map(|p| format!("; first: {p}"))
            .unwrap_or_default();
        format!("{}{first}", parts.join(", "))
    }
}

/// Checks `trajectory` on `map`. The one validity check: `eval`, the runner and `bench import`
/// all call it (through [`crate::report::score::score`] where they score).
pub fn route_validity(trajectory: &[[i64; 2]], map: &EvalMap) -> RouteValidity {
    let occupancy_checked = map.traversable().is_some();
    let free = |c: [i64; 2]| !occupancy_checked || map.is_traversable(c[0], c[1]);
    let mut v = RouteValidity {
        valid: true,
        steps: trajectory.len().saturating_sub(1),
        non_adjacent_steps: 0,
        blocked_cells: 0,
        corner_cuts: 0,
        occupancy_checked,
        first_problem: None,
    };
    let note = |v: &mut RouteValidity, p: RouteProblem| {
        v.valid = false;
        v.first_problem.get_or_insert(p);
    };
    for (i, &cell) in trajectory.iter().enumerate() {
        if !free(cell) {
            v.blocked_cells += 1;
            note(&mut v, RouteProblem::BlockedCell { point: i, cell });
        }
        let Some(&to) = trajectory.get(i + 1) else {
            break;
        };
        if (to[0] - cell[0]).abs() > 1 || (to[1] - cell[1]).abs() > 1 {
            v.non_adjacent_steps += 1;
            note(
                &mut v,
                RouteProblem::NonAdjacentStep {
                    step: i,
                    from: cell,
                    to,
                },
            );
        } else if let Some(corners) = diagonal_corners(cell, to)
            && let Some(&corner) = corners.iter().find(|&&c| !free(c))
        {
            v.corner_cuts += 1;
            note(
                &mut v,
                RouteProblem::CornerCut {
                    step: i,
                    from: cell,
                    to,
                    corner,
                },
            );
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// 4x4: obstacle at (1,1), everything else free.
    fn map() -> EvalMap {
        EvalMap::from_json(&json!({"grid_size": 4, "layers": {"occupancy":
            [[0, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0]]}}))
        .unwrap()
    }

    #[test]
    fn a_driven_route_is_valid_and_staying_put_is_a_legal_step() {
        let v = route_validity(&[[0, 0], [0, 1], [0, 1], [0, 2], [1, 3], [2, 2]], &map());
        assert!(v.valid, "{v:?}");
        assert_eq!(v.steps, 5);
        assert_eq!(v.first_problem, None);
        assert!(route_validity(&[], &map()).valid);
        assert!(route_validity(&[[3, 3]], &map()).valid);
    }

    #[test]
    fn jumps_blocked_cells_and_corner_cuts_are_counted_and_the_first_is_named() {
        // (0,0) -> (2,2) jumps; (1,1) is the obstacle; (1,2) -> (2,1) cuts its corner.
        let v = route_validity(&[[0, 0], [2, 2], [1, 1], [1, 2], [2, 1]], &map());
        assert!(!v.valid);
        assert_eq!(
            (v.non_adjacent_steps, v.blocked_cells, v.corner_cuts),
            (1, 1, 1)
        );
        assert_eq!(
            v.first_problem,
            Some(RouteProblem::NonAdjacentStep {
                step: 0,
                from: [0, 0],
                to: [2, 2]
            })
        );
        let s = v.summary();
        assert!(
            s.contains("1 step that is not to a neighbouring cell")
                && s.contains("1 point on a blocked cell")
                && s.contains("1 corner cut")
                && s.contains("step 0 jumps from [0, 0] to [2, 2]"),
            "{s}"
        );
        let v = route_validity(&[[1, 2], [2, 1]], &map());
        assert_eq!(
            v.first_problem,
            Some(RouteProblem::CornerCut {
                step: 0,
                from: [1, 2],
                to: [2, 1],
                corner: [1, 1]
            })
        );
        let v = route_validity(&[[0, 1], [1, 1]], &map());
        assert_eq!(
            v.first_problem,
            Some(RouteProblem::BlockedCell {
                point: 1,
                cell: [1, 1]
            })
        );
    }

    #[test]
    fn the_json_form_names_the_kind() {
        let v = route_validity(&[[0, 0], [3, 3]], &map());
        let j = serde_json::to_value(&v).unwrap();
        assert_eq!(j["valid"], false);
        assert_eq!(j["first_problem"]["kind"], "non_adjacent_step");
        assert_eq!(j["first_problem"]["to"], json!([3, 3]));
    }

    #[test]
    fn without_an_occupancy_layer_only_adjacency_is_checked() {
        let m = EvalMap::from_json(&json!({"grid_size": 4})).unwrap();
        let v = route_validity(&[[0, 0], [1, 1]], &m);
        assert!(v.valid && !v.occupancy_checked, "{v:?}");
        assert!(!route_validity(&[[0, 0], [2, 2]], &m).valid);
    }

    #[test]
    fn diagonal_corners_only_for_diagonal_neighbours() {
        assert_eq!(diagonal_corners([1, 1], [2, 2]), Some([[2, 1], [1, 2]]));
        assert_eq!(diagonal_corners([1, 1], [1, 2]), None);
        assert_eq!(diagonal_corners([1, 1], [3, 3]), None);
    }
}
