//! The prepared-map format: a map document in a compact binary form that loads without parsing
//! the map JSON. Almost all of a Map2Route file is its three `[row][col]` layers written as
//! decimal text (millions of numbers); here they are raw little-endian arrays, and only the small
//! rest (rooms, objects, metadata) stays JSON, read by the same reader as the source so that a
//! prepared map means exactly what its source means. It can also hold the map's obstacle distance
//! field, which the planner and the evaluator would otherwise compute at every start.
//!
//! Layout: magic `M2RCMAP\0`, format version (u32), the source's length (u64) and CRC-32 (u32),
//! the caller's stamp of the source file (u32 length, bytes: what lets a caller vouch for the
//! source without reading it), grid size n (u32), n² occupancy bytes, n² room ids and n² object
//! ids (u32 LE each), the obstacle field (u8 present; then its tag u32 and n² u32 squared
//! distances), the object footprints (u32 count; per object its id, its cell count and the cells
//! as row, col u32 pairs: hundreds of thousands of cells that would otherwise be most of the JSON
//! left to parse), the rest's JSON length (u64) and bytes, and a CRC-32 of everything before it. A
//! prepared map is only ever used for the source it was made from (its bytes, or a stamp the
//! caller matched); anything else is an error the caller turns into a rebuild, never a map.

use super::format::{Layers, read_map_document_layers};
use super::{MapDocument, write_map_document};
use crate::grid::{Cell, Grid};
use std::collections::BTreeMap;

/// Bumped whenever the layout or the meaning of a field changes.
pub const PREPARED_VERSION: u32 = 3;

const MAGIC: &[u8; 8] = b"M2RCMAP\0";

/// Why a prepared map cannot be used (the caller rebuilds it from the source).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PreparedError {
    #[error("not a prepared map (bad magic)")]
    NotPrepared,
    #[error("prepared-map format version {found}, this m2rc reads version {PREPARED_VERSION}")]
    Version { found: u32 },
    #[error("stale: made from other source bytes than the map file's current ones")]
    Stale,
    #[error("corrupt: {0}")]
    Corrupt(String),
}

/// A precomputed per-cell field stored with the map: squared distances (cells²) to the nearest
/// obstacle, row-major, under the tag of the rule that defined "obstacle" (a reader with another
/// rule ignores it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FieldRef<'a> {
    pub tag: u32,
    pub squared: &'a [u32],
}

/// A decoded prepared map.
#[derive(Debug, Clone, PartialEq)]
pub struct Prepared {
    pub doc: MapDocument,
    /// The obstacle field's tag and squared distances, when the entry holds one.
    pub obstacle_sq: Option<(u32, Vec<u32>)>,
}

/// What the prepared map is checked against.
#[derive(Debug, Clone, Copy)]
pub enum Source<'a> {
    /// The source's current bytes: their length and CRC-32 must be the recorded ones.
    Bytes(&'a [u8]),
    /// The caller matched the header's stamp against the source file and vouches for it.
    Vouched,
}

/// The fixed part of a prepared map, readable without checking the rest.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Header {
    pub source_len: u64,
    pub source_crc: u32,
    pub stamp: Vec<u8>,
}

