//! `m2rc map import | info | render`: load a map argument (ProcTHOR house, Map2Route map, or
//! `demo`), write it as a Map2Route map, summarise it, or draw it.

use crate::io::write_atomic;
use anyhow::{Context, Result, bail};
use clap::{Args, Subcommand, ValueEnum};
use m2rc_stdlib::import::bounds::parse_memory;
use m2rc_stdlib::import::check::rooms_reachable_from;
use m2rc_stdlib::import::{
    AssetDb, DEFAULT_PADDING_M, DEFAULT_RESOLUTION_M, DEFAULT_ROBOT_RADIUS_M, ImportOptions,
    import_warnings,
};
use m2rc_stdlib::load::{LoadOptions, SourceKind, load_map_with};
use m2rc_stdlib::map::{MapDocument, SemanticMap, write_map_document_to};
use m2rc_stdlib::query::open_area;
use m2rc_stdlib::render::{RenderOptions, render_map};
use serde_json::json;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Subcommand)]
pub enum MapCommand {
    /// Import a ProcTHOR house, a Map2Route map or `demo` and write it as a Map2Route map.
    Import(ImportArgs),
    /// Summarise a map: grid, rooms with areas, object categories, adjacency (door or open),
    /// rooms unreachable from the start.
    Info(InfoArgs),
    /// Draw a map as PNG and/or SVG.
    Render(RenderArgs),
    /// Check maps against their ProcTHOR houses: holes, reachability from the start, leaks.
    Check(super::map_check::CheckArgs),
}

/// Where the map comes from and how a house is turned into a grid.
#[derive(Args)]
pub struct SourceArgs {
    /// A ProcTHOR house (.json, or .jsonl/.jsonl.gz with --index), a Map2Route map, `demo`, or
    /// `-` (standard input).
    pub map: String,
    #[command(flatten)]
    pub grid: GridArgs,
}

/// How a house is turned into a grid (shared by `map import | info | render` and `map check`).
#[derive(Args)]
pub struct GridArgs {
    /// Which house of a .jsonl(.gz) file, 0-based.
    #[arg(long)]
    pub index: Option<usize>,
    /// ProcTHOR asset database (asset-database.json); default: `assets/asset-database.json`
    /// beside the houses folder when there is one, else a built-in size table (with a warning).
    #[arg(long)]
    pub assets: Option<PathBuf>,
    /// Metres per grid cell for houses.
    #[arg(long, default_value_t = DEFAULT_RESOLUTION_M)]
    pub resolution: f64,
    /// Robot radius in metres; free space is eroded by it (houses only).
    #[arg(long, default_value_t = DEFAULT_ROBOT_RADIUS_M)]
    pub robot_radius: f64,
    /// Margin around the floor polygons in metres (houses only).
    #[arg(long, default_value_t = DEFAULT_PADDING_M)]
    pub padding: f64,
    /// Refuse a house whose grid would need more memory than this (e.g. 8G, 512M; houses only).
    #[arg(long, default_value = "4G", value_parser = parse_memory)]
    pub max_memory: u64,
}

#[derive(Args)]
pub struct ImportArgs {
    #[command(flatten)]
    pub source: SourceArgs,
    /// Output Map2Route map JSON; `-` writes standard output.
    #[arg(short, long)]
    pub output: PathBuf,
    /// What the input is: told apart by content (a house, a map, `demo`), or `nav2`: a
    /// `map_server` YAML with its PGM/PNG image (`docs/maps.md`, "Nav2 import").
    #[arg(long, value_enum, default_value_t = From::Auto)]
    pub from: From,
    /// With `--from nav2`: the rooms, objects and doors as GeoJSON in the map frame.
    #[arg(long, requires = "from")]
    pub semantics: Option<PathBuf>,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum From {
    Auto,
    Nav2,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum InfoFormat {
    Text,
    Json,
}

#[derive(Args)]
pub struct InfoArgs {
    #[command(flatten)]
    pub source: SourceArgs,
    /// Print a readable summary (text) or one JSON object (json).
    #[arg(long, value_enum, default_value = "text")]
    pub format: InfoFormat,
}

#[derive(Args)]
pub struct RenderArgs {
    #[command(flatten)]
    pub source: SourceArgs,
    /// PNG output.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// SVG output.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Label furniture with its category.
    #[arg(long)]
    pub labels: bool,
}

pub fn run(command: MapCommand) -> Result<ExitCode> {
    match command {
        MapCommand::Import(a) => import(a),
        MapCommand::Info(a) => info(a),
        MapCommand::Render(a) => render(a),
        MapCommand::Check(a) => super::map_check::run(a),
    }
}

pub(crate) fn load_options<'a>(src: &GridArgs, db: Option<&'a AssetDb>) -> LoadOptions<'a> {
    LoadOptions {
        index: src.index,
        assets: db,
        import: ImportOptions {
            resolution: src.resolution,
            padding_m: src.padding,
            robot_radius_m: src.robot_radius,
            map_id: None,
            max_memory_bytes: src.max_memory,
        },
    }
}

