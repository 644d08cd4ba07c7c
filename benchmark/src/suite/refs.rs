//! Referring expressions: descriptions of one object or room that single it out on a map.
//!
//! A description is a small tree (category, room, parent, anchor) that is rendered twice, once as
//! English and once as a `.m2r` expression, so the instruction and its gold program can never
//! drift apart. Each description is resolved here with the plain map semantics before it is kept
//! (exactly one match, with a clear margin for "nearest"), and the compiler later resolves the
//! gold program again as the validity check.

use super::index::{MapIndex, category_words};
use rand::Rng;
use rand::seq::IndexedRandom;
use rand_chacha::ChaCha8Rng;
use std::collections::HashMap;

/// A "nearest" reference is kept only when the runner-up is this much farther, under both the
/// centroid and the footprint distance, so that it does not hinge on the distance definition.
const NEAREST_MARGIN: f64 = 1.25;

#[derive(Clone, Debug, PartialEq)]
pub enum RoomRef {
    /// The only room of its category: "the kitchen".
    Unique { cat: String },
    /// "the largest bedroom".
    Largest { cat: String },
    /// "the smallest bathroom".
    Smallest { cat: String },
    /// The only room of its category holding an object of `obj_cat`: "the bedroom with the desk".
    Containing { cat: String, obj_cat: String },
}

#[derive(Clone, Debug, PartialEq)]
pub enum ObjRef {
    /// The only object of its category: "the fridge".
    Unique { cat: String },
    /// "the bed in the largest bedroom".
    InRoom { cat: String, room: RoomRef },
    /// "the laptop on the desk".
    On { cat: String, parent: Box<ObjRef> },
    /// "the chair nearest to the bed", optionally limited to a room.
    Nearest {
        cat: String,
        room: Option<RoomRef>,
        anchor: Box<ObjRef>,
    },
}

impl RoomRef {
    /// Number of noun phrases (entities) mentioned.
    pub fn depth(&self) -> u32 {
        match self {
            RoomRef::Containing { .. } => 2,
            _ => 1,
        }
    }

    pub fn category(&self) -> &str {
        match self {
            RoomRef::Unique { cat }
            | RoomRef::Largest { cat }
            | RoomRef::Smallest { cat }
            | RoomRef::Containing { cat, .. } => cat,
        }
    }

    pub fn m2r(&self) -> String {
        match self {
            RoomRef::Unique { cat } => format!("rooms({cat}).only()"),
            RoomRef::Largest { cat } => format!("rooms({cat}).largest()"),
            RoomRef::Smallest { cat } => format!("rooms({cat}).smallest()"),
            RoomRef::Containing { cat, obj_cat } => {
                format!("rooms({cat}).containing(objects({obj_cat})).only()")
            }
        }
    }

    pub fn text(&self, rng: &mut ChaCha8Rng) -> String {
        match self {
            RoomRef::Unique { cat } => format!("the {}", category_words(cat)),
            RoomRef::Largest { cat } => {
                let adj = ["largest", "biggest"]
                    .choose(rng)
                    .copied()
                    .unwrap_or("largest");
                format!("the {adj} {}", category_words(cat))
            }
            RoomRef::Smallest { cat } => format!("the smallest {}", category_words(cat)),
            RoomRef::Containing { cat, obj_cat } => {
                let form = ["with the", "that has the", "containing the"]
                    .choose(rng)
                    .copied()
                    .unwrap_or("with the");
                format!(
                    "the {} {form} {}",
                    category_words(cat),
                    category_words(obj_cat)
                )
            }
        }
    }

    pub fn resolve(&self, ix: &MapIndex<'_>) -> Vec<u32> {
        match self {
            RoomRef::Unique { cat } => ix.rooms_of_cat(cat).to_vec(),
            RoomRef::Largest { cat } | RoomRef::Smallest { cat } => {
                let rooms = ix.rooms_of_cat(cat);
                let area = |id: &u32| ix.map.room(*id).map(|r| r.area_m2).unwrap_or(0.0);
                let mut sorted: Vec<u32> = rooms.to_vec();
                sorted.sort_by(|a, b| area(a).total_cmp(&area(b)).then(a.cmp(b)));
                if matches!(self, RoomRef::Largest { .. }) {
                    sorted.reverse();
                }
                match sorted.as_slice() {
                    [] => vec![],
                    [only] => vec![*only],
                    // A near tie is ambiguous to a reader even if the numbers differ.
                    [a, b, ..] if (area(a) - area(b)).abs() < 1.0 => vec![*a, *b],
                    [a, ..] => vec![*a],
                }
            }
            RoomRef::Containing { cat, obj_cat } => ix
                .rooms_of_cat(cat)
                .iter()
                .copied()
                .filter(|&r| {
                    ix.of_cat(obj_cat)
                        .iter()
                        .any(|&o| ix.object(o).room == Some(r))
                })
                .collect(),
        }
    }
}

impl ObjRef {
    pub fn depth(&self) -> u32 {
        match self {
            ObjRef::Unique { .. } => 1,
            ObjRef::InRoom { room, .. } => 1 + room.depth(),
            ObjRef::On { parent, .. } => 1 + parent.depth(),
            ObjRef::Nearest { room, anchor, .. } => {
                1 + anchor.depth() + room.as_ref().map_or(0, RoomRef::depth)
            }
        }
    }

