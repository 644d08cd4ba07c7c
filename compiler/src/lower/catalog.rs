//! The scene catalog the model sees: which room and object categories the map has and how many of
//! each, as the reference does. Never ids, coordinates, cells or sizes: the program must ground on
//! the map through queries, not copy answers out of the prompt.

use m2rc_stdlib::map::SemanticMap;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// How much of the scene the prompt shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CatalogMode {
    /// Room and object categories with their counts (the reference's view).
    #[default]
    Counts,
    /// Additionally, the object categories of each room (rooms numbered per category, not by id).
    PerRoom,
}

impl std::str::FromStr for CatalogMode {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "counts" => Ok(CatalogMode::Counts),
            "per-room" => Ok(CatalogMode::PerRoom),
            _ => Err(format!("catalog `{s}` is not one of counts, per-room")),
        }
    }
}

/// One room of a per-room catalog: its category, its number among rooms of that category, and
/// the object categories in it with counts.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct RoomEntry {
    pub category: String,
    pub ordinal: usize,
    pub objects: BTreeMap<String, usize>,
}

/// Categories and counts of one map, in name order (deterministic).
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct SceneCatalog {
    pub room_counts: BTreeMap<String, usize>,
    pub object_counts: BTreeMap<String, usize>,
    /// Present in [`CatalogMode::PerRoom`] only.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub rooms: Vec<RoomEntry>,
}

impl SceneCatalog {
    pub fn from_map(map: &SemanticMap, mode: CatalogMode) -> Self {
        let mut room_counts: BTreeMap<String, usize> = BTreeMap::new();
        for r in &map.rooms {
            *room_counts.entry(r.category.clone()).or_default() += 1;
        }
        let mut object_counts: BTreeMap<String, usize> = BTreeMap::new();
        for o in &map.objects {
            *object_counts.entry(o.category.clone()).or_default() += 1;
        }
        let mut rooms = Vec::new();
        if mode == CatalogMode::PerRoom {
            let mut seen: BTreeMap<&str, usize> = BTreeMap::new();
            let mut sorted: Vec<_> = map.rooms.iter().collect();
            sorted.sort_by_key(|r| r.id);
            for r in sorted {
                let ordinal = seen.entry(r.category.as_str()).or_default();
                *ordinal += 1;
                let mut objects: BTreeMap<String, usize> = BTreeMap::new();
                for o in map.objects.iter().filter(|o| o.room == Some(r.id)) {
                    *objects.entry(o.category.clone()).or_default() += 1;
                }
                rooms.push(RoomEntry {
                    category: r.category.clone(),
                    ordinal: *ordinal,
                    objects,
                });
            }
        }
        SceneCatalog {
            room_counts,
            object_counts,
            rooms,
        }
    }

    /// The catalog section of the prompt.
    pub fn render(&self) -> String {
        let list = |m: &BTreeMap<String, usize>| m.keys().cloned().collect::<Vec<_>>().join(", ");
        let counts = |m: &BTreeMap<String, usize>| {
            m.iter()
                .map(|(k, n)| format!("{k} {n}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let mut out = format!(
            "Room categories: {}\nObject categories: {}\nRoom counts: {}\nObject counts: {}\n",
            list(&self.room_counts),
            list(&self.object_counts),
            counts(&self.room_counts),
            counts(&self.object_counts)
        );
        if !self.rooms.is_empty() {
            out.push_str("Objects per room (rooms are numbered within their category):\n");
            for r in &self.rooms {
                out.push_str(&format!(
                    "- {} {}: {}\n",
                    r.category,
                    r.ordinal,
                    if r.objects.is_empty() {
                        "(no objects)".to_string()
                    } else {
                        counts(&r.objects)
                    }
                ));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn demo_catalog_has_counts_and_no_ids() {
        let map = m2rc_stdlib::demo::demo_map().expect("demo map");
        let c = SceneCatalog::from_map(&map, CatalogMode::Counts);
        assert_eq!(c.room_counts.values().sum::<usize>(), map.rooms.len());
        assert_eq!(c.object_counts.values().sum::<usize>(), map.objects.len());
        let text = c.render();
        assert!(text.contains("Room categories: "), "{text}");
        assert!(!text.contains("Objects per room"));
        let p = SceneCatalog::from_map(&map, CatalogMode::PerRoom);
        assert_eq!(p.rooms.len(), map.rooms.len());
        assert!(p.render().contains("Objects per room"));
        for o in &map.objects {
            assert!(!text.contains(&format!("object_{}", o.id)));
        }
    }
}
