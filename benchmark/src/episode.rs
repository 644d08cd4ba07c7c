//! The Map2Route instruction ("episode") JSON, read and written so that the reference tools and
//! m2rc can exchange files unchanged.
//!
//! Only the keys the evaluator and the suite generator need are typed; every other key rides along
//! in `extra` maps. A file read with [`Episode::from_json_str`] remembers its source, and
//! [`Episode::to_value`] reconciles the typed data against it: untouched keys keep their original
//! order and their number spelling (`3` stays `3`, not `3.0`), so reading and writing a reference
//! file reproduces the same JSON value. Fields the reference writer emits as `null` (an avoid's
//! `order`, a scope's orders, ...) are written as `null` too, so the reference can index them.
//!
//! m2rc adds two keys the reference ignores: [`GOLD_PROGRAM_KEY`] (the gold `.m2r` program) and
//! [`GENERATION_KEY`] (how the episode was generated).

use indexmap::IndexMap;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

/// Extra key holding the gold `.m2r` program of an m2rc-generated episode.
pub const GOLD_PROGRAM_KEY: &str = "m2rc_gold_program";
/// Extra key holding [`Generation`] metadata of an m2rc-generated episode.
pub const GENERATION_KEY: &str = "m2rc_generation";
/// The scope type that restricts a constraint to one route stage; every other value is global.
pub const BETWEEN_HARD_CONSTRAINTS: &str = "between_hard_constraints";

/// Errors reading an episode file.
#[derive(Debug, thiserror::Error)]
pub enum EpisodeError {
    #[error("{file}: cannot read: {source}")]
    Io {
        file: String,
        #[source]
        source: std::io::Error,
    },
    #[error("{file}: not valid JSON: {source}")]
    Json {
        file: String,
        #[source]
        source: serde_json::Error,
    },
    #[error("{file}: field `{path}`: {message}")]
    Field {
        file: String,
        path: String,
        message: String,
    },
}

/// A `[row, col]` point as stored in region cells and trajectories (integers in the reference files).
pub type CellRc = [i64; 2];

/// One Map2Route instruction file (section B of the format notes).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Episode {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub id: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub map_id: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub template_instruction_id: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub object_count: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub objects: Option<Vec<TemplateObject>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub human_expert_trajectory: Option<Vec<CellRc>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start_pose: Option<StartPose>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub feasible: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub notes: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub created_by: Option<String>,
    #[serde(default)]
    pub hard_constraints: Vec<HardConstraint>,
    #[serde(default)]
    pub soft_constraints: Vec<SoftConstraint>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ordering: Option<String>,
    /// `easy`, `hard` or `extreme`; kept as a string so unknown levels survive a round trip.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub difficulty_level: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub created_at: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub updated_at: Option<String>,
    /// The natural-language instruction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub instruction: Option<String>,
    /// m2rc extension: the gold `.m2r` program this episode was generated from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub m2rc_gold_program: Option<String>,
    /// m2rc extension: generation metadata.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub m2rc_generation: Option<Generation>,
    /// Every other key (legacy human-reference fields, annotator keys, ...), in file order.
    #[serde(flatten)]
    pub extra: IndexMap<String, Value>,
    /// Where this episode was read from (for faithful writing and provenance); never
    /// serialized. Public only so that `Episode { .., ..Episode::default() }` works elsewhere.
    #[doc(hidden)]
    #[serde(skip)]
    pub origin: Origin,
}

/// How an m2rc episode was produced. The suite generator may add more keys in `extra`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Generation {
    /// The generator, e.g. `m2rc-suite`.
    pub generator: String,
    /// m2rc version that generated the episode.
    pub version: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// Source house or scene id.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub house: Option<String>,
    /// Episode template or family name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub template: Option<String>,
    #[serde(flatten)]
    pub extra: IndexMap<String, Value>,
}

/// A template object of the source template (`objects`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TemplateObject {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub order: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub object_id: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub category: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center: Option<[f64; 2]>,
    #[serde(flatten)]
    pub extra: IndexMap<String, Value>,
}

