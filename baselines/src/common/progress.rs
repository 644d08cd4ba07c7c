//! LTLf formula progression by one letter (the set of APs true at a position), with the
//! simplifications that keep a residual small (`true`/`false` absorbed, equal operands merged).
//! Lang2LTL's AP-MDP and LIMP's transition regions both advance a residual formula this way;
//! each method decides which cells' labels it progresses by.
//!
//! `F p -> p' | F p`, `G p -> p' & G p`, `X p -> p`, `p U q -> q' | (p' & p U q)`,
//! `p R q -> q' & (p' | p R q)`, `p W q -> q' | (p' & p W q)`.

use m2rc_compiler::ltl::Formula;
use m2rc_compiler::ltl::syntax::Kind;

fn f(kind: Kind) -> Formula {
    Formula::new(kind)
}

pub fn tt() -> Formula {
    f(Kind::True)
}

pub fn ff() -> Formula {
    f(Kind::False)
}

pub fn and(a: Formula, b: Formula) -> Formula {
    junction(a, b, true)
}

pub fn or(a: Formula, b: Formula) -> Formula {
    junction(a, b, false)
}

/// `a & b` (`conj`) or `a | b`, normalised: nested operands of the same junction flattened,
/// duplicates dropped, `true`/`false` absorbed, operands in a canonical order. So a residual that
/// means the same after two progressions is the same formula, and the set of residuals a search
/// meets stays finite.
fn junction(a: Formula, b: Formula, conj: bool) -> Formula {
    let mut parts: Vec<Formula> = Vec::new();
    fn collect(x: Formula, conj: bool, out: &mut Vec<Formula>) {
        match x.kind {
            Kind::And(l, r) if conj => {
                collect(*l, conj, out);
                collect(*r, conj, out);
            }
            Kind::Or(l, r) if !conj => {
                collect(*l, conj, out);
                collect(*r, conj, out);
            }
            k => out.push(Formula::new(k)),
        }
    }
    collect(a, conj, &mut parts);
    collect(b, conj, &mut parts);
    let (unit, zero) = if conj {
        (Kind::True, Kind::False)
    } else {
        (Kind::False, Kind::True)
    };
    if parts.iter().any(|p| p.kind == zero) {
        return f(zero);
    }
    let mut keyed: Vec<(String, Formula)> = parts
        .into_iter()
        .filter(|p| p.kind != unit)
        .map(|p| (crate::common::prefix_ltl::to_prefix(&p), p))
        .collect();
    keyed.sort_by(|x, y| x.0.cmp(&y.0));
    keyed.dedup_by(|x, y| x.0 == y.0);
    let mut it = keyed.into_iter().rev().map(|(_, p)| p);
    let Some(mut acc) = it.next() else {
        return f(unit);
    };
    for p in it {
        acc = f(if conj {
            Kind::And(Box::new(p), Box::new(acc))
        } else {
            Kind::Or(Box::new(p), Box::new(acc))
        });
    }
    acc
}

pub fn not(a: Formula) -> Formula {
    match a.kind {
        Kind::True => ff(),
        Kind::False => tt(),
        Kind::Not(inner) => *inner,
        k => f(Kind::Not(Box::new(f(k)))),
    }
}

/// The residual of `phi` after one position where exactly the atoms `holds` says are true.
pub fn progress(phi: &Formula, holds: &dyn Fn(&str) -> bool) -> Formula {
    let p = |x: &Formula| progress(x, holds);
    match &phi.kind {
        Kind::True => tt(),
        Kind::False => ff(),
        Kind::Atom(a) => {
            if holds(a) {
                tt()
            } else {
                ff()
            }
        }
        Kind::Not(a) => not(p(a)),
        Kind::And(a, b) => and(p(a), p(b)),
        Kind::Or(a, b) => or(p(a), p(b)),
        Kind::Implies(a, b) => or(not(p(a)), p(b)),
        Kind::Iff(a, b) => {
            let (x, y) = (p(a), p(b));
            or(and(x.clone(), y.clone()), and(not(x), not(y)))
        }
        Kind::Next(a) | Kind::WeakNext(a) => (**a).clone(),
        Kind::Eventually(a) => or(p(a), phi.clone()),
        Kind::Always(a) => and(p(a), phi.clone()),
        Kind::Until(a, b) | Kind::WeakUntil(a, b) => or(p(b), and(p(a), phi.clone())),
        Kind::Release(a, b) => and(p(b), or(p(a), phi.clone())),
    }
}

