//! Reading route files within bounded memory. A route file is parsed as it is read into only what
//! [`crate::route::parse_route`] looks at: the top-level list, or the trajectory keys of an
//! object, each list kept to [`MAX_ROUTE_POINTS`] points (the rest only counted) and each point
//! to a few small values. Everything else (other keys, long strings, deep nesting) is skipped
//! without being stored, so a 100 MB route file costs its own bytes at most, not the gigabytes
//! of a whole JSON tree, before it is refused.

use crate::route::{MAX_ROUTE_POINTS, RouteError, TRAJECTORY_KEYS};
use serde::de::{self, DeserializeSeed, IgnoredAny, MapAccess, SeqAccess, Visitor};
use serde_json::Value;
use std::fmt;
use std::io::Read;
use std::path::Path;

/// The largest route file read, in bytes: 100 000 points pretty-printed take about 3 MB, so this
/// leaves room for any real route file and its other fields; a longer file is refused before
/// it is read to its end.
pub const MAX_ROUTE_FILE_BYTES: usize = 64 * 1024 * 1024;

/// Most JSON values kept of one point (`[row, col]` is three); a larger one is replaced by a
/// marker that fails validation as "not a [row, col] pair".
const MAX_POINT_VALUES: usize = 8;

/// What stands in for a point too large to keep.
const TOO_LARGE: &str = "<a value too large to show>";

/// Reads `path` (at most [`MAX_ROUTE_FILE_BYTES`]) as route text.
pub fn read_route_text(path: &Path) -> Result<String, RouteError> {
    let file = path.display().to_string();
    let io = |source| RouteError::Io {
        file: file.clone(),
        source,
    };
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| {
            f.take(MAX_ROUTE_FILE_BYTES as u64 + 1)
                .read_to_end(&mut bytes)
        })
        .map_err(io)?;
    if bytes.len() > MAX_ROUTE_FILE_BYTES {
        return Err(RouteError::Invalid {
            file,
            message: format!(
                "the file is more than {MAX_ROUTE_FILE_BYTES} bytes, the limit of a route file"
            ),
        });
    }
    String::from_utf8(bytes).map_err(|e| {
        io(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("not UTF-8 text ({e})"),
        ))
    })
}

/// Parses route JSON text into the reduced value described in the module comment; a list longer
/// than [`MAX_ROUTE_POINTS`] is refused here with its full length.
pub fn parse_bounded(text: &str, file: &str) -> Result<Value, RouteError> {
    let json = |source| RouteError::Json {
        file: file.to_string(),
        source,
    };
    let mut de = serde_json::Deserializer::from_str(text);
    let top = Top.deserialize(&mut de).map_err(json)?;
    de.end().map_err(json)?;
    let (value, lists) = top;
    // The list `parse_route` will take: the bare list, or the first trajectory key holding one.
    let chosen = lists
        .iter()
        .filter(|(k, _)| k.is_empty() || TRAJECTORY_KEYS.contains(&k.as_str()))
        .min_by_key(|(k, _)| {
            TRAJECTORY_KEYS
                .iter()
                .position(|t| t == k)
                .map_or(0, |p| p + 1)
        });
    if let Some((key, count)) = chosen
        && *count > MAX_ROUTE_POINTS
    {
        let label = if key.is_empty() { "trajectory" } else { key };
        return Err(RouteError::Invalid {
            file: file.to_string(),
            message: format!(
                "{label} has {count} points, more than the limit of {MAX_ROUTE_POINTS}"
            ),
        });
    }
    Ok(value)
}

/// The whole document: the reduced value and, per kept list (`""` for a bare one), its length.
struct Top;

type Reduced = (Value, Vec<(String, usize)>);

impl<'de> DeserializeSeed<'de> for Top {
    type Value = Reduced;
    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<Reduced, D::Error> {
        d.deserialize_any(TopVisitor)
    }
}

struct TopVisitor;

impl<'de> Visitor<'de> for TopVisitor {
    type Value = Reduced;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a route")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Reduced, A::Error> {
        let (list, count) = PointsVisitor.visit_seq(seq)?;
        Ok((Value::Array(list), vec![(String::new(), count)]))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Reduced, A::Error> {
        let mut obj = serde_json::Map::new();
        let mut lists = Vec::new();
        while let Some(key) = map.next_key::<String>()? {
            if TRAJECTORY_KEYS.contains(&key.as_str()) {
                match map.next_value_seed(Points)? {
                    Some((list, count)) => {
                        lists.retain(|(k, _)| *k != key);
                        lists.push((key.clone(), count));
                        obj.insert(key, Value::Array(list));
                    }
                    None => {
                        lists.retain(|(k, _)| *k != key);
                        obj.insert(key, Value::Null);
                    }
                }
            } else {
                map.next_value::<IgnoredAny>()?;
            }
        }
        Ok((Value::Object(obj), lists))
    }

