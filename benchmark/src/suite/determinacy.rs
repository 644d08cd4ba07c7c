//! Determinacy: every thing an instruction names must pick out the gold's object.
//!
//! An instruction whose words fit several things while the gold program takes one measures luck,
//! not grounding ("circle the dining table" in a house with three). So each mention the
//! realiser writes (destinations, anchors, must-avoids, preference and path-shape subjects,
//! relative pairs, between partners, rooms) is read back as a reader would read it: the words
//! actually written, resolved against the house in the context the sentence gives, and the
//! result must be exactly the gold's object (or, for "all the windows", the gold's set).
//!
//! The [`Reader`] holds that context, with these rules and no others (none of them is "the
//! salient one", which no rule of the language shares):
//! * a description that states its room, parent, anchor or negation resolves as the map says
//!   (the same semantics as the gold program's built-ins);
//! * a bare "the X" is the X of the room the sentence is scoped to ("while in the kitchen, keep
//!   away from the fridge") when that room holds one; otherwise, when the instruction has
//!   already named an X, that one ("go to the desk in the office; on the way to the desk ...");
//!   otherwise every X of the house;
//! * a qualified head with no stated room ("the chair nearest the lamp") ranks the Xs of the
//!   scope room when it holds one, else every X; "closest to you" ranks the whole house;
//! * "that room" is the room named last; "that bedroom", "the same bedroom" the bedroom named
//!   last; "the other X" the X not yet named;
//! * a room phrase after two nouns ("the chair nearest the window in the bedroom") may belong to
//!   either: it is an `attachment` mention, and the realiser writes it so that both readings
//!   agree, or so that it can only belong to one ("the window that is in the bedroom", "the
//!   chair in the bedroom nearest the window"; `refs/say.rs`).
//!
//! A mention that resolves to anything but the gold's object is *underdetermined*; the
//! generator rewords or redraws until an episode has none, and `suite stats` counts them by kind
//! from the record every episode keeps (`m2rc_generation.determinacy`).

use super::index::MapIndex;
use m2rc_stdlib::grid::Cell;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The kinds of mention, as `suite stats` reports them.
pub const KINDS: [&str; 9] = [
    "destination",
    "anchor",
    "must-avoid",
    "preference subject",
    "path-shape subject",
    "relative pair",
    "between partner",
    "room",
    "attachment",
];

/// One mention whose words did not resolve to the gold's object.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Mention {
    pub kind: String,
    pub words: String,
    /// What the gold program means: object or room ids, ascending.
    pub gold: Vec<u32>,
    /// What the words resolve to in their context, ascending.
    pub read: Vec<u32>,
}

/// The check of one episode: mentions checked by kind, and the underdetermined ones.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Determinacy {
    pub checked: BTreeMap<String, usize>,
    pub underdetermined: Vec<Mention>,
}

/// What a reader knows while reading the instruction: what it has named so far, in order, and
/// the room the current sentence is scoped to.
#[derive(Clone, Debug, Default)]
pub struct Reader {
    /// Where the robot starts ("closest to you").
    pub start: Option<Cell>,
    /// The room the current clause's scope phrase names, as read.
    pub scope: Option<u32>,
    /// The object the last destination phrase named, as read ("the other one").
    pub last_destination: Option<u32>,
    rooms: Vec<u32>,
    objects: Vec<u32>,
    pub record: Determinacy,
}

impl Reader {
    /// Checks one mention: `read` must be exactly `gold`.
    pub fn note(&mut self, kind: &str, words: &str, mut gold: Vec<u32>, mut read: Vec<u32>) {
        gold.sort_unstable();
        gold.dedup();
        read.sort_unstable();
        read.dedup();
        *self.record.checked.entry(kind.to_string()).or_default() += 1;
        if read != gold {
            self.record.underdetermined.push(Mention {
                kind: kind.to_string(),
                words: words.to_string(),
                gold,
                read,
            });
        }
    }

    /// A room phrase was read as `read`: a single room becomes the antecedent of "that room".
    pub fn named_room(&mut self, read: &[u32]) {
        if let [r] = read {
            self.rooms.push(*r);
        }
    }

