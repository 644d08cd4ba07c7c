//! Routes out, in the robot's frame: a planned route (grid cells plus where each stage ends)
//! written as a `nav_msgs/Path` YAML, a Nav2 waypoint list, GeoJSON, or an MCAP recording with
//! the map. Every format places cells by the one rule of [`crate::map::frame`], so a pose read
//! back from any of them lands on the cell it came from.
//!
//! Pure functions from a map and a route to bytes; the CLI writes them.

mod cdr;
pub mod geojson;
pub mod mcap;
pub mod nav2;
mod schemas;
pub mod thin;
pub mod yaml;

use crate::grid::Cell;
use crate::map::frame::MapFrame;

/// Waypoints keep every turn where the route strays more than this from the straight line
/// between kept points (metres): a grid route's stair steps are not turns, a corridor corner is.
pub const WAYPOINT_TOLERANCE_M: f64 = 0.10;

/// One stage of a route: where it ends in the trajectory, and what it is for.
#[derive(Clone, Debug, PartialEq)]
pub struct StageMark {
    /// Index into the trajectory of the stage's last cell (its goal).
    pub end_index: usize,
    pub name: String,
    /// The stage's target as the program names it.
    pub target: String,
}

/// A route to export: the trajectory in cells and its stages.
#[derive(Clone, Debug, PartialEq)]
pub struct RouteOut {
    pub map_id: String,
    pub cells: Vec<Cell>,
    pub stages: Vec<StageMark>,
    pub length_m: f64,
}

/// A pose in the map frame: position in metres and heading in radians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose2 {
    pub x: f64,
    pub y: f64,
    pub yaw: f64,
}

impl Pose2 {
    /// The unit quaternion `(x, y, z, w)` of a rotation by `yaw` about z.
    pub fn quaternion(&self) -> [f64; 4] {
        let (s, c) = (self.yaw / 2.0).sin_cos();
        [0.0, 0.0, s, c]
    }
}

/// Poses of `cells` in the map frame, each facing the next distinct cell (the last keeps the
/// heading it arrived with; a route of one cell faces along the frame's x axis).
pub fn poses(frame: &MapFrame, cells: &[Cell]) -> Vec<Pose2> {
    let pts: Vec<(f64, f64)> = cells.iter().map(|&c| frame.cell_to_map(c)).collect();
    let mut out = Vec::with_capacity(pts.len());
    let mut last_yaw = 0.0;
    for (i, &(x, y)) in pts.iter().enumerate() {
        let next = pts[i + 1..].iter().find(|&&(nx, ny)| (nx, ny) != (x, y));
        let yaw = match next {
            Some(&(nx, ny)) => (ny - y).atan2(nx - x),
            None => last_yaw,
        };
        last_yaw = yaw;
        out.push(Pose2 { x, y, yaw });
    }
    out
}

/// A number for a text format: fixed decimals, never `-0`, so that outputs are byte-stable.
pub(crate) fn num(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    if s.trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        format!("{:.decimals$}", 0.0)
    } else {
        s
    }
}

/// `x` rounded to `decimals` places, for JSON outputs.
pub(crate) fn round_to(x: f64, decimals: i32) -> f64 {
    let f = 10f64.powi(decimals);
    let r = (x * f).round() / f;
    if r == 0.0 { 0.0 } else { r }
}
