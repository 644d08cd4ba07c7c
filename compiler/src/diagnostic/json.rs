//! The JSON form of diagnostics (schema documented in `docs/diagnostics.md`).

use super::{Diagnostic, LineIndex};
use m2rc_grammar::ast::Span;
use serde_json::{Value, json};

fn span_json(idx: &LineIndex, span: Span) -> Value {
    let (line, col) = idx.line_col(span.start);
    let (end_line, end_col) = idx.line_col(span.end);
    json!({
        "start": span.start, "end": span.end,
        "line": line, "col": col, "end_line": end_line, "end_col": end_col,
    })
}

/// One diagnostic as a JSON object; `source` gives line and column numbers.
pub fn to_json_value(d: &Diagnostic, source: &str) -> Value {
    let idx = LineIndex::new(source);
    one(d, &idx)
}

fn one(d: &Diagnostic, idx: &LineIndex) -> Value {
    let suggestions: Vec<Value> = d
        .suggestions
        .iter()
        .map(|s| json!({ "span": span_json(idx, s.span), "replacement": s.replacement }))
        .collect();
    json!({
        "code": d.code.id(),
        "severity": d.severity,
        "title": d.code.title(),
        "message": d.message,
        "span": span_json(idx, d.span),
        "labels": d.labels.iter()
            .map(|l| json!({ "span": span_json(idx, l.span), "message": l.message }))
            .collect::<Vec<_>>(),
        "notes": d.notes,
        "help": d.help,
        "suggestion": suggestions.first().cloned(),
        "suggestions": suggestions,
    })
}

/// All diagnostics as a pretty-printed JSON array.
pub fn to_json(diags: &[Diagnostic], source: &str) -> String {
    let idx = LineIndex::new(source);
    let arr: Vec<Value> = diags.iter().map(|d| one(d, &idx)).collect();
    serde_json::to_string_pretty(&arr).unwrap_or_else(|_| "[]".to_string())
}
