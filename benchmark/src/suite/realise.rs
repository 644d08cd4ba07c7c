//! Sentence realisation: the seeded template grammar that turns an episode plan into English.
//!
//! Every clause comes from a named template (`dest.first.2`, `near.1`, `scope.start.0`, ...)
//! whose id is recorded with the gold-program statement it realises (`m2rc_generation.clauses`),
//! so every surface form can be traced back to the program. The [`Speaker`] remembers what the
//! episode has described: a room is described in full once and referred back to afterwards
//! ("that room", "the same bedroom"), which the naturalness counters check.

use super::determinacy::Reader;
use super::index::MapIndex;
use super::lexicon;
use super::refs::RoomRef;
use rand::Rng;
use rand::seq::IndexedRandom;
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeMap;

/// Ways of referring back to a room described before (template `room.back.<i>`).
const BACK_FORMS: [&str; 4] = ["that room", "the same {n}", "that {n}", "this {n}"];

/// The episode's narrator: its RNG, and what it has said.
pub struct Speaker<'r> {
    pub rng: &'r mut ChaCha8Rng,
    /// Full descriptions given per room id.
    pub room_full: BTreeMap<u32, usize>,
    /// Anaphoric references per room id.
    pub room_back: BTreeMap<u32, usize>,
    /// Descriptions given again per room id, where no "that room" would have named it (another
    /// room of its kind was named since).
    pub room_again: BTreeMap<u32, usize>,
    /// Template ids used, in order.
    pub templates: Vec<String>,
    /// The room a clause is already scoped to ("in this lounge, ..."): descriptions inside the
    /// clause leave it out rather than name it a second time.
    pub implied_room: Option<u32>,
    /// Say the next "the X in R" as "the X that is in R": set while an anchor whose room a
    /// reader could attach to the described object is said (`ObjRef::said`).
    pub relative_room: bool,
    /// The episode read back as it is written, to check that every mention names the gold's
    /// object ([`super::determinacy`]).
    pub reader: Reader,
}

impl<'r> Speaker<'r> {
    pub fn new(rng: &'r mut ChaCha8Rng) -> Self {
        Speaker {
            rng,
            room_full: BTreeMap::new(),
            room_back: BTreeMap::new(),
            room_again: BTreeMap::new(),
            templates: Vec::new(),
            implied_room: None,
            relative_room: false,
            reader: Reader::default(),
        }
    }

    /// Whether `r` is the room the current clause is scoped to, so that naming it is redundant.
    pub fn is_implied(&self, ix: &MapIndex<'_>, r: &RoomRef) -> bool {
        self.implied_room
            .is_some_and(|id| r.resolve(ix).as_slice() == [id])
    }

    pub fn noun(&mut self, cat: &str) -> String {
        lexicon::noun(cat, self.rng)
    }

    /// Whether room `id` has been described already.
    pub fn knows_room(&self, id: u32) -> bool {
        self.room_full.contains_key(&id)
    }

    /// A room: described in full the first time, referred back to afterwards.
    pub fn room(&mut self, ix: &MapIndex<'_>, r: &RoomRef) -> String {
        self.room_said(ix, r, "room").0
    }

    /// [`Self::room`], and the rooms a reader takes the words for, checked as a mention of
    /// `kind` against the room `r` describes.
    pub fn room_said(&mut self, ix: &MapIndex<'_>, r: &RoomRef, kind: &str) -> (String, Vec<u32>) {
        match r.resolve(ix).as_slice() {
            [id] => self.room_id_said(ix, *id, Some(r), kind),
            _ => {
                let t = r.full_text(self.rng);
                let read = r.resolve(ix);
                self.reader.note(kind, &t, read.clone(), read.clone());
                (t, read)
            }
        }
    }

    /// Room `id` by its description `r` (or, when none, by its category).
    pub fn room_id(&mut self, ix: &MapIndex<'_>, id: u32, r: Option<&RoomRef>) -> String {
        self.room_id_said(ix, id, r, "room").0
    }

