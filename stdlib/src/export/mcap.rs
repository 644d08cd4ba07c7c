//! The route and its map as an MCAP recording that Foxglove and `ros2 bag` read.
//!
//! Profile `ros2`, schemas `ros2msg` (the message definitions with their dependencies, as
//! `ros2 bag record` writes them) and messages in `cdr`: the combination both tools decode
//! without plugins or generated code, and `ros2 bag play` republishes as ordinary topics.
//! Topics, all in the map frame at time 0, uncompressed and unchunked (deterministic bytes, no
//! codec dependencies; readers read the four messages in one pass):
//!
//! * `/map` `nav_msgs/msg/OccupancyGrid`: the occupancy layer (free 0, obstacle 100, unknown -1),
//!   its origin the map frame's origin;
//! * `/semantic_map` `visualization_msgs/msg/MarkerArray`: each room's name as a text marker
//!   at its centroid (namespace `rooms`, id = room id) and its outline cells as points
//!   (`room_outlines`); each object as a box over its footprint, its height when known
//!   (`objects`, id = object id, `text` = `name (category)`);
//! * `/plan` `nav_msgs/msg/Path`: the route, one pose per cell (as `--emit nav-path`);
//! * `/route_stages` `visualization_msgs/msg/MarkerArray`: a sphere and a label at each stage
//!   goal (namespace `stages`, id = stage number).

use super::cdr::Cdr;
use super::{RouteOut, poses, schemas};
use crate::grid::Cell;
use crate::map::frame::MapFrame;
use crate::map::{FREE, OBSTACLE, SemanticMap};
use std::collections::BTreeMap;
use std::io::Cursor;

const TEXT_VIEW_FACING: i32 = 9;
const POINTS: i32 = 8;
const CUBE: i32 = 1;
const SPHERE: i32 = 2;

/// The MCAP file's bytes.
pub fn route_mcap(
    map: &SemanticMap,
    frame: &MapFrame,
    route: &RouteOut,
) -> Result<Vec<u8>, String> {
    // Unchunked, and no schemas or channels repeated in the summary: the crate writes those
    // from a hash map, in an order that changes from run to run; readers find both in the data
    // section (four messages, read in one pass).
    let opts = ::mcap::WriteOptions::new()
        .profile("ros2")
        .compression(None)
        .use_chunks(false)
        .repeat_schemas(false)
        .repeat_channels(false);
    let mut w = opts
        .create(Cursor::new(Vec::new()))
        .map_err(|e| e.to_string())?;
    let mut seq = 0u32;
    let mut put = |w: &mut ::mcap::Writer<Cursor<Vec<u8>>>,
                   topic: &str,
                   ty: &str,
                   schema: &str,
                   data: Vec<u8>|
     -> Result<(), String> {
        let sid = w
            .add_schema(ty, "ros2msg", schema.as_bytes())
            .map_err(|e| e.to_string())?;
        let cid = w
            .add_channel(sid, topic, "cdr", &BTreeMap::new())
            .map_err(|e| e.to_string())?;
        seq += 1;
        w.write_to_known_channel(
            &::mcap::records::MessageHeader {
                channel_id: cid,
                sequence: seq,
                log_time: 0,
                publish_time: 0,
            },
            &data,
        )
        .map_err(|e| e.to_string())
    };
    put(
        &mut w,
        "/map",
        "nav_msgs/msg/OccupancyGrid",
        schemas::OCCUPANCY_GRID,
        occupancy_grid(map, frame),
    )?;
    put(
        &mut w,
        "/semantic_map",
        "visualization_msgs/msg/MarkerArray",
        schemas::MARKER_ARRAY,
        semantic_markers(map, frame),
    )?;
    put(
        &mut w,
        "/plan",
        "nav_msgs/msg/Path",
        schemas::PATH,
        path(frame, route),
    )?;
    put(
        &mut w,
        "/route_stages",
        "visualization_msgs/msg/MarkerArray",
        schemas::MARKER_ARRAY,
        stage_markers(frame, route),
    )?;
    w.finish().map_err(|e| e.to_string())?;
    Ok(w.into_inner().into_inner())
}

