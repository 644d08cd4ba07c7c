//! Naturalness counters: things a person would never write, counted from the structured facts
//! every episode records (`m2rc_generation.references`, `.room_descriptions`), so the counts do
//! not depend on parsing the English.
//!
//! * stacked rooms: one reference naming two rooms of the same category ("the smallest living
//!   room in the biggest living room");
//! * singleton superlatives: a superlative over fewer than two rooms ("the largest bathroom" in a
//!   house with one bathroom);
//! * circular references: a chain naming one category twice ("the sink closest to the toilet
//!   closest to the sink");
//! * rooms described more than once in one episode (instead of "that room").

use serde::Serialize;
use serde_json::Value;

#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Naturalness {
    pub stacked_same_category_rooms: usize,
    pub singleton_superlatives: usize,
    pub circular_references: usize,
    pub rooms_described_more_than_once: usize,
}

impl Naturalness {
    pub fn total(&self) -> usize {
        self.stacked_same_category_rooms
            + self.singleton_superlatives
            + self.circular_references
            + self.rooms_described_more_than_once
    }

    /// Adds the counts of one episode's generation record.
    pub fn add(&mut self, generation: Option<&Value>) {
        let Some(g) = generation else { return };
        let strings = |v: &Value, k: &str| -> Vec<String> {
            v.get(k)
                .and_then(Value::as_array)
                .map(|a| {
                    a.iter()
                        .filter_map(|x| x.as_str().map(str::to_string))
                        .collect()
                })
                .unwrap_or_default()
        };
        let has_repeat = |mut v: Vec<String>| {
            v.sort();
            v.windows(2).any(|w| w[0] == w[1])
        };
        for r in g
            .get("references")
            .and_then(Value::as_array)
            .map(Vec::as_slice)
            .unwrap_or(&[])
        {
            if has_repeat(strings(r, "room_categories")) {
                self.stacked_same_category_rooms += 1;
            }
            if has_repeat(strings(r, "object_categories")) {
                self.circular_references += 1;
            }
            let singles = r
                .get("superlative_over")
                .and_then(Value::as_array)
                .map(|a| {
                    a.iter()
                        .filter(|n| n.as_u64().is_some_and(|n| n < 2))
                        .count()
                })
                .unwrap_or(0);
            self.singleton_superlatives += singles;
        }
        if let Some(m) = g.get("room_descriptions").and_then(Value::as_object) {
            self.rooms_described_more_than_once += m
                .values()
                .filter(|n| n.as_u64().is_some_and(|n| n > 1))
                .count();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn counts_each_kind() {
        let mut n = Naturalness::default();
        n.add(Some(&json!({
            "references": [
                {"room_categories": ["living_room", "living_room"], "object_categories": ["chair"], "superlative_over": [2, 2]},
                {"room_categories": [], "object_categories": ["sink", "toilet", "sink"], "superlative_over": [1]},
                {"room_categories": ["bedroom"], "object_categories": ["bed"], "superlative_over": []},
            ],
            "room_descriptions": {"3": 2, "4": 1},
        })));
        assert_eq!(
            n,
            Naturalness {
                stacked_same_category_rooms: 1,
                singleton_superlatives: 1,
                circular_references: 1,
                rooms_described_more_than_once: 1,
            }
        );
        assert_eq!(n.total(), 4);
    }
}
