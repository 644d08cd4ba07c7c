//! `m2rc compile`: check, ground, verify and plan a `.m2r` program on a map; print a summary and
//! write the route (Map2Route prediction format plus metadata), the RouteIR and a picture.
//!
//! Everything is computed in memory first and files are written only when compilation succeeded,
//! each atomically, so a failing program never leaves a partial output behind.

use crate::io::{display_name, read_to_string, unusable, write_atomic};
use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::pipeline::{
    CompileFailure, CompiledRoute, PipelineOptions, compile_and_plan_explained_with, stage_ends,
};
use m2rc_compiler::diagnostic::{Diagnostic, render_text, to_json};
use m2rc_compiler::ir::{ConstraintKind, Direction, RouteIr, Shape, StageScope};
use m2rc_planner::PlannerKind;
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use m2rc_stdlib::render::{Overlay, RegionKind, RenderOptions, render_map};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Args)]
pub struct CompileArgs {
    /// The `.m2r` program; `-` reads standard input.
    pub file: PathBuf,
    /// A Map2Route map, a ProcTHOR house, `demo`, or `-` (standard input); defaults to the
    /// episode's map in a suite (with --episode), else the program's `// map: ...` first line
    /// (a path, `demo`, or a suite map key such as `procthor/001_valunseen`).
    #[arg(long)]
    pub map: Option<String>,
    /// Plan from this episode's start (a Map2Route instruction JSON; `-` reads standard input),
    /// and refuse a map the episode was not made for. A gold program inside a suite
    /// (`programs/<map_id>/instruction_<id>.m2r`) uses its episode without this flag.
    #[arg(long, value_name = "INSTRUCTION.json")]
    pub episode: Option<PathBuf>,
    /// Where to write the route (or the RouteIR with `--emit ir`); `-` writes standard output
    /// (the summary then goes to standard error).
    #[arg(short = 'o', long)]
    pub output: Option<PathBuf>,
    /// What `-o` receives (`ir` without `-o` prints the RouteIR to stdout). `ltl`, `dfa`, `hoa`
    /// and `dot` are the route's hard constraints as an LTLf formula and its minimal automaton
    /// (JSON, HOA, Graphviz); without `-o` they go to stdout. `nav-path` (a nav_msgs/Path
    /// YAML), `waypoints` (a Nav2 FollowWaypoints goal), `geojson` and `mcap` (a recording with
    /// the map, for Foxglove and ros2 bag; needs `-o`) are the route in the map frame.
    #[arg(long, value_enum, default_value_t = Emit::Route)]
    pub emit: Emit,
    /// Draw the route over the map into this PNG. When planning fails, the picture shows the
    /// failed plan instead (the avoided regions, the target, the start, the blocking doorway)
    /// and the command still exits with 1.
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// With --png: write the category of each piece of furniture on the picture (as
    /// `map render --labels` does).
    #[arg(long, requires = "png")]
    pub labels: bool,
    /// Route planner: sequential (stage by stage, the default), global (all stages at once) or
    /// shortest (ignore preferences). An LTL route (`route ltl "..."`) is always planned by the
    /// LTL planner.
    #[arg(long, value_enum)]
    pub planner: Option<Planner>,
    /// Start `x,y` in metres in the map's frame (`docs/maps.md`, "The map frame"; default:
    /// the episode's start, else the map's start).
    #[arg(long, value_parser = crate::cmd::route_out::parse_xy, allow_hyphen_values = true, conflicts_with = "start_cell")]
    pub start: Option<[f64; 2]>,
    /// Start cell `row,col`.
    #[arg(long, value_parser = crate::cmd::route_out::parse_cell)]
    pub start_cell: Option<Cell>,
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
    NavPath,
    Waypoints,
    Geojson,
    Mcap,
}

