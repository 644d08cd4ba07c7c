//! The words and program expression of each kind of destination.

use super::Out;
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
                let t = desc.text(ix, sp);
                out.stat(ix, &role, desc, &t);
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
                let r = sp.room(ix, room);
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
                let a = anchor.text(ix, sp);
                out.stat(ix, &role, anchor, &a);
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
                let (ta, tb) = ObjRef::pair_text(a, b, ix, sp);
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
