//! ProcTHOR house -> semantic map, without the simulator.
//!
//! The reference exporter asks AI2-THOR for reachable positions and runtime object boxes; here the
//! same map is built from the house JSON alone:
//! * rooms from floor polygons (cell-centre rule, the first room to claim a cell keeps it);
//! * walls from `walls[]` (the two faces of an interior wall are one `wall` object) rasterized as
//!   a band of half-width `max(res/2, 0.05)` m, as the reference rasterizes runtime walls; a house
//!   without `walls` gets one wall per floor-polygon edge;
//! * doors cut their hole (`holePolygon` along `wall0`) out of the walls and become `doorway` /
//!   `doorframe` objects covering the hole; windows become `window` objects on their wall;
//! * every object and child object is an instance whose footprint is its asset box rotated by
//!   `rotation.y`; children keep their parent, `inside` when the parent is a closed receptacle and
//!   the child sits below its top, `on` otherwise; every `sink` gets a synthesised `sink_basin`
//!   child (`cabinet` and `drawer` parts are not synthesised: their number and place exist only
//!   in the simulator);
//! * traversable = floor minus walls minus floor-standing objects (top-level objects whose bottom
//!   is within 0.1 m of the floor), eroded by the robot radius (default 0.2 m) with the exact EDT;
//! * 1 m padding around the floor polygons, then padded to a square like the reference.

use super::assets::AssetDb;
use super::bounds::{DEFAULT_MAX_IMPORT_MEMORY, GridPlan, plan_grid};
use super::check::check_map;
use super::house::{House, HouseObject, parse_house};
use super::naming::{category_snake, object_type_from_asset_id};
use super::placement::{in_house, placement_warnings};
use super::raster::{Raster, box_corners, polygon_area};
use super::sizes::{builtin_size, has_builtin_size};
use super::walls::collect_walls;
use crate::field::{NO_SOURCE, squared_distances};
use crate::grid::{Cell, Grid};
use crate::map::error::{ErrCtx, MapError};
use crate::map::format::{centroid, dominant_room};
use crate::map::model::{
    FREE, GridFrame, MapDocument, MapExtra, OBSTACLE, Object, OpenBoundary, Parent, Relation, Room,
    SemanticMap,
};
use serde_json::{Map, Value, json};
use std::collections::{BTreeMap, HashMap};

/// Robot radius the importer erodes free space by, metres (about a LoCoBot / AI2-THOR agent).
pub const DEFAULT_ROBOT_RADIUS_M: f64 = 0.2;
/// Grid resolution of the benchmark maps, metres per cell.
pub const DEFAULT_RESOLUTION_M: f64 = 0.05;
/// Margin around the floor polygons, metres (the reference's `padding`).
pub const DEFAULT_PADDING_M: f64 = 1.0;
/// Objects whose bottom is at most this far above the floor stand on it and block the robot.
pub const FLOOR_STANDING_MAX_ELEVATION_M: f64 = 0.1;

#[derive(Clone, Debug)]
pub struct ImportOptions {
    pub resolution: f64,
    pub padding_m: f64,
    pub robot_radius_m: f64,
    /// Map id to record; the caller derives it from the file name when `None`.
    pub map_id: Option<String>,
    /// Refuse a house whose grid would need more memory than this, bytes (see
    /// [`super::bounds::IMPORT_BYTES_PER_CELL`]).
    pub max_memory_bytes: u64,
}

impl Default for ImportOptions {
    fn default() -> Self {
        ImportOptions {
            resolution: DEFAULT_RESOLUTION_M,
            padding_m: DEFAULT_PADDING_M,
            robot_radius_m: DEFAULT_ROBOT_RADIUS_M,
            map_id: None,
            max_memory_bytes: DEFAULT_MAX_IMPORT_MEMORY,
        }
    }
}

/// Parents whose children can sit inside them.
const RECEPTACLES: [&str; 11] = [
    "fridge",
    "microwave",
    "drawer",
    "cabinet",
    "box",
    "safe",
    "garbage_can",
    "laundry_hamper",
    "dresser",
    "washing_machine",
    "clothes_dryer",
];