/// `nav_msgs/OccupancyGrid` of the occupancy layer; grid row 0 is the message's row 0.
pub fn occupancy_grid(map: &SemanticMap, frame: &MapFrame) -> Vec<u8> {
    let n = map.n() as u32;
    let mut c = Cdr::new();
    c.header(&frame.frame_id);
    c.i32(0);
    c.u32(0);
    c.f32(frame.resolution as f32);
    c.u32(n);
    c.u32(n);
    let [ox, oy, yaw] = frame.origin;
    c.pose(ox, oy, 0.0, yaw);
    let data: Vec<u8> = map
        .occupancy
        .data()
        .iter()
        .map(|&o| match o {
            FREE => 0u8,
            OBSTACLE => 100,
            _ => (-1i8) as u8,
        })
        .collect();
    c.bytes(&data);
    c.finish()
}

/// `nav_msgs/Path` of the route.
pub fn path(frame: &MapFrame, route: &RouteOut) -> Vec<u8> {
    let mut c = Cdr::new();
    c.header(&frame.frame_id);
    let ps = poses(frame, &route.cells);
    c.seq_len(ps.len());
    for p in ps {
        c.header(&frame.frame_id);
        c.pose(p.x, p.y, 0.0, p.yaw);
    }
    c.finish()
}

/// One `visualization_msgs/Marker`'s fields that differ between the markers written here.
struct Marker<'a> {
    ns: &'a str,
    id: i32,
    kind: i32,
    at: (f64, f64, f64),
    yaw: f64,
    scale: [f64; 3],
    color: [f32; 4],
    points: Vec<(f64, f64)>,
    text: String,
}

fn marker(c: &mut Cdr, frame_id: &str, m: &Marker<'_>) {
    c.header(frame_id);
    c.string(m.ns);
    c.i32(m.id);
    c.i32(m.kind);
    c.i32(0); // ADD
    c.pose(m.at.0, m.at.1, m.at.2, m.yaw);
    for s in m.scale {
        c.f64(s);
    }
    for v in m.color {
        c.f32(v);
    }
    c.i32(0); // lifetime: forever
    c.u32(0);
    c.bool(false);
    c.seq_len(m.points.len());
    for &(x, y) in &m.points {
        c.f64(x);
        c.f64(y);
        c.f64(0.0);
    }
    c.seq_len(0); // colors
    c.string(""); // texture_resource
    c.header(""); // texture: sensor_msgs/CompressedImage
    c.string("");
    c.bytes(&[]);
    c.seq_len(0); // uv_coordinates
    c.string(&m.text);
    c.string(""); // mesh_resource
    c.string(""); // mesh_file
    c.bytes(&[]);
    c.bool(false);
}