fn load(src: &SourceArgs) -> Result<(MapDocument, SourceKind)> {
    let db = crate::io::asset_db_for(&src.map, src.grid.assets.as_deref())?;
    let mut opts = load_options(&src.grid, db.as_ref());
    let staged = crate::io::MapArg::new(&src.map)?;
    if staged.is_stdin() && opts.import.map_id.is_none() {
        opts.import.map_id = Some("stdin".into());
    }
    let loaded = load_map_with(&staged.arg, &opts).map_err(|e| {
        crate::io::unusable(anyhow::Error::new(e).context(format!("cannot load map `{}`", src.map)))
    })?;
    crate::io::warn_without_assets(&src.map, loaded.1, db.is_some());
    for w in import_warnings(&loaded.0) {
        eprintln!("warning: {}: {w}", src.map);
    }
    Ok(loaded)
}

fn import(args: ImportArgs) -> Result<ExitCode> {
    if args.from == From::Nav2 {
        return import_nav2(&args);
    }
    if args.semantics.is_some() {
        bail!("--semantics belongs to a Nav2 map: pass `--from nav2 map.yaml`");
    }
    let (doc, kind) = load(&args.source)?;
    if crate::io::is_dash(&args.output) {
        write_stdout(&doc)?;
    } else {
        write_streamed(&args.output, &doc)?;
    }
    eprintln!(
        "wrote {} ({} x {} cells, {} rooms, {} objects, from {})",
        if crate::io::is_dash(&args.output) {
            "the map to standard output".to_string()
        } else {
            args.output.display().to_string()
        },
        doc.map.n(),
        doc.map.n(),
        doc.map.rooms.len(),
        doc.map.objects.len(),
        kind_name(kind)
    );
    Ok(ExitCode::SUCCESS)
}

fn import_nav2(args: &ImportArgs) -> Result<ExitCode> {
    use m2rc_stdlib::import::nav2::{Nav2Options, import_nav2};
    let yaml = PathBuf::from(&args.source.map);
    // The image the YAML names is an input too.
    let image = std::fs::read_to_string(&yaml).ok().and_then(|t| {
        let dir = yaml.parent().unwrap_or(std::path::Path::new("."));
        m2rc_stdlib::import::nav2::params::parse_map_yaml(&t, "", dir)
            .ok()
            .map(|y| y.image)
    });
    for input in std::iter::once(&yaml)
        .chain(args.semantics.as_ref())
        .chain(image.as_ref())
    {
        if crate::io::is_dash(input) {
            return Err(crate::io::unusable(anyhow::anyhow!(
                "--from nav2 reads files (the YAML names its image beside it): standard input is not taken"
            )));
        }
        if !crate::io::is_dash(&args.output)
            && crate::outputs::resolved(input) == crate::outputs::resolved(&args.output)
        {
            return Err(crate::io::unusable(anyhow::anyhow!(
                "-o {} is an input; write the map elsewhere",
                args.output.display()
            )));
        }
    }
    let opts = Nav2Options {
        robot_radius_m: args.source.grid.robot_radius,
        max_memory_bytes: args.source.grid.max_memory,
        map_id: None,
    };
    let (doc, notes) = import_nav2(&yaml, args.semantics.as_deref(), &opts).map_err(|e| {
        crate::io::unusable(anyhow::Error::new(e).context("cannot import the Nav2 map"))
    })?;
    for n in notes {
        eprintln!("note: {n}");
    }
    if crate::io::is_dash(&args.output) {
        write_stdout(&doc)?;
    } else {
        write_streamed(&args.output, &doc)?;
    }
    let outside = outside_vocabulary(&doc.map);
    eprintln!(
        "wrote {} ({} x {} cells, {} rooms, {} objects, from a Nav2 map{})",
        if crate::io::is_dash(&args.output) {
            "the map to standard output".to_string()
        } else {
            args.output.display().to_string()
        },
        doc.map.n(),
        doc.map.n(),
        doc.map.rooms.len(),
        doc.map.objects.len(),
        if outside.is_empty() {
            String::new()
        } else {
            format!(
                "; categories outside the benchmark vocabulary, kept: {}",
                outside.join(", ")
            )
        }
    );
    Ok(ExitCode::SUCCESS)
}