/// Encodes `doc`, read from the map file whose bytes are `source`, with the caller's `stamp` of
/// that file and, optionally, its obstacle field.
pub fn encode_prepared(
    doc: &MapDocument,
    source: &[u8],
    stamp: &[u8],
    obstacle_sq: Option<FieldRef<'_>>,
) -> Vec<u8> {
    let map = &doc.map;
    let n = map.n();
    let mut rest = write_map_document(doc);
    if let Some(obj) = rest.as_object_mut() {
        obj.remove("layers");
        // Derived from the footprints on every write and never read back.
        obj.remove("cell_object_ids");
        // Written below in binary.
        obj.remove("object_footprints");
    }
    let rest = serde_json::to_vec(&rest).expect("a JSON value serialises");
    let field = obstacle_sq.filter(|f| f.squared.len() == n * n);
    let mut out = Vec::with_capacity(64 + stamp.len() + n * n * 13 + rest.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&PREPARED_VERSION.to_le_bytes());
    out.extend_from_slice(&(source.len() as u64).to_le_bytes());
    out.extend_from_slice(&crc32fast::hash(source).to_le_bytes());
    out.extend_from_slice(&(stamp.len() as u32).to_le_bytes());
    out.extend_from_slice(stamp);
    out.extend_from_slice(&(n as u32).to_le_bytes());
    out.extend_from_slice(map.occupancy.data());
    for layer in [&map.room_layer, &map.object_layer] {
        put_u32s(&mut out, layer.data());
    }
    match field {
        Some(f) => {
            out.push(1);
            out.extend_from_slice(&f.tag.to_le_bytes());
            put_u32s(&mut out, f.squared);
        }
        None => out.push(0),
    }
    out.extend_from_slice(&(map.objects.len() as u32).to_le_bytes());
    for o in &map.objects {
        out.extend_from_slice(&o.id.to_le_bytes());
        out.extend_from_slice(&(o.footprint.len() as u32).to_le_bytes());
        for c in &o.footprint {
            out.extend_from_slice(&c.row.to_le_bytes());
            out.extend_from_slice(&c.col.to_le_bytes());
        }
    }
    out.extend_from_slice(&(rest.len() as u64).to_le_bytes());
    out.extend_from_slice(&rest);
    let crc = crc32fast::hash(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

fn put_u32s(out: &mut Vec<u8>, values: &[u32]) {
    for v in values {
        out.extend_from_slice(&v.to_le_bytes());
    }
}

fn corrupt(what: &str) -> PreparedError {
    PreparedError::Corrupt(what.to_string())
}

/// Reads the header (magic, version, the source's length, CRC and stamp) without checking the
/// rest of the entry.
pub fn read_header(bytes: &[u8]) -> Result<Header, PreparedError> {
    PreparedReader::open(bytes, bytes.len() as u64).map(|r| r.header)
}

/// Decodes a prepared map made from `source`; `file` names the source in errors.
pub fn decode_prepared(
    bytes: &[u8],
    source: Source<'_>,
    file: &str,
) -> Result<Prepared, PreparedError> {
    PreparedReader::open(bytes, bytes.len() as u64)?.decode(source, file)
}

/// A prepared map being read from a stream (a cache file), its header read and the rest not
/// yet: the caller decides from the header how to check the source, then decodes. The layers
/// and the field are read straight into the map's own arrays, with no copy of the whole entry in
/// between (which was a third of a cached start on a suite map).
pub struct PreparedReader<R> {
    stream: Stream<R>,
    header: Header,
}

impl<R: std::io::Read> PreparedReader<R> {
    /// Reads the header of the `len`-byte entry `input`.
    pub fn open(input: R, len: u64) -> Result<Self, PreparedError> {
        let mut stream = Stream {
            input,
            crc: crc32fast::Hasher::new(),
            left: len.saturating_sub(4),
        };
        let mut magic = [0u8; 8];
        if len < 12 || stream.fill(&mut magic).is_none() || &magic != MAGIC {
            return Err(PreparedError::NotPrepared);
        }
        let truncated = || corrupt("truncated header");
        let version = stream.u32().ok_or_else(truncated)?;
        if version != PREPARED_VERSION {
            return Err(PreparedError::Version { found: version });
        }
        let source_len = stream.u64().ok_or_else(truncated)?;
        let source_crc = stream.u32().ok_or_else(truncated)?;
        let stamp_len = stream.u32().ok_or_else(truncated)?;
        let stamp = stream.bytes(stamp_len as usize).ok_or_else(truncated)?;
        let header = Header {
            source_len,
            source_crc,
            stamp,
        };
        Ok(PreparedReader { stream, header })
    }

    pub fn header(&self) -> &Header {
        &self.header
    }

    /// Decodes the rest, checked against `source` and the entry's own checksum.
    pub fn decode(self, source: Source<'_>, file: &str) -> Result<Prepared, PreparedError> {
        let PreparedReader { mut stream, header } = self;
        if let Source::Bytes(src) = source
            && (header.source_len != src.len() as u64 || header.source_crc != crc32fast::hash(src))
        {
            return Err(PreparedError::Stale);
        }
        let r = &mut stream;
        let n = r.u32().ok_or_else(|| corrupt("truncated header"))? as usize;
        if n as u64 > super::format::MAX_GRID_SIZE {
            return Err(corrupt("grid size larger than a map may be"));
        }
        let cells = n
            .checked_mul(n)
            .filter(|c| c.saturating_mul(9) as u64 <= r.left)
            .ok_or_else(|| corrupt("grid size larger than the file"))?;
        let occupancy = r.bytes(cells).ok_or_else(|| corrupt("truncated layers"))?;
        let occupancy = Grid::from_vec(n, occupancy).expect("n*n cells");
        let room = r.u32s(cells).ok_or_else(|| corrupt("truncated layers"))?;
        let object = r.u32s(cells).ok_or_else(|| corrupt("truncated layers"))?;
        let obstacle_sq = match r.u8().ok_or_else(|| corrupt("truncated field"))? {
            0 => None,
            1 => {
                let tag = r.u32().ok_or_else(|| corrupt("truncated field"))?;
                Some((
                    tag,
                    r.u32s(cells).ok_or_else(|| corrupt("truncated field"))?,
                ))
            }
            _ => return Err(corrupt("bad field marker")),
        };
        let objects = r.u32().ok_or_else(|| corrupt("truncated footprints"))?;
        let mut footprints = BTreeMap::new();
        for _ in 0..objects {
            let id = r.u32().ok_or_else(|| corrupt("truncated footprints"))?;
            let len = r.u32().ok_or_else(|| corrupt("truncated footprints"))? as usize;
            let raw = r
                .u32s(len.saturating_mul(2))
                .ok_or_else(|| corrupt("truncated footprints"))?;
            let cells = raw.chunks_exact(2).map(|p| Cell::new(p[0], p[1])).collect();
            if footprints.insert(id, cells).is_some() {
                return Err(corrupt("an object's footprint appears twice"));
            }
        }
        let rest_len = r.u64().ok_or_else(|| corrupt("truncated rest"))?;
        let rest = usize::try_from(rest_len)
            .ok()
            .and_then(|l| r.bytes(l))
            .ok_or_else(|| corrupt("truncated rest"))?;
        if r.left != 0 {
            return Err(corrupt("trailing bytes"));
        }
        let mut stored = [0u8; 4];
        r.input
            .read_exact(&mut stored)
            .map_err(|_| corrupt("truncated"))?;
        let extra = r
            .input
            .read(&mut [0u8; 1])
            .map_err(|_| corrupt("unreadable"))?;
        if extra != 0 {
            return Err(corrupt("longer than its length"));
        }
        if stream.crc.finalize() != u32::from_le_bytes(stored) {
            return Err(corrupt("checksum mismatch"));
        }
        let rest: serde_json::Value =
            serde_json::from_slice(&rest).map_err(|e| PreparedError::Corrupt(e.to_string()))?;
        let layers = Layers {
            occupancy,
            room: Grid::from_vec(n, room).expect("n*n cells"),
            object: Grid::from_vec(n, object).expect("n*n cells"),
            footprints: Some(footprints),
        };
        let doc = read_map_document_layers(&rest, file, Some(layers))
            .map_err(|e| PreparedError::Corrupt(e.to_string()))?;
        Ok(Prepared { doc, obstacle_sq })
    }
}

/// The entry's bytes in order, summed into its CRC as they are read; `left` counts the bytes
/// before the trailing CRC, so that no count read from the entry makes it allocate more than
/// the entry holds.
struct Stream<R> {
    input: R,
    crc: crc32fast::Hasher,
    left: u64,
}

impl<R: std::io::Read> Stream<R> {
    fn fill(&mut self, buf: &mut [u8]) -> Option<()> {
        let len = buf.len() as u64;
        if len > self.left {
            return None;
        }
        self.input.read_exact(buf).ok()?;
        self.crc.update(buf);
        self.left -= len;
        Some(())
    }
    fn u8(&mut self) -> Option<u8> {
        let mut b = [0u8; 1];
        self.fill(&mut b)?;
        Some(b[0])
    }
    fn u32(&mut self) -> Option<u32> {
        let mut b = [0u8; 4];
        self.fill(&mut b)?;
        Some(u32::from_le_bytes(b))
    }
    fn u64(&mut self) -> Option<u64> {
        let mut b = [0u8; 8];
        self.fill(&mut b)?;
        Some(u64::from_le_bytes(b))
    }
    fn bytes(&mut self, len: usize) -> Option<Vec<u8>> {
        if len as u64 > self.left {
            return None;
        }
        let mut out = vec![0u8; len];
        self.fill(&mut out)?;
        Some(out)
    }
    /// `count` little-endian u32s, read through a small buffer that stays in cache.
    fn u32s(&mut self, count: usize) -> Option<Vec<u32>> {
        let total = count.checked_mul(4)?;
        if total as u64 > self.left {
            return None;
        }
        let mut out = Vec::with_capacity(count);
        let mut buf = [0u8; 1 << 16];
        let mut rest = total;
        while rest > 0 {
            let chunk = &mut buf[..rest.min(1 << 16)];
            self.fill(chunk)?;
            out.extend(
                chunk
                    .chunks_exact(4)
                    .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])),
            );
            rest -= chunk.len();
        }
        Some(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::{read_map_document_json, write_map_document_json};

    /// The demo house as a Map2Route file: the source bytes and the document read from them.
    fn source() -> (Vec<u8>, MapDocument) {
        let doc = crate::demo::demo_document(&Default::default()).unwrap();
        let bytes = write_map_document_json(&doc);
        let read = read_map_document_json(&bytes, "demo.json").unwrap();
        (bytes, read)
    }

    fn encode(doc: &MapDocument, src: &[u8]) -> Vec<u8> {
        encode_prepared(doc, src, b"stamp", None)
    }

    fn decode(bytes: &[u8], src: &[u8]) -> Result<MapDocument, PreparedError> {
        decode_prepared(bytes, Source::Bytes(src), "demo.json").map(|p| p.doc)
    }

    #[test]
    fn a_prepared_map_is_the_map_its_source_reads_as() {
        let (src, doc) = source();
        let prepared = encode(&doc, &src);
        assert!(
            prepared.len() < src.len(),
            "{} vs {}",
            prepared.len(),
            src.len()
        );
        assert_eq!(decode(&prepared, &src).unwrap(), doc);
        assert_eq!(encode(&doc, &src), prepared, "deterministic");
    }

    #[test]
    fn the_stamp_and_the_field_come_back_as_written() {
        let (src, doc) = source();
        let n = doc.map.n();
        let squared: Vec<u32> = (0..(n * n) as u32).collect();
        let field = FieldRef {
            tag: 7,
            squared: &squared,
        };
        let prepared = encode_prepared(&doc, &src, b"dev ino mtime", Some(field));
        let h = read_header(&prepared).unwrap();
        assert_eq!(h.stamp, b"dev ino mtime");
        assert_eq!(h.source_len, src.len() as u64);
        assert_eq!(h.source_crc, crc32fast::hash(&src));
        let back = decode_prepared(&prepared, Source::Vouched, "demo.json").unwrap();
        assert_eq!(back.doc, doc);
        assert_eq!(back.obstacle_sq, Some((7, squared.clone())));
        // A field of the wrong size is not stored.
        let short = FieldRef {
            tag: 7,
            squared: &squared[1..],
        };
        let without = encode_prepared(&doc, &src, b"", Some(short));
        assert_eq!(decode(&without, &src).unwrap(), doc);
        assert_eq!(
            decode_prepared(&without, Source::Vouched, "d")
                .unwrap()
                .obstacle_sq,
            None
        );
    }

    #[test]
    fn other_source_bytes_make_it_stale() {
        let (src, doc) = source();
        let prepared = encode(&doc, &src);
        let mut edited = src.clone();
        let last = edited.iter().rposition(|b| b.is_ascii_digit()).unwrap();
        edited[last] = if edited[last] == b'1' { b'2' } else { b'1' };
        assert_eq!(decode(&prepared, &edited), Err(PreparedError::Stale));
    }

    #[test]
    fn any_flipped_or_missing_byte_is_refused() {
        let (src, doc) = source();
        let prepared = encode(&doc, &src);
        for at in [
            0,
            9,
            30,
            prepared.len() / 2,
            prepared.len() - 10,
            prepared.len() - 1,
        ] {
            let mut bad = prepared.clone();
            bad[at] ^= 0x40;
            assert!(decode(&bad, &src).is_err(), "byte {at}");
        }
        for len in [0, 7, 20, prepared.len() / 3, prepared.len() - 1] {
            assert!(decode(&prepared[..len], &src).is_err(), "len {len}");
        }
    }

    #[test]
    fn a_grid_size_no_map_may_have_is_refused_before_anything_is_allocated() {
        let (src, doc) = source();
        let mut prepared = encode(&doc, &src);
        // magic, version, source length and CRC, stamp length, the 5-byte stamp, then n.
        let at = 8 + 4 + 8 + 4 + 4 + b"stamp".len();
        assert_eq!(prepared[at..at + 4], (doc.map.n() as u32).to_le_bytes());
        prepared[at..at + 4].copy_from_slice(&40_000u32.to_le_bytes());
        assert_eq!(
            decode(&prepared, &src),
            Err(PreparedError::Corrupt(
                "grid size larger than a map may be".into()
            ))
        );
    }

    #[test]
    fn another_version_is_refused() {
        let (src, doc) = source();
        let mut prepared = encode(&doc, &src);
        prepared[8..12].copy_from_slice(&(PREPARED_VERSION + 1).to_le_bytes());
        assert_eq!(
            decode(&prepared, &src),
            Err(PreparedError::Version {
                found: PREPARED_VERSION + 1
            })
        );
    }
}
