//! Grounding a `route ltl "..."` program: the form is replaced by one `go <atom>` stage per atom
//! (first-occurrence order, each at the span of the atom's first occurrence, so the checker's
//! resolutions still apply) and its preferences are removed. Grounding that program gives each
//! atom's place as a stage target (with the planner's goal-mask reading: an object is reached in
//! the band around it) and each `avoid` as a route-wide constraint; the planner then ignores the
//! stage order and follows the formula.

use super::scope::formula_text;
use super::syntax::{Formula, Kind, parse};
use m2rc_grammar::ast::{
    ConstraintKind, Expr, ExprKind, Ident, Item, LtlForm, Program, RouteItem, Span, Stage,
};

/// An LTL program ready for grounding.
#[derive(Clone, Debug)]
pub struct Desugared {
    pub program: Program,
    /// The formula, spans in source coordinates.
    pub formula: Formula,
    /// Atom names, in the order of the generated stages.
    pub atoms: Vec<String>,
    /// The whole formula literal.
    pub span: Span,
    /// One line per preference removed.
    pub dropped: Vec<String>,
}

/// The program's LTL form, if it is an LTL program.
pub fn ltl_form(program: &Program) -> Option<&LtlForm> {
    program.items.iter().find_map(|i| match i {
        Item::Route(r) => r.items.iter().find_map(|x| match x {
            RouteItem::Ltl(f) => Some(f),
            _ => None,
        }),
        _ => None,
    })
}

/// `None` when the program has no LTL form or its formula does not parse (the checker has
/// reported why).
pub fn desugar(program: &Program, src: &str) -> Option<Desugared> {
    let form = ltl_form(program)?;
    let (text, offset) = formula_text(src, form);
    let mut formula = parse(text).ok()?;
    formula.offset(offset);
    let mut atoms: Vec<(String, Span)> = Vec::new();
    formula.walk(&mut |g| {
        if let Kind::Atom(a) = &g.kind
            && !atoms.iter().any(|(n, _)| n == a)
        {
            atoms.push((a.clone(), g.span));
        }
    });
    let mut out = program.clone();
    let mut dropped = Vec::new();
    for item in &mut out.items {
        if let Item::Route(r) = item {
            let mut items = Vec::new();
            for it in std::mem::take(&mut r.items) {
                match it {
                    RouteItem::Ltl(_) => items.extend(atoms.iter().map(|(name, span)| {
                        RouteItem::Stage(Stage {
                            target: Expr {
                                kind: ExprKind::Name(Ident {
                                    name: name.clone(),
                                    span: *span,
                                }),
                                span: *span,
                            },
                            name: None,
                            body: Vec::new(),
                            span: *span,
                        })
                    })),
                    RouteItem::Constraint(c) if c.kind == ConstraintKind::Prefer => {
                        dropped.push(
                            src.get(c.span.start..c.span.end)
                                .unwrap_or("prefer")
                                .to_string(),
                        );
                    }
                    other => items.push(other),
                }
            }
            r.items = items;
        }
    }
    Some(Desugared {
        program: out,
        formula,
        atoms: atoms.into_iter().map(|(n, _)| n).collect(),
        span: form.formula_span,
        dropped,
    })
}

/// `formula & G !a1 & G !a2 ...` for the block's avoids.
pub fn with_avoids(formula: &Formula, avoids: &[String]) -> Formula {
    let mut parts = vec![formula.clone()];
    parts.extend(
        avoids
            .iter()
            .map(|a| Formula::new(Kind::Always(Box::new(Formula::negation(Formula::atom(a)))))),
    );
    Formula::and_all(parts)
}

/// Atoms with a positive occurrence in `formula` (under an even number of negations, reading
/// `a -> b` as `!a | b` and `a <-> b` as both polarities), in first-occurrence order: the places
/// the formula can ask the route to enter. An atom that occurs only negated (`G !bath`) is a
/// place to keep out of, never a destination.
pub fn visit_atoms(formula: &Formula) -> Vec<String> {
    fn go(f: &Formula, neg: bool, out: &mut Vec<String>) {
        match &f.kind {
            Kind::True | Kind::False => {}
            Kind::Atom(a) => {
                if !neg && !out.contains(a) {
                    out.push(a.clone());
                }
            }
            Kind::Not(x) => go(x, !neg, out),
            Kind::Next(x) | Kind::WeakNext(x) | Kind::Eventually(x) | Kind::Always(x) => {
                go(x, neg, out)
            }
            Kind::Implies(a, b) => {
                go(a, !neg, out);
                go(b, neg, out);
            }
            Kind::Iff(a, b) => {
                for n in [neg, !neg] {
                    go(a, n, out);
                    go(b, n, out);
                }
            }
            Kind::And(a, b)
            | Kind::Or(a, b)
            | Kind::Until(a, b)
            | Kind::Release(a, b)
            | Kind::WeakUntil(a, b) => {
                go(a, neg, out);
                go(b, neg, out);
            }
        }
    }
    let mut out = Vec::new();
    go(formula, false, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn visit_atoms_are_the_positive_ones() {
        let f = parse("F(kitchen & F bed) & G !bath").unwrap();
        assert_eq!(visit_atoms(&f), vec!["kitchen", "bed"]);
        let f = parse("!(a -> b) | (c <-> !d) | !!e").unwrap();
        assert_eq!(visit_atoms(&f), vec!["a", "c", "d", "e"]);
        let f = parse("G !a & !F b").unwrap();
        assert!(visit_atoms(&f).is_empty());
    }
}