    /// [`Self::room_id`], and what a reader takes the words for.
    pub fn room_id_said(
        &mut self,
        ix: &MapIndex<'_>,
        id: u32,
        r: Option<&RoomRef>,
        kind: &str,
    ) -> (String, Vec<u32>) {
        let cat = ix.room_category(id).to_string();
        // A room already described is referred back to by a form a reader resolves to it:
        // "that room" is the room named last, "that bedroom" the bedroom named last. When none
        // does (another bedroom was named since), the description is given again.
        let fits = self.back_forms(ix, id);
        let full = match r {
            Some(r) if !self.knows_room(id) || fits.is_empty() => Some(r),
            _ => None,
        };
        let (t, read) = match full {
            Some(r) => {
                if self.knows_room(id) {
                    *self.room_again.entry(id).or_default() += 1;
                } else {
                    *self.room_full.entry(id).or_default() += 1;
                }
                (r.full_text(self.rng), r.resolve(ix))
            }
            None => {
                *self.room_back.entry(id).or_default() += 1;
                let n = lexicon::noun(&cat, self.rng);
                // Only a form that names the room; with none, any (the check flags it).
                let pool: Vec<usize> = if fits.is_empty() {
                    (0..BACK_FORMS.len()).collect()
                } else {
                    fits
                };
                let i = pool[self.rng.random_range(0..pool.len())];
                self.templates.push(format!("room.back.{i}"));
                let form = BACK_FORMS[i];
                let read = self
                    .reader
                    .back_room(ix, form.contains("{n}").then_some(cat.as_str()));
                (form.replace("{n}", &n), read)
            }
        };
        self.reader.note(kind, &t, vec![id], read.clone());
        self.reader.named_room(&read);
        (t, read)
    }

    /// The forms of [`BACK_FORMS`] (indices) a reader would resolve to room `id` now.
    pub fn back_forms(&self, ix: &MapIndex<'_>, id: u32) -> Vec<usize> {
        let cat = ix.room_category(id);
        (0..BACK_FORMS.len())
            .filter(|&i| {
                let of = BACK_FORMS[i].contains("{n}").then_some(cat);
                self.reader.back_room(ix, of) == [id]
            })
            .collect()
    }

    /// One of `options`, recording the template id `family.index`.
    pub fn pick<'a>(&mut self, family: &str, options: &[&'a str]) -> &'a str {
        let i = self.rng.random_range(0..options.len());
        self.templates.push(format!("{family}.{i}"));
        options[i]
    }

    pub fn chance(&mut self, p: f64) -> bool {
        self.rng.random_bool(p)
    }

    pub fn choose<'a, T>(&mut self, v: &'a [T]) -> Option<&'a T> {
        v.choose(self.rng)
    }
}

pub fn fill(template: &str, pairs: &[(&str, &str)]) -> String {
    let mut s = template.to_string();
    for (k, v) in pairs {
        s = s.replace(&format!("{{{k}}}"), v);
    }
    s
}

pub fn capitalize(s: &str) -> String {
    let mut chars = s.chars();
    match chars.next() {
        Some(c) => c.to_uppercase().collect::<String>() + chars.as_str(),
        None => String::new(),
    }
}

/// A finished sentence: capitalised, with a full stop.
pub fn sentence(s: &str) -> String {
    let s = s.trim();
    let s = capitalize(s);
    if s.ends_with('.') || s.ends_with('?') {
        s
    } else {
        format!("{s}.")
    }
}

/// Where a destination sits in the sequence.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Position {
    Only,
    First,
    Middle,
    Last,
}

pub fn destination(sp: &mut Speaker<'_>, pos: Position, t: &str) -> String {
    let tpl = match pos {
        Position::Only => sp.pick(
            "dest.only",
            &[
                "go to {t}",
                "head to {t}",
                "make your way to {t}",
                "please walk over to {t}",
                "your destination is {t}",
                "I need you at {t}",
                "find {t} and go there",
            ],
        ),
        Position::First => sp.pick(
            "dest.first",
            &[
                "first, go to {t}",
                "start by heading to {t}",
                "begin by walking to {t}",
                "go to {t} first",
            ],
        ),
        Position::Middle => sp.pick(
            "dest.middle",
            &[
                "then continue to {t}",
                "after that, head over to {t}",
                "next, make your way to {t}",
                "from there, go to {t}",
            ],
        ),
        Position::Last => sp.pick(
            "dest.last",
            &[
                "finally, go to {t}",
                "finish at {t}",
                "your last stop is {t}",
                "end the route at {t}",
                "and lastly, head to {t}",
            ],
        ),
    };
    sentence(&fill(tpl, &[("t", t)]))
}

