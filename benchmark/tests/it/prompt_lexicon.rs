//! The suite's phrase templates against the built-in table (issue 35 item 1): a model reads the
//! prompt's one-line description of each built-in and matches it to the instruction's words, so
//! no template the suite writes for one constraint may appear in another built-in's description
//! ("pass close by the box" is a near preference; `through` once said "Pass close by `a`, then
//! `b`", and three of five answers wrote `through(box)`).

use m2rc_benchmark::suite::realise::{self, Speaker};
use m2rc_stdlib::builtins::BUILTINS;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeSet;

/// Every phrase one realiser writes, collected over enough seeds to draw each template, with the
/// places written as `@a`, `@b`, `@c`.
fn phrases(f: impl Fn(&mut Speaker<'_>) -> String) -> BTreeSet<String> {
    (0..256u64)
        .map(|seed| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let mut sp = Speaker::new(&mut rng);
            f(&mut sp)
        })
        .collect()
}

/// The fixed wording of a phrase: its runs of two or more words between the places.
fn segments(phrase: &str) -> Vec<String> {
    phrase
        .to_lowercase()
        .split(['@', ',', '.'])
        .map(|s| {
            // Drop the place letter left at the start of a run.
            let s = s.trim();
            let s = s
                .strip_prefix(|c: char| c == 'a' || c == 'b' || c == 'c')
                .filter(|r| r.is_empty() || r.starts_with(' '))
                .unwrap_or(s);
            s.split_whitespace().collect::<Vec<_>>().join(" ")
        })
        .filter(|s| s.split(' ').count() >= 2)
        .collect()
}

#[test]
fn no_suite_phrase_for_one_constraint_describes_another_builtin() {
    type Realiser = Box<dyn Fn(&mut Speaker<'_>) -> String>;
    // (template family, the built-in that expresses it; "" for statements such as `go`)
    let families: Vec<(&str, &str, Realiser)> = vec![
        ("near", "near", Box::new(|sp| realise::near(sp, "@a"))),
        (
            "near.passing",
            "near",
            Box::new(|sp| realise::near_passing(sp, "@a")),
        ),
        ("far", "far", Box::new(|sp| realise::far(sp, "@a"))),
        (
            "relative",
            "closer",
            Box::new(|sp| realise::relative(sp, "@a", "@b")),
        ),
        (
            "circle",
            "circle",
            Box::new(|sp| realise::circle(sp, "@a", true)),
        ),
        ("patrol", "patrol", Box::new(|sp| realise::patrol(sp, true))),
        (
            "follow_wall",
            "follow_wall",
            Box::new(|sp| realise::follow_wall(sp, false)),
        ),
        (
            "through.two",
            "through",
            Box::new(|sp| realise::through(sp, &["@a", "@b"])),
        ),
        (
            "through.many",
            "through",
            Box::new(|sp| realise::through(sp, &["@a", "@b", "@c"])),
        ),
        (
            "dest.pair",
            "",
            Box::new(|sp| realise::before_pair(sp, "@a", "@b")),
        ),
    ];
    let mut checked = 0;
    for (family, owner, f) in &families {
        let all = phrases(f);
        assert!(all.len() >= 3, "{family}: only {all:?}");
        for phrase in &all {
            for seg in segments(phrase) {
                for b in BUILTINS.iter().filter(|b| b.name != *owner) {
                    assert!(
                        !b.doc.to_lowercase().contains(&seg),
                        "the suite writes \"{phrase}\" for `{owner}` ({family}), and the prompt's line for `{}` says \"{seg}\": {}",
                        b.name,
                        b.doc
                    );
                }
                checked += 1;
            }
        }
    }
    assert!(checked > 30, "{checked} segments");
}

#[test]
fn segments_are_the_fixed_words_between_places() {
    assert_eq!(segments("pass close by @a"), vec!["pass close by"]);
    assert_eq!(
        segments("walk past @a first and then past @b"),
        vec!["walk past", "first and then past"]
    );
}
