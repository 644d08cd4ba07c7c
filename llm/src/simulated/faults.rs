//! Faults a language model makes when writing `.m2r`, injected into a correct program as text
//! edits, and the repair a model that reads only the diagnostics would make.

use m2rc_stdlib::vocab::SYNONYMS;
use rand::Rng;
use rand::seq::IndexedRandom;
use serde_json::Value;

/// Most faults in one answer.
const MAX_FAULTS: usize = 3;

type Fault = fn(&str, &mut dyn rand::RngCore) -> Option<String>;

/// Every fault kind with its record name.
pub const FAULTS: &[(&str, Fault)] = &[
    ("misspelled_category", misspell),
    ("unknown_category", unknown_category),
    ("synonym", synonym),
    ("wrong_argument_type", drop_unit),
    ("wrong_argument_count", extra_argument),
    ("set_as_object", drop_only),
    ("missing_scope", drop_within),
    ("dropped_constraint", drop_constraint),
    ("syntax_slip", drop_paren),
];

/// Injects faults: each further fault with probability `rate`, up to [`MAX_FAULTS`], each kind at
/// most once. Returns the program and the fault names, in order.
pub fn inject(gold: &str, rate: f64, rng: &mut dyn rand::RngCore) -> (String, Vec<&'static str>) {
    let mut program = gold.to_string();
    let mut applied = Vec::new();
    let mut kinds: Vec<usize> = (0..FAULTS.len()).collect();
    while applied.len() < MAX_FAULTS && rng.random::<f64>() < rate {
        // Try kinds in random order until one applies to this program.
        let mut done = false;
        while !kinds.is_empty() {
            let i = rng.random_range(0..kinds.len());
            let k = kinds.swap_remove(i);
            let (name, f) = FAULTS[k];
            if let Some(p) = f(&program, rng) {
                program = p;
                applied.push(name);
                done = true;
                break;
            }
        }
        if !done {
            break;
        }
    }
    (program, applied)
}

/// Byte ranges of the category words inside `objects(...)` / `rooms(...)`.
fn category_spans(src: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for head in ["objects(", "rooms("] {
        let mut from = 0;
        while let Some(i) = src[from..].find(head) {
            let start = from + i + head.len();
            let mut pos = start;
            loop {
                let rest = &src[pos..];
                let word_len = rest
                    .find(|c: char| !(c.is_ascii_lowercase() || c == '_'))
                    .unwrap_or(rest.len());
                if word_len > 0 {
                    out.push((pos, pos + word_len));
                }
                let after = pos + word_len;
                let trimmed = src[after..].trim_start();
                if let Some(t) = trimmed.strip_prefix('|') {
                    pos = src.len() - t.trim_start().len();
                } else {
                    break;
                }
            }
            from = start;
        }
    }
    out.sort_unstable();
    out
}

fn pick<T: Copy>(v: &[T], rng: &mut dyn rand::RngCore) -> Option<T> {
    v.choose(&mut RngRef(rng)).copied()
}

/// `&mut dyn RngCore` as a sized `Rng` for the slice helpers.
struct RngRef<'a>(&'a mut dyn rand::RngCore);

impl rand::RngCore for RngRef<'_> {
    fn next_u32(&mut self) -> u32 {
        self.0.next_u32()
    }
    fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
    }
    fn fill_bytes(&mut self, dst: &mut [u8]) {
        self.0.fill_bytes(dst)
    }
}

fn replace(src: &str, (a, b): (usize, usize), with: &str) -> String {
    format!("{}{}{}", &src[..a], with, &src[b..])
}

fn misspell(src: &str, rng: &mut dyn rand::RngCore) -> Option<String> {
    let spans: Vec<_> = category_spans(src)
        .into_iter()
        .filter(|(a, b)| b - a >= 4)
        .collect();
    let (a, b) = pick(&spans, rng)?;
    let word: Vec<char> = src[a..b].chars().collect();
    let i = rng.random_range(1..word.len() - 1);
    let mut w = word.clone();
    w.swap(i, i + 1);
    (w != word).then(|| replace(src, (a, b), &w.iter().collect::<String>()))
}

fn unknown_category(src: &str, rng: &mut dyn rand::RngCore) -> Option<String> {
    let spans: Vec<_> = category_spans(src)
        .into_iter()
        .filter(|&(a, _)| src[..a].ends_with("objects("))
        .collect();
    let s = pick(&spans, rng)?;
    let word = pick(&["furniture", "item", "appliance", "decoration"], rng)?;
    Some(replace(src, s, word))
}

fn synonym(src: &str, rng: &mut dyn rand::RngCore) -> Option<String> {
    let options: Vec<((usize, usize), &str)> = category_spans(src)
        .into_iter()
        .filter_map(|s| {
            let cat = &src[s.0..s.1];
            SYNONYMS
                .iter()
                .find(|(_, cands)| cands.len() == 1 && cands[0] == cat)
                .map(|(w, _)| (s, *w))
        })
        .collect();
    let (s, w) = pick(&options, rng)?;
    Some(replace(src, s, w))
}

/// Occurrences of `pat` as byte offsets.
fn find_all(src: &str, pat: &str) -> Vec<usize> {
    src.match_indices(pat).map(|(i, _)| i).collect()
}

fn drop_unit(src: &str, rng: &mut dyn rand::RngCore) -> Option<String> {
    let bytes = src.as_bytes();
    let mut spans = Vec::new();
    for (i, _) in src.match_indices('m') {
        let after_ok = bytes
            .get(i + 1)
            .is_none_or(|c| !c.is_ascii_alphanumeric() && *c != b'_');
        if i > 0 && bytes[i - 1].is_ascii_digit() && after_ok {
            let unit_start = if i >= 2 && bytes[i - 1] == b'c' {
                i - 1
            } else {
                i
            };
            spans.push((unit_start, i + 1));
        }
    }
    let s = pick(&spans, rng)?;
    Some(replace(src, s, ""))
}

