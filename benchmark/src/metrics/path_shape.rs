//! Validation of the annotation tool's embedded path-shape reference, which replaces a path-shape
//! preference's `reference_trajectory` at evaluation. An invalid annotation stops evaluation,
//! as in the reference.

use crate::episode::{CellRc, PathShapeAnnotation};
use serde_json::{Map, Value};

pub const PATH_SHAPE_ANNOTATION_TYPE: &str = "canonical_path_shape_reference";
pub const DEFAULT_SHAPE_REFERENCE_SOURCE: &str = "human_expert_canonical_v1";

/// The normalized reference trajectory (in-grid integer cells, consecutive duplicates removed,
/// at least two points) and its source label.
pub fn normalize_annotation(
    a: &PathShapeAnnotation,
    n: usize,
    label: &str,
) -> Result<(Vec<CellRc>, String), String> {
    let v = serde_json::to_value(a).map_err(|e| format!("{label}: {e}"))?;
    normalize_value(&v, n, label, true)
}

fn normalize_value(
    v: &Value,
    n: usize,
    label: &str,
    with_history: bool,
) -> Result<(Vec<CellRc>, String), String> {
    let empty = Map::new();
    let obj = v
        .as_object()
        .ok_or_else(|| format!("{label} must be an object"))?;
    match obj.get("version") {
        None => {}
        Some(x) if x.as_i64().is_some_and(|k| k >= 1) => {}
        Some(_) => return Err(format!("{label}.version must be a positive integer")),
    }
    match obj.get("annotation_type") {
        None => {}
        Some(Value::String(s)) if s == PATH_SHAPE_ANNOTATION_TYPE => {}
        Some(_) => {
            return Err(format!(
                "{label}.annotation_type must be '{PATH_SHAPE_ANNOTATION_TYPE}'"
            ));
        }
    }
    let spec = match obj.get("shape_spec") {
        None => &empty,
        Some(Value::Object(m)) => m,
        Some(_) => return Err(format!("{label}.shape_spec must be an object")),
    };
    let no_points = Value::Array(Vec::new());
    points(
        spec.get("ordered_control_points").unwrap_or(&no_points),
        n,
        &format!("{label}.shape_spec.ordered_control_points"),
        0,
    )?;
    let trajectory = points(
        obj.get("shape_reference_trajectory")
            .unwrap_or(&Value::Null),
        n,
        &format!("{label}.shape_reference_trajectory"),
        2,
    )?;
    let source = obj
        .get("shape_reference_source")
        .and_then(Value::as_str)
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .unwrap_or(DEFAULT_SHAPE_REFERENCE_SOURCE)
        .to_string();
    if with_history {
        match obj.get("history") {
            None => {}
            Some(Value::Array(items)) => {
                for (i, item) in items.iter().enumerate() {
                    normalize_value(item, n, &format!("{label}.history[{i}]"), false)?;
                }
            }
            Some(_) => return Err(format!("{label}.history must be a list")),
        }
    }
    Ok((trajectory, source))
}

fn points(v: &Value, n: usize, label: &str, minimum: usize) -> Result<Vec<CellRc>, String> {
    let list = v
        .as_array()
        .ok_or_else(|| format!("{label} must be a list of [row, col] points"))?;
    let mut out: Vec<CellRc> = Vec::new();
    for (i, p) in list.iter().enumerate() {
        let pair = p
            .as_array()
            .filter(|a| a.len() == 2)
            .ok_or_else(|| format!("{label}[{i}] must be [row, col]"))?;
        let (Some(r), Some(c)) = (pair[0].as_i64(), pair[1].as_i64()) else {
            return Err(format!("{label}[{i}] must contain integers"));
        };
        if r < 0 || c < 0 || r as u64 >= n as u64 || c as u64 >= n as u64 {
            return Err(format!("{label}[{i}] is outside the map"));
        }
        if out.last() != Some(&[r, c]) {
            out.push([r, c]);
        }
    }
    if out.len() < minimum {
        return Err(format!("{label} needs at least {minimum} points"));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ann(traj: Vec<CellRc>) -> PathShapeAnnotation {
        PathShapeAnnotation {
            shape_reference_trajectory: Some(traj),
            ..PathShapeAnnotation::default()
        }
    }

    #[test]
    fn dedups_consecutive_points_and_defaults_the_source() {
        let (t, s) = normalize_annotation(&ann(vec![[1, 1], [1, 1], [1, 2]]), 5, "a").unwrap();
        assert_eq!(t, vec![[1, 1], [1, 2]]);
        assert_eq!(s, DEFAULT_SHAPE_REFERENCE_SOURCE);
    }

    #[test]
    fn rejects_short_or_out_of_grid_trajectories() {
        assert!(
            normalize_annotation(&ann(vec![[1, 1], [1, 1]]), 5, "a")
                .unwrap_err()
                .contains("at least 2")
        );
        assert!(
            normalize_annotation(&ann(vec![[1, 1], [1, 5]]), 5, "a")
                .unwrap_err()
                .contains("outside")
        );
        let mut a = ann(vec![[1, 1], [1, 2]]);
        a.annotation_type = Some("other".into());
        assert!(normalize_annotation(&a, 5, "a").is_err());
        assert!(normalize_annotation(&PathShapeAnnotation::default(), 5, "a").is_err());
    }
}
