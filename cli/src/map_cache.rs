//! The prepared-map cache: the second process to load a Map2Route map file reads its prepared
//! form (`m2rc_stdlib::map::prepared`) instead of parsing the JSON, which is most of what
//! `compile`, `run` and `eval` spend on a suite map. An entry is keyed by the map file's
//! canonical path and checked against the file's current bytes; a stale, corrupt or other-version
//! entry is rebuilt with a warning, never used.

use m2rc_stdlib::map::MapDocument;
use m2rc_stdlib::map::prepared::{PreparedError, decode_prepared, encode_prepared};
use std::path::{Path, PathBuf};

/// `off` (or `0`, or empty) turns the cache off; an absolute path puts it there.
pub const ENV: &str = "M2RC_MAP_CACHE";

/// `$M2RC_MAP_CACHE` when set, else `$XDG_CACHE_HOME/m2rc/map-cache`, else
/// `$HOME/.cache/m2rc/map-cache` (the run cache's rule); none when neither variable is set, so
/// that running in a checkout never leaves a directory behind in it.
fn cache_dir() -> Option<PathBuf> {
    let absolute = |name: &str| {
        std::env::var_os(name)
            .map(PathBuf::from)
            .filter(|p| p.is_absolute())
    };
    if let Some(v) = std::env::var_os(ENV) {
        return match v.to_str() {
            Some("off" | "0" | "") => None,
            _ => Some(PathBuf::from(v)),
        };
    }
    absolute("XDG_CACHE_HOME")
        .or_else(|| absolute("HOME").map(|h| h.join(".cache")))
        .map(|b| b.join("m2rc").join("map-cache"))
}

/// One map file's cache entry, with the file's bytes it is checked against.
pub struct Entry {
    path: PathBuf,
    source: Vec<u8>,
    label: String,
}

impl Entry {
    /// The entry for a map argument that is a regular file, when the cache is on.
    pub fn for_arg(arg: &str) -> Option<Entry> {
        let file = Path::new(arg);
        if arg == "-" || !file.is_file() {
            return None;
        }
        let dir = cache_dir()?;
        let canonical = std::fs::canonicalize(file).ok()?;
        let stem = canonical.file_stem()?.to_string_lossy().to_string();
        let key = crc32fast::hash(canonical.as_os_str().as_encoded_bytes());
        let source = std::fs::read(file).ok()?;
        Some(Entry {
            path: dir.join(format!("{stem}-{key:08x}.m2rmap")),
            source,
            label: arg.to_string(),
        })
    }

    /// The prepared map, when a usable one is cached.
    pub fn get(&self) -> Option<MapDocument> {
        let bytes = std::fs::read(&self.path).ok()?;
        match decode_prepared(&bytes, &self.source, &self.label) {
            Ok(doc) => Some(doc),
            Err(e) => {
                let why = match e {
                    PreparedError::Stale => "is stale".to_string(),
                    e => format!("cannot be used ({e})"),
                };
                eprintln!(
                    "warning: {}: prepared map {} {why}; rebuilding it",
                    self.label,
                    self.path.display()
                );
                None
            }
        }
    }

    /// Stores `doc`, read from this entry's source; a cache that cannot be written is only warned.
    pub fn put(&self, doc: &MapDocument) {
        let bytes = encode_prepared(doc, &self.source);
        if let Err(e) = m2rc_benchmark::atomic::write_atomic(&self.path, &bytes) {
            eprintln!(
                "warning: {}: cannot write prepared map {}: {e}",
                self.label,
                self.path.display()
            );
        }
    }
}