    pub fn category(&self) -> &str {
        match self {
            ObjRef::Unique { cat }
            | ObjRef::InRoom { cat, .. }
            | ObjRef::On { cat, .. }
            | ObjRef::Nearest { cat, .. } => cat,
        }
    }

    pub fn m2r(&self) -> String {
        match self {
            ObjRef::Unique { cat } => format!("objects({cat}).only()"),
            ObjRef::InRoom { cat, room } => format!("objects({cat}).in({}).only()", room.m2r()),
            ObjRef::On { cat, parent } => format!("objects({cat}).on({}).only()", parent.m2r()),
            ObjRef::Nearest { cat, room, anchor } => match room {
                Some(room) => format!(
                    "objects({cat}).in({}).nearest(to: {})",
                    room.m2r(),
                    anchor.m2r()
                ),
                None => format!("objects({cat}).nearest(to: {})", anchor.m2r()),
            },
        }
    }

    pub fn text(&self, rng: &mut ChaCha8Rng) -> String {
        match self {
            ObjRef::Unique { cat } => format!("the {}", category_words(cat)),
            ObjRef::InRoom { cat, room } => {
                let prep = ["in", "in", "inside"].choose(rng).copied().unwrap_or("in");
                format!("the {} {prep} {}", category_words(cat), room.text(rng))
            }
            ObjRef::On { cat, parent } => {
                let prep = ["on", "sitting on", "on top of"]
                    .choose(rng)
                    .copied()
                    .unwrap_or("on");
                format!("the {} {prep} {}", category_words(cat), parent.text(rng))
            }
            ObjRef::Nearest { cat, room, anchor } => {
                let rel = ["nearest to", "closest to"]
                    .choose(rng)
                    .copied()
                    .unwrap_or("nearest to");
                let anchor = anchor.text(rng);
                match room {
                    Some(room) => {
                        let room = room.text(rng);
                        if rng.random_bool(0.5) {
                            format!("the {} in {room} {rel} {anchor}", category_words(cat))
                        } else {
                            format!("the {} {rel} {anchor} in {room}", category_words(cat))
                        }
                    }
                    None => format!("the {} {rel} {anchor}", category_words(cat)),
                }
            }
        }
    }

    /// The objects this description matches on the map.
    pub fn resolve(&self, ix: &MapIndex<'_>) -> Vec<u32> {
        match self {
            ObjRef::Unique { cat } => ix.of_cat(cat).to_vec(),
            ObjRef::InRoom { cat, room } => {
                let rooms = room.resolve(ix);
                ix.of_cat(cat)
                    .iter()
                    .copied()
                    .filter(|&o| ix.object(o).room.is_some_and(|r| rooms.contains(&r)))
                    .collect()
            }
            ObjRef::On { cat, parent } => {
                let parents = parent.resolve(ix);
                ix.of_cat(cat)
                    .iter()
                    .copied()
                    .filter(|&o| parents.iter().any(|&p| ix.is_on(o, p)))
                    .collect()
            }
            ObjRef::Nearest { cat, room, anchor } => {
                let anchors = anchor.resolve(ix);
                let [a] = anchors.as_slice() else {
                    return vec![];
                };
                let pool: Vec<u32> = match room {
                    Some(room) => {
                        let rooms = room.resolve(ix);
                        ix.of_cat(cat)
                            .iter()
                            .copied()
                            .filter(|&o| ix.object(o).room.is_some_and(|r| rooms.contains(&r)))
                            .collect()
                    }
                    None => ix.of_cat(cat).to_vec(),
                };
                nearest_with_margin(ix, &pool, *a).into_iter().collect()
            }
        }
    }

    /// Number of objects of the head category: what a reader must choose among.
    pub fn candidates(&self, ix: &MapIndex<'_>) -> usize {
        ix.of_cat(self.category()).len()
    }
}

/// The member of `pool` nearest to `anchor`, if it wins clearly under both distance definitions.
fn nearest_with_margin(ix: &MapIndex<'_>, pool: &[u32], anchor: u32) -> Option<u32> {
    let pool: Vec<u32> = pool.iter().copied().filter(|&o| o != anchor).collect();
    let best_by = |d: &dyn Fn(u32) -> f64| -> Option<u32> {
        let mut scored: Vec<(f64, u32)> = pool.iter().map(|&o| (d(o), o)).collect();
        scored.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        match scored.as_slice() {
            [] => None,
            [(_, only)] => Some(*only),
            [(d0, o), (d1, _), ..] => (*d1 >= NEAREST_MARGIN * d0.max(1.0)).then_some(*o),
        }
    };
    let a = best_by(&|o| ix.center_distance(o, anchor))?;
    let b = best_by(&|o| ix.footprint_distance(o, anchor))?;
    (a == b).then_some(a)
}

