//! Checking a `route ltl "..."` block inside the checker, so the formula's atoms resolve like any
//! other name (unknown names get the usual "did you mean", uses count, hover works) and must be
//! places. The block's body may state `avoid` (kept: a global `G !a`) and `prefer` (dropped with
//! a warning: preferences have no meaning in the formula); `go` stages are refused.

use super::check::{AtomKind, check_formula};
use super::syntax::{Kind, parse};
use crate::check::Checker;
use crate::diagnostic::{Code, Diagnostic};
use crate::slot::Slot;
use m2rc_grammar::ast::{ConstraintKind, Expr, ExprKind, Ident, LtlForm, RouteItem, Span};
use m2rc_stdlib::builtins::{Ty, Type};

const PLACE: &[Ty] = &[Ty::PLACE];

/// The formula's text as written and the offset of its first byte in the source. Falls back to
/// the string's value (spans then approximate) when the literal holds escapes.
pub fn formula_text<'s>(src: &'s str, f: &'s LtlForm) -> (&'s str, usize) {
    let inner = Span::new(
        f.formula_span.start + 1,
        f.formula_span.end.saturating_sub(1),
    );
    match src.get(inner.start..inner.end) {
        Some(raw) if raw == f.formula => (raw, inner.start),
        _ => (f.formula.as_str(), inner.start),
    }
}

impl Checker<'_> {
    pub(crate) fn ltl_form(&mut self, f: &LtlForm, items: &[RouteItem]) {
        if f.keyword.name != "ltl" {
            self.report(
                Diagnostic::new(
                    Code::LtlSyntax,
                    f.keyword.span,
                    format!(
                        "expected `{{` or `ltl` after `route`, found `{}`",
                        f.keyword.name
                    ),
                )
                .help("an LTL route is written `route ltl \"F(a & F b)\"`")
                .suggest(f.keyword.span, "ltl"),
            );
            return;
        }
        for it in items {
            match it {
                RouteItem::Stage(s) => self.report(
                    Diagnostic::new(
                        Code::LtlMixedRoute,
                        s.span,
                        "an LTL route has no `go` stages: its formula says where to go",
                    )
                    .help("add the destination to the formula, e.g. `F(a & F b)` for a then b"),
                ),
                RouteItem::For(fs) => self.report(
                    Diagnostic::new(
                        Code::LtlMixedRoute,
                        fs.span,
                        "an LTL route has no `for` stages: its formula says where to go",
                    )
                    .help("name each place with `let` and list them in the formula"),
                ),
                RouteItem::Constraint(c) if c.kind == ConstraintKind::Prefer => self.report(
                    Diagnostic::new(
                        Code::LtlDropped,
                        c.span,
                        "the LTL planner ignores preferences: this one does not change the route",
                    )
                    .note("soft preferences and their scopes have no meaning in an LTL formula")
                    .help("plan with `route { go ... }` to use preferences"),
                ),
                RouteItem::Constraint(c) if c.kind == ConstraintKind::Pass => self.report(
                    Diagnostic::new(
                        Code::LtlMixedRoute,
                        c.span,
                        "`pass` has no stage to belong to in an LTL route",
                    )
                    .help("write the order in the formula: `F(p & F dest)`"),
                ),
                _ => {}
            }
        }
        let (text, offset) = formula_text(self.src, f);
        let Ok(parsed) = parse(text) else {
            // `check_formula` turns the syntax error into its diagnostic.
            if let Err(ds) = check_formula(text, offset, &|_| AtomKind::Place, &[]) {
                for d in ds {
                    self.report(d);
                }
            }
            return;
        };
        let mut atoms_ok = true;
        let mut occurrences: Vec<(String, Span)> = Vec::new();
        parsed.walk(&mut |g| {
            if let Kind::Atom(a) = &g.kind {
                occurrences.push((
                    a.clone(),
                    Span::new(g.span.start + offset, g.span.end + offset),
                ));
            }
        });
        for (name, span) in occurrences {
            let e = Expr {
                kind: ExprKind::Name(Ident {
                    name: name.clone(),
                    span,
                }),
                span,
            };
            let ty = self.expr(&e, Slot::alts(PLACE));
            if ty == Type::Error {
                atoms_ok = false;
            } else if !Slot::alts(PLACE).accepts(ty) {
                atoms_ok = false;
                self.report(
                    Diagnostic::new(
                        Code::LtlNotPlace,
                        span,
                        format!("atom `{name}` is a {ty}, not a place"),
                    )
                    .help(format!(
                        "atoms are places bound with `let`; e.g. `let {name} = ...only()` before the route"
                    )),
                );
            }
        }
        if !atoms_ok {
            return;
        }
        match check_formula(text, offset, &|_| AtomKind::Place, &[]) {
            Ok(c) => {
                for w in c.warnings {
                    self.report(w);
                }
            }
            Err(ds) => {
                for d in ds {
                    self.report(d);
                }
            }
        }
    }
}
