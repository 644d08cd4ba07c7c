//! LTLCodeGen's map abstraction: the prompt's listing of AP names with their categories, with no
//! coordinates and no room of each object (reference §7), over the crate's instance inventory;
//! and the label map that makes each AP true on grid cells (the shared one, Lang2LTL's: a room
//! on its traversable cells, an object on the traversable cells within 1 m of its centre).

use crate::common::inventory::Inventory as Shared;
use crate::common::labels;
use m2rc_stdlib::map::SemanticMap;
use serde_json::{Value, json};
use std::collections::{BTreeMap, BTreeSet};

/// Objects listed in the prompt.
pub const MAX_PROMPT_OBJECTS: usize = 120;

#[derive(Clone, Debug)]
pub struct Inventory {
    /// Every room and object of the map (the crate's instance inventory).
    pub shared: Shared,
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
            shared: Shared::from_map(map),
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

/// The cells where an AP (`room_<id>` or `object_<id>`) is true, ascending row-major indices:
/// the shared label map ([`labels::label_cells`]) at the 1 m object radius.
pub fn label_cells(map: &SemanticMap, inv: &Inventory, ap: &str) -> Vec<u32> {
    let n = map.n();
    inv.shared.get(ap).map_or_else(Vec::new, |a| {
        labels::label_cells(map, a, labels::OBJECT_LABEL_RADIUS_CELLS)
            .into_iter()
            .map(|c| (c.row as usize * n + c.col as usize) as u32)
            .collect()
    })
}
