//! Prefix (Polish) LTL, the text format the Lang2LTL family's translators write (`& F a G ! b`),
//! read into and written from m2rc's LTLf formula type, so every baseline's formula can go
//! through m2rc's automaton construction and printing.
//!
//! Operators: `!` `F` `G` `X` (unary); `&` `|` `U` `R` `W` `i`/`->` `e`/`<->` `M` (binary; `a M b`
//! is read as `b U (a & b)`); `true`/`false`. Parentheses are ignored, as the original parser does.
//! Anything else is an atom. Input size and nesting are bounded, so a hostile reply is an error,
//! never a stack overflow.

use m2rc_compiler::ltl::Formula;
use m2rc_compiler::ltl::syntax::Kind;

/// Most tokens read from one formula.
pub const MAX_TOKENS: usize = 4096;
/// Deepest operator nesting read.
pub const MAX_DEPTH: usize = 256;

/// Reads a prefix formula; the error says what is wrong and where (token position).
pub fn parse_prefix(text: &str) -> Result<Formula, String> {
    let spaced = text.replace(['(', ')'], " ");
    let tokens: Vec<&str> = spaced.split_whitespace().collect();
    if tokens.is_empty() {
        return Err("the formula is empty".into());
    }
    if tokens.len() > MAX_TOKENS {
        return Err(format!(
            "the formula has {} tokens, more than the limit of {MAX_TOKENS}",
            tokens.len()
        ));
    }
    let mut pos = 0;
    let f = read(&tokens, &mut pos, 0)?;
    if pos != tokens.len() {
        return Err(format!(
            "unexpected `{}` at token {} after a complete formula",
            tokens[pos],
            pos + 1
        ));
    }
    Ok(f)
}

fn b(f: Formula) -> Box<Formula> {
    Box::new(f)
}

fn read(t: &[&str], pos: &mut usize, depth: usize) -> Result<Formula, String> {
    if depth > MAX_DEPTH {
        return Err(format!(
            "the formula nests deeper than {MAX_DEPTH} operators"
        ));
    }
    let Some(&tok) = t.get(*pos) else {
        return Err(format!(
            "the formula ends early: an operand is missing after token {}",
            *pos
        ));
    };
    *pos += 1;
    let one = |pos: &mut usize| read(t, pos, depth + 1);
    let kind = match tok {
        "!" | "~" => Kind::Not(b(one(pos)?)),
        "F" => Kind::Eventually(b(one(pos)?)),
        "G" => Kind::Always(b(one(pos)?)),
        "X" => Kind::Next(b(one(pos)?)),
        "&" | "|" | "U" | "R" | "W" | "i" | "->" | "e" | "<->" | "M" => {
            let l = read(t, pos, depth + 1)?;
            let r = read(t, pos, depth + 1)?;
            match tok {
                "&" => Kind::And(b(l), b(r)),
                "|" => Kind::Or(b(l), b(r)),
                "U" => Kind::Until(b(l), b(r)),
                "R" => Kind::Release(b(l), b(r)),
                "W" => Kind::WeakUntil(b(l), b(r)),
                "i" | "->" => Kind::Implies(b(l), b(r)),
                "e" | "<->" => Kind::Iff(b(l), b(r)),
                _ => {
                    // a M b = b U (a & b)
                    let both = Formula::new(Kind::And(b(l), b(r.clone())));
                    Kind::Until(b(r), b(both))
                }
            }
        }
        "true" | "True" => Kind::True,
        "false" | "False" => Kind::False,
        atom => {
            if !atom
                .chars()
                .all(|c| c.is_alphanumeric() || c == '_' || c == '.' || c == '-')
            {
                return Err(format!(
                    "`{atom}` at token {} is not an operator or an atom",
                    *pos
                ));
            }
            Kind::Atom(atom.to_string())
        }
    };
    Ok(Formula::new(kind))
}

/// Writes `f` in prefix form (`W` and `R` as themselves, `->` as `i`, `<->` as `e`).
pub fn to_prefix(f: &Formula) -> String {
    let mut out = Vec::new();
    write(f, &mut out);
    out.join(" ")
}

fn write(f: &Formula, out: &mut Vec<String>) {
    let bin = |op: &str, l: &Formula, r: &Formula, out: &mut Vec<String>| {
        out.push(op.into());
        write(l, out);
        write(r, out);
    };
    match &f.kind {
        Kind::True => out.push("true".into()),
        Kind::False => out.push("false".into()),
        Kind::Atom(a) => out.push(a.clone()),
        Kind::Not(a) => {
            out.push("!".into());
            write(a, out)
        }
        Kind::Next(a) | Kind::WeakNext(a) => {
            out.push("X".into());
            write(a, out)
        }
        Kind::Eventually(a) => {
            out.push("F".into());
            write(a, out)
        }
        Kind::Always(a) => {
            out.push("G".into());
            write(a, out)
        }
        Kind::And(l, r) => bin("&", l, r, out),
        Kind::Or(l, r) => bin("|", l, r, out),
        Kind::Implies(l, r) => bin("i", l, r, out),
        Kind::Iff(l, r) => bin("e", l, r, out),
        Kind::Until(l, r) => bin("U", l, r, out),
        Kind::Release(l, r) => bin("R", l, r, out),
        Kind::WeakUntil(l, r) => bin("W", l, r, out),
    }
}

/// `f` with every atom renamed by `rename` (an atom it returns `None` for is kept).
pub fn rename_atoms(f: &Formula, rename: &dyn Fn(&str) -> Option<String>) -> Formula {
    let r = |x: &Formula| Box::new(rename_atoms(x, rename));
    let kind = match &f.kind {
        Kind::Atom(a) => Kind::Atom(rename(a).unwrap_or_else(|| a.clone())),
        Kind::True => Kind::True,
        Kind::False => Kind::False,
        Kind::Not(a) => Kind::Not(r(a)),
        Kind::Next(a) => Kind::Next(r(a)),
        Kind::WeakNext(a) => Kind::WeakNext(r(a)),
        Kind::Eventually(a) => Kind::Eventually(r(a)),
        Kind::Always(a) => Kind::Always(r(a)),
        Kind::And(a, c) => Kind::And(r(a), r(c)),
        Kind::Or(a, c) => Kind::Or(r(a), r(c)),
        Kind::Implies(a, c) => Kind::Implies(r(a), r(c)),
        Kind::Iff(a, c) => Kind::Iff(r(a), r(c)),
        Kind::Until(a, c) => Kind::Until(r(a), r(c)),
        Kind::Release(a, c) => Kind::Release(r(a), r(c)),
        Kind::WeakUntil(a, c) => Kind::WeakUntil(r(a), r(c)),
    };
    Formula::new(kind)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_and_errors() {
        for s in [
            "F a",
            "F & a F b",
            "& U ! b a F b",
            "G ! a",
            "& F a G ! b",
            "| F a F b",
        ] {
            assert_eq!(to_prefix(&parse_prefix(s).unwrap()), s);
        }
        assert_eq!(to_prefix(&parse_prefix("( F ( a ) )").unwrap()), "F a");
        assert!(parse_prefix("& a").unwrap_err().contains("ends early"));
        assert!(
            parse_prefix("F a b")
                .unwrap_err()
                .contains("unexpected `b`")
        );
        assert!(parse_prefix("").is_err());
        assert!(parse_prefix("F a{").is_err());
        let deep = "! ".repeat(10_000) + "a";
        assert!(parse_prefix(&deep).is_err());
        let deep = "! ".repeat(1_000) + "a";
        assert!(parse_prefix(&deep).unwrap_err().contains("deeper"));
    }
}
