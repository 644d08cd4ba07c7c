//! The instance inventory of atomic propositions (APs) the LTL-family baselines ground into: one
//! AP per room (`room_<id>`) and per object (`object_<id>`), as the adaptation's flat inventory
//! does. Sorted by (category, id), the adaptation's order, so every listing and every tie-break
//! that follows it is deterministic.

use m2rc_stdlib::map::SemanticMap;
use serde::Serialize;

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind", content = "id")]
pub enum ApKind {
    Room(u32),
    Object(u32),
}

/// One atomic proposition: a room or an object instance of the map.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Ap {
    /// `room_<id>` or `object_<id>`.
    pub name: String,
    pub kind: ApKind,
    pub category: String,
    /// The map's instance name (`painting_2`, `bedroom_1`).
    pub label: String,
    /// The room the instance is in (a room is in itself).
    pub room: Option<u32>,
    pub room_category: Option<String>,
    /// Centre `[row, col]` in cells (a room's: the mean of its room-layer cells).
    pub center: [f64; 2],
    pub attributes: Vec<String>,
}

impl Ap {
    pub fn is_room(&self) -> bool {
        matches!(self.kind, ApKind::Room(_))
    }

    /// The category in words (`tv_stand` -> `tv stand`).
    pub fn category_words(&self) -> String {
        self.category.replace('_', " ")
    }
}

#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Inventory {
    pub aps: Vec<Ap>,
}

impl Inventory {
    /// Every room and object of `map` (objects without a footprint included: their centre
    /// still labels cells).
    pub fn from_map(map: &SemanticMap) -> Inventory {
        let n = map.n();
        let mut sums = std::collections::BTreeMap::<u32, (f64, f64, f64)>::new();
        for (i, &room) in map.room_layer.data().iter().enumerate() {
            if room != 0 {
                let e = sums.entry(room).or_default();
                e.0 += (i / n) as f64;
                e.1 += (i % n) as f64;
                e.2 += 1.0;
            }
        }
        let room_category =
            |id: Option<u32>| id.and_then(|r| map.room(r)).map(|r| r.category.clone());
        let mut aps: Vec<Ap> = map
            .rooms
            .iter()
            .map(|r| {
                let (sr, sc, k) = sums.get(&r.id).copied().unwrap_or((0.0, 0.0, 0.0));
                Ap {
                    name: format!("room_{}", r.id),
                    kind: ApKind::Room(r.id),
                    category: r.category.clone(),
                    label: r.name.clone(),
                    room: Some(r.id),
                    room_category: Some(r.category.clone()),
                    center: if k > 0.0 {
                        [sr / k, sc / k]
                    } else {
                        [0.0, 0.0]
                    },
                    attributes: r.attributes.clone(),
                }
            })
            .collect();
        aps.extend(map.objects.iter().map(|o| Ap {
            name: format!("object_{}", o.id),
            kind: ApKind::Object(o.id),
            category: o.category.clone(),
            label: o.name.clone(),
            room: o.room,
            room_category: room_category(o.room),
            center: o.center,
            attributes: o.attributes.iter().take(4).cloned().collect(),
        }));
        aps.sort_by(|a, b| (&a.category, a.kind).cmp(&(&b.category, b.kind)));
        Inventory { aps }
    }

    pub fn get(&self, name: &str) -> Option<&Ap> {
        self.aps.iter().find(|a| a.name == name)
    }

    pub fn by_kind(&self, kind: ApKind) -> Option<&Ap> {
        self.aps.iter().find(|a| a.kind == kind)
    }

    pub fn len(&self) -> usize {
        self.aps.len()
    }

    pub fn is_empty(&self) -> bool {
        self.aps.is_empty()
    }
}
