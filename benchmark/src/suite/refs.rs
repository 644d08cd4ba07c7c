//! Referring expressions: descriptions of one object or room that single it out on a map.
//!
//! A description is a small tree (category, room, parent, anchor, the robot) rendered twice, once
//! as English (through a [`super::realise::Speaker`], which remembers what the episode has
//! already described; `refs/say.rs`) and once as a `.m2r` expression with the language's existing built-ins, so the instruction and its
//! gold program cannot drift apart. Each description is resolved here with the plain map
//! semantics before it is kept, and the compiler resolves the gold program again as the validity
//! check.
//!
//! What a person would write, as rules every kept description obeys:
//! * a qualifier only when it disambiguates: "the fridge" when there is one fridge; a room, a
//!   parent or an anchor only when the bare category is ambiguous, and a room on a "nearest"
//!   only when the nearest alone is not unique;
//! * a superlative ("the largest bedroom") only over two or more rooms of the category;
//! * no category twice in one chain (no "the sink closest to the toilet closest to the sink",
//!   no "the smallest living room in the biggest living room");
//! * "nearest" only with a clear winner (25 % margin under both distance definitions).

use super::index::MapIndex;
use super::lexicon::{self, number_word, plural};
use m2rc_stdlib::grid::Cell;
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
    /// "the largest bedroom" (two or more bedrooms).
    Largest { cat: String },
    /// "the smallest bathroom" (two or more bathrooms).
    Smallest { cat: String },
    /// The only room of its category holding an object of `obj_cat`: "the bedroom with the desk".
    Containing { cat: String, obj_cat: String },
    /// The only room of its category with exactly `n` objects of `obj_cat`: "the bedroom with two
    /// windows".
    Counting {
        cat: String,
        obj_cat: String,
        n: usize,
    },
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
    /// Relative to the robot: "the chair closest to you", "the plant farthest from where you
    /// start" (`objects(c).nearest(start)` / `.farthest(start)`).
    FromYou {
        cat: String,
        room: Option<RoomRef>,
        farthest: bool,
    },
    /// Negation: "the book that is not on a desk"
    /// (`objects(book).where(b => not b.on(objects(desk))).only()`).
    NotOn {
        cat: String,
        room: Option<RoomRef>,
        other: String,
    },
}

impl RoomRef {
    /// Number of noun phrases (entities) mentioned.
    pub fn depth(&self) -> u32 {
        match self {
            RoomRef::Containing { .. } | RoomRef::Counting { .. } => 2,
            _ => 1,
        }
    }

    pub fn category(&self) -> &str {
        match self {
            RoomRef::Unique { cat }
            | RoomRef::Largest { cat }
            | RoomRef::Smallest { cat }
            | RoomRef::Containing { cat, .. }
            | RoomRef::Counting { cat, .. } => cat,
        }
    }

    /// Object categories the description names.
    fn object_cats(&self) -> Vec<&str> {
        match self {
            RoomRef::Containing { obj_cat, .. } | RoomRef::Counting { obj_cat, .. } => {
                vec![obj_cat]
            }
            _ => vec![],
        }
    }

    /// Whether the description ranks rooms ("largest", "smallest"), and over how many.
    pub fn superlative_over(&self, ix: &MapIndex<'_>) -> Option<usize> {
        match self {
            RoomRef::Largest { cat } | RoomRef::Smallest { cat } => {
                Some(ix.rooms_of_cat(cat).len())
            }
            _ => None,
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
            RoomRef::Counting { cat, obj_cat, n } => {
                format!("rooms({cat}).where(r => objects({obj_cat}).in(r).count() == {n}).only()")
            }
        }
    }

