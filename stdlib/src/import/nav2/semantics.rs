//! The semantic layer of a Nav2 map: a GeoJSON FeatureCollection in the map frame, metres.
//!
//! * rooms: `Polygon` (or `MultiPolygon`) features with `"kind": "room"`, a `category` and an
//!   optional `name`;
//! * objects: `Point`, `Polygon` or `MultiPolygon` features with `"kind": "object"` (a Point needs
//!   no kind), a `category`, and optional `name`, `room` (a room's name), `size` (a Point's
//!   footprint, metres: `0.5` or `[width, depth]`, default 0.3), `height`, `elevation` (metres)
//!   and `parent` (another object's name, with `parent_relation` `on` | `inside`);
//! * doors: `LineString` features (`"kind": "door"` optional) and an optional `name`, each a
//!   `doorway` object over the cells within half a cell (at least 5 cm) of the line;
//! * open boundaries: `"kind": "open_boundary"` with `rooms: [name, name]`, a LineString or a
//!   Polygon over the cells where two rooms meet with no wall (an open-plan kitchen), passable
//!   like a doorway (`open_boundaries` in the model).
//!
//! Cells are assigned by the cell-centre rule of houses; the first room to claim a cell keeps it;
//! in the object layer later features paint over earlier ones. An object's id is its Feature's
//! `id` when it has one. Every error names the feature.

use super::params::MapYaml;
use crate::grid::{Cell, Grid};
use crate::import::raster::{Raster, polygon_area};
use crate::map::error::MapError;
use crate::map::{Object, Parent, Relation, Room};
use serde_json::Value;
use std::collections::BTreeMap;

/// A ring has at most this many vertices: the self-intersection check is quadratic in it.
pub const MAX_RING_VERTICES: usize = 4096;

pub struct Semantics {
    pub open_boundaries: Vec<crate::map::OpenBoundary>,
    pub rooms: Vec<Room>,
    pub room_layer: Grid<u32>,
    pub objects: Vec<Object>,
    pub object_layer: Grid<u32>,
}

struct Ctx<'a> {
    file: &'a str,
    yaml: &'a MapYaml,
    /// Image extent in metres along the grid's own axes.
    extent: (f64, f64),
    ras: Raster,
}

impl Ctx<'_> {
    fn err(&self, feature: &str, msg: impl Into<String>) -> MapError {
        MapError::new(self.file, feature, msg)
    }

    /// Map-frame metres into the grid's own axes (metres from the origin corner).
    fn local(&self, p: [f64; 2]) -> [f64; 2] {
        let [ox, oy, yaw] = self.yaml.origin;
        let (dx, dy) = (p[0] - ox, p[1] - oy);
        if yaw == 0.0 {
            return [dx, dy];
        }
        let (s, c) = yaw.sin_cos();
        [c * dx + s * dy, -s * dx + c * dy]
    }

    fn point(&self, v: &Value, at: &str) -> Result<[f64; 2], MapError> {
        let a = v
            .as_array()
            .filter(|a| a.len() >= 2)
            .ok_or_else(|| self.err(at, "a position is not [x, y]"))?;
        let x = a[0].as_f64().filter(|f| f.is_finite());
        let y = a[1].as_f64().filter(|f| f.is_finite());
        match (x, y) {
            (Some(x), Some(y)) => Ok(self.local([x, y])),
            _ => Err(self.err(at, "a position is not two finite numbers")),
        }
    }

    /// Checks that a local point lies on the image.
    fn inside(&self, p: [f64; 2], at: &str, orig: &Value) -> Result<(), MapError> {
        let e = 1e-9;
        if p[0] < -e || p[1] < -e || p[0] > self.extent.0 + e || p[1] > self.extent.1 + e {
            return Err(self.err(
                at,
                format!(
                    "{} lies outside the image, which covers {:.2} x {:.2} m from its origin \
                     ({}, {}); coordinates are metres in the map frame",
                    orig, self.extent.0, self.extent.1, self.yaml.origin[0], self.yaml.origin[1]
                ),
            ));
        }
        Ok(())
    }

    /// The rings of a Polygon or MultiPolygon, in local metres, checked.
    fn polygons(&self, geom: &Value, at: &str) -> Result<Vec<Vec<[f64; 2]>>, MapError> {
        let ty = geom.get("type").and_then(Value::as_str).unwrap_or("");
        let coords = geom
            .get("coordinates")
            .ok_or_else(|| self.err(at, "the geometry has no coordinates"))?;
        let polys: Vec<&Value> = match ty {
            "Polygon" => vec![coords],
            "MultiPolygon" => coords
                .as_array()
                .ok_or_else(|| self.err(at, "MultiPolygon coordinates are not a list"))?
                .iter()
                .collect(),
            _ => return Err(self.err(at, format!("is a {ty}, expected a Polygon"))),
        };
        let mut out = Vec::new();
        for (k, poly) in polys.iter().enumerate() {
            let rings = poly
                .as_array()
                .filter(|r| !r.is_empty())
                .ok_or_else(|| self.err(at, "a polygon has no rings"))?;
            if rings.len() > 1 {
                return Err(self.err(
                    at,
                    "a polygon with holes is not supported: draw the area as several polygons",
                ));
            }
            let ring = rings[0]
                .as_array()
                .ok_or_else(|| self.err(at, "a ring is not a list of positions"))?;
            if ring.len() > MAX_RING_VERTICES {
                return Err(self.err(
                    at,
                    format!(
                        "a ring has {} vertices, more than {MAX_RING_VERTICES}",
                        ring.len()
                    ),
                ));
            }
            let mut pts = Vec::with_capacity(ring.len());
            for v in ring {
                let p = self.point(v, at)?;
                self.inside(p, at, v)?;
                pts.push(p);
            }
            if pts.len() > 1 && pts.first() == pts.last() {
                pts.pop();
            }
            if pts.len() < 3 {
                return Err(self.err(at, "a polygon needs at least 3 distinct vertices"));
            }
            if let Some((i, j)) = self_intersection(&pts) {
                let part = if polys.len() > 1 {
                    format!("polygon {k}: ")
                } else {
                    String::new()
                };
                return Err(self.err(
                    at,
                    format!("{part}is self-intersecting: edge {i} crosses edge {j}"),
                ));
            }
            out.push(pts);
        }
        Ok(out)
    }
}

