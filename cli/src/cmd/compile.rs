//! `m2rc compile`: check, ground, verify and plan a `.m2r` program on a map; print a summary and
//! write the route (Map2Route prediction format plus metadata), the RouteIR and a picture.
//!
//! Everything is computed in memory first and files are written only when compilation succeeded,
//! each atomically, so a failing program never leaves a partial output behind.

use crate::io::{read_to_string, write_atomic};
use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use m2rc_benchmark::pipeline::{CompiledRoute, PipelineOptions, compile_and_plan, stage_ends};
use m2rc_compiler::diagnostic::{Diagnostic, render_text, to_json};
use m2rc_compiler::ir::{ConstraintKind, RouteIr, StageScope};
use m2rc_planner::PlannerKind;
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use m2rc_stdlib::render::{Overlay, RegionKind, RenderOptions, render_map};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Args)]
pub struct CompileArgs {
    /// The `.m2r` program.
    pub file: PathBuf,
    /// Map file (Map2Route JSON, ProcTHOR house JSON) or `demo`; defaults to the program's
    /// `// map: ...` first line.
    #[arg(long)]
    pub map: Option<String>,
    /// Where to write the route (or the RouteIR with `--emit ir`).
    #[arg(short = 'o', long)]
    pub output: Option<PathBuf>,
    /// What `-o` receives (`ir` without `-o` prints the RouteIR to stdout). `ltl`, `dfa`, `hoa`
    /// and `dot` are the route's hard constraints as an LTLf formula and its minimal automaton
    /// (JSON, HOA, Graphviz); without `-o` they go to stdout.
    #[arg(long, value_enum, default_value_t = Emit::Route)]
    pub emit: Emit,
    /// Draw the route over the map into this PNG.
    #[arg(long)]
    pub png: Option<PathBuf>,
    #[arg(long, value_enum, default_value_t = Planner::Sequential)]
    pub planner: Planner,
    /// Start cell `row,col` (default: the map's start).
    #[arg(long, value_parser = parse_cell)]
    pub start: Option<Cell>,
    /// Summary and diagnostics as text or as JSON.
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub format: Format,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Emit {
    Route,
    Ir,
    Ltl,
    Dfa,
    Hoa,
    Dot,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Planner {
    Sequential,
    Global,
    Shortest,
    /// The LTL backend: the route's hard constraints as an LTLf automaton, planned on the product
    /// of the grid and the automaton (soft preferences dropped).
    Ltl,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Format {
    Text,
    Json,
}

fn parse_cell(s: &str) -> Result<Cell, String> {
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

/// The `// map: <path|demo>` line of a program, if any (first non-empty line).
pub fn map_line(source: &str) -> Option<&str> {
    let first = source.lines().find(|l| !l.trim().is_empty())?;
    first
        .trim()
        .strip_prefix("//")?
        .trim()
        .strip_prefix("map:")
        .map(str::trim)
        .filter(|s| !s.is_empty())
}

/// Resolves a map argument: `demo`, a path as given (relative to the working directory), or
/// relative to the program's folder and its parents.
fn resolve_map(arg: &str, program: &Path) -> String {
    if arg == "demo" || Path::new(arg).exists() {
        return arg.to_string();
    }
    let mut dir = program.parent();
    while let Some(d) = dir {
        let p = d.join(arg);
        if p.exists() {
            return p.to_string_lossy().into_owned();
        }
        dir = d.parent();
    }
    arg.to_string()
}

pub fn run(args: CompileArgs) -> Result<ExitCode> {
    let source = read_to_string(&args.file)?;
    let file_name = args.file.display().to_string();
    let map_arg = match args.map.as_deref().or_else(|| map_line(&source)) {
        Some(m) => resolve_map(m, &args.file),
        None => bail!(
            "no map: pass `--map <map.json|demo>` or start {file_name} with `// map: <path|demo>`"
        ),
    };
    let map = m2rc_stdlib::load::load_map(&map_arg)
        .with_context(|| format!("cannot load map `{map_arg}`"))?;
    let opts = PipelineOptions {
        planner: match args.planner {
            Planner::Sequential => PlannerKind::Sequential,
            Planner::Global => PlannerKind::Global,
            Planner::Shortest => PlannerKind::Shortest,
            Planner::Ltl => PlannerKind::Ltl,
        },
        start: args.start,
        ..PipelineOptions::default()
    };
    let compiled = match compile_and_plan(&source, &map, &opts) {
        Ok(c) => c,
        Err(diags) => {
            print_diagnostics(&diags, &file_name, &source, args.format);
            return Ok(ExitCode::FAILURE);
        }
    };
    // Build every output before writing any.
    let ir_json = compiled.ir.to_json();
    let route_json = serde_json::to_string_pretty(&route_document(&compiled, &map))?;
    let ltl_text = match ltl_emit(args.emit) {
        Some(kind) => Some(
            m2rc_compiler::ltl::emit(&compiled.ltl_route(), kind, &compiled.ir.map_id)
                .map_err(anyhow::Error::msg)
                .context("cannot build the route's automaton")?,
        ),
        None => None,
    };
    let png = match &args.png {
        Some(_) => Some(
            render_map(&map, &render_options(&compiled))
                .context("cannot render the route")?
                .png,
        ),
        None => None,
    };
    match (&args.output, args.emit) {
        (Some(out), Emit::Route) => write_atomic(out, route_json.as_bytes())?,
        (Some(out), Emit::Ir) => write_atomic(out, ir_json.as_bytes())?,
        (Some(out), _) => write_atomic(out, ltl_text.as_deref().unwrap_or("").as_bytes())?,
        (None, _) => {}
    }
    if let (Some(path), Some(png)) = (&args.png, png) {
        write_atomic(path, &png)?;
    }
    match args.format {
        Format::Json => println!(
            "{}",
            serde_json::to_string_pretty(&summary_json(&compiled, &source))?
        ),
        Format::Text => {
            if !compiled.warnings.is_empty() {
                eprint!("{}", render_text(&compiled.warnings, &file_name, &source));
            }
            if args.emit == Emit::Ir && args.output.is_none() {
                println!("{ir_json}");
            } else if let (Some(text), None) = (&ltl_text, &args.output) {
                print!("{text}");
            } else {
                print!("{}", summary_text(&compiled));
            }
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// The LTL backend's output for `--emit`, if it is one of its kinds.
fn ltl_emit(e: Emit) -> Option<m2rc_compiler::ltl::EmitKind> {
    use m2rc_compiler::ltl::EmitKind;
    match e {
        Emit::Route | Emit::Ir => None,
        Emit::Ltl => Some(EmitKind::Ltl),
        Emit::Dfa => Some(EmitKind::Dfa),
        Emit::Hoa => Some(EmitKind::Hoa),
        Emit::Dot => Some(EmitKind::Dot),
    }
}

fn print_diagnostics(diags: &[Diagnostic], file_name: &str, source: &str, format: Format) {
    match format {
        Format::Text => eprint!("{}", render_text(diags, file_name, source)),
        Format::Json => println!("{}", to_json(diags, source)),
    }
}

/// `{"trajectory": [[row, col], ...], "m2rc": {...}}`.
pub fn route_document(c: &CompiledRoute, map: &SemanticMap) -> serde_json::Value {
    let ends = stage_ends(&c.route);
    let stages: Vec<serde_json::Value> =
        c.ir.stages
            .iter()
            .enumerate()
            .map(|(i, s)| {
                json!({
                    "name": s.name,
                    "target": s.target.label,
                    "end_index": ends.get(i),
                    "length_m": c.route.segments.get(i).map(|x| x.length_m),
                })
            })
            .collect();
    json!({
        "trajectory": c.route.trajectory,
        "m2rc": {
            "map_id": map.map_id,
            "planner": c.route.planner,
            "profile": c.route.profile,
            "status": c.route.status,
            "length_m": c.route.length_m,
            "cost": c.route.cost,
            "binding_rounds": c.rounds,
            "binding_stable": c.stable,
            "stages": stages,
        }
    })
}

fn constraint_line(ir: &RouteIr, i: usize) -> String {
    let c = &ir.constraints[i];
    let what = match &c.kind {
        ConstraintKind::Avoid { place } => format!("avoid {}", place.label),
        ConstraintKind::Near { reference } => format!("near {}", reference.label),
        ConstraintKind::Far { reference } => format!("far from {}", reference.label),
        ConstraintKind::Relative { closer, farther } => {
            format!("closer to {} than to {}", closer.label, farther.label)
        }
        ConstraintKind::PathShape {
            shape,
            direction,
            around,
            waypoints,
        } => format!(
            "{shape:?} {direction:?} around {} ({} waypoints)",
            around.label,
            waypoints.len()
        )
        .to_lowercase(),
        ConstraintKind::Clearance { distance_m } => format!("clearance {distance_m} m"),
    };
    match &c.spatial_scope {
        Some(s) => format!("{} {what} within {}", c.id, s.label),
        None => format!("{} {what}", c.id),
    }
}

pub fn summary_text(c: &CompiledRoute) -> String {
    let mut out = format!(
        "route on `{}`: {} stage(s), {:.2} m, planner {}{}\n",
        c.ir.map_id,
        c.ir.stages.len(),
        c.route.length_m,
        c.route.planner,
        if c.ir.route_bindings.is_empty() {
            String::new()
        } else {
            format!(
                ", route-dependent places bound in {} round(s){}",
                c.rounds,
                if c.stable { "" } else { " (not stable)" }
            )
        }
    );
    for (i, s) in c.ir.stages.iter().enumerate() {
        let len = c.route.segments.get(i).map_or(0.0, |x| x.length_m);
        out.push_str(&format!(
            "  {}. {} -> {} ({len:.2} m)\n",
            i + 1,
            s.name,
            s.target.label
        ));
        for p in &s.passes {
            out.push_str(&format!("       pass {}\n", p.place.label));
        }
        for (ci, con) in c.ir.constraints.iter().enumerate() {
            if con.active_in(i) {
                out.push_str(&format!("       {}\n", constraint_line(&c.ir, ci)));
            }
        }
    }
    for b in &c.ir.route_bindings {
        out.push_str(&format!(
            "  {} = {} (line {})\n",
            b.function, b.resolved, b.span.line
        ));
    }
    out
}

fn summary_json(c: &CompiledRoute, source: &str) -> serde_json::Value {
    let stages: Vec<serde_json::Value> = c
        .ir
        .stages
        .iter()
        .enumerate()
        .map(|(i, s)| {
            json!({
                "name": s.name,
                "target": s.target.label,
                "length_m": c.route.segments.get(i).map(|x| x.length_m),
                "constraints": (0..c.ir.constraints.len()).filter(|&k| c.ir.constraints[k].active_in(i)).map(|k| constraint_line(&c.ir, k)).collect::<Vec<_>>(),
            })
        })
        .collect();
    json!({
        "status": "ok",
        "map_id": c.ir.map_id,
        "length_m": c.route.length_m,
        "planner": c.route.planner,
        "stages": stages,
        "route_bindings": c.ir.route_bindings,
        "warnings": serde_json::from_str::<serde_json::Value>(&to_json(&c.warnings, source)).unwrap_or_default(),
    })
}

/// The route over the map: destinations, must-pass places, avoid regions, preference references and
/// scopes, the route coloured by stage and numbered markers at the destinations.
pub fn render_options(c: &CompiledRoute) -> RenderOptions {
    let mut overlays = Vec::new();
    let region = |cells: &[Cell], kind, label: String| Overlay::Region {
        cells: cells.to_vec(),
        kind,
        label: Some(label),
    };
    for con in &c.ir.constraints {
        let scope = match &con.stage_scope {
            StageScope::Global => String::new(),
            StageScope::Stages(s) => {
                format!(
                    " [stage {}]",
                    s.iter()
                        .map(|i| (i + 1).to_string())
                        .collect::<Vec<_>>()
                        .join(",")
                )
            }
        };
        if let Some(s) = &con.spatial_scope {
            overlays.push(region(
                s.cells.cells(),
                RegionKind::Scope,
                format!("{} scope{scope}", con.id),
            ));
        }
        match &con.kind {
            ConstraintKind::Avoid { place } => overlays.push(region(
                place.cells.cells(),
                RegionKind::Avoid,
                format!("avoid {}{scope}", place.label),
            )),
            ConstraintKind::Near { reference } => overlays.push(region(
                reference.cells.cells(),
                RegionKind::PreferenceRef,
                format!("near {}{scope}", reference.label),
            )),
            ConstraintKind::Far { reference } => overlays.push(region(
                reference.cells.cells(),
                RegionKind::PreferenceRef,
                format!("far {}{scope}", reference.label),
            )),
            ConstraintKind::Relative { closer, farther } => {
                overlays.push(region(
                    closer.cells.cells(),
                    RegionKind::PreferenceRef,
                    format!("closer: {}{scope}", closer.label),
                ));
                overlays.push(region(
                    farther.cells.cells(),
                    RegionKind::PreferenceRef,
                    format!("farther: {}{scope}", farther.label),
                ));
            }
            ConstraintKind::PathShape { waypoints, .. } => {
                for (k, w) in waypoints.iter().enumerate() {
                    overlays.push(region(
                        w.cells.cells(),
                        RegionKind::PreferenceRef,
                        format!("w{}{scope}", k + 1),
                    ));
                }
            }
            ConstraintKind::Clearance { .. } => {}
        }
    }
    for (i, s) in c.ir.stages.iter().enumerate() {
        for p in &s.passes {
            overlays.push(region(
                p.place.cells.cells(),
                RegionKind::Pass,
                format!("{}: pass {}", i + 1, p.place.label),
            ));
        }
        overlays.push(region(
            s.target.cells.cells(),
            RegionKind::Destination,
            format!("{}: {}", i + 1, s.target.label),
        ));
    }
    let stages: Vec<Vec<Cell>> = c.route.segments.iter().map(|s| s.path.clone()).collect();
    overlays.push(Overlay::StagedRoute {
        stages,
        label: Some(format!("route {:.1} m", c.route.length_m)),
    });
    for (i, s) in c.route.segments.iter().enumerate() {
        if let Some(&end) = s.path.last() {
            overlays.push(Overlay::Marker {
                cell: end,
                label: (i + 1).to_string(),
            });
        }
    }
    if let Some(&start) = c.route.trajectory.first() {
        overlays.push(Overlay::Marker {
            cell: start,
            label: "S".into(),
        });
    }
    RenderOptions {
        overlays,
        title: Some(format!(
            "{} ({} m)",
            c.ir.map_id,
            (c.route.length_m * 10.0).round() / 10.0
        )),
        ..RenderOptions::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_line_and_cells_parse() {
        assert_eq!(map_line("// map: demo\nroute { go start }"), Some("demo"));
        assert_eq!(map_line("\n//map:  ../x.json \n"), Some("../x.json"));
        assert_eq!(map_line("let a = 1"), None);
        assert_eq!(parse_cell("3, 4"), Ok(Cell::new(3, 4)));
        assert!(parse_cell("3").is_err());
    }
}
