//! Finding a suite's files from one of them, by the documented layout (`docs/benchmark.md`):
//!
//! ```text
//! <suite>/suite.json
//! <suite>/maps/<map_id>/<map_id>.json
//! <suite>/instructions/<map_id>/instruction_files/instruction_<id>.json
//! <suite>/programs/<map_id>/instruction_<id>.m2r
//! ```
//!
//! so that `m2rc compile programs/001_valunseen/instruction_000003.m2r` inside a suite compiles the
//! gold program as written (`// map: procthor/001_valunseen`) from the episode's start, and
//! `compile --episode instructions/.../instruction_000003.json` finds the episode's map.

use std::path::{Path, PathBuf};

/// The nearest folder at or above `from` holding `suite.json`.
pub fn suite_root(from: &Path) -> Option<PathBuf> {
    let start = std::fs::canonicalize(from).ok()?;
    let mut dir = if start.is_dir() {
        Some(start.as_path())
    } else {
        start.parent()
    };
    while let Some(d) = dir {
        if d.join("suite.json").is_file() {
            return Some(d.to_path_buf());
        }
        dir = d.parent();
    }
    None
}

/// The map file of `key` (`procthor/<map_id>` or `<map_id>`) in the suite above `from`.
pub fn map_for_key(from: &Path, key: &str) -> Option<PathBuf> {
    let id = key.rsplit('/').next()?;
    if id.is_empty() || id.contains(['\\', '.']) {
        return None;
    }
    let root = suite_root(from)?;
    let path = root.join("maps").join(id).join(format!("{id}.json"));
    path.is_file().then_some(path)
}

/// The episode of a gold program `<suite>/programs/<map_id>/<stem>.m2r`.
pub fn episode_for_program(program: &Path) -> Option<PathBuf> {
    let root = suite_root(program)?;
    let program = std::fs::canonicalize(program).ok()?;
    let rel = program.strip_prefix(&root).ok()?;
    let parts: Vec<_> = rel.components().collect();
    if parts.len() != 3 || parts[0].as_os_str() != "programs" {
        return None;
    }
    let map_id = parts[1].as_os_str();
    let stem = program.file_stem()?;
    let path = root
        .join("instructions")
        .join(map_id)
        .join("instruction_files")
        .join(stem)
        .with_extension("json");
    path.is_file().then_some(path)
}
