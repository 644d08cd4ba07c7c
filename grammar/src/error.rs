//! Parse errors as data: a kind with a stable code, a primary span, a one-line message, and
//! optionally a help text, a machine-applicable fix and secondary labels. Rendering (codespan,
//! JSON, LSP) belongs to the compiler's diagnostic type; it converts these one to one.
//!
//! Codes `E0001`-`E00xx` are owned here. Never renumber a code: LLM repair prompts, docs and
//! benchmark logs refer to them. Add new kinds at the end.

use crate::ast::Span;
use serde::Serialize;

/// One thing wrong with the source text. Every variant is a distinct situation with its own code.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub enum ParseErrorKind {
    /// A character that cannot start any token (`@`, `%`, a non-ASCII letter outside a string).
    InvalidToken { text: String },
    /// A token the grammar cannot accept here; `expected` is in human words (see
    /// [`crate::expected_words`]).
    UnexpectedToken {
        found: String,
        expected: Vec<String>,
    },
    /// The file ended in the middle of a construct.
    UnexpectedEof { expected: Vec<String> },
    /// Input left over after a complete program (the parser's own safety net; rarely seen).
    ExtraToken { found: String },
    /// A `"` string with no closing `"` on the same line.
    UnterminatedString,
    /// An integer that does not fit in 64 bits or a number too large to represent.
    BadNumber { text: String },
    /// A number glued to a suffix that is not a unit: `3ft`, `5mm`, `1e5`.
    UnknownUnit { unit: String },
    /// A backslash escape the language does not know, such as `\q`.
    BadEscape { escape: String },
    /// `'chair'`: strings use double quotes, and categories are bare names anyway.
    SingleQuotedString,
    /// `;` after a statement: the language has no separators.
    Semicolon,
    /// `x := value`, from Python or Go.
    Walrus,
    /// `=` where a comparison `==` can stand.
    AssignInsteadOfEq,
    /// A word from another language where a statement or expression should start: `def`,
    /// `lambda`, `return`, `var`, `elif`, ...
    ForeignKeyword { word: String },
    /// `&&`, `||` or `!` instead of `and`, `or`, `not`.
    ForeignOperator { op: String, replacement: String },
    /// A `(` or `{` that is never closed: the parser reached something that cannot continue
    /// inside it.
    UnclosedDelimiter { open: Span, delimiter: String },
    /// A `#` comment; comments start with `//`.
    HashComment,
    /// A statement so long that later phases could overflow their stack walking it.
    StatementTooLong { tokens: usize, limit: usize },
    /// `name = value` where a binding was meant: `let` is missing.
    MissingLet { name: String },
}

impl ParseErrorKind {
    /// The stable diagnostic code of this kind.
    pub fn code(&self) -> &'static str {
        match self {
            ParseErrorKind::InvalidToken { .. } => "E0001",
            ParseErrorKind::UnexpectedToken { .. } => "E0002",
            ParseErrorKind::UnexpectedEof { .. } => "E0003",
            ParseErrorKind::ExtraToken { .. } => "E0004",
            ParseErrorKind::UnterminatedString => "E0005",
            ParseErrorKind::BadNumber { .. } => "E0006",
            ParseErrorKind::UnknownUnit { .. } => "E0007",
            ParseErrorKind::BadEscape { .. } => "E0008",
            ParseErrorKind::SingleQuotedString => "E0009",
            ParseErrorKind::Semicolon => "E0010",
            ParseErrorKind::Walrus => "E0011",
            ParseErrorKind::AssignInsteadOfEq => "E0012",
            ParseErrorKind::ForeignKeyword { .. } => "E0013",
            ParseErrorKind::ForeignOperator { .. } => "E0014",
            ParseErrorKind::UnclosedDelimiter { .. } => "E0015",
            ParseErrorKind::HashComment => "E0016",
            ParseErrorKind::StatementTooLong { .. } => "E0017",
            ParseErrorKind::MissingLet { .. } => "E0018",
        }
    }

    /// A short kebab-case name for docs and logs.
    pub fn slug(&self) -> &'static str {
        match self {
            ParseErrorKind::InvalidToken { .. } => "invalid-token",
            ParseErrorKind::UnexpectedToken { .. } => "unexpected-token",
            ParseErrorKind::UnexpectedEof { .. } => "unexpected-end-of-file",
            ParseErrorKind::ExtraToken { .. } => "extra-token",
            ParseErrorKind::UnterminatedString => "unterminated-string",
            ParseErrorKind::BadNumber { .. } => "bad-number",
            ParseErrorKind::UnknownUnit { .. } => "unknown-unit",
            ParseErrorKind::BadEscape { .. } => "bad-escape",
            ParseErrorKind::SingleQuotedString => "single-quoted-string",
            ParseErrorKind::Semicolon => "semicolon",
            ParseErrorKind::Walrus => "walrus-assignment",
            ParseErrorKind::AssignInsteadOfEq => "assign-instead-of-equality",
            ParseErrorKind::ForeignKeyword { .. } => "foreign-keyword",
            ParseErrorKind::ForeignOperator { .. } => "foreign-operator",
            ParseErrorKind::UnclosedDelimiter { .. } => "unclosed-delimiter",
            ParseErrorKind::HashComment => "hash-comment",
            ParseErrorKind::StatementTooLong { .. } => "statement-too-long",
            ParseErrorKind::MissingLet { .. } => "missing-let",
        }
    }
}

