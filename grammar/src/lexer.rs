//! Tokens of `.m2r`, produced by a logos lexer, and the clean-up pass that turns the raw logos
//! stream into what the LALRPOP parser reads.
//!
//! The raw lexer recognises more than the language: `;`, `:=`, `&&`, `||`, `!`, `#` comments,
//! single-quoted strings and numbers with unknown units are the mistakes language models make
//! most, so they get their own tokens or errors and a precise message instead of "invalid
//! token". [`tokenize`] reports each such mistake once and then hands the parser the token the
//! author obviously meant (`and` for `&&`, `=` for `:=`, nothing for `;`, an invalid-literal
//! token for a broken number or string), so that one slip does not hide the rest of the file.
//!
//! Two contextual rules also live here rather than in the grammar, which keeps the grammar free
//! of keyword alternatives: after `.` every keyword is a method name (`.in(room)`), and a keyword
//! directly followed by `:` inside an argument list is an argument name (`near(x, within: 2m)`).

use crate::ast::{DistanceUnit, Span};
use logos::Logos;

/// Why a stretch of source is not a token. Carried out of logos callbacks, then turned into a
/// [`crate::ParseErrorKind`] by [`tokenize`].
#[derive(Clone, Debug, Default, PartialEq)]
pub enum LexError {
    /// A character that starts no token.
    #[default]
    InvalidChar,
    /// An integer literal that does not fit in 64 bits, or a number that is not finite.
    BadNumber,
    /// `3ft`, `5mm`, `1e5`: a number glued to a suffix that is not `m` or `cm`.
    UnknownUnit(String),
    /// A string literal with no closing `"` on its line.
    UnterminatedString,
    /// A backslash escape other than `\"`, `\\`, `\n`, `\t`, `\r`.
    BadEscape(String),
    /// `'chair'`: single quotes.
    SingleQuoted,
}

/// A distance literal: the value as written and its unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dist {
    pub value: f64,
    pub unit: DistanceUnit,
}

/// One token. Variants after `BadLiteral` never reach the parser as themselves (see the module
/// docs); they exist so that their mistakes can be named.
#[derive(Logos, Clone, Debug, PartialEq)]
#[logos(skip r"[ \t\r\n\f\u{FEFF}]+")]
#[logos(error = LexError)]
pub enum Tok<'s> {
    // **IMPORTANT** keep in sync with `KEYWORDS`.
    #[token("let")]
    Let,
    #[token("route")]
    Route,
    #[token("go")]
    Go,
    #[token("as")]
    As,
    #[token("pass")]
    Pass,
    #[token("avoid")]
    Avoid,
    #[token("prefer")]
    Prefer,
    #[token("within")]
    Within,
    #[token("during")]
    During,
    #[token("for")]
    For,
    #[token("in")]
    In,
    #[token("if")]
    If,
    #[token("else")]
    Else,
    #[token("and")]
    And,
    #[token("or")]
    Or,
    #[token("not")]
    Not,
    #[token("true")]
    True,
    #[token("false")]
    False,

    #[regex(r"[A-Za-z_][A-Za-z0-9_]*")]
    Ident(&'s str),
    #[regex(r"[0-9]+", lex_int)]
    Int(i64),
    #[regex(r"[0-9]+\.[0-9]+", lex_number)]
    Number(f64),
    #[regex(r"[0-9]+(\.[0-9]+)?[A-Za-z_][A-Za-z0-9_]*", lex_distance)]
    Distance(Dist),
    #[regex(r#""([^"\\\r\n]|\\[^\r\n])*""#, lex_string)]
    #[regex(r#""([^"\\\r\n]|\\[^\r\n])*"#, lex_unterminated)]
    Str(String),
    /// Stands for a literal that failed to lex (its error is already reported), so that the
    /// parser can go on as if a value were there.
    BadLiteral,

    #[token("(")]
    LParen,
    #[token(")")]
    RParen,
    #[token("{")]
    LBrace,
    #[token("}")]
    RBrace,
    #[token("[")]
    LBracket,
    #[token("]")]
    RBracket,
    #[token(",")]
    Comma,
    #[token(":")]
    Colon,
    #[token(".")]
    Dot,
    #[token("=")]
    Assign,
    #[token("=>")]
    FatArrow,
    #[token("==")]
    EqEq,
    #[token("!=")]
    NotEq,
    #[token("<")]
    Lt,
    #[token("<=")]
    Le,
    #[token(">")]
    Gt,
    #[token(">=")]
    Ge,
    #[token("|")]
    Pipe,
    #[token("+")]
    Plus,
    #[token("-")]
    Minus,
    #[token("*")]
    Star,
    #[token("/")]
    Slash,

    /// `// ...` to the end of the line (kept for the pretty-printer, never parsed).
    #[regex(r"//[^\r\n]*", allow_greedy = true)]
    Comment(&'s str),

    // Mistakes with a dedicated message; `tokenize` reports and replaces them.
    #[token(";")]
    Semicolon,
    #[token(":=")]
    Walrus,
    #[token("&&")]
    AmpAmp,
    #[token("||")]
    PipePipe,
    #[token("!")]
    Bang,
    #[regex(r"#[^\r\n]*", allow_greedy = true)]
    HashComment,
    #[regex(r"'([^'\\\r\n]|\\[^\r\n])*'?", lex_single_quoted)]
    SingleQuoted,
}

/// The reserved words, in the order of the design document.
pub const KEYWORDS: &[&str] = &[
    "let", "route", "go", "as", "pass", "avoid", "prefer", "within", "during", "for", "in", "if",
    "else", "and", "or", "not", "true", "false",
];

/// Whether `word` is reserved (the pretty-printer and the checker use this to refuse keywords
/// as binding names).
pub fn is_keyword(word: &str) -> bool {
    KEYWORDS.contains(&word)
}

fn lex_int<'s>(lex: &mut logos::Lexer<'s, Tok<'s>>) -> Result<i64, LexError> {
    lex.slice().parse().map_err(|_| LexError::BadNumber)
}

