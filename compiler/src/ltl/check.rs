//! Checking a formula written by a user (the `ltl "..."` route form): syntax, atoms, the
//! finite-route reading, satisfiability. Every problem is a [`Diagnostic`] with a span into the
//! `.m2r` source (the formula's offset is added), a `help:` and, where one is certain, a rewrite.

use super::dfa::{BuildError, Dfa};
use super::syntax::{Formula, Kind, SyntaxErrorKind, parse};
use crate::diagnostic::{Code, Diagnostic};
use m2rc_grammar::ast::Span;

/// What a name in the formula refers to.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum AtomKind {
    /// A place binding: usable as an atom.
    Place,
    /// A binding of another type (its type, for the message).
    Other(String),
    /// No binding of that name.
    Unknown,
}

/// A formula that passed every check, with its atoms (first-occurrence order) and automaton.
#[derive(Clone, Debug)]
pub struct CheckedFormula {
    pub formula: Formula,
    pub atoms: Vec<String>,
    pub dfa: Dfa,
    /// Warnings (e.g. `X` steps).
    pub warnings: Vec<Diagnostic>,
}

fn shift(s: Span, offset: usize) -> Span {
    Span::new(s.start + offset, s.end + offset)
}

/// Checks `text`, whose first byte is at `offset` in the program, against the program's names.
/// `names` lists every binding in scope, for "did you mean" suggestions.
pub fn check_formula(
    text: &str,
    offset: usize,
    lookup: &dyn Fn(&str) -> AtomKind,
    names: &[String],
) -> Result<CheckedFormula, Vec<Diagnostic>> {
    let mut f = match parse(text) {
        Ok(f) => f,
        Err(e) => {
            let code = match e.kind {
                SyntaxErrorKind::Unsupported => Code::LtlUnsupported,
                SyntaxErrorKind::Unbalanced => Code::LtlUnbalanced,
                SyntaxErrorKind::Syntax => Code::LtlSyntax,
            };
            let span = shift(e.span, offset);
            let mut d = Diagnostic::new(code, span, e.message);
            if let Some(h) = e.help {
                d = d.help(h);
            }
            if let Some(fix) = e.fix {
                d = d.suggest(span, fix);
            }
            return Err(vec![d]);
        }
    };
    let mut errors = Vec::new();
    let mut warnings = Vec::new();
    // Atoms.
    f.walk(&mut |g| {
        if let Kind::Atom(name) = &g.kind {
            let span = shift(g.span, offset);
            match lookup(name) {
                AtomKind::Place => {}
                AtomKind::Other(ty) => errors.push(
                    Diagnostic::new(
                        Code::LtlNotPlace,
                        span,
                        format!("atom `{name}` is a {ty}, not a place"),
                    )
                    .help(
                        "atoms are places bound with `let` (an object, a room or a region); \
                         read as \"the route is in that place\"",
                    ),
                ),
                AtomKind::Unknown => {
                    let mut d = Diagnostic::new(
                        Code::LtlUnknownAtom,
                        span,
                        format!("no place named `{name}` is bound before this formula"),
                    );
                    match crate::suggest::best(name, names.iter().map(String::as_str)) {
                        Some(s) => {
                            d = d.help(format!("did you mean `{s}`?")).suggest(span, s);
                        }
                        None => {
                            d = d.help(format!(
                                "bind it first, e.g. `let {name} = objects(...).only()`"
                            ))
                        }
                    }
                    errors.push(d);
                }
            }
        }
    });
    // Idioms of infinite-trace LTL that mean something else (or nothing) on a finite route.
    f.walk(&mut |g| {
        let span = shift(g.span, offset);
        let inner_text = |h: &Formula| text.get(h.span.start..h.span.end).unwrap_or("").to_string();
        match &g.kind {
            Kind::Always(h) if matches!(h.kind, Kind::Eventually(_)) => {
                let Kind::Eventually(x) = &h.kind else { return };
                errors.push(
                    Diagnostic::new(
                        Code::LtlInfiniteIdiom,
                        span,
                        "`G F` (visit again and again) has no meaning on a finite route: \
                         on a finished route it only says where the route ends",
                    )
                    .help("to visit the place, write `F` alone")
                    .suggest(span, format!("F({})", inner_text(x))),
                );
            }
            Kind::Eventually(h) if matches!(h.kind, Kind::Always(_)) => {
                errors.push(
                    Diagnostic::new(
                        Code::LtlInfiniteIdiom,
                        span,
                        "`F G` (eventually stay forever) has no meaning on a finite route: \
                         on a finished route it only says where the route ends",
                    )
                    .help("write `F x` to reach x, or `G x` to stay in x for the whole route"),
                );
            }
            Kind::Next(_) | Kind::WeakNext(_) => warnings.push(
                Diagnostic::new(
                    Code::LtlNextStep,
                    span,
                    "`X` steps one grid cell: `X a` means the next cell of the route is in `a`",
                )
                .help("to say \"later\", write `F`; to say \"next place\", nest `F`: `F(a & F b)`"),
            ),
            _ => {}
        }
    });
    if !errors.is_empty() {
        return Err(errors);
    }
    let atoms: Vec<String> = f.atoms().into_iter().map(str::to_string).collect();
    let whole = shift(f.span, offset);
    let dfa = match Dfa::build(&f, &atoms, true) {
        Ok(d) => d,
        Err(
            e @ (BuildError::TooManyAtoms(_)
            | BuildError::TooManyStates(_)
            | BuildError::TooDeep(_)
            | BuildError::Budget { .. }),
        ) => {
            let help = if matches!(e, BuildError::TooDeep(_)) {
                "drop nested `X` operators, or split the formula"
            } else {
                "use fewer places, or fewer unordered ones: each `F x` conjoined with the others \
                 doubles the automaton, while an ordered chain `F(a & F b)` adds one state per \
                 place"
            };
            return Err(vec![
                Diagnostic::new(Code::LtlTooLarge, whole, e.to_string()).help(help),
            ]);
        }
        Err(e) => {
            return Err(vec![Diagnostic::new(
                Code::LtlUnknownAtom,
                whole,
                e.to_string(),
            )]);
        }
    };
    if !dfa.is_satisfiable() {
        return Err(vec![
            Diagnostic::new(
                Code::LtlUnsatisfiable,
                whole,
                "no route satisfies this formula, on any map",
            )
            .help("look for a place that is both required and avoided, or contradictory order"),
        ]);
    }
    f.offset(offset);
    Ok(CheckedFormula {
        formula: f,
        atoms,
        dfa,
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lookup(n: &str) -> AtomKind {
        match n {
            "bed" | "kitchen" | "bath" => AtomKind::Place,
            "k" => AtomKind::Other("number".into()),
            _ => AtomKind::Unknown,
        }
    }

    fn err(text: &str) -> Diagnostic {
        let names: Vec<String> = ["bed", "kitchen", "bath", "k"].map(String::from).to_vec();
        check_formula(text, 10, &lookup, &names)
            .unwrap_err()
            .remove(0)
    }

    #[test]
    fn each_bad_formula_gets_its_code_and_span() {
        let d = err("F(bed & kichen)");
        assert_eq!(d.code, Code::LtlUnknownAtom);
        assert_eq!(d.span, Span::new(18, 24));
        assert_eq!(d.suggestions[0].replacement, "kitchen");
        let d = err("F k");
        assert_eq!((d.code, d.span), (Code::LtlNotPlace, Span::new(12, 13)));
        let d = err("F(bed S kitchen)");
        assert_eq!((d.code, d.span), (Code::LtlUnsupported, Span::new(16, 17)));
        let d = err("F(bed & F kitchen");
        assert_eq!((d.code, d.span), (Code::LtlUnbalanced, Span::new(11, 12)));
        let d = err("F bed & G !bed");
        assert_eq!(
            (d.code, d.span),
            (Code::LtlUnsatisfiable, Span::new(10, 24))
        );
        let d = err("G F bed");
        assert_eq!(d.code, Code::LtlInfiniteIdiom);
        assert_eq!(d.suggestions[0].replacement, "F(bed)");
        assert_eq!(err("F G bed").code, Code::LtlInfiniteIdiom);
        assert_eq!(err("F(bed &)").code, Code::LtlSyntax);
    }

    #[test]
    fn good_formula_has_atoms_and_warnings() {
        let c = check_formula("F(bed & X kitchen)", 0, &lookup, &[]).unwrap();
        assert_eq!(c.atoms, vec!["bed", "kitchen"]);
        assert_eq!(c.warnings[0].code, Code::LtlNextStep);
    }
}
