//! The JSON Schemas of the two catalog-id replies, generated from the same kind and shape lists
//! the validator reads ([`super::validate::KINDS`], [`super::validate::SHAPES`]), so the schema a
//! server's structured output is held to cannot drift from what m2rc accepts. What a schema
//! cannot say (ids that exist, arities per kind, a well-formed formula) the validator checks.

use super::validate::{KINDS, MAX_WITHIN_M, SHAPES};
use serde_json::{Value, json};

fn id() -> Value {
    json!({"type": "string", "pattern": "^(task_start|room_[0-9]+|object_[0-9]+)$"})
}

fn ids() -> Value {
    json!({"type": "array", "items": id(), "minItems": 1})
}

fn path_shape() -> Value {
    json!({
        "type": "object",
        "properties": {
            "type": {"enum": SHAPES},
            "direction": {"enum": ["clockwise", "counterclockwise"]},
        },
        "required": ["type"],
        "additionalProperties": false,
    })
}

fn common() -> serde_json::Map<String, Value> {
    let v = json!({
        "ref_ids": ids(),
        "spatial_scope_ids": ids(),
        "within_m": {"type": "number", "exclusiveMinimum": 0, "maximum": MAX_WITHIN_M},
        "relation": {"enum": ["closer_to", "farther_from"]},
        "path_shape": path_shape(),
        "source_text": {"type": "string"},
    });
    v.as_object().cloned().unwrap_or_default()
}

/// Direct ID's reply.
pub fn direct_id_schema() -> Value {
    let mut c = common();
    c.insert("kind".into(), json!({"enum": KINDS}));
    c.insert(
        "segment_ids".into(),
        json!({"type": "array", "items": {"type": "string"}}),
    );
    json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "m2rc Direct ID grounding",
        "type": "object",
        "properties": {
            "segments": {
                "type": "array",
                "minItems": 1,
                "items": {
                    "type": "object",
                    "properties": {"id": {"type": "string", "minLength": 1}, "target_id": id()},
                    "required": ["id", "target_id"],
                    "additionalProperties": false,
                },
            },
            "constraints": {
                "type": "array",
                "items": {
                    "type": "object",
                    "properties": c,
                    "required": ["kind", "ref_ids"],
                    "additionalProperties": false,
                },
            },
        },
        "required": ["segments"],
        "additionalProperties": false,
    })
}

/// Catalog-LTL's reply.
pub fn catalog_ltl_schema() -> Value {
    let mut p = common();
    let kinds: Vec<&str> = ["visit", "avoid"]
        .into_iter()
        .chain(KINDS.iter().copied().filter(|k| k.starts_with("prefer_")))
        .collect();
    p.insert(
        "name".into(),
        json!({"type": "string", "pattern": "^[A-Za-z0-9_]+$"}),
    );
    p.insert("kind".into(), json!({"enum": kinds}));
    p.insert(
        "during".into(),
        json!({"type": "array", "items": {"type": "string"}}),
    );
    json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "m2rc catalog-LTL grounding",
        "type": "object",
        "properties": {
            "formula": {"type": "string", "pattern": "^[A-Za-z0-9_ FGX!&|()◇□○¬∧∨]+$"},
            "propositions": {
                "type": "array",
                "items": {
                    "type": "object",
                    "properties": p,
                    "required": ["name", "kind", "ref_ids"],
                    "additionalProperties": false,
                },
            },
        },
        "required": ["formula", "propositions"],
        "additionalProperties": false,
    })
}
