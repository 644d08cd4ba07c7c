//! The parser facade: source text in, AST plus every error out. Nothing of LALRPOP leaks past
//! this module.
//!
//! Parsing never stops at the first error. Lex mistakes are repaired by the lexer, the grammar
//! recovers at statement and argument level, and delimiters still open at the end of the file are
//! closed here before parsing (each reported once), so that a missing final `}` does not throw
//! away the whole `route` block.

use crate::ast::{BinOp, Expr, ExprKind, Item, Program, Span, UnOp};
use crate::error::{ParseError, ParseErrorKind, join_alternatives};
use crate::lexer::{LexError, LexIssue, Spanned, Tok, tokenize};
use lalrpop_util::{ErrorRecovery, ParseError as LalrError, lalrpop_mod};
use std::collections::BTreeMap;

lalrpop_mod!(
    #[allow(clippy::all, clippy::pedantic, unused_parens, unused_imports, dead_code)]
    #[rustfmt::skip]
    route
);

/// The parser's user error type. The lexer never fails (it reports and repairs), so no value of
/// this type is ever built.
#[derive(Clone, Debug, PartialEq)]
pub enum NoError {}

/// The result of parsing one file: always a program (with `Error` nodes where the source made
/// no sense), every error, and the comments for the pretty-printer.
#[derive(Clone, Debug, PartialEq)]
pub struct Parsed {
    pub program: Program,
    pub errors: Vec<ParseError>,
    /// Every `// ...` comment, in source order, with trailing whitespace trimmed.
    pub comments: Vec<(Span, String)>,
}

impl Parsed {
    pub fn is_ok(&self) -> bool {
        self.errors.is_empty()
    }
}

/// Statements longer than this are refused (see [`ParseErrorKind::StatementTooLong`]). Real
/// statements have a few dozen tokens; the limit bounds the depth of any expression tree, so
/// that every recursive walk over the AST (printer, checker) stays within a thread's stack.
pub const MAX_STATEMENT_TOKENS: usize = 600;

/// Words from other languages that models write where a statement or expression starts.
const FOREIGN_KEYWORDS: &[&str] = &[
    "def", "fn", "func", "function", "lambda", "return", "var", "const", "val", "elif", "while",
    "then",
];

/// Parses a whole `.m2r` file.
pub fn parse(source: &str) -> Parsed {
    let whole = Span::new(0, source.len());
    let (program, errors, comments) = run(source, |recovered, tokens| {
        route::ProgramParser::new().parse(recovered, tokens.iter().cloned().map(Ok::<_, NoError>))
    });
    let mut program = program.unwrap_or(Program {
        items: vec![Item::Error(whole)],
        span: whole,
    });
    program.span = whole;
    Parsed {
        program,
        errors,
        comments,
    }
}

/// Parses a single expression (for tests and tools that work on one expression).
pub fn parse_expr(source: &str) -> Result<Expr, Vec<ParseError>> {
    let (expr, errors, _) = run(source, |recovered, tokens| {
        route::ExprParser::new().parse(recovered, tokens.iter().cloned().map(Ok::<_, NoError>))
    });
    match expr {
        Some(expr) if errors.is_empty() => Ok(expr),
        _ => Err(errors),
    }
}

/// At most this many syntax errors are reported per file (lex errors are all reported): past
/// the first few, more errors only bury the useful ones, and classifying each costs a pass over
/// the tokens.
pub const MAX_SYNTAX_ERRORS: usize = 50;

type Recovered<'s> = Vec<ErrorRecovery<usize, Tok<'s>, NoError>>;
type LalrErr<'s> = LalrError<usize, Tok<'s>, NoError>;

