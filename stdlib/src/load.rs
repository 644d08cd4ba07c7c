//! One entry point for "a map argument": a Map2Route map JSON, a ProcTHOR house JSON (a file, or
//! one line of a `.jsonl` / `.jsonl.gz`), or the built-in `demo`. Files are told apart by
//! content, not by name, so a house saved as `map.json` still imports.

use crate::demo::{DEMO_NAME, demo_document};
use crate::import::house::looks_like_house;
use crate::import::{AssetDb, ImportOptions, import_house_document};
use crate::map::{MapDocument, MapError, SemanticMap, read_map_document};
use serde_json::Value;
use std::io::Read;
use std::path::Path;

/// How to load a map argument.
#[derive(Clone, Debug, Default)]
pub struct LoadOptions<'a> {
    /// Which house of a `.jsonl(.gz)` file (0-based line number); default 0.
    pub index: Option<usize>,
    /// Asset database for ProcTHOR houses; without one the built-in size table is used.
    pub assets: Option<&'a AssetDb>,
    pub import: ImportOptions,
}

/// What a document turned out to be.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SourceKind {
    Demo,
    ProcthorHouse,
    Map2RouteMap,
}

/// Loads `demo`, a map or a house with default options. `path#i` selects line `i` of a
/// `.jsonl(.gz)` file.
pub fn load_map(path_or_demo: &str) -> Result<SemanticMap, MapError> {
    load_map_with(path_or_demo, &LoadOptions::default()).map(|(d, _)| d.map)
}

/// Loads a map argument, keeping the file's extra content, and says what it was.
pub fn load_map_with(
    path_or_demo: &str,
    opts: &LoadOptions<'_>,
) -> Result<(MapDocument, SourceKind), MapError> {
    if path_or_demo == DEMO_NAME && !Path::new(DEMO_NAME).exists() {
        return Ok((demo_document(&opts.import)?, SourceKind::Demo));
    }
    let (path, index) = split_index(path_or_demo, opts.index);
    let (doc, label, line) = read_document(path, index)?;
    if doc.get("grid_size").is_some() && doc.get("layers").is_some() {
        return Ok((read_map_document(&doc, &label)?, SourceKind::Map2RouteMap));
    }
    if looks_like_house(&doc) {
        let mut import = opts.import.clone();
        if import.map_id.is_none() {
            let stem = file_stem(path);
            import.map_id = Some(match line {
                Some(i) => format!("{stem}_{i:03}"),
                None => stem,
            });
        }
        return Ok((
            import_house_document(&doc, &label, opts.assets, &import)?,
            SourceKind::ProcthorHouse,
        ));
    }
    Err(MapError::new(
        label,
        "",
        "neither a Map2Route map (no `grid_size` and `layers`) nor a ProcTHOR house (no `rooms`)",
    ))
}

/// `houses.jsonl.gz#7` -> (`houses.jsonl.gz`, Some(7)), when the suffix is a number and the
/// whole string is not itself a file.
fn split_index(arg: &str, index: Option<usize>) -> (&str, Option<usize>) {
    if let Some((p, i)) = arg.rsplit_once('#')
        && let Ok(i) = i.parse::<usize>()
        && !Path::new(arg).exists()
    {
        return (p, Some(index.unwrap_or(i)));
    }
    (arg, index)
}

fn file_stem(path: &str) -> String {
    let name = Path::new(path)
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut stem = name.as_str();
    for ext in [".gz", ".jsonl", ".json"] {
        stem = stem.strip_suffix(ext).unwrap_or(stem);
    }
    if stem.is_empty() {
        "map".into()
    } else {
        stem.to_string()
    }
}

/// Reads a JSON document from a file, un-gzipping by magic bytes and picking line `index` of a
/// JSON-lines file. Returns the document, the label errors should use, and the line read.
pub fn read_document(
    path: &str,
    index: Option<usize>,
) -> Result<(Value, String, Option<usize>), MapError> {
    let raw =
        std::fs::read(path).map_err(|e| MapError::new(path, "", format!("cannot read: {e}")))?;
    let bytes = if raw.starts_with(&[0x1f, 0x8b]) {
        let mut out = Vec::new();
        flate2::read::MultiGzDecoder::new(raw.as_slice())
            .read_to_end(&mut out)
            .map_err(|e| MapError::new(path, "", format!("cannot decompress: {e}")))?;
        out
    } else {
        raw
    };
    let name = path.strip_suffix(".gz").unwrap_or(path);
    let jsonl = name.ends_with(".jsonl") || (index.is_some() && !name.ends_with(".json"));
    if jsonl {
        let i = index.unwrap_or(0);
        let mut lines = bytes
            .split(|&b| b == b'\n')
            .filter(|l| !l.iter().all(u8::is_ascii_whitespace));
        let count_hint = || {
            bytes
                .split(|&b| b == b'\n')
                .filter(|l| !l.iter().all(u8::is_ascii_whitespace))
                .count()
        };
        let Some(line) = lines.nth(i) else {
            return Err(MapError::new(
                path,
                "",
                format!("has {} houses, index {i} is out of range", count_hint()),
            ));
        };
        let label = format!("{path}#{i}");
        let v = serde_json::from_slice(line)
            .map_err(|e| MapError::new(&label, "", format!("not valid JSON: {e}")))?;
        return Ok((v, label, Some(i)));
    }
    if let Some(i) = index.filter(|&i| i != 0) {
        return Err(MapError::new(
            path,
            "",
            format!("holds one document, index {i} is out of range"),
        ));
    }
    let v = serde_json::from_slice(&bytes)
        .map_err(|e| MapError::new(path, "", format!("not valid JSON: {e}")))?;
    Ok((v, path.to_string(), None))
}

/// Number of houses in a `.jsonl(.gz)` file (1 for a plain JSON file).
pub fn count_documents(path: &str) -> Result<usize, MapError> {
    let raw =
        std::fs::read(path).map_err(|e| MapError::new(path, "", format!("cannot read: {e}")))?;
    let bytes = if raw.starts_with(&[0x1f, 0x8b]) {
        let mut out = Vec::new();
        flate2::read::MultiGzDecoder::new(raw.as_slice())
            .read_to_end(&mut out)
            .map_err(|e| MapError::new(path, "", format!("cannot decompress: {e}")))?;
        out
    } else {
        raw
    };
    let name = path.strip_suffix(".gz").unwrap_or(path);
    if name.ends_with(".jsonl") {
        Ok(bytes
            .split(|&b| b == b'\n')
            .filter(|l| !l.iter().all(u8::is_ascii_whitespace))
            .count())
    } else {
        Ok(1)
    }
}
