//! Lang2LTL's language side: reading the recogniser's reply, grounding each expression to one AP
//! by embedding similarity (REG), lifting the command to letters, and reading the translator's
//! formula back onto APs.

use crate::calls::embed::cosine;
use crate::common::inventory::{Ap, Inventory};
use crate::common::prefix_ltl::{parse_prefix, rename_atoms};
use m2rc_compiler::ltl::Formula;
use serde::Serialize;

/// The placeholder letters, in the order APs take them (the original's alphabet, which leaves out
/// letters that read as operators: e, f, g, i, m, t, u, v, w, x).
pub const LETTERS: [&str; 16] = [
    "a", "b", "c", "d", "h", "j", "k", "l", "n", "o", "p", "q", "r", "s", "y", "z",
];

/// Candidates kept per expression; the first is chosen.
pub const TOP_K: usize = 3;

/// The longest expression list read from a reply.
const MAX_EXPRESSIONS: usize = 64;

/// The expressions of a recogniser reply (`{"referring_expressions": [...]}`, possibly inside a
/// code fence or after some text), de-duplicated case-insensitively, in order.
pub fn parse_rer(reply: &str) -> Result<Vec<String>, String> {
    let start = reply.find('{').ok_or("the reply holds no JSON object")?;
    let end = reply
        .rfind('}')
        .ok_or("the reply's JSON object is not closed")?;
    if end < start {
        return Err("the reply holds no JSON object".into());
    }
    let v: serde_json::Value = serde_json::from_str(&reply[start..=end])
        .map_err(|e| format!("the reply's JSON does not parse: {e}"))?;
    let list = v
        .get("referring_expressions")
        .and_then(|l| l.as_array())
        .ok_or("the reply has no `referring_expressions` list")?;
    let mut out: Vec<String> = Vec::new();
    for item in list.iter().take(MAX_EXPRESSIONS) {
        let Some(s) = item.as_str().map(str::trim).filter(|s| !s.is_empty()) else {
            continue;
        };
        if !out.iter().any(|o| o.eq_ignore_ascii_case(s)) {
            out.push(s.to_string());
        }
    }
    Ok(out)
}

/// The fallback when the recogniser names nothing: the map's categories that occur in the text,
/// in the order they occur.
pub fn categories_in_text(inventory: &Inventory, instruction: &str) -> Vec<String> {
    let lower = instruction.to_lowercase();
    let mut found: Vec<(usize, String)> = Vec::new();
    for ap in &inventory.aps {
        let words = ap.category_words();
        if let Some(pos) = lower.find(&words)
            && !found.iter().any(|(_, w)| *w == words)
        {
            found.push((pos, words));
        }
    }
    found.sort();
    found.into_iter().map(|(_, w)| w).collect()
}

/// The text each AP is embedded as: rooms `a <category>`; objects `a <category> located in a
/// <room category>`, then ` with label <name>` and ` with attributes ...` when there are any.
pub fn description(ap: &Ap) -> String {
    if ap.is_room() {
        return format!("a {}", ap.category_words());
    }
    let mut s = format!("a {}", ap.category_words());
    if let Some(rc) = &ap.room_category {
        s.push_str(&format!(" located in a {}", rc.replace('_', " ")));
    }
    if ap.label != ap.category {
        s.push_str(&format!(" with label {}", ap.label));
    }
    if !ap.attributes.is_empty() {
        s.push_str(&format!(" with attributes {}", ap.attributes.join(", ")));
    }
    s
}

/// One expression grounded to an AP.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Grounding {
    pub expression: String,
    pub ap: String,
    /// The best [`TOP_K`] APs and their cosine similarity.
    pub candidates: Vec<(String, f64)>,
}

/// REG: the AP most similar to each expression (ties broken by AP name).
pub fn ground(
    inventory: &Inventory,
    ap_vectors: &[Vec<f32>],
    expressions: &[String],
    expr_vectors: &[Vec<f32>],
) -> Vec<Grounding> {
    expressions
        .iter()
        .zip(expr_vectors)
        .map(|(e, q)| {
            let mut scored: Vec<(String, f64)> = inventory
                .aps
                .iter()
                .zip(ap_vectors)
                .map(|(ap, v)| (ap.name.clone(), cosine(q, v)))
                .collect();
            scored.sort_by(|a, b| b.1.total_cmp(&a.1).then_with(|| a.0.cmp(&b.0)));
            scored.truncate(TOP_K);
            Grounding {
                expression: e.clone(),
                ap: scored.first().map(|s| s.0.clone()).unwrap_or_default(),
                candidates: scored,
            }
        })
        .collect()
}

