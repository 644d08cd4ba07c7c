//! The `map_server` YAML of a Nav2 / ROS map: every field `nav2_map_server` reads, with its
//! defaults and checks, so a map that loads in Nav2 loads here the same way.

use crate::map::error::{ErrCtx, MapError};
use serde_yaml_ng::Value;
use std::path::{Path, PathBuf};

/// How image pixels become occupancy, as `map_server`'s `mode`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    Trinary,
    Scale,
    Raw,
}

#[derive(Clone, Debug, PartialEq)]
pub struct MapYaml {
    /// The image, resolved against the YAML's folder.
    pub image: PathBuf,
    pub resolution: f64,
    /// `[x, y, yaw]` of the image's lower-left pixel corner in the map frame.
    pub origin: [f64; 3],
    pub negate: bool,
    pub occupied_thresh: f64,
    pub free_thresh: f64,
    pub mode: Mode,
}

/// Reads the YAML text of `file` (`dir` is where `image` is looked for).
pub fn parse_map_yaml(text: &str, file: &str, dir: &Path) -> Result<MapYaml, MapError> {
    let ctx = ErrCtx::new(file);
    let v: Value =
        serde_yaml_ng::from_str(text).map_err(|e| ctx.err("", format!("not YAML: {e}")))?;
    let m = v.as_mapping().ok_or_else(|| {
        ctx.err(
            "",
            "is not a YAML mapping of map_server fields (image, resolution, origin, ...)",
        )
    })?;
    let get = |k: &str| m.get(Value::String(k.into()));
    let num = |k: &str| -> Result<Option<f64>, MapError> {
        match get(k) {
            None => Ok(None),
            Some(x) => x
                .as_f64()
                .filter(|f| f.is_finite())
                .map(Some)
                .ok_or_else(|| ctx.err(k, format!("is not a number: {}", show(x)))),
        }
    };
    let image = get("image")
        .ok_or_else(|| ctx.err("image", "is missing: the PGM or PNG file of the map"))?
        .as_str()
        .ok_or_else(|| ctx.err("image", "is not a file name"))?;
    let image = dir.join(image);
    let resolution =
        num("resolution")?.ok_or_else(|| ctx.err("resolution", "is missing: metres per pixel"))?;
    if resolution <= 0.0 {
        return Err(ctx.err("resolution", format!("must be positive, got {resolution}")));
    }
    let origin = match get("origin") {
        None => return Err(ctx.err("origin", "is missing: [x, y, yaw] of the lower-left pixel")),
        Some(o) => {
            let seq = o
                .as_sequence()
                .filter(|s| s.len() == 3)
                .ok_or_else(|| ctx.err("origin", format!("is not [x, y, yaw]: {}", show(o))))?;
            let mut out = [0.0; 3];
            for (i, x) in seq.iter().enumerate() {
                out[i] = x
                    .as_f64()
                    .filter(|f| f.is_finite() && f.abs() <= 1e5)
                    .ok_or_else(|| {
                        ctx.err(
                            format!("origin[{i}]"),
                            format!("is not a number within ±100 km: {}", show(x)),
                        )
                    })?;
            }
            out
        }
    };
    let negate = match get("negate") {
        None => false,
        Some(Value::Bool(b)) => *b,
        Some(x) => match x.as_i64() {
            Some(0) => false,
            Some(1) => true,
            _ => return Err(ctx.err("negate", format!("is not 0 or 1: {}", show(x)))),
        },
    };
    let occupied_thresh = num("occupied_thresh")?.unwrap_or(0.65);
    let free_thresh = num("free_thresh")?.unwrap_or(0.196);
    for (k, t) in [
        ("occupied_thresh", occupied_thresh),
        ("free_thresh", free_thresh),
    ] {
        if !(0.0..=1.0).contains(&t) {
            return Err(ctx.err(k, format!("must lie in [0, 1], got {t}")));
        }
    }
    if free_thresh > occupied_thresh {
        return Err(ctx.err(
            "free_thresh",
            format!("{free_thresh} is above occupied_thresh {occupied_thresh}"),
        ));
    }
    let mode = match get("mode") {
        None => Mode::Trinary,
        Some(x) => match x.as_str() {
            Some("trinary") => Mode::Trinary,
            Some("scale") => Mode::Scale,
            Some("raw") => Mode::Raw,
            _ => {
                return Err(ctx.err("mode", format!("is not trinary, scale or raw: {}", show(x))));
            }
        },
    };
    Ok(MapYaml {
        image,
        resolution,
        origin,
        negate,
        occupied_thresh,
        free_thresh,
        mode,
    })
}

fn show(v: &Value) -> String {
    serde_yaml_ng::to_string(v)
        .map(|s| s.trim().chars().take(60).collect())
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_and_every_field() {
        let y = parse_map_yaml(
            "image: m.pgm\nresolution: 0.05\norigin: [-1.0, 2.5, 0.0]\n",
            "m.yaml",
            Path::new("/x"),
        )
        .unwrap();
        assert_eq!(y.image, Path::new("/x/m.pgm"));
        assert_eq!((y.negate, y.mode), (false, Mode::Trinary));
        assert_eq!((y.occupied_thresh, y.free_thresh), (0.65, 0.196));
        let y = parse_map_yaml(
            "image: m.png\nmode: scale\nresolution: 0.1\norigin: [0, 0, 0.5]\nnegate: 1\noccupied_thresh: 0.9\nfree_thresh: 0.1\n",
            "m.yaml",
            Path::new("."),
        )
        .unwrap();
        assert_eq!((y.negate, y.mode, y.origin[2]), (true, Mode::Scale, 0.5));
    }

    #[test]
    fn errors_name_the_field() {
        let e = parse_map_yaml(
            "image: m.pgm\nresolution: -1\norigin: [0,0,0]\n",
            "m.yaml",
            Path::new("."),
        )
        .unwrap_err();
        assert_eq!(e.path, "resolution");
        let e = parse_map_yaml(
            "image: m.pgm\nresolution: 1\norigin: [0,0]\n",
            "m.yaml",
            Path::new("."),
        )
        .unwrap_err();
        assert_eq!(e.path, "origin");
        let e = parse_map_yaml(
            "image: m.pgm\nresolution: 1\norigin: [0,0,0]\nmode: fancy\n",
            "m.yaml",
            Path::new("."),
        )
        .unwrap_err();
        assert_eq!(e.path, "mode");
    }
}
