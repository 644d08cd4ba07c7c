//! Did-you-mean: the closest known name to a misspelt one.
//!
//! An exact case-insensitive match wins outright (`Chair` -> `chair`); otherwise the candidate with
//! the highest normalised Damerau-Levenshtein similarity at or above [`THRESHOLD`], ties broken by
//! the candidate's order in the input so results are deterministic. Underscores are ignored when
//! comparing, so `diningtable` finds `dining_table`.

/// Minimum similarity (0..1) for a suggestion.
pub const THRESHOLD: f64 = 0.6;

fn squash(s: &str) -> String {
    s.chars()
        .filter(|c| *c != '_')
        .flat_map(char::to_lowercase)
        .collect()
}

/// Similarity in 0..1 between a written word and a candidate.
pub fn similarity(word: &str, candidate: &str) -> f64 {
    let (a, b) = (squash(word), squash(candidate));
    if a == b {
        return 1.0;
    }
    let sim = strsim::normalized_damerau_levenshtein(&a, &b);
    // A written prefix of a long name ("vacuum" for "vacuum_cleaner") is a strong hint too.
    if a.len() >= 4 && b.starts_with(&a) {
        sim.max(0.75)
    } else {
        sim
    }
}

/// The best candidate for `word`, if any is close enough.
pub fn best<'a, I>(word: &str, candidates: I) -> Option<&'a str>
where
    I: IntoIterator<Item = &'a str>,
{
    let mut best: Option<(&'a str, f64)> = None;
    for c in candidates {
        if c == word {
            continue;
        }
        if c.eq_ignore_ascii_case(word) {
            return Some(c);
        }
        let s = similarity(word, c);
        if s >= THRESHOLD && best.is_none_or(|(_, b)| s > b) {
            best = Some((c, s));
        }
    }
    best.map(|(c, _)| c)
}

/// Up to `n` candidates, most similar first, for listing in a note.
pub fn ranked<'a, I>(word: &str, candidates: I, n: usize) -> Vec<&'a str>
where
    I: IntoIterator<Item = &'a str>,
{
    let mut v: Vec<(&'a str, f64)> = candidates
        .into_iter()
        .map(|c| (c, similarity(word, c)))
        .collect();
    v.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(b.0)));
    v.into_iter().take(n).map(|(c, _)| c).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_close_names_and_rejects_far_ones() {
        let cands = ["chair", "arm_chair", "sofa", "dining_table"];
        assert_eq!(best("chiar", cands), Some("chair"));
        assert_eq!(best("CHAIR", cands), Some("chair"));
        assert_eq!(best("diningtable", cands), Some("dining_table"));
        assert_eq!(best("xylophone", cands), None);
        assert_eq!(ranked("sofaa", cands, 1), vec!["sofa"]);
    }
}
