//! Reader and writer of the Map2Route layered map JSON (fact sheet section A).
//!
//! The writer produces the reference key order and Python's `indent=2` layout, so our maps are
//! valid inputs for the reference tools; the reader accepts the reference's own files. What the
//! reference format has no field for travels in extra keys the reference tools ignore: `area_m2`
//! on rooms, `elevation_m`, `height_m`, `parent_id` and `parent_relation` on objects, and
//! `metadata.start_grid`. Derived parts (`object_footprints` metadata, `cell_object_ids`,
//! `num_grid_cells`) are regenerated from the model on every write, which is what makes
//! write -> read -> write byte-identical.

use super::error::{ErrCtx, MapError};
use super::model::{
    FREE, GridFrame, MapDocument, MapExtra, OBSTACLE, Object, Parent, Relation, Room, SemanticMap,
};
use super::open::read_open_boundaries;
use crate::grid::{Cell, Grid};
use serde_json::{Map, Value};
use std::collections::BTreeMap;

/// Largest grid side the reader accepts; a 20,000² map would need gigabytes in memory.
pub const MAX_GRID_SIZE: u64 = 16384;

const TOP_KEYS: [&str; 9] = [
    "grid_size",
    "layer_legends",
    "metadata",
    "layers",
    "room_instances",
    "object_instances",
    "object_footprints",
    "cell_object_ids",
    "open_boundaries",
];
const ROOM_KEYS: [&str; 5] = ["id", "category", "name", "attributes", "area_m2"];
const OBJECT_KEYS: [&str; 11] = [
    "id",
    "category",
    "name",
    "attributes",
    "center_grid",
    "room_id",
    "num_grid_cells",
    "elevation_m",
    "height_m",
    "parent_id",
    "parent_relation",
];

/// Parses map JSON text; `file` names the source in errors.
pub fn read_map_json(bytes: &[u8], file: &str) -> Result<SemanticMap, MapError> {
    read_map_document_json(bytes, file).map(|d| d.map)
}

/// Parses map JSON text, keeping what the model has no field for.
pub fn read_map_document_json(bytes: &[u8], file: &str) -> Result<MapDocument, MapError> {
    let v: Value = serde_json::from_slice(bytes)
        .map_err(|e| MapError::new(file, "", format!("not valid JSON: {e}")))?;
    read_map_document(&v, file)
}

/// Reads a parsed map document into the model.
pub fn read_map_value(v: &Value, file: &str) -> Result<SemanticMap, MapError> {
    read_map_document(v, file).map(|d| d.map)
}

pub(super) fn get<'a>(
    obj: &'a Map<String, Value>,
    key: &str,
    path: &str,
    ctx: &ErrCtx,
) -> Result<&'a Value, MapError> {
    obj.get(key)
        .ok_or_else(|| ctx.err(join(path, key), "missing required key"))
}

pub(super) fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}

pub(super) fn as_obj<'a>(
    v: &'a Value,
    path: &str,
    ctx: &ErrCtx,
) -> Result<&'a Map<String, Value>, MapError> {
    v.as_object()
        .ok_or_else(|| ctx.err(path, format!("expected an object, found {}", kind(v))))
}

pub(super) fn as_arr<'a>(
    v: &'a Value,
    path: &str,
    ctx: &ErrCtx,
) -> Result<&'a Vec<Value>, MapError> {
    v.as_array()
        .ok_or_else(|| ctx.err(path, format!("expected an array, found {}", kind(v))))
}

pub(super) fn as_u32(v: &Value, path: &str, ctx: &ErrCtx) -> Result<u32, MapError> {
    match v.as_u64() {
        Some(x) if x <= u32::MAX as u64 => Ok(x as u32),
        _ => Err(ctx.err(
            path,
            format!("expected a non-negative integer, found {}", short(v)),
        )),
    }
}

fn as_f64(v: &Value, path: &str, ctx: &ErrCtx) -> Result<f64, MapError> {
    match v.as_f64() {
        Some(x) if x.is_finite() => Ok(x),
        _ => Err(ctx.err(
            path,
            format!("expected a finite number, found {}", short(v)),
        )),
    }
}

fn as_str<'a>(v: &'a Value, path: &str, ctx: &ErrCtx) -> Result<&'a str, MapError> {
    v.as_str()
        .ok_or_else(|| ctx.err(path, format!("expected a string, found {}", short(v))))
}