/// The reference's overlap priorities for the object layer (higher wins a cell).
fn priority(category: &str) -> u8 {
    match category {
        "wall" => 5,
        "sofa" | "table" | "desk" | "bed" => 100,
        "chair" | "counter_top" | "fridge" => 90,
        "cabinet" | "sink" | "toilet" | "bathtub" | "door" => 80,
        "garbage_can" | "house_plant" => 60,
        "apple" | "egg" | "fork" | "plate" => 10,
        _ => 50,
    }
}

fn r4(x: f64) -> f64 {
    (x * 10_000.0).round() / 10_000.0
}

/// An instance under construction.
struct Proto {
    category: String,
    object_type: String,
    source_id: String,
    asset_id: Option<String>,
    footprint: Vec<Cell>,
    footprint_source: &'static str,
    /// World position `(x, z)` and height of the box centre, for the overlap tie-break.
    position: [f64; 3],
    elevation: Option<f64>,
    height: Option<f64>,
    parent: Option<(usize, Relation)>,
    extra_attrs: Vec<String>,
    floor_standing: bool,
}

struct Resolver<'a> {
    assets: Option<&'a AssetDb>,
    ctx: &'a ErrCtx,
}

impl Resolver<'_> {
    /// Object type and box size of an asset.
    fn resolve(
        &self,
        asset_id: &str,
        explicit: Option<&str>,
        path: &str,
    ) -> Result<(String, [f64; 3]), MapError> {
        if let Some(db) = self.assets {
            if let Some(info) = db.get(asset_id) {
                return Ok((explicit.unwrap_or(&info.object_type).to_string(), info.size));
            }
            if explicit.is_none() {
                return Err(self.ctx.err(
                    format!("{path}.assetId"),
                    format!("asset {asset_id:?} is not in the asset database"),
                ));
            }
        }
        let ty = match explicit {
            Some(t) => t.to_string(),
            None => object_type_from_asset_id(asset_id).map(str::to_string).ok_or_else(|| {
                self.ctx.err(
                    format!("{path}.assetId"),
                    format!("cannot tell the object type of asset {asset_id:?}; pass an asset database"),
                )
            })?,
        };
        if !has_builtin_size(&ty) && self.assets.is_none() && explicit.is_some() {
            return Err(self.ctx.err(
                format!("{path}.objectType"),
                format!("unknown object type {ty:?}"),
            ));
        }
        Ok((ty.clone(), builtin_size(&ty)))
    }
}

/// Imports a parsed house document. `file` names it in errors.
pub fn import_house(
    doc: &Value,
    file: &str,
    assets: Option<&AssetDb>,
    opts: &ImportOptions,
) -> Result<SemanticMap, MapError> {
    import_house_document(doc, file, assets, opts).map(|d| d.map)
}

/// Imports a house, keeping the metadata the Map2Route writer records (`map_info`, import
/// settings, `footprint_source` per object).
pub fn import_house_document(
    doc: &Value,
    file: &str,
    assets: Option<&AssetDb>,
    opts: &ImportOptions,
) -> Result<MapDocument, MapError> {
    let ctx = ErrCtx::new(file);
    check_options(opts, &ctx)?;
    let house = parse_house(doc, &ctx)?;
    build(&house, &ctx, assets, opts, file)
}

fn check_options(opts: &ImportOptions, ctx: &ErrCtx) -> Result<(), MapError> {
    if !(opts.resolution.is_finite() && opts.resolution >= 0.005 && opts.resolution <= 10.0) {
        return Err(ctx.err(
            "",
            format!(
                "resolution must be between 0.005 and 10 m, got {}",
                opts.resolution
            ),
        ));
    }
    if !(opts.robot_radius_m.is_finite() && (0.0..=5.0).contains(&opts.robot_radius_m)) {
        return Err(ctx.err(
            "",
            format!(
                "robot radius must be between 0 and 5 m, got {}",
                opts.robot_radius_m
            ),
        ));
    }
    if !(opts.padding_m.is_finite() && (0.0..=100.0).contains(&opts.padding_m)) {
        return Err(ctx.err(
            "",
            format!(
                "padding must be between 0 and 100 m, got {}",
                opts.padding_m
            ),
        ));
    }
    Ok(())
}