    /// The full description, as English.
    pub fn full_text(&self, rng: &mut ChaCha8Rng) -> String {
        let noun = |c: &str, rng: &mut ChaCha8Rng| lexicon::noun(c, rng);
        match self {
            RoomRef::Unique { cat } => format!("the {}", noun(cat, rng)),
            RoomRef::Largest { cat } => {
                let adj = ["largest", "biggest"]
                    .choose(rng)
                    .copied()
                    .unwrap_or("largest");
                format!("the {adj} {}", noun(cat, rng))
            }
            RoomRef::Smallest { cat } => format!("the smallest {}", noun(cat, rng)),
            RoomRef::Containing { cat, obj_cat } => {
                let form = ["with the", "that has the", "where the {} is"]
                    .choose(rng)
                    .copied()
                    .unwrap_or("with the");
                let o = noun(obj_cat, rng);
                if form.contains("{}") {
                    format!("the {} {}", noun(cat, rng), form.replace("{}", &o))
                } else {
                    format!("the {} {form} {o}", noun(cat, rng))
                }
            }
            RoomRef::Counting { cat, obj_cat, n } => {
                let things = plural(&lexicon::plain(obj_cat));
                let form = ["with {n} {x}", "that has {n} {x}", "with exactly {n} {x}"]
                    .choose(rng)
                    .copied()
                    .unwrap_or("with {n} {x}");
                format!(
                    "the {} {}",
                    noun(cat, rng),
                    form.replace("{n}", &number_word(*n))
                        .replace("{x}", &things)
                )
            }
        }
    }

    /// The rooms this description matches.
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
                    // A superlative over a single room is not something a person says.
                    [] | [_] => vec![],
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
                    ix.all_of_cat(obj_cat)
                        .iter()
                        .any(|&o| ix.object_room(o) == Some(r))
                })
                .collect(),
            RoomRef::Counting { cat, obj_cat, n } => ix
                .rooms_of_cat(cat)
                .iter()
                .copied()
                .filter(|&r| count_in(ix, obj_cat, r) == *n)
                .collect(),
        }
    }
}

/// Objects of `cat` (fixtures included) in room `r`, as the compiler's `.in(r)` counts them.
pub fn count_in(ix: &MapIndex<'_>, cat: &str, r: u32) -> usize {
    ix.all_of_cat(cat)
        .iter()
        .filter(|&&o| ix.object_room(o) == Some(r))
        .count()
}

impl ObjRef {
    pub fn depth(&self) -> u32 {
        let room_depth = |r: &Option<RoomRef>| r.as_ref().map_or(0, RoomRef::depth);
        match self {
            ObjRef::Unique { .. } => 1,
            ObjRef::InRoom { room, .. } => 1 + room.depth(),
            ObjRef::On { parent, .. } => 1 + parent.depth(),
            ObjRef::Nearest { room, anchor, .. } => 1 + anchor.depth() + room_depth(room),
            ObjRef::FromYou { room, .. } | ObjRef::NotOn { room, .. } => 2 + room_depth(room),
        }
    }

    pub fn category(&self) -> &str {
        match self {
            ObjRef::Unique { cat }
            | ObjRef::InRoom { cat, .. }
            | ObjRef::On { cat, .. }
            | ObjRef::Nearest { cat, .. }
            | ObjRef::FromYou { cat, .. }
            | ObjRef::NotOn { cat, .. } => cat,
        }
    }

    /// The one room the description itself names (not "closest to you", whose room keeps a
    /// house-wide phrase local), if any.
    pub fn stated_room(&self, ix: &MapIndex<'_>) -> Option<u32> {
        if matches!(self, ObjRef::FromYou { .. }) {
            return None;
        }
        match self.room()?.resolve(ix).as_slice() {
            [id] => Some(*id),
            _ => None,
        }
    }

    pub(crate) fn room(&self) -> Option<&RoomRef> {
        match self {
            ObjRef::InRoom { room, .. } => Some(room),
            ObjRef::Nearest { room, .. }
            | ObjRef::FromYou { room, .. }
            | ObjRef::NotOn { room, .. } => room.as_ref(),
            _ => None,
        }
    }

