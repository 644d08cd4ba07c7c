//! `m2rc map check`: import ProcTHOR houses (or read maps already made from them) and check each
//! map against its house: door and window holes where ProcTHOR cuts them, every room the house
//! connects reachable from the start, no way between rooms the house keeps apart.

use super::map::GridArgs;
use crate::io::unusable;
use anyhow::{Context, Result};
use clap::Args;
use m2rc_stdlib::import::check::{ImportCheck, check_house};
use m2rc_stdlib::import::house::looks_like_house;
use m2rc_stdlib::load::{LoadOptions, count_documents, load_map_with, read_document};
use m2rc_stdlib::map::read_map_document_json;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub struct CheckArgs {
    /// The ProcTHOR houses: a house .json, a .jsonl/.jsonl.gz of houses (every one, or one with
    /// --index or `file#i`), or `-` (one house JSON on standard input). Not a Map2Route map or
    /// `demo`: the check compares a map with the house it was made from.
    #[arg(value_name = "HOUSES")]
    pub house: String,
    #[command(flatten)]
    pub grid: GridArgs,
    /// Check these maps instead of importing: a map JSON (one house), or a directory holding
    /// `<stem>_<index:03>.json` per house of a .jsonl(.gz) (as `m2rc map import` names them).
    #[arg(long)]
    pub maps: Option<PathBuf>,
    /// Print only the totals.
    #[arg(long)]
    pub quiet: bool,
}

/// Refuses what is not a house file before anything is imported, then checks.
pub fn run(a: CheckArgs) -> Result<ExitCode> {
    if a.house == "demo" {
        return Err(unusable(anyhow::anyhow!(
            "`demo` is the built-in demo map, not a ProcTHOR house: `map check` compares a map \
             with the house it was made from; pass a house file (.json, or .jsonl/.jsonl.gz of \
             houses)"
        )));
    }
    let staged = crate::io::MapArg::new(&a.house)?;
    let db = crate::io::asset_db_for(&a.house, a.grid.assets.as_deref())?;
    if db.is_none() && a.maps.is_none() {
        eprintln!("warning: {}", crate::io::NO_ASSETS_WARNING);
    }
    let opts = super::map::load_options(&a.grid, db.as_ref());
    check(&a, &staged.arg, &opts)
}

#[derive(Default)]
struct Totals {
    houses: usize,
    holes: usize,
    misplaced: usize,
    misplaced_houses: usize,
    connected: usize,
    unreachable: usize,
    unreachable_houses: usize,
    leaks: usize,
    leak_houses: usize,
}

impl Totals {
    fn add(&mut self, r: &ImportCheck) {
        self.houses += 1;
        self.holes += r.holes;
        self.misplaced += r.misplaced_holes.len();
        self.misplaced_houses += usize::from(!r.misplaced_holes.is_empty());
        self.connected += r.connected_rooms.len();
        self.unreachable += r.unreachable_rooms.len();
        self.unreachable_houses += usize::from(!r.unreachable_rooms.is_empty());
        self.leaks += r.leaks.len();
        self.leak_houses += usize::from(!r.leaks.is_empty());
    }
}

fn stem(path: &str) -> String {
    let name = std::path::Path::new(path)
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut s = name.as_str();
    for ext in [".gz", ".jsonl", ".json"] {
        s = s.strip_suffix(ext).unwrap_or(s);
    }
    s.to_string()
}

fn check(args: &CheckArgs, src: &str, opts: &LoadOptions<'_>) -> Result<ExitCode> {
    let (path, fixed) = match src.rsplit_once('#') {
        Some((p, i)) if i.parse::<usize>().is_ok() && !std::path::Path::new(src).exists() => {
            (p.to_string(), i.parse::<usize>().ok())
        }
        _ => (src.to_string(), args.grid.index),
    };
    let indices: Vec<Option<usize>> = match fixed {
        Some(i) => vec![Some(i)],
        None => {
            let n = count_documents(&path)?;
            let name = path.strip_suffix(".gz").unwrap_or(&path);
            if name.ends_with(".jsonl") {
                (0..n).map(Some).collect()
            } else {
                vec![None]
            }
        }
    };
    let mut totals = Totals::default();
    for index in indices {
        let (house, mut label, _) = read_document(&path, index)?;
        if crate::io::is_dash(std::path::Path::new(&args.house)) {
            label = "<stdin>".into();
        }
        if !looks_like_house(&house) {
            return Err(unusable(anyhow::anyhow!(
                "{label}: not a ProcTHOR house (a Map2Route map, or no `rooms`): `map check` \
                 compares a map with the house it was made from; pass the house, and the map with \
                 --maps"
            )));
        }
        let map = match (&args.maps, index) {
            (None, _) => {
                let mut o = opts.clone();
                o.index = index;
                load_map_with(&path, &o)?.0.map
            }
            (Some(m), i) => {
                let file = if m.is_dir() {
                    m.join(format!("{}_{:03}.json", stem(&path), i.unwrap_or(0)))
                } else {
                    m.clone()
                };
                let bytes = std::fs::read(&file)
                    .with_context(|| format!("cannot read {}", file.display()))?;
                read_map_document_json(&bytes, &file.display().to_string())?.map
            }
        };
        let r = check_house(&house, &label, &map)?;
        if !args.quiet {
            println!(
                "{label}: holes {} (misplaced {}), connected rooms {}, unreachable {}, leaks {}",
                r.holes,
                r.misplaced_holes.len(),
                r.connected_rooms.len(),
                r.unreachable_rooms.len(),
                r.leaks.len()
            );
            for (field, msg) in r.warnings(&map) {
                println!("  {field}: {msg}");
            }
        }
        totals.add(&r);
    }
    let t = &totals;
    println!(
        "houses {}: holes {}, misplaced {} (in {} houses); connected rooms {}, unreachable {} (in \
         {} houses); leaks {} (in {} houses)",
        t.houses,
        t.holes,
        t.misplaced,
        t.misplaced_houses,
        t.connected,
        t.unreachable,
        t.unreachable_houses,
        t.leaks,
        t.leak_houses
    );
    let clean = t.misplaced == 0 && t.unreachable == 0 && t.leaks == 0;
    Ok(if clean {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
