//! `m2rc tools --map MAP`: m2rc's read-only semantic queries and RouteIR builders served over
//! stdio as an MCP server (JSON-RPC 2.0, one message per line, as MCP's stdio transport has it),
//! so an external agent grounds routes with the same tools as the ToolCall variant. `task` is the
//! final call: its route is compiled and planned like `m2rc compile`'s, the path comes back, and
//! a fresh session starts for the next route.
//!
//! Nothing a client sends can crash the server: an over-long line, bytes that are not JSON, a
//! message that is not a request, an unknown method or tool, or bad arguments are each answered
//! (JSON-RPC errors for the first four, tool results with `isError` for the rest), and the
//! handles of a session are bounded (`--max-handles`).

use crate::io::unusable;
use anyhow::{Result, anyhow};
use clap::Args;
use m2rc_benchmark::pipeline::{PipelineOptions, compile_and_plan_with};
use m2rc_compiler::tools::{Limits, ToolSession, mcp_tools};
use m2rc_planner::context::MapContext;
use m2rc_stdlib::export::geojson;
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use m2rc_stdlib::map::frame::MapFrame;
use serde_json::{Value, json};
use std::io::{BufRead, Write};
use std::process::ExitCode;

/// The MCP revision this server answers with when the client asks for none it speaks.
pub const PROTOCOL_VERSION: &str = "2025-06-18";

/// The MCP revisions whose `initialize`, `ping`, `tools/list` and `tools/call` this server
/// answers as they define them (later ones only add fields an earlier client ignores).
pub const SUPPORTED_VERSIONS: &[&str] = &[PROTOCOL_VERSION, "2025-03-26", "2024-11-05"];

#[derive(Args, Debug)]
pub struct ToolsArgs {
    /// The map the queries run on: a Map2Route map, a ProcTHOR house or `demo`.
    #[arg(long)]
    pub map: String,
    /// Start `x,y` in metres in the map's frame (default: the map's start).
    #[arg(long, value_name = "X,Y", value_parser = crate::cmd::route_out::parse_xy, allow_hyphen_values = true)]
    pub start: Option<[f64; 2]>,
    /// Longest message line, in bytes; a longer one is answered with a JSON-RPC error and skipped.
    #[arg(long, default_value_t = 1024 * 1024)]
    pub max_line_bytes: usize,
    /// Handles one session may hold before its task must be submitted.
    #[arg(long, default_value_t = 1024)]
    pub max_handles: usize,
}

struct Server<'m> {
    map: &'m SemanticMap,
    frame: MapFrame,
    start: Option<Cell>,
    limits: Limits,
    session: ToolSession<'m>,
    ctx: Option<Result<MapContext, String>>,
}

fn error(id: &Value, code: i64, message: impl Into<String>) -> Value {
    json!({"jsonrpc": "2.0", "id": id, "error": {"code": code, "message": message.into()}})
}

fn result(id: &Value, result: Value) -> Value {
    json!({"jsonrpc": "2.0", "id": id, "result": result})
}

impl<'m> Server<'m> {
    /// The answer to one line (`None` for a notification).
    fn line(&mut self, text: &str) -> Option<Value> {
        let msg: Value = match serde_json::from_str(text) {
            Ok(v) => v,
            Err(e) => return Some(error(&Value::Null, -32700, format!("parse error: {e}"))),
        };
        let Some(obj) = msg.as_object() else {
            return Some(error(
                &Value::Null,
                -32600,
                "invalid request: a message is a JSON object (batches are not taken)",
            ));
        };
        let id = obj.get("id").cloned();
        let valid_id = matches!(id, None | Some(Value::String(_)) | Some(Value::Number(_)));
        let method = obj.get("method").and_then(Value::as_str);
        if obj.get("jsonrpc") != Some(&json!("2.0")) || method.is_none() || !valid_id {
            // A reply from the client (it has `result` or `error`) needs no answer.
            if id.is_some() && (obj.contains_key("result") || obj.contains_key("error")) {
                return None;
            }
            return Some(error(
                &id.filter(|_| valid_id).unwrap_or(Value::Null),
                -32600,
                "invalid request: `jsonrpc` must be \"2.0\" and `method` a string (and `id` a string or number)",
            ));
        }
        let method = method.unwrap_or_default();
        let Some(id) = id else {
            // Notifications (`notifications/initialized`, cancellations) need no answer.
            return None;
        };
        let params = obj.get("params").cloned().unwrap_or(Value::Null);
        Some(match method {
            "initialize" => {
                // The MCP rule: the client's version when this server speaks it, else the
                // latest it does (the client then decides whether to go on).
                let version = params["protocolVersion"]
                    .as_str()
                    .filter(|v| SUPPORTED_VERSIONS.contains(v))
                    .unwrap_or(PROTOCOL_VERSION)
                    .to_string();
                result(
                    &id,
                    json!({
                        "protocolVersion": version,
                        "capabilities": {"tools": {"listChanged": false}},
                        "serverInfo": {"name": "m2rc", "version": env!("CARGO_PKG_VERSION")},
                        "instructions": format!(
                            "Read-only semantic queries over map `{}`. Results are opaque handles \
                             with previews; pass handles to later calls. Build constraints and \
                             segments, then call `task` to get the planned route.",
                            self.map.map_id
                        ),
                    }),
                )
            }
            "ping" => result(&id, json!({})),
            "tools/list" => result(&id, json!({"tools": mcp_tools()})),
            "tools/call" => {
                let Some(name) = params["name"].as_str() else {
                    return Some(error(
                        &id,
                        -32602,
                        "invalid params: `name` (a string) is required",
                    ));
                };
                let args = params.get("arguments").cloned().unwrap_or(Value::Null);
                let r = self.call(name, &args);
                result(&id, r)
            }
            other => error(
                &id,
                -32601,
                format!(
                    "method not found: `{}`",
                    other.chars().take(80).collect::<String>()
                ),
            ),
        })
    }