    /// Every object category the chain names, head first.
    pub fn object_cats(&self) -> Vec<&str> {
        let mut out = vec![self.category()];
        if let Some(r) = self.room() {
            out.extend(r.object_cats());
        }
        match self {
            ObjRef::On { parent, .. } => out.extend(parent.object_cats()),
            ObjRef::Nearest { anchor, .. } => out.extend(anchor.object_cats()),
            ObjRef::NotOn { other, .. } => out.push(other),
            _ => {}
        }
        out
    }

    /// Every room description in the chain.
    pub fn rooms(&self) -> Vec<&RoomRef> {
        let mut out: Vec<&RoomRef> = self.room().into_iter().collect();
        match self {
            ObjRef::On { parent, .. } => out.extend(parent.rooms()),
            ObjRef::Nearest { anchor, .. } => out.extend(anchor.rooms()),
            _ => {}
        }
        out
    }

    /// Whether the chain reads as a person would write it: no category named twice (a circular
    /// chain), and no two rooms of one category.
    pub fn is_natural(&self) -> bool {
        let cats = self.object_cats();
        let rooms: Vec<&str> = self.rooms().iter().map(|r| r.category()).collect();
        let distinct = |v: &[&str]| {
            let mut s = v.to_vec();
            s.sort_unstable();
            s.windows(2).all(|w| w[0] != w[1])
        };
        distinct(&cats) && distinct(&rooms)
    }

    pub fn m2r(&self) -> String {
        let set = |cat: &str, room: &Option<RoomRef>| match room {
            Some(r) => format!("objects({cat}).in({})", r.m2r()),
            None => format!("objects({cat})"),
        };
        match self {
            ObjRef::Unique { cat } => format!("objects({cat}).only()"),
            ObjRef::InRoom { cat, room } => format!("objects({cat}).in({}).only()", room.m2r()),
            ObjRef::On { cat, parent } => format!("objects({cat}).on({}).only()", parent.m2r()),
            ObjRef::Nearest { cat, room, anchor } => {
                format!("{}.nearest(to: {})", set(cat, room), anchor.m2r())
            }
            ObjRef::FromYou {
                cat,
                room,
                farthest,
            } => format!(
                "{}.{}(start)",
                set(cat, room),
                if *farthest { "farthest" } else { "nearest" }
            ),
            ObjRef::NotOn { cat, room, other } => format!(
                "{}.where(x => not x.on(objects({other}))).only()",
                set(cat, room)
            ),
        }
    }

    /// The objects this description matches on the map (robot-relative ones need `start`).
    pub fn resolve(&self, ix: &MapIndex<'_>, start: Option<Cell>) -> Vec<u32> {
        let in_rooms = |cat: &str, room: &Option<RoomRef>| -> Vec<u32> {
            match room {
                Some(room) => {
                    let rooms = room.resolve(ix);
                    ix.all_of_cat(cat)
                        .iter()
                        .copied()
                        .filter(|&o| ix.object_room(o).is_some_and(|r| rooms.contains(&r)))
                        .collect()
                }
                None => ix.all_of_cat(cat).to_vec(),
            }
        };
        match self {
            ObjRef::Unique { cat } => ix.all_of_cat(cat).to_vec(),
            ObjRef::InRoom { cat, room } => in_rooms(cat, &Some(room.clone())),
            ObjRef::On { cat, parent } => {
                let parents = parent.resolve(ix, start);
                ix.of_cat(cat)
                    .iter()
                    .copied()
                    .filter(|&o| parents.iter().any(|&p| ix.is_on(o, p)))
                    .collect()
            }
            ObjRef::Nearest { cat, room, anchor } => {
                let anchors = anchor.resolve(ix, start);
                let [a] = anchors.as_slice() else {
                    return vec![];
                };
                let pool = in_rooms(cat, room);
                nearest_with_margin(ix, &pool, *a).into_iter().collect()
            }
            ObjRef::FromYou {
                cat,
                room,
                farthest,
            } => {
                let Some(s) = start else { return vec![] };
                let pool = in_rooms(cat, room);
                ranked_from(ix, &pool, s, *farthest).into_iter().collect()
            }
            ObjRef::NotOn { cat, room, other } => in_rooms(cat, room)
                .into_iter()
                .filter(|&o| !ix.of_cat(other).iter().any(|&p| ix.is_on(o, p)))
                .collect(),
        }
    }