fn marker_array(frame: &MapFrame, markers: &[Marker<'_>]) -> Vec<u8> {
    let mut c = Cdr::new();
    c.seq_len(markers.len());
    for m in markers {
        marker(&mut c, &frame.frame_id, m);
    }
    c.finish()
}

fn semantic_markers(map: &SemanticMap, frame: &MapFrame) -> Vec<u8> {
    let yaw = frame.origin[2];
    let res = frame.resolution;
    let mut ms = Vec::new();
    let mut sums: BTreeMap<u32, (f64, f64, usize)> = BTreeMap::new();
    let mut outline: BTreeMap<u32, Vec<(f64, f64)>> = BTreeMap::new();
    let n = map.n() as i64;
    for (cell, &room) in map.room_layer.iter_cells() {
        if room == 0 {
            continue;
        }
        let e = sums.entry(room).or_insert((0.0, 0.0, 0));
        e.0 += cell.row as f64;
        e.1 += cell.col as f64;
        e.2 += 1;
        let (r, col) = (cell.row as i64, cell.col as i64);
        let edge = [(r - 1, col), (r + 1, col), (r, col - 1), (r, col + 1)]
            .iter()
            .any(|&(a, b)| {
                a < 0
                    || b < 0
                    || a >= n
                    || b >= n
                    || map.room_at(Cell::new(a as u32, b as u32)) != room
            });
        if edge {
            outline
                .entry(room)
                .or_default()
                .push(frame.cell_to_map(cell));
        }
    }
    for room in &map.rooms {
        let Some(&(sr, sc, k)) = sums.get(&room.id) else {
            continue;
        };
        let (x, y) = frame.grid_to_map(sr / k as f64, sc / k as f64);
        ms.push(Marker {
            ns: "rooms",
            id: room.id as i32,
            kind: TEXT_VIEW_FACING,
            at: (x, y, 1.0),
            yaw: 0.0,
            scale: [0.0, 0.0, 0.4],
            color: [1.0, 1.0, 1.0, 1.0],
            points: Vec::new(),
            text: format!("{} ({})", room.name, room.category),
        });
        ms.push(Marker {
            ns: "room_outlines",
            id: room.id as i32,
            kind: POINTS,
            at: (0.0, 0.0, 0.0),
            yaw: 0.0,
            scale: [res, res, 0.0],
            color: room_colour(room.id),
            points: outline.remove(&room.id).unwrap_or_default(),
            text: room.name.clone(),
        });
    }
    for o in &map.objects {
        let (Some(r0), Some(r1)) = (
            o.footprint.iter().map(|c| c.row).min(),
            o.footprint.iter().map(|c| c.row).max(),
        ) else {
            continue;
        };
        let c0 = o.footprint.iter().map(|c| c.col).min().unwrap_or(0);
        let c1 = o.footprint.iter().map(|c| c.col).max().unwrap_or(0);
        let (x, y) =
            frame.grid_to_map((r0 as f64 + r1 as f64) / 2.0, (c0 as f64 + c1 as f64) / 2.0);
        let h = o.height_m.filter(|h| *h > 0.0).unwrap_or(0.5);
        let z = o.elevation_m.unwrap_or(0.0) + h / 2.0;
        let structural = matches!(
            o.category.as_str(),
            "wall" | "doorway" | "doorframe" | "window"
        );
        ms.push(Marker {
            ns: "objects",
            id: o.id as i32,
            kind: CUBE,
            at: (x, y, z),
            yaw,
            scale: [(c1 - c0 + 1) as f64 * res, (r1 - r0 + 1) as f64 * res, h],
            color: if structural {
                [0.5, 0.5, 0.5, 0.6]
            } else {
                [0.95, 0.6, 0.2, 0.8]
            },
            points: Vec::new(),
            text: format!("{} ({})", o.name, o.category),
        });
    }
    marker_array(frame, &ms)
}

fn stage_markers(frame: &MapFrame, route: &RouteOut) -> Vec<u8> {
    let mut ms = Vec::new();
    let last = route.cells.len().saturating_sub(1);
    for (i, s) in route.stages.iter().enumerate() {
        let Some(&cell) = route.cells.get(s.end_index.min(last)) else {
            continue;
        };
        let (x, y) = frame.cell_to_map(cell);
        ms.push(Marker {
            ns: "stages",
            id: i as i32 + 1,
            kind: SPHERE,
            at: (x, y, 0.2),
            yaw: 0.0,
            scale: [0.3, 0.3, 0.3],
            color: [0.1, 0.8, 0.2, 1.0],
            points: Vec::new(),
            text: format!("{}: {} ({})", i + 1, s.name, s.target),
        });
    }
    marker_array(frame, &ms)
}

/// A stable colour per room id.
fn room_colour(id: u32) -> [f32; 4] {
    const PALETTE: [[f32; 3]; 6] = [
        [0.35, 0.6, 0.9],
        [0.9, 0.45, 0.45],
        [0.45, 0.8, 0.5],
        [0.85, 0.75, 0.35],
        [0.7, 0.5, 0.85],
        [0.4, 0.8, 0.8],
    ];
    let [r, g, b] = PALETTE[id as usize % PALETTE.len()];
    [r, g, b, 0.8]
}