    fn call(&mut self, name: &str, args: &Value) -> Value {
        let out = self.session.call(name, args);
        let mut content = out.content;
        if let Some(done) = self.session.finished.clone() {
            content["program"] = json!(done.program);
            // The next route starts from a fresh session, whether this one planned or not.
            self.session = ToolSession::new(self.map, self.start, self.limits);
            match self.plan(&done.program) {
                Ok(route) => content["route"] = route,
                Err(e) => {
                    content["error"] = json!(e);
                    return tool_result(content, true);
                }
            }
        }
        tool_result(content, !out.ok)
    }

    fn plan(&mut self, program: &str) -> Result<Value, String> {
        let map = self.map;
        let ctx = self
            .ctx
            .get_or_insert_with(|| MapContext::new(map))
            .as_ref()
            .map_err(|e| format!("the map cannot be planned on: {e}"))?;
        let opts = PipelineOptions {
            start: self.start,
            ..PipelineOptions::default()
        };
        let c = compile_and_plan_with(program, map, ctx, &opts).map_err(|ds| {
            ds.iter()
                .filter(|d| d.is_error())
                .map(|d| format!("{}: {}", d.code.id(), d.message))
                .collect::<Vec<_>>()
                .join("; ")
        })?;
        let out = crate::cmd::route_out::route_out(&c, map);
        Ok(json!({
            "length_m": c.route.length_m,
            "cells": c.route.trajectory.len(),
            "geojson": geojson::route_geojson(&self.frame, &out),
        }))
    }
}

fn tool_result(content: Value, is_error: bool) -> Value {
    json!({
        "content": [{"type": "text", "text": content.to_string()}],
        "structuredContent": content,
        "isError": is_error,
    })
}

/// Reads one line of at most `cap` bytes: `Ok(None)` at the end of input, `Err(n)` for a line
/// longer than the cap (its `n` bytes are read and dropped, never held).
fn read_line(
    input: &mut impl BufRead,
    cap: usize,
) -> std::io::Result<Option<Result<Vec<u8>, usize>>> {
    let mut line = Vec::new();
    let mut total = 0usize;
    loop {
        let buf = input.fill_buf()?;
        if buf.is_empty() {
            if total == 0 {
                return Ok(None);
            }
            return Ok(Some(if total > cap { Err(total) } else { Ok(line) }));
        }
        let (chunk, done) = match buf.iter().position(|&b| b == b'\n') {
            Some(i) => (&buf[..i], Some(i + 1)),
            None => (buf, None),
        };
        total += chunk.len();
        if total <= cap {
            line.extend_from_slice(chunk);
        } else {
            line.clear();
        }
        let used = done.unwrap_or(chunk.len());
        input.consume(used);
        if done.is_some() {
            return Ok(Some(if total > cap { Err(total) } else { Ok(line) }));
        }
    }
}

pub fn run(args: ToolsArgs) -> Result<ExitCode> {
    let (doc, _) = crate::io::load_map_doc_kind(&args.map)?;
    let frame = MapFrame::of(&doc.map, Some(&doc.extra))
        .map_err(|e| unusable(anyhow::Error::new(e).context(format!("map `{}`", args.map))))?;
    let map = doc.map;
    let start = crate::cmd::route_out::start_from(args.start, None, &frame, map.n())?;
    if args.max_handles == 0 || args.max_line_bytes < 64 {
        return Err(unusable(anyhow!(
            "--max-handles must be at least 1 and --max-line-bytes at least 64"
        )));
    }
    let limits = Limits {
        max_handles: args.max_handles,
        ..Limits::default()
    };
    let mut server = Server {
        map: &map,
        frame,
        start,
        limits,
        session: ToolSession::new(&map, start, limits),
        ctx: None,
    };
    let stdin = std::io::stdin();
    let mut input = stdin.lock();
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    while let Some(line) = read_line(&mut input, args.max_line_bytes)? {
        let reply = match line {
            Err(n) => Some(error(
                &Value::Null,
                -32600,
                format!(
                    "invalid request: the line is {n} bytes, more than --max-line-bytes {}",
                    args.max_line_bytes
                ),
            )),
            Ok(bytes) => match std::str::from_utf8(&bytes) {
                Ok(t) if t.trim().is_empty() => None,
                Ok(t) => server.line(t.trim_end_matches('\r')),
                Err(_) => Some(error(
                    &Value::Null,
                    -32700,
                    "parse error: the line is not UTF-8",
                )),
            },
        };
        if let Some(r) = reply {
            writeln!(out, "{r}")?;
            out.flush()?;
        }
    }
    Ok(ExitCode::SUCCESS)
}