/// Lexes, closes delimiters left open at the end, runs `parser`, and turns every error into a
/// [`ParseError`]; `None` when the parser could not recover at all.
fn run<'s, T>(
    source: &'s str,
    parser: impl FnOnce(&mut Recovered<'s>, &[Spanned<'s>]) -> Result<T, LalrErr<'s>>,
) -> (Option<T>, Vec<ParseError>, Vec<(Span, String)>) {
    let lexed = tokenize(source);
    let mut errors: Vec<ParseError> = lexed
        .issues
        .iter()
        .map(|(span, issue)| lex_error(source, *span, issue))
        .collect();
    if let Some(err) = statement_too_long(&lexed.tokens) {
        errors.push(err);
        return (None, errors, lexed.comments);
    }
    let mut tokens = lexed.tokens;
    close_open_delimiters(&mut tokens, &mut errors);

    let mut recovered = Vec::new();
    let result = parser(&mut recovered, &tokens);
    let mut raw: Vec<LalrErr<'s>> = recovered.into_iter().map(|r| r.error).collect();
    let value = match result {
        Ok(v) => Some(v),
        Err(err) => {
            raw.push(err);
            None
        }
    };
    let raw = drop_cascades(&tokens, &errors, raw);
    let syntax: Vec<ParseError> = raw
        .into_iter()
        .take(MAX_SYNTAX_ERRORS)
        .filter_map(|e| convert(source, &tokens, e))
        .collect();

    // Inside an `if` written as a route statement, later errors echo that one.
    let if_statements: Vec<(usize, usize)> = syntax
        .iter()
        .filter(|e| e.help.as_deref() == Some(crate::conditional::HELP))
        .filter_map(|e| {
            let i = tokens.iter().position(|t| t.0 == e.span.start)?;
            Some((e.span.start, crate::conditional::statement_end(&tokens, i)?))
        })
        .collect();
    let syntax: Vec<ParseError> = syntax
        .into_iter()
        .filter(|e| {
            !if_statements
                .iter()
                .any(|&(s, end)| e.span.start > s && e.span.start < end)
        })
        .collect();
    // An opener the parser already reported as unclosed is not reported again at the end.
    errors.retain(|e| match &e.kind {
        ParseErrorKind::UnclosedDelimiter { open, .. } => !syntax.iter().any(
            |s| matches!(&s.kind, ParseErrorKind::UnclosedDelimiter { open: o, .. } if o == open),
        ),
        _ => true,
    });
    errors.extend(syntax);
    errors.sort_by_key(|e| e.span.start);
    errors.dedup_by(|later, earlier| later.span == earlier.span && later.kind == earlier.kind);
    (value, errors, lexed.comments)
}

fn error_location(err: &LalrErr<'_>) -> usize {
    match err {
        LalrError::UnrecognizedToken { token, .. } | LalrError::ExtraToken { token } => token.0,
        LalrError::UnrecognizedEof { location, .. } | LalrError::InvalidToken { location } => {
            *location
        }
        LalrError::User { error } => match *error {},
    }
}

/// Keeps only the first syntax error of each statement, and none after a lex error in the same
/// statement. Recovery resumes at the next token that can follow the broken node, often still
/// inside the broken statement (the `)` of an inner call), and what it reports there is an echo
/// of the first error rather than a second mistake; likewise `b @ c` without its `@`.
fn drop_cascades<'s>(
    tokens: &[Spanned<'s>],
    lex: &[ParseError],
    mut raw: Vec<LalrErr<'s>>,
) -> Vec<LalrErr<'s>> {
    raw.sort_by_key(error_location);
    let starts: Vec<usize> = tokens
        .iter()
        .filter(|t| is_statement_start(&t.1))
        .map(|t| t.0)
        .collect();
    // The statement a position belongs to: the number of statement keywords before it.
    let statement_of = |pos: usize| starts.partition_point(|&s| s < pos);
    let mut first_error: BTreeMap<usize, usize> = BTreeMap::new();
    for e in lex
        .iter()
        .filter(|e| !matches!(e.kind, ParseErrorKind::UnclosedDelimiter { .. }))
    {
        let slot = first_error
            .entry(statement_of(e.span.start))
            .or_insert(e.span.start);
        *slot = (*slot).min(e.span.start);
    }
    raw.retain(|e| {
        let at = error_location(e);
        let stmt = statement_of(at);
        match first_error.get(&stmt) {
            Some(&first) if first < at => false,
            _ => {
                first_error.insert(stmt, at);
                true
            }
        }
    });
    raw
}

/// Spans an error node from where the failed statement began to the last token thrown away.
pub(crate) fn recovery_span<T>(l: usize, r: usize, rec: &ErrorRecovery<usize, T, NoError>) -> Span {
    let (start, end) = match &rec.error {
        LalrError::UnrecognizedToken { token, .. } | LalrError::ExtraToken { token } => {
            (token.0, token.0)
        }
        LalrError::UnrecognizedEof { location, .. } | LalrError::InvalidToken { location } => {
            (*location, *location)
        }
        LalrError::User { .. } => (l, r),
    };
    let end = rec.dropped_tokens.last().map_or(end, |t| t.2);
    Span::new(l.min(start), r.max(end))
}