/// Two destinations stated out of route order: "Before you go to B, stop at A."
pub fn before_pair(sp: &mut Speaker<'_>, a: &str, b: &str) -> String {
    let tpl = sp.pick(
        "dest.pair",
        &[
            "before you go to {b}, stop at {a}",
            "you will end up at {b}, but visit {a} on the way",
            "on your way to {b}, pass by {a} first",
        ],
    );
    sentence(&fill(tpl, &[("a", a), ("b", b)]))
}

/// "If the bedroom has a lamp, go to it; otherwise go to the desk."
pub fn conditional(sp: &mut Speaker<'_>, room: &str, thing: &str, otherwise: &str) -> String {
    let art = lexicon::article(thing);
    let tpl = sp.pick(
        "dest.if",
        &[
            "if {r} has {art} {x}, go to it; otherwise go to {o}",
            "check whether there is {art} {x} in {r}: if there is, head to it, and if not, head to {o}",
            "go to the {x} in {r} if there is one, and to {o} if there is not",
        ],
    );
    sentence(&fill(
        tpl,
        &[("r", room), ("x", thing), ("o", otherwise), ("art", art)],
    ))
}

pub fn near(sp: &mut Speaker<'_>, x: &str) -> String {
    let t = sp.pick(
        "near",
        &[
            "stay close to {x}",
            "keep near {x}",
            "stay as close to {x} as you can",
            "try to remain close to {x}",
            "pass close by {x}",
        ],
    );
    fill(t, &[("x", x)])
}

/// A near preference said of passing its subject (R is the floor around it).
pub fn near_passing(sp: &mut Speaker<'_>, x: &str) -> String {
    let t = sp.pick(
        "near.passing",
        &[
            "stay close to {x} as you pass it",
            "keep near {x} as you go by it",
            "keep close to {x} whenever you pass it",
            "pass right by {x}",
        ],
    );
    fill(t, &[("x", x)])
}

pub fn far(sp: &mut Speaker<'_>, x: &str) -> String {
    let t = sp.pick(
        "far",
        &[
            "keep away from {x}",
            "stay far from {x}",
            "give {x} a wide berth",
            "keep your distance from {x}",
            "stay well clear of {x}",
        ],
    );
    fill(t, &[("x", x)])
}

pub fn relative(sp: &mut Speaker<'_>, a: &str, b: &str) -> String {
    let t = sp.pick(
        "relative",
        &[
            "stay closer to {a} than to {b}",
            "keep nearer to {a} than to {b}",
            "keep to the side of {a} rather than {b}",
            "try to stay closer to {a} than to {b}",
        ],
    );
    fill(t, &[("a", a), ("b", b)])
}

fn dir_word(clockwise: bool) -> &'static str {
    if clockwise {
        "clockwise"
    } else {
        "counterclockwise"
    }
}

pub fn circle(sp: &mut Speaker<'_>, x: &str, clockwise: bool) -> String {
    let t = sp.pick(
        "circle",
        &[
            "circle {x} once {d}",
            "walk a {d} loop around {x}",
            "go once around {x}, {d}",
        ],
    );
    fill(t, &[("x", x), ("d", dir_word(clockwise))])
}

pub fn patrol(sp: &mut Speaker<'_>, clockwise: bool) -> String {
    let t = sp.pick(
        "patrol",
        &[
            "first make a {d} patrol around the room you start in, and stop the patrol when you reach the doorway you leave by",
            "begin with a {d} patrol along the walls of the starting room, ending at the door you leave through",
            "patrol the current room {d} along its walls before leaving it",
        ],
    );
    fill(t, &[("d", dir_word(clockwise))])
}

