//! Route (prediction) files: a bare `[[row, col], ...]` list, or an object holding it under
//! `trajectory`, `predicted_trajectory` or `human_expert_trajectory` (first list found, in that
//! order). Points must be two JSON integers inside the grid; traversability and adjacency are
//! not required (jumps are scored as straight segments, as the reference does); [`validity`]
//! says whether a route could be driven.

pub mod validity;

use serde_json::Value;
use std::path::Path;

/// Keys an object-form route file may hold the trajectory under, in priority order.
pub const TRAJECTORY_KEYS: [&str; 3] = [
    "trajectory",
    "predicted_trajectory",
    "human_expert_trajectory",
];

#[derive(Debug, thiserror::Error)]
pub enum RouteError {
    #[error("{file}: cannot read: {source}")]
    Io {
        file: String,
        #[source]
        source: std::io::Error,
    },
    #[error("{file}: not valid JSON: {source}")]
    Json {
        file: String,
        #[source]
        source: serde_json::Error,
    },
    #[error("{file}: {message}")]
    Invalid { file: String, message: String },
}

/// Extracts and validates the trajectory of a route JSON value on an `n` x `n` grid.
pub fn parse_route(value: &Value, n: usize, file: &str) -> Result<Vec<[i64; 2]>, RouteError> {
    let invalid = |message: String| RouteError::Invalid {
        file: file.to_string(),
        message,
    };
    let (list, label) = match value {
        Value::Array(list) => (list, "trajectory".to_string()),
        Value::Object(obj) => TRAJECTORY_KEYS
            .iter()
            .find_map(|k| {
                obj.get(*k)
                    .and_then(Value::as_array)
                    .map(|l| (l, (*k).to_string()))
            })
            .ok_or_else(|| {
                invalid(
                    "a route must be a point list or contain trajectory, predicted_trajectory, or \
                     human_expert_trajectory"
                        .into(),
                )
            })?,
        _ => {
            return Err(invalid(
                "a route must be a point list or an object with a trajectory".into(),
            ));
        }
    };
    validate_points(list, n, &label).map_err(invalid)
}

/// The most points a route may have: 100 000 cells is 5 km at 0.05 m per cell, far beyond any
/// house; longer routes are refused before anything is allocated for them, so a runaway
/// generator cannot make the evaluator (whose path-shape term is quadratic) hang.
pub const MAX_ROUTE_POINTS: usize = 100_000;

/// Validates `[[row, col], ...]`: integers (not floats or booleans), inside `[0, n)`, at most
/// [`MAX_ROUTE_POINTS`] of them.
pub fn validate_points(list: &[Value], n: usize, label: &str) -> Result<Vec<[i64; 2]>, String> {
    if list.len() > MAX_ROUTE_POINTS {
        return Err(format!(
            "{label} has {} points, more than the limit of {MAX_ROUTE_POINTS}",
            list.len()
        ));
    }
    let mut out = Vec::with_capacity(list.len());
    for (i, p) in list.iter().enumerate() {
        let pair = match p.as_array() {
            Some(a) if a.len() == 2 => a,
            _ => {
                return Err(format!(
                    "{label}[{i}] must be a [row, col] list of two integers, got {p}"
                ));
            }
        };
        let mut rc = [0i64; 2];
        for (k, v) in pair.iter().enumerate() {
            let x = match v {
                Value::Number(num) if num.is_i64() || num.is_u64() => num.as_i64(),
                _ => None,
            };
            let Some(x) = x else {
                return Err(format!("{label}[{i}][{k}] must be an integer, got {v}"));
            };
            if x < 0 || x as u64 >= n as u64 {
                return Err(format!("{label}[{i}] = {p} is outside the {n}x{n} grid"));
            }
            rc[k] = x;
        }
        out.push(rc);
    }
    Ok(out)
}

/// Reads and validates a route file.
pub fn read_route(path: &Path, n: usize) -> Result<Vec<[i64; 2]>, RouteError> {
    let file = path.display().to_string();
    let text = crate::route_read::read_route_text(path)?;
    parse_route_text(&text, n, &file)
}

/// Parses and validates route JSON text; `file` names it in errors. Parsed within bounded memory
/// (`crate::route_read`): only the trajectory is kept, and a list past [`MAX_ROUTE_POINTS`] is
/// refused as it is read.
pub fn parse_route_text(text: &str, n: usize, file: &str) -> Result<Vec<[i64; 2]>, RouteError> {
    let value = crate::route_read::parse_bounded(text, file)?;
    parse_route(&value, n, file)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn accepts_bare_lists_and_objects() {
        assert_eq!(
            parse_route(&json!([[0, 1], [2, 3]]), 5, "r").unwrap(),
            vec![[0, 1], [2, 3]]
        );
        let v = json!({"predicted_trajectory": [[1, 1]], "human_expert_trajectory": [[2, 2]]});
        assert_eq!(parse_route(&v, 5, "r").unwrap(), vec![[1, 1]]);
        let v = json!({"trajectory": "x", "human_expert_trajectory": [[2, 2]]});
        assert_eq!(parse_route(&v, 5, "r").unwrap(), vec![[2, 2]]);
        assert!(parse_route(&json!([]), 5, "r").unwrap().is_empty());
    }

    #[test]
    fn rejects_floats_bools_out_of_range_and_bad_shapes() {
        for bad in [
            json!([[0.0, 1]]),
            json!([[true, 1]]),
            json!([[0, 5]]),
            json!([[-1, 0]]),
            json!([[0, 1, 2]]),
            json!([[0]]),
            json!([7]),
            json!({"route": [[0, 0]]}),
            json!("x"),
            json!([[0, 18446744073709551615u64]]),
        ] {
            let err = parse_route(&bad, 5, "route.json").unwrap_err().to_string();
            assert!(err.starts_with("route.json: "), "{err}");
        }
    }
}