    /// Number of objects of the head category: what a reader must choose among.
    pub fn candidates(&self, ix: &MapIndex<'_>) -> usize {
        ix.all_of_cat(self.category()).len()
    }
}

/// The member of `pool` nearest to `anchor`, if it wins clearly under both distance definitions.
pub(crate) fn nearest_with_margin(ix: &MapIndex<'_>, pool: &[u32], anchor: u32) -> Option<u32> {
    let pool: Vec<u32> = pool.iter().copied().filter(|&o| o != anchor).collect();
    let a = best_by(&pool, &|o| ix.center_distance(o, anchor), false)?;
    let b = best_by(&pool, &|o| ix.footprint_distance(o, anchor), false)?;
    (a == b).then_some(a)
}

/// The member of `pool` nearest to (farthest from) the start cell, with the same margin.
pub(crate) fn ranked_from(ix: &MapIndex<'_>, pool: &[u32], s: Cell, farthest: bool) -> Option<u32> {
    let centre = |o: u32| {
        let c = ix.object(o).center;
        (c[0] - s.row as f64).hypot(c[1] - s.col as f64)
    };
    let foot = |o: u32| s.nearest_dist(&ix.object(o).footprint);
    let a = best_by(pool, &centre, farthest)?;
    let b = best_by(pool, &foot, farthest)?;
    (a == b).then_some(a)
}

/// The best of `pool` under `d` (smallest, or largest when `largest`), if it wins by the margin.
fn best_by(pool: &[u32], d: &dyn Fn(u32) -> f64, largest: bool) -> Option<u32> {
    let mut scored: Vec<(f64, u32)> = pool.iter().map(|&o| (d(o), o)).collect();
    scored.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    if largest {
        scored.reverse();
    }
    match scored.as_slice() {
        [] => None,
        [(_, only)] => Some(*only),
        [(d0, o), (d1, _), ..] if !largest => (*d1 >= NEAREST_MARGIN * d0.max(1.0)).then_some(*o),
        [(d0, o), (d1, _), ..] => (*d0 >= NEAREST_MARGIN * d1.max(1.0)).then_some(*o),
    }
}