fn build(
    house: &House,
    ctx: &ErrCtx,
    assets: Option<&AssetDb>,
    opts: &ImportOptions,
    file: &str,
) -> Result<MapDocument, MapError> {
    let res = opts.resolution;
    let GridPlan {
        x_min,
        x_max,
        z_min,
        z_max,
        h,
        w,
        n,
    } = plan_grid(house, opts, ctx)?;
    let ras = Raster {
        x_min,
        z_min,
        res,
        n,
    };

    let mut warnings = house.warnings.clone();

    // Rooms.
    let mut room_layer = Grid::new(n, 0u32);
    let mut room_ids: HashMap<&str, u32> = HashMap::new();
    let mut rooms = Vec::new();
    let mut per_cat: BTreeMap<String, usize> = BTreeMap::new();
    let mut scene_size = 0.0;
    for (i, r) in house.rooms.iter().enumerate() {
        let id = i as u32 + 1;
        room_ids.entry(r.id.as_str()).or_insert(id);
        for c in ras.polygon_cells(&r.polygon) {
            let slot = room_layer.get_mut(c).expect("raster cells lie in the grid");
            if *slot == 0 {
                *slot = id;
            }
        }
        let category = category_snake(&r.room_type);
        let k = per_cat.entry(category.clone()).or_insert(0);
        *k += 1;
        let area = r4(polygon_area(&r.polygon));
        scene_size += area;
        rooms.push(Room {
            id,
            name: format!("{category}_{k}"),
            category,
            area_m2: area,
            attributes: vec![
                format!("procthor_room_id={}", r.id),
                format!("procthor_room_type={}", r.room_type),
            ],
        });
    }
    let mut room_cells = vec![0usize; rooms.len() + 1];
    for &v in room_layer.data() {
        room_cells[v as usize] += 1;
    }
    for (i, room) in rooms.iter().enumerate() {
        if room_cells[room.id as usize] == 0 {
            warnings.push((
                format!("rooms[{i}]"),
                format!(
                    "{} ({:.3} m²) covers no cell at {res} m per cell; it has no floor in the map",
                    house.rooms[i].id, room.area_m2
                ),
            ));
        }
    }
    for room in &mut rooms {
        let grid_area = r4(room_cells[room.id as usize] as f64 * res * res);
        room.attributes.push(format!(
            "area={}",
            crate::map::pyjson::py_float(room.area_m2)
        ));
        room.attributes.push(format!(
            "grid_area={}",
            crate::map::pyjson::py_float(grid_area)
        ));
    }

    // Walls, door holes, windows. Open (`empty`) walls are not built: they become open
    // boundaries between their two rooms.
    let half_width = (res * 0.5).max(0.05);
    let wall_set = collect_walls(house, &mut warnings);
    let walls = &wall_set.walls;
    let mut wall_mask = Grid::new(n, false);
    let mut wall_cells: Vec<Vec<Cell>> = Vec::with_capacity(walls.len());
    let mut open: BTreeMap<(u32, u32), Vec<Cell>> = BTreeMap::new();
    for wall in walls {
        let cells: Vec<Cell> = ras
            .segment_cells(wall.a, wall.b, half_width)
            .into_iter()
            .map(|(c, _)| c)
            .collect();
        if wall.open {
            let ids: Vec<u32> = wall
                .rooms
                .iter()
                .filter_map(|r| room_ids.get(r.as_str()).copied())
                .collect();
            if let [p, q] = ids[..] {
                open.entry((p.min(q), p.max(q))).or_default().extend(cells);
            } else {
                warnings.push((
                    format!("walls ({})", wall.ids.join(", ")),
                    "is empty (open) but does not lie between two rooms of the house; it is \
                     left out"
                        .into(),
                ));
            }
            wall_cells.push(Vec::new());
            continue;
        }
        for &c in &cells {
            wall_mask.set(c, true);
        }
        wall_cells.push(cells);
    }
    let open_boundaries: Vec<OpenBoundary> = open
        .into_iter()
        .map(|(rooms, mut cells)| {
            cells.sort_unstable();
            cells.dedup();
            OpenBoundary { rooms, cells }
        })
        .collect();
    let resolver = Resolver { assets, ctx };
    let mut protos: Vec<Proto> = Vec::new();
    let mut holes: Vec<Cell> = Vec::new();
    let mut door_protos = Vec::new();
    for (i, d) in house.doors.iter().enumerate() {
        let path = format!("doors[{i}]");
        let cells = wall_set.hole_cells(d, &ras, half_width, &path, ctx, &mut warnings)?;
        holes.extend(&cells);
        let (ty, _) = resolver.resolve(&d.asset_id, None, &path)?;
        let connects = if d.room0 == d.room1 {
            d.room0.clone()
        } else {
            format!("{},{}", d.room0, d.room1)
        };
        door_protos.push(Proto {
            category: category_snake(&ty),
            object_type: ty,
            source_id: d.id.clone(),
            asset_id: Some(d.asset_id.clone()),
            footprint: cells,
            footprint_source: "wall_hole",
            position: [0.0; 3],
            elevation: Some(r4(d.vertical[0])),
            height: Some(r4(d.vertical[1] - d.vertical[0])),
            parent: None,
            extra_attrs: vec![format!("procthor_connects={connects}")],
            floor_standing: false,
        });
    }
    for &c in &holes {
        wall_mask.set(c, false);
    }
    for (wall, cells) in walls.iter().zip(&mut wall_cells) {
        if wall.open {
            continue;
        }
        cells.retain(|&c| wall_mask.get(c) == Some(&true));
        protos.push(Proto {
            category: "wall".into(),
            object_type: "Wall".into(),
            source_id: wall.ids[0].clone(),
            asset_id: None,
            footprint: std::mem::take(cells),
            footprint_source: "wall_segment",
            position: [0.0; 3],
            elevation: Some(0.0),
            height: Some(r4(wall.height)),
            parent: None,
            extra_attrs: if wall.ids.len() > 1 {
                vec![format!("procthor_wall_faces={}", wall.ids.join(","))]
            } else {
                vec![]
            },
            floor_standing: false,
        });
    }
    protos.extend(door_protos);
    for (i, win) in house.windows.iter().enumerate() {
        let path = format!("windows[{i}]");
        let cells = wall_set.hole_cells(win, &ras, half_width, &path, ctx, &mut warnings)?;
        let (ty, _) = resolver.resolve(&win.asset_id, None, &path)?;
        protos.push(Proto {
            category: category_snake(&ty),
            object_type: ty,
            source_id: win.id.clone(),
            asset_id: Some(win.asset_id.clone()),
            footprint: cells,
            footprint_source: "wall_hole",
            position: [0.0; 3],
            elevation: Some(r4(win.vertical[0])),
            height: Some(r4(win.vertical[1] - win.vertical[0])),
            parent: None,
            extra_attrs: vec![format!("procthor_wall={}", win.wall0)],
            floor_standing: false,
        });
    }

    // Objects and their children, depth first.
    fn add_object(
        o: &HouseObject,
        parent: Option<(usize, [f64; 3], f64, &str)>,
        resolver: &Resolver<'_>,
        ras: &Raster,
        protos: &mut Vec<Proto>,
    ) -> Result<(), MapError> {
        let (ty, size) = resolver.resolve(&o.asset_id, o.object_type.as_deref(), &o.path)?;
        let category = category_snake(&ty);
        let [x, y, z] = o.position;
        let corners = box_corners(x, z, size[0], size[2], o.rotation_y);
        let mut footprint = ras.polygon_cells(&corners);
        let mut source = "bbox";
        if footprint.is_empty() {
            // Too small for any cell centre: the reference's plus-shaped centre fallback.
            let c = ras.clamp_cell(x, z);
            let (r, col) = (c.row as i64, c.col as i64);
            for (dr, dc) in [(0, 0), (-1, 0), (1, 0), (0, -1), (0, 1)] {
                let (rr, cc) = (r + dr, col + dc);
                if rr >= 0 && cc >= 0 && (rr as usize) < ras.n && (cc as usize) < ras.n {
                    footprint.push(Cell::new(rr as u32, cc as u32));
                }
            }
            source = "center_fallback";
        }
        let elevation = r4((y - size[1] / 2.0).max(0.0));
        let relation = parent.map(|(pid, ppos, ptop, pcat)| {
            let below_top = y < ppos[1].max(0.0) + ptop - 0.02;
            let rel = if RECEPTACLES.contains(&pcat) && below_top {
                Relation::Inside
            } else {
                Relation::On
            };
            (pid, rel)
        });
        let me = protos.len();
        protos.push(Proto {
            category: category.clone(),
            object_type: ty,
            source_id: o.id.clone(),
            asset_id: Some(o.asset_id.clone()),
            footprint,
            footprint_source: source,
            position: o.position,
            elevation: Some(elevation),
            height: Some(r4(size[1])),
            parent: relation,
            extra_attrs: vec![],
            floor_standing: parent.is_none() && elevation <= FLOOR_STANDING_MAX_ELEVATION_M,
        });
        if category == "sink" {
            let fp = protos[me].footprint.clone();
            protos.push(Proto {
                category: "sink_basin".into(),
                object_type: "SinkBasin".into(),
                source_id: format!("{}|SinkBasin", o.id),
                asset_id: None,
                footprint: fp,
                footprint_source: "synthesized_from_parent",
                position: o.position,
                elevation: None,
                height: None,
                parent: Some((me, Relation::Inside)),
                extra_attrs: vec!["synthesized=true".into()],
                floor_standing: false,
            });
        }
        let half_height = size[1] / 2.0;
        let cat = protos[me].category.clone();
        for child in &o.children {
            add_object(
                child,
                Some((me, o.position, half_height, cat.as_str())),
                resolver,
                ras,
                protos,
            )?;
        }
        Ok(())
    }
    for o in &house.objects {
        add_object(o, None, &resolver, &ras, &mut protos)?;
    }

    // Occupancy: floor minus walls minus floor-standing objects, eroded by the robot radius.
    let mut blocked = room_layer.map(|&r| r == 0);
    for (b, &w) in blocked.data_mut().iter_mut().zip(wall_mask.data()) {
        *b |= w;
    }
    for p in protos.iter().filter(|p| p.floor_standing) {
        for &c in &p.footprint {
            blocked.set(c, true);
        }
    }
    let occupancy = if opts.robot_radius_m > 0.0 {
        // Squared distances as exact integers (4 bytes a cell instead of 8).
        let d2 = squared_distances(blocked.data(), n);
        let r_cells = opts.robot_radius_m / res;
        let limit = r_cells * r_cells - 1e-9;
        let occ: Vec<u8> = d2
            .iter()
            .map(|&d| {
                if d != NO_SOURCE && d as f64 >= limit {
                    FREE
                } else {
                    OBSTACLE
                }
            })
            .collect();
        Grid::from_vec(n, occ).expect("one value per cell")
    } else {
        blocked.map(|&b| if b { OBSTACLE } else { FREE })
    };
    drop(blocked);

    // Object layer: per cell the highest (priority, footprint area, -height) wins, ties to the
    // earlier instance.
    let mut object_layer = Grid::new(n, 0u32);
    let keys: Vec<(u8, f64, f64)> = protos
        .iter()
        .map(|p| {
            (
                priority(&p.category),
                p.footprint.len() as f64 * res * res,
                -p.position[1],
            )
        })
        .collect();
    for (i, p) in protos.iter().enumerate() {
        for &c in &p.footprint {
            let slot = object_layer.get_mut(c).expect("footprints lie in the grid");
            let better = *slot == 0 || {
                let cur = keys[*slot as usize - 1];
                let k = keys[i];
                k.0 > cur.0 || (k.0 == cur.0 && (k.1 > cur.1 || (k.1 == cur.1 && k.2 > cur.2)))
            };
            if better {
                *slot = i as u32 + 1;
            }
        }
    }

    // Instances.
    let mut objects = Vec::with_capacity(protos.len());
    let mut object_keys = BTreeMap::new();
    let mut per_cat: BTreeMap<String, usize> = BTreeMap::new();
    for (i, mut p) in protos.into_iter().enumerate() {
        let id = i as u32 + 1;
        p.footprint.sort_unstable();
        p.footprint.dedup();
        let k = per_cat.entry(p.category.clone()).or_insert(0);
        *k += 1;
        let room = dominant_room(&p.footprint, &room_layer).or_else(|| {
            ras.cell_of(p.position[0], p.position[2])
                .map(|c| *room_layer.get(c).unwrap_or(&0))
                .filter(|&r| r != 0)
        });
        let mut attributes = vec![
            format!("procthor_object_id={}", p.source_id),
            format!("procthor_object_type={}", p.object_type),
        ];
        if let Some(a) = &p.asset_id {
            attributes.push(format!("asset_id={a}"));
        }
        attributes.push(format!("footprint_source={}", p.footprint_source));
        attributes.push(format!("num_grid_cells={}", p.footprint.len()));
        attributes.push(format!(
            "footprint_area={}",
            crate::map::pyjson::py_float(r4(p.footprint.len() as f64 * res * res))
        ));
        attributes.extend(p.extra_attrs);
        let mut keys = Map::new();
        keys.insert("footprint_source".into(), json!(p.footprint_source));
        object_keys.insert(id, keys);
        objects.push(Object {
            id,
            name: format!("{}_{k}", p.category),
            center: centroid(&p.footprint),
            category: p.category,
            footprint: p.footprint,
            elevation_m: p.elevation,
            height_m: p.height,
            room,
            parent: p.parent.map(|(pi, relation)| Parent {
                id: pi as u32 + 1,
                relation,
            }),
            attributes,
        });
    }

    let map_id = opts.map_id.clone().unwrap_or_else(|| {
        let name = file.rsplit(['/', '\\']).next().unwrap_or(file);
        name.split('.').next().unwrap_or("house").to_string()
    });
    placement_warnings(house, &mut warnings);
    let start = house.agent.and_then(|(p, _)| {
        let cell = ras.cell_of(p[0], p[1]);
        if cell.is_none() {
            warnings.push((
                "metadata.agent.position".into(),
                format!(
                    "({:.2}, {:.2}) is outside the map's grid; the map has no start",
                    p[0], p[1]
                ),
            ));
        } else if !in_house(house, p) {
            warnings.push((
                "metadata.agent.position".into(),
                format!(
                    "({:.2}, {:.2}) is outside every room's floor; planning starts from the \
                     nearest free cell",
                    p[0], p[1]
                ),
            ));
        }
        cell
    });
    let mut metadata = Map::new();
    metadata.insert("map_id".into(), json!(map_id));
    metadata.insert("name".into(), json!(format!("ProcTHOR {map_id}")));
    metadata.insert(
        "description".into(),
        json!(format!(
            "ProcTHOR house {file} imported by m2rc without the simulator"
        )),
    );
    metadata.insert("source".into(), json!("procthor"));
    if let Some(spec) = &house.room_spec {
        metadata.insert("procthor_room_spec_id".into(), json!(spec));
    }
    metadata.insert("scene_size".into(), json!(r4(scene_size)));
    metadata.insert("original_grid_shape".into(), json!([h, w]));
    metadata.insert("padded_grid_size".into(), json!(n));
    metadata.insert(
        "map_info".into(),
        json!({"x_min": x_min, "x_max": x_max, "z_min": z_min, "z_max": z_max, "resolution": res, "H": h, "W": w}),
    );
    metadata.insert(
        "m2rc_import".into(),
        json!({
            "traversability": "floor_polygons_minus_walls_and_floor_objects",
            "robot_radius_m": opts.robot_radius_m,
            "padding_m": opts.padding_m,
            "wall_half_width_m": half_width,
            "asset_sizes": if assets.is_some() { "asset_database" } else { "builtin_table" },
        }),
    );
    if let Some((_, yaw)) = house.agent {
        metadata.insert("start_yaw_deg".into(), json!(r4(yaw)));
    }

    let frame = GridFrame {
        resolution: res,
        x_min,
        z_min,
    };
    let extra = MapExtra {
        metadata,
        object_keys,
        ..MapExtra::default()
    };
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
    let mut doc = MapDocument { map, extra };
    warnings.extend(check_map(house, &doc.map).warnings(&doc.map));
    if !warnings.is_empty() {
        let list: Vec<String> = warnings
            .iter()
            .map(|(path, msg)| format!("{path}: {msg}"))
            .collect();
        if let Some(Value::Object(imp)) = doc.extra.metadata.get_mut("m2rc_import") {
            imp.insert("warnings".into(), json!(list));
        }
    }
    Ok(doc)
}

/// The warnings an import recorded (`metadata.m2rc_import.warnings`): inputs read in a documented
/// way that a user should hear about, and failed checks against the house. Empty for a clean
/// house or a map that is not an import.
pub fn import_warnings(doc: &MapDocument) -> Vec<String> {
    doc.extra
        .metadata
        .get("m2rc_import")
        .and_then(|v| v.get("warnings"))
        .and_then(Value::as_array)
        .map(|a| {
            a.iter()
                .filter_map(Value::as_str)
                .map(str::to_string)
                .collect()
        })
        .unwrap_or_default()
}
