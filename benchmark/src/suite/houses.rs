//! Reading ProcTHOR house files and choosing benchmark scenes.
//!
//! The paper's scenes are the largest multi-room houses, so houses are ranked by total floor
//! polygon area, then room count, then their position in the input (a stable tie-break), and
//! single-room houses are skipped.

use super::SuiteError;
use flate2::read::GzDecoder;
use serde_json::Value;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};

/// One house read from the input, with what ranking needs.
#[derive(Clone, Debug)]
pub struct House {
    /// `file:line` (1-based line for JSON-lines files), for messages and the manifest.
    pub source: String,
    /// 0-based position over all inputs in read order.
    pub index: usize,
    pub rooms: usize,
    pub area_m2: f64,
    pub json: Value,
}

/// Reads every house under `path`: a `.jsonl.gz` / `.jsonl` file (one house per line), a `.json`
/// file (one house), or a directory of such files (sorted by name).
///
/// `-` reads standard input: gzip-compressed or plain, one house (a JSON document) or JSON lines.
pub fn read_houses(path: &Path) -> Result<Vec<House>, SuiteError> {
    if path == Path::new("-") {
        let mut bytes = Vec::new();
        std::io::stdin()
            .lock()
            .read_to_end(&mut bytes)
            .map_err(|e| SuiteError::io(path, e))?;
        let mut houses = Vec::new();
        read_bytes(STDIN_NAME, &bytes, &mut houses)?;
        return non_empty(houses, path);
    }
    let files: Vec<PathBuf> = if path.is_dir() {
        let mut files: Vec<PathBuf> = std::fs::read_dir(path)
            .map_err(|e| SuiteError::io(path, e))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                let name = p.to_string_lossy();
                name.ends_with(".jsonl.gz") || name.ends_with(".jsonl") || name.ends_with(".json")
            })
            .collect();
        files.sort();
        files
    } else {
        vec![path.to_path_buf()]
    };
    let mut houses = Vec::new();
    for file in files {
        read_file(&file, &mut houses)?;
    }
    non_empty(houses, path)
}

/// How houses read from standard input are named in messages and the manifest.
pub const STDIN_NAME: &str = "<stdin>";

fn non_empty(houses: Vec<House>, path: &Path) -> Result<Vec<House>, SuiteError> {
    if houses.is_empty() {
        return Err(SuiteError::Input(format!(
            "{}: no houses found",
            if path == Path::new("-") {
                STDIN_NAME.into()
            } else {
                path.display().to_string()
            }
        )));
    }
    Ok(houses)
}

/// Houses from a stream whose kind is not given by a file name: gzip by its magic bytes, then one
/// JSON document if the whole text is one, else JSON lines.
fn read_bytes(name: &str, bytes: &[u8], out: &mut Vec<House>) -> Result<(), SuiteError> {
    let stdin = Path::new("-");
    let text = if bytes.starts_with(&[0x1f, 0x8b]) {
        let mut text = String::new();
        GzDecoder::new(bytes)
            .read_to_string(&mut text)
            .map_err(|e| SuiteError::io(stdin, e))?;
        text
    } else {
        String::from_utf8(bytes.to_vec())
            .map_err(|e| SuiteError::Input(format!("{name}: not UTF-8 text: {e}")))?
    };
    if let Ok(json) = serde_json::from_str::<Value>(&text) {
        return push(out, name.to_string(), json);
    }
    read_lines(name, std::io::Cursor::new(text), stdin, out)
}

fn read_file(file: &Path, out: &mut Vec<House>) -> Result<(), SuiteError> {
    let name = file.to_string_lossy().to_string();
    let raw = std::fs::File::open(file).map_err(|e| SuiteError::io(file, e))?;
    if name.ends_with(".json") {
        let mut text = String::new();
        BufReader::new(raw)
            .read_to_string(&mut text)
            .map_err(|e| SuiteError::io(file, e))?;
        let json: Value = serde_json::from_str(&text)
            .map_err(|e| SuiteError::Input(format!("{name}: not valid JSON: {e}")))?;
        push(out, name.to_string(), json)?;
        return Ok(());
    }
    let reader: Box<dyn BufRead> = if name.ends_with(".gz") {
        Box::new(BufReader::new(GzDecoder::new(raw)))
    } else {
        Box::new(BufReader::new(raw))
    };
    read_lines(&name, reader, file, out)
}

