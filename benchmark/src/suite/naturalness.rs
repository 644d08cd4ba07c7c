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
//! * rooms described more than once in one episode (instead of "that room");
//! * preference subjects of a category a destination names ("go to the spray bottle that is not
//!   on a shelf", then "stay closer to the spray bottle than to the mug" about another one),
//!   which a reader takes for the destination's own;
//! * must-avoids of a category a destination names ("go to the armchair", then "keep out of the
//!   area around the armchair" about another one), which reads as avoiding the destination;
//! * objects that are the subject of two preferences (said twice, perhaps in other words, it
//!   reads as two things), counted from the episode's soft constraints.

use serde::Serialize;
use serde_json::Value;

#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Naturalness {
    pub stacked_same_category_rooms: usize,
    pub singleton_superlatives: usize,
    pub circular_references: usize,
    pub rooms_described_more_than_once: usize,
    pub preference_subjects_named_like_a_destination: usize,
    pub must_avoids_named_like_a_destination: usize,
    pub objects_in_two_preferences: usize,
}

impl Naturalness {
    pub fn total(&self) -> usize {
        self.stacked_same_category_rooms
            + self.singleton_superlatives
            + self.circular_references
            + self.rooms_described_more_than_once
            + self.preference_subjects_named_like_a_destination
            + self.must_avoids_named_like_a_destination
            + self.objects_in_two_preferences
    }

    /// Adds the objects that more than one of an episode's `soft_constraints` is about.
    pub fn add_soft(&mut self, soft_constraints: Option<&Value>) {
        let mut ids: Vec<u64> = soft_constraints
            .and_then(Value::as_array)
            .map(Vec::as_slice)
            .unwrap_or(&[])
            .iter()
            .flat_map(|c| {
                let mut own: Vec<u64> = c
                    .get("object_ids")
                    .and_then(Value::as_array)
                    .map(|a| a.iter().filter_map(Value::as_u64).collect())
                    .unwrap_or_default();
                own.sort_unstable();
                own.dedup();
                own
            })
            .collect();
        ids.sort_unstable();
        let mut repeated: Vec<u64> = ids
            .windows(2)
            .filter(|w| w[0] == w[1])
            .map(|w| w[0])
            .collect();
        repeated.dedup();
        self.objects_in_two_preferences += repeated.len();
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
        let refs = g
            .get("references")
            .and_then(Value::as_array)
            .map(Vec::as_slice)
            .unwrap_or(&[]);
        let role = |r: &Value| {
            r.get("role")
                .and_then(Value::as_str)
                .unwrap_or("")
                .to_string()
        };
        let named: Vec<String> = refs
            .iter()
            .filter(|r| role(r).starts_with("destination"))
            .flat_map(|r| strings(r, "object_categories"))
            .collect();
        let named_like_a_destination = |r: &&Value| {
            r.get("category")
                .and_then(Value::as_str)
                .is_some_and(|c| named.iter().any(|n| n == c))
        };
        self.preference_subjects_named_like_a_destination += refs
            .iter()
            .filter(|r| role(r).ends_with("preference"))
            .filter(named_like_a_destination)
            .count();
        self.must_avoids_named_like_a_destination += refs
            .iter()
            .filter(|r| role(r).starts_with("must-avoid"))
            .filter(named_like_a_destination)
            .count();
        for r in refs {
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
                {"role": "destination 1", "category": "bed", "room_categories": ["bedroom"], "object_categories": ["bed", "pillow"], "superlative_over": []},
                {"role": "near preference", "category": "pillow", "room_categories": [], "object_categories": ["pillow"], "superlative_over": []},
                {"role": "far preference", "category": "sofa", "room_categories": [], "object_categories": ["sofa"], "superlative_over": []},
                {"role": "must-avoid", "category": "bed", "room_categories": [], "object_categories": ["bed"], "superlative_over": []},
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
                preference_subjects_named_like_a_destination: 1,
                must_avoids_named_like_a_destination: 1,
                objects_in_two_preferences: 0,
            }
        );
        assert_eq!(n.total(), 6);
        // Object 4 is in two preferences (a through passing 4 and 9 counts it once itself).
        n.add_soft(Some(&json!([
            {"object_ids": [4]},
            {"object_ids": [4, 9, 4]},
            {"object_ids": [7]},
            {"object_ids": []},
        ])));
        assert_eq!(n.objects_in_two_preferences, 1);
    }
}