impl Emit {
    /// The robot-frame outputs (`docs/maps.md`, "Routes out").
    pub fn robot(self) -> Option<crate::cmd::route_out::RobotEmit> {
        use crate::cmd::route_out::RobotEmit;
        match self {
            Emit::NavPath => Some(RobotEmit::NavPath),
            Emit::Waypoints => Some(RobotEmit::Waypoints),
            Emit::Geojson => Some(RobotEmit::Geojson),
            Emit::Mcap => Some(RobotEmit::Mcap),
            _ => None,
        }
    }
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

/// Resolves a map argument: `demo`, a path as given (relative to the working directory), a
/// suite map key (`procthor/<map_id>`) of the suite the program is in, or a path relative to
/// the program's folder and its parents.
fn resolve_map(arg: &str, program: &Path) -> String {
    if arg == "demo" || arg == "-" || Path::new(arg).exists() {
        return arg.to_string();
    }
    if let Some(p) = crate::suite_layout::map_for_key(program, arg) {
        return p.to_string_lossy().into_owned();
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

/// What to do when the map a program's `// map:` line names cannot be loaded: a suite key
/// (`procthor/<map_id>`) is found only from inside its suite, so a program copied out of it needs
/// `--map`.
fn header_map_help(line: &str, file_name: &str) -> String {
    let is_key = line.contains('/') && !line.ends_with(".json") && !line.starts_with(['.', '/']);
    match line.rsplit('/').next() {
        Some(id) if is_key && !id.is_empty() => format!(
            "`// map: {line}` in {file_name} names a map of a benchmark suite, which is found only \
             when the program lies inside that suite (`<suite>/programs/...`); pass the map \
             file: `--map <suite>/maps/{id}/{id}.json`"
        ),
        _ => format!(
            "the map comes from the `// map: {line}` line of {file_name}; pass `--map \
             <map.json|house.json|demo>` to use another"
        ),
    }
}

pub fn run(args: CompileArgs) -> Result<ExitCode> {
    let source = read_to_string(&args.file)?;
    let file_name = display_name(&args.file);
    m2rc_benchmark::limits::check_program_size(&source)
        .map_err(|m| unusable(anyhow::anyhow!("{file_name}: {m}")))?;
    // The episode: given, or the gold program's own inside a suite.
    let episode_path = match &args.episode {
        Some(p) => Some(p.clone()),
        None if !crate::io::is_dash(&args.file) => {
            crate::suite_layout::episode_for_program(&args.file)
        }
        None => None,
    };
    let episode = match &episode_path {
        Some(p) => {
            let name = display_name(p);
            let ep = Episode::from_json_str(&read_to_string(p)?, &name)?;
            m2rc_benchmark::episode_check::check_episode(&ep, None, &name).map_err(unusable)?;
            Some((name, p.clone(), ep))
        }
        None => None,
    };
    let episode_map = || {
        let (_, path, ep) = episode.as_ref()?;
        let key = ep.map_id.as_deref()?;
        crate::suite_layout::map_for_key(path, key).map(|p| p.to_string_lossy().into_owned())
    };
    let mut from_header = None;
    let map_arg = match args.map.clone().or_else(episode_map) {
        Some(m) => m,
        None => match map_line(&source) {
            Some(m) => {
                from_header = Some(m.to_string());
                resolve_map(m, &args.file)
            }
            None => {
                return Err(unusable(anyhow::anyhow!(
                    "no map: pass `--map <map.json|demo>` or start {file_name} with `// map: <path|demo>`"
                )));
            }
        },
    };
    let loaded = crate::io::load_map_prepared(&map_arg).map_err(|e| match &from_header {
        Some(line) => unusable(anyhow::anyhow!(
            "{e:#}\nhelp: {}",
            header_map_help(line, &file_name)
        )),
        None => e,
    })?;
    let frame = m2rc_stdlib::map::frame::MapFrame::of(&loaded.doc.map, Some(&loaded.doc.extra))
        .map_err(|e| unusable(anyhow::Error::new(e).context(format!("map `{map_arg}`"))))?;
    let kind = loaded.kind;
    let map = &loaded.doc.map;
    if args.emit.robot().is_some_and(|r| r.is_binary()) && args.output.is_none() {
        return Err(unusable(anyhow::anyhow!(
            "--emit mcap writes a binary recording: pass `-o route.mcap` (or `-o -` for standard output)"
        )));
    }
    let mut start =
        crate::cmd::route_out::start_from(args.start, args.start_cell, &frame, map.n())?;
    if let Some((name, _, ep)) = &episode {
        m2rc_benchmark::episode_check::check_episode(ep, Some(map.n()), name).map_err(unusable)?;
        if kind == m2rc_stdlib::load::SourceKind::Map2RouteMap {
            crate::cmd::eval::check_same_map(ep, name, Some(map.map_id.as_str()), &map_arg)?;
        }
        if start.is_none() {
            let cell = m2rc_benchmark::methods::start_cell(map, ep)
                .map_err(|e| unusable(anyhow::anyhow!("{name}: {e}")))?;
            start = Some(cell);
            if args.episode.is_none() {
                eprintln!("note: planning from the start of the episode {name}");
            }
        }
    }
    if let Some(s) = start {
        let n = map.n();
        if s.row as usize >= n || s.col as usize >= n {
            return Err(unusable(anyhow::anyhow!(
                "--start-cell {},{} is outside the map: the grid is {n}x{n} cells (rows and columns 0..{})",
                s.row,
                s.col,
                n.saturating_sub(1)
            )));
        }
    }
    let opts = PipelineOptions {
        planner: match args.planner.unwrap_or(Planner::Sequential) {
            Planner::Sequential => PlannerKind::Sequential,
            Planner::Global => PlannerKind::Global,
            Planner::Shortest => PlannerKind::Shortest,
            Planner::Ltl => PlannerKind::Ltl,
        },
        start,
        ..PipelineOptions::default()
    };
    crate::timings::mark("compile: ready to compile");
    let planning = loaded.planning()?;
    let compiled = match compile_and_plan_explained_with(&source, map, &planning, &opts) {
        Ok(c) => c,
        Err(failure) => {
            print_diagnostics(&failure.diagnostics, &file_name, &source, args.format);
            if let Some(path) = &args.png {
                failed_png(path, map, &failure, args.labels)?;
            }
            return Ok(ExitCode::FAILURE);
        }
    };
    if let Some(p) = args
        .planner
        .filter(|p| *p != Planner::Ltl && compiled.ltl.is_some())
    {
        eprintln!(
            "note: an LTL route is always planned by the LTL planner; `--planner {}` does not apply to it",
            p.to_possible_value()
                .map_or_else(String::new, |v| v.get_name().to_string())
        );
    }
    crate::timings::mark("compile: compiled and planned");
    // Build every output before writing any.
    let ir_json = compiled.ir.to_json();
    let route_json = serde_json::to_string_pretty(&route_document(&compiled, map))?;
    let ltl_text = match ltl_emit(args.emit) {
        Some(kind) => Some(
            m2rc_compiler::ltl::emit(&compiled.ltl_route(), kind, &compiled.ir.map_id)
                .map_err(anyhow::Error::msg)
                .context("cannot build the route's automaton")?,
        ),
        None => None,
    };
    let robot = match args.emit.robot() {
        Some(kind) => Some(crate::cmd::route_out::emit(kind, map, &frame, &compiled)?),
        None => None,
    };
    let png = match &args.png {
        Some(_) => Some(
            render_map(
                &shown_map(map, &compiled),
                &RenderOptions {
                    labels: args.labels,
                    ..render_options(&compiled)
                },
            )
            .context("cannot render the route")?
            .png,
        ),
        None => None,
    };
    match (&args.output, args.emit) {
        (Some(out), Emit::Route) => write_atomic(out, route_json.as_bytes())?,
        (Some(out), Emit::Ir) => write_atomic(out, ir_json.as_bytes())?,
        (Some(out), _) if robot.is_some() => write_atomic(out, robot.as_deref().unwrap_or(&[]))?,
        (Some(out), _) => write_atomic(out, ltl_text.as_deref().unwrap_or("").as_bytes())?,
        (None, _) => {}
    }
    if let (Some(path), Some(png)) = (&args.png, png) {
        write_atomic(path, &png)?;
    }
    // With `-o -` standard output holds the route; the summary goes to standard error.
    let to_stderr = args.output.as_deref().is_some_and(crate::io::is_dash);
    let say = |text: String| -> Result<()> {
        if to_stderr {
            eprint!("{text}");
            Ok(())
        } else {
            crate::io::stdout(&text)
        }
    };
    match args.format {
        Format::Json => say(format!(
            "{}\n",
            serde_json::to_string_pretty(&summary_json(&compiled, &source))?
        ))?,
        Format::Text => {
            if !compiled.warnings.is_empty() {
                eprint!("{}", render_text(&compiled.warnings, &file_name, &source));
            }
            if args.emit == Emit::Ir && args.output.is_none() {
                say(format!("{ir_json}\n"))?;
            } else if let (Some(bytes), None) = (&robot, &args.output) {
                crate::io::stdout_bytes(bytes)?;
            } else if let (Some(text), None) = (&ltl_text, &args.output) {
                say(text.clone())?;
            } else {
                say(summary_text(&compiled))?;
            }
        }
    }
    crate::timings::mark("compile: written");
    Ok(ExitCode::SUCCESS)
}

/// The picture of a failed plan (`--png` on a program that does not compile); a program that
/// failed before planning has no plan to draw, and the user is told so.
fn failed_png(
    path: &Path,
    map: &SemanticMap,
    failure: &CompileFailure,
    labels: bool,
) -> Result<()> {
    let Some(plan) = &failure.plan else {
        eprintln!(
            "note: {} not written: the program failed before planning, so there is no plan to draw",
            path.display()
        );
        return Ok(());
    };
    let code = failure
        .diagnostics
        .iter()
        .find(|d| d.is_error())
        .map_or("E0705", |d| d.code.id());
    let mut shown = map.clone();
    if let Some(&s) = plan.route_so_far.first() {
        shown.start = Some(s);
    }
    let opts = RenderOptions {
        labels,
        ..plan.render_options(code)
    };
    let png = render_map(&shown, &opts)
        .context("cannot render the failed plan")?
        .png;
    write_atomic(path, &png)?;
    eprintln!("note: drew the failed plan in {}", path.display());
    Ok(())
}

/// The map as the picture shows it: its start is where the route starts (the episode's or
/// `--start`), not also the map's own start pose.
fn shown_map(map: &SemanticMap, c: &CompiledRoute) -> SemanticMap {
    let mut shown = map.clone();
    if let Some(&s) = c.route.trajectory.first() {
        shown.start = Some(s);
    }
    shown
}

/// The LTL backend's output for `--emit`, if it is one of its kinds.
fn ltl_emit(e: Emit) -> Option<m2rc_compiler::ltl::EmitKind> {
    use m2rc_compiler::ltl::EmitKind;
    match e {
        Emit::Route | Emit::Ir | Emit::NavPath | Emit::Waypoints | Emit::Geojson | Emit::Mcap => {
            None
        }
        Emit::Ltl => Some(EmitKind::Ltl),
        Emit::Dfa => Some(EmitKind::Dfa),
        Emit::Hoa => Some(EmitKind::Hoa),
        Emit::Dot => Some(EmitKind::Dot),
    }
}

fn print_diagnostics(diags: &[Diagnostic], file_name: &str, source: &str, format: Format) {
    match format {
        Format::Text => eprint!("{}", render_text(diags, file_name, source)),
        Format::Json => {
            let _ = crate::io::stdout(&format!("{}\n", to_json(diags, source)));
        }
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

/// Metres with two decimals, never `-0.00`.
fn metres(x: f64) -> String {
    let x = if x.abs() < 0.005 { 0.0 } else { x };
    format!("{x:.2} m")
}

/// What a constraint asks for, in the language's own words (`follow_wall`, not `followwall`).
fn constraint_what(ir: &RouteIr, i: usize) -> String {
    let c = &ir.constraints[i];
    match &c.kind {
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
        } => {
            let shape = match shape {
                Shape::Circle => "circle",
                Shape::FollowWall => "follow_wall",
                Shape::Patrol => "patrol",
                Shape::Through => "through",
            };
            match direction {
                Some(d) => {
                    let d = match d {
                        Direction::Clockwise => "clockwise",
                        Direction::Counterclockwise => "counterclockwise",
                    };
                    format!(
                        "{shape} {d} around {} ({} waypoints)",
                        around.label,
                        waypoints.len()
                    )
                }
                None => format!("{shape} {} ({} waypoints)", around.label, waypoints.len()),
            }
        }
        ConstraintKind::Clearance { distance_m } => format!("clearance {}", metres(*distance_m)),
    }
}

fn constraint_line(ir: &RouteIr, i: usize) -> String {
    let c = &ir.constraints[i];
    let what = constraint_what(ir, i);
    match &c.spatial_scope {
        Some(s) => format!("{} {what} within {}", c.id, s.label),
        None => format!("{} {what}", c.id),
    }
}

pub fn summary_text(c: &CompiledRoute) -> String {
    let mut out = format!(
        "route on `{}`: {} stage(s), {}, planner {}{}\n",
        c.ir.map_id,
        c.ir.stages.len(),
        metres(c.route.length_m),
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
            "  {}. {} -> {} ({})\n",
            i + 1,
            s.name,
            s.target.label,
            metres(len)
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
    for (ci, con) in c.ir.constraints.iter().enumerate() {
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
                format!(
                    "where {} applies: {}{scope}",
                    constraint_what(&c.ir, ci),
                    s.label
                ),
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
        use crate::cmd::route_out::{parse_cell, parse_xy};
        assert_eq!(parse_cell("3, 4"), Ok(Cell::new(3, 4)));
        assert!(parse_cell("3").is_err());
        assert_eq!(parse_xy("-1.5, 2"), Ok([-1.5, 2.0]));
        assert!(parse_xy("1.5").is_err() && parse_xy("x,1").is_err());
    }

    fn compile_example(name: &str) -> CompiledRoute {
        let path = format!("{}/../examples/{name}", env!("CARGO_MANIFEST_DIR"));
        let source = std::fs::read_to_string(path).unwrap();
        let map = m2rc_stdlib::demo::demo_map().unwrap();
        m2rc_benchmark::pipeline::compile_and_plan(&source, &map, &PipelineOptions::default())
            .unwrap()
    }

    /// Labels a user reads: the map's room names, scopes named by what they scope, the
    /// language's own shape words, no negative zero.
    #[test]
    fn labels_name_rooms_and_scopes_as_users_see_them() {
        let c = compile_example("05_closer_to_table.m2r");
        let labels: Vec<String> = render_options(&c)
            .overlays
            .iter()
            .filter_map(|o| match o {
                Overlay::Region { label, .. } => label.clone(),
                _ => None,
            })
            .collect();
        let scope = labels
            .iter()
            .find(|l| l.starts_with("where closer to"))
            .unwrap_or_else(|| panic!("no scope label in {labels:?}"));
        assert!(scope.contains("living_room"), "{scope}");
        assert!(!labels.iter().any(|l| l.contains("c0 scope")), "{labels:?}");
        let text = summary_text(&compile_example("07_follow_wall.m2r"));
        assert!(
            text.contains("follow_wall") && !text.contains("followwall"),
            "{text}"
        );
        assert_eq!(metres(-0.001), "0.00 m");
        for line in summary_text(&c).lines() {
            let bad = ["bathroom ", "bedroom ", "kitchen ", "living_room "]
                .iter()
                .any(|w| {
                    line.match_indices(w).any(|(i, _)| {
                        line[i + w.len()..].starts_with(|ch: char| ch.is_ascii_digit())
                    })
                });
            assert!(!bad, "room id instead of the map's name: {line}");
        }
    }
}
