//! The words and program expression of each kind of destination.

use super::Out;
use crate::suite::determinacy::Reader;
use crate::suite::generate::Scene;
use crate::suite::lexicon;
use crate::suite::plan::{Dest, Stage};
use crate::suite::realise::{self, Speaker};
use crate::suite::refs::ObjRef;

impl<'a> Scene<'a> {
    /// (text, program expression, short anaphoric name) of a destination.
    pub(super) fn dest_text(
        &self,
        sp: &mut Speaker<'_>,
        out: &mut Out,
        k: usize,
        stages: &[Stage],
    ) -> (String, String, String) {
        let ix = &self.ix;
        let stage = &stages[k];
        let role = format!("destination {}", k + 1);
        match &stage.dest {
            Dest::Object { id, desc } => {
                let (t, read) = desc.said(ix, sp);
                out.stat(ix, &role, desc, &t);
                self.check_destination(sp, &t, *id, read);
                let short = format!("the {}", lexicon::plain(&ix.object(*id).category));
                (t, desc.m2r(), short)
            }
            Dest::Conditional {
                id,
                room,
                cond_cat,
                holds,
                then_desc,
                else_desc,
            } => {
                let (r, rooms) = sp.room_said(ix, room, "room");
                out.stat_room(ix, &role, room, &r);
                let thing = lexicon::plain(cond_cat);
                let other_cat = else_desc.category();
                let other = format!(
                    "the {} {}",
                    sp.noun(other_cat),
                    sp.pick("if.there", &["there", "in that room", "instead"])
                );
                let live = if *holds { then_desc } else { else_desc };
                out.stat(ix, &role, live, &format!("the {}", live.category()));
                // "Go to it" / "the desk there": the live branch's object in the room as read.
                let words = if *holds {
                    format!("the {thing} in {r}")
                } else {
                    other.clone()
                };
                let read = Reader::in_rooms(ix, live.category(), &rooms);
                self.check_destination(sp, &words, *id, read);
                let s = realise::conditional(sp, &r, &thing, &other);
                let m2r = format!(
                    "if objects({cond_cat}).in({}).exists() {{ {} }} else {{ {} }}",
                    room.m2r(),
                    then_desc.m2r(),
                    else_desc.m2r()
                );
                let short = format!("the {}", lexicon::plain(&ix.object(*id).category));
                (s, m2r, short)
            }
            Dest::Corner {
                room,
                room_ref,
                anchor,
            } => {
                let r = sp.room_id(ix, *room, Some(room_ref));
                out.stat_room(ix, &role, room_ref, &r);
                let (a, read) = anchor.said(ix, sp);
                out.stat(ix, &role, anchor, &a);
                let gold = anchor.resolve(ix, sp.reader.start);
                sp.reader.note("anchor", &a, gold, read);
                let rel = sp.pick("corner", &["nearest to", "closest to", "next to"]);
                let t = format!("the corner of {r} {rel} {a}");
                out.stat_structure(&role, "corner", self.corner_count(), &t);
                let m2r = format!("{}.corners().nearest(to: {})", room_ref.m2r(), anchor.m2r());
                (t, m2r, "that corner".into())
            }
            Dest::Doorway { a, b } => {
                let ta = sp.room(ix, a);
                out.stat_room(ix, &role, a, &ta);
                let tb = sp.room(ix, b);
                out.stat_room(ix, &role, b, &tb);
                let form = sp.pick(
                    "doorway",
                    &[
                        "the doorway between {a} and {b}",
                        "the door connecting {a} and {b}",
                        "the doorway from {a} into {b}",
                    ],
                );
                let t = realise::fill(form, &[("a", &ta), ("b", &tb)]);
                out.stat_structure(
                    &role,
                    "doorway",
                    ix.count_any(&["doorway", "doorframe"]),
                    &t,
                );
                (
                    t,
                    format!("doorways_between({}, {}).only()", a.m2r(), b.m2r()),
                    "that doorway".into(),
                )
            }
            Dest::Other { id, cat, first } => {
                let noun = sp.noun(cat);
                // "The other one" only right after its pair's first member: a preference said
                // in between ("circle the dining table") would become its antecedent.
                let nothing_between =
                    stages[*first].softs.is_empty() && stages[*first].avoids.is_empty();
                let t = if *first + 1 == k && sp.chance(0.5) && nothing_between {
                    "the other one".to_string()
                } else {
                    format!("the other {noun}")
                };
                out.stat_implied(ix, &role, cat, &t);
                // "The other one": the other of the last destination's category, as read.
                let of = match (t.as_str(), sp.reader.last_destination) {
                    ("the other one", Some(last)) => ix.object(last).category.clone(),
                    _ => cat.clone(),
                };
                let read = sp.reader.other(ix, &of);
                self.check_destination(sp, &t, *id, read);
                // "While heading to the other couch": "the couch" would be either of the two.
                let short = format!("the other {}", lexicon::plain(&ix.object(*id).category));
                (
                    t,
                    format!("objects({cat}).except(t{}).only()", first + 1),
                    short,
                )
            }
            Dest::Return => (
                "the starting point".into(),
                "start".into(),
                "your starting point".into(),
            ),
            Dest::Between { a, b } => {
                let (ta, tb) = self.partners(sp, a, b);
                out.stat(ix, &role, a, &ta);
                out.stat(ix, &role, b, &tb);
                let form = sp.pick(
                    "between",
                    &[
                        "the small area between {a} and {b}",
                        "the spot between {a} and {b}",
                    ],
                );
                let t = realise::fill(form, &[("a", &ta), ("b", &tb)]);
                (
                    t,
                    format!("area_between({}, {})", a.m2r(), b.m2r()),
                    "that spot".into(),
                )
            }
        }
    }

    /// Checks a destination's words, which become the antecedent of "the other one".
    fn check_destination(&self, sp: &mut Speaker<'_>, words: &str, id: u32, read: Vec<u32>) {
        sp.reader.last_destination = match read.as_slice() {
            [o] => Some(*o),
            _ => None,
        };
        sp.reader.named_object(&read);
        sp.reader.note("destination", words, vec![id], read);
    }

    /// The two partners of an area between ("between the sofa and the TV"), each checked.
    pub(super) fn partners(
        &self,
        sp: &mut Speaker<'_>,
        a: &ObjRef,
        b: &ObjRef,
    ) -> (String, String) {
        let ix = &self.ix;
        let ((ta, ra), (tb, rb)) = ObjRef::pair_said(a, b, ix, sp);
        for (d, t, read) in [(a, &ta, ra), (b, &tb, rb)] {
            let gold = d.resolve(ix, sp.reader.start);
            sp.reader.note("between partner", t, gold, read);
        }
        (ta, tb)
    }

    /// Corners of every room of the house, as `rooms(..).corners()` finds them.
    fn corner_count(&self) -> usize {
        self.ix
            .rooms_by_cat
            .values()
            .flatten()
            .map(|&r| self.q.corners(r).len())
            .sum()
    }
}