/// The start pose, equal to the first cell of the expert trajectory. No heading.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StartPose {
    #[serde(default)]
    pub row: Option<i64>,
    #[serde(default)]
    pub col: Option<i64>,
    #[serde(flatten)]
    pub extra: IndexMap<String, Value>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ConstraintKind {
    MustPass,
    MustAvoid,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Shape {
    Circle,
    Rectangle,
    Freeform,
}

/// The annotator's defaults for a new region (the evaluator itself requires explicit values).
pub const DEFAULT_RADIUS: f64 = 6.0;
pub const DEFAULT_WIDTH: f64 = 12.0;
pub const DEFAULT_HEIGHT: f64 = 12.0;

/// The route-stage scope: global, or "while travelling from must-pass `from_order` to `to_order`".
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Scope {
    #[serde(rename = "type", default, skip_serializing_if = "Option::is_none")]
    pub kind: Option<String>,
    #[serde(default)]
    pub from_order: Option<i64>,
    #[serde(default)]
    pub to_order: Option<i64>,
    #[serde(flatten)]
    pub extra: IndexMap<String, Value>,
}

impl Scope {
    pub fn global() -> Self {
        Scope {
            kind: Some("global".into()),
            ..Scope::default()
        }
    }

    pub fn between(from_order: i64, to_order: i64) -> Self {
        Scope {
            kind: Some(BETWEEN_HARD_CONSTRAINTS.into()),
            from_order: Some(from_order),
            to_order: Some(to_order),
            extra: IndexMap::new(),
        }
    }

    /// Stage-scoped iff the type is exactly `between_hard_constraints`; anything else is global.
    pub fn is_between(&self) -> bool {
        self.kind.as_deref() == Some(BETWEEN_HARD_CONSTRAINTS)
    }
}

/// A hard constraint (B.1): a must-pass goal or a must-avoid region.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HardConstraint {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub constraint_id: Option<String>,
    pub kind: ConstraintKind,
    pub shape: Shape,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center: Option<[f64; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    /// 1-based position among the must-pass constraints; `null` for must-avoids.
    #[serde(default)]
    pub order: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    #[serde(default)]
    pub object_id: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scope: Option<Scope>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub label: Option<String>,
    /// Region cells, used only when the shape is freeform.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cells: Option<Vec<CellRc>>,
    #[serde(flatten)]
    pub extra: IndexMap<String, Value>,
}

impl HardConstraint {
    /// A freeform region over `cells`, centred on their mean.
    pub fn freeform(id: &str, kind: ConstraintKind, cells: Vec<CellRc>) -> Self {
        let center = cells_center(&cells);
        HardConstraint {
            constraint_id: Some(id.to_string()),
            kind,
            shape: Shape::Freeform,
            center: Some(center),
            radius: None,
            width: None,
            height: None,
            order: None,
            source: None,
            object_id: None,
            scope: Some(Scope::global()),
            label: None,
            cells: Some(cells),
            extra: IndexMap::new(),
        }
    }

    /// Stage-scoped (`between_hard_constraints`) must-avoid; must-passes are always global.
    pub fn is_scoped(&self) -> bool {
        self.scope.as_ref().is_some_and(Scope::is_between)
    }
}

fn cells_center(cells: &[CellRc]) -> [f64; 2] {
    if cells.is_empty() {
        return [0.0, 0.0];
    }
    let n = cells.len() as f64;
    let r = cells.iter().map(|c| c[0] as f64).sum::<f64>() / n;
    let c = cells.iter().map(|c| c[1] as f64).sum::<f64>() / n;
    [r, c]
}

/// An object footprint a soft preference is measured against.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ReferenceRegion {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mode: Option<String>,
    #[serde(default)]
    pub object_id: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cells: Option<Vec<CellRc>>,
    #[serde(flatten)]
    pub extra: IndexMap<String, Value>,
}

/// The annotation tool's canonical path-shape reference; its trajectory overrides
/// `reference_trajectory` at evaluation.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PathShapeAnnotation {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub version: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub annotation_type: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape_spec: Option<Value>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape_reference_trajectory: Option<Vec<CellRc>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape_reference_source: Option<String>,
    #[serde(flatten)]
    pub extra: IndexMap<String, Value>,
}

