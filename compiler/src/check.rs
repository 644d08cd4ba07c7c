//! The checker's entry point: parse, resolve names, type-check and scope-check a program, and
//! hand later phases a side table of what every expression means.
//!
//! The grounding evaluator walks the AST and looks things up by span: `types[&expr.span]`,
//! `resolutions[&ident.span]` (for `Name` expressions the ident span is the expression span; for
//! calls the key is the function or method identifier's span), `calls[&expr.span]` (which row of
//! the built-in table a call uses and which argument fills each parameter), and `stages`.

use crate::diagnostic::{self, Diagnostic};
use crate::resolve::{BindingInfo, BindingKind, Frame, FrameKind};
use m2rc_grammar::ast::{Program, Span};
use m2rc_stdlib::builtins::{Builtin, Direction, Elem, Metric, Type};
use m2rc_stdlib::vocab::{CategoryKind, Vocabulary};
use std::collections::HashMap;

/// What a name or call identifier refers to.
#[derive(Clone, Debug, PartialEq)]
pub enum Resolution {
    /// A `let`, lambda parameter or `for` variable, identified by the span of its declaring
    /// identifier.
    Binding {
        def: Span,
        kind: BindingKind,
    },
    /// A category, canonical (a synonym such as `tv` is resolved to `television`).
    Category {
        name: String,
        kind: CategoryKind,
    },
    Direction(Direction),
    Metric(Metric),
    /// `start` or `here`.
    Constant(&'static str),
    /// A built-in function or method, with the receiver's element type bound to `T`.
    Builtin {
        builtin: &'static Builtin,
        t: Elem,
    },
    /// A stage name in `during` or `go ... as`: index into [`CheckResult::stages`].
    Stage(usize),
}

/// How a call's arguments fill the built-in's parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct CallInfo {
    pub builtin: &'static Builtin,
    /// The receiver's element type (`Elem::Place` for free functions).
    pub t: Elem,
    /// For each parameter of `builtin.params`, the index into the call's `args` that fills it,
    /// or `None` when it is left to its default (or omitted, if optional).
    pub args: Vec<Option<usize>>,
}

/// A `go` stage in route order (stages inside a `for` body are listed once each).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StageInfo {
    pub name: Option<String>,
    pub name_span: Option<Span>,
    pub span: Span,
    pub target: Span,
    /// Whether the stage sits in a `for` body (and so runs once per element).
    pub in_for: bool,
}

/// Everything later phases need from checking.
#[derive(Clone, Debug)]
pub struct CheckResult {
    pub program: Program,
    /// Parse and check diagnostics, sorted by position then code.
    pub diagnostics: Vec<Diagnostic>,
    /// The type of every expression, by expression span.
    pub types: HashMap<Span, Type>,
    pub resolutions: HashMap<Span, Resolution>,
    pub calls: HashMap<Span, CallInfo>,
    pub stages: Vec<StageInfo>,
    pub comments: Vec<(Span, String)>,
}

impl CheckResult {
    pub fn has_errors(&self) -> bool {
        self.diagnostics.iter().any(Diagnostic::is_error)
    }

    pub fn errors(&self) -> impl Iterator<Item = &Diagnostic> {
        self.diagnostics.iter().filter(|d| d.is_error())
    }
}

/// Parses and checks a program. Never panics, whatever the source.
pub fn check(source: &str, vocab: &Vocabulary) -> CheckResult {
    let parsed = m2rc_grammar::parse(source);
    let mut diagnostics: Vec<Diagnostic> =
        parsed.errors.iter().map(Diagnostic::from_parse).collect();
    crate::hints::two_word_categories(&mut diagnostics, source, vocab);
    let analysis = check_program(&parsed.program, source, vocab, !parsed.errors.is_empty());
    let mut found = analysis.diagnostics;
    if !parsed.errors.is_empty() {
        crate::hints::suppress_follow_ons(&mut found, &crate::hints::broken_spans(&parsed.program));
    }
    diagnostics.extend(found);
    diagnostic::sort(&mut diagnostics);
    diagnostics.dedup();
    CheckResult {
        program: parsed.program,
        diagnostics,
        types: analysis.types,
        resolutions: analysis.resolutions,
        calls: analysis.calls,
        stages: analysis.stages,
        comments: parsed.comments,
    }
}

/// The checker's findings about an already parsed program.
#[derive(Clone, Debug, Default)]
pub struct Analysis {
    pub diagnostics: Vec<Diagnostic>,
    pub types: HashMap<Span, Type>,
    pub resolutions: HashMap<Span, Resolution>,
    pub calls: HashMap<Span, CallInfo>,
    pub stages: Vec<StageInfo>,
}

/// Checks a parsed program (hand-built ASTs in tests, or after `m2rc_grammar::parse`).
/// `had_parse_errors` silences structural errors (missing route, empty route) that a parse error
/// probably caused.
pub fn check_program(
    program: &Program,
    source: &str,
    vocab: &Vocabulary,
    had_parse_errors: bool,
) -> Analysis {
    let mut c = Checker::new(source, vocab, had_parse_errors);
    c.program(program);
    let mut diagnostics = c.diags;
    diagnostic::sort(&mut diagnostics);
    Analysis {
        diagnostics,
        types: c.types,
        resolutions: c.resolutions,
        calls: c.calls,
        stages: c.stages,
    }
}

/// Where in the route the checker is, for the rules that depend on it.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Ctx {
    /// Inside a stage body.
    pub in_stage: bool,
    /// Checking a constraint outside every stage (where `here` means nothing).
    pub route_wide: bool,
}

pub(crate) struct Checker<'a> {
    pub src: &'a str,
    pub vocab: &'a Vocabulary,
    pub had_parse_errors: bool,
    pub diags: Vec<Diagnostic>,
    pub types: HashMap<Span, Type>,
    pub resolutions: HashMap<Span, Resolution>,
    pub calls: HashMap<Span, CallInfo>,
    pub stages: Vec<StageInfo>,
    pub scopes: Vec<Frame>,
    pub retired: Vec<(BindingInfo, FrameKind)>,
    pub ctx: Ctx,
    /// Set while checking the arguments of a call that could not be resolved.
    pub lenient: bool,
}

impl<'a> Checker<'a> {
    fn new(src: &'a str, vocab: &'a Vocabulary, had_parse_errors: bool) -> Self {
        Checker {
            src,
            vocab,
            had_parse_errors,
            diags: Vec::new(),
            types: HashMap::new(),
            resolutions: HashMap::new(),
            calls: HashMap::new(),
            stages: Vec::new(),
            scopes: Vec::new(),
            retired: Vec::new(),
            ctx: Ctx::default(),
            lenient: false,
        }
    }

    /// The source text of a span (empty when the span does not fit the source).
    pub(crate) fn text(&self, span: Span) -> &'a str {
        self.src.get(span.start..span.end).unwrap_or("")
    }

    pub(crate) fn report(&mut self, d: Diagnostic) {
        self.diags.push(d);
    }
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod tests_v2;
