//! `--emit nav-path|waypoints|geojson|mcap` of `compile` and `run`: the planned route in the map
//! frame, for a ROS 2 / Nav2 stack, GIS tools and Foxglove (`docs/maps.md`, "Routes out").

use anyhow::{Result, anyhow};
use m2rc_benchmark::pipeline::{CompiledRoute, stage_ends};
use m2rc_stdlib::export::{RouteOut, StageMark, geojson, mcap, yaml};
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
