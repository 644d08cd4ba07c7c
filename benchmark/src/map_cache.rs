//! The prepared-map cache: the second process to load a Map2Route map file reads its prepared
//! form (`m2rc_stdlib::map::prepared`), with the map's obstacle distance field, instead of parsing
//! the JSON and computing the field, which is most of what `compile`, `run`, `eval` and each map
//! of `bench run` spend on a suite map. An entry is keyed by the map file's canonical path and
//! checked against the file; a stale, corrupt or other-version entry is rebuilt with a warning,
//! never used.
//!
//! Checking an entry against the file's bytes means reading and checksumming 12-20 MB, a large
//! part of a cached start. So the entry also records the file's identity when it was made (device,
//! inode, length, modification and status-change times) and a CRC of 16 sampled 4 KiB blocks; when
//! all of them still match, the bytes are not read. The status-change time (ctime) is set by the
//! kernel on every write, rename onto the path or `touch`, and no program can set it back, so a
//! rewritten file does not match. The one gap is a change within the file system's timestamp
//! granularity of the moment the identity was taken: as git does with "racily clean" index
//! entries, an identity whose times are less than [`RACY_SECONDS`] older than the moment it was
//! recorded is never trusted, and such a file is checked by its full CRC. What remains is a file
//! changed while the clock was set back, or on a file system that keeps no ctime; docs/maps.md
//! says so.

use m2rc_planner::context::{MapContext, OBSTACLE_FIELD_TAG};
use m2rc_stdlib::map::MapDocument;
use m2rc_stdlib::map::prepared::{
    FieldRef, PreparedError, PreparedReader, Source, encode_prepared,
};
use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

/// `off` (or `0`, or empty) turns the cache off; an absolute path puts it there.
pub const ENV: &str = "M2RC_MAP_CACHE";

/// Times closer than this to the moment an identity was recorded make it untrusted.
pub const RACY_SECONDS: i64 = 3;

/// The cache directory: `$M2RC_MAP_CACHE` when set, else `$XDG_CACHE_HOME/m2rc/map-cache`, else
/// `$HOME/.cache/m2rc/map-cache` (the run cache's rule); none when neither variable is set, so
/// that running in a checkout never leaves a directory behind in it.
pub fn dir_from_env() -> Option<PathBuf> {
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

static FOR_RUNS: OnceLock<PathBuf> = OnceLock::new();

/// Makes `bench run` (the runner's map loading) use the cache in `dir`; off until called, so a
/// library user or a test never writes a cache it did not ask for.
pub fn enable_for_runs(dir: PathBuf) {
    let _ = FOR_RUNS.set(dir);
}

/// The directory [`enable_for_runs`] set.
pub fn dir_for_runs() -> Option<&'static Path> {
    FOR_RUNS.get().map(PathBuf::as_path)
}

/// A map read through the cache.
pub struct Loaded {
    pub doc: MapDocument,
    /// Squared distances to the nearest obstacle by the planner's rule
    /// ([`m2rc_planner::context::MapFields::obstacle_sq`]), when known.
    pub obstacle_sq: Option<Arc<Vec<u32>>>,
    /// Whether the entry was matched to the file by its identity, without reading the file.
    pub by_identity: bool,
}

/// One map file's cache entry.
pub struct Entry {
    file: PathBuf,
    path: PathBuf,
    label: String,
    /// The file's identity when the entry was opened (empty where there is none to take).
    stamp: Vec<u8>,
    source: Option<Vec<u8>>,
}

impl Entry {
    /// The entry in `dir` for the regular file `file` (`label` names it in warnings).
    pub fn open(dir: &Path, file: &Path, label: &str) -> Option<Entry> {
        if !file.is_file() {
            return None;
        }
        let canonical = std::fs::canonicalize(file).ok()?;
        let stem = canonical.file_stem()?.to_string_lossy().to_string();
        let key = crc32fast::hash(canonical.as_os_str().as_encoded_bytes());
        Some(Entry {
            stamp: stamp_of(file).unwrap_or_default(),
            file: file.to_path_buf(),
            path: dir.join(format!("{stem}-{key:08x}.m2rmap")),
            label: label.to_string(),
            source: None,
        })
    }

