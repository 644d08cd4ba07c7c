//! `--emit nav-path|waypoints|geojson|mcap` of `compile` and `run`: the planned route in the map
//! frame, for a ROS 2 / Nav2 stack, GIS tools and Foxglove (`docs/maps.md`, "Routes out").

use anyhow::{Result, anyhow};
use m2rc_benchmark::pipeline::{CompiledRoute, stage_ends};
use m2rc_stdlib::export::{RouteOut, StageMark, geojson, mcap, yaml};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use m2rc_stdlib::map::frame::MapFrame;

/// The robot-frame output formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RobotEmit {
    NavPath,
    Waypoints,
    Geojson,
    Mcap,
}

impl RobotEmit {
    /// Whether the output is binary (written only to a file or `-o -`, never to a terminal).
    pub fn is_binary(self) -> bool {
        self == RobotEmit::Mcap
    }
}

/// The route to export: the trajectory and each stage's goal.
pub fn route_out(c: &CompiledRoute, map: &SemanticMap) -> RouteOut {
    let ends = stage_ends(&c.route);
    RouteOut {
        map_id: map.map_id.clone(),
        cells: c.route.trajectory.clone(),
        stages: c
            .ir
            .stages
            .iter()
            .zip(ends)
            .map(|(s, end_index)| StageMark {
                end_index,
                name: s.name.clone(),
                target: s.target.label.clone(),
            })
            .collect(),
        length_m: c.route.length_m,
    }
}

/// The bytes of one output.
pub fn emit(
    kind: RobotEmit,
    map: &SemanticMap,
    frame: &MapFrame,
    c: &CompiledRoute,
) -> Result<Vec<u8>> {
    let route = route_out(c, map);
    Ok(match kind {
        RobotEmit::NavPath => yaml::nav_path(frame, &route).into_bytes(),
        RobotEmit::Waypoints => yaml::waypoints(frame, &route).into_bytes(),
        RobotEmit::Geojson => {
            let mut s = serde_json::to_string_pretty(&geojson::route_geojson(frame, &route))?;
            s.push('\n');
            s.into_bytes()
        }
        RobotEmit::Mcap => mcap::route_mcap(map, frame, &route)
            .map_err(|e| anyhow!("cannot write the MCAP recording: {e}"))?,
    })
}

pub fn parse_cell(s: &str) -> Result<Cell, String> {
    let (r, c) = s
        .split_once(',')
        .ok_or_else(|| format!("`{s}` is not `row,col`"))?;
    let r = r
        .trim()
        .parse::<u32>()
        .map_err(|e| format!("row `{r}`: {e}"))?;
    let c = c
        .trim()
        .parse::<u32>()
        .map_err(|e| format!("col `{c}`: {e}"))?;
    Ok(Cell::new(r, c))
}

/// `x,y` in metres.
pub fn parse_xy(s: &str) -> Result<[f64; 2], String> {
    let (x, y) = s.split_once(',').ok_or_else(|| {
        format!("`{s}` is not `x,y` in metres (for a cell: --start-cell row,col)")
    })?;
    let num = |v: &str, what: &str| {
        v.trim()
            .parse::<f64>()
            .ok()
            .filter(|f| f.is_finite())
            .ok_or_else(|| format!("{what} `{v}` is not a number of metres"))
    };
    Ok([num(x, "x")?, num(y, "y")?])
}

/// The start cell from `--start x,y` (metres, map frame) or `--start-cell row,col`.
pub fn start_from(
    xy: Option<[f64; 2]>,
    cell: Option<Cell>,
    frame: &MapFrame,
    n: usize,
) -> Result<Option<Cell>> {
    let Some([x, y]) = xy else {
        return Ok(cell);
    };
    match frame.map_to_cell(x, y, n) {
        Some(c) => Ok(Some(c)),
        None => {
            let (x0, y0) = frame.corner_to_map(0.0, 0.0);
            let (x1, y1) = frame.corner_to_map(n as f64, n as f64);
            Err(crate::io::unusable(anyhow!(
                "--start {x},{y} is outside the map: its grid covers x {:.2}..{:.2} m and y {:.2}..{:.2} m in frame `{}`",
                x0.min(x1),
                x0.max(x1),
                y0.min(y1),
                y0.max(y1),
                frame.frame_id
            )))
        }
    }
}
