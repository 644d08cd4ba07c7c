//! Maps from a ROS 2 mapping stack: a Nav2 `map_server` map (YAML + PGM/PNG) and a semantic
//! layer in GeoJSON, imported into the one map model (`docs/maps.md`, "Nav2 import").

pub mod occupancy;
pub mod params;
pub mod semantics;

use crate::grid::Grid;
use crate::map::error::MapError;
use crate::map::frame::{MAP_FRAME_KEY, MapFrame};
use crate::map::{GridFrame, MapDocument, MapExtra, SemanticMap};
use serde_json::{Map, json};
use std::path::Path;

/// Options of a Nav2 import.
#[derive(Clone, Debug)]
pub struct Nav2Options {
    /// Robot radius the free space is eroded by, metres.
    pub robot_radius_m: f64,
    /// Memory an import may use, bytes.
    pub max_memory_bytes: u64,
    /// The map key; default the YAML's file stem.
    pub map_id: Option<String>,
}

impl Default for Nav2Options {
    fn default() -> Self {
        Nav2Options {
            robot_radius_m: super::DEFAULT_ROBOT_RADIUS_M,
            max_memory_bytes: super::bounds::DEFAULT_MAX_IMPORT_MEMORY,
            map_id: None,
        }
    }
}

/// Imports `map.yaml` (its image beside it) and, when given, the semantic layer. Also returns the
/// notes a user should hear (the padding to a square grid).
pub fn import_nav2(
    yaml_path: &Path,
    semantics_path: Option<&Path>,
    opts: &Nav2Options,
) -> Result<(MapDocument, Vec<String>), MapError> {
    let file = yaml_path.display().to_string();
    if !(opts.robot_radius_m.is_finite() && (0.0..=5.0).contains(&opts.robot_radius_m)) {
        return Err(MapError::new(
            &file,
            "",
            format!(
                "robot radius must be between 0 and 5 m, got {}",
                opts.robot_radius_m
            ),
        ));
    }
    let text = std::fs::read_to_string(yaml_path)
        .map_err(|e| MapError::new(&file, "", format!("cannot read: {e}")))?;
    let dir = yaml_path.parent().unwrap_or(Path::new("."));
    let y = params::parse_map_yaml(&text, &file, dir)?;
    let occ = occupancy::read_occupancy(&y, opts.robot_radius_m, opts.max_memory_bytes)?;
    let n = occ.grid.n();
    let mut notes = Vec::new();
    if occ.width != occ.height {
        notes.push(format!(
            "{}: the {}x{} image is padded to a square {n}x{n} grid (the Map2Route grid is \
             square) with unknown cells {}",
            y.image.display(),
            occ.width,
            occ.height,
            if occ.width > occ.height {
                "above its top row"
            } else {
                "right of its last column"
            }
        ));
    }
    let sem = match semantics_path {
        Some(p) => {
            let name = p.display().to_string();
            let text = std::fs::read_to_string(p)
                .map_err(|e| MapError::new(&name, "", format!("cannot read: {e}")))?;
            Some(semantics::read_semantics(
                &text,
                &name,
                &y,
                n,
                (occ.width, occ.height),
            )?)
        }
        None => None,
    };
    let map_id = opts.map_id.clone().unwrap_or_else(|| {
        yaml_path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "nav2".into())
    });
    let res = y.resolution;
    // The grid frame is the map frame when the origin is not turned; otherwise the grid's own
    // axes, and only `map_frame` places it in the map.
    let frame = if y.origin[2] == 0.0 {
        GridFrame {
            resolution: res,
            x_min: y.origin[0] + res / 2.0,
            z_min: y.origin[1] + res / 2.0,
        }
    } else {
        GridFrame {
            resolution: res,
            x_min: res / 2.0,
            z_min: res / 2.0,
        }
    };
    let map_frame = MapFrame {
        frame_id: "map".into(),
        source: "nav2".into(),
        resolution: res,
        origin: y.origin,
    };
    let mut metadata = Map::new();
    metadata.insert("map_id".into(), json!(map_id));
    metadata.insert("name".into(), json!(format!("Nav2 map {map_id}")));
    metadata.insert("source".into(), json!("nav2"));
    metadata.insert("original_grid_shape".into(), json!([occ.height, occ.width]));
    metadata.insert("padded_grid_size".into(), json!(n));
    metadata.insert(MAP_FRAME_KEY.into(), map_frame.to_json());
    metadata.insert(
        "m2rc_import".into(),
        json!({
            "traversability": "map_server_free_cells",
            "robot_radius_m": opts.robot_radius_m,
            "image": y.image.file_name().map(|s| s.to_string_lossy().into_owned()),
            "mode": format!("{:?}", y.mode).to_lowercase(),
            "negate": y.negate,
            "occupied_thresh": y.occupied_thresh,
            "free_thresh": y.free_thresh,
            "semantics": semantics_path.and_then(|p| p.file_name()).map(|s| s.to_string_lossy().into_owned()),
        }),
    );
    let (rooms, room_layer, objects, object_layer, open_boundaries) = match sem {
        Some(s) => (
            s.rooms,
            s.room_layer,
            s.objects,
            s.object_layer,
            s.open_boundaries,
        ),
        None => (
            Vec::new(),
            Grid::new(n, 0),
            Vec::new(),
            Grid::new(n, 0),
            Vec::new(),
        ),
    };
    let map = SemanticMap {
        map_id,
        frame,
        occupancy: occ.grid,
        room_layer,
        object_layer,
        rooms,
        objects,
        start: None,
        open_boundaries,
    };
    Ok((
        MapDocument {
            map,
            extra: MapExtra {
                metadata,
                ..MapExtra::default()
            },
        },
        notes,
    ))
}
