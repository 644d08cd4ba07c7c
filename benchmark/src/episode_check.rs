//! Checks of an episode file that serde's types cannot express: cells inside the map (and never
//! negative), 1-based orders, known preference types. Run by every command that uses an episode
//! on a map, so a bad file gets a message naming the field instead of a silent HCS 0 or a
//! region quietly cut to the grid.

use crate::episode::{CellRc, Episode, EpisodeError, PreferenceType};

/// The `preference_type` values the evaluator scores, for a message.
pub fn known_preferences() -> String {
    crate::episode::PREFERENCE_TYPE_NAMES
        .iter()
        .map(|(name, _)| *name)
        .collect::<Vec<_>>()
        .join(", ")
}

/// Checks `ep` (read from `file`) for use on an `n` x `n` map; without `n` only what needs no
/// map (negative cells and orders, preference types) is checked.
pub fn check_episode(ep: &Episode, n: Option<usize>, file: &str) -> Result<(), EpisodeError> {
    let err = |path: String, message: String| EpisodeError::Field {
        file: file.to_string(),
        path,
        message,
    };
    let cells = |cells: &[CellRc], path: &str| -> Result<(), EpisodeError> {
        for (i, c) in cells.iter().enumerate() {
            if c[0] < 0 || c[1] < 0 {
                return Err(err(
                    format!("{path}[{i}]"),
                    format!(
                        "cell [{}, {}] is negative; cells are [row, col] from 0",
                        c[0], c[1]
                    ),
                ));
            }
            if let Some(n) = n
                && (c[0] as u64 >= n as u64 || c[1] as u64 >= n as u64)
            {
                return Err(err(
                    format!("{path}[{i}]"),
                    format!(
                        "cell [{}, {}] is outside the {n}x{n} map (rows and columns 0..{}); is this the episode's map?",
                        c[0],
                        c[1],
                        n - 1
                    ),
                ));
            }
        }
        Ok(())
    };
    let order = |o: Option<i64>, path: String| -> Result<(), EpisodeError> {
        match o {
            Some(o) if o < 1 => Err(err(
                path,
                format!("order {o} is not a 1-based position (must-pass orders are 1, 2, 3, ...)"),
            )),
            _ => Ok(()),
        }
    };
    let size = |x: Option<f64>, path: String| -> Result<(), EpisodeError> {
        match x {
            Some(x) if !x.is_finite() || x < 0.0 => Err(err(
                path,
                format!("{x} is not a non-negative size in cells"),
            )),
            _ => Ok(()),
        }
    };
    if let Some(p) = &ep.start_pose
        && let (Some(r), Some(c)) = (p.row, p.col)
    {
        cells(&[[r, c]], "start_pose")?;
    }
    if let Some(t) = &ep.human_expert_trajectory {
        cells(t, "human_expert_trajectory")?;
    }
    for (i, h) in ep.hard_constraints.iter().enumerate() {
        let at = format!("hard_constraints[{i}]");
        order(h.order, format!("{at}.order"))?;
        if let Some(s) = &h.scope {
            order(s.from_order, format!("{at}.scope.from_order"))?;
            order(s.to_order, format!("{at}.scope.to_order"))?;
        }
        size(h.radius, format!("{at}.radius"))?;
        size(h.width, format!("{at}.width"))?;
        size(h.height, format!("{at}.height"))?;
        if let Some(c) = &h.cells {
            cells(c, &format!("{at}.cells"))?;
        }
    }
    for (i, s) in ep.soft_constraints.iter().enumerate() {
        let at = format!("soft_constraints[{i}]");
        if let Some(t) = &s.preference_type
            && PreferenceType::parse(t).is_none()
        {
            return Err(err(
                format!("{at}.preference_type"),
                format!(
                    "unknown preference type `{t}` (known: {})",
                    known_preferences()
                ),
            ));
        }
        if let Some(sc) = &s.scope {
            order(sc.from_order, format!("{at}.scope.from_order"))?;
            order(sc.to_order, format!("{at}.scope.to_order"))?;
        }
        size(s.radius, format!("{at}.radius"))?;
        if let Some(c) = &s.cells {
            cells(c, &format!("{at}.cells"))?;
        }
        if let Some(r) = &s.reference_region
            && let Some(c) = &r.cells
        {
            cells(c, &format!("{at}.reference_region.cells"))?;
        }
        for (k, r) in s.reference_regions.iter().flatten().enumerate() {
            if let Some(c) = &r.cells {
                cells(c, &format!("{at}.reference_regions[{k}].cells"))?;
            }
        }
        if let Some(t) = &s.reference_trajectory {
            cells(t, &format!("{at}.reference_trajectory"))?;
        }
        if let Some(t) = s
            .path_shape_annotation
            .as_ref()
            .and_then(|a| a.shape_reference_trajectory.as_ref())
        {
            cells(
                t,
                &format!("{at}.path_shape_annotation.shape_reference_trajectory"),
            )?;
        }
    }
    Ok(())
}

/// A copy of `value` with every float that is a whole number (`223.0`) written as an integer,
/// as the reference tools' Python writer sometimes emits cells; other numbers are unchanged.
pub fn integral_floats_as_ints(value: &serde_json::Value) -> serde_json::Value {
    use serde_json::Value;
    match value {
        Value::Number(n) if n.is_f64() => match n.as_f64() {
            Some(x) if x.fract() == 0.0 && x.abs() < 9.0e15 => Value::from(x as i64),
            _ => value.clone(),
        },
        Value::Array(a) => Value::Array(a.iter().map(integral_floats_as_ints).collect()),
        Value::Object(o) => Value::Object(
            o.iter()
                .map(|(k, v)| (k.clone(), integral_floats_as_ints(v)))
                .collect(),
        ),
        _ => value.clone(),
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