pub(crate) fn kind(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

pub(crate) fn short(v: &Value) -> String {
    let s = v.to_string();
    if s.len() > 40 {
        format!("{}...", &s[..s.floor_char_boundary(40)])
    } else {
        s
    }
}

fn opt_f64(
    obj: &Map<String, Value>,
    key: &str,
    path: &str,
    ctx: &ErrCtx,
) -> Result<Option<f64>, MapError> {
    match obj.get(key) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => as_f64(v, &join(path, key), ctx).map(Some),
    }
}

fn read_layer(
    layers: &Map<String, Value>,
    key: &str,
    n: usize,
    ctx: &ErrCtx,
) -> Result<Vec<u32>, MapError> {
    let path = format!("layers.{key}");
    let rows = as_arr(get(layers, key, "layers", ctx)?, &path, ctx)?;
    if rows.len() != n {
        return Err(ctx.err(&path, format!("has {} rows, grid_size is {n}", rows.len())));
    }
    let mut data = Vec::with_capacity(n * n);
    for (r, row) in rows.iter().enumerate() {
        let rp = || format!("{path}[{r}]");
        let cols = as_arr(row, &rp(), ctx)?;
        if cols.len() != n {
            return Err(ctx.err(
                rp(),
                format!("has {} columns, grid_size is {n}", cols.len()),
            ));
        }
        for (c, v) in cols.iter().enumerate() {
            match v.as_u64() {
                Some(x) if x <= u32::MAX as u64 => data.push(x as u32),
                _ => {
                    return Err(ctx.err(
                        format!("{path}[{r}][{c}]"),
                        format!("expected a non-negative integer, found {}", short(v)),
                    ));
                }
            }
        }
    }
    Ok(data)
}

pub(super) fn read_cell(v: &Value, n: usize, path: &str, ctx: &ErrCtx) -> Result<Cell, MapError> {
    read_cell_at(v, n, || path.to_string(), ctx)
}

/// [`read_cell`] with the path built only for an error: footprints are hundreds of thousands of
/// cells, and formatting a path for each was most of reading them.
pub(super) fn read_cell_at(
    v: &Value,
    n: usize,
    path: impl Fn() -> String,
    ctx: &ErrCtx,
) -> Result<Cell, MapError> {
    if let Some([r, c]) = v.as_array().map(Vec::as_slice)
        && let (Some(r), Some(c)) = (r.as_u64(), c.as_u64())
        && (r as usize) < n
        && (c as usize) < n
    {
        return Ok(Cell::new(r as u32, c as u32));
    }
    let path = &path();
    let a = as_arr(v, path, ctx)?;
    if a.len() != 2 {
        return Err(ctx.err(path, "expected a [row, col] pair"));
    }
    let r = as_u32(&a[0], &format!("{path}[0]"), ctx)?;
    let c = as_u32(&a[1], &format!("{path}[1]"), ctx)?;
    if r as usize >= n || c as usize >= n {
        return Err(ctx.err(
            path,
            format!("cell [{r}, {c}] lies outside the {n}x{n} grid"),
        ));
    }
    Ok(Cell::new(r, c))
}

fn read_attributes(
    obj: &Map<String, Value>,
    path: &str,
    ctx: &ErrCtx,
) -> Result<Vec<String>, MapError> {
    match obj.get("attributes") {
        None | Some(Value::Null) => Ok(Vec::new()),
        Some(v) => {
            let p = join(path, "attributes");
            as_arr(v, &p, ctx)?
                .iter()
                .enumerate()
                .map(|(i, a)| as_str(a, &format!("{p}[{i}]"), ctx).map(str::to_string))
                .collect()
        }
    }
}

fn unknown_keys(obj: &Map<String, Value>, known: &[&str]) -> Map<String, Value> {
    obj.iter()
        .filter(|(k, _)| !known.contains(&k.as_str()))
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect()
}

/// Reads the grid frame the way the reference does: `grid_coordinate_frame`, then `map_info`,
/// else resolution 1.0 at the origin.
fn read_frame(meta: &Map<String, Value>, ctx: &ErrCtx) -> Result<GridFrame, MapError> {
    for key in ["grid_coordinate_frame", "map_info"] {
        if let Some(v) = meta.get(key) {
            let path = format!("metadata.{key}");
            let o = as_obj(v, &path, ctx)?;
            let Some(res) = opt_f64(o, "resolution", &path, ctx)? else {
                continue;
            };
            if res <= 0.0 {
                return Err(ctx.err(join(&path, "resolution"), "must be positive"));
            }
            let x_min = opt_f64(o, "x_min", &path, ctx)?.unwrap_or(0.0);
            let z_min = opt_f64(o, "z_min", &path, ctx)?.unwrap_or(0.0);
            return Ok(GridFrame {
                resolution: res,
                x_min,
                z_min,
            });
        }
    }
    Ok(GridFrame {
        resolution: 1.0,
        x_min: 0.0,
        z_min: 0.0,
    })
}

