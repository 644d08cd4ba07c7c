//! File and terminal I/O shared by the subcommands.
//!
//! * Every write is atomic (temporary file in the same directory, then rename), writes through a
//!   symbolic link to its target file, and refuses a directory, device, pipe or socket (see
//!   `m2rc_benchmark::atomic`); the path `-` writes to standard output instead.
//! * The path `-` reads standard input wherever a file is read (once per command).
//! * Standard output closed early (`m2rc ... | head -1`) ends the command quietly with status 0.
//! * Exit status: 2 when an input cannot be used at all (unreadable, not JSON, not a map, a bad
//!   flag value), 1 when it was read and found wrong (diagnostics, a refused run, a mismatch).

use anyhow::{Context, Result};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};

/// Exit status of a command whose input cannot be used at all.
pub const EXIT_UNUSABLE: u8 = 2;
/// Exit status of a command whose input was read and found wrong.
pub const EXIT_WRONG: u8 = 1;

/// An error meaning "the input cannot be used at all" (exit status 2); it holds the message of
/// the error it replaced.
#[derive(Debug)]
pub struct Unusable(pub String);

impl std::fmt::Display for Unusable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Unusable {}

/// Turns `err` into an [`Unusable`] error, so that the command exits with status 2.
pub fn unusable(err: impl Into<anyhow::Error>) -> anyhow::Error {
    let err: anyhow::Error = err.into();
    if err.chain().any(|c| c.is::<Unusable>()) {
        return err;
    }
    let mut text = String::new();
    for cause in err.chain() {
        let t = cause.to_string();
        if t.is_empty() || text.contains(&t) {
            continue;
        }
        if !text.is_empty() {
            text.push_str(": ");
        }
        text.push_str(&t);
    }
    anyhow::Error::new(Unusable(text))
}

/// Whether `err` is standard output going away (a closed pipe).
pub fn is_broken_pipe(err: &anyhow::Error) -> bool {
    err.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|e| e.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// The exit status for a command that failed with `err`: 2 for unusable input (marked with
/// [`unusable`], or an input that could not be read or parsed), else 1.
pub fn exit_code(err: &anyhow::Error) -> ExitCode {
    let unusable = err.chain().any(|c| {
        c.is::<Unusable>()
            || c.is::<std::io::Error>()
            || c.is::<serde_json::Error>()
            || c.is::<m2rc_stdlib::map::MapError>()
            || c.is::<m2rc_benchmark::episode::EpisodeError>()
            || c.is::<m2rc_benchmark::route::RouteError>()
            || c.is::<m2rc_benchmark::suite::SuiteError>()
    });
    ExitCode::from(if unusable { EXIT_UNUSABLE } else { EXIT_WRONG })
}

/// Makes a panic from `print!`/`println!` on a closed standard output end the process quietly
/// (status 0), as `head` expects of the command before it; other panics are reported as usual.
pub fn quiet_broken_pipe() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let text = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if text.contains("failed printing to stdout") && text.contains("Broken pipe") {
            std::process::exit(0);
        }
        default(info);
    }));
}

/// Writes `bytes` to standard output and flushes; a closed pipe is an error that [`is_broken_pipe`]
/// recognizes (the command then exits quietly).
pub fn stdout_bytes(bytes: &[u8]) -> Result<()> {
    let mut out = std::io::stdout().lock();
    out.write_all(bytes)
        .and_then(|()| out.flush())
        .context("cannot write standard output")
}

/// [`stdout_bytes`] for text.
pub fn stdout(text: &str) -> Result<()> {
    stdout_bytes(text.as_bytes())
}

/// Whether a path argument means standard input or output.
pub fn is_dash(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// Writes `bytes` to `path` atomically, creating parent directories; `-` writes to standard
/// output. A symbolic link is written through; a directory or special file is refused.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    if is_dash(path) {
        return stdout_bytes(bytes);
    }
    // An output that cannot be written is not an unusable input: plain message, status 1.
    m2rc_benchmark::atomic::write_atomic(path, bytes)
        .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", path.display()))
}

static STDIN_TAKEN: AtomicBool = AtomicBool::new(false);

/// Reads all of standard input; a second read in the same command is refused (only one input
/// can be `-`).
pub fn read_stdin() -> Result<Vec<u8>> {
    if STDIN_TAKEN.swap(true, Ordering::SeqCst) {
        return Err(unusable(anyhow::anyhow!(
            "only one input can be `-` (standard input) per command"
        )));
    }
    let mut bytes = Vec::new();
    std::io::stdin()
        .read_to_end(&mut bytes)
        .context("cannot read standard input")?;
    Ok(bytes)
}

