//! Diagnostics as the Language Server Protocol sees them.

use super::{Diagnostic, LineIndex, Severity};
use lsp_types as lsp;
use m2rc_grammar::ast::Span;

pub fn range(idx: &LineIndex, span: Span) -> lsp::Range {
    let (sl, sc) = idx.utf16(span.start);
    let (el, ec) = idx.utf16(span.end);
    lsp::Range::new(lsp::Position::new(sl, sc), lsp::Position::new(el, ec))
}

/// Converts diagnostics for one document; `uri` names it in related-information links.
/// Help and suggestions travel in `data` (`{"help", "suggestions": [{"range", "newText"}]}`) so
/// that the server can turn them into code actions.
pub fn to_lsp(diags: &[Diagnostic], source: &str, uri: &lsp::Uri) -> Vec<lsp::Diagnostic> {
    let idx = LineIndex::new(source);
    diags
        .iter()
        .map(|d| {
            let related: Vec<lsp::DiagnosticRelatedInformation> = d
                .labels
                .iter()
                .map(|l| lsp::DiagnosticRelatedInformation {
                    location: lsp::Location::new(uri.clone(), range(&idx, l.span)),
                    message: l.message.clone(),
                })
                .collect();
            let mut message = d.message.clone();
            for n in &d.notes {
                message.push_str("\nnote: ");
                message.push_str(n);
            }
            if let Some(h) = &d.help {
                message.push_str("\nhelp: ");
                message.push_str(h);
            }
            let suggestions: Vec<serde_json::Value> = d
                .suggestions
                .iter()
                .map(|s| serde_json::json!({ "range": range(&idx, s.span), "newText": s.replacement }))
                .collect();
            lsp::Diagnostic {
                range: range(&idx, d.span),
                severity: Some(match d.severity {
                    Severity::Error => lsp::DiagnosticSeverity::ERROR,
                    Severity::Warning => lsp::DiagnosticSeverity::WARNING,
                }),
                code: Some(lsp::NumberOrString::String(d.code.id().to_string())),
                code_description: None,
                source: Some("m2rc".to_string()),
                message,
                related_information: (!related.is_empty()).then_some(related),
                tags: (d.code == super::Code::UnusedBinding)
                    .then(|| vec![lsp::DiagnosticTag::UNNECESSARY]),
                data: Some(serde_json::json!({ "help": d.help, "suggestions": suggestions })),
            }
        })
        .collect()
}