/// The first pair of non-adjacent edges of a closed ring that touch or cross.
fn self_intersection(p: &[[f64; 2]]) -> Option<(usize, usize)> {
    let n = p.len();
    for i in 0..n {
        let (a, b) = (p[i], p[(i + 1) % n]);
        for j in i + 1..n {
            if j == i + 1 || (i == 0 && j == n - 1) {
                continue;
            }
            let (c, d) = (p[j], p[(j + 1) % n]);
            if segments_intersect(a, b, c, d) {
                return Some((i, j));
            }
        }
    }
    None
}

fn cross(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

fn segments_intersect(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let d1 = cross(c, d, a);
    let d2 = cross(c, d, b);
    let d3 = cross(a, b, c);
    let d4 = cross(a, b, d);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        q[0] <= p[0].max(r[0])
            && q[0] >= p[0].min(r[0])
            && q[1] <= p[1].max(r[1])
            && q[1] >= p[1].min(r[1])
    };
    (d1 == 0.0 && on(c, a, d))
        || (d2 == 0.0 && on(c, b, d))
        || (d3 == 0.0 && on(a, c, b))
        || (d4 == 0.0 && on(a, d, b))
}

/// A category must be a name the language can write: lower-case snake_case.
fn check_category(ctx: &Ctx<'_>, at: &str, v: Option<&Value>) -> Result<String, MapError> {
    let Some(v) = v else {
        return Err(ctx.err(
            at,
            "has no `category` property (e.g. \"kitchen\", \"sofa\")",
        ));
    };
    let s = v
        .as_str()
        .ok_or_else(|| ctx.err(at, format!("category {v} is not a string")))?;
    let ok = !s.is_empty()
        && s.starts_with(|c: char| c.is_ascii_lowercase())
        && s.chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
    if ok {
        return Ok(s.to_string());
    }
    let fixed = crate::import::naming::category_snake(s.trim());
    let help = if !fixed.is_empty() && fixed != s {
        format!("; help: write it as `{fixed}`")
    } else {
        String::new()
    };
    Err(ctx.err(
        at,
        format!("unknown category `{s}`: categories are lower-case snake_case names{help}"),
    ))
}

fn feature_label(i: usize, props: &serde_json::Map<String, Value>) -> String {
    match props.get("name").and_then(Value::as_str) {
        Some(n) => format!("features[{i}] (`{n}`)"),
        None => format!("features[{i}]"),
    }
}

fn positive(
    ctx: &Ctx<'_>,
    at: &str,
    props: &serde_json::Map<String, Value>,
    k: &str,
) -> Result<Option<f64>, MapError> {
    match props.get(k) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => v
            .as_f64()
            .filter(|f| f.is_finite() && *f >= 0.0 && *f <= 1e4)
            .map(Some)
            .ok_or_else(|| {
                ctx.err(
                    at,
                    format!("`{k}` is not a non-negative number of metres: {v}"),
                )
            }),
    }
}

