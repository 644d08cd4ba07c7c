//! The parts of a ProcTHOR house JSON the importer uses, checked field by field so that a
//! malformed house names the field at fault (`rooms[3].floorPolygon: needs at least 3 points`).

use crate::map::error::{ErrCtx, MapError};
use crate::map::format::{kind, short};
use serde_json::{Map, Value};

pub struct HouseRoom {
    pub id: String,
    pub room_type: String,
    /// `(x, z)` vertices.
    pub polygon: Vec<[f64; 2]>,
}

pub struct HouseWall {
    pub id: String,
    /// Start and end `(x, z)` of the wall's bottom edge.
    pub a: [f64; 2],
    pub b: [f64; 2],
    pub height: f64,
    /// `"empty": true`: ProcTHOR left this face out (an open-plan boundary between two rooms).
    pub empty: bool,
    /// The room this face belongs to (`roomId`, else read off the id `wall|<n>|...`); `None` for
    /// exterior faces.
    pub room_id: Option<String>,
}

/// A door or window: a hole in a wall.
pub struct HouseHole {
    pub id: String,
    pub asset_id: String,
    pub room0: String,
    pub room1: String,
    pub wall0: String,
    /// Hole extent along the wall from the wall's start, metres, and its vertical extent.
    pub along: [f64; 2],
    pub vertical: [f64; 2],
}

pub struct HouseObject {
    /// Index path in the house (`objects[3].children[1]`), for error messages.
    pub path: String,
    pub id: String,
    pub asset_id: String,
    /// An explicit type (m2rc extension, used by the demo house); ProcTHOR houses leave it out.
    pub object_type: Option<String>,
    pub position: [f64; 3],
    pub rotation_y: f64,
    pub children: Vec<HouseObject>,
}

pub struct House {
    pub rooms: Vec<HouseRoom>,
    pub walls: Vec<HouseWall>,
    pub doors: Vec<HouseHole>,
    pub windows: Vec<HouseHole>,
    pub objects: Vec<HouseObject>,
    /// Agent start `(x, z)` and yaw in degrees.
    pub agent: Option<([f64; 2], f64)>,
    pub room_spec: Option<String>,
    /// What the house does that the importer reads in a documented way but a user should hear
    /// about: `(field path, message)`.
    pub warnings: Vec<(String, String)>,
}

/// Largest coordinate magnitude accepted, metres. Real houses span tens of metres; a value like
/// 1e20 is a broken file, and would otherwise overflow the grid-size arithmetic.
pub const MAX_COORDINATE_M: f64 = 100_000.0;

/// Whether a JSON document looks like a ProcTHOR house rather than a Map2Route map.
pub fn looks_like_house(v: &Value) -> bool {
    v.get("rooms").is_some() && v.get("grid_size").is_none() && v.get("layers").is_none()
}

fn field<'a>(
    o: &'a Map<String, Value>,
    key: &str,
    path: &str,
    ctx: &ErrCtx,
) -> Result<&'a Value, MapError> {
    o.get(key)
        .ok_or_else(|| ctx.err(format!("{path}.{key}"), "missing required key"))
}

fn obj<'a>(v: &'a Value, path: &str, ctx: &ErrCtx) -> Result<&'a Map<String, Value>, MapError> {
    v.as_object()
        .ok_or_else(|| ctx.err(path, format!("expected an object, found {}", kind(v))))
}

fn arr<'a>(v: &'a Value, path: &str, ctx: &ErrCtx) -> Result<&'a Vec<Value>, MapError> {
    v.as_array()
        .ok_or_else(|| ctx.err(path, format!("expected an array, found {}", kind(v))))
}

fn string(o: &Map<String, Value>, key: &str, path: &str, ctx: &ErrCtx) -> Result<String, MapError> {
    let v = field(o, key, path, ctx)?;
    v.as_str().map(str::to_string).ok_or_else(|| {
        ctx.err(
            format!("{path}.{key}"),
            format!("expected a string, found {}", short(v)),
        )
    })
}

fn num(o: &Map<String, Value>, key: &str, path: &str, ctx: &ErrCtx) -> Result<f64, MapError> {
    let v = field(o, key, path, ctx)?;
    match v.as_f64() {
        Some(x) if x.is_finite() => Ok(x),
        _ => Err(ctx.err(
            format!("{path}.{key}"),
            format!("expected a finite number, found {}", short(v)),
        )),
    }
}

/// Optional number: absent or null gives `default`.
fn num_or(
    o: &Map<String, Value>,
    key: &str,
    default: f64,
    path: &str,
    ctx: &ErrCtx,
) -> Result<f64, MapError> {
    match o.get(key) {
        None | Some(Value::Null) => Ok(default),
        Some(_) => num(o, key, path, ctx),
    }
}

fn point(v: &Value, path: &str, ctx: &ErrCtx) -> Result<[f64; 3], MapError> {
    let o = obj(v, path, ctx)?;
    let p = [
        num(o, "x", path, ctx)?,
        num_or(o, "y", 0.0, path, ctx)?,
        num(o, "z", path, ctx)?,
    ];
    for (k, x) in ["x", "y", "z"].iter().zip(p) {
        if x.abs() > MAX_COORDINATE_M {
            return Err(ctx.err(
                format!("{path}.{k}"),
                format!(
                    "{x:e} m is beyond the {MAX_COORDINATE_M:.0} m any coordinate of a house may reach"
                ),
            ));
        }
    }
    Ok(p)
}

