//! `m2rc map check`: import ProcTHOR houses (or read maps already made from them) and check each
//! map against its house: door and window holes where ProcTHOR cuts them, every room the house
//! connects reachable from the start, no way between rooms the house keeps apart.

use super::map::SourceArgs;
use anyhow::{Context, Result, bail};
use clap::Args;
use m2rc_stdlib::import::check::{ImportCheck, check_house};
use m2rc_stdlib::load::{LoadOptions, count_documents, load_map_with, read_document};
use m2rc_stdlib::map::read_map_document_json;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub struct CheckArgs {
    #[command(flatten)]
    pub source: SourceArgs,
    /// Check these maps instead of importing: a map JSON (one house), or a directory holding
    /// `<stem>_<index:03>.json` per house of a .jsonl(.gz) (as `m2rc map import` names them).
    #[arg(long)]
    pub maps: Option<PathBuf>,
    /// Print only the totals.
    #[arg(long)]
    pub quiet: bool,
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

pub fn check(args: CheckArgs, opts: &LoadOptions<'_>) -> Result<ExitCode> {
    let src = &args.source.map;
    let (path, fixed) = match src.rsplit_once('#') {
        Some((p, i)) if i.parse::<usize>().is_ok() && !std::path::Path::new(src).exists() => {
            (p.to_string(), i.parse::<usize>().ok())
        }
        _ => (src.clone(), args.source.index),
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
        let (house, label, _) = read_document(&path, index)?;
        if house.get("rooms").is_none() {
            bail!("{label}: not a ProcTHOR house (no `rooms`); map check needs the house");
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
