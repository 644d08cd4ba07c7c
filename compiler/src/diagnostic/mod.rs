//! The one diagnostic type of m2rc, shared by the parser (converted), the checker, the grounding
//! evaluator, the verifier and the planner, with its renderers (terminal text, JSON, LSP).

pub mod codes;
pub mod doc;
pub mod json;
pub mod lines;
pub mod lsp;
pub mod text;

pub use codes::{Code, CodeInfo};
pub use json::{to_json, to_json_value};
pub use lines::LineIndex;
pub use lsp::to_lsp;
pub use text::{render_text, render_text_colored};

use m2rc_grammar::ParseError;
use m2rc_grammar::ast::Span;
use serde::Serialize;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    Error,
    Warning,
}

/// A secondary location with its own short message.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Label {
    pub span: Span,
    pub message: String,
}

/// A machine-applicable edit: put `replacement` in place of `span` (an empty span inserts).
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub struct Suggestion {
    pub span: Span,
    pub replacement: String,
}

/// One finding about a program. `message` stands on its own; `help` says what to do; the
/// suggestions do it (the first is the preferred one; several are alternatives, e.g. each
/// candidate of an ambiguous category).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Diagnostic {
    pub code: Code,
    pub severity: Severity,
    pub message: String,
    pub span: Span,
    pub labels: Vec<Label>,
    pub notes: Vec<String>,
    pub help: Option<String>,
    pub suggestions: Vec<Suggestion>,
}

impl Diagnostic {
    /// A diagnostic with the code's default severity.
    pub fn new(code: Code, span: Span, message: impl Into<String>) -> Self {
        Diagnostic {
            code,
            severity: code.default_severity(),
            message: message.into(),
            span,
            labels: Vec::new(),
            notes: Vec::new(),
            help: None,
            suggestions: Vec::new(),
        }
    }

    pub fn label(mut self, span: Span, message: impl Into<String>) -> Self {
        self.labels.push(Label {
            span,
            message: message.into(),
        });
        self
    }

    pub fn note(mut self, note: impl Into<String>) -> Self {
        self.notes.push(note.into());
        self
    }

    pub fn help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }

    pub fn suggest(mut self, span: Span, replacement: impl Into<String>) -> Self {
        self.suggestions.push(Suggestion {
            span,
            replacement: replacement.into(),
        });
        self
    }

    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }

    /// Converts a parse error; its code comes from the grammar crate's `ParseErrorKind::code()`.
    pub fn from_parse(err: &ParseError) -> Self {
        let code = Code::from_id(err.code()).unwrap_or(Code::SyntaxError);
        let mut d = Diagnostic::new(code, err.span, err.message.clone());
        for (span, msg) in &err.labels {
            d = d.label(*span, msg.clone());
        }
        if let Some(h) = &err.help {
            d = d.help(h.clone());
        }
        if let Some(fix) = &err.fix {
            d = d.suggest(fix.span, fix.replacement.clone());
        }
        d
    }
}

/// The deterministic order of diagnostics: by span start, then code, then message.
pub fn sort(diags: &mut [Diagnostic]) {
    diags.sort_by(|a, b| {
        (a.span.start, a.code.id(), a.span.end, &a.message).cmp(&(
            b.span.start,
            b.code.id(),
            b.span.end,
            &b.message,
        ))
    });
}

/// Applies the first suggestion of every diagnostic that has one, skipping overlapping edits;
/// used by tests (and `m2rc fix`, should it exist) to check that suggestions really repair.
pub fn apply_suggestions(source: &str, diags: &[Diagnostic]) -> String {
    let mut edits: Vec<&Suggestion> = diags.iter().filter_map(|d| d.suggestions.first()).collect();
    edits.sort_by_key(|s| (s.span.start, s.span.end));
    let mut out = String::with_capacity(source.len());
    let mut pos = 0;
    for e in edits {
        if e.span.start < pos || e.span.end > source.len() {
            continue;
        }
        out.push_str(&source[pos..e.span.start]);
        out.push_str(&e.replacement);
        pos = e.span.end;
    }
    out.push_str(&source[pos..]);
    out
}

#[cfg(test)]
mod tests;