    fn source(&mut self) -> Option<&[u8]> {
        if self.source.is_none() {
            self.source = Some(std::fs::read(&self.file).ok()?);
        }
        self.source.as_deref()
    }

    fn warn(&self, what: &str) {
        eprintln!(
            "warning: {}: prepared map {} {what}",
            self.label,
            self.path.display()
        );
    }

    /// The prepared map, when a usable one is cached.
    pub fn get(&mut self) -> Option<Loaded> {
        // A regular file only: opening a FIFO someone left at the entry's path would block.
        if !self.path.is_file() {
            return None;
        }
        let file = std::fs::File::open(&self.path).ok()?;
        let len = file.metadata().ok()?.len();
        let input = std::io::BufReader::with_capacity(1 << 16, file);
        let decoded = match PreparedReader::open(input, len) {
            Ok(reader) => {
                let vouched = trusted(&reader.header().stamp, &self.stamp);
                let label = self.label.clone();
                if vouched {
                    reader.decode(Source::Vouched, &label)
                } else {
                    let source = self.source()?;
                    reader.decode(Source::Bytes(source), &label)
                }
                .map(|p| (p, vouched))
            }
            Err(e) => Err(e),
        };
        match decoded {
            Ok((p, vouched)) => {
                let obstacle_sq = p
                    .obstacle_sq
                    .filter(|(tag, _)| *tag == OBSTACLE_FIELD_TAG)
                    .map(|(_, sq)| Arc::new(sq));
                let loaded = Loaded {
                    doc: p.doc,
                    obstacle_sq,
                    by_identity: vouched,
                };
                if !vouched && trusted(&self.stamp, &self.stamp) {
                    // Same bytes, new identity (copied, touched): record it for the next load.
                    self.write(
                        &loaded.doc,
                        loaded.obstacle_sq.as_deref().map(Vec::as_slice),
                    );
                }
                Some(loaded)
            }
            Err(e) => {
                self.warn(&match e {
                    PreparedError::Stale => "is stale; rebuilding it".to_string(),
                    e => format!("cannot be used ({e}); rebuilding it"),
                });
                None
            }
        }
    }

    /// Stores `doc`, read from this entry's file, with its obstacle field (computed here), which
    /// is returned for the caller to use. Nothing is stored when the file changed since the
    /// entry was opened (the document may be of either version); a cache that cannot be written
    /// is only warned.
    pub fn put(&mut self, doc: &MapDocument) -> Option<Arc<Vec<u32>>> {
        let field = MapContext::new(&doc.map)
            .ok()
            .map(|c| c.fields().obstacle_sq());
        self.source()?;
        if !same_file(&stamp_of(&self.file).unwrap_or_default(), &self.stamp) {
            return field;
        }
        self.write(doc, field.as_deref().map(Vec::as_slice));
        field
    }

    fn write(&mut self, doc: &MapDocument, field: Option<&[u32]>) {
        if self.source().is_none() {
            return;
        }
        let source = self.source.as_deref().unwrap_or_default();
        let field = field.map(|squared| FieldRef {
            tag: OBSTACLE_FIELD_TAG,
            squared,
        });
        let bytes = encode_prepared(doc, source, &self.stamp, field);
        if let Err(e) = crate::atomic::write_atomic(&self.path, &bytes) {
            self.warn(&format!("cannot be written: {e}"));
        }
    }
}

/// Loads the Map2Route map file `file` through the cache in `dir`, parsing it with `parse` on a
/// miss (`dir` none: always parsed, no field).
pub fn load_map_file<E>(
    dir: Option<&Path>,
    file: &Path,
    parse: impl FnOnce(&[u8]) -> Result<MapDocument, E>,
    unreadable: impl FnOnce(std::io::Error) -> E,
) -> Result<Loaded, E> {
    let label = file.display().to_string();
    let mut entry = dir.and_then(|d| Entry::open(d, file, &label));
    if let Some(hit) = entry.as_mut().and_then(Entry::get) {
        return Ok(hit);
    }
    let doc = match entry.as_mut().and_then(|e| e.source.take()) {
        Some(bytes) => {
            let doc = parse(&bytes)?;
            if let Some(e) = entry.as_mut() {
                e.source = Some(bytes);
            }
            doc
        }
        None => parse(&std::fs::read(file).map_err(unreadable)?)?,
    };
    let obstacle_sq = entry.as_mut().and_then(|e| e.put(&doc));
    Ok(Loaded {
        doc,
        obstacle_sq,
        by_identity: false,
    })
}

