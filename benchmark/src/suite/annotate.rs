//! JSON builders for the Map2Route annotation (instruction format B.1 / B.2).

use super::index::MapIndex;
use serde_json::{Value, json};

/// Fixed timestamp so that a suite is byte-identical from its seed.
pub const TIMESTAMP: &str = "2026-01-01T00:00:00Z";

pub fn global_scope() -> Value {
    json!({"type": "global", "from_order": null, "to_order": null})
}

pub fn stage_scope(order: u32) -> Value {
    json!({"type": "between_hard_constraints", "from_order": order - 1, "to_order": order})
}

pub fn avoid_json(
    ix: &MapIndex<'_>,
    no: usize,
    cells: &[usize],
    label: &str,
    scope: Value,
) -> Value {
    let center = cells_center(ix, cells);
    json!({
        "constraint_id": format!("avoid_{no}"), "kind": "must_avoid", "shape": "freeform",
        "center": center, "radius": 1.0, "width": 1.0, "height": 1.0, "order": null, "source": "custom",
        "object_id": null, "scope": scope, "label": label, "cells": cells_json(ix, cells),
    })
}

pub fn soft_base(
    no: usize,
    kind: &str,
    scope: Value,
    label: &str,
    ix: &MapIndex<'_>,
    cells: &[usize],
) -> Value {
    json!({
        "constraint_id": format!("soft_{no}"), "preference_type": kind, "shape": "freeform",
        "center": cells_center(ix, cells), "radius": 1.0, "width": 1.0, "height": 1.0, "object_ids": [],
        "reference_regions": [], "reference_region": null, "D_ref": null, "Q_relative_ref": null,
        "C_smooth_ref": null, "C_clear_ref": null, "reference_trajectory": [], "reference_waypoint_count": 0,
        "reference_valid_path_length": 0.0, "reference_metric_status": null, "relative_reference_status": null,
        "scope": scope, "label": label, "cells": cells_json(ix, cells),
    })
}

/// The annotator's default clearance entry, always present.
pub fn default_clearance() -> Value {
    json!({
        "constraint_id": "__global_clearance__", "preference_type": "clearance", "shape": "freeform",
        "center": [0.0, 0.0], "radius": 1.0, "width": 1.0, "height": 1.0, "object_ids": [],
        "reference_regions": [], "reference_region": null, "reference_trajectory": [],
        "reference_waypoint_count": 0, "scope": global_scope(), "label": "Clearance", "cells": [],
    })
}

pub fn cells_json(ix: &MapIndex<'_>, cells: &[usize]) -> Value {
    Value::Array(
        cells
            .iter()
            .map(|&i| {
                let c = ix.cell(i);
                json!([c.row, c.col])
            })
            .collect(),
    )
}

/// The union of the footprints of `ids`, deduplicated, in id order.
pub fn footprints_json(ix: &MapIndex<'_>, ids: &[u32]) -> Value {
    let mut seen = std::collections::BTreeSet::new();
    let mut out = Vec::new();
    for &o in ids {
        for c in &ix.object(o).footprint {
            if seen.insert((c.row, c.col)) {
                out.push(json!([c.row, c.col]));
            }
        }
    }
    Value::Array(out)
}

pub fn cells_center(ix: &MapIndex<'_>, cells: &[usize]) -> [f64; 2] {
    if cells.is_empty() {
        return [0.0, 0.0];
    }
    let (mut r, mut c) = (0.0, 0.0);
    for &i in cells {
        let cell = ix.cell(i);
        r += cell.row as f64;
        c += cell.col as f64;
    }
    [
        round3(r / cells.len() as f64),
        round3(c / cells.len() as f64),
    ]
}

pub fn round3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

pub fn wrap(s: &str, width: usize) -> Vec<String> {
    let mut lines = vec![String::new()];
    for word in s.split_whitespace() {
        let last = lines.last_mut().expect("non-empty");
        if !last.is_empty() && last.len() + 1 + word.len() > width {
            lines.push(word.to_string());
        } else {
            if !last.is_empty() {
                last.push(' ');
            }
            last.push_str(word);
        }
    }
    lines
}
