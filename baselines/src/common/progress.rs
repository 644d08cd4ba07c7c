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
    match (&a.kind, &b.kind) {
        (Kind::False, _) | (_, Kind::False) => ff(),
        (Kind::True, _) => b,
        (_, Kind::True) => a,
        _ if a == b => a,
        _ => f(Kind::And(Box::new(a), Box::new(b))),
    }
}

pub fn or(a: Formula, b: Formula) -> Formula {
    match (&a.kind, &b.kind) {
        (Kind::True, _) | (_, Kind::True) => tt(),
        (Kind::False, _) => b,
        (_, Kind::False) => a,
        _ if a == b => a,
        _ => f(Kind::Or(Box::new(a), Box::new(b))),
    }
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
        assert_eq!(step("F & a F b", &["a"]), "| F b F & a F b");
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