/// Whether two formulas are the same, spans aside (a parsed formula carries its text's spans,
/// a progressed one none).
pub fn same(a: &Formula, b: &Formula) -> bool {
    crate::common::prefix_ltl::to_prefix(a) == crate::common::prefix_ltl::to_prefix(b)
}

/// Nodes in `phi` (a residual's size, checked against a method's budget).
pub fn size(phi: &Formula) -> usize {
    let mut n = 0;
    phi.walk(&mut |_| n += 1);
    n
}

/// The atoms of `phi` that occur under `F` without a negation on the way (the "eventually" APs
/// whose labels can advance it), in first-occurrence order.
pub fn eventual_atoms(phi: &Formula) -> Vec<String> {
    fn go(x: &Formula, under_f: bool, neg: bool, out: &mut Vec<String>) {
        match &x.kind {
            Kind::Atom(a) if under_f && !neg && !out.contains(a) => out.push(a.clone()),
            Kind::Not(a) => go(a, under_f, !neg, out),
            Kind::Eventually(a) => go(a, true, neg, out),
            Kind::Until(a, b) | Kind::WeakUntil(a, b) => {
                go(a, under_f, neg, out);
                go(b, true, neg, out)
            }
            Kind::And(a, b) | Kind::Or(a, b) | Kind::Release(a, b) => {
                go(a, under_f, neg, out);
                go(b, under_f, neg, out)
            }
            Kind::Implies(a, b) => {
                go(a, under_f, !neg, out);
                go(b, under_f, neg, out)
            }
            Kind::Iff(a, b) => {
                go(a, under_f, neg, out);
                go(b, under_f, neg, out)
            }
            Kind::Next(a) | Kind::WeakNext(a) => go(a, true, neg, out),
            Kind::Always(a) => go(a, under_f, neg, out),
            _ => {}
        }
    }
    let mut out = Vec::new();
    go(phi, false, false, &mut out);
    out
}

/// The atoms under a top-level `G !a` conjunct (global avoids), in order.
pub fn global_avoids(phi: &Formula) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![phi];
    while let Some(x) = stack.pop() {
        match &x.kind {
            Kind::And(a, b) => {
                stack.push(b);
                stack.push(a);
            }
            Kind::Always(a) => {
                if let Kind::Not(inner) = &a.kind
                    && let Kind::Atom(name) = &inner.kind
                    && !out.contains(name)
                {
                    out.push(name.clone());
                }
            }
            _ => {}
        }
    }
    out
}

/// Accepting in the adaptation's sense: the residual is `true`, a `G`-formula (nothing left to
/// reach), or a conjunction / disjunction of accepting parts.
pub fn accepting(phi: &Formula) -> bool {
    match &phi.kind {
        Kind::True | Kind::Always(_) => true,
        Kind::And(a, b) => accepting(a) && accepting(b),
        Kind::Or(a, b) => accepting(a) || accepting(b),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::common::prefix_ltl::{parse_prefix, to_prefix};

    fn step(s: &str, on: &[&str]) -> String {
        to_prefix(&progress(&parse_prefix(s).unwrap(), &|a| on.contains(&a)))
    }

    #[test]
    fn progression_rules() {
        assert_eq!(step("F & a F b", &[]), "F & a F b");
        assert_eq!(step("F & a F b", &["a"]), "| F & a F b F b");
        // Progressing again by the same label changes nothing: the residual is normalised.
        let once = progress(&parse_prefix("F & a F b").unwrap(), &|x| x == "a");
        assert_eq!(progress(&once, &|x| x == "a"), once);
        assert_eq!(step("F & a F b", &["a", "b"]), "true");
        assert_eq!(step("& F a G ! b", &["b"]), "false");
        assert_eq!(step("& F a G ! b", &["a"]), "G ! b");
        assert_eq!(step("U ! b a", &["a"]), "true");
        assert_eq!(step("U ! b a", &["b"]), "false");
        assert!(accepting(&parse_prefix("G ! b").unwrap()));
        assert!(!accepting(&parse_prefix("& F a G ! b").unwrap()));
        let f = parse_prefix("& F & a F b G ! c").unwrap();
        assert_eq!(eventual_atoms(&f), ["a", "b"]);
        assert_eq!(global_avoids(&f), ["c"]);
    }
}