pub fn follow_wall(sp: &mut Speaker<'_>, clockwise: bool) -> String {
    let t = sp.pick(
        "follow_wall",
        &[
            "follow the walls of the room you start in once around, {d}",
            "walk {d} along the walls of the starting room before you head off",
            "trace the walls of your current room {d}",
        ],
    );
    fill(t, &[("d", dir_word(clockwise))])
}

/// "the sofa, then the lamp" / "the sofa, then the lamp, and then the desk".
fn in_order(xs: &[&str]) -> String {
    match xs {
        [] => String::new(),
        [a] => (*a).to_string(),
        [a, b] => format!("{a} and then {b}"),
        [init @ .., last] => format!("{}, and then {last}", init.join(", then ")),
    }
}

pub fn through(sp: &mut Speaker<'_>, xs: &[&str]) -> String {
    let list = in_order(xs);
    let t = match xs {
        [a, b] => {
            let t = sp.pick(
                "through.two",
                &[
                    "weave past {l}",
                    "walk past {a} first and then past {b}",
                    "pass first by {a} and then by {b}",
                    "make your way past {a} and then {b}",
                ],
            );
            return fill(t, &[("l", &list), ("a", a), ("b", b)]);
        }
        _ => sp.pick(
            "through.many",
            &["weave past {l}", "pass by {l}", "walk past {l}"],
        ),
    };
    fill(t, &[("l", &list)])
}

/// A leg qualifier for preferences when the episode has several stages.
pub fn leg(sp: &mut Speaker<'_>, dest: &str) -> String {
    let t = sp.pick(
        "leg",
        &[
            "on the way to {t}",
            "while heading to {t}",
            "as you go to {t}",
        ],
    );
    fill(t, &[("t", dest)])
}

/// A leg qualifier for a conditional destination, which must not be named (the same number of
/// choices as [`leg`], so the draw after it is the same).
pub fn leg_there(sp: &mut Speaker<'_>) -> String {
    sp.pick(
        "leg.there",
        &["on the way there", "while heading there", "as you go there"],
    )
    .to_string()
}

/// The last destination when it is the start again.
pub fn return_to_start(sp: &mut Speaker<'_>) -> String {
    let t = sp.pick(
        "dest.back",
        &[
            "then return to the starting point",
            "finally, come back to where you started",
            "after that, head back to your starting position",
            "and then return to where you began",
        ],
    );
    sentence(t)
}

/// The leg phrase of the way back to the start.
pub fn leg_back(sp: &mut Speaker<'_>) -> String {
    sp.pick(
        "leg.back",
        &["on your way back", "as you head back", "on the way back"],
    )
    .to_string()
}

/// A must-avoid sentence: for the whole route (`global`) or for one leg (`leg` phrase).
pub fn avoid(sp: &mut Speaker<'_>, kind: &str, x: &str, leg: Option<&str>) -> String {
    let t = match (kind, leg.is_none()) {
        ("room", true) => sp.pick(
            "avoid.room.global",
            &[
                "never enter {x}",
                "do not go through {x} at any point",
                "stay out of {x} for the whole route",
            ],
        ),
        ("room", false) => sp.pick(
            "avoid.room.leg",
            &[
                "{l}, do not pass through {x}",
                "{l}, avoid {x}",
                "do not cut through {x} {l}",
            ],
        ),
        ("around", true) => sp.pick(
            "avoid.around.global",
            &["keep out of the area around {x}", "never step close to {x}"],
        ),
        ("around", false) => sp.pick(
            "avoid.around.leg",
            &[
                "{l}, keep out of the area around {x}",
                "do not step close to {x} {l}",
            ],
        ),
        (_, true) => sp.pick(
            "avoid.between.global",
            &["don't walk between {x}", "never pass between {x}"],
        ),
        (_, false) => sp.pick(
            "avoid.between.leg",
            &["{l}, don't walk between {x}", "do not pass between {x} {l}"],
        ),
    };
    sentence(&fill(t, &[("x", x), ("l", leg.unwrap_or(""))]))
}