fn parse_finite(text: &str) -> Result<f64, LexError> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(LexError::BadNumber),
    }
}

fn lex_number<'s>(lex: &mut logos::Lexer<'s, Tok<'s>>) -> Result<f64, LexError> {
    parse_finite(lex.slice())
}

fn lex_distance<'s>(lex: &mut logos::Lexer<'s, Tok<'s>>) -> Result<Dist, LexError> {
    let text = lex.slice();
    let split = text
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(text.len());
    let (digits, suffix) = text.split_at(split);
    let unit = match suffix {
        "m" => DistanceUnit::M,
        "cm" => DistanceUnit::Cm,
        _ => return Err(LexError::UnknownUnit(suffix.to_string())),
    };
    Ok(Dist {
        value: parse_finite(digits)?,
        unit,
    })
}

fn lex_string<'s>(lex: &mut logos::Lexer<'s, Tok<'s>>) -> Result<String, LexError> {
    let text = lex.slice();
    let inner = &text[1..text.len() - 1];
    let mut out = String::with_capacity(inner.len());
    let mut chars = inner.chars();
    while let Some(c) = chars.next() {
        if c != '\\' {
            out.push(c);
            continue;
        }
        match chars.next() {
            Some('"') => out.push('"'),
            Some('\\') => out.push('\\'),
            Some('n') => out.push('\n'),
            Some('t') => out.push('\t'),
            Some('r') => out.push('\r'),
            Some(other) => return Err(LexError::BadEscape(format!("\\{other}"))),
            None => return Err(LexError::BadEscape("\\".to_string())),
        }
    }
    Ok(out)
}

fn lex_single_quoted<'s>(_lex: &mut logos::Lexer<'s, Tok<'s>>) -> Result<(), LexError> {
    Err(LexError::SingleQuoted)
}

fn lex_unterminated<'s>(_lex: &mut logos::Lexer<'s, Tok<'s>>) -> Result<String, LexError> {
    Err(LexError::UnterminatedString)
}