/// A replacement that fixes the error mechanically: put `replacement` in place of `span`
/// (an empty span inserts).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Fix {
    pub span: Span,
    pub replacement: String,
}

/// One parse error. `message` is complete on its own ("expected an expression, found `)`");
/// `help` says what to write instead; `fix` does it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ParseError {
    pub span: Span,
    pub kind: ParseErrorKind,
    pub message: String,
    pub help: Option<String>,
    pub fix: Option<Fix>,
    /// Secondary locations, such as the `(` that a missing `)` should close.
    pub labels: Vec<(Span, String)>,
}

impl ParseError {
    pub(crate) fn new(span: Span, kind: ParseErrorKind, message: impl Into<String>) -> Self {
        ParseError {
            span,
            kind,
            message: message.into(),
            help: None,
            fix: None,
            labels: Vec::new(),
        }
    }

    pub(crate) fn with_help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }

    pub(crate) fn with_fix(mut self, span: Span, replacement: impl Into<String>) -> Self {
        self.fix = Some(Fix {
            span,
            replacement: replacement.into(),
        });
        self
    }

    pub(crate) fn with_label(mut self, span: Span, text: impl Into<String>) -> Self {
        self.labels.push((span, text.into()));
        self
    }

    /// The stable code of the kind.
    pub fn code(&self) -> &'static str {
        self.kind.code()
    }
}

impl std::fmt::Display for ParseError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "error[{}] at {}..{}: {}",
            self.code(),
            self.span.start,
            self.span.end,
            self.message
        )?;
        if let Some(help) = &self.help {
            write!(f, " (help: {help})")?;
        }
        Ok(())
    }
}

impl std::error::Error for ParseError {}

/// Joins words the way the messages read: "`a`", "`a` or `b`", "one of `a`, `b` or `c`".
pub fn join_alternatives(words: &[String]) -> String {
    match words {
        [] => "nothing".to_string(),
        [one] => one.clone(),
        [a, b] => format!("{a} or {b}"),
        [init @ .., last] => format!("one of {} or {last}", init.join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn every_kind() -> Vec<ParseErrorKind> {
        let s = String::new;
        vec![
            ParseErrorKind::InvalidToken { text: s() },
            ParseErrorKind::UnexpectedToken {
                found: s(),
                expected: vec![],
            },
            ParseErrorKind::UnexpectedEof { expected: vec![] },
            ParseErrorKind::ExtraToken { found: s() },
            ParseErrorKind::UnterminatedString,
            ParseErrorKind::BadNumber { text: s() },
            ParseErrorKind::UnknownUnit { unit: s() },
            ParseErrorKind::BadEscape { escape: s() },
            ParseErrorKind::SingleQuotedString,
            ParseErrorKind::Semicolon,
            ParseErrorKind::Walrus,
            ParseErrorKind::AssignInsteadOfEq,
            ParseErrorKind::ForeignKeyword { word: s() },
            ParseErrorKind::ForeignOperator {
                op: s(),
                replacement: s(),
            },
            ParseErrorKind::UnclosedDelimiter {
                open: Span::default(),
                delimiter: s(),
            },
            ParseErrorKind::HashComment,
            ParseErrorKind::StatementTooLong {
                tokens: 0,
                limit: 0,
            },
            ParseErrorKind::MissingLet { name: s() },
        ]
    }

    #[test]
    fn codes_are_unique_sequential_and_slugs_unique() {
        let kinds = every_kind();
        for (i, kind) in kinds.iter().enumerate() {
            assert_eq!(kind.code(), format!("E{:04}", i + 1), "{kind:?}");
        }
        let slugs: std::collections::BTreeSet<_> = kinds.iter().map(ParseErrorKind::slug).collect();
        assert_eq!(slugs.len(), kinds.len());
    }

    #[test]
    fn alternatives_read_naturally() {
        let w =
            |v: &[&str]| join_alternatives(&v.iter().map(|s| s.to_string()).collect::<Vec<_>>());
        assert_eq!(w(&["`)`"]), "`)`");
        assert_eq!(w(&["`,`", "`)`"]), "`,` or `)`");
        assert_eq!(w(&["a", "b", "c"]), "one of a, b or c");
    }
}