/// The identity of `file` now: device, inode, length, mtime and ctime (seconds and nanoseconds),
/// the moment it was taken, and a CRC of 16 sampled blocks. None off Unix (entries are then
/// checked by the full CRC).
#[cfg(unix)]
fn stamp_of(file: &Path) -> Option<Vec<u8>> {
    use std::os::unix::fs::{FileExt, MetadataExt};
    let now = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .ok()?;
    let f = std::fs::File::open(file).ok()?;
    let m = f.metadata().ok()?;
    let mut out = Vec::with_capacity(76);
    for v in [m.dev(), m.ino(), m.len()] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    for (s, ns) in [
        (m.mtime(), m.mtime_nsec()),
        (m.ctime(), m.ctime_nsec()),
        (now.as_secs() as i64, i64::from(now.subsec_nanos())),
    ] {
        out.extend_from_slice(&s.to_le_bytes());
        out.extend_from_slice(&ns.to_le_bytes());
    }
    const BLOCK: u64 = 4096;
    let mut sample = crc32fast::Hasher::new();
    let mut buf = vec![0u8; BLOCK as usize];
    let span = m.len().saturating_sub(BLOCK);
    for i in 0..16u64 {
        let at = span * i / 15;
        let got = f.read_at(&mut buf, at).ok()?;
        sample.update(&buf[..got]);
    }
    out.extend_from_slice(&sample.finalize().to_le_bytes());
    Some(out)
}

#[cfg(not(unix))]
fn stamp_of(_file: &Path) -> Option<Vec<u8>> {
    None
}

/// Whether two identities are of the same file in the same state (all but the moment taken).
fn same_file(a: &[u8], b: &[u8]) -> bool {
    a.len() == b.len() && (a.len() != 76 || (a[..56] == b[..56] && a[72..] == b[72..]))
}

