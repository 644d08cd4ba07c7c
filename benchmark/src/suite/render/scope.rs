//! The words of a preference's scope room, its subjects and the leg phrase before them, each
//! read back as written ([`crate::suite::determinacy`]): the scope phrase a sentence says is the
//! room its bare subjects are read in, and a leg phrase ("on the way to the desk") names its
//! destination outside that scope.

use super::Out;
use crate::suite::determinacy::Reader;
use crate::suite::generate::Scene;
use crate::suite::lexicon;
use crate::suite::plan::{RoomScope, SoftPlan, Subject};
use crate::suite::realise::{self, Speaker};

/// The destination of a leg, as a preference's sentence refers to it.
#[derive(Clone, Copy)]
pub(super) struct StageDest<'a> {
    /// Its short name ("the desk", "that corner").
    pub short: &'a str,
    pub room: u32,
    /// The object `short` names by its category alone ("the desk"), when it does.
    pub named: Option<u32>,
}

/// A leg phrase ("on the way to the desk"), the destination object it names by category, and
/// what a reader takes that name for where the phrase stands: first in its sentence, so before
/// anything the rest of the sentence names.
pub(super) struct LegPhrase {
    pub text: String,
    pub names: Option<u32>,
    pub read: Vec<u32>,
}

/// The kind of mention a preference's subject is, by the preference's role.
fn subject_kind(role: &str) -> &'static str {
    match role {
        "relative preference" => "relative pair",
        "path_shape preference" => "path-shape subject",
        _ => "preference subject",
    }
}

impl<'a> Scene<'a> {
    /// What a reader in state `reader` takes a leg phrase's destination name for: outside any
    /// clause's scope, "the desk" is the desk the instruction has named.
    pub(super) fn leg_read(&self, reader: &Reader, names: Option<u32>) -> Vec<u32> {
        let Some(id) = names else { return vec![] };
        let mut outside = reader.clone();
        outside.scope = None;
        outside.bare(&self.ix, &self.ix.object(id).category)
    }

    /// Checks the destination a leg phrase names, once the phrase is said.
    pub(super) fn check_leg(&self, sp: &mut Speaker<'_>, leg: &LegPhrase) {
        if let Some(id) = leg.names {
            sp.reader
                .note("destination", &leg.text, vec![id], leg.read.clone());
        }
    }

    /// The room a short name ("the desk") puts its destination in, as read.
    fn room_named_by(&self, sp: &Speaker<'_>, dest: StageDest<'_>) -> Vec<u32> {
        let ix = &self.ix;
        match dest.named {
            Some(id) => Reader::rooms_of(ix, &sp.reader.bare(ix, &ix.object(id).category)),
            // "That corner", "the other sofa", "that spot": the destination just named.
            None => vec![dest.room],
        }
    }

    /// The program expression and the words for a scope room R; the room as read becomes the
    /// reader's scope for the clause.
    pub(super) fn scope(
        &self,
        sp: &mut Speaker<'_>,
        out: &mut Out,
        soft: &SoftPlan,
        var: &str,
        dest: StageDest<'_>,
    ) -> (String, String) {
        let ix = &self.ix;
        // The destination's room (for `Before`, the room after R, not R itself), and as read.
        let dest_room = |sp: &mut Speaker<'_>| {
            if var == "start" {
                let t = "the room you started in".to_string();
                sp.reader.note("room", &t, vec![dest.room], vec![dest.room]);
                sp.reader.named_room(&[dest.room]);
                (t, vec![dest.room])
            } else if sp.knows_room(dest.room) && !sp.back_forms(ix, dest.room).is_empty() {
                sp.room_id_said(ix, dest.room, None, "room")
            } else {
                let t = sp.pick("room.of", &["the room with {d}", "the room where {d} is"]);
                let t = realise::fill(t, &[("d", dest.short)]);
                let read = self.room_named_by(sp, dest);
                sp.reader.note("room", &t, vec![dest.room], read.clone());
                sp.reader.named_room(&read);
                (t, read)
            }
        };
        let (m2r, text, read) = match &soft.scope {
            RoomScope::Destination => {
                let (r, read) = dest_room(sp);
                let t = sp.pick(
                    "scope.dest",
                    &["once you are in {r}", "in {r}", "when you enter {r}"],
                );
                (
                    format!("{var}.room()"),
                    realise::fill(t, &[("r", &r)]),
                    read,
                )
            }
            RoomScope::Start => {
                let t = sp.pick(
                    "scope.start",
                    &[
                        "while you are still in the starting room",
                        "before you leave the room you start in",
                        "in the room you start in",
                    ],
                );
                sp.reader.note("room", t, vec![soft.room], vec![soft.room]);
                sp.reader.named_room(&[soft.room]);
                ("start.room()".into(), t.to_string(), vec![soft.room])
            }
            RoomScope::Before => {
                let (r, after) = dest_room(sp);
                let t = sp.pick(
                    "scope.before",
                    &[
                        "in the room just before {r}",
                        "in the room right before you enter {r}",
                    ],
                );
                let t = realise::fill(t, &[("r", &r)]);
                // The only way into the room after it, as the language's `room_before_entering`.
                let read = if after == [dest.room] {
                    vec![soft.room]
                } else {
                    after
                };
                sp.reader.note("room", &t, vec![soft.room], read.clone());
                sp.reader.named_room(&read);
                (format!("room_before_entering({var}.room())"), t, read)
            }
            RoomScope::Crossed(rr) => {
                let (r, read) = sp.room_said(ix, rr, "room");
                out.stat_room(ix, "scope", rr, &r);
                let t = sp.pick(
                    "scope.cross",
                    &[
                        "as you pass through {r}",
                        "when you cross {r}",
                        "while in {r}",
                    ],
                );
                (rr.m2r(), realise::fill(t, &[("r", &r)]), read)
            }
        };
        sp.reader.scope = match read.as_slice() {
            [r] => Some(*r),
            _ => None,
        };
        (m2r, text)
    }

    /// (text, program) of a preference subject measured in scope `s`, checked as read in the
    /// clause's scope.
    pub(super) fn subject_text(
        &self,
        sp: &mut Speaker<'_>,
        out: &mut Out,
        x: &Subject,
        s: &str,
        role: &str,
    ) -> (String, String) {
        let ix = &self.ix;
        let kind = subject_kind(role);
        match x {
            Subject::One(o, None) => {
                let cat = &ix.object(*o).category;
                let t = format!("the {}", sp.noun(cat));
                out.stat_implied(ix, role, cat, &t);
                let read = sp.reader.bare(ix, cat);
                sp.reader.note(kind, &t, vec![*o], read.clone());
                sp.reader.named_object(&read);
                (t, format!("objects({cat}).in({s}).only()"))
            }
            Subject::One(o, Some(d)) => {
                let (t, read) = d.said(ix, sp);
                out.stat(ix, role, d, &t);
                sp.reader.note(kind, &t, vec![*o], read);
                (t, d.m2r())
            }
            Subject::All { cat, ids } => {
                let p = lexicon::plural(&lexicon::plain(cat));
                let t = sp.pick("all", &["the {p}", "all the {p}", "any of the {p}"]);
                let t = realise::fill(t, &[("p", &p)]);
                out.stat_implied(ix, role, cat, &t);
                let read = match sp.reader.scope {
                    Some(r) => Reader::in_rooms(ix, cat, &[r]),
                    None => ix.all_of_cat(cat).to_vec(),
                };
                sp.reader.note(kind, &t, ids.clone(), read);
                (t, format!("objects({cat}).in({s})"))
            }
        }
    }
}