/// `[a, b, c]` is read as `a | b | c` (so `m2rc fmt` writes it that way); `[a]` is `a`.
pub(crate) fn set_literal(first: Expr, rest: Vec<Expr>, span: Span) -> Expr {
    if rest.is_empty() {
        return first;
    }
    let mut acc = first;
    for e in rest {
        let op_span = Span::new(acc.span.end, e.span.start);
        acc = binary(BinOp::Union, op_span, acc, e);
    }
    acc.span = span;
    acc
}

pub(crate) fn binary(op: BinOp, op_span: Span, lhs: Expr, rhs: Expr) -> Expr {
    let span = lhs.span.to(rhs.span);
    Expr {
        kind: ExprKind::Binary {
            op,
            op_span,
            lhs: Box::new(lhs),
            rhs: Box::new(rhs),
        },
        span,
    }
}

pub(crate) fn unary(op: UnOp, op_span: Span, operand: Expr, span: Span) -> Expr {
    Expr {
        kind: ExprKind::Unary {
            op,
            op_span,
            operand: Box::new(operand),
        },
        span,
    }
}

fn is_statement_start(tok: &Tok<'_>) -> bool {
    matches!(
        tok,
        Tok::Let | Tok::Route | Tok::Go | Tok::Pass | Tok::Avoid | Tok::Prefer | Tok::For
    )
}