/// Reads the semantic layer onto an `n`×`n` grid whose image covers `w`×`h` cells.
pub fn read_semantics(
    text: &str,
    file: &str,
    yaml: &MapYaml,
    n: usize,
    (w, h): (usize, usize),
) -> Result<Semantics, MapError> {
    let res = yaml.resolution;
    let ctx = Ctx {
        file,
        yaml,
        extent: (w as f64 * res, h as f64 * res),
        ras: Raster {
            x_min: res / 2.0,
            z_min: res / 2.0,
            res,
            n,
        },
    };
    let root: Value = serde_json::from_str(text)
        .map_err(|e| MapError::new(file, "", format!("not JSON: {e}")))?;
    if root.get("type").and_then(Value::as_str) != Some("FeatureCollection") {
        return Err(ctx.err("type", "is not \"FeatureCollection\""));
    }
    let feats = root
        .get("features")
        .and_then(Value::as_array)
        .ok_or_else(|| ctx.err("features", "is missing or not a list"))?;

    let mut rooms: Vec<Room> = Vec::new();
    let mut room_layer = Grid::new(n, 0u32);
    let mut room_names: BTreeMap<String, u32> = BTreeMap::new();
    // Objects are read after every room, so `room` may name a room defined later.
    let mut pending = Vec::new();
    let empty = serde_json::Map::new();
    for (i, f) in feats.iter().enumerate() {
        let props = f
            .get("properties")
            .and_then(Value::as_object)
            .unwrap_or(&empty);
        let at = feature_label(i, props);
        let geom = f
            .get("geometry")
            .filter(|g| g.is_object())
            .ok_or_else(|| ctx.err(&at, "has no geometry"))?;
        let gty = geom.get("type").and_then(Value::as_str).unwrap_or("");
        let kind = match props.get("kind").and_then(Value::as_str) {
            Some(k) => k.to_string(),
            None => match gty {
                "Point" => "object".into(),
                "LineString" => "door".into(),
                _ => {
                    return Err(ctx.err(
                        &at,
                        "a polygon needs `\"kind\": \"room\"` or `\"kind\": \"object\"`",
                    ));
                }
            },
        };
        match kind.as_str() {
            "room" => {
                let category = check_category(&ctx, &at, props.get("category"))?;
                let polys = ctx.polygons(geom, &at)?;
                let id = rooms.len() as u32 + 1;
                let name = match props.get("name").and_then(Value::as_str) {
                    Some(s) => s.to_string(),
                    None => format!(
                        "{category}_{}",
                        rooms.iter().filter(|r| r.category == category).count() + 1
                    ),
                };
                if room_names.insert(name.clone(), id).is_some() {
                    return Err(ctx.err(&at, format!("a second room is named `{name}`")));
                }
                let mut area = 0.0;
                let mut cells = 0usize;
                for p in &polys {
                    area += polygon_area(p).abs();
                    for c in ctx.ras.polygon_cells(p) {
                        let slot = room_layer.get_mut(c).expect("inside the grid");
                        if *slot == 0 {
                            *slot = id;
                            cells += 1;
                        }
                    }
                }
                rooms.push(Room {
                    id,
                    category,
                    name,
                    area_m2: (area * 1e4).round() / 1e4,
                    attributes: vec![format!("grid_area={cells}")],
                });
            }
            "object" | "door" | "open_boundary" => pending.push((i, at, kind, geom, props)),
            other => {
                return Err(ctx.err(
                    &at,
                    format!("unknown kind `{other}`: expected room, object or door"),
                ));
            }
        }
    }

    let mut objects: Vec<Object> = Vec::new();
    let mut object_names: BTreeMap<String, u32> = BTreeMap::new();
    let mut parents: Vec<(usize, String, Relation, String)> = Vec::new();
    let mut per_category: BTreeMap<String, usize> = BTreeMap::new();
    let mut open_boundaries = Vec::new();
    // A Feature's own `id` (a positive integer) is the object's id; the others take the
    // smallest ids left, in file order.
    let mut taken = std::collections::BTreeSet::new();
    for (i, at, _, _, _) in &pending {
        if let Some(v) = feats[*i].get("id") {
            let id = v
                .as_u64()
                .filter(|&id| id > 0 && id < u32::MAX as u64)
                .ok_or_else(|| ctx.err(at, format!("`id` {v} is not a positive integer")))?;
            if !taken.insert(id as u32) {
                return Err(ctx.err(at, format!("a second feature has id {id}")));
            }
        }
    }
    let mut next_free = 0u32;
    for (fi, at, kind, geom, props) in pending {
        let gty = geom.get("type").and_then(Value::as_str).unwrap_or("");
        if kind == "open_boundary" {
            open_boundaries.push(open_boundary(&ctx, &at, geom, props, &room_names)?);
            continue;
        }
        let category = if kind == "door" {
            "doorway".to_string()
        } else {
            check_category(&ctx, &at, props.get("category"))?
        };
        let mut footprint: Vec<Cell> = match (kind.as_str(), gty) {
            ("door", "LineString") => {
                let pts = geom
                    .get("coordinates")
                    .and_then(Value::as_array)
                    .filter(|a| a.len() >= 2)
                    .ok_or_else(|| {
                        ctx.err(&at, "a door's LineString needs at least 2 positions")
                    })?;
                let mut ps = Vec::new();
                for v in pts {
                    let p = ctx.point(v, &at)?;
                    ctx.inside(p, &at, v)?;
                    ps.push(p);
                }
                let hw = (res / 2.0).max(0.05);
                ps.windows(2)
                    .flat_map(|s| ctx.ras.segment_cells(s[0], s[1], hw))
                    .map(|(c, _)| c)
                    .collect()
            }
            ("door", _) => return Err(ctx.err(&at, format!("a door is a LineString, not a {gty}"))),
            (_, "Point") => {
                let v = geom.get("coordinates").cloned().unwrap_or(Value::Null);
                let p = ctx.point(&v, &at)?;
                ctx.inside(p, &at, &v)?;
                let (sx, sy) = match props.get("size") {
                    None | Some(Value::Null) => (0.3, 0.3),
                    Some(Value::Array(a)) if a.len() == 2 => match (a[0].as_f64(), a[1].as_f64()) {
                        (Some(x), Some(y)) if x > 0.0 && y > 0.0 && x < 1e3 && y < 1e3 => (x, y),
                        _ => return Err(ctx.err(&at, "`size` is not [width, depth] in metres")),
                    },
                    Some(v) => match v.as_f64() {
                        Some(s) if s > 0.0 && s < 1e3 => (s, s),
                        _ => {
                            return Err(
                                ctx.err(&at, "`size` is not a size in metres or [width, depth]")
                            );
                        }
                    },
                };
                let sq = [
                    [p[0] - sx / 2.0, p[1] - sy / 2.0],
                    [p[0] + sx / 2.0, p[1] - sy / 2.0],
                    [p[0] + sx / 2.0, p[1] + sy / 2.0],
                    [p[0] - sx / 2.0, p[1] + sy / 2.0],
                ];
                let mut cells = ctx.ras.polygon_cells(&sq);
                if cells.is_empty() {
                    let col = ((p[0] / res).floor() as u32).min(n as u32 - 1);
                    let row = ((p[1] / res).floor() as u32).min(n as u32 - 1);
                    cells.push(Cell::new(row, col));
                }
                cells
            }
            (_, "Polygon" | "MultiPolygon") => {
                let polys = ctx.polygons(geom, &at)?;
                let mut cells: Vec<Cell> = polys
                    .iter()
                    .flat_map(|p| ctx.ras.polygon_cells(p))
                    .collect();
                if cells.is_empty() {
                    let p = &polys[0];
                    let cx = p.iter().map(|q| q[0]).sum::<f64>() / p.len() as f64;
                    let cy = p.iter().map(|q| q[1]).sum::<f64>() / p.len() as f64;
                    let col = ((cx / res).floor() as u32).min(n as u32 - 1);
                    let row = ((cy / res).floor() as u32).min(n as u32 - 1);
                    cells.push(Cell::new(row, col));
                }
                cells
            }
            _ => {
                return Err(ctx.err(
                    &at,
                    format!("an object is a Point or a Polygon, not a {gty}"),
                ));
            }
        };
        footprint.sort_unstable();
        footprint.dedup();
        let id = match feats[fi].get("id").and_then(Value::as_u64) {
            Some(id) => id as u32,
            None => {
                next_free += 1;
                while taken.contains(&next_free) {
                    next_free += 1;
                }
                next_free
            }
        };
        let k = per_category.entry(category.clone()).or_insert(0);
        *k += 1;
        let name = match props.get("name").and_then(Value::as_str) {
            Some(s) => s.to_string(),
            None => format!("{category}_{k}"),
        };
        if object_names.insert(name.clone(), id).is_some() {
            return Err(ctx.err(&at, format!("a second object is named `{name}`")));
        }
        let room = match props.get("room") {
            None | Some(Value::Null) => dominant_room(&room_layer, &footprint),
            Some(v) => {
                let r = v.as_str().unwrap_or_default();
                Some(*room_names.get(r).ok_or_else(|| {
                    let known: Vec<&str> = room_names.keys().map(String::as_str).collect();
                    ctx.err(
                        &at,
                        format!(
                            "room `{r}` is not the name of any room feature (rooms: {})",
                            known.join(", ")
                        ),
                    )
                })?)
            }
        };
        if let Some(p) = props.get("parent").and_then(Value::as_str) {
            let rel = match props.get("parent_relation").and_then(Value::as_str) {
                None | Some("on") => Relation::On,
                Some("inside") => Relation::Inside,
                Some(o) => {
                    return Err(ctx.err(&at, format!("parent_relation `{o}` is not on or inside")));
                }
            };
            parents.push((objects.len(), p.to_string(), rel, at.clone()));
        }
        let (sr, sc) = footprint
            .iter()
            .fold((0.0, 0.0), |(r, c), x| (r + x.row as f64, c + x.col as f64));
        let k = footprint.len().max(1) as f64;
        let r3 = |x: f64| (x * 1000.0).round() / 1000.0;
        objects.push(Object {
            id,
            category,
            name,
            center: [r3(sr / k), r3(sc / k)],
            footprint,
            elevation_m: positive(&ctx, &at, props, "elevation")?,
            height_m: positive(&ctx, &at, props, "height")?,
            room,
            parent: None,
            attributes: Vec::new(),
        });
    }
    for (i, p, relation, at) in parents {
        let id = *object_names
            .get(&p)
            .ok_or_else(|| ctx.err(&at, format!("parent `{p}` is not the name of any object")))?;
        objects[i].parent = Some(Parent { id, relation });
    }
    // Painted in file order; the model keeps objects sorted by id.
    let mut object_layer = Grid::new(n, 0u32);
    for o in &objects {
        for &c in &o.footprint {
            object_layer.set(c, o.id);
        }
    }
    objects.sort_by_key(|o| o.id);
    open_boundaries.sort_by_key(|o: &crate::map::OpenBoundary| o.rooms);
    Ok(Semantics {
        open_boundaries,
        rooms,
        room_layer,
        objects,
        object_layer,
    })
}

