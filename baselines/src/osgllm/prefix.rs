//! The prefix LTL of OSG-LLM's translation reply (`F & enter(room_3) F reach(object_12)`), read
//! with the shared prefix reader (`common::prefix_ltl`) into m2rc's formula type.
//!
//! As in the adaptation, the allowed AP names are first replaced by aliases `p<i>` (their index
//! in the allowed list), so the parentheses inside `enter(room_3)` never reach the tokenizer. Any
//! other atom is an error (an AP the prompt did not allow, or a stray word), and so are the
//! operators the prompt does not allow (`X`, `R`, `W`, `<->`): OSG-LLM's are `F G ! & | U ->`.

use crate::common::prefix_ltl;
use m2rc_compiler::ltl::Formula;
use m2rc_compiler::ltl::syntax::Kind;

pub use prefix_ltl::MAX_DEPTH;

/// The alias of the `i`-th allowed AP.
pub fn alias(i: usize) -> String {
    format!("p{i}")
}

fn alias_index(atom: &str, n: usize) -> Option<usize> {
    let i: usize = atom.strip_prefix('p')?.parse().ok()?;
    (i < n && atom == alias(i)).then_some(i)
}

/// Reads `text` over `aps`; atoms of the result are the aliases of the APs used.
pub fn parse_prefix(text: &str, aps: &[String]) -> Result<Formula, String> {
    let mut order: Vec<usize> = (0..aps.len()).collect();
    // Longest name first, so `reach(object_1)` never eats the head of `reach(object_12)`.
    order.sort_by(|&a, &b| aps[b].len().cmp(&aps[a].len()).then(a.cmp(&b)));
    let mut s = text.to_string();
    for i in order {
        if !aps[i].is_empty() {
            s = s.replace(&aps[i], &format!(" {} ", alias(i)));
        }
    }
    let f = prefix_ltl::parse_prefix(&s)?;
    let mut bad: Option<String> = None;
    f.walk(&mut |g| {
        if bad.is_some() {
            return;
        }
        match &g.kind {
            Kind::Atom(a) if alias_index(a, aps.len()).is_none() => {
                bad = Some(format!(
                    "`{a}` is neither an allowed atomic proposition nor one of the operators F G ! & | U ->"
                ));
            }
            Kind::Next(_) | Kind::WeakNext(_) | Kind::Release(..) | Kind::WeakUntil(..) | Kind::Iff(..) => {
                bad = Some("only the operators F G ! & | U -> are allowed".into());
            }
            _ => {}
        }
    });
    match bad {
        Some(e) => Err(e),
        None => Ok(f),
    }
}

/// The formula in prefix text, with aliases written back as AP names (for records).
pub fn to_prefix(f: &Formula, aps: &[String]) -> String {
    let named = prefix_ltl::rename_atoms(f, &|a| alias_index(a, aps.len()).map(|i| aps[i].clone()));
    prefix_ltl::to_prefix(&named)
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
        assert!(e.contains("ends early"), "{e}");
        let e = parse_prefix("F kitchen", &aps()).unwrap_err();
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