/// The lifted command: each expression (longest first, case-insensitive) replaced by the letter of
/// its AP. Returns the text and the letters with their APs, in the order the APs were grounded.
pub fn lift(
    instruction: &str,
    groundings: &[Grounding],
) -> Result<(String, Vec<(String, String)>), String> {
    let mut letters: Vec<(String, String)> = Vec::new();
    for g in groundings {
        if !letters.iter().any(|(_, ap)| *ap == g.ap) {
            let Some(l) = LETTERS.get(letters.len()) else {
                return Err(format!(
                    "more than {} distinct landmarks; the lifted alphabet has {} letters",
                    LETTERS.len(),
                    LETTERS.len()
                ));
            };
            letters.push((l.to_string(), g.ap.clone()));
        }
    }
    let mut order: Vec<&Grounding> = groundings.iter().collect();
    order.sort_by_key(|g| std::cmp::Reverse(g.expression.len()));
    let mut text = instruction.to_string();
    for g in order {
        let letter = &letters
            .iter()
            .find(|(_, ap)| *ap == g.ap)
            .expect("lettered")
            .0;
        text = replace_ci(&text, &g.expression, letter);
    }
    Ok((text, letters))
}

/// `text` with every case-insensitive, whole-word occurrence of `what` replaced by `with` ("the
/// bed" is not replaced inside "the bedroom").
fn replace_ci(text: &str, what: &str, with: &str) -> String {
    if what.is_empty() {
        return text.to_string();
    }
    let (lt, lw) = (text.to_lowercase(), what.to_lowercase());
    // Lower-casing may change byte lengths outside ASCII; match exactly then.
    let (hay, needle) = if lt.len() == text.len() && lw.len() == what.len() {
        (lt.as_str(), lw.as_str())
    } else {
        (text, what)
    };
    let word = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || c == '_');
    let mut out = String::new();
    let mut i = 0;
    let mut from = 0;
    while let Some(p) = hay[from..].find(needle) {
        let at = from + p;
        let end = at + needle.len();
        if word(hay[..at].chars().next_back()) || word(hay[end..].chars().next()) {
            from = at + needle.chars().next().map_or(1, char::len_utf8);
            continue;
        }
        out.push_str(&text[i..at]);
        out.push_str(with);
        i = end;
        from = end;
    }
    out.push_str(&text[i..]);
    out
}

/// The formula in a translator reply (the last non-empty line, without a code fence or an
/// `LTL:` label), read as prefix LTL over `letters`, and grounded back onto their APs.
pub fn read_formula(
    reply: &str,
    letters: &[(String, String)],
) -> Result<(Formula, Formula), String> {
    let line = reply
        .lines()
        .map(str::trim)
        .rfind(|l| !l.is_empty() && !l.starts_with("```"))
        .ok_or("the reply is empty")?;
    let mut line = line.trim_matches('`').trim();
    for label in ["ltl formula:", "ltl:", "formula:", "output:", "answer:"] {
        if line.len() >= label.len() && line[..label.len()].eq_ignore_ascii_case(label) {
            line = line[label.len()..].trim().trim_matches('`');
        }
    }
    let lifted = parse_prefix(line)?;
    for a in lifted.atoms() {
        if !letters.iter().any(|(l, _)| l == a) {
            return Err(format!(
                "`{a}` is not one of the letters {}",
                letters
                    .iter()
                    .map(|(l, _)| l.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
    }
    let grounded = rename_atoms(&lifted, &|a| {
        letters
            .iter()
            .find(|(l, _)| l == a)
            .map(|(_, ap)| ap.clone())
    });
    Ok((lifted, grounded))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rer_replies() {
        assert_eq!(
            parse_rer("```json\n{\"referring_expressions\": [\"the sofa\", \"The Sofa\", \"the bed\"]}\n```").unwrap(),
            ["the sofa", "the bed"]
        );
        assert!(parse_rer("no json here").is_err());
        assert!(parse_rer("{\"expressions\": []}").is_err());
        assert!(parse_rer("{\"referring_expressions\": [").is_err());
    }

    #[test]
    fn lifting_and_reading_back() {
        let g = |e: &str, ap: &str| Grounding {
            expression: e.into(),
            ap: ap.into(),
            candidates: vec![],
        };
        let (text, letters) = lift(
            "Go to the sofa in the kitchen, then the Sofa, avoid the kitchen, not the kitchens",
            &[
                g("the sofa in the kitchen", "object_3"),
                g("the kitchen", "room_1"),
            ],
        )
        .unwrap();
        assert_eq!(text, "Go to a, then the Sofa, avoid b, not the kitchens");
        let (_, grounded) = read_formula("LTL: & F a G ! b", &letters).unwrap();
        assert_eq!(
            crate::common::prefix_ltl::to_prefix(&grounded),
            "& F object_3 G ! room_1"
        );
        assert!(
            read_formula("F c", &letters)
                .unwrap_err()
                .contains("not one of the letters")
        );
        let many: Vec<Grounding> = (0..17)
            .map(|i| g(&format!("x{i}"), &format!("object_{i}")))
            .collect();
        assert!(lift("x", &many).is_err());
    }
}