/// Reads a whole file (`-`: standard input), naming the file in the error.
pub fn read_bytes(path: &Path) -> Result<Vec<u8>> {
    if is_dash(path) {
        return read_stdin();
    }
    std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))
}

/// Reads a file (`-`: standard input) of at most `limit` bytes as UTF-8, naming the file in the
/// error. The size is checked while reading (one byte past the limit at most is read), so a huge
/// or endless input is refused before it takes memory; `what` names the limit in the message.
pub fn read_to_string_capped(path: &Path, limit: usize, what: &str) -> Result<String> {
    let name = display_name(path);
    let mut bytes = Vec::new();
    let read = if is_dash(path) {
        if STDIN_TAKEN.swap(true, Ordering::SeqCst) {
            return Err(unusable(anyhow::anyhow!(
                "only one input can be `-` (standard input) per command"
            )));
        }
        std::io::stdin()
            .lock()
            .take(limit as u64 + 1)
            .read_to_end(&mut bytes)
    } else {
        std::fs::File::open(path).and_then(|f| f.take(limit as u64 + 1).read_to_end(&mut bytes))
    };
    read.with_context(|| format!("cannot read {name}"))?;
    if bytes.len() > limit {
        return Err(anyhow::anyhow!(
            "{name}: more than {limit} bytes, the limit of {what}"
        ));
    }
    String::from_utf8(bytes).map_err(|_| unusable(anyhow::anyhow!("{name}: not UTF-8 text")))
}

/// Reads a whole file (`-`: standard input) as UTF-8, naming the file in the error.
pub fn read_to_string(path: &Path) -> Result<String> {
    let bytes = read_bytes(path)?;
    String::from_utf8(bytes)
        .map_err(|_| unusable(anyhow::anyhow!("{}: not UTF-8 text", display_name(path))))
}

/// How an input is named in messages: `<stdin>` for `-`.
pub fn display_name(path: &Path) -> String {
    if is_dash(path) {
        "<stdin>".into()
    } else {
        path.display().to_string()
    }
}

/// A map argument as the map loaders take it: `-` is copied from standard input to a temporary
/// file (removed when the guard drops), anything else is passed through.
pub struct MapArg {
    pub arg: String,
    temp: Option<PathBuf>,
}

impl MapArg {
    pub fn new(arg: &str) -> Result<MapArg> {
        if arg != "-" {
            return Ok(MapArg {
                arg: arg.to_string(),
                temp: None,
            });
        }
        let bytes = read_stdin()?;
        let path = std::env::temp_dir().join(format!("m2rc-stdin-{}.json", std::process::id()));
        std::fs::write(&path, &bytes)
            .with_context(|| format!("cannot stage standard input in {}", path.display()))?;
        Ok(MapArg {
            arg: path.to_string_lossy().into_owned(),
            temp: Some(path),
        })
    }

    /// Whether the map came from standard input (its file name then means nothing).
    pub fn is_stdin(&self) -> bool {
        self.temp.is_some()
    }
}

impl Drop for MapArg {
    fn drop(&mut self) {
        if let Some(p) = &self.temp {
            let _ = std::fs::remove_file(p);
        }
    }
}

/// The asset database for a map argument: `explicit` when given, else
/// `assets/asset-database.json` beside the folder holding the house file (the layout of the
/// ProcTHOR data, and the rule `suite build` uses), else none. Without one, object sizes come from
/// a built-in table by category, which is much coarser (every bed the same size).
pub fn asset_db_for(
    map_arg: &str,
    explicit: Option<&Path>,
) -> Result<Option<m2rc_stdlib::import::AssetDb>> {
    let path = match explicit {
        Some(p) => Some(p.to_path_buf()),
        None => default_asset_path(map_arg),
    };
    match path {
        None => Ok(None),
        Some(p) => m2rc_stdlib::import::AssetDb::load(&p)
            .map(Some)
            .map_err(|e| unusable(anyhow::Error::new(e).context("cannot load the asset database"))),
    }
}

fn default_asset_path(map_arg: &str) -> Option<PathBuf> {
    if map_arg == "-" || map_arg == "demo" {
        return None;
    }
    // `file#i` names one house of a JSON-lines file.
    let file = match map_arg.rsplit_once('#') {
        Some((f, i)) if i.parse::<usize>().is_ok() => f,
        _ => map_arg,
    };
    let file = Path::new(file);
    if !file.is_file() {
        return None;
    }
    asset_path_beside(file)
}