/// Whether the `recorded` identity vouches for a file whose identity is now `current`: both
/// present, equal but for the moment taken, and recorded at least [`RACY_SECONDS`] after the
/// file's last modification and status change.
fn trusted(recorded: &[u8], current: &[u8]) -> bool {
    const TIMES: usize = 24;
    if recorded.len() != 76 || current.len() != 76 {
        return false;
    }
    let same = same_file(recorded, current);
    let secs = |at: usize| i64::from_le_bytes(recorded[at..at + 8].try_into().unwrap_or([0; 8]));
    let (mtime, ctime, made) = (secs(TIMES), secs(TIMES + 16), secs(TIMES + 32));
    same && mtime.max(ctime) + RACY_SECONDS <= made
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fresh_file_is_racy_and_an_older_one_is_trusted() {
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("m.json");
        std::fs::write(&f, vec![b'x'; 100_000]).unwrap();
        let now = stamp_of(&f).unwrap();
        assert_eq!(now.len(), 76);
        assert!(!trusted(&now, &now), "just written: racy");
        // The same identity, recorded RACY_SECONDS later, is trusted.
        let mut later = now.clone();
        let made = i64::from_le_bytes(later[56..64].try_into().unwrap()) + RACY_SECONDS + 1;
        later[56..64].copy_from_slice(&made.to_le_bytes());
        assert!(trusted(&later, &now));
        // Any other length, inode, time or sampled content is not.
        for at in [0, 8, 16, 24, 32, 40, 48, 72] {
            let mut other = now.clone();
            other[at] ^= 1;
            assert!(!trusted(&later, &other), "byte {at}");
        }
        assert!(!trusted(&later, &[]));
    }

    #[test]
    fn rewriting_a_file_changes_its_identity() {
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("m.json");
        std::fs::write(&f, vec![b'x'; 10_000]).unwrap();
        let before = stamp_of(&f).unwrap();
        std::thread::sleep(std::time::Duration::from_millis(50));
        // Same length, same first and last blocks: only the times tell.
        let mut bytes = vec![b'x'; 10_000];
        bytes[5000] = b'y';
        std::fs::write(&f, &bytes).unwrap();
        let after = stamp_of(&f).unwrap();
        assert_ne!(before[24..56], after[24..56]);
        assert!(!same_file(&before, &after));
        assert!(same_file(&after, &stamp_of(&f).unwrap()), "unchanged: same");
    }

    fn demo() -> MapDocument {
        m2rc_stdlib::demo::demo_document(&Default::default()).unwrap()
    }

    #[test]
    fn the_planner_and_the_evaluator_take_a_field_only_when_it_is_this_maps() {
        let doc = demo();
        let sq = MapContext::new(&doc.map).unwrap().fields().obstacle_sq();
        let fresh = MapContext::new(&doc.map).unwrap();
        assert!(fresh.fields().seed_obstacle_sq(sq.clone()));
        assert_eq!(fresh.fields().obstacle_sq(), sq);

        let computed = crate::metrics::map::EvalMap::from_semantic_map(&doc.map);
        let seeded = crate::metrics::map::EvalMap::from_semantic_map(&doc.map);
        assert!(seeded.seed_clearance_sq(&sq));
        assert_eq!(seeded.clearance_field(), computed.clearance_field());

        // One obstacle cell less: another map's field, refused by both.
        let mut other = (*sq).clone();
        let at = other.iter().position(|&d| d == 0).unwrap();
        other[at] = 1;
        let fresh = MapContext::new(&doc.map).unwrap();
        assert!(!fresh.fields().seed_obstacle_sq(Arc::new(other.clone())));
        assert_eq!(fresh.fields().obstacle_sq(), sq, "computed instead");
        let eval = crate::metrics::map::EvalMap::from_semantic_map(&doc.map);
        assert!(!eval.seed_clearance_sq(&Arc::new(other)));
        assert_eq!(eval.clearance_field(), computed.clearance_field());
    }

    /// Something other than a file at an entry's path (here a FIFO, whose opening would block)
    /// is passed over: the map is parsed, and the FIFO left alone (an atomic write never replaces
    /// what is not a file; it only warns).
    #[cfg(unix)]
    #[test]
    fn a_fifo_at_the_entry_path_is_passed_over() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("demo.json");
        std::fs::write(&file, m2rc_stdlib::map::write_map_document_json(&demo())).unwrap();
        let cache = dir.path().join("cache");
        let parse = |b: &[u8]| m2rc_stdlib::map::read_map_document_json(b, "demo.json");
        load_map_file(Some(&cache), &file, parse, |e| panic!("{e}")).unwrap();
        let entry = std::fs::read_dir(&cache)
            .unwrap()
            .next()
            .unwrap()
            .unwrap()
            .path();
        std::fs::remove_file(&entry).unwrap();
        let made = std::process::Command::new("mkfifo").arg(&entry).status();
        if !made.is_ok_and(|s| s.success()) {
            return; // no mkfifo on this system
        }
        let again = load_map_file(Some(&cache), &file, parse, |e| panic!("{e}")).unwrap();
        assert_eq!(again.doc, demo_read(&file));
        assert!(
            !entry.is_file() && entry.exists(),
            "the FIFO is left as it was"
        );
    }

    fn demo_read(file: &Path) -> MapDocument {
        let bytes = std::fs::read(file).unwrap();
        m2rc_stdlib::map::read_map_document_json(&bytes, "demo.json").unwrap()
    }

    #[test]
    fn a_second_load_hits_with_the_same_map_and_field() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("demo.json");
        std::fs::write(&file, m2rc_stdlib::map::write_map_document_json(&demo())).unwrap();
        let cache = dir.path().join("cache");
        let parse = |b: &[u8]| m2rc_stdlib::map::read_map_document_json(b, "demo.json");
        let miss = load_map_file(Some(&cache), &file, parse, |e| panic!("{e}")).unwrap();
        let hit = load_map_file(Some(&cache), &file, parse, |e| panic!("{e}")).unwrap();
        let off = load_map_file(None, &file, parse, |e| panic!("{e}")).unwrap();
        assert_eq!(hit.doc, off.doc);
        assert_eq!(miss.doc, off.doc);
        assert!(hit.obstacle_sq.is_some());
        assert_eq!(hit.obstacle_sq, miss.obstacle_sq);
        assert!(off.obstacle_sq.is_none());
        assert_eq!(std::fs::read_dir(&cache).unwrap().count(), 1);
    }
}
