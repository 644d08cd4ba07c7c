//! Sentence templates for instructions. Several phrasings per clause, chosen by the episode's seeded
//! RNG, so that a suite does not read as one sentence pattern repeated a thousand times.

use super::generate::AvoidPlace;
use rand::seq::IndexedRandom;
use rand_chacha::ChaCha8Rng;

fn pick<'a>(rng: &mut ChaCha8Rng, options: &[&'a str]) -> &'a str {
    options.choose(rng).copied().unwrap_or(options[0])
}

fn fill(template: &str, pairs: &[(&str, &str)]) -> String {
    let mut s = template.to_string();
    for (k, v) in pairs {
        s = s.replace(&format!("{{{k}}}"), v);
    }
    capitalize(&s)
}

pub fn capitalize(s: &str) -> String {
    let mut chars = s.chars();
    match chars.next() {
        Some(c) => c.to_uppercase().collect::<String>() + chars.as_str(),
        None => String::new(),
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

pub fn destination(rng: &mut ChaCha8Rng, pos: Position, target: &str) -> String {
    let t = match pos {
        Position::Only => pick(
            rng,
            &[
                "go to {t}.",
                "head to {t}.",
                "make your way to {t}.",
                "please walk over to {t}.",
                "navigate to {t}.",
                "your destination is {t}.",
            ],
        ),
        Position::First => pick(
            rng,
            &[
                "first, go to {t}.",
                "start by heading to {t}.",
                "begin by walking to {t}.",
            ],
        ),
        Position::Middle => pick(
            rng,
            &[
                "then continue to {t}.",
                "after that, head over to {t}.",
                "next, make your way to {t}.",
            ],
        ),
        Position::Last => pick(
            rng,
            &[
                "finally, go to {t}.",
                "finish at {t}.",
                "your last stop is {t}.",
                "end the route at {t}.",
            ],
        ),
    };
    fill(t, &[("t", target)])
}

pub fn near(rng: &mut ChaCha8Rng, x: &str, room: &str) -> String {
    let t = pick(
        rng,
        &[
            "in {r}, stay close to {x}.",
            "keep near {x} as you cross {r}.",
            "while crossing {r}, hug {x}.",
        ],
    );
    fill(t, &[("x", x), ("r", room)])
}

pub fn far(rng: &mut ChaCha8Rng, x: &str, room: &str) -> String {
    let t = pick(
        rng,
        &[
            "in {r}, keep well away from {x}.",
            "stay far from {x} when crossing {r}.",
            "in {r}, give {x} a wide berth.",
        ],
    );
    fill(t, &[("x", x), ("r", room)])
}

pub fn relative(rng: &mut ChaCha8Rng, a: &str, b: &str, room: &str) -> String {
    let t = pick(
        rng,
        &[
            "in {r}, stay closer to {a} than to {b}.",
            "crossing {r}, keep nearer to {a} than to {b}.",
            "in {r}, favour the side of {a} over {b}.",
        ],
    );
    fill(t, &[("a", a), ("b", b), ("r", room)])
}

pub fn circle(rng: &mut ChaCha8Rng, x: &str, clockwise: bool) -> String {
    let dir = if clockwise {
        "clockwise"
    } else {
        "counterclockwise"
    };
    let t = pick(
        rng,
        &[
            "on the way there, circle around {x} {d}.",
            "on this leg, loop {d} around {x}.",
            "walk a {d} loop around {x} on the way.",
        ],
    );
    fill(t, &[("x", x), ("d", dir)])
}

pub fn clearance(rng: &mut ChaCha8Rng) -> String {
    pick(
        rng,
        &[
            "Keep a safe distance from furniture.",
            "Stay clear of obstacles on the way.",
            "Do not brush past any furniture.",
        ],
    )
    .to_string()
}

/// A must-avoid sentence: for the whole route (`global`) or for the current leg.
pub fn avoid(rng: &mut ChaCha8Rng, place: &AvoidPlace, x: &str, global: bool) -> String {
    let t = match (place, global) {
        (AvoidPlace::Room(_), true) => pick(
            rng,
            &[
                "never enter {x}.",
                "do not go through {x} at any point.",
                "stay out of {x} for the whole route.",
            ],
        ),
        (AvoidPlace::Room(_), false) => pick(
            rng,
            &[
                "on the way there, do not pass through {x}.",
                "on this leg, avoid {x}.",
                "do not cut through {x} while heading there.",
            ],
        ),
        (AvoidPlace::Around(_), true) => pick(
            rng,
            &[
                "keep out of the area around {x}.",
                "never step close to {x}.",
            ],
        ),
        (AvoidPlace::Around(_), false) => pick(
            rng,
            &[
                "on this leg, keep out of the area around {x}.",
                "on the way there, do not step close to {x}.",
            ],
        ),
        (AvoidPlace::Between(..), true) => {
            pick(rng, &["don't walk between {x}.", "never pass between {x}."])
        }
        (AvoidPlace::Between(..), false) => pick(
            rng,
            &[
                "on this leg, don't walk between {x}.",
                "on the way there, do not pass between {x}.",
            ],
        ),
    };
    fill(t, &[("x", x)])
}