fn list<'a>(
    root: &'a Map<String, Value>,
    key: &str,
    ctx: &ErrCtx,
) -> Result<&'a [Value], MapError> {
    match root.get(key) {
        None | Some(Value::Null) => Ok(&[]),
        Some(v) => Ok(arr(v, key, ctx)?.as_slice()),
    }
}

/// Parses the wall segment out of an id `wall|<room>|x0|z0|x1|z1`, the way the reference does for
/// runtime walls; used when a door names a wall the house does not list.
pub fn wall_segment_from_id(id: &str) -> Option<([f64; 2], [f64; 2])> {
    let parts: Vec<&str> = id.split('|').collect();
    if parts.len() < 6 || parts[0] != "wall" {
        return None;
    }
    let n = parts.len();
    let f: Vec<f64> = parts[n - 4..]
        .iter()
        .filter_map(|p| p.parse::<f64>().ok())
        .filter(|x| x.is_finite())
        .collect();
    (f.len() == 4).then(|| ([f[0], f[1]], [f[2], f[3]]))
}

fn parse_hole(v: &Value, path: &str, ctx: &ErrCtx) -> Result<HouseHole, MapError> {
    let o = obj(v, path, ctx)?;
    let hole = arr(
        field(o, "holePolygon", path, ctx)?,
        &format!("{path}.holePolygon"),
        ctx,
    )?;
    if hole.len() < 2 {
        return Err(ctx.err(
            format!("{path}.holePolygon"),
            "needs its two corners [min, max]",
        ));
    }
    let p0 = point(&hole[0], &format!("{path}.holePolygon[0]"), ctx)?;
    let p1 = point(&hole[1], &format!("{path}.holePolygon[1]"), ctx)?;
    let id = string(o, "id", path, ctx)?;
    let room0 = string(o, "room0", path, ctx)?;
    let room1 = match o.get("room1") {
        Some(Value::String(s)) => s.clone(),
        _ => room0.clone(),
    };
    Ok(HouseHole {
        id,
        asset_id: string(o, "assetId", path, ctx)?,
        room0,
        room1,
        wall0: string(o, "wall0", path, ctx)?,
        along: [p0[0].min(p1[0]), p0[0].max(p1[0])],
        vertical: [p0[1].min(p1[1]), p0[1].max(p1[1])],
    })
}

fn parse_object(
    v: &Value,
    path: &str,
    ctx: &ErrCtx,
    depth: usize,
    warnings: &mut Vec<(String, String)>,
) -> Result<HouseObject, MapError> {
    let o = obj(v, path, ctx)?;
    if depth > 8 {
        return Err(ctx.err(path, "children nested more than 8 deep"));
    }
    let position = point(
        field(o, "position", path, ctx)?,
        &format!("{path}.position"),
        ctx,
    )?;
    let rot_path = format!("{path}.rotation");
    let rotation_y = match o.get("rotation") {
        None => 0.0,
        Some(Value::Null) => {
            warnings.push((
                rot_path,
                "is null; the object is placed unrotated (0°)".into(),
            ));
            0.0
        }
        Some(r) => {
            let ro = obj(r, &rot_path, ctx)?;
            if matches!(ro.get("y"), None | Some(Value::Null)) {
                warnings.push((
                    format!("{rot_path}.y"),
                    "is missing or null; the object is placed unrotated (0°)".into(),
                ));
            }
            num_or(ro, "y", 0.0, &rot_path, ctx)?
        }
    };
    let object_type = match o.get("objectType") {
        None | Some(Value::Null) => None,
        Some(_) => Some(string(o, "objectType", path, ctx)?),
    };
    let mut children = Vec::new();
    if let Some(c) = o.get("children").filter(|c| !c.is_null()) {
        for (i, cv) in arr(c, &format!("{path}.children"), ctx)?.iter().enumerate() {
            children.push(parse_object(
                cv,
                &format!("{path}.children[{i}]"),
                ctx,
                depth + 1,
                warnings,
            )?);
        }
    }
    Ok(HouseObject {
        path: path.to_string(),
        id: string(o, "id", path, ctx)?,
        asset_id: string(o, "assetId", path, ctx)?,
        object_type,
        position,
        rotation_y,
        children,
    })
}