    // Anything else is not a route; `parse_route` says so.
    fn visit_bool<E>(self, _: bool) -> Result<Reduced, E> {
        Ok((Value::Null, vec![]))
    }
    fn visit_i64<E>(self, _: i64) -> Result<Reduced, E> {
        Ok((Value::Null, vec![]))
    }
    fn visit_u64<E>(self, _: u64) -> Result<Reduced, E> {
        Ok((Value::Null, vec![]))
    }
    fn visit_f64<E>(self, _: f64) -> Result<Reduced, E> {
        Ok((Value::Null, vec![]))
    }
    fn visit_str<E>(self, _: &str) -> Result<Reduced, E> {
        Ok((Value::Null, vec![]))
    }
    fn visit_unit<E>(self) -> Result<Reduced, E> {
        Ok((Value::Null, vec![]))
    }
}

/// A trajectory key's value: a list of points (kept up to the limit, counted in full), or `None`
/// when it is not a list (skipped).
struct Points;

impl<'de> DeserializeSeed<'de> for Points {
    type Value = Option<(Vec<Value>, usize)>;
    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        d.deserialize_any(MaybePoints)
    }
}

struct MaybePoints;

impl<'de> Visitor<'de> for MaybePoints {
    type Value = Option<(Vec<Value>, usize)>;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a point list")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Self::Value, A::Error> {
        PointsVisitor.visit_seq(seq).map(Some)
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
        while map.next_entry::<IgnoredAny, IgnoredAny>()?.is_some() {}
        Ok(None)
    }

    fn visit_bool<E>(self, _: bool) -> Result<Self::Value, E> {
        Ok(None)
    }
    fn visit_i64<E>(self, _: i64) -> Result<Self::Value, E> {
        Ok(None)
    }
    fn visit_u64<E>(self, _: u64) -> Result<Self::Value, E> {
        Ok(None)
    }
    fn visit_f64<E>(self, _: f64) -> Result<Self::Value, E> {
        Ok(None)
    }
    fn visit_str<E>(self, _: &str) -> Result<Self::Value, E> {
        Ok(None)
    }
    fn visit_unit<E>(self) -> Result<Self::Value, E> {
        Ok(None)
    }
}

struct PointsVisitor;

impl PointsVisitor {
    fn visit_seq<'de, A: SeqAccess<'de>>(
        self,
        mut seq: A,
    ) -> Result<(Vec<Value>, usize), A::Error> {
        let mut list = Vec::new();
        let mut count = 0usize;
        loop {
            if count < MAX_ROUTE_POINTS {
                match seq.next_element_seed(Small {
                    left: MAX_POINT_VALUES,
                })? {
                    Some(v) => list.push(v.unwrap_or_else(|| Value::String(TOO_LARGE.into()))),
                    None => break,
                }
            } else if seq.next_element::<IgnoredAny>()?.is_none() {
                break;
            }
            count += 1;
        }
        Ok((list, count))
    }
}

/// One point: its JSON value when it has at most `left` values and no long string, else `None`
/// (the rest is skipped unstored).
struct Small {
    left: usize,
}

impl<'de> DeserializeSeed<'de> for Small {
    type Value = Option<Value>;
    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<Option<Value>, D::Error> {
        let mut left = self.left;
        d.deserialize_any(SmallVisitor { left: &mut left })
    }
}

struct SmallVisitor<'a> {
    left: &'a mut usize,
}

impl SmallVisitor<'_> {
    /// Counts one value against the allowance; false when it is spent.
    fn take(&mut self) -> bool {
        if *self.left == 0 {
            return false;
        }
        *self.left -= 1;
        true
    }
}

/// The seed of a value nested in a point, sharing the point's allowance.
struct Nested<'a> {
    left: &'a mut usize,
}

impl<'de> DeserializeSeed<'de> for Nested<'_> {
    type Value = Option<Value>;
    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<Option<Value>, D::Error> {
        d.deserialize_any(SmallVisitor { left: self.left })
    }
}