impl Tok<'_> {
    /// The token's name in "expected one of ..." messages: punctuation and keywords quoted,
    /// classes of tokens in words.
    pub fn name(&self) -> &'static str {
        match self {
            Tok::Let => "`let`",
            Tok::Route => "`route`",
            Tok::Go => "`go`",
            Tok::As => "`as`",
            Tok::Pass => "`pass`",
            Tok::Avoid => "`avoid`",
            Tok::Prefer => "`prefer`",
            Tok::Within => "`within`",
            Tok::During => "`during`",
            Tok::For => "`for`",
            Tok::In => "`in`",
            Tok::If => "`if`",
            Tok::Else => "`else`",
            Tok::And => "`and`",
            Tok::Or => "`or`",
            Tok::Not => "`not`",
            Tok::True => "`true`",
            Tok::False => "`false`",
            Tok::Ident(_) => "an identifier",
            Tok::Int(_) => "an integer",
            Tok::Number(_) => "a number",
            Tok::Distance(_) => "a distance",
            Tok::Str(_) => "a string",
            Tok::BadLiteral => "an invalid literal",
            Tok::LParen => "`(`",
            Tok::RParen => "`)`",
            Tok::LBrace => "`{`",
            Tok::RBrace => "`}`",
            Tok::LBracket => "`[`",
            Tok::RBracket => "`]`",
            Tok::Comma => "`,`",
            Tok::Colon => "`:`",
            Tok::Dot => "`.`",
            Tok::Assign => "`=`",
            Tok::FatArrow => "`=>`",
            Tok::EqEq => "`==`",
            Tok::NotEq => "`!=`",
            Tok::Lt => "`<`",
            Tok::Le => "`<=`",
            Tok::Gt => "`>`",
            Tok::Ge => "`>=`",
            Tok::Pipe => "`|`",
            Tok::Plus => "`+`",
            Tok::Minus => "`-`",
            Tok::Star => "`*`",
            Tok::Slash => "`/`",
            Tok::Comment(_) => "a comment",
            Tok::Semicolon => "`;`",
            Tok::Walrus => "`:=`",
            Tok::AmpAmp => "`&&`",
            Tok::PipePipe => "`||`",
            Tok::Bang => "`!`",
            Tok::HashComment => "a `#` comment",
            Tok::SingleQuoted => "a single-quoted string",
        }
    }

    fn is_keyword_token(&self) -> bool {
        matches!(
            self,
            Tok::Let
                | Tok::Route
                | Tok::Go
                | Tok::As
                | Tok::Pass
                | Tok::Avoid
                | Tok::Prefer
                | Tok::Within
                | Tok::During
                | Tok::For
                | Tok::In
                | Tok::If
                | Tok::Else
                | Tok::And
                | Tok::Or
                | Tok::Not
                | Tok::True
                | Tok::False
        )
    }
}

/// A token with its byte range, as LALRPOP wants it.
pub type Spanned<'s> = (usize, Tok<'s>, usize);

/// A lexing mistake, located. [`crate::parse()`] turns these into `ParseError`s.
#[derive(Clone, Debug, PartialEq)]
pub enum LexIssue {
    Lex(LexError),
    Semicolon,
    Walrus,
    /// `&&`, `||` or `!`, with the keyword that replaces it.
    ForeignOperator {
        op: &'static str,
        replacement: &'static str,
    },
    HashComment,
}

/// Everything the lexer found in one source: parser tokens, comments, and mistakes.
#[derive(Clone, Debug, Default)]
pub struct Lexed<'s> {
    pub tokens: Vec<Spanned<'s>>,
    pub comments: Vec<(Span, String)>,
    pub issues: Vec<(Span, LexIssue)>,
}

/// Lexes `source` completely. Never fails: every mistake is recorded in `issues` and replaced
/// as described in the module docs.
pub fn tokenize(source: &str) -> Lexed<'_> {
    let mut out = Lexed::default();
    let mut lexer = Tok::lexer(source);
    while let Some(result) = lexer.next() {
        let range = lexer.span();
        let span = Span::new(range.start, range.end);
        let tok = match result {
            Ok(tok) => tok,
            Err(err) => {
                let literal = !matches!(err, LexError::InvalidChar);
                out.issues.push((span, LexIssue::Lex(err)));
                if literal {
                    out.tokens.push((span.start, Tok::BadLiteral, span.end));
                }
                continue;
            }
        };
        let replacement = match tok {
            Tok::Comment(text) => {
                out.comments.push((span, text.trim_end().to_string()));
                continue;
            }
            Tok::HashComment => {
                out.issues.push((span, LexIssue::HashComment));
                continue;
            }
            Tok::Semicolon => {
                out.issues.push((span, LexIssue::Semicolon));
                continue;
            }
            Tok::Walrus => {
                out.issues.push((span, LexIssue::Walrus));
                Tok::Assign
            }
            Tok::AmpAmp => {
                out.issues.push((
                    span,
                    LexIssue::ForeignOperator {
                        op: "&&",
                        replacement: "and",
                    },
                ));
                Tok::And
            }
            Tok::PipePipe => {
                out.issues.push((
                    span,
                    LexIssue::ForeignOperator {
                        op: "||",
                        replacement: "or",
                    },
                ));
                Tok::Or
            }
            Tok::Bang => {
                out.issues.push((
                    span,
                    LexIssue::ForeignOperator {
                        op: "!",
                        replacement: "not",
                    },
                ));
                Tok::Not
            }
            other => other,
        };
        out.tokens.push((span.start, replacement, span.end));
    }
    apply_contextual_names(source, &mut out.tokens);
    out
}

