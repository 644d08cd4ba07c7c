//! Grounding and verification findings, before they become [`crate::diagnostic`] diagnostics.
//!
//! Kept as a small local type so that the evaluator and verifier do not depend on how the
//! diagnostic renderer is built; `into_diagnostic` is the one bridge.

use m2rc_grammar::ast::Span;

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Level {
    Error,
    Warning,
}

/// One finding: a stable code, a message, the span of the expression responsible, and evidence.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    pub code: &'static str,
    pub level: Level,
    pub message: String,
    pub span: Span,
    /// Secondary spans with their explanation.
    pub labels: Vec<(Span, String)>,
    /// Evidence, one line each (the candidates of an ambiguous selection, ...).
    pub notes: Vec<String>,
    pub help: Option<String>,
}

impl Problem {
    pub fn error(code: &'static str, span: Span, message: impl Into<String>) -> Self {
        Problem {
            code,
            level: Level::Error,
            message: message.into(),
            span,
            labels: vec![],
            notes: vec![],
            help: None,
        }
    }

    pub fn warning(code: &'static str, span: Span, message: impl Into<String>) -> Self {
        Problem {
            level: Level::Warning,
            ..Problem::error(code, span, message)
        }
    }

    pub fn note(mut self, note: impl Into<String>) -> Self {
        self.notes.push(note.into());
        self
    }

    pub fn notes(mut self, notes: impl IntoIterator<Item = String>) -> Self {
        self.notes.extend(notes);
        self
    }

    pub fn label(mut self, span: Span, text: impl Into<String>) -> Self {
        self.labels.push((span, text.into()));
        self
    }

    pub fn help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }

    pub fn is_error(&self) -> bool {
        self.level == Level::Error
    }
}

impl Problem {
    /// The shared diagnostic form (code from the registry in `diagnostic::codes`).
    pub fn into_diagnostic(self) -> crate::diagnostic::Diagnostic {
        use crate::diagnostic::{Code, Diagnostic, Severity};
        let code = Code::from_id(self.code).unwrap_or(Code::EvalUnsupported);
        let mut d = Diagnostic::new(code, self.span, self.message);
        d.severity = match self.level {
            Level::Error => Severity::Error,
            Level::Warning => Severity::Warning,
        };
        for (span, text) in self.labels {
            d = d.label(span, text);
        }
        for n in self.notes {
            d = d.note(n);
        }
        if let Some(h) = self.help {
            d = d.help(h);
        }
        d
    }
}