impl<'de> Visitor<'de> for SmallVisitor<'_> {
    type Value = Option<Value>;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a point")
    }

    fn visit_bool<E>(mut self, v: bool) -> Result<Option<Value>, E> {
        Ok(self.take().then_some(Value::Bool(v)))
    }
    fn visit_i64<E>(mut self, v: i64) -> Result<Option<Value>, E> {
        Ok(self.take().then_some(Value::from(v)))
    }
    fn visit_u64<E>(mut self, v: u64) -> Result<Option<Value>, E> {
        Ok(self.take().then_some(Value::from(v)))
    }
    fn visit_f64<E>(mut self, v: f64) -> Result<Option<Value>, E> {
        Ok(self
            .take()
            .then(|| serde_json::Number::from_f64(v).map_or(Value::Null, Value::Number)))
    }
    fn visit_str<E>(mut self, v: &str) -> Result<Option<Value>, E> {
        Ok((self.take() && v.len() <= 64).then(|| Value::String(v.to_string())))
    }
    fn visit_unit<E>(mut self) -> Result<Option<Value>, E> {
        Ok(self.take().then_some(Value::Null))
    }

    fn visit_seq<A: SeqAccess<'de>>(mut self, mut seq: A) -> Result<Option<Value>, A::Error> {
        let mut items = Some(Vec::new());
        if !self.take() {
            items = None;
        }
        loop {
            match &mut items {
                Some(list) => match seq.next_element_seed(Nested {
                    left: &mut *self.left,
                })? {
                    Some(Some(v)) => list.push(v),
                    Some(None) => items = None,
                    None => break,
                },
                None => {
                    if seq.next_element::<IgnoredAny>()?.is_none() {
                        break;
                    }
                }
            }
        }
        Ok(items.map(Value::Array))
    }

    fn visit_map<A: MapAccess<'de>>(mut self, mut map: A) -> Result<Option<Value>, A::Error> {
        // A point is never an object: keep a small one (for the message), skip a large one.
        let mut obj = Some(serde_json::Map::new());
        if !self.take() {
            obj = None;
        }
        while let Some(key) = map.next_key::<IgnoredKey>()? {
            match (&mut obj, key.0) {
                (Some(o), Some(k)) => match map.next_value_seed(Nested {
                    left: &mut *self.left,
                })? {
                    Some(v) => {
                        o.insert(k, v);
                    }
                    None => obj = None,
                },
                _ => {
                    obj = None;
                    map.next_value::<IgnoredAny>()?;
                }
            }
        }
        Ok(obj.map(Value::Object))
    }
}

/// An object key, kept only when short.
struct IgnoredKey(Option<String>);

impl<'de> de::Deserialize<'de> for IgnoredKey {
    fn deserialize<D: de::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct K;
        impl Visitor<'_> for K {
            type Value = IgnoredKey;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a key")
            }
            fn visit_str<E>(self, v: &str) -> Result<IgnoredKey, E> {
                Ok(IgnoredKey((v.len() <= 64).then(|| v.to_string())))
            }
        }
        d.deserialize_str(K)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn same_as_full(text: &str) {
        let full: Value = serde_json::from_str(text).unwrap();
        let bounded = parse_bounded(text, "r").unwrap();
        let a = crate::route::parse_route(&full, 50, "r").map_err(|e| e.to_string());
        let b = crate::route::parse_route(&bounded, 50, "r").map_err(|e| e.to_string());
        assert_eq!(a, b, "{text}");
    }

    #[test]
    fn the_reduced_value_validates_as_the_whole_document() {
        for text in [
            "[[0, 1], [2, 3]]",
            "[]",
            r#"{"predicted_trajectory": [[1, 1]], "human_expert_trajectory": [[2, 2]]}"#,
            r#"{"trajectory": "x", "human_expert_trajectory": [[2, 2]], "other": {"a": [1, 2, 3]}}"#,
            r#"{"trajectory": [[1, 1]], "trajectory": [[3, 3]]}"#,
            "[[0.0, 1]]",
            "[[true, 1]]",
            "[[0, 99]]",
            "[[0, 1, 2]]",
            "[[0]]",
            "[7]",
            r#"[{"row": 1}]"#,
            r#"{"route": [[0, 0]]}"#,
            r#""x""#,
            "[[0, 18446744073709551615]]",
        ] {
            same_as_full(text);
        }
    }

    #[test]
    fn long_lists_and_large_points_are_refused_without_being_kept() {
        let many = format!(
            "{{\"trajectory\": [{}[0, 0]], \"note\": \"{}\"}}",
            "[0, 0],".repeat(MAX_ROUTE_POINTS),
            "n".repeat(10_000)
        );
        let e = parse_bounded(&many, "r.json").unwrap_err().to_string();
        assert_eq!(
            e,
            format!(
                "r.json: trajectory has 100001 points, more than the limit of {MAX_ROUTE_POINTS}"
            )
        );
        let big = format!("[[0, 1], [{}]]", "1, ".repeat(1000) + "1");
        let v = parse_bounded(&big, "r").unwrap();
        assert_eq!(v, json!([[0, 1], TOO_LARGE]));
        let e = crate::route::parse_route(&v, 5, "r")
            .unwrap_err()
            .to_string();
        assert!(e.contains("trajectory[1] must be a [row, col]"), "{e}");
        // A long list under a key that is not read is skipped, not refused.
        let other = format!(
            "{{\"x\": [{}0], \"trajectory\": [[1, 1]]}}",
            "0,".repeat(MAX_ROUTE_POINTS + 5)
        );
        assert_eq!(
            parse_bounded(&other, "r").unwrap(),
            json!({"trajectory": [[1, 1]]})
        );
    }

    #[test]
    fn syntax_errors_are_json_errors() {
        for bad in ["[[0, 1]", "[[0, 1]] x", "{\"trajectory\": }"] {
            assert!(matches!(
                parse_bounded(bad, "r"),
                Err(RouteError::Json { .. })
            ));
        }
    }
}