fn statement_too_long(tokens: &[Spanned<'_>]) -> Option<ParseError> {
    let mut run_start = 0;
    for (i, tok) in tokens.iter().enumerate() {
        if is_statement_start(&tok.1) {
            run_start = i;
        }
        let len = i + 1 - run_start;
        if len > MAX_STATEMENT_TOKENS {
            let span = Span::new(tokens[run_start].0, tok.2);
            let kind = ParseErrorKind::StatementTooLong {
                tokens: len,
                limit: MAX_STATEMENT_TOKENS,
            };
            let message =
                format!("statement is too long (more than {MAX_STATEMENT_TOKENS} tokens)");
            return Some(
                ParseError::new(span, kind, message)
                    .with_help("split it with `let` bindings for the parts"),
            );
        }
    }
    None
}

fn closer_of(tok: &Tok<'_>) -> Option<Tok<'static>> {
    match tok {
        Tok::LParen => Some(Tok::RParen),
        Tok::LBrace => Some(Tok::RBrace),
        _ => None,
    }
}

/// The openers (index into `tokens`) still unclosed after the first `upto` tokens. A closer
/// that matches a deeper opener closes everything above it; a closer matching nothing is left
/// for the parser to report.
fn open_delimiters(tokens: &[Spanned<'_>], upto: usize) -> Vec<usize> {
    let mut stack: Vec<usize> = Vec::new();
    for (i, tok) in tokens.iter().enumerate().take(upto) {
        if is_statement_start(&tok.1) {
            // No statement fits inside parentheses: a `(` still open here was never closed, and
            // the parser reports it where the statement starts.
            while stack.last().is_some_and(|&o| tokens[o].1 == Tok::LParen) {
                stack.pop();
            }
        }
        if closer_of(&tok.1).is_some() {
            stack.push(i);
        } else if matches!(tok.1, Tok::RParen | Tok::RBrace)
            && let Some(pos) = stack
                .iter()
                .rposition(|&o| closer_of(&tokens[o].1).as_ref() == Some(&tok.1))
        {
            stack.truncate(pos);
        }
    }
    stack
}

fn close_open_delimiters(tokens: &mut Vec<Spanned<'_>>, errors: &mut Vec<ParseError>) {
    let open = open_delimiters(tokens, tokens.len());
    let Some(last) = tokens.last() else { return };
    let at = last.2;
    let mut closers = Vec::new();
    for &o in open.iter().rev() {
        let (start, opener, end) = tokens[o].clone();
        let Some(closer) = closer_of(&opener) else {
            continue;
        };
        let open_span = Span::new(start, end);
        let close = closer.name().trim_matches('`').to_string();
        let err = ParseError::new(
            Span::new(at, at),
            ParseErrorKind::UnclosedDelimiter {
                open: open_span,
                delimiter: close.clone(),
            },
            format!("missing `{close}` at the end of the file"),
        )
        .with_label(open_span, format!("this {} is never closed", opener.name()))
        .with_help(format!("insert `{close}`"))
        .with_fix(Span::new(at, at), close);
        errors.push(err);
        closers.push((at, closer, at));
    }
    tokens.extend(closers);
}

/// The human words for LALRPOP's expected terminals, with the expression-start and operator
/// groups collapsed to "an expression" / "an operator".
pub fn expected_words(expected: &[String]) -> Vec<String> {
    const EXPR_START: &[&str] = &[
        "identifier",
        "integer",
        "number",
        "distance",
        "string",
        "true",
        "false",
        "(",
        "-",
        "not",
        "if",
    ];
    const OPERATORS: &[&str] = &[
        "or", "and", "==", "!=", "<", "<=", ">", ">=", "|", "+", "-", "*",
    ];
    let names: Vec<&str> = expected.iter().map(|e| e.trim_matches('"')).collect();
    let has_all = |group: &[&str]| group.iter().all(|g| names.contains(g));
    let expr = has_all(EXPR_START);
    let ops = has_all(OPERATORS);
    let mut out: Vec<String> = Vec::new();
    let mut push = |w: String| {
        if !out.contains(&w) {
            out.push(w);
        }
    };
    for name in &names {
        if *name == "invalid literal" {
            continue;
        }
        if expr && (EXPR_START.contains(name) || *name == "[") {
            // A set literal `[a, b]` is one more way to start an expression.
            push("an expression".to_string());
        } else if ops && OPERATORS.contains(name) {
            push("an operator".to_string());
        } else {
            push(terminal_word(name));
        }
    }
    out
}

fn terminal_word(name: &str) -> String {
    match name {
        "identifier" => "an identifier".to_string(),
        "integer" => "an integer".to_string(),
        "number" => "a number".to_string(),
        "distance" => "a distance".to_string(),
        "string" => "a string".to_string(),
        other => format!("`{other}`"),
    }
}

/// How a found token reads in a message: keywords and punctuation quoted, names and literals
/// with their text.
fn describe_found(source: &str, tok: &Spanned<'_>) -> String {
    let text = source.get(tok.0..tok.2).unwrap_or("");
    let short: String = if text.chars().count() > 30 {
        format!("{}...", text.chars().take(27).collect::<String>())
    } else {
        text.to_string()
    };
    match &tok.1 {
        Tok::Ident(_) => format!("identifier `{short}`"),
        Tok::Int(_) | Tok::Number(_) | Tok::Distance(_) | Tok::Str(_) => format!("`{short}`"),
        other => other.name().to_string(),
    }
}

fn lex_error(source: &str, span: Span, issue: &LexIssue) -> ParseError {
    let text = source.get(span.start..span.end).unwrap_or("").to_string();
    match issue {
        LexIssue::Lex(LexError::InvalidChar) => ParseError::new(
            span,
            ParseErrorKind::InvalidToken { text: text.clone() },
            format!("unexpected character `{}`", text.escape_debug()),
        ),
        LexIssue::Lex(LexError::BadNumber) => ParseError::new(
            span,
            ParseErrorKind::BadNumber { text: text.clone() },
            format!("number `{text}` is too large"),
        ),
        LexIssue::Lex(LexError::UnknownUnit(unit)) => {
            let digits = text
                .strip_suffix(unit.as_str())
                .unwrap_or(&text)
                .to_string();
            let mut err = ParseError::new(
                span,
                ParseErrorKind::UnknownUnit { unit: unit.clone() },
                format!("unknown unit `{unit}` in `{text}`"),
            )
            .with_help("distances are written in metres or centimetres, like `1.5m` or `30cm`");
            if unit == "mm" {
                err = err.with_fix(span, format!("{}m", format_millimetres(&digits)));
            }
            err
        }
        LexIssue::Lex(LexError::UnterminatedString) => {
            let err = ParseError::new(
                span,
                ParseErrorKind::UnterminatedString,
                "unterminated string: no closing `\"` on this line",
            );
            match leading_bare_name(&text) {
                // No built-in takes a string argument, so `"bed)` is the category `bed` with a
                // stray quote, not a string missing its end.
                Some(name) => err
                    .with_help(format!(
                        "categories and names are written without quotes: `{name}`"
                    ))
                    .with_fix(Span::new(span.start, span.start + 1), ""),
                None => {
                    let end = span.start + text.trim_end().len();
                    err.with_fix(Span::new(end, end), "\"")
                }
            }
        }
        LexIssue::Lex(LexError::BadEscape(escape)) => ParseError::new(
            span,
            ParseErrorKind::BadEscape {
                escape: escape.clone(),
            },
            format!("unknown escape `{escape}` in a string"),
        )
        .with_help("the escapes are `\\\"`, `\\\\`, `\\n`, `\\t` and `\\r`"),
        LexIssue::Lex(LexError::SingleQuoted) => {
            let inner = text.trim_matches('\'');
            let mut err = ParseError::new(
                span,
                ParseErrorKind::SingleQuotedString,
                "single quotes are not .m2r syntax",
            );
            if is_plain_name(inner) {
                err = err
                    .with_help(format!("categories and names are written bare: `{inner}`"))
                    .with_fix(span, inner.to_string());
            } else {
                err = err
                    .with_help("strings use double quotes")
                    .with_fix(span, format!("\"{inner}\""));
            }
            err
        }
        LexIssue::Semicolon => ParseError::new(
            span,
            ParseErrorKind::Semicolon,
            "unexpected `;`: .m2r has no statement separators",
        )
        .with_help("remove the `;`; a new line starts a new statement")
        .with_fix(span, ""),
        LexIssue::Walrus => {
            ParseError::new(span, ParseErrorKind::Walrus, "`:=` is not .m2r syntax")
                .with_help("bind a value with `let name = value`")
        }
        LexIssue::ForeignOperator { op, replacement } => ParseError::new(
            span,
            ParseErrorKind::ForeignOperator {
                op: op.to_string(),
                replacement: replacement.to_string(),
            },
            format!("`{op}` is not .m2r syntax"),
        )
        .with_help(format!("write `{replacement}`"))
        .with_fix(span, *replacement),
        LexIssue::HashComment => ParseError::new(
            span,
            ParseErrorKind::HashComment,
            "comments start with `//`, not `#`",
        )
        .with_help("write `// ...`")
        .with_fix(Span::new(span.start, span.start + 1), "//"),
    }
}

fn format_millimetres(digits: &str) -> String {
    match digits.parse::<f64>() {
        Ok(mm) => crate::print::format_f64(mm / 1000.0),
        Err(_) => digits.to_string(),
    }
}

/// The name an unterminated string starts with when punctuation that ends an argument follows
/// it (`"bed).nearest()` -> `bed`); `None` for anything else, such as a formula `"F(a & b)`.
fn leading_bare_name(text: &str) -> Option<&str> {
    let body = text.strip_prefix('"')?;
    let run = body
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(body.len());
    let name = &body[..run];
    let ends_argument = body[run..].trim_start().starts_with([')', ',', '.', '}']);
    (!name.is_empty() && ends_argument && is_plain_name(name)).then_some(name)
}

fn is_plain_name(text: &str) -> bool {
    let mut chars = text.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !crate::lexer::is_keyword(text)
}

/// Turns one LALRPOP error into ours, classifying the common slips. `None` for errors that an
/// earlier lex error already explains.
fn convert(
    source: &str,
    tokens: &[Spanned<'_>],
    err: LalrError<usize, Tok<'_>, NoError>,
) -> Option<ParseError> {
    match err {
        LalrError::InvalidToken { location } => Some(ParseError::new(
            Span::new(location, location),
            ParseErrorKind::InvalidToken {
                text: String::new(),
            },
            "invalid token",
        )),
        LalrError::UnrecognizedEof { location, expected } => {
            let words = expected_words(&expected);
            let message = format!(
                "unexpected end of file: expected {}",
                join_alternatives(&words)
            );
            Some(ParseError::new(
                Span::new(location, location),
                ParseErrorKind::UnexpectedEof { expected: words },
                message,
            ))
        }
        LalrError::UnrecognizedToken { token, expected } => {
            if token.1 == Tok::BadLiteral {
                return None;
            }
            Some(classify_unexpected(source, tokens, token, &expected))
        }
        LalrError::ExtraToken { token } => {
            let found = describe_found(source, &token);
            let message = format!("unexpected {found} after the end of the program");
            Some(ParseError::new(
                Span::new(token.0, token.2),
                ParseErrorKind::ExtraToken { found },
                message,
            ))
        }
        LalrError::User { error } => match error {},
    }
}

fn classify_unexpected(
    source: &str,
    tokens: &[Spanned<'_>],
    token: Spanned<'_>,
    expected: &[String],
) -> ParseError {
    let span = Span::new(token.0, token.2);
    let words = expected_words(expected);
    let expects = |name: &str| expected.iter().any(|e| e.trim_matches('"') == name);
    let index = tokens.iter().position(|t| t.0 == token.0 && t.2 == token.2);
    let prev = index
        .and_then(|i| i.checked_sub(1))
        .and_then(|i| tokens.get(i));
    let next = index.and_then(|i| tokens.get(i + 1));
    let found = describe_found(source, &token);

    if token.1 == Tok::If
        && expects("go")
        && let Some(i) = index
    {
        return crate::conditional::if_statement(source, tokens, i, words);
    }
    if token.1 == Tok::Assign && expects("==") {
        return ParseError::new(
            span,
            ParseErrorKind::AssignInsteadOfEq,
            "found `=` where a comparison can stand",
        )
        .with_help("to compare, write `==`; to bind a name, start a statement with `let`")
        .with_fix(span, "==");
    }
    if let Some((ps, Tok::Ident("lambda"), pe)) = prev {
        let param = if let Tok::Ident(p) = token.1 { p } else { "x" };
        return ParseError::new(
            Span::new(*ps, *pe),
            ParseErrorKind::ForeignKeyword {
                word: "lambda".into(),
            },
            "`lambda` is not .m2r syntax",
        )
        .with_help(format!("write a lambda as `{param} => body`"));
    }
    if let Tok::Ident(word) = token.1 {
        if FOREIGN_KEYWORDS.contains(&word) {
            return ParseError::new(
                span,
                ParseErrorKind::ForeignKeyword {
                    word: word.to_string(),
                },
                format!("`{word}` is not .m2r syntax"),
            )
            .with_help(foreign_keyword_help(word));
        }
        if expects("let") && next.is_some_and(|n| n.1 == Tok::Assign) {
            return ParseError::new(
                span,
                ParseErrorKind::MissingLet {
                    name: word.to_string(),
                },
                format!("expected a statement, found `{word} =`"),
            )
            .with_help("bindings start with `let`")
            .with_fix(Span::new(token.0, token.0), "let ");
        }
    }
    let upto = index.unwrap_or(tokens.len());
    if let Some(&o) = open_delimiters(tokens, upto).last()
        && let Some(closer) = closer_of(&tokens[o].1)
        && expects(closer.name().trim_matches('`'))
        && (is_statement_start(&token.1) || (closer == Tok::RParen && token.1 == Tok::RBrace))
    {
        let close = closer.name().trim_matches('`').to_string();
        let open_span = Span::new(tokens[o].0, tokens[o].2);
        let at = prev.map_or(token.0, |p| p.2);
        let wanted: Vec<String> = words
            .iter()
            .filter(|w| *w == "`,`" || w.trim_matches('`') == close)
            .cloned()
            .collect();
        return ParseError::new(
            Span::new(at, at),
            ParseErrorKind::UnclosedDelimiter {
                open: open_span,
                delimiter: close.clone(),
            },
            format!("expected {}, found {found}", join_alternatives(&wanted)),
        )
        .with_label(
            open_span,
            format!("this {} is never closed", tokens[o].1.name()),
        )
        .with_label(span, "found here")
        .with_help(format!("insert `{close}`"))
        .with_fix(Span::new(at, at), close);
    }

    let mut err = ParseError::new(
        span,
        ParseErrorKind::UnexpectedToken {
            found: found.clone(),
            expected: words.clone(),
        },
        format!("expected {}, found {found}", join_alternatives(&words)),
    );
    match token.1 {
        Tok::Colon if expects("{") => {
            err = err.with_help("blocks are written with braces: `if c { a } else { b }`")
        }
        Tok::RBracket => {
            err = err.with_help("a set literal lists at least one place: `[kitchen, living_room]`")
        }
        Tok::LBracket => {
            err = err.with_help(
                "a set literal `[a, b]` stands where a value goes; sets also come from `objects(...)`, `rooms(...)` and `|`",
            )
        }
        Tok::Slash => {
            err = err.with_help("there is no division; write distances with units, like `50cm`")
        }
        _ => {}
    }
    err
}

fn foreign_keyword_help(word: &str) -> &'static str {
    match word {
        "def" | "fn" | "func" | "function" => {
            "there are no user-defined functions; bind values with `let name = value`"
        }
        "return" => "there is no `return`: the `route { ... }` block is the program's result",
        "var" | "const" | "val" => "bind values with `let name = value`",
        "elif" => "write `else if cond { ... } else { ... }`",
        "while" => {
            "there are no loops; `for x in set { ... }` makes one group of stages per element"
        }
        "then" => "write `if cond { a } else { b }`",
        _ => "write `x => body` for a lambda",
    }
}
