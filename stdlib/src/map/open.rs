//! Open boundaries in the map JSON: the m2rc key `open_boundaries` (the reference's tools ignore
//! it), `[{"rooms": [a, b], "cells": [[r, c], ...]}]`, written only when a map has one so maps
//! without open-plan rooms are byte-identical to before.

use super::error::{ErrCtx, MapError};
use super::format::{as_arr, as_obj, as_u32, get, join, read_cell};
use super::model::{OpenBoundary, Room, SemanticMap};
use super::write::cell_value;
use serde_json::{Map, Value, json};

/// `open_boundaries` (an m2rc key the reference's tools ignore): `[{"rooms": [a, b], "cells":
/// [[r, c], ...]}]`, the walls a ProcTHOR house leaves out between open-plan rooms.
pub(super) fn read_open_boundaries(
    root: &Map<String, Value>,
    n: usize,
    rooms: &[Room],
    ctx: &ErrCtx,
) -> Result<Vec<OpenBoundary>, MapError> {
    let list = match root.get("open_boundaries") {
        None | Some(Value::Null) => return Ok(Vec::new()),
        Some(v) => as_arr(v, "open_boundaries", ctx)?,
    };
    let mut out = Vec::with_capacity(list.len());
    for (i, item) in list.iter().enumerate() {
        let path = format!("open_boundaries[{i}]");
        let o = as_obj(item, &path, ctx)?;
        let pair = as_arr(get(o, "rooms", &path, ctx)?, &join(&path, "rooms"), ctx)?;
        if pair.len() != 2 {
            return Err(ctx.err(join(&path, "rooms"), "needs exactly two room ids"));
        }
        let a = as_u32(&pair[0], &format!("{path}.rooms[0]"), ctx)?;
        let b = as_u32(&pair[1], &format!("{path}.rooms[1]"), ctx)?;
        for id in [a, b] {
            if rooms.binary_search_by_key(&id, |r| r.id).is_err() {
                return Err(ctx.err(
                    join(&path, "rooms"),
                    format!("room {id} is not in room_instances"),
                ));
            }
        }
        if a == b {
            return Err(ctx.err(join(&path, "rooms"), "joins a room to itself"));
        }
        let cells_path = join(&path, "cells");
        let mut cells = as_arr(get(o, "cells", &path, ctx)?, &cells_path, ctx)?
            .iter()
            .enumerate()
            .map(|(k, c)| read_cell(c, n, &format!("{cells_path}[{k}]"), ctx))
            .collect::<Result<Vec<_>, _>>()?;
        cells.sort_unstable();
        cells.dedup();
        out.push(OpenBoundary {
            rooms: (a.min(b), a.max(b)),
            cells,
        });
    }
    out.sort_by(|x, y| x.rooms.cmp(&y.rooms).then(x.cells.cmp(&y.cells)));
    Ok(out)
}

pub(super) fn open_boundaries_value(map: &SemanticMap) -> Value {
    Value::Array(
        map.open_boundaries
            .iter()
            .map(|o| {
                json!({
                    "rooms": [o.rooms.0, o.rooms.1],
                    "cells": o.cells.iter().map(|&c| cell_value(c)).collect::<Vec<_>>(),
                })
            })
            .collect(),
    )
}