fn open_boundary(
    ctx: &Ctx<'_>,
    at: &str,
    geom: &Value,
    props: &serde_json::Map<String, Value>,
    room_names: &BTreeMap<String, u32>,
) -> Result<crate::map::OpenBoundary, MapError> {
    let names: Vec<&str> = props
        .get("rooms")
        .and_then(Value::as_array)
        .map(|a| a.iter().filter_map(Value::as_str).collect())
        .unwrap_or_default();
    let ids: Vec<u32> = names
        .iter()
        .filter_map(|n| room_names.get(*n).copied())
        .collect();
    if names.len() != 2 || ids.len() != 2 || ids[0] == ids[1] {
        return Err(ctx.err(
            at,
            "an open boundary needs `rooms`: the names of two different room features",
        ));
    }
    let mut cells: Vec<Cell> = match geom.get("type").and_then(Value::as_str) {
        Some("LineString") => {
            let pts = geom
                .get("coordinates")
                .and_then(Value::as_array)
                .filter(|a| a.len() >= 2)
                .ok_or_else(|| ctx.err(at, "a LineString needs at least 2 positions"))?;
            let mut ps = Vec::new();
            for v in pts {
                let p = ctx.point(v, at)?;
                ctx.inside(p, at, v)?;
                ps.push(p);
            }
            let hw = (ctx.yaml.resolution / 2.0).max(0.05);
            ps.windows(2)
                .flat_map(|s| ctx.ras.segment_cells(s[0], s[1], hw))
                .map(|(c, _)| c)
                .collect()
        }
        _ => ctx
            .polygons(geom, at)?
            .iter()
            .flat_map(|p| ctx.ras.polygon_cells(p))
            .collect(),
    };
    cells.sort_unstable();
    cells.dedup();
    Ok(crate::map::OpenBoundary {
        rooms: (ids[0].min(ids[1]), ids[0].max(ids[1])),
        cells,
    })
}

/// The room covering most of `cells`, ties to the smaller id.
fn dominant_room(layer: &Grid<u32>, cells: &[Cell]) -> Option<u32> {
    let mut count: BTreeMap<u32, usize> = BTreeMap::new();
    for c in cells {
        let r = layer.get(*c).copied().unwrap_or(0);
        if r != 0 {
            *count.entry(r).or_insert(0) += 1;
        }
    }
    count
        .into_iter()
        .max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(&a.0)))
        .map(|(r, _)| r)
}
