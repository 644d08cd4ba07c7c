//! `POST /route` of `m2rc serve`: one request body in, the route (or the diagnostics) out. Pure
//! of I/O, so it runs on a blocking thread and is tested without a socket.

use axum::http::StatusCode;
use m2rc_benchmark::budget::{EpisodeBudget, Meter};
use m2rc_benchmark::pipeline::{PipelineOptions, compile_and_plan_explained_with};
use m2rc_compiler::diagnostic::to_json;
use m2rc_stdlib::map::SemanticMap;
use m2rc_stdlib::map::frame::MapFrame;
use serde::Deserialize;
use serde_json::{Value, json};
use std::sync::Arc;
use std::time::Duration;

/// What every request shares: the map, loaded once, and the service's limits.
pub struct Shared {
    pub map: SemanticMap,
    /// The map's planning context: its distance fields are computed once and shared by requests.
    pub planning: m2rc_planner::context::MapContext,
    pub frame: MapFrame,
    pub max_wall: Duration,
    /// At most this many requests compile at once; the others wait their turn.
    pub slots: tokio::sync::Semaphore,
    /// SHA-256 of the bearer token, when one is required.
    pub token: Option<[u8; 32]>,
}

/// A refused request: its status and JSON body.
#[derive(Debug)]
pub struct RouteError {
    pub status: StatusCode,
    pub body: Value,
}

fn refuse(status: StatusCode, message: String, help: Option<&str>) -> RouteError {
    RouteError {
        status,
        body: json!({"status": "error", "message": message, "help": help}),
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RouteRequest {
    program: Option<String>,
    instruction: Option<String>,
    /// `[x, y]` in metres in the map frame.
    start: Option<[f64; 2]>,
}

/// Compiles and plans one request body.
pub fn plan_request(s: &Shared, body: &[u8]) -> Result<Value, RouteError> {
    let bad = |m: String, help: Option<&str>| refuse(StatusCode::BAD_REQUEST, m, help);
    let req: RouteRequest = serde_json::from_slice(body).map_err(|e| {
        bad(
            format!("the request body is not a valid route request: {e}"),
            Some(r#"send a JSON object such as {"program": "route { go kitchen }", "start": [1.0, 2.5]}"#),
        )
    })?;
    let source = match (req.program, req.instruction) {
        (Some(p), None) => p,
        (None, Some(_)) => {
            return Err(bad(
                "no model configured: this service plans `.m2r` programs only".into(),
                Some("send {\"program\": \"...\"} with a .m2r program"),
            ));
        }
        (Some(_), Some(_)) => {
            return Err(bad(
                "the request has both `program` and `instruction`: send one".into(),
                None,
            ));
        }
        (None, None) => {
            return Err(bad(
                "the request has no `program`".into(),
                Some("send {\"program\": \"...\"} with a .m2r program"),
            ));
        }
    };
    m2rc_benchmark::limits::check_program_size(&source)
        .map_err(|m| refuse(StatusCode::PAYLOAD_TOO_LARGE, format!("program: {m}"), None))?;
    let n = s.map.n();
    let start = match req.start {
        None => None,
        Some([x, y]) => Some(s.frame.map_to_cell(x, y, n).ok_or_else(|| {
            let (x0, y0) = s.frame.corner_to_map(0.0, 0.0);
            let (x1, y1) = s.frame.corner_to_map(n as f64, n as f64);
            bad(
                format!(
                    "start [{x}, {y}] is outside the map: its grid covers x {:.2}..{:.2} m and \
                     y {:.2}..{:.2} m in frame `{}`",
                    x0.min(x1),
                    x0.max(x1),
                    y0.min(y1),
                    y0.max(y1),
                    s.frame.frame_id
                ),
                None,
            )
        })?),
    };
    let meter = Arc::new(Meter::new(EpisodeBudget {
        max_wall: Some(s.max_wall),
        ..EpisodeBudget::default()
    }));
    let opts = PipelineOptions {
        start,
        meter: Some(meter.clone()),
        ..PipelineOptions::default()
    };
    let diagnostics = |d| serde_json::from_str::<Value>(&to_json(d, &source)).unwrap_or_default();
    let compiled = match compile_and_plan_explained_with(&source, &s.map, &s.planning, &opts) {
        Ok(c) => c,
        Err(failure) => {
            let (status, message) = match meter.exceeded() {
                Some(why) => (
                    StatusCode::SERVICE_UNAVAILABLE,
                    format!("the request went over the service's limits: {why}"),
                ),
                None => (
                    StatusCode::UNPROCESSABLE_ENTITY,
                    "the program does not compile on this map".to_string(),
                ),
            };
            return Err(RouteError {
                status,
                body: json!({
                    "status": "error",
                    "message": message,
                    "program": source,
                    "diagnostics": diagnostics(&failure.diagnostics),
                }),
            });
        }
    };
    let route = crate::cmd::route_out::route_out(&compiled, &s.map);
    let poses: Vec<[f64; 2]> = route
        .cells
        .iter()
        .map(|&c| {
            let (x, y) = s.frame.cell_to_map(c);
            [x, y]
        })
        .collect();
    let doc = crate::cmd::compile::route_document(&compiled, &s.map);
    Ok(json!({
        "status": "ok",
        "program": source,
        "diagnostics": diagnostics(&compiled.warnings),
        "route": {
            "cells": route.cells,
            "map_frame": {"frame_id": s.frame.frame_id, "points_m": poses},
            "length_m": compiled.route.length_m,
            "stages": doc["m2rc"]["stages"],
        },
        "nav_path": m2rc_stdlib::export::yaml::nav_path(&s.frame, &route),
    }))
}
