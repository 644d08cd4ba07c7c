//! Checks of an episode file that serde's types cannot express: cells inside the map (and never
//! negative), 1-based orders, known preference types. Planning and `suite build` refuse such a
//! file, so a bad file gets a message naming the field instead of a silent HCS 0 or a region
//! quietly cut to the grid. The reference evaluator scores these files all the same (an
//! out-of-grid cell is left out, an unknown preference is `unsupported_preference`), so `eval`
//! does too and reports each problem as a warning; `eval --strict` refuses them.

use crate::episode::{CellRc, Episode, EpisodeError, PreferenceType};

/// The `preference_type` values the evaluator scores, for a message.
pub fn known_preferences() -> String {
    crate::episode::PREFERENCE_TYPE_NAMES
        .iter()
        .map(|(name, _)| *name)
        .collect::<Vec<_>>()
        .join(", ")
}

/// Something in an episode file that m2rc's own tools refuse but the reference evaluator scores
/// anyway; `reference` says how the reference treats it, for a warning.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EpisodeProblem {
    /// The field, e.g. `soft_constraints[0].cells[3]`.
    pub path: String,
    pub message: String,
    /// What the reference evaluator does with it when it scores the episode all the same;
    /// `None` when the reference refuses it too.
    pub reference: Option<&'static str>,
}

impl EpisodeProblem {
    /// The problem as the error a strict command refuses the file with.
    pub fn into_error(self, file: &str) -> EpisodeError {
        EpisodeError::Field {
            file: file.to_string(),
            path: self.path,
            message: self.message,
        }
    }

    /// A one-line warning for a command that scores the episode anyway (`None` for a problem
    /// the reference refuses too).
    pub fn warning(&self, file: &str) -> Option<String> {
        let reference = self.reference?;
        Some(format!(
            "warning: {file}: field `{}`: {}; scored as the reference evaluator scores it ({reference}); --strict refuses it",
            self.path, self.message
        ))
    }
}

/// The reference's treatment of a cell outside the grid, by the field it is in.
fn outside_cell_treatment(path: &str) -> Option<&'static str> {
    Some(if path.contains("path_shape_annotation") {
        // The annotation schema requires in-grid points; the evaluator raises on the episode.
        return None;
    } else if path.starts_with("hard_constraints") {
        "a route inside the map never reaches it, and a target left without cells in the map has no shortest route"
    } else if path.contains("reference_region") {
        "distances are measured to it where it lies"
    } else if path.contains("trajectory") {
        "it is compared with the route where it lies"
    } else if path.starts_with("soft_constraints") {
        "it is left out of the region, as an empty region is"
    } else {
        "the evaluator does not read it"
    })
}

/// Checks `ep` (read from `file`) for use on an `n` x `n` map; without `n` only what needs no
/// map (negative cells and orders, preference types) is checked. This is the strict check that
/// planning, `suite build` and `eval --strict` use: the first problem is an error.
pub fn check_episode(ep: &Episode, n: Option<usize>, file: &str) -> Result<(), EpisodeError> {
    match episode_problems(ep, n).into_iter().next() {
        Some(p) => Err(p.into_error(file)),
        None => Ok(()),
    }
}

