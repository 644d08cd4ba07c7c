//! Hover text: the signature and one-line doc of a built-in (every overload, since the receiver
//! picks one), the type of a binding, what a category or keyword means.

use super::locate::{self, Word};
use lsp_types as lsp;
use m2rc_stdlib::builtins;
use m2rc_stdlib::vocab::{CategoryKind, Vocabulary};

/// Keywords and what they do, for hover.
pub const KEYWORDS: &[(&str, &str)] = &[
    (
        "let",
        "`let name = value` binds a name for the rest of its scope.",
    ),
    (
        "route",
        "`route { ... }` holds the ordered stages and the route-wide constraints.",
    ),
    (
        "go",
        "`go place [as name] [{ ... }]` is one stage: head to the place.",
    ),
    (
        "as",
        "`go place as name` names a stage so that `during name` can refer to it.",
    ),
    (
        "pass",
        "`pass place`: a hard must-pass, in the order written, before the stage's destination.",
    ),
    (
        "avoid",
        "`avoid place`: a hard must-avoid while the constraint is active.",
    ),
    (
        "prefer",
        "`prefer preference`: a soft preference (near, far, closer, path shape, clearance).",
    ),
    (
        "within",
        "`within place`: spatial scope; the constraint counts only inside the place.",
    ),
    (
        "during",
        "`during stage, ...`: route-stage scope for a constraint written outside the stages.",
    ),
    (
        "for",
        "`for x in set { go x ... }`: one group of stages per element, in the set's order.",
    ),
    ("in", "`for x in set`: the set to iterate."),
    (
        "if",
        "`if cond { a } else { b }`: chooses between two values.",
    ),
    (
        "else",
        "`if cond { a } else { b }`: the value when the condition is false.",
    ),
    ("and", "Logical and."),
    ("or", "Logical or."),
    ("not", "Logical negation."),
    ("true", "The boolean true."),
    ("false", "The boolean false."),
];

pub fn hover(text: &str, pos: lsp::Position, vocab: &Vocabulary) -> Option<lsp::Hover> {
    let offset = super::offset(text, pos);
    if locate::in_comment(text, offset) {
        return None;
    }
    let word = locate::word_at(text, offset)?;
    let markdown = describe(text, &word, vocab)?;
    let idx = crate::diagnostic::LineIndex::new(text);
    let range =
        crate::diagnostic::lsp::range(&idx, m2rc_grammar::ast::Span::new(word.start, word.end));
    Some(lsp::Hover {
        contents: lsp::HoverContents::Markup(lsp::MarkupContent {
            kind: lsp::MarkupKind::Markdown,
            value: markdown,
        }),
        range: Some(range),
    })
}

fn describe(text: &str, word: &Word<'_>, vocab: &Vocabulary) -> Option<String> {
    let name = word.text;
    if word.after_dot {
        let rows: Vec<_> = builtins::methods(name).collect();
        return (!rows.is_empty()).then(|| signatures(&rows));
    }
    // A binding shadows built-ins and categories of the same name.
    if locate::bindings_before(text, word.start).contains(&name)
        || locate::bindings_before(text, text.len()).contains(&name)
    {
        let ty = binding_type(text, name, vocab);
        return Some(match ty {
            Some(t) => format!("```m2r\nlet {name}: {t}\n```"),
            None => format!("```m2r\nlet {name}\n```"),
        });
    }
    if word.called {
        let rows: Vec<_> = builtins::functions(name).collect();
        if !rows.is_empty() {
            return Some(signatures(&rows));
        }
    }
    if let Some(c) = builtins::constant(name) {
        return Some(format!("```m2r\n{}: {}\n```\n{}", c.name, c.ty, c.doc));
    }
    if let Some(w) = builtins::enum_word(name) {
        return Some(format!("```m2r\n{}: {}\n```\n{}", w.name, w.ty, w.doc));
    }
    if let Some(kind) = vocab.kind(name) {
        let what = match kind {
            CategoryKind::Object => format!("object category; `objects({name})` is every {name}"),
            CategoryKind::Room => format!("room category; `rooms({name})` is every {name}"),
        };
        return Some(format!("```m2r\n{name}: Category\n```\n{what}."));
    }
    if let Some((_, doc)) = KEYWORDS.iter().find(|(k, _)| *k == name) {
        return Some(format!("**{name}** (keyword)\n\n{doc}"));
    }
    let rows: Vec<_> = builtins::functions(name).collect();
    (!rows.is_empty()).then(|| signatures(&rows))
}

fn signatures(rows: &[&builtins::Builtin]) -> String {
    let mut out = String::from("```m2r\n");
    for b in rows {
        out.push_str(&b.signature(None));
        out.push('\n');
    }
    out.push_str("```\n");
    let mut seen: Vec<&str> = Vec::new();
    for b in rows {
        if !seen.contains(&b.doc) {
            seen.push(b.doc);
            out.push_str(&format!("\n{}", b.doc));
        }
    }
    if let Some(b) = rows.first() {
        out.push_str(&format!("\n\nExample: `{}`", b.example));
    }
    out
}

/// The checked type of a `let` binding, from the type checker's side table (the last binding of
/// that name in the file, which is the one in scope at the end of most programs).
fn binding_type(text: &str, name: &str, vocab: &Vocabulary) -> Option<String> {
    use m2rc_grammar::ast::{Item, Let, RouteItem, StageItem};
    fn route_lets<'a>(items: &'a [RouteItem], out: &mut Vec<&'a Let>) {
        for item in items {
            match item {
                RouteItem::Let(l) => out.push(l),
                RouteItem::Stage(s) => {
                    for si in &s.body {
                        if let StageItem::Let(l) = si {
                            out.push(l);
                        }
                    }
                }
                RouteItem::For(f) => route_lets(&f.body, out),
                RouteItem::Constraint(_) | RouteItem::Error(_) | RouteItem::Ltl(_) => {}
            }
        }
    }
    let result = crate::check::check(text, vocab);
    let mut lets: Vec<&Let> = Vec::new();
    for item in &result.program.items {
        match item {
            Item::Let(l) => lets.push(l),
            Item::Route(r) => route_lets(&r.items, &mut lets),
            Item::Error(_) => {}
        }
    }
    let binding = lets.into_iter().rev().find(|l| l.name.name == name)?;
    result.types.get(&binding.value.span).map(|t| t.to_string())
}
