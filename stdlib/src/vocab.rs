//! Category vocabulary: the Map2Route benchmark's 97 object and 4 room categories, and the
//! everyday words people (and language models) use for them.
//!
//! A program is checked against a map's own vocabulary when a map is given, otherwise against the
//! benchmark's. Synonyms are resolved in one of two ways: an unambiguous synonym (`tv`,
//! `houseplant`, `countertop`) names exactly one category and the checker accepts it with a
//! warning whose fix writes the canonical name; an ambiguous word (`table`, `lamp`) names several
//! and the checker rejects it, offering every candidate.
//!
//! `tv` means `television`, not `tv_stand`: "stay close to the TV" in the benchmark's instructions
//! is about the screen; "TV stand" is always written out.

use crate::map::SemanticMap;
use std::collections::BTreeSet;

/// The benchmark's object and room categories; the list itself lives in `map::vocab` (one copy).
pub use crate::map::vocab::{
    OBJECT_CATEGORIES as BENCHMARK_OBJECT_CATEGORIES, ROOM_CATEGORIES as BENCHMARK_ROOM_CATEGORIES,
};

/// Everyday words and the categories they may mean. One candidate: resolved; several: ambiguous.
pub const SYNONYMS: &[(&str, &[&str])] = &[
    ("tv", &["television"]),
    ("telly", &["television"]),
    ("plant", &["house_plant"]),
    ("houseplant", &["house_plant"]),
    ("potted_plant", &["house_plant"]),
    ("table", &["dining_table", "side_table", "desk"]),
    ("coffee_table", &["side_table"]),
    ("nightstand", &["side_table"]),
    ("night_stand", &["side_table"]),
    ("counter", &["counter_top"]),
    ("countertop", &["counter_top"]),
    ("kitchen_counter", &["counter_top"]),
    ("lamp", &["floor_lamp", "desk_lamp"]),
    ("basin", &["sink_basin"]),
    ("washbasin", &["sink_basin"]),
    ("refrigerator", &["fridge"]),
    ("couch", &["sofa"]),
    ("armchair", &["arm_chair"]),
    ("trash_can", &["garbage_can"]),
    ("trashcan", &["garbage_can"]),
    ("bin", &["garbage_can"]),
    ("garbage", &["garbage_can"]),
    ("wastebasket", &["garbage_can"]),
    ("trash_bag", &["garbage_bag"]),
    ("basketball", &["basket_ball"]),
    ("bat", &["baseball_bat"]),
    ("racket", &["tennis_racket"]),
    ("phone", &["cell_phone"]),
    ("cellphone", &["cell_phone"]),
    ("remote", &["remote_control"]),
    ("hamper", &["laundry_hamper"]),
    ("dryer", &["clothes_dryer"]),
    ("washer", &["washing_machine"]),
    ("vacuum", &["vacuum_cleaner"]),
    ("teddy", &["teddy_bear"]),
    ("door", &["doorway"]),
    ("bookshelf", &["shelf"]),
    ("shelves", &["shelf"]),
    ("cupboard", &["cabinet"]),
    ("picture", &["painting"]),
    ("toilet_roll", &["toilet_paper"]),
    ("soap", &["soap_bar", "soap_bottle"]),
    ("sponge", &["dish_sponge"]),
    ("keys", &["key_chain"]),
    ("coffee_maker", &["coffee_machine"]),
    ("tv_table", &["tv_stand"]),
    ("bath", &["bathroom"]),
    ("restroom", &["bathroom"]),
    ("toilet_room", &["bathroom"]),
    ("washroom", &["bathroom"]),
    ("lounge", &["living_room"]),
    ("livingroom", &["living_room"]),
    ("sitting_room", &["living_room"]),
    ("bed_room", &["bedroom"]),
];

/// Is a category an object or a room category?
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum CategoryKind {
    Object,
    Room,
}

/// Where a vocabulary comes from; decides the wording of "not in the vocabulary" diagnostics.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum VocabSource {
    Benchmark,
    /// The categories present in this map.
    Map(String),
}

/// The categories a program may name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Vocabulary {
    pub objects: BTreeSet<String>,
    pub rooms: BTreeSet<String>,
    pub source: VocabSource,
}

/// What a category word means in a vocabulary.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Lookup {
    /// A category of this vocabulary.
    Found(CategoryKind),
    /// An unambiguous synonym of a category of this vocabulary.
    Synonym(String, CategoryKind),
    /// A synonym of several categories (only those present in this vocabulary are listed).
    Ambiguous(Vec<String>),
    /// A benchmark category (or a synonym of one) that this map does not have.
    NotInMap(String, CategoryKind),
    Unknown,
}

impl Vocabulary {
    pub fn benchmark() -> Self {
        Vocabulary {
            objects: BENCHMARK_OBJECT_CATEGORIES
                .iter()
                .map(|s| s.to_string())
                .collect(),
            rooms: BENCHMARK_ROOM_CATEGORIES
                .iter()
                .map(|s| s.to_string())
                .collect(),
            source: VocabSource::Benchmark,
        }
    }