/// Every problem [`check_episode`] refuses, in file order. None of them stops the reference
/// evaluator, so `eval` scores such an episode and reports these as warnings.
pub fn episode_problems(ep: &Episode, n: Option<usize>) -> Vec<EpisodeProblem> {
    let mut out = Vec::new();
    let cells = |cells: &[CellRc], path: &str, out: &mut Vec<EpisodeProblem>| {
        for (i, c) in cells.iter().enumerate() {
            let path = format!("{path}[{i}]");
            let message = if c[0] < 0 || c[1] < 0 {
                format!(
                    "cell [{}, {}] is negative; cells are [row, col] from 0",
                    c[0], c[1]
                )
            } else if let Some(n) = n
                && (c[0] as u64 >= n as u64 || c[1] as u64 >= n as u64)
            {
                format!(
                    "cell [{}, {}] is outside the {n}x{n} map (rows and columns 0..{}); is this the episode's map?",
                    c[0],
                    c[1],
                    n.saturating_sub(1)
                )
            } else {
                continue;
            };
            let reference = outside_cell_treatment(&path);
            out.push(EpisodeProblem {
                path,
                message,
                reference,
            });
        }
    };
    let order = |o: Option<i64>, path: String, out: &mut Vec<EpisodeProblem>| {
        if let Some(o) = o
            && o < 1
        {
            out.push(EpisodeProblem {
                path,
                message: format!(
                    "order {o} is not a 1-based position (must-pass orders are 1, 2, 3, ...)"
                ),
                reference: Some("orders are only compared and sorted"),
            });
        }
    };
    let size = |x: Option<f64>, path: String, out: &mut Vec<EpisodeProblem>| {
        if let Some(x) = x
            && (!x.is_finite() || x < 0.0)
        {
            out.push(EpisodeProblem {
                path,
                message: format!("{x} is not a non-negative size in cells"),
                reference: Some(
                    "a size the region's shape does not use is ignored; one it uses is an evaluation error",
                ),
            });
        }
    };
    if let Some(p) = &ep.start_pose
        && let (Some(r), Some(c)) = (p.row, p.col)
    {
        cells(&[[r, c]], "start_pose", &mut out);
    }
    if let Some(t) = &ep.human_expert_trajectory {
        cells(t, "human_expert_trajectory", &mut out);
    }
    for (i, h) in ep.hard_constraints.iter().enumerate() {
        let at = format!("hard_constraints[{i}]");
        order(h.order, format!("{at}.order"), &mut out);
        if let Some(s) = &h.scope {
            order(s.from_order, format!("{at}.scope.from_order"), &mut out);
            order(s.to_order, format!("{at}.scope.to_order"), &mut out);
        }
        size(h.radius, format!("{at}.radius"), &mut out);
        size(h.width, format!("{at}.width"), &mut out);
        size(h.height, format!("{at}.height"), &mut out);
        if let Some(c) = &h.cells {
            cells(c, &format!("{at}.cells"), &mut out);
        }
    }
    for (i, s) in ep.soft_constraints.iter().enumerate() {
        let at = format!("soft_constraints[{i}]");
        if let Some(t) = &s.preference_type
            && PreferenceType::parse(t).is_none()
        {
            out.push(EpisodeProblem {
                path: format!("{at}.preference_type"),
                message: format!(
                    "unknown preference type `{t}` (known: {})",
                    known_preferences()
                ),
                reference: Some("status `unsupported_preference`, no value, the rest scored"),
            });
        }
        if let Some(sc) = &s.scope {
            order(sc.from_order, format!("{at}.scope.from_order"), &mut out);
            order(sc.to_order, format!("{at}.scope.to_order"), &mut out);
        }
        size(s.radius, format!("{at}.radius"), &mut out);
        if let Some(c) = &s.cells {
            cells(c, &format!("{at}.cells"), &mut out);
        }
        if let Some(r) = &s.reference_region
            && let Some(c) = &r.cells
        {
            cells(c, &format!("{at}.reference_region.cells"), &mut out);
        }
        for (k, r) in s.reference_regions.iter().flatten().enumerate() {
            if let Some(c) = &r.cells {
                cells(c, &format!("{at}.reference_regions[{k}].cells"), &mut out);
            }
        }
        if let Some(t) = &s.reference_trajectory {
            cells(t, &format!("{at}.reference_trajectory"), &mut out);
        }
        if let Some(t) = s
            .path_shape_annotation
            .as_ref()
            .and_then(|a| a.shape_reference_trajectory.as_ref())
        {
            cells(
                t,
                &format!("{at}.path_shape_annotation.shape_reference_trajectory"),
                &mut out,
            );
        }
    }
    out
}

/// Whether [`integral_floats_to_ints`] would change anything in `value`.
pub fn has_integral_float(value: &serde_json::Value) -> bool {
    use serde_json::Value;
    match value {
        Value::Number(n) if n.is_f64() => n
            .as_f64()
            .is_some_and(|x| x.fract() == 0.0 && x.abs() < 9.0e15),
        Value::Array(a) => a.iter().any(has_integral_float),
        Value::Object(o) => o.values().any(has_integral_float),
        _ => false,
    }
}