fn extra_argument(src: &str, rng: &mut dyn rand::RngCore) -> Option<String> {
    let at = pick(&find_all(src, ".only()"), rng)?;
    Some(replace(src, (at, at + 7), ".only(1)"))
}

fn drop_only(src: &str, rng: &mut dyn rand::RngCore) -> Option<String> {
    let at = pick(&find_all(src, ".only()"), rng)?;
    Some(replace(src, (at, at + 7), ""))
}

/// Line byte ranges (without the newline) whose trimmed text satisfies `keep`.
fn lines_where(src: &str, keep: impl Fn(&str) -> bool) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut pos = 0;
    for line in src.split_inclusive('\n') {
        let body = line.trim_end_matches('\n');
        if keep(body.trim()) {
            out.push((pos, pos + body.len()));
        }
        pos += line.len();
    }
    out
}

fn drop_within(src: &str, rng: &mut dyn rand::RngCore) -> Option<String> {
    let lines = lines_where(src, |l| {
        (l.starts_with("prefer ") || l.starts_with("avoid ")) && l.contains(" within ")
    });
    let (a, b) = pick(&lines, rng)?;
    let w = src[a..b].find(" within ")? + a;
    Some(replace(src, (w, b), ""))
}

fn drop_constraint(src: &str, rng: &mut dyn rand::RngCore) -> Option<String> {
    let lines = lines_where(src, |l| l.starts_with("prefer ") || l.starts_with("avoid "));
    let (a, b) = pick(&lines, rng)?;
    let end = if src[b..].starts_with('\n') { b + 1 } else { b };
    Some(replace(src, (a, end), ""))
}

fn drop_paren(src: &str, rng: &mut dyn rand::RngCore) -> Option<String> {
    let lines = lines_where(src, |l| l.starts_with("let ") && l.ends_with(')'));
    let (_, b) = pick(&lines, rng)?;
    Some(replace(src, (b - 1, b), ""))
}

/// The edits a diagnostics-only model makes: each error's first suggestion, or the text of a
/// `help: write `X`` over the error's span; overlapping edits after the first are left out.
pub fn apply_diagnostics(program: &str, diagnostics: &[Value]) -> String {
    let span = |v: &Value| -> Option<(usize, usize)> {
        Some((
            v.get("start")?.as_u64()? as usize,
            v.get("end")?.as_u64()? as usize,
        ))
    };
    let mut edits: Vec<((usize, usize), String)> = Vec::new();
    for d in diagnostics {
        if d.get("severity").and_then(Value::as_str) != Some("error") {
            continue;
        }
        let suggestion = d
            .get("suggestions")
            .and_then(Value::as_array)
            .and_then(|s| s.first())
            .and_then(|s| {
                Some((
                    span(s.get("span")?)?,
                    s.get("replacement")?.as_str()?.to_string(),
                ))
            });
        let from_help = || {
            let help = d.get("help")?.as_str()?;
            let rest = &help[help.find("write `")? + 7..];
            let text = &rest[..rest.find('`')?];
            Some((span(d.get("span")?)?, text.to_string()))
        };
        if let Some(e) = suggestion.or_else(from_help) {
            edits.push(e);
        }
    }
    edits.sort_by_key(|((a, b), _)| (*a, *b));
    let mut out = String::with_capacity(program.len());
    let mut pos = 0;
    for ((a, b), text) in edits {
        if a < pos
            || b > program.len()
            || a > b
            || !program.is_char_boundary(a)
            || !program.is_char_boundary(b)
        {
            continue;
        }
        out.push_str(&program[pos..a]);
        out.push_str(&text);
        pos = b;
    }
    out.push_str(&program[pos..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    const GOLD: &str = "let bathroom = rooms(bathroom).smallest()\nlet can = objects(garbage_can).in(bathroom).only()\n\nroute {\n  go can {\n    prefer near(objects(dresser).only()) within bathroom\n    avoid area_near(can, within: 1.5m)\n  }\n}\n";

    #[test]
    fn every_fault_changes_the_program() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        for (name, f) in FAULTS {
            let out = f(GOLD, &mut rng).unwrap_or_else(|| panic!("{name} did not apply"));
            assert_ne!(out, GOLD, "{name}");
        }
        assert_eq!(category_spans("objects(a_b | cc)").len(), 2);
    }

    #[test]
    fn injection_is_seeded_and_rate_zero_is_the_gold_program() {
        let run = |seed| inject(GOLD, 0.9, &mut rand_chacha::ChaCha8Rng::seed_from_u64(seed));
        assert_eq!(run(3), run(3));
        assert!(!run(3).1.is_empty());
        let (p, f) = inject(GOLD, 0.0, &mut rand_chacha::ChaCha8Rng::seed_from_u64(3));
        assert_eq!(p, GOLD);
        assert!(f.is_empty());
    }

    #[test]
    fn repairs_follow_suggestions_only() {
        let diags = serde_json::json!([{
            "severity": "error", "span": {"start": 4, "end": 9},
            "suggestions": [{"span": {"start": 4, "end": 9}, "replacement": "chair"}]
        }, {"severity": "error", "span": {"start": 0, "end": 3}, "help": "write `let`"}]);
        let out = apply_diagnostics("lex chiar", diags.as_array().unwrap());
        assert_eq!(out, "let chair");
    }
}