    /// The categories that actually occur in the map.
    pub fn from_map(map: &SemanticMap) -> Self {
        Vocabulary {
            objects: map.objects.iter().map(|o| o.category.clone()).collect(),
            rooms: map.rooms.iter().map(|r| r.category.clone()).collect(),
            source: VocabSource::Map(map.map_id.clone()),
        }
    }

    pub fn kind(&self, name: &str) -> Option<CategoryKind> {
        if self.objects.contains(name) {
            Some(CategoryKind::Object)
        } else if self.rooms.contains(name) {
            Some(CategoryKind::Room)
        } else {
            None
        }
    }

    /// Classifies a word as written in a program.
    pub fn lookup(&self, word: &str) -> Lookup {
        if let Some(k) = self.kind(word) {
            return Lookup::Found(k);
        }
        let lower = word.to_ascii_lowercase();
        if lower != word
            && let Some(k) = self.kind(&lower)
        {
            return Lookup::Synonym(lower, k);
        }
        if let Some((_, cands)) = SYNONYMS.iter().find(|(w, _)| *w == lower) {
            let present: Vec<String> = cands
                .iter()
                .filter(|c| self.kind(c).is_some())
                .map(|c| c.to_string())
                .collect();
            return match present.as_slice() {
                [one] => {
                    Lookup::Synonym(one.clone(), self.kind(one).unwrap_or(CategoryKind::Object))
                }
                [] => match benchmark_kind(cands[0]) {
                    Some(k) if cands.len() == 1 => Lookup::NotInMap(cands[0].to_string(), k),
                    _ => Lookup::Unknown,
                },
                _ => Lookup::Ambiguous(present),
            };
        }
        if let Some(k) = benchmark_kind(&lower) {
            return Lookup::NotInMap(lower, k);
        }
        Lookup::Unknown
    }

    /// Every category name, objects first, each sorted.
    pub fn all(&self) -> impl Iterator<Item = (&str, CategoryKind)> {
        self.objects
            .iter()
            .map(|s| (s.as_str(), CategoryKind::Object))
            .chain(self.rooms.iter().map(|s| (s.as_str(), CategoryKind::Room)))
    }
}

/// The kind of a benchmark category, whatever the current vocabulary.
pub fn benchmark_kind(name: &str) -> Option<CategoryKind> {
    if BENCHMARK_OBJECT_CATEGORIES.contains(&name) {
        Some(CategoryKind::Object)
    } else if BENCHMARK_ROOM_CATEGORIES.contains(&name) {
        Some(CategoryKind::Room)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn benchmark_vocabulary_is_sorted_unique_and_complete() {
        let v = Vocabulary::benchmark();
        assert_eq!(v.objects.len(), 97);
        assert_eq!(v.rooms.len(), 4);
        assert!(BENCHMARK_OBJECT_CATEGORIES.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn matches_the_reference_statistics_file() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../shared/reference/map2route-evaluation-statistics.json"
        );
        let Ok(text) = std::fs::read_to_string(path) else {
            return;
        };
        let json: serde_json::Value = serde_json::from_str(&text).unwrap();
        let objs: Vec<&str> = json["object_categories"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_str().unwrap())
            .collect();
        let rooms: Vec<&str> = json["room_categories"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_str().unwrap())
            .collect();
        assert_eq!(objs, BENCHMARK_OBJECT_CATEGORIES);
        assert_eq!(rooms, BENCHMARK_ROOM_CATEGORIES);
    }

    #[test]
    fn synonyms_point_at_benchmark_categories() {
        for (word, cands) in SYNONYMS {
            assert!(
                benchmark_kind(word).is_none(),
                "{word} is itself a category"
            );
            for c in *cands {
                assert!(benchmark_kind(c).is_some(), "{word} -> {c}");
            }
        }
    }

    #[test]
    fn lookup_classifies_words() {
        let v = Vocabulary::benchmark();
        assert_eq!(v.lookup("bed"), Lookup::Found(CategoryKind::Object));
        assert_eq!(v.lookup("kitchen"), Lookup::Found(CategoryKind::Room));
        assert_eq!(
            v.lookup("tv"),
            Lookup::Synonym("television".into(), CategoryKind::Object)
        );
        assert_eq!(
            v.lookup("Sofa"),
            Lookup::Synonym("sofa".into(), CategoryKind::Object)
        );
        assert_eq!(
            v.lookup("table"),
            Lookup::Ambiguous(vec![
                "dining_table".into(),
                "side_table".into(),
                "desk".into()
            ])
        );
        assert_eq!(v.lookup("chiar"), Lookup::Unknown);
        let small = Vocabulary {
            objects: ["desk".to_string(), "bed".to_string()]
                .into_iter()
                .collect(),
            rooms: ["kitchen".to_string()].into_iter().collect(),
            source: VocabSource::Map("m".into()),
        };
        assert_eq!(
            small.lookup("table"),
            Lookup::Synonym("desk".into(), CategoryKind::Object)
        );
        assert_eq!(
            small.lookup("sofa"),
            Lookup::NotInMap("sofa".into(), CategoryKind::Object)
        );
        assert_eq!(
            small.lookup("couch"),
            Lookup::NotInMap("sofa".into(), CategoryKind::Object)
        );
    }
}