    /// An object phrase was read as `read`: a single object becomes an antecedent.
    pub fn named_object(&mut self, read: &[u32]) {
        if let [o] = read {
            self.objects.push(*o);
        }
    }

    /// Objects of `cat` in any of `rooms`.
    pub fn in_rooms(ix: &MapIndex<'_>, cat: &str, rooms: &[u32]) -> Vec<u32> {
        ix.all_of_cat(cat)
            .iter()
            .copied()
            .filter(|&o| ix.object_room(o).is_some_and(|r| rooms.contains(&r)))
            .collect()
    }

    /// The Xs of the scope room, when it holds any.
    fn scoped(&self, ix: &MapIndex<'_>, cat: &str) -> Option<Vec<u32>> {
        let inside = Self::in_rooms(ix, cat, &[self.scope?]);
        (!inside.is_empty()).then_some(inside)
    }

    /// What a bare "the X" names.
    pub fn bare(&self, ix: &MapIndex<'_>, cat: &str) -> Vec<u32> {
        if let Some(inside) = self.scoped(ix, cat) {
            return inside;
        }
        let mut named: Vec<u32> = self
            .objects
            .iter()
            .copied()
            .filter(|&o| ix.object(o).category == cat)
            .collect();
        named.sort_unstable();
        named.dedup();
        if named.is_empty() {
            ix.all_of_cat(cat).to_vec()
        } else {
            named
        }
    }

    /// The pool a qualified head with no stated room ranks or filters.
    pub fn head(&self, ix: &MapIndex<'_>, cat: &str) -> Vec<u32> {
        self.scoped(ix, cat)
            .unwrap_or_else(|| ix.all_of_cat(cat).to_vec())
    }

    /// "The other X": the Xs the instruction has not named.
    pub fn other(&self, ix: &MapIndex<'_>, cat: &str) -> Vec<u32> {
        ix.all_of_cat(cat)
            .iter()
            .copied()
            .filter(|o| !self.objects.contains(o))
            .collect()
    }

    /// "That room" (`cat` none) or "that bedroom": the last such room named.
    pub fn back_room(&self, ix: &MapIndex<'_>, cat: Option<&str>) -> Vec<u32> {
        let last = self
            .rooms
            .iter()
            .rev()
            .find(|&&r| cat.is_none_or(|c| ix.room_category(r) == c));
        match (last, cat) {
            (Some(&r), _) => vec![r],
            (None, Some(c)) => ix.rooms_of_cat(c).to_vec(),
            (None, None) => ix.map.rooms.iter().map(|r| r.id).collect(),
        }
    }

    /// The rooms of the objects in `read` (for "the room with the desk").
    pub fn rooms_of(ix: &MapIndex<'_>, read: &[u32]) -> Vec<u32> {
        let mut out: Vec<u32> = read.iter().filter_map(|&o| ix.object_room(o)).collect();
        out.sort_unstable();
        out.dedup();
        out
    }
}

/// Underdetermined mentions of a set of episodes' records, by kind (every kind listed).
pub fn count_by_kind<'d>(records: impl Iterator<Item = &'d Determinacy>) -> Counts {
    let mut out = Counts::default();
    for k in KINDS {
        out.underdetermined.insert(k.to_string(), 0);
        out.checked.insert(k.to_string(), 0);
    }
    for d in records {
        for (k, n) in &d.checked {
            *out.checked.entry(k.clone()).or_default() += n;
        }
        for m in &d.underdetermined {
            *out.underdetermined.entry(m.kind.clone()).or_default() += 1;
        }
    }
    out
}

/// Mentions checked and underdetermined, by kind.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Counts {
    pub checked: BTreeMap<String, usize>,
    pub underdetermined: BTreeMap<String, usize>,
}

impl Counts {
    pub fn total_underdetermined(&self) -> usize {
        self.underdetermined.values().sum()
    }

    pub fn total_checked(&self) -> usize {
        self.checked.values().sum()
    }
}

#[cfg(test)]
mod tests;