/// Every room description (up to `max_depth`) that singles out `room`.
pub fn room_descriptions(ix: &MapIndex<'_>, room: u32, max_depth: u32) -> Vec<RoomRef> {
    let cat = ix.room_category(room).to_string();
    let mut out = Vec::new();
    let mut push = |r: RoomRef| {
        if r.depth() <= max_depth && r.resolve(ix) == [room] {
            out.push(r);
        }
    };
    push(RoomRef::Unique { cat: cat.clone() });
    push(RoomRef::Largest { cat: cat.clone() });
    push(RoomRef::Smallest { cat: cat.clone() });
    if ix.rooms_of_cat(&cat).len() > 1 {
        // Distinctive contents, deterministic order, a few at most.
        let mut cats: Vec<&String> = ix
            .objects_by_cat
            .iter()
            .filter(|(_, ids)| ids.iter().any(|&o| ix.object(o).room == Some(room)))
            .map(|(c, _)| c)
            .collect();
        cats.truncate(64);
        for oc in cats {
            push(RoomRef::Containing {
                cat: cat.clone(),
                obj_cat: oc.clone(),
            });
        }
    }
    out
}

/// Descriptions already enumerated, by (object, depth bound).
pub type DescriptionMemo = HashMap<(u32, u32), Vec<ObjRef>>;

/// Every description of `id` up to `max_depth` (a bounded sample when there are many).
pub fn object_descriptions(ix: &MapIndex<'_>, id: u32, max_depth: u32) -> Vec<ObjRef> {
    describe(ix, id, max_depth, &mut DescriptionMemo::new())
}

/// [`object_descriptions`] sharing a memo across calls (anchors recur across objects).
pub fn describe(
    ix: &MapIndex<'_>,
    id: u32,
    max_depth: u32,
    memo: &mut DescriptionMemo,
) -> Vec<ObjRef> {
    if let Some(d) = memo.get(&(id, max_depth)) {
        return d.clone();
    }
    let out = describe_uncached(ix, id, max_depth, memo);
    memo.insert((id, max_depth), out.clone());
    out
}

fn describe_uncached(
    ix: &MapIndex<'_>,
    id: u32,
    max_depth: u32,
    memo: &mut DescriptionMemo,
) -> Vec<ObjRef> {
    let mut out = Vec::new();
    if max_depth == 0 {
        return out;
    }
    let o = ix.object(id);
    let cat = o.category.clone();
    let keep = |r: ObjRef, out: &mut Vec<ObjRef>| {
        if r.depth() <= max_depth && !out.contains(&r) && r.resolve(ix) == [id] {
            out.push(r);
        }
    };
    keep(ObjRef::Unique { cat: cat.clone() }, &mut out);
    let room_refs = o
        .room
        .map(|r| room_descriptions(ix, r, max_depth.saturating_sub(1)))
        .unwrap_or_default();
    for room in &room_refs {
        keep(
            ObjRef::InRoom {
                cat: cat.clone(),
                room: room.clone(),
            },
            &mut out,
        );
    }
    if let Some(p) = o
        .parent
        .filter(|p| p.relation == m2rc_stdlib::map::Relation::On)
        && ix.map.object(p.id).is_some()
        && max_depth >= 2
    {
        for parent in describe(ix, p.id, max_depth - 1, memo).into_iter().take(4) {
            keep(
                ObjRef::On {
                    cat: cat.clone(),
                    parent: Box::new(parent),
                },
                &mut out,
            );
        }
    }
    if max_depth >= 2 && ix.of_cat(&cat).len() > 1 {
        // Anchors: distinct-category objects in the same room, closest first.
        let mut anchors: Vec<u32> = ix
            .objects_by_cat
            .iter()
            .filter(|(c, _)| **c != cat)
            .flat_map(|(_, ids)| ids.iter().copied())
            .filter(|&a| {
                o.room.is_some() && ix.object(a).room == o.room && ix.object(a).parent.is_none()
            })
            .collect();
        anchors.sort_by(|&a, &b| {
            ix.center_distance(id, a)
                .total_cmp(&ix.center_distance(id, b))
                .then(a.cmp(&b))
        });
        anchors.truncate(4);
        for a in anchors {
            for anchor in describe(ix, a, max_depth - 1, memo).into_iter().take(3) {
                keep(
                    ObjRef::Nearest {
                        cat: cat.clone(),
                        room: None,
                        anchor: Box::new(anchor.clone()),
                    },
                    &mut out,
                );
                for room in room_refs.iter().take(2) {
                    keep(
                        ObjRef::Nearest {
                            cat: cat.clone(),
                            room: Some(room.clone()),
                            anchor: Box::new(anchor.clone()),
                        },
                        &mut out,
                    );
                }
            }
        }
    }
    out
}

/// Picks a description, preferring depths near `want` (ties broken by the seeded RNG).
pub fn pick_description(descs: &[ObjRef], want: u32, rng: &mut ChaCha8Rng) -> Option<ObjRef> {
    let best = descs.iter().map(|d| d.depth().abs_diff(want)).min()?;
    let close: Vec<&ObjRef> = descs
        .iter()
        .filter(|d| d.depth().abs_diff(want) == best)
        .collect();
    close.choose(rng).map(|d| (*d).clone())
}