/// Room and object categories the benchmark vocabulary does not have (kept: the language's
/// category names come from the map), sorted.
fn outside_vocabulary(map: &SemanticMap) -> Vec<String> {
    use m2rc_stdlib::map::vocab::{is_benchmark_object_category, is_room_category, is_structure};
    let mut out: Vec<String> = map
        .rooms
        .iter()
        .map(|r| r.category.as_str())
        .filter(|c| !is_room_category(c))
        .chain(
            map.objects
                .iter()
                .map(|o| o.category.as_str())
                .filter(|c| !is_benchmark_object_category(c) && !is_structure(c)),
        )
        .map(str::to_string)
        .collect();
    out.sort();
    out.dedup();
    out
}

/// Writes the map JSON to standard output, streamed like [`write_streamed`]; a closed pipe ends
/// the command quietly, as everywhere.
fn write_stdout(doc: &MapDocument) -> Result<()> {
    use std::io::Write;
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    write_map_document_to(doc, &mut out)
        .and_then(|()| out.flush())
        .map_err(|e| {
            // The serializer wraps the pipe's error; its kind is what says "closed pipe".
            let kind = e
                .get_ref()
                .and_then(|i| i.downcast_ref::<serde_json::Error>())
                .and_then(serde_json::Error::io_error_kind)
                .unwrap_or(e.kind());
            std::io::Error::new(kind, e.to_string())
        })
        .context("cannot write standard output")
}

/// Writes the map JSON straight into a temporary file beside `path`, then renames it into place:
/// atomic like every other write, and the text of a fine-resolution map (gigabytes) is never
/// held in memory.
fn write_streamed(path: &std::path::Path, doc: &MapDocument) -> Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => std::path::Path::new("."),
    };
    std::fs::create_dir_all(dir)
        .with_context(|| format!("cannot create directory {}", dir.display()))?;
    let name = path
        .file_name()
        .with_context(|| format!("{} is not a file path", path.display()))?
        .to_string_lossy();
    let tmp = dir.join(format!(".{name}.tmp{}", std::process::id()));
    let result = (|| -> Result<()> {
        let f = std::fs::File::create(&tmp)
            .with_context(|| format!("cannot create {}", tmp.display()))?;
        write_map_document_to(doc, &f)
            .with_context(|| format!("cannot write {}", tmp.display()))?;
        f.sync_all().ok();
        std::fs::rename(&tmp, path).with_context(|| format!("cannot write {}", path.display()))
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

fn kind_name(kind: SourceKind) -> &'static str {
    match kind {
        SourceKind::Demo => "the built-in demo",
        SourceKind::ProcthorHouse => "a ProcTHOR house",
        SourceKind::Map2RouteMap => "a Map2Route map",
    }
}

fn info(args: InfoArgs) -> Result<ExitCode> {
    let (doc, _) = load(&args.source)?;
    let map = &doc.map;
    match args.format {
        InfoFormat::Json => {
            let text = serde_json::to_string_pretty(&info_json(map))
                .context("cannot format the summary")?;
            println!("{text}");
        }
        InfoFormat::Text => print!("{}", info_text(map)),
    }
    Ok(ExitCode::SUCCESS)
}

fn free_cells(map: &SemanticMap) -> usize {
    map.occupancy
        .data()
        .iter()
        .filter(|&&v| v == m2rc_stdlib::map::FREE)
        .count()
}

/// Rooms no traversable path from the start reaches, by id (empty when the map has no start).
fn unreachable_rooms(map: &SemanticMap) -> Vec<u32> {
    let Some(start) = map.start else {
        return Vec::new();
    };
    let reached = rooms_reachable_from(map, start);
    map.rooms
        .iter()
        .map(|r| r.id)
        .filter(|id| !reached.contains(id))
        .collect()
}

/// Open-plan areas of more than one room, each sorted, in order of their first room.
fn open_areas(map: &SemanticMap) -> Vec<Vec<u32>> {
    let mut out: Vec<Vec<u32>> = Vec::new();
    for r in &map.rooms {
        let area = open_area(map, r.id);
        if area.len() > 1 && !out.contains(&area) {
            out.push(area);
        }
    }
    out
}

pub(crate) fn info_json(map: &SemanticMap) -> serde_json::Value {
    let adjacency = map.room_adjacency();
    let links = map.room_links();
    json!({
        "map_id": map.map_id,
        "grid_size": map.n(),
        "resolution_m": map.resolution(),
        "extent_m": map.n() as f64 * map.resolution(),
        "free_cells": free_cells(map),
        "start": map.start.map(|c| [c.row, c.col]),
        "rooms": map.rooms.iter().map(|r| json!({
            "id": r.id, "category": r.category, "name": r.name, "area_m2": r.area_m2,
            "objects": map.objects_in_room(r.id).count(),
            "neighbours": map.neighbours(r.id),
        })).collect::<Vec<_>>(),
        "object_count": map.objects.len(),
        "categories": map.category_counts(),
        "outside_vocabulary": outside_vocabulary(map),
        "adjacency": adjacency.iter().map(|(a, b)| [a, b]).collect::<Vec<_>>(),
        "links": links.iter().map(|(a, b, k)| json!({"rooms": [a, b], "kind": k.name()})).collect::<Vec<_>>(),
        "open_areas": open_areas(map),
        "reachable_from_start": map.start.map(|_| map.rooms.len() - unreachable_rooms(map).len()),
        "unreachable_from_start": unreachable_rooms(map),
    })
}

fn info_text(map: &SemanticMap) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let n = map.n();
    let res = map.resolution();
    let _ = writeln!(s, "map {}", map.map_id);
    let _ = writeln!(
        s,
        "grid {n} x {n} cells at {res} m ({:.2} x {:.2} m), {} free cells",
        n as f64 * res,
        n as f64 * res,
        free_cells(map)
    );
    if let Some(c) = map.start {
        let _ = writeln!(s, "start [{}, {}]", c.row, c.col);
    }
    let _ = writeln!(s, "rooms {}", map.rooms.len());
    for r in &map.rooms {
        let _ = writeln!(
            s,
            "  {:>3}  {:<14} {:<16} {:>8.2} m2  {:>3} objects",
            r.id,
            r.category,
            r.name,
            r.area_m2,
            map.objects_in_room(r.id).count()
        );
    }
    let counts = map.category_counts();
    let _ = writeln!(
        s,
        "objects {} in {} categories",
        map.objects.len(),
        counts.len()
    );
    let mut sorted: Vec<(&str, usize)> = counts.into_iter().collect();
    sorted.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
    for chunk in sorted.chunks(4) {
        let line: Vec<String> = chunk.iter().map(|(c, k)| format!("{c} {k}")).collect();
        let _ = writeln!(s, "  {}", line.join(", "));
    }
    let outside = outside_vocabulary(map);
    if !outside.is_empty() {
        let _ = writeln!(
            s,
            "outside the benchmark vocabulary: {}",
            outside.join(", ")
        );
    }
    let name = |id: u32| {
        map.room(id)
            .map_or_else(|| id.to_string(), |r| r.name.clone())
    };
    let links = map.room_links();
    let _ = writeln!(s, "adjacency {}", links.len());
    for (a, b, kind) in links {
        let _ = writeln!(s, "  {} - {}  {}", name(a), name(b), kind.name());
    }
    for area in open_areas(map) {
        let names: Vec<String> = area.iter().map(|&r| name(r)).collect();
        let _ = writeln!(s, "open area {}", names.join(" + "));
    }
    if map.start.is_some() {
        let unreachable = unreachable_rooms(map);
        let _ = writeln!(
            s,
            "reachable from the start: {} of {} rooms",
            map.rooms.len() - unreachable.len(),
            map.rooms.len()
        );
        if !unreachable.is_empty() {
            let names: Vec<String> = unreachable.iter().map(|&r| name(r)).collect();
            let _ = writeln!(s, "  unreachable: {}", names.join(", "));
        }
    }
    s
}

