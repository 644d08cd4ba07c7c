//! The prefix LTL of OSG-LLM's translation reply (`F & enter(room_3) F reach(object_12)`), read
//! into m2rc's formula type.
//!
//! As in the adaptation, the allowed AP names are first replaced by aliases `p<i>` (their index
//! in the allowed list), so the parentheses inside `enter(room_3)` never reach the tokenizer. The
//! operators are the ones the prompt allows, `F G ! & | U ->`, plus `true` and `false`. Prefix
//! notation needs no grouping, so parentheses and commas the model adds are read as spaces. Depth
//! and length are bounded: a reply cannot exhaust the stack.

use m2rc_compiler::ltl::Formula;
use m2rc_compiler::ltl::syntax::Kind;

/// Most tokens a formula may have.
pub const MAX_TOKENS: usize = 4096;
/// Deepest nesting a formula may have.
pub const MAX_DEPTH: usize = 200;

/// The alias of the `i`-th allowed AP.
pub fn alias(i: usize) -> String {
    format!("p{i}")
}

/// Reads `text` over `aps`; atoms of the result are the aliases of the APs used.
pub fn parse_prefix(text: &str, aps: &[String]) -> Result<Formula, String> {
    let mut order: Vec<usize> = (0..aps.len()).collect();
    // Longest name first, so `reach(object_1)` never eats the head of `reach(object_12)`.
    order.sort_by(|&a, &b| aps[b].len().cmp(&aps[a].len()).then(a.cmp(&b)));
    let mut s = text.to_string();
    for i in order {
        if !aps[i].is_empty() {
            s = s.replace(&aps[i], &format!(" \u{1}{i} "));
        }
    }
    let tokens: Vec<String> = s
        .split(|c: char| c.is_whitespace() || c == '(' || c == ')' || c == ',')
        .filter(|t| !t.is_empty())
        .map(|t| match t.strip_prefix('\u{1}') {
            Some(i) => alias(i.parse().unwrap_or(usize::MAX)),
            None => t.to_string(),
        })
        .collect();
    if tokens.is_empty() {
        return Err("the formula is empty".into());
    }
    if tokens.len() > MAX_TOKENS {
        return Err(format!(
            "the formula has {} tokens, more than {MAX_TOKENS}",
            tokens.len()
        ));
    }
    let mut pos = 0;
    let f = term(&tokens, &mut pos, 0, aps.len())?;
    if pos != tokens.len() {
        return Err(format!(
            "unexpected `{}` after a complete formula (prefix notation: an operator, then its operands)",
            tokens[pos]
        ));
    }
    Ok(f)
}

fn term(t: &[String], pos: &mut usize, depth: usize, n_aps: usize) -> Result<Formula, String> {
    if depth > MAX_DEPTH {
        return Err(format!("the formula nests deeper than {MAX_DEPTH}"));
    }
    let Some(tok) = t.get(*pos) else {
        return Err("the formula ends where an operand is missing".into());
    };
    *pos += 1;
    let mut sub = || term(t, pos, depth + 1, n_aps).map(Box::new);
    let kind = match tok.as_str() {
        "F" => Kind::Eventually(sub()?),
        "G" => Kind::Always(sub()?),
        "!" => Kind::Not(sub()?),
        "&" => {
            let a = sub()?;
            Kind::And(a, sub()?)
        }
        "|" => {
            let a = sub()?;
            Kind::Or(a, sub()?)
        }
        "U" => {
            let a = sub()?;
            Kind::Until(a, sub()?)
        }
        "->" => {
            let a = sub()?;
            Kind::Implies(a, sub()?)
        }
        "true" => Kind::True,
        "false" => Kind::False,
        other => match other
            .strip_prefix('p')
            .and_then(|i| i.parse::<usize>().ok())
        {
            Some(i) if i < n_aps && other == alias(i) => Kind::Atom(other.to_string()),
            _ => {
                return Err(format!(
                    "`{other}` is neither an allowed atomic proposition nor one of the operators F G ! & | U ->"
                ));
            }
        },
    };
    Ok(Formula::new(kind))
}

/// The formula in prefix text, with aliases written back as AP names (for records).
pub fn to_prefix(f: &Formula, aps: &[String]) -> String {
    let mut out = Vec::new();
    write(f, aps, &mut out);
    out.join(" ")
}

fn write(f: &Formula, aps: &[String], out: &mut Vec<String>) {
    let op = |s: &str, parts: &[&Formula], out: &mut Vec<String>| {
        out.push(s.to_string());
        for p in parts {
            write(p, aps, out);
        }
    };
    match &f.kind {
        Kind::True => out.push("true".into()),
        Kind::False => out.push("false".into()),
        Kind::Atom(a) => out.push(
            a.strip_prefix('p')
                .and_then(|i| i.parse::<usize>().ok())
                .and_then(|i| aps.get(i))
                .cloned()
                .unwrap_or_else(|| a.clone()),
        ),
        Kind::Not(a) => op("!", &[a], out),
        Kind::Eventually(a) => op("F", &[a], out),
        Kind::Always(a) => op("G", &[a], out),
        Kind::Next(a) => op("X", &[a], out),
        Kind::WeakNext(a) => op("WX", &[a], out),
        Kind::And(a, b) => op("&", &[a, b], out),
        Kind::Or(a, b) => op("|", &[a, b], out),
        Kind::Until(a, b) => op("U", &[a, b], out),
        Kind::Implies(a, b) => op("->", &[a, b], out),
        Kind::Iff(a, b) => op("<->", &[a, b], out),
        Kind::Release(a, b) => op("R", &[a, b], out),
        Kind::WeakUntil(a, b) => op("W", &[a, b], out),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn aps() -> Vec<String> {
        ["enter(room_3)", "reach(object_1)", "reach(object_12)"]
            .map(String::from)
            .to_vec()
    }

    #[test]
    fn names_with_parentheses_and_shared_heads_are_read_as_their_own_atoms() {
        let f = parse_prefix(
            "& F & enter(room_3) F reach(object_12) G ! reach(object_1)",
            &aps(),
        )
        .unwrap();
        assert_eq!(
            to_prefix(&f, &aps()),
            "& F & enter(room_3) F reach(object_12) G ! reach(object_1)"
        );
        let mut atoms = f.atoms();
        atoms.sort();
        assert_eq!(atoms, ["p0", "p1", "p2"]);
    }

    #[test]
    fn malformed_and_foreign_formulas_are_refused_with_the_reason() {
        let e = parse_prefix("F & enter(room_3)", &aps()).unwrap_err();
        assert!(e.contains("operand is missing"), "{e}");
        let e = parse_prefix("F reach(object_99)", &aps()).unwrap_err();
        assert!(e.contains("neither an allowed"), "{e}");
        let e = parse_prefix("F enter(room_3) F reach(object_1)", &aps()).unwrap_err();
        assert!(e.contains("after a complete formula"), "{e}");
        assert!(parse_prefix("X enter(room_3)", &aps()).is_err());
        assert!(parse_prefix("p0", &aps()).is_ok(), "an alias is an atom");
        assert!(parse_prefix("p7", &aps()).is_err());
        let deep = "! ".repeat(MAX_DEPTH + 5) + "enter(room_3)";
        assert!(parse_prefix(&deep, &aps()).unwrap_err().contains("deeper"));
    }
}