/// Every room description (up to `max_depth`) that singles out `room`, plainest first.
pub fn room_descriptions(ix: &MapIndex<'_>, room: u32, max_depth: u32) -> Vec<RoomRef> {
    let cat = ix.room_category(room).to_string();
    let unique = RoomRef::Unique { cat: cat.clone() };
    if unique.resolve(ix) == [room] {
        // The only room of its kind needs no qualifier.
        return vec![unique];
    }
    let mut out = Vec::new();
    let mut push = |r: RoomRef| {
        if r.depth() <= max_depth && r.resolve(ix) == [room] {
            out.push(r);
        }
    };
    push(RoomRef::Largest { cat: cat.clone() });
    push(RoomRef::Smallest { cat: cat.clone() });
    // Distinctive contents, deterministic order, a few at most.
    let mut cats: Vec<&String> = ix
        .objects_by_cat
        .keys()
        .chain(ix.fixtures_by_cat.keys())
        .filter(|c| count_in(ix, c, room) > 0)
        .collect();
    cats.truncate(64);
    for oc in cats {
        push(RoomRef::Containing {
            cat: cat.clone(),
            obj_cat: oc.clone(),
        });
        let n = count_in(ix, oc, room);
        if (2..=4).contains(&n) {
            push(RoomRef::Counting {
                cat: cat.clone(),
                obj_cat: oc.clone(),
                n,
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

fn keep(ix: &MapIndex<'_>, id: u32, max_depth: u32, r: ObjRef, out: &mut Vec<ObjRef>) -> bool {
    if r.depth() <= max_depth && !out.contains(&r) && r.is_natural() && r.resolve(ix, None) == [id]
    {
        out.push(r);
        return true;
    }
    false
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
    if keep(
        ix,
        id,
        max_depth,
        ObjRef::Unique { cat: cat.clone() },
        &mut out,
    ) {
        // One of its kind: any qualifier would be noise.
        return out;
    }
    let room_refs = ix
        .object_room(id)
        .map(|r| room_descriptions(ix, r, max_depth.saturating_sub(1)))
        .unwrap_or_default();
    for room in &room_refs {
        let r = ObjRef::InRoom {
            cat: cat.clone(),
            room: room.clone(),
        };
        keep(ix, id, max_depth, r, &mut out);
    }
    if let Some(p) = o
        .parent
        .filter(|p| p.relation == m2rc_stdlib::map::Relation::On)
        && ix.map.object(p.id).is_some()
        && max_depth >= 2
    {
        for parent in describe(ix, p.id, max_depth - 1, memo).into_iter().take(4) {
            let r = ObjRef::On {
                cat: cat.clone(),
                parent: Box::new(parent),
            };
            keep(ix, id, max_depth, r, &mut out);
        }
    }
    if max_depth >= 2 {
        // Negation: the one object of its kind (in its room, when needed) not on a `other`.
        let others: Vec<String> = ix
            .of_cat(&cat)
            .iter()
            .filter_map(|&x| ix.object(x).parent.map(|p| p.id))
            .filter_map(|p| ix.map.object(p).map(|o| o.category.clone()))
            .collect();
        for other in others.into_iter().take(3) {
            let r = ObjRef::NotOn {
                cat: cat.clone(),
                room: None,
                other: other.clone(),
            };
            if !keep(ix, id, max_depth, r, &mut out) {
                for room in room_refs.iter().take(1) {
                    let r = ObjRef::NotOn {
                        cat: cat.clone(),
                        room: Some(room.clone()),
                        other: other.clone(),
                    };
                    keep(ix, id, max_depth, r, &mut out);
                }
            }
        }
        // Anchors: distinct-category objects (windows too) in the same room, closest first.
        let mut anchors: Vec<u32> = ix
            .objects_by_cat
            .iter()
            .chain(ix.fixtures_by_cat.iter())
            .filter(|(c, _)| **c != cat)
            .flat_map(|(_, ids)| ids.iter().copied())
            .filter(|&a| {
                o.room.is_some() && ix.object_room(a) == o.room && ix.object(a).parent.is_none()
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
                let plain = ObjRef::Nearest {
                    cat: cat.clone(),
                    room: None,
                    anchor: Box::new(anchor.clone()),
                };
                if keep(ix, id, max_depth, plain, &mut out) {
                    continue;
                }
                for room in room_refs.iter().take(2) {
                    let r = ObjRef::Nearest {
                        cat: cat.clone(),
                        room: Some(room.clone()),
                        anchor: Box::new(anchor.clone()),
                    };
                    keep(ix, id, max_depth, r, &mut out);
                }
            }
        }
    }
    out
}

/// Descriptions of `id` relative to the robot at `start` ("the chair closest to you"), with a
/// room only when the bare ranking is not clear.
pub fn from_start(ix: &MapIndex<'_>, id: u32, start: Cell, max_depth: u32) -> Vec<ObjRef> {
    let cat = ix.object(id).category.clone();
    if ix.all_of_cat(&cat).len() < 2 || max_depth < 2 {
        return vec![];
    }
    let mut out = Vec::new();
    for farthest in [false, true] {
        let r = ObjRef::FromYou {
            cat: cat.clone(),
            room: None,
            farthest,
        };
        if r.resolve(ix, Some(start)) == [id] {
            out.push(r);
            continue;
        }
        if let Some(room) = ix.object_room(id) {
            for rr in room_descriptions(ix, room, max_depth.saturating_sub(2)) {
                let r = ObjRef::FromYou {
                    cat: cat.clone(),
                    room: Some(rr),
                    farthest,
                };
                if r.depth() <= max_depth && r.is_natural() && r.resolve(ix, Some(start)) == [id] {
                    out.push(r);
                    break;
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

mod say;
#[cfg(test)]
mod tests;
