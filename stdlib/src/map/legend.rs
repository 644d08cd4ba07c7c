//! `layer_legends`: the labels and colours the reference writes beside the layers. Evaluation
//! ignores them, but viewers of the reference project read them, so every category present in the
//! map gets an entry. Legends read from a file are kept and only completed.

use super::model::{MapExtra, SemanticMap};
use serde_json::{Map, Value, json};
use std::collections::BTreeSet;

/// Fixed room colours, so the same room category always looks the same.
fn room_color(category: &str) -> String {
    match category {
        "bathroom" => "#8ECAE6".into(),
        "bedroom" => "#FFB4A2".into(),
        "kitchen" => "#FFD166".into(),
        "living_room" => "#B5E48C".into(),
        other => hashed_color(other),
    }
}

/// A stable colour from the category name (FNV-1a hash -> hue), mid saturation and value.
pub fn hashed_color(name: &str) -> String {
    let mut h: u32 = 0x811c_9dc5;
    for b in name.bytes() {
        h ^= b as u32;
        h = h.wrapping_mul(0x0100_0193);
    }
    let hue = (h % 360) as f64;
    let (s, v) = (0.55, 0.85);
    let c = v * s;
    let x = c * (1.0 - ((hue / 60.0) % 2.0 - 1.0).abs());
    let m = v - c;
    let (r, g, b) = match (hue / 60.0) as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let to = |f: f64| ((f + m) * 255.0).round() as u8;
    format!("#{:02X}{:02X}{:02X}", to(r), to(g), to(b))
}

/// `living_room` -> `Living Room`.
pub fn label(category: &str) -> String {
    category
        .split('_')
        .filter(|w| !w.is_empty())
        .map(|w| {
            let mut cs = w.chars();
            match cs.next() {
                Some(f) => f.to_uppercase().chain(cs).collect::<String>(),
                None => String::new(),
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

fn complete(
    section: &mut Map<String, Value>,
    categories: &BTreeSet<&str>,
    color: impl Fn(&str) -> String,
) {
    for c in categories {
        if !section.contains_key(*c) {
            section.insert(c.to_string(), json!({"label": label(c), "color": color(c)}));
        }
    }
}

pub fn build_legends(map: &SemanticMap, extra: &MapExtra) -> Value {
    let mut legends = match &extra.layer_legends {
        Some(Value::Object(o)) => o.clone(),
        _ => Map::new(),
    };
    // The model stores free as 0, so a legend that says otherwise no longer describes the layer.
    let free_is_zero = legends
        .get("occupancy")
        .and_then(|o| o.pointer("/free/value"))
        .and_then(Value::as_u64)
        == Some(0);
    if !free_is_zero {
        legends.insert(
            "occupancy".into(),
            json!({
                "free": {"value": 0, "label": "Free Space", "color": "#FFFFFF"},
                "obstacle": {"value": 1, "label": "Obstacle", "color": "#111111"},
                "unknown": {"value": 2, "label": "Unknown", "color": "#9E9E9E"},
            }),
        );
    }
    let rooms: BTreeSet<&str> = map.rooms.iter().map(|r| r.category.as_str()).collect();
    let objects: BTreeSet<&str> = map.objects.iter().map(|o| o.category.as_str()).collect();
    for (key, cats, is_room) in [
        ("room_categories", rooms, true),
        ("object_categories", objects, false),
    ] {
        let mut section = match legends.get(key) {
            Some(Value::Object(o)) => o.clone(),
            _ => Map::new(),
        };
        if is_room {
            complete(&mut section, &cats, room_color);
        } else {
            complete(&mut section, &cats, hashed_color);
        }
        legends.insert(key.into(), Value::Object(section));
    }
    Value::Object(legends)
}