/// Reads and checks a house document.
pub fn parse_house(v: &Value, ctx: &ErrCtx) -> Result<House, MapError> {
    let root = obj(v, "", ctx)?;
    let room_list = arr(
        root.get("rooms")
            .ok_or_else(|| ctx.err("rooms", "missing required key"))?,
        "rooms",
        ctx,
    )?;
    if room_list.is_empty() {
        return Err(ctx.err("rooms", "the house has no rooms"));
    }
    let mut rooms = Vec::new();
    for (i, rv) in room_list.iter().enumerate() {
        let path = format!("rooms[{i}]");
        let o = obj(rv, &path, ctx)?;
        let poly_path = format!("{path}.floorPolygon");
        let pts = arr(field(o, "floorPolygon", &path, ctx)?, &poly_path, ctx)?;
        if pts.len() < 3 {
            return Err(ctx.err(
                poly_path,
                format!("needs at least 3 points, found {}", pts.len()),
            ));
        }
        let polygon = pts
            .iter()
            .enumerate()
            .map(|(k, p)| point(p, &format!("{poly_path}[{k}]"), ctx).map(|q| [q[0], q[2]]))
            .collect::<Result<Vec<_>, _>>()?;
        if super::raster::polygon_area(&polygon) < 1e-6 {
            return Err(ctx.err(
                poly_path,
                "encloses no floor (zero area): its points are repeated or on one line",
            ));
        }
        rooms.push(HouseRoom {
            id: string(o, "id", &path, ctx)?,
            room_type: string(o, "roomType", &path, ctx)?,
            polygon,
        });
    }

    let mut walls = Vec::new();
    for (i, wv) in list(root, "walls", ctx)?.iter().enumerate() {
        let path = format!("walls[{i}]");
        let o = obj(wv, &path, ctx)?;
        let id = string(o, "id", &path, ctx)?;
        let poly_path = format!("{path}.polygon");
        let pts = match o.get("polygon") {
            Some(p) => arr(p, &poly_path, ctx)?
                .iter()
                .enumerate()
                .map(|(k, p)| point(p, &format!("{poly_path}[{k}]"), ctx))
                .collect::<Result<Vec<_>, _>>()?,
            None => Vec::new(),
        };
        let seg = if pts.len() >= 2 {
            let low = pts.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
            let bottom: Vec<[f64; 2]> = pts
                .iter()
                .filter(|p| p[1] <= low + 1e-6)
                .map(|p| [p[0], p[2]])
                .collect();
            let b = bottom.iter().copied().find(|q| *q != bottom[0]);
            b.map(|b| (bottom[0], b))
        } else {
            None
        };
        let Some((a, b)) = seg.or_else(|| wall_segment_from_id(&id)) else {
            return Err(ctx.err(
                poly_path,
                "needs two distinct bottom corners (or an id wall|room|x0|z0|x1|z1)",
            ));
        };
        let height = pts.iter().map(|p| p[1]).fold(0.0, f64::max);
        let empty = match o.get("empty") {
            None | Some(Value::Null) => false,
            Some(Value::Bool(e)) => *e,
            Some(v) => {
                return Err(ctx.err(
                    format!("{path}.empty"),
                    format!("expected true or false, found {}", short(v)),
                ));
            }
        };
        // Exterior faces carry the `roomId` of the room inside; they belong to no room pair.
        let part = id.split('|').nth(1).unwrap_or("");
        let room_id = match o.get("roomId") {
            _ if part == "exterior" => None,
            Some(Value::String(r)) => Some(r.clone()),
            _ => (!part.is_empty()).then(|| format!("room|{part}")),
        };
        walls.push(HouseWall {
            id,
            a,
            b,
            height,
            empty,
            room_id,
        });
    }

    let doors = list(root, "doors", ctx)?
        .iter()
        .enumerate()
        .map(|(i, d)| parse_hole(d, &format!("doors[{i}]"), ctx))
        .collect::<Result<Vec<_>, _>>()?;
    let windows = list(root, "windows", ctx)?
        .iter()
        .enumerate()
        .map(|(i, d)| parse_hole(d, &format!("windows[{i}]"), ctx))
        .collect::<Result<Vec<_>, _>>()?;
    let mut warnings = Vec::new();
    let objects = list(root, "objects", ctx)?
        .iter()
        .enumerate()
        .map(|(i, o)| parse_object(o, &format!("objects[{i}]"), ctx, 0, &mut warnings))
        .collect::<Result<Vec<_>, _>>()?;

    let mut agent = None;
    let mut room_spec = None;
    if let Some(meta) = root.get("metadata").and_then(Value::as_object) {
        if let Some(a) = meta.get("agent").filter(|a| !a.is_null()) {
            let ao = obj(a, "metadata.agent", ctx)?;
            let p = point(
                field(ao, "position", "metadata.agent", ctx)?,
                "metadata.agent.position",
                ctx,
            )?;
            let yaw = match ao.get("rotation") {
                None => 0.0,
                Some(Value::Null) => {
                    warnings.push((
                        "metadata.agent.rotation".into(),
                        "is null; the start faces yaw 0°".into(),
                    ));
                    0.0
                }
                Some(r) => num_or(
                    obj(r, "metadata.agent.rotation", ctx)?,
                    "y",
                    0.0,
                    "metadata.agent.rotation",
                    ctx,
                )?,
            };
            agent = Some(([p[0], p[2]], yaw));
        }
        room_spec = meta
            .get("roomSpecId")
            .and_then(Value::as_str)
            .map(str::to_string);
    }
    Ok(House {
        rooms,
        walls,
        doors,
        windows,
        objects,
        agent,
        room_spec,
        warnings,
    })
}
