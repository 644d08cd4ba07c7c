//! The prepared-map format: a map document in a compact binary form that loads without parsing
//! the map JSON. Almost all of a Map2Route file is its three `[row][col]` layers written as
//! decimal text (millions of numbers); here they are raw little-endian arrays, and only the small
//! rest (rooms, objects, metadata) stays JSON, read by the same reader as the source so that a
//! prepared map means exactly what its source means.
//!
//! Layout: magic `M2RCMAP\0`, format version (u32), the source's length (u64) and CRC-32 (u32),
//! grid size n (u32), n² occupancy bytes, n² room ids and n² object ids (u32 LE each), the rest's
//! JSON length (u64) and bytes, and a CRC-32 of everything before it. A prepared map is only ever
//! used for the source bytes it was made from; anything else is an error the caller turns into a
//! rebuild, never a map.

use super::format::{Layers, read_map_document_layers};
use super::{MapDocument, write_map_document};
use crate::grid::Grid;

/// Bumped whenever the layout or the meaning of a field changes.
pub const PREPARED_VERSION: u32 = 1;

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

/// Encodes `doc`, read from the map file whose bytes are `source`.
pub fn encode_prepared(doc: &MapDocument, source: &[u8]) -> Vec<u8> {
    let map = &doc.map;
    let n = map.n();
    let mut rest = write_map_document(doc);
    if let Some(obj) = rest.as_object_mut() {
        obj.remove("layers");
    }
    let rest = serde_json::to_vec(&rest).expect("a JSON value serialises");
    let mut out = Vec::with_capacity(40 + n * n * 9 + rest.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&PREPARED_VERSION.to_le_bytes());
    out.extend_from_slice(&(source.len() as u64).to_le_bytes());
    out.extend_from_slice(&crc32fast::hash(source).to_le_bytes());
    out.extend_from_slice(&(n as u32).to_le_bytes());
    out.extend_from_slice(map.occupancy.data());
    for layer in [&map.room_layer, &map.object_layer] {
        for v in layer.data() {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    out.extend_from_slice(&(rest.len() as u64).to_le_bytes());
    out.extend_from_slice(&rest);
    let crc = crc32fast::hash(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

/// Decodes a prepared map made from `source`; `file` names the source in errors.
pub fn decode_prepared(
    bytes: &[u8],
    source: &[u8],
    file: &str,
) -> Result<MapDocument, PreparedError> {
    let corrupt = |what: &str| PreparedError::Corrupt(what.to_string());
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
    let len = r.u64().ok_or_else(|| corrupt("truncated header"))?;
    let crc = r.u32().ok_or_else(|| corrupt("truncated header"))?;
    if len != source.len() as u64 || crc != crc32fast::hash(source) {
        return Err(PreparedError::Stale);
    }
    let (body, tail) = bytes
        .split_at_checked(bytes.len().saturating_sub(4))
        .filter(|(b, _)| b.len() >= r.at)
        .ok_or_else(|| corrupt("truncated"))?;
    let stored = u32::from_le_bytes(tail.try_into().map_err(|_| corrupt("truncated"))?);
    if crc32fast::hash(body) != stored {
        return Err(corrupt("checksum mismatch"));
    }
    let mut r = Reader { bytes: body, ..r };
    let n = r.u32().ok_or_else(|| corrupt("truncated header"))? as usize;
    let cells = n
        .checked_mul(n)
        .filter(|c| c.saturating_mul(9) <= body.len())
        .ok_or_else(|| corrupt("grid size larger than the file"))?;
    let occupancy = r.take(cells).ok_or_else(|| corrupt("truncated layers"))?;
    let occupancy = Grid::from_vec(n, occupancy.to_vec()).expect("n*n cells");
    let mut u32_layer = || -> Option<Grid<u32>> {
        let raw = r.take(cells.checked_mul(4)?)?;
        let data = raw
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        Grid::from_vec(n, data)
    };
    let room = u32_layer().ok_or_else(|| corrupt("truncated layers"))?;
    let object = u32_layer().ok_or_else(|| corrupt("truncated layers"))?;
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
        room,
        object,
    };
    read_map_document_layers(&rest, file, Some(layers))
        .map_err(|e| PreparedError::Corrupt(e.to_string()))
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

    #[test]
    fn a_prepared_map_is_the_map_its_source_reads_as() {
        let (src, doc) = source();
        let prepared = encode_prepared(&doc, &src);
        assert!(
            prepared.len() < src.len(),
            "{} vs {}",
            prepared.len(),
            src.len()
        );
        assert_eq!(decode_prepared(&prepared, &src, "demo.json").unwrap(), doc);
        assert_eq!(encode_prepared(&doc, &src), prepared, "deterministic");
    }

    #[test]
    fn other_source_bytes_make_it_stale() {
        let (src, doc) = source();
        let prepared = encode_prepared(&doc, &src);
        let mut edited = src.clone();
        let last = edited.iter().rposition(|b| b.is_ascii_digit()).unwrap();
        edited[last] = if edited[last] == b'1' { b'2' } else { b'1' };
        assert_eq!(
            decode_prepared(&prepared, &edited, "demo.json"),
            Err(PreparedError::Stale)
        );
    }

    #[test]
    fn any_flipped_or_missing_byte_is_refused() {
        let (src, doc) = source();
        let prepared = encode_prepared(&doc, &src);
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
            assert!(
                decode_prepared(&bad, &src, "demo.json").is_err(),
                "byte {at}"
            );
        }
        for len in [0, 7, 20, prepared.len() / 3, prepared.len() - 1] {
            assert!(
                decode_prepared(&prepared[..len], &src, "d").is_err(),
                "len {len}"
            );
        }
    }

    #[test]
    fn another_version_is_refused() {
        let (src, doc) = source();
        let mut prepared = encode_prepared(&doc, &src);
        prepared[8..12].copy_from_slice(&(PREPARED_VERSION + 1).to_le_bytes());
        assert_eq!(
            decode_prepared(&prepared, &src, "demo.json"),
            Err(PreparedError::Version {
                found: PREPARED_VERSION + 1
            })
        );
    }
}