fn render(args: RenderArgs) -> Result<ExitCode> {
    if args.output.is_none() && args.svg.is_none() {
        bail!("nothing to write: pass -o out.png and/or --svg out.svg");
    }
    let (doc, _) = load(&args.source)?;
    let opts = RenderOptions {
        labels: args.labels,
        ..RenderOptions::default()
    };
    let out = render_map(&doc.map, &opts)?;
    if let Some(p) = &args.output {
        write_atomic(p, &out.png)?;
        eprintln!("wrote {}", p.display());
    }
    if let Some(p) = &args.svg {
        write_atomic(p, out.svg.as_bytes())?;
        eprintln!("wrote {}", p.display());
    }
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn info_summarises_the_demo() {
        let map = m2rc_stdlib::demo::demo_map().unwrap();
        let v = info_json(&map);
        assert_eq!(v["grid_size"], json!(map.n()));
        assert_eq!(v["rooms"].as_array().unwrap().len(), 7);
        assert_eq!(v["adjacency"].as_array().unwrap().len(), 6);
        assert_eq!(v["categories"]["window"], json!(6));
        let text = info_text(&map);
        assert!(text.contains("rooms 7\n"), "{text}");
        assert!(
            text.contains("  living_room_1 - kitchen_1  door\n"),
            "{text}"
        );
        assert!(
            text.contains("reachable from the start: 7 of 7 rooms\n"),
            "{text}"
        );
        assert_eq!(v["unreachable_from_start"], json!([]));
    }
}