/// `assets/asset-database.json` beside the folder of house files: the folder itself when `houses`
/// is one, else the folder holding the file.
pub fn asset_path_beside(houses: &Path) -> Option<PathBuf> {
    let folder = if houses.is_dir() {
        houses
    } else {
        houses.parent()?
    };
    let candidate = folder.parent()?.join("assets").join("asset-database.json");
    candidate.is_file().then_some(candidate)
}

/// What a house imported without an asset database is warned with.
pub const NO_ASSETS_WARNING: &str = "no asset database (none given with --assets, none beside \
     the houses folder): object sizes come from a built-in table by category";

/// The warning for a house imported without an asset database.
pub fn warn_without_assets(map_arg: &str, kind: m2rc_stdlib::load::SourceKind, had_db: bool) {
    if kind == m2rc_stdlib::load::SourceKind::ProcthorHouse && !had_db {
        eprintln!("warning: {map_arg}: {NO_ASSETS_WARNING}");
    }
}

/// Loads a map argument (a Map2Route map, a ProcTHOR house, `demo`, or `-`).
pub fn load_map(arg: &str) -> Result<m2rc_stdlib::map::SemanticMap> {
    load_map_kind(arg).map(|(m, _)| m)
}

/// [`load_map`], also saying what the argument was.
pub fn load_map_kind(
    arg: &str,
) -> Result<(m2rc_stdlib::map::SemanticMap, m2rc_stdlib::load::SourceKind)> {
    load_map_doc_kind(arg).map(|(d, k)| (d.map, k))
}

/// [`load_map_kind`] with the file's content the model has no field for (the map frame).
pub fn load_map_doc_kind(
    arg: &str,
) -> Result<(m2rc_stdlib::map::MapDocument, m2rc_stdlib::load::SourceKind)> {
    load_map_prepared(arg).map(|m| (m.doc, m.kind))
}

/// A map argument loaded through the prepared-map cache (`m2rc_benchmark::map_cache`).
pub struct LoadedMap {
    pub doc: m2rc_stdlib::map::MapDocument,
    pub kind: m2rc_stdlib::load::SourceKind,
    /// The planner's obstacle field, when the cache had it or computed it.
    pub obstacle_sq: Option<std::sync::Arc<Vec<u32>>>,
}

impl LoadedMap {
    /// The planner's context for this map, seeded with the cached obstacle field.
    pub fn planning(&self) -> Result<m2rc_planner::context::MapContext> {
        let ctx = m2rc_planner::context::MapContext::new(&self.doc.map)
            .map_err(|e| anyhow::anyhow!("the map cannot be planned on: {e}"))?;
        if let Some(sq) = &self.obstacle_sq {
            ctx.fields().seed_obstacle_sq(sq.clone());
        }
        Ok(ctx)
    }
}

/// [`load_map_doc_kind`], with the prepared-map cache's obstacle field (a Map2Route map file
/// only; houses, the demo and standard input are parsed every time).
pub fn load_map_prepared(arg: &str) -> Result<LoadedMap> {
    let staged = MapArg::new(arg)?;
    let file = Path::new(&staged.arg);
    let mut cache = (!staged.is_stdin() && arg != "demo")
        .then(m2rc_benchmark::map_cache::dir_from_env)
        .flatten()
        .and_then(|dir| m2rc_benchmark::map_cache::Entry::open(&dir, file, &staged.arg));
    crate::timings::mark("map: cache entry opened");
    if let Some(hit) = cache.as_mut().and_then(|c| c.get()) {
        crate::timings::mark(if hit.by_identity {
            "map: prepared map read (file identity matched)"
        } else {
            "map: prepared map read (source bytes checked)"
        });
        return Ok(LoadedMap {
            doc: hit.doc,
            kind: m2rc_stdlib::load::SourceKind::Map2RouteMap,
            obstacle_sq: hit.obstacle_sq,
        });
    }
    let db = asset_db_for(arg, None)?;
    let opts = m2rc_stdlib::load::LoadOptions {
        import: m2rc_stdlib::import::ImportOptions {
            map_id: staged.is_stdin().then(|| "stdin".to_string()),
            ..Default::default()
        },
        assets: db.as_ref(),
        ..Default::default()
    };
    let (doc, kind) = m2rc_stdlib::load::load_map_with(&staged.arg, &opts)
        .map_err(|e| unusable(anyhow::Error::new(e).context(format!("cannot load map `{arg}`"))))?;
    warn_without_assets(arg, kind, db.is_some());
    crate::timings::mark("map: parsed");
    let obstacle_sq = match cache.as_mut() {
        Some(c) if kind == m2rc_stdlib::load::SourceKind::Map2RouteMap => c.put(&doc),
        _ => None,
    };
    Ok(LoadedMap {
        doc,
        kind,
        obstacle_sq,
    })
}