fn read_lines(
    name: &str,
    reader: impl BufRead,
    file: &Path,
    out: &mut Vec<House>,
) -> Result<(), SuiteError> {
    // Houses are named `<file>#<i>` with `i` the 0-based index among the file's non-empty
    // lines, exactly what `m2rc map import <file> --index i` (or `<file>#i`) takes.
    let mut index = 0usize;
    for (i, line) in reader.lines().enumerate() {
        let line = line.map_err(|e| SuiteError::io(file, e))?;
        if line.trim().is_empty() {
            continue;
        }
        let json: Value = serde_json::from_str(&line).map_err(|e| {
            SuiteError::Input(format!(
                "{name}#{index} (line {}): not valid JSON: {e}",
                i + 1
            ))
        })?;
        push(out, format!("{name}#{index}"), json)?;
        index += 1;
    }
    Ok(())
}

fn push(out: &mut Vec<House>, source: String, json: Value) -> Result<(), SuiteError> {
    let rooms = json.get("rooms").and_then(Value::as_array).ok_or_else(|| {
        SuiteError::Input(format!("{source}: field `rooms`: missing or not a list"))
    })?;
    let mut area = 0.0;
    for (k, room) in rooms.iter().enumerate() {
        let poly = room
            .get("floorPolygon")
            .and_then(Value::as_array)
            .ok_or_else(|| {
                SuiteError::Input(format!(
                    "{source}: field `rooms[{k}].floorPolygon`: missing or not a list"
                ))
            })?;
        let pts: Vec<(f64, f64)> = poly
            .iter()
            .filter_map(|p| Some((p.get("x")?.as_f64()?, p.get("z")?.as_f64()?)))
            .collect();
        area += shoelace(&pts);
    }
    let index = out.len();
    out.push(House {
        source,
        index,
        rooms: rooms.len(),
        area_m2: area,
        json,
    });
    Ok(())
}

fn shoelace(pts: &[(f64, f64)]) -> f64 {
    if pts.len() < 3 {
        return 0.0;
    }
    let mut s = 0.0;
    for i in 0..pts.len() {
        let (x0, z0) = pts[i];
        let (x1, z1) = pts[(i + 1) % pts.len()];
        s += x0 * z1 - x1 * z0;
    }
    s.abs() / 2.0
}

/// Multi-room houses, largest first (area, then rooms, then input position).
pub fn rank_houses(houses: &[House]) -> Vec<&House> {
    let mut ranked: Vec<&House> = houses.iter().filter(|h| h.rooms >= 2).collect();
    ranked.sort_by(|a, b| {
        b.area_m2
            .total_cmp(&a.area_m2)
            .then(b.rooms.cmp(&a.rooms))
            .then(a.index.cmp(&b.index))
    });
    ranked
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shoelace_of_a_square() {
        assert_eq!(
            shoelace(&[(0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0)]),
            16.0
        );
    }

    #[test]
    fn ranking_skips_single_rooms_and_is_stable() {
        let h = |i, rooms, area| House {
            source: format!("h{i}"),
            index: i,
            rooms,
            area_m2: area,
            json: Value::Null,
        };
        let houses = vec![
            h(0, 1, 500.0),
            h(1, 4, 100.0),
            h(2, 5, 100.0),
            h(3, 3, 200.0),
            h(4, 5, 100.0),
        ];
        let ranked: Vec<usize> = rank_houses(&houses).iter().map(|h| h.index).collect();
        assert_eq!(ranked, vec![3, 2, 4, 1]);
    }
}