/// Reads a parsed map document, keeping unknown content in [`MapExtra`].
pub fn read_map_document(v: &Value, file: &str) -> Result<MapDocument, MapError> {
    read_map_document_layers(v, file, None)
}

/// The three grid layers already in model form: what the prepared-map cache stores, so that a
/// cached map skips parsing the millions of layer numbers that dominate a map file.
pub(crate) struct Layers {
    pub occupancy: Grid<u8>,
    pub room: Grid<u32>,
    pub object: Grid<u32>,
    /// Each object's `object_footprints` cells by id, read instead of that key when given.
    pub footprints: Option<BTreeMap<u32, Vec<Cell>>>,
}

/// [`read_map_document`], taking the layers from `pre` (when given) instead of `layers`.
pub(crate) fn read_map_document_layers(
    v: &Value,
    file: &str,
    pre: Option<Layers>,
) -> Result<MapDocument, MapError> {
    let ctx = ErrCtx::new(file);
    let root = as_obj(v, "", &ctx)?;
    let n64 = get(root, "grid_size", "", &ctx)?.as_u64().ok_or_else(|| {
        ctx.err(
            "grid_size",
            format!(
                "expected a positive integer, found {}",
                short(&root["grid_size"])
            ),
        )
    })?;
    if n64 == 0 || n64 > MAX_GRID_SIZE {
        return Err(ctx.err(
            "grid_size",
            format!("must be between 1 and {MAX_GRID_SIZE}, found {n64}"),
        ));
    }
    let n = n64 as usize;

    let legends = match root.get("layer_legends") {
        None | Some(Value::Null) => None,
        Some(l) => {
            as_obj(l, "layer_legends", &ctx)?;
            Some(l.clone())
        }
    };
    let free_value = legends
        .as_ref()
        .and_then(|l| l.pointer("/occupancy/free/value"))
        .and_then(Value::as_u64)
        .unwrap_or(FREE as u64);

    let metadata = match root.get("metadata") {
        None | Some(Value::Null) => Map::new(),
        Some(m) => as_obj(m, "metadata", &ctx)?.clone(),
    };
    let frame = read_frame(&metadata, &ctx)?;
    let map_id = match metadata.get("map_id") {
        Some(v) => as_str(v, "metadata.map_id", &ctx)?.to_string(),
        None => file_stem(file),
    };
    let start = match metadata.get("start_grid") {
        None | Some(Value::Null) => None,
        Some(v) => Some(read_cell(v, n, "metadata.start_grid", &ctx)?),
    };

    let (pre, mut pre_footprints) = match pre {
        Some(mut l) => {
            let f = l.footprints.take();
            (Some(l), f)
        }
        None => (None, None),
    };
    let (occupancy, room_layer, object_layer) = match pre {
        Some(l) if [l.occupancy.n(), l.room.n(), l.object.n()] == [n; 3] => {
            (l.occupancy, l.room, l.object)
        }
        Some(_) => return Err(ctx.err("layers", format!("prepared layers are not {n}x{n}"))),
        None => {
            let layers = as_obj(get(root, "layers", "", &ctx)?, "layers", &ctx)?;
            let occ_raw = read_layer(layers, "occupancy", n, &ctx)?;
            let occupancy: Vec<u8> = occ_raw
                .iter()
                .map(|&x| {
                    if x as u64 == free_value {
                        FREE
                    } else if x == FREE as u32 || x > u8::MAX as u32 {
                        OBSTACLE
                    } else {
                        x as u8
                    }
                })
                .collect();
            let room_data = read_layer(layers, "room", n, &ctx)?;
            let object_data = read_layer(layers, "object_instance", n, &ctx)?;
            let occupancy = Grid::from_vec(n, occupancy).expect("checked size");
            let room_layer = Grid::from_vec(n, room_data).expect("checked size");
            let object_layer = Grid::from_vec(n, object_data).expect("checked size");
            (occupancy, room_layer, object_layer)
        }
    };

    let mut extra = MapExtra {
        metadata,
        layer_legends: legends,
        ..MapExtra::default()
    };
    extra.top_level = unknown_keys(root, &TOP_KEYS);

    // Counted by runs of equal ids (a room is long runs of its id): one map update per run, not
    // per cell, which is most of what reading a prepared map would otherwise spend here.
    let mut cell_counts: BTreeMap<u32, usize> = BTreeMap::new();
    for run in room_layer.data().chunk_by(|a, b| a == b) {
        *cell_counts.entry(run[0]).or_insert(0) += run.len();
    }

    let mut rooms = Vec::new();
    let room_list = as_arr(
        get(root, "room_instances", "", &ctx)?,
        "room_instances",
        &ctx,
    )?;
    for (i, rv) in room_list.iter().enumerate() {
        let path = format!("room_instances[{i}]");
        let o = as_obj(rv, &path, &ctx)?;
        let id = as_u32(get(o, "id", &path, &ctx)?, &join(&path, "id"), &ctx)?;
        if id == 0 {
            return Err(ctx.err(join(&path, "id"), "room ids must be positive"));
        }
        let category = as_str(
            get(o, "category", &path, &ctx)?,
            &join(&path, "category"),
            &ctx,
        )?
        .to_string();
        let name = match o.get("name") {
            Some(v) => as_str(v, &join(&path, "name"), &ctx)?.to_string(),
            None => format!("{category}_{id}"),
        };
        let attributes = read_attributes(o, &path, &ctx)?;
        let attr_area = attributes
            .iter()
            .find_map(|a| a.strip_prefix("area="))
            .and_then(|s| s.parse::<f64>().ok())
            .filter(|a| a.is_finite());
        let grid_area =
            *cell_counts.get(&id).unwrap_or(&0) as f64 * frame.resolution * frame.resolution;
        let area_m2 = opt_f64(o, "area_m2", &path, &ctx)?
            .or(attr_area)
            .unwrap_or(grid_area);
        let keys = unknown_keys(o, &ROOM_KEYS);
        if !keys.is_empty() {
            extra.room_keys.insert(id, keys);
        }
        rooms.push(Room {
            id,
            category,
            name,
            area_m2,
            attributes,
        });
    }
    rooms.sort_by_key(|r| r.id);
    if let Some(w) = rooms.windows(2).find(|w| w[0].id == w[1].id) {
        return Err(ctx.err(
            "room_instances",
            format!("room id {} appears twice", w[0].id),
        ));
    }

    let footprints = match root.get("object_footprints") {
        None | Some(Value::Null) => None,
        Some(f) => Some(as_obj(f, "object_footprints", &ctx)?),
    };
    // Each object's cells in the object layer: only needed for an object without a footprint
    // entry, so built on first need.
    let mut layer_cells: Option<BTreeMap<u32, Vec<Cell>>> = None;
    let mut cells_of = |id: u32| -> Vec<Cell> {
        let by_id = layer_cells.get_or_insert_with(|| {
            let mut by_id: BTreeMap<u32, Vec<Cell>> = BTreeMap::new();
            for (cell, &id) in object_layer.iter_cells() {
                if id != 0 {
                    by_id.entry(id).or_default().push(cell);
                }
            }
            by_id
        });
        by_id.get(&id).cloned().unwrap_or_default()
    };

    let mut objects = Vec::new();
    let object_list = as_arr(
        get(root, "object_instances", "", &ctx)?,
        "object_instances",
        &ctx,
    )?;
    for (i, ov) in object_list.iter().enumerate() {
        let path = format!("object_instances[{i}]");
        let o = as_obj(ov, &path, &ctx)?;
        let id = as_u32(get(o, "id", &path, &ctx)?, &join(&path, "id"), &ctx)?;
        if id == 0 {
            return Err(ctx.err(join(&path, "id"), "object ids must be positive"));
        }
        let category = as_str(
            get(o, "category", &path, &ctx)?,
            &join(&path, "category"),
            &ctx,
        )?
        .to_string();
        let name = match o.get("name") {
            Some(v) => as_str(v, &join(&path, "name"), &ctx)?.to_string(),
            None => format!("{category}_{id}"),
        };
        let attributes = read_attributes(o, &path, &ctx)?;

        let mut footprint = Vec::new();
        if let Some(pre) = pre_footprints.as_mut() {
            footprint = pre.remove(&id).unwrap_or_default();
            if let Some(c) = footprint
                .iter()
                .find(|c| c.row as usize >= n || c.col as usize >= n)
            {
                return Err(ctx.err(
                    format!("object_footprints.\"{id}\".cells"),
                    format!("cell [{}, {}] lies outside the {n}x{n} grid", c.row, c.col),
                ));
            }
        } else if let Some(fp) = footprints.and_then(|f| f.get(&id.to_string())) {
            let fpath = format!("object_footprints.\"{id}\"");
            let fo = as_obj(fp, &fpath, &ctx)?;
            if let Some(cells) = fo.get("cells") {
                let cpath = join(&fpath, "cells");
                for (k, c) in as_arr(cells, &cpath, &ctx)?.iter().enumerate() {
                    footprint.push(read_cell_at(c, n, || format!("{cpath}[{k}]"), &ctx)?);
                }
            }
        }
        if footprint.is_empty() {
            footprint = cells_of(id);
        }
        let center = match o.get("center_grid") {
            None | Some(Value::Null) => None,
            Some(v) => {
                let p = join(&path, "center_grid");
                let a = as_arr(v, &p, &ctx)?;
                if a.len() != 2 {
                    return Err(ctx.err(p, "expected a [row, col] pair"));
                }
                Some([
                    as_f64(&a[0], &format!("{p}[0]"), &ctx)?,
                    as_f64(&a[1], &format!("{p}[1]"), &ctx)?,
                ])
            }
        };
        if footprint.is_empty()
            && let Some([r, c]) = center
        {
            let (r, c) = (r.round(), c.round());
            if r >= 0.0 && c >= 0.0 && (r as usize) < n && (c as usize) < n {
                footprint.push(Cell::new(r as u32, c as u32));
            }
        }
        footprint.sort_unstable();
        footprint.dedup();
        let center = center.unwrap_or_else(|| centroid(&footprint));
        let room = match o.get("room_id") {
            Some(Value::Null) => None,
            Some(v) => Some(as_u32(v, &join(&path, "room_id"), &ctx)?).filter(|&r| r != 0),
            None => dominant_room(&footprint, &room_layer),
        };
        let parent = match o.get("parent_id") {
            None | Some(Value::Null) => None,
            Some(v) => {
                let pid = as_u32(v, &join(&path, "parent_id"), &ctx)?;
                let rel = match o.get("parent_relation").and_then(Value::as_str) {
                    Some("inside") => Relation::Inside,
                    Some("on") | None => Relation::On,
                    Some(other) => {
                        return Err(ctx.err(
                            join(&path, "parent_relation"),
                            format!("expected \"on\" or \"inside\", found {other:?}"),
                        ));
                    }
                };
                Some(Parent {
                    id: pid,
                    relation: rel,
                })
            }
        };
        let keys = unknown_keys(o, &OBJECT_KEYS);
        if !keys.is_empty() {
            extra.object_keys.insert(id, keys);
        }
        objects.push(Object {
            id,
            category,
            name,
            footprint,
            center,
            elevation_m: opt_f64(o, "elevation_m", &path, &ctx)?,
            height_m: opt_f64(o, "height_m", &path, &ctx)?,
            room,
            parent,
            attributes,
        });
    }
    objects.sort_by_key(|o| o.id);
    if let Some(w) = objects.windows(2).find(|w| w[0].id == w[1].id) {
        return Err(ctx.err(
            "object_instances",
            format!("object id {} appears twice", w[0].id),
        ));
    }

    let open_boundaries = read_open_boundaries(root, n, &rooms, &ctx)?;
    let map = SemanticMap {
        map_id,
        frame,
        occupancy,
        room_layer,
        object_layer,
        rooms,
        objects,
        start,
        open_boundaries,
    };
    Ok(MapDocument { map, extra })
}

