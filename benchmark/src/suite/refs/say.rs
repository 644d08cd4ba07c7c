//! A description said in English, and read back: each branch that decides what the words say
//! (a room left out because the clause is scoped to it, a room referred back to as "that room")
//! also decides what a reader takes them for ([`super::super::determinacy`]), so the check reads
//! exactly the words written.

use super::super::determinacy::Reader;
use super::super::index::MapIndex;
use super::super::lexicon;
use super::super::realise::Speaker;
use super::{ObjRef, nearest_with_margin, ranked_from};
use rand::Rng;
use rand::seq::IndexedRandom;

impl ObjRef {
    /// "The sink in this bathroom and the toilet": the second of two objects described in the
    /// same room leaves the room out, as a person would.
    pub fn pair_text(
        a: &ObjRef,
        b: &ObjRef,
        ix: &MapIndex<'_>,
        sp: &mut Speaker<'_>,
    ) -> (String, String) {
        let ((ta, _), (tb, _)) = Self::pair_said(a, b, ix, sp);
        (ta, tb)
    }

    /// [`Self::pair_text`], with what a reader takes each member for: the second, whose room
    /// is left out, is read in the room of the first as read.
    pub fn pair_said(
        a: &ObjRef,
        b: &ObjRef,
        ix: &MapIndex<'_>,
        sp: &mut Speaker<'_>,
    ) -> ((String, Vec<u32>), (String, Vec<u32>)) {
        let first = a.said(ix, sp);
        let (outer, outer_scope) = (sp.implied_room, sp.reader.scope);
        if let Some(r) = a.stated_room(ix).filter(|&r| b.stated_room(ix) == Some(r)) {
            sp.implied_room = Some(r);
            sp.reader.scope = match Reader::rooms_of(ix, &first.1).as_slice() {
                [read] => Some(*read),
                _ => None,
            };
        }
        let second = b.said(ix, sp);
        sp.implied_room = outer;
        sp.reader.scope = outer_scope;
        (first, second)
    }

    /// The description as English. Rooms the episode has already described are referred back
    /// to ("that bedroom") rather than described again.
    pub fn text(&self, ix: &MapIndex<'_>, sp: &mut Speaker<'_>) -> String {
        self.said(ix, sp).0
    }

    /// [`Self::text`], and the objects a reader takes the words for. The rooms, parents and
    /// anchors inside are checked as mentions of their own; the caller checks the whole.
    pub fn said(&self, ix: &MapIndex<'_>, sp: &mut Speaker<'_>) -> (String, Vec<u32>) {
        let (text, read) = self.said_inner(ix, sp);
        sp.reader.named_object(&read);
        (text, read)
    }

    /// A description inside this one (a parent, an anchor): said, read and checked.
    fn said_anchor(&self, ix: &MapIndex<'_>, sp: &mut Speaker<'_>) -> (String, Vec<u32>) {
        let (text, read) = self.said(ix, sp);
        let gold = self.resolve(ix, sp.reader.start);
        sp.reader.note("anchor", &text, gold, read.clone());
        (text, read)
    }