/// The preference types the current evaluator scores.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PreferenceType {
    Near,
    Far,
    Relative,
    PathShape,
    Clearance,
}

/// Every `preference_type` string an episode may use, with its type: the evaluator's own names
/// (the strings it dispatches on), so the episode check and the evaluator accept the same set.
/// `docs/formats.md` lists the same names; a test compares the two.
pub const PREFERENCE_TYPE_NAMES: [(&str, PreferenceType); 6] = {
    use crate::metrics::soft::{CLEARANCE, FAR, GEOMETRIC_PATH, NEAR, PATH_SHAPE, RELATIVE};
    [
        (NEAR, PreferenceType::Near),
        (FAR, PreferenceType::Far),
        (RELATIVE, PreferenceType::Relative),
        (PATH_SHAPE, PreferenceType::PathShape),
        (GEOMETRIC_PATH, PreferenceType::PathShape),
        (CLEARANCE, PreferenceType::Clearance),
    ]
};

impl PreferenceType {
    /// Maps a `preference_type` string ([`PREFERENCE_TYPE_NAMES`]);
    /// `geometric_path_preference` is an alias of path shape.
    pub fn parse(s: &str) -> Option<Self> {
        PREFERENCE_TYPE_NAMES
            .iter()
            .find(|(name, _)| *name == s)
            .map(|&(_, t)| t)
    }

    /// The canonical `preference_type` string.
    pub fn as_str(self) -> &'static str {
        match self {
            PreferenceType::Near => "near_preference",
            PreferenceType::Far => "far_preference",
            PreferenceType::Relative => "relative_preference",
            PreferenceType::PathShape => "path_shape_preference",
            PreferenceType::Clearance => "clearance",
        }
    }
}

/// A soft constraint (B.2). Region fields give the spatial scope R; `scope` the route stage.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SoftConstraint {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub constraint_id: Option<String>,
    /// Kept as a string: unknown types are reported `unsupported_preference`, not rejected.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preference_type: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape: Option<Shape>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center: Option<[f64; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub object_ids: Option<Vec<i64>>,
    /// `[A, B]` for relative preferences; A is preferred.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference_regions: Option<Vec<ReferenceRegion>>,
    #[serde(default)]
    pub reference_region: Option<ReferenceRegion>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference_trajectory: Option<Vec<CellRc>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scope: Option<Scope>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub label: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cells: Option<Vec<CellRc>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub path_shape_annotation: Option<PathShapeAnnotation>,
    /// Legacy reference values (`D_ref`, `C_clear_ref`, ...) and any other key.
    #[serde(flatten)]
    pub extra: IndexMap<String, Value>,
}

impl SoftConstraint {
    pub fn preference(&self) -> Option<PreferenceType> {
        self.preference_type
            .as_deref()
            .and_then(PreferenceType::parse)
    }

    pub fn is_scoped(&self) -> bool {
        self.scope.as_ref().is_some_and(Scope::is_between)
    }
}

/// The JSON an episode was read from, and the file it came from. Compares equal to anything: it
/// is bookkeeping, not data.
#[derive(Clone, Debug, Default)]
pub struct Origin {
    json: Option<Arc<SourceJson>>,
    path: Option<PathBuf>,
}

/// The source JSON: the value itself, or the text it was read from, parsed again only when the
/// episode is written (scoring never writes one, and keeping a second tree of a 100 KB episode
/// cost a cached `m2rc eval` a tenth of its time).
#[derive(Debug)]
enum SourceJson {
    Value(Value),
    Text {
        text: String,
        value: OnceLock<Value>,
    },
}

impl SourceJson {
    fn value(&self) -> &Value {
        match self {
            SourceJson::Value(v) => v,
            // The text parsed once already, as this episode.
            SourceJson::Text { text, value } => {
                value.get_or_init(|| serde_json::from_str(text).unwrap_or(Value::Null))
            }
        }
    }
}