fn file_stem(file: &str) -> String {
    let name = file.rsplit(['/', '\\']).next().unwrap_or(file);
    name.split('.')
        .next()
        .filter(|s| !s.is_empty())
        .unwrap_or("map")
        .to_string()
}

/// Centroid of cells, rounded to 3 decimals as the reference's `center_grid`.
pub fn centroid(cells: &[Cell]) -> [f64; 2] {
    if cells.is_empty() {
        return [0.0, 0.0];
    }
    let k = cells.len() as f64;
    let r = cells.iter().map(|c| c.row as f64).sum::<f64>() / k;
    let c = cells.iter().map(|c| c.col as f64).sum::<f64>() / k;
    [(r * 1000.0).round() / 1000.0, (c * 1000.0).round() / 1000.0]
}

/// The room covering most of `cells` (ties to the smaller id), as the reference's thinggraph.
pub fn dominant_room(cells: &[Cell], rooms: &Grid<u32>) -> Option<u32> {
    let mut counts: BTreeMap<u32, usize> = BTreeMap::new();
    for &c in cells {
        if let Some(&r) = rooms.get(c)
            && r != 0
        {
            *counts.entry(r).or_insert(0) += 1;
        }
    }
    let mut best: Option<(u32, usize)> = None;
    for (r, k) in counts {
        if best.is_none_or(|(_, bk)| k > bk) {
            best = Some((r, k));
        }
    }
    best.map(|(r, _)| r)
}
