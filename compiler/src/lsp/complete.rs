//! Completion: methods after `.`, otherwise bindings in scope, free built-ins, constants, keywords
//! and (from the configured map, or the benchmark vocabulary) categories.

use super::hover::KEYWORDS;
use super::locate;
use lsp_types as lsp;
use m2rc_stdlib::builtins;
use m2rc_stdlib::vocab::{CategoryKind, Vocabulary};

pub fn complete(text: &str, pos: lsp::Position, vocab: &Vocabulary) -> Vec<lsp::CompletionItem> {
    let offset = super::offset(text, pos);
    if locate::in_comment(text, offset) {
        return Vec::new();
    }
    let (prefix, after_dot) = locate::prefix_at(text, offset);
    let mut items: Vec<lsp::CompletionItem> = Vec::new();
    let mut push = |label: &str, kind: lsp::CompletionItemKind, detail: String, doc: &str| {
        if label.starts_with(prefix) && !items.iter().any(|i| i.label == label) {
            items.push(lsp::CompletionItem {
                label: label.to_string(),
                kind: Some(kind),
                detail: Some(detail),
                documentation: (!doc.is_empty()).then(|| {
                    lsp::Documentation::MarkupContent(lsp::MarkupContent {
                        kind: lsp::MarkupKind::Markdown,
                        value: doc.to_string(),
                    })
                }),
                ..Default::default()
            });
        }
    };
    if after_dot {
        for b in builtins::BUILTINS.iter().filter(|b| b.is_method()) {
            push(
                b.name,
                lsp::CompletionItemKind::METHOD,
                b.signature(None),
                b.doc,
            );
        }
        return items;
    }
    for name in locate::bindings_before(text, offset) {
        push(
            name,
            lsp::CompletionItemKind::VARIABLE,
            "binding".to_string(),
            "",
        );
    }
    for b in builtins::BUILTINS.iter().filter(|b| !b.is_method()) {
        push(
            b.name,
            lsp::CompletionItemKind::FUNCTION,
            b.signature(None),
            b.doc,
        );
    }
    for c in builtins::CONSTANTS {
        push(
            c.name,
            lsp::CompletionItemKind::CONSTANT,
            c.ty.to_string(),
            c.doc,
        );
    }
    for w in builtins::ENUM_WORDS {
        push(
            w.name,
            lsp::CompletionItemKind::ENUM_MEMBER,
            w.ty.to_string(),
            w.doc,
        );
    }
    for (k, doc) in KEYWORDS {
        push(
            k,
            lsp::CompletionItemKind::KEYWORD,
            "keyword".to_string(),
            doc,
        );
    }
    for (cat, kind) in vocab.all() {
        let detail = match kind {
            CategoryKind::Object => "object category",
            CategoryKind::Room => "room category",
        };
        push(
            cat,
            lsp::CompletionItemKind::ENUM_MEMBER,
            detail.to_string(),
            "",
        );
    }
    items
}