    fn said_inner(&self, ix: &MapIndex<'_>, sp: &mut Speaker<'_>) -> (String, Vec<u32>) {
        match self {
            ObjRef::Unique { cat } => (format!("the {}", sp.noun(cat)), sp.reader.bare(ix, cat)),
            ObjRef::InRoom { cat, room } if sp.is_implied(ix, room) => {
                (format!("the {}", sp.noun(cat)), sp.reader.bare(ix, cat))
            }
            ObjRef::InRoom { cat, room } => {
                let relative = std::mem::take(&mut sp.relative_room);
                let n = sp.noun(cat);
                let prep = ["in", "in", "inside"]
                    .choose(sp.rng)
                    .copied()
                    .unwrap_or("in");
                let (r, rooms) = sp.room_said(ix, room, "room");
                let that = if relative { "that is " } else { "" };
                (
                    format!("the {n} {that}{prep} {r}"),
                    Reader::in_rooms(ix, cat, &rooms),
                )
            }
            ObjRef::On { cat, parent } => {
                let n = sp.noun(cat);
                let prep = ["on", "sitting on", "on top of"]
                    .choose(sp.rng)
                    .copied()
                    .unwrap_or("on");
                let (p, parents) = parent.said_anchor(ix, sp);
                let read = sp
                    .reader
                    .head(ix, cat)
                    .into_iter()
                    .filter(|&o| parents.iter().any(|&p| ix.is_on(o, p)))
                    .collect();
                (format!("the {n} {prep} {p}"), read)
            }
            ObjRef::Nearest { cat, room, anchor } => {
                let n = sp.noun(cat);
                let rel = ["nearest to", "closest to", "nearest the"]
                    .choose(sp.rng)
                    .copied()
                    .unwrap_or("nearest to");
                let rel = if rel == "nearest the" { "nearest" } else { rel };
                let head_room = room.as_ref().filter(|r| !sp.is_implied(ix, r));
                // "The chair closest to the window in the bedroom": a reader may attach the
                // anchor's room to the chair. When that reading picks another chair, the anchor
                // says "the window that is in the bedroom", which attaches to the window only.
                let anchor_room = head_room
                    .is_none()
                    .then(|| self.anchor_room_misread(ix, sp, cat, anchor))
                    .flatten();
                sp.relative_room = anchor_room == Some(true);
                let (a, anchors) = anchor.said_anchor(ix, sp);
                sp.relative_room = false;
                if anchor_room.is_some() {
                    // As written, the room attaches to the anchor alone.
                    let gold = self.resolve(ix, sp.reader.start);
                    sp.reader.note("attachment", &a, gold.clone(), gold);
                }
                let (text, pool) = match head_room {
                    Some(room) => {
                        let (r, rooms) = sp.room_said(ix, room, "room");
                        // "The chair closest to the window in the bedroom", the bedroom being
                        // the chair's: a reader may take it for the window's. Said first
                        // ("the chair in the bedroom closest to the window") when that reading
                        // picks another chair.
                        let after = sp.rng.random_bool(0.5);
                        let misread = after && self.head_room_misread(ix, sp, &rooms, &anchors);
                        if after {
                            // As written, the room follows the object it belongs to, or is
                            // read with it either way.
                            let gold = self.resolve(ix, sp.reader.start);
                            sp.reader.note("attachment", &r, gold.clone(), gold);
                        }
                        let text = if after && !misread {
                            format!("the {n} {rel} {a} in {r}")
                        } else {
                            format!("the {n} in {r} {rel} {a}")
                        };
                        (text, Reader::in_rooms(ix, cat, &rooms))
                    }
                    None => (format!("the {n} {rel} {a}"), sp.reader.head(ix, cat)),
                };
                let read = match anchors.as_slice() {
                    [a] => nearest_with_margin(ix, &pool, *a).into_iter().collect(),
                    _ => pool,
                };
                (text, read)
            }
            ObjRef::FromYou {
                cat,
                room,
                farthest,
            } => {
                let n = sp.noun(cat);
                let rel = if *farthest {
                    [
                        "farthest from you",
                        "farthest from where you start",
                        "farthest from your current position",
                    ]
                } else {
                    [
                        "closest to you",
                        "nearest to where you are now",
                        "closest to your starting position",
                    ]
                };
                let rel = rel.choose(sp.rng).copied().unwrap_or(rel[0]);
                // Kept even inside a scoped clause: "the chair closest to you" alone would be
                // read house-wide.
                let (text, pool) = match room {
                    Some(room) => {
                        let (r, rooms) = sp.room_said(ix, room, "room");
                        (
                            format!("the {n} in {r} {rel}"),
                            Reader::in_rooms(ix, cat, &rooms),
                        )
                    }
                    None => (format!("the {n} {rel}"), ix.all_of_cat(cat).to_vec()),
                };
                let read = match sp.reader.start {
                    Some(s) => ranked_from(ix, &pool, s, *farthest).into_iter().collect(),
                    None => pool,
                };
                (text, read)
            }
            ObjRef::NotOn { cat, room, other } => {
                let n = sp.noun(cat);
                let o = sp.noun(other);
                let art = lexicon::article(&o);
                let (tail, pool) = match room.as_ref().filter(|r| !sp.is_implied(ix, r)) {
                    Some(room) => {
                        let (r, rooms) = sp.room_said(ix, room, "room");
                        (format!(" in {r}"), Reader::in_rooms(ix, cat, &rooms))
                    }
                    None => (String::new(), sp.reader.head(ix, cat)),
                };
                let read = pool
                    .into_iter()
                    .filter(|&x| !ix.of_cat(other).iter().any(|&p| ix.is_on(x, p)))
                    .collect();
                (format!("the {n}{tail} that is not on {art} {o}"), read)
            }
        }
    }

    /// Whether "the X nearest the Y in R" (this description, `cat` the X, `anchor` "the Y in
    /// R") read with "in R" attached to the X picks something other than the gold's object;
    /// `None` when the anchor ends in no room. The other reading: the Xs of R, nearest the Y as
    /// read bare.
    fn anchor_room_misread(
        &self,
        ix: &MapIndex<'_>,
        sp: &Speaker<'_>,
        cat: &str,
        anchor: &ObjRef,
    ) -> Option<bool> {
        let ObjRef::InRoom {
            cat: anchor_cat,
            room,
        } = anchor
        else {
            return None;
        };
        if sp.is_implied(ix, room) {
            return None;
        }
        let pool = Reader::in_rooms(ix, cat, &room.resolve(ix));
        let read: Vec<u32> = match sp.reader.bare(ix, anchor_cat).as_slice() {
            [a] => nearest_with_margin(ix, &pool, *a).into_iter().collect(),
            _ => pool,
        };
        let mut gold = self.resolve(ix, sp.reader.start);
        gold.sort_unstable();
        let mut read = read;
        read.sort_unstable();
        Some(read != gold)
    }

    /// Whether "the X nearest the Y in R" (R the X's room, read as `rooms`; the Y read as
    /// `anchors`) read with "in R" attached to the Y picks something other than the gold's
    /// object. The other reading: the Xs of the reader's scope (else of the house), nearest
    /// the Ys of R.
    fn head_room_misread(
        &self,
        ix: &MapIndex<'_>,
        sp: &Speaker<'_>,
        rooms: &[u32],
        anchors: &[u32],
    ) -> bool {
        let ObjRef::Nearest { cat, .. } = self else {
            return false;
        };
        let in_room: Vec<u32> = anchors
            .iter()
            .copied()
            .filter(|&a| ix.object_room(a).is_some_and(|r| rooms.contains(&r)))
            .collect();
        let pool = sp.reader.head(ix, cat);
        let read: Vec<u32> = match in_room.as_slice() {
            [a] => nearest_with_margin(ix, &pool, *a).into_iter().collect(),
            _ => pool,
        };
        let mut gold = self.resolve(ix, sp.reader.start);
        gold.sort_unstable();
        let mut read = read;
        read.sort_unstable();
        read != gold
    }
}
