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
    /// The model for `{"instruction"}` requests, when one is configured.
    pub model: Option<Model>,
}

/// What lowers an instruction into a program: the model (client, reply cache, API key) and the
/// prompt, repair and budget settings of `m2rc run`.
pub struct Model {
    pub client: m2rc_llm::HttpClient,
    pub store: m2rc_llm::Store,
    /// Only to take it out of anything a reply could carry back into a response.
    pub key: Option<m2rc_llm::ApiKey>,
    pub prompt: m2rc_compiler::lower::PromptOptions,
    pub repair: m2rc_compiler::lower::RepairOptions,
    pub budget: EpisodeBudget,
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

/// Compiles and plans one request body; the model's API key appears in no response (a reply
/// that quotes it gets `***` in its place).
pub fn plan_request(s: &Shared, body: &[u8]) -> Result<Value, RouteError> {
    let key = s.model.as_ref().and_then(|m| m.key.as_ref());
    let redact = |v: Value| match key {
        Some(k) => {
            let text = v.to_string();
            let clean = k.redact(&text);
            if clean == text {
                v
            } else {
                serde_json::from_str(&clean).unwrap_or(v)
            }
        }
        None => v,
    };
    plan_body(s, body).map(redact).map_err(|e| RouteError {
        status: e.status,
        body: redact(e.body),
    })
}

fn plan_body(s: &Shared, body: &[u8]) -> Result<Value, RouteError> {
    let bad = |m: String, help: Option<&str>| refuse(StatusCode::BAD_REQUEST, m, help);
    let req: RouteRequest = serde_json::from_slice(body).map_err(|e| {
        bad(
            format!("the request body is not a valid route request: {e}"),
            Some(r#"send a JSON object such as {"program": "route { go kitchen }", "start": [1.0, 2.5]}"#),
        )
    })?;
    let source = match (req.program, req.instruction) {
        (Some(p), None) => p,
        (None, Some(instruction)) => {
            let Some(model) = &s.model else {
                return Err(bad(
                    "no model configured: this service plans `.m2r` programs only".into(),
                    Some(
                        "send {\"program\": \"...\"} with a .m2r program, or restart the service with --llm-base-url",
                    ),
                ));
            };
            let start = start_cell(s, req.start)?;
            return plan_instruction(s, model, &instruction, start);
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
    let start = start_cell(s, req.start)?;
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
    let mut out = route_body(s, &compiled);
    out["program"] = json!(source);
    out["diagnostics"] = diagnostics(&compiled.warnings);
    Ok(out)
}

/// The request's start in metres as a cell of the map.
fn start_cell(
    s: &Shared,
    start: Option<[f64; 2]>,
) -> Result<Option<m2rc_stdlib::grid::Cell>, RouteError> {
    let n = s.map.n();
    match start {
        None => Ok(None),
        Some([x, y]) => Ok(Some(s.frame.map_to_cell(x, y, n).ok_or_else(|| {
            let (x0, y0) = s.frame.corner_to_map(0.0, 0.0);
            let (x1, y1) = s.frame.corner_to_map(n as f64, n as f64);
            refuse(
                StatusCode::BAD_REQUEST,
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
        })?)),
    }
}

/// Lowers an instruction through the model (with the repair loop of `m2rc run`) and plans it:
/// the program the model wrote, every round (its reply, program, local fixes and diagnostics),
/// and the route.
fn plan_instruction(
    s: &Shared,
    model: &Model,
    instruction: &str,
    start: Option<m2rc_stdlib::grid::Cell>,
) -> Result<Value, RouteError> {
    use m2rc_compiler::lower::EpisodeOutcome;
    if instruction.trim().is_empty() {
        return Err(refuse(
            StatusCode::BAD_REQUEST,
            "the instruction is empty".into(),
            Some("give the route in words, e.g. {\"instruction\": \"Go to the kitchen\"}"),
        ));
    }
    m2rc_benchmark::limits::check_program_size(instruction).map_err(|m| {
        refuse(
            StatusCode::PAYLOAD_TOO_LARGE,
            format!("instruction: {m}"),
            None,
        )
    })?;
    let meter = Arc::new(Meter::new(EpisodeBudget {
        max_wall: Some(s.max_wall),
        ..model.budget.clone()
    }));
    let exchange = m2rc_llm::Exchange {
        store: &model.store,
        fetch: &model.client,
    };
    let (_, trace) = m2rc_benchmark::methods::grounding2route::lower_and_plan(
        &exchange,
        &s.map,
        &s.planning,
        instruction,
        &format!("{}/serve", s.map.map_id),
        &model.prompt,
        &model.repair,
        &PipelineOptions {
            start,
            meter: Some(meter.clone()),
            ..PipelineOptions::default()
        },
    );
    let rounds = serde_json::to_value(&trace.attempts).unwrap_or_default();
    match (&trace.outcome, trace.output) {
        (EpisodeOutcome::Success { .. }, Some(compiled)) => {
            let program = trace.final_program.unwrap_or_default();
            let diagnostics = serde_json::from_str::<Value>(&to_json(&compiled.warnings, &program))
                .unwrap_or_default();
            let mut out = route_body(s, &compiled);
            out["instruction"] = json!(instruction);
            out["program"] = json!(program);
            out["diagnostics"] = diagnostics;
            out["rounds"] = rounds;
            Ok(out)
        }
        (outcome, _) => {
            let (status, message) = match (meter.exceeded(), outcome) {
                (Some(why), _) => (
                    StatusCode::SERVICE_UNAVAILABLE,
                    format!("the request went over the service's limits: {why}"),
                ),
                (None, EpisodeOutcome::ModelFailed { .. } | EpisodeOutcome::Pending { .. }) => (
                    StatusCode::BAD_GATEWAY,
                    "the model did not answer".to_string(),
                ),
                (None, _) => (
                    StatusCode::UNPROCESSABLE_ENTITY,
                    format!(
                        "no program the model wrote compiles on this map ({} after {} round(s))",
                        outcome.status(),
                        trace.attempts.len()
                    ),
                ),
            };
            Err(RouteError {
                status,
                body: json!({
                    "status": "error",
                    "message": message,
                    "instruction": instruction,
                    "program": trace.final_program,
                    "rounds": rounds,
                }),
            })
        }
    }
}

/// The route part of a response: cells, the same in the map frame, stages and the `nav-path`.
fn route_body(s: &Shared, compiled: &m2rc_benchmark::pipeline::CompiledRoute) -> Value {
    let route = crate::cmd::route_out::route_out(compiled, &s.map);
    let poses: Vec<[f64; 2]> = route
        .cells
        .iter()
        .map(|&c| {
            let (x, y) = s.frame.cell_to_map(c);
            [x, y]
        })
        .collect();
    let doc = crate::cmd::compile::route_document(compiled, &s.map);
    json!({
        "status": "ok",
        "route": {
            "cells": route.cells,
            "map_frame": {"frame_id": s.frame.frame_id, "points_m": poses},
            "length_m": compiled.route.length_m,
            "stages": doc["m2rc"]["stages"],
        },
        "nav_path": m2rc_stdlib::export::yaml::nav_path(&s.frame, &route),
    })
}