impl PartialEq for Origin {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl Episode {
    /// Parses an episode from a JSON value. `file` names the input in error messages.
    pub fn from_value(value: Value, file: &str) -> Result<Episode, EpisodeError> {
        not_an_object(&value, file)?;
        // Whole-number floats (`[223.0, 117.0]`, as Python writers emit them) are read as the
        // integers they are; the source value is kept as it was for faithful writing.
        let mut episode = if crate::episode_check::has_integral_float(&value) {
            let mut converted = value.clone();
            crate::episode_check::integral_floats_to_ints(&mut converted);
            Episode::typed(&converted, file)?
        } else {
            Episode::typed(&value, file)?
        };
        episode.origin.json = Some(Arc::new(SourceJson::Value(value)));
        Ok(episode)
    }

    /// Parses an episode from JSON text. `file` names the input in error messages.
    pub fn from_json_str(text: &str, file: &str) -> Result<Episode, EpisodeError> {
        let mut value: Value = serde_json::from_str(text).map_err(|source| EpisodeError::Json {
            file: file.to_string(),
            source,
        })?;
        not_an_object(&value, file)?;
        // As `from_value`, converted in place: the source is kept as its text.
        crate::episode_check::integral_floats_to_ints(&mut value);
        let mut episode = Episode::typed(&value, file)?;
        episode.origin.json = Some(Arc::new(SourceJson::Text {
            text: text.to_string(),
            value: OnceLock::new(),
        }));
        Ok(episode)
    }

    /// The typed episode of a value whose integral floats are already integers: the plain
    /// deserializer first, the path-tracking one (slower) only to name the path of an error.
    fn typed(value: &Value, file: &str) -> Result<Episode, EpisodeError> {
        match Episode::deserialize(value) {
            Ok(e) => Ok(e),
            Err(_) => serde_path_to_error::deserialize(value).map_err(|e| EpisodeError::Field {
                file: file.to_string(),
                path: e.path().to_string(),
                message: e.inner().to_string(),
            }),
        }
    }

    /// Checks what the types cannot: cells inside an `n` x `n` map and not negative, 1-based
    /// orders, known preference types (see [`crate::episode_check`]).
    pub fn check(&self, n: Option<usize>) -> Result<(), EpisodeError> {
        let file = self
            .origin
            .path
            .as_ref()
            .map_or("<episode>".to_string(), |p| p.display().to_string());
        crate::episode_check::check_episode(self, n, &file)
    }

    /// Reads an instruction file.
    pub fn read(path: &Path) -> Result<Episode, EpisodeError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| EpisodeError::Io {
            file: file.clone(),
            source,
        })?;
        let mut episode = Episode::from_json_str(&text, &file)?;
        episode.origin.path = Some(path.to_path_buf());
        Ok(episode)
    }

    /// The file this episode was read from, if any (reported with path-shape references).
    pub fn source_path(&self) -> Option<&Path> {
        self.origin.path.as_deref()
    }

    /// Records the file this episode belongs to, e.g. after reading it from memory.
    pub fn set_source_path(&mut self, path: Option<PathBuf>) {
        self.origin.path = path;
    }

    /// The episode as JSON. For an episode read from a file, keys and number spellings that the
    /// typed data did not change are kept exactly as in the source.
    pub fn to_value(&self) -> Value {
        // Serializing plain data (strings, numbers, maps with string keys) cannot fail; a NaN
        // would become `null`, as serde_json does for non-finite floats.
        let fresh = serde_json::to_value(self).unwrap_or(Value::Null);
        match &self.origin.json {
            Some(source) => reconcile(fresh, source.value()),
            None => fresh,
        }
    }

    /// Pretty JSON with two-space indentation, like the reference writer.
    pub fn to_json_pretty(&self) -> String {
        let mut s = serde_json::to_string_pretty(&self.to_value()).unwrap_or_default();
        s.push('\n');
        s
    }

    /// `instruction_{id:06d}`, the reference's derived instruction id.
    pub fn instruction_id(&self) -> Option<String> {
        self.id.map(|id| format!("instruction_{id:06}"))
    }

    /// Forgets the source JSON, so that the next write is the canonical serialization.
    pub fn detach_source(&mut self) {
        self.origin.json = None;
    }
}

