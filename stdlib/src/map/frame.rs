//! The map frame: where a grid cell lies in the robot's world, in metres.
//!
//! Every map has one rule, the one `nav_msgs/OccupancyGrid` uses, so that routes leave m2rc in
//! the frame a ROS 2 stack plans in: the grid's row 0 lies along the origin, rows grow along
//! the frame's y axis and columns along its x axis, and the centre of cell `[row, col]` is
//!
//! ```text
//! (x, y) = (origin_x, origin_y) + R(origin_yaw) · ((col + 1/2)·res, (row + 1/2)·res)
//! ```
//!
//! A map imported from Nav2 records its YAML `origin` (the image is flipped on import, so image
//! row 0, the top as `map_server` reads it, is the grid's last row). A map that records no frame
//! (ProcTHOR imports, Map2Route maps) has the frame of its `grid_coordinate_frame`: the house's
//! world x and z, `origin = (x_min - res/2, z_min - res/2, 0)`, so cell centres are exactly
//! [`SemanticMap::cell_to_world`].

use super::{MapError, MapExtra, SemanticMap};
use crate::grid::Cell;
use serde_json::{Value, json};

/// The metadata key a map records its frame under.
pub const MAP_FRAME_KEY: &str = "map_frame";

#[derive(Clone, Debug, PartialEq)]
pub struct MapFrame {
    /// The ROS frame id the poses are expressed in (`map`).
    pub frame_id: String,
    /// Where the frame came from: `nav2` (the YAML origin) or `grid` (the map's grid frame,
    /// world x/z for ProcTHOR houses).
    pub source: String,
    /// Metres per cell.
    pub resolution: f64,
    /// `[x, y, yaw]` of the grid's outer corner before cell `[0, 0]`, metres and radians.
    pub origin: [f64; 3],
}

impl MapFrame {
    /// The frame of a map: the one recorded in its metadata, else its grid frame.
    pub fn of(map: &SemanticMap, extra: Option<&MapExtra>) -> Result<MapFrame, MapError> {
        match extra.and_then(|e| e.metadata.get(MAP_FRAME_KEY)) {
            Some(v) => Self::from_json(v, map.frame.resolution),
            None => Ok(Self::from_grid(map)),
        }
    }

    /// The frame of a map that records none: its grid frame (world x/z for ProcTHOR houses).
    pub fn from_grid(map: &SemanticMap) -> MapFrame {
        let r = map.frame.resolution;
        MapFrame {
            frame_id: "map".into(),
            source: "grid".into(),
            resolution: r,
            origin: [map.frame.x_min - r / 2.0, map.frame.z_min - r / 2.0, 0.0],
        }
    }

    fn from_json(v: &Value, resolution: f64) -> Result<MapFrame, MapError> {
        let bad = |what: &str| {
            MapError::new(
                "map",
                format!("metadata.{MAP_FRAME_KEY}"),
                format!(
                    "{what}; expected {{\"frame_id\": \"map\", \"source\": \"nav2\", \"origin\": [x, y, yaw]}}"
                ),
            )
        };
        let o = v.as_object().ok_or_else(|| bad("is not an object"))?;
        let origin = o
            .get("origin")
            .and_then(Value::as_array)
            .filter(|a| a.len() == 3)
            .and_then(|a| {
                let v: Vec<f64> = a.iter().filter_map(Value::as_f64).collect();
                (v.len() == 3 && v.iter().all(|x| x.is_finite())).then(|| [v[0], v[1], v[2]])
            })
            .ok_or_else(|| bad("`origin` is not three finite numbers"))?;
        let text = |k: &str, d: &str| o.get(k).and_then(Value::as_str).unwrap_or(d).to_string();
        Ok(MapFrame {
            frame_id: text("frame_id", "map"),
            source: text("source", "nav2"),
            resolution,
            origin,
        })
    }

    /// The metadata value [`MapFrame::of`] reads back.
    pub fn to_json(&self) -> Value {
        json!({
            "frame_id": self.frame_id,
            "source": self.source,
            "origin": self.origin,
            "rule": "centre of [row, col] = origin + R(yaw) * ((col + 0.5) * res, (row + 0.5) * res)",
        })
    }

    /// Map-frame `(x, y)` of a cell centre, metres.
    pub fn cell_to_map(&self, cell: Cell) -> (f64, f64) {
        self.grid_to_map(cell.row as f64, cell.col as f64)
    }

    /// Map-frame `(x, y)` of a point in cell units (`[row, col]` centre coordinates, fractional
    /// allowed: an object's centre).
    pub fn grid_to_map(&self, row: f64, col: f64) -> (f64, f64) {
        self.local_to_map((col + 0.5) * self.resolution, (row + 0.5) * self.resolution)
    }

    /// Map-frame `(x, y)` of a cell corner: `(row, col)` in cell units from the origin corner
    /// (`(0, 0)` is the origin itself).
    pub fn corner_to_map(&self, row: f64, col: f64) -> (f64, f64) {
        self.local_to_map(col * self.resolution, row * self.resolution)
    }

    fn local_to_map(&self, u: f64, v: f64) -> (f64, f64) {
        let [ox, oy, yaw] = self.origin;
        if yaw == 0.0 {
            return (ox + u, oy + v);
        }
        let (s, c) = yaw.sin_cos();
        (ox + c * u - s * v, oy + s * u + c * v)
    }

    /// The cell whose square contains map-frame `(x, y)`, or `None` outside an `n`×`n` grid.
    pub fn map_to_cell(&self, x: f64, y: f64, n: usize) -> Option<Cell> {
        let [ox, oy, yaw] = self.origin;
        let (dx, dy) = (x - ox, y - oy);
        let (s, c) = yaw.sin_cos();
        let (u, v) = if yaw == 0.0 {
            (dx, dy)
        } else {
            (c * dx + s * dy, -s * dx + c * dy)
        };
        let col = (u / self.resolution).floor();
        let row = (v / self.resolution).floor();
        let n = n as f64;
        (row >= 0.0 && col >= 0.0 && row < n && col < n).then(|| Cell::new(row as u32, col as u32))
    }

    /// Yaw of a heading in the grid (radians, along +col = 0, +row = π/2) in the map frame.
    pub fn grid_heading_to_map(&self, heading: f64) -> f64 {
        normalise_angle(heading + self.origin[2])
    }
}

/// An angle in (-π, π].
pub fn normalise_angle(a: f64) -> f64 {
    let mut a = a % std::f64::consts::TAU;
    if a > std::f64::consts::PI {
        a -= std::f64::consts::TAU;
    } else if a <= -std::f64::consts::PI {
        a += std::f64::consts::TAU;
    }
    a
}
