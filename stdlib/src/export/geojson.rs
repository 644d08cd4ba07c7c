//! The route as GeoJSON for GIS tools: a FeatureCollection with the route as a LineString, the
//! start and every stage goal as Points, coordinates in the map frame in metres (a local frame,
//! not WGS 84: the collection says so in its `m2rc_map_frame` member, which GeoJSON readers
//! ignore).

use super::{RouteOut, round_to};
use crate::map::frame::MapFrame;
use serde_json::{Value, json};

pub fn route_geojson(frame: &MapFrame, route: &RouteOut) -> Value {
    let xy = |i: usize| {
        let (x, y) = frame.cell_to_map(route.cells[i]);
        json!([round_to(x, 4), round_to(y, 4)])
    };
    let line: Vec<Value> = (0..route.cells.len()).map(xy).collect();
    let mut features = vec![json!({
        "type": "Feature",
        "geometry": {"type": "LineString", "coordinates": line},
        "properties": {
            "kind": "route",
            "map_id": route.map_id,
            "cells": route.cells.len(),
            "length_m": round_to(route.length_m, 3),
        },
    })];
    if !route.cells.is_empty() {
        features.push(json!({
            "type": "Feature",
            "geometry": {"type": "Point", "coordinates": xy(0)},
            "properties": {"kind": "start", "cell": route.cells[0]},
        }));
    }
    let last = route.cells.len().saturating_sub(1);
    for (i, s) in route.stages.iter().enumerate() {
        if route.cells.is_empty() {
            break;
        }
        let at = s.end_index.min(last);
        features.push(json!({
            "type": "Feature",
            "geometry": {"type": "Point", "coordinates": xy(at)},
            "properties": {
                "kind": "stage",
                "stage": i + 1,
                "name": s.name,
                "target": s.target,
                "cell": route.cells[at],
                "index": at,
            },
        }));
    }
    json!({
        "type": "FeatureCollection",
        "m2rc_map_frame": {
            "frame_id": frame.frame_id,
            "source": frame.source,
            "resolution": frame.resolution,
            "origin": frame.origin,
            "units": "metres",
        },
        "features": features,
    })
}
