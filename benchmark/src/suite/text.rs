//! Sentence templates for instructions. Several phrasings per clause, chosen by the episode's seeded
//! RNG, so that a suite does not read as one sentence pattern repeated a thousand times.

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
            "on the way there, while you are in {r}, stay as close as you can to {x}.",
            "on this leg, keep near {x} as you move through {r}.",
            "while crossing {r} on the way, hug {x} as closely as possible.",
        ],
    );
    fill(t, &[("x", x), ("r", room)])
}

pub fn far(rng: &mut ChaCha8Rng, x: &str, room: &str) -> String {
    let t = pick(
        rng,
        &[
            "on the way there, keep well away from {x} while you are in {r}.",
            "on this leg, stay as far as possible from {x} when crossing {r}.",
            "in {r}, give {x} a wide berth on the way.",
        ],
    );
    fill(t, &[("x", x), ("r", room)])
}

pub fn relative(rng: &mut ChaCha8Rng, a: &str, b: &str, room: &str) -> String {
    let t = pick(
        rng,
        &[
            "on the way there, inside {r}, stay closer to {a} than to {b}.",
            "on this leg, when moving through {r}, keep nearer to {a} than to {b}.",
            "while in {r} on the way, favour the side of {a} over {b}.",
        ],
    );
    fill(t, &[("a", a), ("b", b), ("r", room)])
}

pub fn circle(rng: &mut ChaCha8Rng, x: &str, room: &str, clockwise: bool) -> String {
    let dir = if clockwise {
        "clockwise"
    } else {
        "counterclockwise"
    };
    let t = pick(
        rng,
        &[
            "on the way there, circle around {x} {d} while you are in {r}.",
            "on this leg, loop {d} around {x} in {r}.",
        ],
    );
    fill(t, &[("x", x), ("r", room), ("d", dir)])
}

pub fn clearance(rng: &mut ChaCha8Rng) -> String {
    pick(
        rng,
        &[
            "On this leg, keep a safe distance from furniture and walls.",
            "Stay clear of obstacles while you go there.",
            "On the way, do not brush past any furniture; keep some clearance.",
        ],
    )
    .to_string()
}

pub fn avoid_global(rng: &mut ChaCha8Rng, room: &str) -> String {
    let t = pick(
        rng,
        &[
            "never enter {r}.",
            "do not go through {r} at any point.",
            "stay out of {r} for the whole route.",
            "at no time should you pass through {r}.",
        ],
    );
    fill(t, &[("r", room)])
}

pub fn avoid_stage(rng: &mut ChaCha8Rng, room: &str) -> String {
    let t = pick(
        rng,
        &[
            "on the way there, do not pass through {r}.",
            "on this leg, avoid {r}.",
            "do not cut through {r} while heading there.",
        ],
    );
    fill(t, &[("r", room)])
}
