//! LTLCodeGen's map abstraction: an inventory of AP names with their categories, with no
//! coordinates and no room of each object (reference §7), and the label map that makes each AP
//! true on grid cells (Lang2LTL's: a room on its traversable cells, an object on the traversable
//! cells within 1 m of its centre).

use crate::osgllm::graph::nearest_traversable;
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use serde_json::{Value, json};
use std::collections::{BTreeMap, BTreeSet};

/// Objects listed in the prompt.
pub const MAX_PROMPT_OBJECTS: usize = 120;
/// An object AP is true within this many cells of the object's centre (1 m).
pub const OBJECT_LABEL_RADIUS: u32 = 20;
/// How far the nearest traversable cell may be when none is within the radius: max(80, 4 r).
pub const NEAREST_FREE_CELLS: u32 = 80;

#[derive(Clone, Debug)]
pub struct Inventory {
    /// `(ap, category)` of every room, by id.
    pub rooms: Vec<(String, String)>,
    /// `(ap, category)` of the listed objects, by id.
    pub objects: Vec<(String, String)>,
    pub room_category_counts: BTreeMap<String, usize>,
    pub object_category_counts: BTreeMap<String, usize>,
    listed: BTreeSet<String>,
}

impl Inventory {
    /// All rooms; objects: the first instance of each category (by category, then id), then
    /// more by id, up to [`MAX_PROMPT_OBJECTS`], listed by id.
    pub fn build(map: &SemanticMap) -> Inventory {
        let rooms: Vec<(String, String)> = map
            .rooms
            .iter()
            .map(|r| (format!("room_{}", r.id), r.category.clone()))
            .collect();
        let mut chosen: BTreeSet<u32> = BTreeSet::new();
        let mut firsts: BTreeMap<&str, u32> = BTreeMap::new();
        for o in &map.objects {
            let e = firsts.entry(o.category.as_str()).or_insert(o.id);
            *e = (*e).min(o.id);
        }
        for id in firsts.values().take(MAX_PROMPT_OBJECTS) {
            chosen.insert(*id);
        }
        for o in &map.objects {
            if chosen.len() >= MAX_PROMPT_OBJECTS {
                break;
            }
            chosen.insert(o.id);
        }
        let objects: Vec<(String, String)> = map
            .objects
            .iter()
            .filter(|o| chosen.contains(&o.id))
            .map(|o| (format!("object_{}", o.id), o.category.clone()))
            .collect();
        let mut room_category_counts = BTreeMap::new();
        for r in &map.rooms {
            *room_category_counts.entry(r.category.clone()).or_insert(0) += 1;
        }
        let mut object_category_counts = BTreeMap::new();
        for o in &map.objects {
            *object_category_counts
                .entry(o.category.clone())
                .or_insert(0) += 1;
        }
        let listed = rooms
            .iter()
            .chain(&objects)
            .map(|(ap, _)| ap.clone())
            .collect();
        Inventory {
            rooms,
            objects,
            room_category_counts,
            object_category_counts,
            listed,
        }
    }

    pub fn is_listed(&self, ap: &str) -> bool {
        self.listed.contains(ap)
    }

    /// The first listed AP of an object category (the duplicate-category rule).
    pub fn first_of(&self, category: &str) -> Option<&str> {
        self.objects
            .iter()
            .find(|(_, c)| c == category)
            .map(|(ap, _)| ap.as_str())
    }

    /// The inventory as the prompt shows it.
    pub fn prompt_json(&self) -> Value {
        let line = |(ap, c): &(String, String)| format!("{ap}: {c}");
        json!({
            "rooms": self.rooms.iter().map(line).collect::<Vec<_>>(),
            "objects": self.objects.iter().map(line).collect::<Vec<_>>(),
            "room_category_counts": self.room_category_counts,
            "object_category_counts": self.object_category_counts,
            "duplicate_category_rule": "when several instances share a category, use the first AP in listed instance-id order",
            "usage_rule": "use only the AP names listed above",
        })
    }
}

/// The cells where an AP (`room_<id>` or `object_<id>`) is true, ascending row-major indices.
pub fn label_cells(map: &SemanticMap, traversable: &[bool], ap: &str) -> Vec<u32> {
    let n = map.n();
    if let Some(id) = ap.strip_prefix("room_").and_then(|x| x.parse::<u32>().ok()) {
        return (0..n * n)
            .filter(|&i| traversable[i] && map.room_layer.data().get(i) == Some(&id))
            .map(|i| i as u32)
            .collect();
    }
    let Some(o) = ap
        .strip_prefix("object_")
        .and_then(|x| x.parse::<u32>().ok())
        .and_then(|id| map.object(id))
    else {
        return Vec::new();
    };
    if n == 0 {
        return Vec::new();
    }
    let lim = (n - 1) as f64;
    let (cr, cc) = (o.center[0].clamp(0.0, lim), o.center[1].clamp(0.0, lim));
    let r = OBJECT_LABEL_RADIUS as f64;
    let mut out = Vec::new();
    for row in (cr - r).floor().max(0.0) as usize..=((cr + r).ceil().min(lim) as usize) {
        for col in (cc - r).floor().max(0.0) as usize..=((cc + r).ceil().min(lim) as usize) {
            let i = row * n + col;
            if traversable[i] && (row as f64 - cr).hypot(col as f64 - cc) <= r {
                out.push(i as u32);
            }
        }
    }
    if out.is_empty() {
        let seed = Cell::new(cr.round() as u32, cc.round() as u32);
        let radius = NEAREST_FREE_CELLS.max(4 * OBJECT_LABEL_RADIUS);
        if let Some(c) = nearest_traversable(traversable, n, seed, radius) {
            out.push((c.row as usize * n + c.col as usize) as u32);
        }
    }
    out
}
