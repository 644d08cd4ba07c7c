//! Words a writer (or an LLM) reaches for that mean a built-in without being spelt like it, for
//! the did-you-mean of unknown functions: `keep_away(x)` is `far(x)` whatever the edit distance.
//! Kept next to the built-in table so that a renamed built-in fails the test below.

/// `(word written, what it means, how to write it)`. The meaning is a built-in's name, or a
/// constraint keyword (`avoid`, `pass`) when the idea is a statement rather than a call.
pub static SYNONYMS: &[(&str, &str)] = &[
    ("keep_away", "far"),
    ("keep_away_from", "far"),
    ("stay_away", "far"),
    ("stay_away_from", "far"),
    ("away_from", "far"),
    ("distant", "far"),
    ("avoid_near", "far"),
    ("stay_close", "near"),
    ("stay_close_to", "near"),
    ("keep_close", "near"),
    ("keep_close_to", "near"),
    ("close_to", "near"),
    ("hug", "near"),
    ("stay_near", "near"),
    ("prefer_near", "near"),
    ("closer_to", "closer"),
    ("avoid_area", "avoid"),
    ("avoid_room", "avoid"),
    ("never_enter", "avoid"),
    ("do_not_enter", "avoid"),
    ("go_through", "pass"),
    ("pass_through", "pass"),
    ("via", "pass"),
    ("around", "circle"),
    ("go_around", "circle"),
    ("circle_around", "circle"),
    ("loop_around", "circle"),
    ("along_walls", "follow_wall"),
    ("wall_follow", "follow_wall"),
    ("follow_walls", "follow_wall"),
    ("hug_wall", "follow_wall"),
    ("weave", "through"),
    ("weave_through", "through"),
    ("pass_by", "through"),
    ("middle", "center"),
    ("centre", "center"),
    ("midpoint", "center"),
    ("closest", "nearest"),
    ("furthest", "farthest"),
    ("biggest", "largest"),
    ("smallest_room", "smallest"),
    ("entered_first", "first_entered"),
    ("previous_room", "room_before_entering"),
    ("exit_door", "doorway_leaving"),
    ("entry_door", "doorway_entering"),
    ("clearance_from_obstacles", "clearance"),
];

/// What `word` means, if it is a known synonym: a built-in name or a constraint keyword.
pub fn meaning(word: &str) -> Option<&'static str> {
    let w = word.to_ascii_lowercase();
    SYNONYMS.iter().find(|(s, _)| *s == w).map(|(_, m)| *m)
}

/// Constraint keywords a synonym may stand for.
pub const KEYWORD_MEANINGS: &[&str] = &["avoid", "pass"];

#[cfg(test)]
mod tests {
    #[test]
    fn every_synonym_names_a_builtin_or_a_keyword() {
        for (word, m) in super::SYNONYMS {
            assert!(
                super::KEYWORD_MEANINGS.contains(m)
                    || super::super::BUILTINS.iter().any(|b| b.name == *m),
                "synonym `{word}` means `{m}`, which is no built-in"
            );
            assert!(
                !super::super::BUILTINS.iter().any(|b| b.name == *word),
                "`{word}` is a built-in itself"
            );
        }
        assert_eq!(super::meaning("Keep_Away"), Some("far"));
        assert_eq!(super::meaning("chair"), None);
    }
}