fn not_an_object(value: &Value, file: &str) -> Result<(), EpisodeError> {
    if value.is_object() {
        return Ok(());
    }
    Err(EpisodeError::Field {
        file: file.to_string(),
        path: ".".into(),
        message: "an instruction file must be a JSON object".into(),
    })
}

/// Rebuilds `fresh` using `old`'s key order and number spellings wherever the data is unchanged.
/// Keys that only the typed defaults introduced (`null` or `[]` where the source had no key) are
/// dropped, so a round trip adds nothing.
fn reconcile(fresh: Value, old: &Value) -> Value {
    match (fresh, old) {
        (Value::Object(mut new), Value::Object(old)) => {
            let mut out = Map::new();
            for (key, old_value) in old {
                match new.shift_remove(key) {
                    Some(v) => {
                        out.insert(key.clone(), reconcile(v, old_value));
                    }
                    None if old_value.is_null() => {
                        out.insert(key.clone(), Value::Null);
                    }
                    None => {}
                }
            }
            for (key, v) in new {
                let filler = v.is_null() || v.as_array().is_some_and(Vec::is_empty);
                if !filler {
                    out.insert(key, v);
                }
            }
            Value::Object(out)
        }
        (Value::Array(new), Value::Array(old)) => {
            let mut out = Vec::with_capacity(new.len());
            let mut old_iter = old.iter();
            for v in new {
                match old_iter.next() {
                    Some(o) => out.push(reconcile(v, o)),
                    None => out.push(v),
                }
            }
            Value::Array(out)
        }
        (Value::Number(n), Value::Number(o)) => {
            if n.as_f64() == o.as_f64() {
                Value::Number(o.clone())
            } else {
                Value::Number(n)
            }
        }
        (fresh, _) => fresh,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SAMPLE: &str = r#"{
  "id": 7,
  "map_id": "procthor/003_valunseen",
  "template_instruction_id": "template_2_000001",
  "object_count": 2,
  "objects": [{"order": 1, "object_id": 5, "name": "bed_1", "category": "bed", "center": [10.5, 3]}],
  "human_expert_trajectory": [[1, 1], [1, 2]],
  "start_pose": {"row": 1, "col": 1},
  "feasible": true,
  "name": "", "notes": "", "created_by": "ann",
  "hard_constraints": [
    {"constraint_id": "a", "kind": "must_pass", "shape": "circle", "center": [3, 4], "radius": 20,
     "width": 40, "height": 40, "order": 1, "source": "template_object", "object_id": 5,
     "scope": {"type": "global", "from_order": null, "to_order": null}, "label": "bed", "cells": []},
    {"constraint_id": "b", "kind": "must_avoid", "shape": "freeform", "center": [0.5, 1.25],
     "order": null, "object_id": null, "scope": {"type": "between_hard_constraints", "from_order": 1, "to_order": 2},
     "cells": [[0, 1], [1, 1]], "custom_annotator_key": {"x": 1}}
  ],
  "soft_constraints": [
    {"preference_type": "clearance", "constraint_id": "__global_clearance__", "D_ref": 1e-06,
     "reference_region": null, "shape": "freeform", "cells": []}
  ],
  "ordering": "obj1 -> obj2",
  "difficulty_level": "easy",
  "created_at": "2025-01-01T00:00:00",
  "updated_at": "2025-01-01T00:00:00",
  "instruction": "Go to the bed.",
  "unknown_trailing": [1, 2.5, "x"]
}"#;

    #[test]
    fn round_trip_is_identical_value_and_key_order() {
        let original: Value = serde_json::from_str(SAMPLE).unwrap();
        let ep = Episode::from_json_str(SAMPLE, "sample.json").unwrap();
        assert_eq!(ep.hard_constraints.len(), 2);
        assert_eq!(
            ep.hard_constraints[1].cells.as_deref(),
            Some(&[[0, 1], [1, 1]][..])
        );
        assert!(ep.hard_constraints[1].is_scoped());
        assert_eq!(ep.hard_constraints[0].radius, Some(20.0));
        let written = ep.to_value();
        assert_eq!(written, original);
        // Same text, key order included.
        assert_eq!(
            serde_json::to_string(&written).unwrap(),
            serde_json::to_string(&original).unwrap()
        );
    }

    #[test]
    fn whole_number_floats_are_read_as_integers_and_written_as_the_source_spelt_them() {
        let text = r#"{"hard_constraints": [{"kind": "must_pass", "shape": "freeform", "order": 1.0, "cells": [[223.0, 117.0]], "extra_note": 2.0}], "radius_note": 3.5}"#;
        let original: Value = serde_json::from_str(text).unwrap();
        let from_text = Episode::from_json_str(text, "a.json").unwrap();
        let from_value = Episode::from_value(original.clone(), "a.json").unwrap();
        assert_eq!(from_text, from_value);
        assert_eq!(
            from_text.hard_constraints[0].cells.as_deref(),
            Some(&[[223, 117]][..])
        );
        for ep in [&from_text, &from_value] {
            let written = serde_json::to_string(&ep.to_value()).unwrap();
            assert_eq!(written, serde_json::to_string(&original).unwrap());
            assert!(written.contains("[[223.0,117.0]]"), "{written}");
        }
    }

    #[test]
    fn m2rc_keys_round_trip_and_are_appended() {
        let mut ep = Episode::from_json_str(SAMPLE, "sample.json").unwrap();
        ep.m2rc_gold_program = Some("route { visit bed }".into());
        ep.m2rc_generation = Some(Generation {
            generator: "m2rc-suite".into(),
            version: "0.1.0".into(),
            seed: Some(42),
            ..Generation::default()
        });
        let text = ep.to_json_pretty();
        let v: Value = serde_json::from_str(&text).unwrap();
        let keys: Vec<&String> = v.as_object().unwrap().keys().collect();
        assert_eq!(keys.last().unwrap().as_str(), GENERATION_KEY);
        let back = Episode::from_json_str(&text, "x").unwrap();
        assert_eq!(
            back.m2rc_gold_program.as_deref(),
            Some("route { visit bed }")
        );
        assert_eq!(back.m2rc_generation.unwrap().seed, Some(42));
    }

    #[test]
    fn fresh_episode_writes_reference_nulls() {
        let mut avoid = HardConstraint::freeform("x", ConstraintKind::MustAvoid, vec![[1, 2]]);
        avoid.scope = Some(Scope::between(1, 2));
        let ep = Episode {
            hard_constraints: vec![avoid],
            ..Episode::default()
        };
        let v = ep.to_value();
        let h = &v["hard_constraints"][0];
        assert!(h.get("order").unwrap().is_null());
        assert!(h.get("object_id").unwrap().is_null());
        assert_eq!(h["scope"]["from_order"], 1);
        assert_eq!(h["kind"], "must_avoid");
        assert_eq!(h["cells"], serde_json::json!([[1, 2]]));
    }

    #[test]
    fn malformed_fields_are_named() {
        let bad = r#"{"hard_constraints": [{"kind": "must_pass", "shape": "hexagon"}]}"#;
        let err = Episode::from_json_str(bad, "ep.json")
            .unwrap_err()
            .to_string();
        assert!(err.contains("ep.json"), "{err}");
        assert!(err.contains("hard_constraints[0]"), "{err}");
        let bad = r#"{"soft_constraints": [{"cells": [[1.5, 2]]}]}"#;
        let err = Episode::from_json_str(bad, "ep.json")
            .unwrap_err()
            .to_string();
        assert!(err.contains("soft_constraints[0]"), "{err}");
        assert!(Episode::from_json_str("[1]", "ep.json").is_err());
        assert!(Episode::from_json_str("{", "ep.json").is_err());
    }

    #[test]
    fn instruction_id_is_zero_padded() {
        let ep = Episode {
            id: Some(12),
            ..Episode::default()
        };
        assert_eq!(ep.instruction_id().as_deref(), Some("instruction_000012"));
    }
}
