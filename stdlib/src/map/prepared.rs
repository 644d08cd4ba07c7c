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
//! distances), the rest's JSON length (u64) and bytes, and a CRC-32 of everything before it. A
//! prepared map is only ever used for the source it was made from (its bytes, or a stamp the
//! caller matched); anything else is an error the caller turns into a rebuild, never a map.

use super::format::{Layers, read_map_document_layers};
use super::{MapDocument, write_map_document};
use crate::grid::Grid;

/// Bumped whenever the layout or the meaning of a field changes.
pub const PREPARED_VERSION: u32 = 2;

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
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Header<'a> {
    pub source_len: u64,
    pub source_crc: u32,
    pub stamp: &'a [u8],
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
pub fn read_header(bytes: &[u8]) -> Result<Header<'_>, PreparedError> {
    header(bytes).map(|(h, _)| h)
}

fn header(bytes: &[u8]) -> Result<(Header<'_>, usize), PreparedError> {
    if bytes.len() < MAGIC.len() || &bytes[..MAGIC.len()] != MAGIC {
        return Err(PreparedError::NotPrepared);
    }
    let mut r = Reader {
        bytes,
        at: MAGIC.len(),
    };
    let version = r.u32().ok_or_else(|| corrupt("truncated header"))?;
    if version != PREPARED_VERSION {
        return Err(PreparedError::Version { found: version });
    }
    let source_len = r.u64().ok_or_else(|| corrupt("truncated header"))?;
    let source_crc = r.u32().ok_or_else(|| corrupt("truncated header"))?;
    let stamp_len = r.u32().ok_or_else(|| corrupt("truncated header"))?;
    let stamp = r
        .take(stamp_len as usize)
        .ok_or_else(|| corrupt("truncated header"))?;
    let h = Header {
        source_len,
        source_crc,
        stamp,
    };
    Ok((h, r.at))
}

/// Decodes a prepared map made from `source`; `file` names the source in errors.
pub fn decode_prepared(
    bytes: &[u8],
    source: Source<'_>,
    file: &str,
) -> Result<Prepared, PreparedError> {
    let (h, at) = header(bytes)?;
    if let Source::Bytes(src) = source
        && (h.source_len != src.len() as u64 || h.source_crc != crc32fast::hash(src))
    {
        return Err(PreparedError::Stale);
    }
    let (body, tail) = bytes
        .split_at_checked(bytes.len().saturating_sub(4))
        .filter(|(b, _)| b.len() >= at)
        .ok_or_else(|| corrupt("truncated"))?;
    let stored = u32::from_le_bytes(tail.try_into().map_err(|_| corrupt("truncated"))?);
    if crc32fast::hash(body) != stored {
        return Err(corrupt("checksum mismatch"));
    }
    let mut r = Reader { bytes: body, at };
    let n = r.u32().ok_or_else(|| corrupt("truncated header"))? as usize;
    let cells = n
        .checked_mul(n)
        .filter(|c| c.saturating_mul(9) <= body.len())
        .ok_or_else(|| corrupt("grid size larger than the file"))?;
    let occupancy = r.take(cells).ok_or_else(|| corrupt("truncated layers"))?;
    let occupancy = Grid::from_vec(n, occupancy.to_vec()).expect("n*n cells");
    let room = r.u32s(cells).ok_or_else(|| corrupt("truncated layers"))?;
    let object = r.u32s(cells).ok_or_else(|| corrupt("truncated layers"))?;
    let obstacle_sq = match r.take(1).ok_or_else(|| corrupt("truncated field"))? {
        [0] => None,
        [1] => {
            let tag = r.u32().ok_or_else(|| corrupt("truncated field"))?;
            Some((
                tag,
                r.u32s(cells).ok_or_else(|| corrupt("truncated field"))?,
            ))
        }
        _ => return Err(corrupt("bad field marker")),
    };
    let rest_len = r.u64().ok_or_else(|| corrupt("truncated rest"))?;
    let rest = usize::try_from(rest_len)
        .ok()
        .and_then(|l| r.take(l))
        .ok_or_else(|| corrupt("truncated rest"))?;
    if r.at != body.len() {
        return Err(corrupt("trailing bytes"));
    }
    let rest: serde_json::Value =
        serde_json::from_slice(rest).map_err(|e| PreparedError::Corrupt(e.to_string()))?;
    let layers = Layers {
        occupancy,
        room: Grid::from_vec(n, room).expect("n*n cells"),
        object: Grid::from_vec(n, object).expect("n*n cells"),
    };
    let doc = read_map_document_layers(&rest, file, Some(layers))
        .map_err(|e| PreparedError::Corrupt(e.to_string()))?;
    Ok(Prepared { doc, obstacle_sq })
}

struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, len: usize) -> Option<&'a [u8]> {
        let end = self.at.checked_add(len)?;
        let out = self.bytes.get(self.at..end)?;
        self.at = end;
        Some(out)
    }
    fn u32(&mut self) -> Option<u32> {
        Some(u32::from_le_bytes(self.take(4)?.try_into().ok()?))
    }
    fn u64(&mut self) -> Option<u64> {
        Some(u64::from_le_bytes(self.take(8)?.try_into().ok()?))
    }
    fn u32s(&mut self, count: usize) -> Option<Vec<u32>> {
        let raw = self.take(count.checked_mul(4)?)?;
        Some(
            raw.chunks_exact(4)
                .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                .collect(),
        )
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