/// Writes every float of `value` that is a whole number (`223.0`) as an integer, as the
/// reference tools' Python writer sometimes emits cells; other numbers are unchanged.
pub fn integral_floats_to_ints(value: &mut serde_json::Value) {
    use serde_json::Value;
    match value {
        Value::Number(n) if n.is_f64() => {
            if let Some(x) = n.as_f64()
                && x.fract() == 0.0
                && x.abs() < 9.0e15
            {
                *value = Value::from(x as i64);
            }
        }
        Value::Array(a) => a.iter_mut().for_each(integral_floats_to_ints),
        Value::Object(o) => o.values_mut().for_each(integral_floats_to_ints),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ep(text: &str) -> Episode {
        Episode::from_json_str(text, "ep.json").unwrap()
    }

    #[test]
    fn bad_cells_orders_and_types_are_named() {
        let e = ep(
            r#"{"hard_constraints": [{"kind": "must_pass", "shape": "freeform", "order": 1, "cells": [[3, 400]]}]}"#,
        );
        check_episode(&e, None, "ep.json").unwrap();
        let m = check_episode(&e, Some(100), "ep.json")
            .unwrap_err()
            .to_string();
        assert!(
            m.contains("hard_constraints[0].cells[0]") && m.contains("outside the 100x100"),
            "{m}"
        );
        let e = ep(
            r#"{"hard_constraints": [{"kind": "must_pass", "shape": "freeform", "order": -1, "cells": []}]}"#,
        );
        let m = check_episode(&e, None, "ep.json").unwrap_err().to_string();
        assert!(m.contains("order -1"), "{m}");
        let e = ep(r#"{"soft_constraints": [{"preference_type": "nearish"}]}"#);
        let m = check_episode(&e, None, "ep.json").unwrap_err().to_string();
        assert!(m.contains("unknown preference type `nearish`"), "{m}");
    }

    #[test]
    fn every_problem_is_listed_with_what_the_reference_does_with_it() {
        let e = ep(r#"{"soft_constraints": [
            {"preference_type": "near_preference", "cells": [[0, 1], [0, 9]],
             "reference_region": {"cells": [[7, 0]]}},
            {"preference_type": "move_smoothness"},
            {"preference_type": "path_shape_preference", "path_shape_annotation":
                {"shape_reference_trajectory": [[0, 0], [0, 8]]}}]}"#);
        let p = episode_problems(&e, Some(5));
        let paths: Vec<&str> = p.iter().map(|p| p.path.as_str()).collect();
        assert_eq!(
            paths,
            [
                "soft_constraints[0].cells[1]",
                "soft_constraints[0].reference_region.cells[0]",
                "soft_constraints[1].preference_type",
                "soft_constraints[2].path_shape_annotation.shape_reference_trajectory[1]",
            ]
        );
        assert!(p[0].reference.unwrap().contains("left out of the region"));
        assert!(p[1].reference.unwrap().contains("measured to it"));
        assert!(p[2].reference.unwrap().contains("unsupported_preference"));
        // The annotation schema wants in-grid points: the reference refuses the file too.
        assert_eq!(p[3].reference, None);
        assert_eq!(p[3].warning("ep.json"), None);
        let w = p[2].warning("ep.json").unwrap();
        assert!(
            w.starts_with("warning: ep.json: field `soft_constraints[1].preference_type`"),
            "{w}"
        );
        // The strict check refuses the first.
        let m = check_episode(&e, Some(5), "ep.json")
            .unwrap_err()
            .to_string();
        assert!(m.contains("soft_constraints[0].cells[1]"), "{m}");
    }

    #[test]
    fn integral_floats_are_read_as_cells() {
        let e = ep(
            r#"{"hard_constraints": [{"kind": "must_pass", "shape": "freeform", "order": 1.0, "cells": [[223.0, 117.0]]}]}"#,
        );
        assert_eq!(
            e.hard_constraints[0].cells.as_deref(),
            Some(&[[223, 117]][..])
        );
        // The written file keeps the source spelling.
        assert_eq!(
            e.to_value()["hard_constraints"][0]["cells"][0][0].as_f64(),
            Some(223.0)
        );
        assert!(e.to_value()["hard_constraints"][0]["cells"][0][0].is_f64());
    }
}
