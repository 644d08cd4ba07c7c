//! `if cond { go a } else { go b }` written as a route statement (issue 35 item 2). A conditional
//! in `.m2r` is an expression that chooses a value, so the destination is chosen instead:
//! `go if cond { a } else { b }`. The parser reports the statement form and, when each branch is
//! exactly one `go` without a body, offers that rewrite; otherwise it shows the form to write.

use crate::ast::Span;
use crate::error::{ParseError, ParseErrorKind};
use crate::lexer::{Spanned, Tok};

pub(crate) const HELP: &str = "a conditional chooses a value, not statements: choose the \
destination with an `if` expression, `go if cond { a } else { b }`";

/// The error for an `if` at `index` where a route statement was expected.
pub(crate) fn if_statement(
    source: &str,
    tokens: &[Spanned<'_>],
    index: usize,
    expected: Vec<String>,
) -> ParseError {
    let (s, _, e) = tokens[index];
    let err = ParseError::new(
        Span::new(s, e),
        ParseErrorKind::UnexpectedToken {
            found: "`if`".into(),
            expected,
        },
        "`if` is not a route statement",
    )
    .with_help(HELP);
    match rewrite(source, tokens, index) {
        Some((span, text)) => err.with_fix(span, text),
        None => err,
    }
}

/// `if C { go A } else { go B }` → `go if C { A } else { B }`, when both branches are one `go`
/// without a stage body, name or further statement.
fn rewrite(source: &str, tokens: &[Spanned<'_>], index: usize) -> Option<(Span, String)> {
    let mut i = index + 1;
    let cond_start = tokens.get(i)?.0;
    let cond_end = span_until_open_brace(tokens, &mut i)?;
    let (a, next) = go_branch(source, tokens, i)?;
    if tokens.get(next)?.1 != Tok::Else || tokens.get(next + 1)?.1 != Tok::LBrace {
        return None;
    }
    let (b, end) = go_branch(source, tokens, next + 1)?;
    let last = tokens.get(end - 1)?.2;
    let cond = source.get(cond_start..cond_end)?.trim();
    Some((
        Span::new(tokens[index].0, last),
        format!("go if {cond} {{ {a} }} else {{ {b} }}"),
    ))
}

/// Advances `i` to the first `{` outside parentheses and brackets; the end of the text before it.
fn span_until_open_brace(tokens: &[Spanned<'_>], i: &mut usize) -> Option<usize> {
    let mut depth = 0i32;
    let mut end = None;
    while let Some(t) = tokens.get(*i) {
        match t.1 {
            Tok::LParen | Tok::LBracket => depth += 1,
            Tok::RParen | Tok::RBracket => depth -= 1,
            Tok::LBrace if depth == 0 => return end,
            Tok::LBrace | Tok::RBrace => return None,
            _ => {}
        }
        end = Some(t.2);
        *i += 1;
    }
    None
}

/// At `{` (index `i`): `{ go X }` with X holding no brace and no other statement keyword; X's text
/// and the index after the closing `}`.
fn go_branch<'s>(source: &'s str, tokens: &[Spanned<'_>], i: usize) -> Option<(&'s str, usize)> {
    if tokens.get(i)?.1 != Tok::LBrace || tokens.get(i + 1)?.1 != Tok::Go {
        return None;
    }
    let start = tokens.get(i + 2)?.0;
    let mut j = i + 2;
    let mut end = start;
    loop {
        let t = tokens.get(j)?;
        match t.1 {
            Tok::RBrace => break,
            Tok::LBrace | Tok::Go | Tok::As | Tok::Let | Tok::Pass | Tok::Avoid | Tok::Prefer => {
                return None;
            }
            _ => end = t.2,
        }
        j += 1;
    }
    (end > start).then(|| (source[start..end].trim(), j + 1))
}

/// Where an `if` statement starting at token `index` ends: after the block of its last `else`
/// (or of its `if` when there is none). Errors inside it echo the first one.
pub(crate) fn statement_end(tokens: &[Spanned<'_>], index: usize) -> Option<usize> {
    let mut i = index + 1;
    loop {
        span_until_open_brace(tokens, &mut i)?;
        let mut depth = 0i32;
        loop {
            match tokens.get(i)?.1 {
                Tok::LBrace => depth += 1,
                Tok::RBrace => {
                    depth -= 1;
                    if depth == 0 {
                        break;
                    }
                }
                _ => {}
            }
            i += 1;
        }
        let end = tokens[i].2;
        match tokens.get(i + 1).map(|t| &t.1) {
            Some(Tok::Else) if tokens.get(i + 2).is_some_and(|t| t.1 == Tok::If) => i += 3,
            Some(Tok::Else) => i += 1,
            _ => return Some(end),
        }
    }
}
