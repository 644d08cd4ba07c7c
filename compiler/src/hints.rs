//! Repairs that need the parse and the vocabulary together, and the suppression of follow-on
//! errors after a syntax error.

use crate::diagnostic::{Code, Diagnostic};
use m2rc_grammar::ast::{
    Constraint, Expr, ExprKind, Item, Program, RouteItem, Scope, Span, StageItem,
};
use m2rc_stdlib::vocab::{Lookup, Vocabulary};

fn is_word_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// `objects(dog bed)`: the parser stops at `bed`; when `dog_bed` is a category, say so and offer
/// the snake_case name.
pub(crate) fn two_word_categories(diags: &mut [Diagnostic], source: &str, vocab: &Vocabulary) {
    for d in diags.iter_mut() {
        if d.code != Code::UnexpectedToken || !d.suggestions.is_empty() {
            continue;
        }
        let Some(second) = source.get(d.span.start..d.span.end) else {
            continue;
        };
        if second.is_empty() || !second.chars().all(is_word_char) {
            continue;
        }
        let before = &source[..d.span.start];
        let gap = before.len() - before.trim_end_matches([' ', '\t']).len();
        if gap == 0 {
            continue;
        }
        let head = &before[..before.len() - gap];
        let first_len = head.len() - head.trim_end_matches(is_word_char).len();
        if first_len == 0 {
            continue;
        }
        let first = &head[head.len() - first_len..];
        let joined = format!("{first}_{second}");
        if !matches!(
            vocab.lookup(&joined),
            Lookup::Unknown | Lookup::Ambiguous(_)
        ) {
            d.help = Some(format!(
                "a category is one word: write `{joined}` for `{first} {second}`"
            ));
            d.suggestions.push(crate::diagnostic::Suggestion {
                span: Span::new(head.len() - first_len, d.span.end),
                replacement: joined,
            });
        }
    }
}

/// Spans of expressions that directly hold a part the parser could not read. Checker errors
/// inside them are follow-ons of the syntax error, which already has its diagnostic.
pub(crate) fn broken_spans(p: &Program) -> Vec<Span> {
    let mut out = Vec::new();
    for item in &p.items {
        match item {
            Item::Let(l) => expr(&l.value, &mut out),
            Item::Route(r) => route_items(&r.items, &mut out),
            Item::Error(_) => {}
        }
    }
    out
}

fn route_items(items: &[RouteItem], out: &mut Vec<Span>) {
    for it in items {
        match it {
            RouteItem::Stage(s) => {
                expr(&s.target, out);
                for b in &s.body {
                    match b {
                        StageItem::Constraint(c) => constraint(c, out),
                        StageItem::Let(l) => expr(&l.value, out),
                        StageItem::Error(_) => {}
                    }
                }
            }
            RouteItem::Constraint(c) => constraint(c, out),
            RouteItem::Let(l) => expr(&l.value, out),
            RouteItem::For(f) => {
                expr(&f.iter, out);
                route_items(&f.body, out);
            }
            // The formula is a string the LTL checker reads on its own.
            RouteItem::Ltl(_) | RouteItem::Error(_) => {}
        }
    }
}

fn constraint(c: &Constraint, out: &mut Vec<Span>) {
    expr(&c.value, out);
    for s in &c.scopes {
        if let Scope::Within { place, .. } = s {
            expr(place, out);
        }
    }
}

fn expr(e: &Expr, out: &mut Vec<Span>) {
    broken(e, out);
}

/// Walks `e`; returns whether `e` itself is an error node.
fn broken(e: &Expr, out: &mut Vec<Span>) -> bool {
    let children: Vec<&Expr> = match &e.kind {
        ExprKind::Error => return true,
        ExprKind::Call { args, .. } => args.iter().map(|a| &a.value).collect(),
        ExprKind::Method { receiver, args, .. } => std::iter::once(&**receiver)
            .chain(args.iter().map(|a| &a.value))
            .collect(),
        ExprKind::Lambda { body, .. } => vec![body],
        ExprKind::Binary { lhs, rhs, .. } => vec![lhs, rhs],
        ExprKind::Unary { operand, .. } => vec![operand],
        ExprKind::If {
            cond,
            then,
            otherwise,
        } => vec![cond, then, otherwise],
        _ => Vec::new(),
    };
    let mut any = false;
    for c in children {
        any |= broken(c, out);
    }
    if any {
        out.push(e.span);
    }
    false
}

/// Drops checker diagnostics that lie inside a broken expression.
pub(crate) fn suppress_follow_ons(diags: &mut Vec<Diagnostic>, broken: &[Span]) {
    if broken.is_empty() {
        return;
    }
    diags.retain(|d| {
        !broken
            .iter()
            .any(|b| d.span.start >= b.start && d.span.end <= b.end)
    });
}