/// Turns keywords into identifiers where only a name can stand: after `.` (method names) and
/// before `:` directly after `(` or `,` (argument names).
fn apply_contextual_names<'s>(source: &'s str, tokens: &mut [Spanned<'s>]) {
    for i in 0..tokens.len() {
        if !tokens[i].1.is_keyword_token() {
            continue;
        }
        let after_dot = i > 0 && tokens[i - 1].1 == Tok::Dot;
        let arg_name = i > 0
            && matches!(tokens[i - 1].1, Tok::LParen | Tok::Comma)
            && tokens.get(i + 1).is_some_and(|t| t.1 == Tok::Colon);
        if after_dot || arg_name {
            let (start, _, end) = tokens[i];
            tokens[i].1 = Tok::Ident(&source[start..end]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(src: &str) -> Vec<Tok<'_>> {
        tokenize(src).tokens.into_iter().map(|t| t.1).collect()
    }

    /// One sample of every variant; the exhaustive match makes adding a variant without a sample
    /// a compile error.
    fn samples() -> Vec<Tok<'static>> {
        let all = vec![
            Tok::Let,
            Tok::Route,
            Tok::Go,
            Tok::As,
            Tok::Pass,
            Tok::Avoid,
            Tok::Prefer,
            Tok::Within,
            Tok::During,
            Tok::For,
            Tok::In,
            Tok::If,
            Tok::Else,
            Tok::And,
            Tok::Or,
            Tok::Not,
            Tok::True,
            Tok::False,
            Tok::Ident("x"),
            Tok::Int(1),
            Tok::Number(1.5),
            Tok::Distance(Dist {
                value: 1.0,
                unit: DistanceUnit::M,
            }),
            Tok::Str(String::new()),
            Tok::BadLiteral,
            Tok::LParen,
            Tok::RParen,
            Tok::LBrace,
            Tok::RBrace,
            Tok::LBracket,
            Tok::RBracket,
            Tok::Comma,
            Tok::Colon,
            Tok::Dot,
            Tok::Assign,
            Tok::FatArrow,
            Tok::EqEq,
            Tok::NotEq,
            Tok::Lt,
            Tok::Le,
            Tok::Gt,
            Tok::Ge,
            Tok::Pipe,
            Tok::Plus,
            Tok::Minus,
            Tok::Star,
            Tok::Slash,
            Tok::Comment("//"),
            Tok::Semicolon,
            Tok::Walrus,
            Tok::AmpAmp,
            Tok::PipePipe,
            Tok::Bang,
            Tok::HashComment,
            Tok::SingleQuoted,
        ];
        for t in &all {
            match t {
                Tok::Let
                | Tok::Route
                | Tok::Go
                | Tok::As
                | Tok::Pass
                | Tok::Avoid
                | Tok::Prefer
                | Tok::Within
                | Tok::During
                | Tok::For
                | Tok::In
                | Tok::If
                | Tok::Else
                | Tok::And
                | Tok::Or
                | Tok::Not
                | Tok::True
                | Tok::False
                | Tok::Ident(_)
                | Tok::Int(_)
                | Tok::Number(_)
                | Tok::Distance(_)
                | Tok::Str(_)
                | Tok::BadLiteral
                | Tok::LParen
                | Tok::RParen
                | Tok::LBrace
                | Tok::RBrace
                | Tok::LBracket
                | Tok::RBracket
                | Tok::Comma
                | Tok::Colon
                | Tok::Dot
                | Tok::Assign
                | Tok::FatArrow
                | Tok::EqEq
                | Tok::NotEq
                | Tok::Lt
                | Tok::Le
                | Tok::Gt
                | Tok::Ge
                | Tok::Pipe
                | Tok::Plus
                | Tok::Minus
                | Tok::Star
                | Tok::Slash
                | Tok::Comment(_)
                | Tok::Semicolon
                | Tok::Walrus
                | Tok::AmpAmp
                | Tok::PipePipe
                | Tok::Bang
                | Tok::HashComment
                | Tok::SingleQuoted => {}
            }
        }
        all
    }

    #[test]
    fn every_token_has_a_unique_nonempty_name() {
        let names: Vec<&str> = samples().iter().map(Tok::name).collect();
        let mut seen = std::collections::BTreeSet::new();
        for n in &names {
            assert!(!n.trim().is_empty());
            assert!(seen.insert(*n), "duplicate token name {n}");
        }
    }

    #[test]
    fn keywords_lex_as_keywords_and_match_the_list() {
        for kw in KEYWORDS {
            let toks = kinds(kw);
            assert_eq!(toks.len(), 1);
            assert!(toks[0].is_keyword_token(), "{kw}");
            assert_eq!(toks[0].name(), format!("`{kw}`"));
        }
        assert_eq!(kinds("letter"), vec![Tok::Ident("letter")]);
    }

    #[test]
    fn numbers_and_distances() {
        assert_eq!(
            kinds("2 0.5 1.5m 30cm"),
            vec![
                Tok::Int(2),
                Tok::Number(0.5),
                Tok::Distance(Dist {
                    value: 1.5,
                    unit: DistanceUnit::M
                }),
                Tok::Distance(Dist {
                    value: 30.0,
                    unit: DistanceUnit::Cm
                }),
            ]
        );
        assert_eq!(
            kinds("2.count"),
            vec![Tok::Int(2), Tok::Dot, Tok::Ident("count")]
        );
        let lexed = tokenize("3ft 99999999999999999999");
        assert_eq!(lexed.tokens.len(), 2);
        assert_eq!(
            lexed.issues[0].1,
            LexIssue::Lex(LexError::UnknownUnit("ft".into()))
        );
        assert_eq!(lexed.issues[1].1, LexIssue::Lex(LexError::BadNumber));
    }

    #[test]
    fn strings_with_escapes() {
        assert_eq!(kinds(r#""a\"b\\c\n""#), vec![Tok::Str("a\"b\\c\n".into())]);
        let lexed = tokenize("\"abc\nx");
        assert_eq!(
            lexed.issues[0],
            (Span::new(0, 4), LexIssue::Lex(LexError::UnterminatedString))
        );
        assert_eq!(lexed.tokens[1].1, Tok::Ident("x"));
        let lexed = tokenize(r#""a\qb""#);
        assert_eq!(
            lexed.issues[0].1,
            LexIssue::Lex(LexError::BadEscape("\\q".into()))
        );
    }

    #[test]
    fn comments_are_recorded_not_parsed() {
        let lexed = tokenize("let x = 1 // one  \n// two\n");
        assert_eq!(lexed.tokens.len(), 4);
        assert_eq!(
            lexed.comments,
            vec![
                (Span::new(10, 18), "// one".to_string()),
                (Span::new(19, 25), "// two".to_string())
            ]
        );
    }

    #[test]
    fn keywords_after_dot_and_before_colon_are_names() {
        assert_eq!(
            kinds("x.in(r, within: 2m)"),
            vec![
                Tok::Ident("x"),
                Tok::Dot,
                Tok::Ident("in"),
                Tok::LParen,
                Tok::Ident("r"),
                Tok::Comma,
                Tok::Ident("within"),
                Tok::Colon,
                Tok::Distance(Dist {
                    value: 2.0,
                    unit: DistanceUnit::M
                }),
                Tok::RParen,
            ]
        );
        assert_eq!(kinds("a within b")[1], Tok::Within);
    }

    #[test]
    fn llm_mistakes_are_reported_and_replaced() {
        let lexed = tokenize("a && b || !c; x := 'y' # py");
        let toks: Vec<_> = lexed.tokens.iter().map(|t| t.1.clone()).collect();
        assert_eq!(
            toks,
            vec![
                Tok::Ident("a"),
                Tok::And,
                Tok::Ident("b"),
                Tok::Or,
                Tok::Not,
                Tok::Ident("c"),
                Tok::Ident("x"),
                Tok::Assign,
                Tok::BadLiteral,
            ]
        );
        assert_eq!(lexed.issues.len(), 7);
    }

    #[test]
    fn invalid_characters_are_dropped_with_an_issue() {
        let lexed = tokenize("a @ é b");
        assert_eq!(lexed.tokens.len(), 2);
        assert_eq!(lexed.issues.len(), 2);
        assert_eq!(lexed.issues[1].0, Span::new(4, 6));
    }
}
