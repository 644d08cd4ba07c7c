//! The LTLf text syntax: a small hand-written lexer and precedence-climbing parser, shared by
//! `m2rc compile --emit ltl` (which prints it), the automaton guards (which use its propositional
//! part) and the `ltl "..."` route form of `.m2r` (whose string it parses).
//!
//! Precedence, loosest first: `->` / `<->` (right associative), `|`, `&`, `U` / `R` / `W` (right
//! associative), then the prefix operators `! X WX F G`. This is the order Spot and LTLf2DFA use,
//! so `a & b U c` is `a & (b U c)`. Synonyms: `<>` `◇` for `F`, `[]` `□` for `G`, `◯` `○` for `X`,
//! `~` `¬` for `!`, `&&` `∧` for `&`, `||` `∨` for `|`, `=>` `→` for `->`, `<=>` `↔` for `<->`,
//! `⊤` `⊥` for `true` `false`.

use m2rc_grammar::ast::Span;
use std::fmt::Write as _;

/// A formula of the surface syntax; atoms are names (resolved against the program's places by
/// `check.rs`, or against an automaton's atom list).
#[derive(Clone, Debug, PartialEq)]
pub struct Formula {
    pub kind: Kind,
    /// Byte range in the formula text (offset by the caller for formulas inside `.m2r`).
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Kind {
    True,
    False,
    Atom(String),
    Not(Box<Formula>),
    And(Box<Formula>, Box<Formula>),
    Or(Box<Formula>, Box<Formula>),
    Implies(Box<Formula>, Box<Formula>),
    Iff(Box<Formula>, Box<Formula>),
    /// Strong next: there is a next position and the operand holds there.
    Next(Box<Formula>),
    /// Weak next: the current position is the last one, or the operand holds at the next.
    WeakNext(Box<Formula>),
    Eventually(Box<Formula>),
    Always(Box<Formula>),
    Until(Box<Formula>, Box<Formula>),
    Release(Box<Formula>, Box<Formula>),
    /// Weak until: `a W b` = `(a U b) | G a`.
    WeakUntil(Box<Formula>, Box<Formula>),
}

/// A syntax error in a formula, before it becomes a [`crate::diagnostic::Diagnostic`].
#[derive(Clone, Debug, PartialEq)]
pub struct SyntaxError {
    pub kind: SyntaxErrorKind,
    pub message: String,
    pub span: Span,
    pub help: Option<String>,
    /// A replacement for `span`, when one is certain.
    pub fix: Option<String>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SyntaxErrorKind {
    /// A token that is not part of the syntax at all, or an operator we do not support.
    Unsupported,
    /// `(` without `)` or the reverse.
    Unbalanced,
    /// Anything else: a missing operand, two operands in a row.
    Syntax,
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Ident(String),
    True,
    False,
    LParen,
    RParen,
    Not,
    And,
    Or,
    Implies,
    Iff,
    Next,
    WeakNext,
    Eventually,
    Always,
    Until,
    Release,
    WeakUntil,
}

impl Tok {
    fn describe(&self) -> String {
        match self {
            Tok::Ident(s) => format!("atom `{s}`"),
            Tok::True => "`true`".into(),
            Tok::False => "`false`".into(),
            Tok::LParen => "`(`".into(),
            Tok::RParen => "`)`".into(),
            Tok::Not => "`!`".into(),
            Tok::And => "`&`".into(),
            Tok::Or => "`|`".into(),
            Tok::Implies => "`->`".into(),
            Tok::Iff => "`<->`".into(),
            Tok::Next => "`X`".into(),
            Tok::WeakNext => "`WX`".into(),
            Tok::Eventually => "`F`".into(),
            Tok::Always => "`G`".into(),
            Tok::Until => "`U`".into(),
            Tok::Release => "`R`".into(),
            Tok::WeakUntil => "`W`".into(),
        }
    }
}

/// Past-time and other operators users bring from other tools, with what to write instead.
fn unsupported_word(w: &str) -> Option<&'static str> {
    Some(match w {
        "Y" | "S" | "O" | "H" | "Z" => {
            "past-time operators (Y, S, O, H) are not supported: state the route forward in time"
        }
        "M" => "strong release `M` is not supported: write `b U (a & b)` for `a M b`",
        _ => return None,
    })
}

fn lex(text: &str) -> Result<Vec<(Tok, Span)>, SyntaxError> {
    let mut out = Vec::new();
    let b = text.as_bytes();
    let mut i = 0;
    while i < text.len() {
        let rest = &text[i..];
        let ch = rest.chars().next().unwrap_or(' ');
        if ch.is_whitespace() {
            i += ch.len_utf8();
            continue;
        }
        let two = rest.get(..2).unwrap_or("");
        let three = rest.get(..3).unwrap_or("");
        let (tok, len) = if three == "<->" || three == "<=>" {
            (Tok::Iff, 3)
        } else if two == "->" || two == "=>" {
            (Tok::Implies, 2)
        } else if two == "&&" || two == "/\\" {
            (Tok::And, 2)
        } else if two == "||" || two == "\\/" {
            (Tok::Or, 2)
        } else if two == "<>" {
            (Tok::Eventually, 2)
        } else if two == "[]" {
            (Tok::Always, 2)
        } else {
            match ch {
                '(' => (Tok::LParen, 1),
                ')' => (Tok::RParen, 1),
                '!' | '~' | '¬' => (Tok::Not, ch.len_utf8()),
                '&' | '∧' => (Tok::And, ch.len_utf8()),
                '|' | '∨' => (Tok::Or, ch.len_utf8()),
                '→' | '⇒' => (Tok::Implies, ch.len_utf8()),
                '↔' | '⇔' => (Tok::Iff, ch.len_utf8()),
                '◇' | '◊' => (Tok::Eventually, ch.len_utf8()),
                '□' | '◻' => (Tok::Always, ch.len_utf8()),
                '◯' | '○' => (Tok::Next, ch.len_utf8()),
                '⊤' => (Tok::True, ch.len_utf8()),
                '⊥' => (Tok::False, ch.len_utf8()),
                c if c.is_ascii_alphabetic() || c == '_' => {
                    let len = b[i..]
                        .iter()
                        .take_while(|c| c.is_ascii_alphanumeric() || **c == b'_')
                        .count();
                    let word = &text[i..i + len];
                    let tok = match word {
                        "true" | "TRUE" | "tt" => Tok::True,
                        "false" | "FALSE" | "ff" => Tok::False,
                        "X" => Tok::Next,
                        "WX" | "N" => Tok::WeakNext,
                        "F" => Tok::Eventually,
                        "G" => Tok::Always,
                        "U" => Tok::Until,
                        "R" | "V" => Tok::Release,
                        "W" => Tok::WeakUntil,
                        w => {
                            if let Some(help) = unsupported_word(w) {
                                return Err(SyntaxError {
                                    kind: SyntaxErrorKind::Unsupported,
                                    message: format!("unsupported operator `{w}`"),
                                    span: Span::new(i, i + len),
                                    help: Some(help.into()),
                                    fix: None,
                                });
                            }
                            Tok::Ident(w.to_string())
                        }
                    };
                    (tok, len)
                }
                c => {
                    let (help, fix) = match c {
                        '^' => (Some("conjunction is `&`"), Some("&")),
                        '+' => (Some("disjunction is `|`"), Some("|")),
                        '=' => (Some("implication is `->`"), Some("->")),
                        _ => (None, None),
                    };
                    return Err(SyntaxError {
                        kind: SyntaxErrorKind::Unsupported,
                        message: format!("unsupported character `{c}` in a formula"),
                        span: Span::new(i, i + c.len_utf8()),
                        help: Some(help.map(str::to_string).unwrap_or_else(|| {
                            "operators are F G X WX U R W ! & | -> <-> (or <> [] ~ && ||)".into()
                        })),
                        fix: fix.map(str::to_string),
                    });
                }
            }
        };
        out.push((tok, Span::new(i, i + len)));
        i += len;
    }
    Ok(out)
}

struct Parser {
    toks: Vec<(Tok, Span)>,
    pos: usize,
    end: usize,
    /// Spans of the `(` still open, innermost last.
    open: Vec<Span>,
    /// How many `implication` / `until` / `unary` calls are active: the parser and everything
    /// after it recurse over the formula, so nesting is bounded (`MAX_NESTING`).
    depth: usize,
}

/// Deepest nesting of operators and parentheses a formula may have. Route formulas nest a few
/// levels; this keeps parsing, the automaton construction and dropping the tree inside a
/// thread's stack for any input.
pub const MAX_NESTING: usize = 200;

/// Parses `text` as a formula. Spans are byte offsets into `text`.
pub fn parse(text: &str) -> Result<Formula, SyntaxError> {
    let toks = lex(text)?;
    let mut p = Parser {
        toks,
        pos: 0,
        end: text.len(),
        open: Vec::new(),
        depth: 0,
    };
    if p.toks.is_empty() {
        return Err(p.error(
            SyntaxErrorKind::Syntax,
            "the formula is empty".into(),
            Span::new(0, text.len()),
            Some("write e.g. `F(kitchen & F(bed)) & G !bathroom`"),
        ));
    }
    let f = p.implication()?;
    if let Some((t, span)) = p.toks.get(p.pos).cloned() {
        if t == Tok::RParen {
            return Err(p.error(
                SyntaxErrorKind::Unbalanced,
                "unbalanced parentheses: this `)` closes nothing".into(),
                span,
                Some("remove it, or add the `(` it should close"),
            ));
        }
        return Err(p.error(
            SyntaxErrorKind::Syntax,
            format!("expected an operator, found {}", t.describe()),
            span,
            Some("join the two parts with `&`, `|`, `->` or `U`"),
        ));
    }
    Ok(f)
}

impl Parser {
    fn error(
        &self,
        kind: SyntaxErrorKind,
        message: String,
        span: Span,
        help: Option<&str>,
    ) -> SyntaxError {
        SyntaxError {
            kind,
            message,
            span,
            help: help.map(str::to_string),
            fix: None,
        }
    }

    fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.pos).map(|t| &t.0)
    }

    fn bump(&mut self) -> Option<(Tok, Span)> {
        let t = self.toks.get(self.pos).cloned();
        self.pos += 1;
        t
    }

    fn implication(&mut self) -> Result<Formula, SyntaxError> {
        self.nested(Self::implication_inner)
    }

    fn implication_inner(&mut self) -> Result<Formula, SyntaxError> {
        let lhs = self.or()?;
        match self.peek() {
            Some(Tok::Implies) | Some(Tok::Iff) => {
                let (t, _) = self.bump().unwrap_or((Tok::Implies, Span::default()));
                let rhs = self.implication()?;
                let span = Span::new(lhs.span.start, rhs.span.end);
                let kind = if t == Tok::Implies {
                    Kind::Implies(Box::new(lhs), Box::new(rhs))
                } else {
                    Kind::Iff(Box::new(lhs), Box::new(rhs))
                };
                Ok(Formula { kind, span })
            }
            _ => Ok(lhs),
        }
    }

    /// Runs one level of the descent, refusing past [`MAX_NESTING`].
    fn nested(
        &mut self,
        level: fn(&mut Self) -> Result<Formula, SyntaxError>,
    ) -> Result<Formula, SyntaxError> {
        if self.depth >= MAX_NESTING {
            let at = self
                .toks
                .get(self.pos)
                .map_or(Span::new(self.end, self.end), |t| t.1);
            return Err(self.error(
                SyntaxErrorKind::Syntax,
                format!("the formula nests more than {MAX_NESTING} levels deep"),
                at,
                Some("write it with fewer nested operators and parentheses"),
            ));
        }
        self.depth += 1;
        let r = level(self);
        self.depth -= 1;
        r
    }

    fn or(&mut self) -> Result<Formula, SyntaxError> {
        self.left_assoc(Tok::Or, Self::and, Kind::Or)
    }

    fn and(&mut self) -> Result<Formula, SyntaxError> {
        self.left_assoc(Tok::And, Self::until, Kind::And)
    }

    /// `operand (op operand)*`, nested to the left.
    fn left_assoc(
        &mut self,
        op: Tok,
        operand: fn(&mut Self) -> Result<Formula, SyntaxError>,
        make: fn(Box<Formula>, Box<Formula>) -> Kind,
    ) -> Result<Formula, SyntaxError> {
        let mut lhs = operand(self)?;
        while self.peek() == Some(&op) {
            self.bump();
            let rhs = operand(self)?;
            let span = Span::new(lhs.span.start, rhs.span.end);
            lhs = Formula {
                kind: make(Box::new(lhs), Box::new(rhs)),
                span,
            };
        }
        Ok(lhs)
    }

    fn until(&mut self) -> Result<Formula, SyntaxError> {
        self.nested(Self::until_inner)
    }

    fn until_inner(&mut self) -> Result<Formula, SyntaxError> {
        let lhs = self.unary()?;
        let make: fn(Box<Formula>, Box<Formula>) -> Kind = match self.peek() {
            Some(Tok::Until) => Kind::Until,
            Some(Tok::Release) => Kind::Release,
            Some(Tok::WeakUntil) => Kind::WeakUntil,
            _ => return Ok(lhs),
        };
        self.bump();
        let rhs = self.until()?;
        let span = Span::new(lhs.span.start, rhs.span.end);
        Ok(Formula {
            kind: make(Box::new(lhs), Box::new(rhs)),
            span,
        })
    }

    fn unary(&mut self) -> Result<Formula, SyntaxError> {
        self.nested(Self::unary_inner)
    }

    fn unary_inner(&mut self) -> Result<Formula, SyntaxError> {
        let Some((tok, span)) = self.bump() else {
            let at = Span::new(self.end, self.end);
            if let Some(open) = self.open.last() {
                return Err(self.error(
                    SyntaxErrorKind::Unbalanced,
                    "unbalanced parentheses: this `(` is never closed".into(),
                    *open,
                    Some("add a `)` where the group ends"),
                ));
            }
            return Err(self.error(
                SyntaxErrorKind::Syntax,
                "the formula ends where an operand is expected".into(),
                at,
                Some("complete the formula or remove the trailing operator"),
            ));
        };
        let prefix: Option<fn(Box<Formula>) -> Kind> = match tok {
            Tok::Not => Some(Kind::Not),
            Tok::Next => Some(Kind::Next),
            Tok::WeakNext => Some(Kind::WeakNext),
            Tok::Eventually => Some(Kind::Eventually),
            Tok::Always => Some(Kind::Always),
            _ => None,
        };
        if let Some(make) = prefix {
            let operand = self.unary()?;
            let s = Span::new(span.start, operand.span.end);
            return Ok(Formula {
                kind: make(Box::new(operand)),
                span: s,
            });
        }
        match tok {
            Tok::Ident(name) => Ok(Formula {
                kind: Kind::Atom(name),
                span,
            }),
            Tok::True => Ok(Formula {
                kind: Kind::True,
                span,
            }),
            Tok::False => Ok(Formula {
                kind: Kind::False,
                span,
            }),
            Tok::LParen => {
                self.open.push(span);
                let inner = self.implication()?;
                match self.bump() {
                    Some((Tok::RParen, close)) => {
                        self.open.pop();
                        Ok(Formula {
                            kind: inner.kind,
                            span: Span::new(span.start, close.end),
                        })
                    }
                    Some((t, s)) => Err(self.error(
                        SyntaxErrorKind::Syntax,
                        format!("expected `)` or an operator, found {}", t.describe()),
                        s,
                        Some("join the two parts with `&`, `|`, `->` or `U`"),
                    )),
                    None => Err(SyntaxError {
                        kind: SyntaxErrorKind::Unbalanced,
                        message: "unbalanced parentheses: this `(` is never closed".into(),
                        span,
                        help: Some("add a `)` where the group ends".into()),
                        fix: None,
                    }),
                }
            }
            Tok::RParen => Err(self.error(
                if self.open.is_empty() {
                    SyntaxErrorKind::Unbalanced
                } else {
                    SyntaxErrorKind::Syntax
                },
                if self.open.is_empty() {
                    "unbalanced parentheses: this `)` closes nothing".into()
                } else {
                    "empty parentheses or a missing operand before `)`".into()
                },
                span,
                Some("put a formula inside the parentheses, or remove the `)`"),
            )),
            t => Err(self.error(
                SyntaxErrorKind::Syntax,
                format!("expected an operand, found {}", t.describe()),
                span,
                Some("a binary operator needs a formula on both sides"),
            )),
        }
    }
}

impl Formula {
    pub fn new(kind: Kind) -> Self {
        Formula {
            kind,
            span: Span::default(),
        }
    }

    pub fn atom(name: &str) -> Self {
        Formula::new(Kind::Atom(name.to_string()))
    }

    pub fn negation(f: Formula) -> Self {
        Formula::new(Kind::Not(Box::new(f)))
    }

    /// Conjunction of `parts` (`true` when empty), left-nested.
    pub fn and_all(parts: Vec<Formula>) -> Self {
        parts
            .into_iter()
            .reduce(|a, b| Formula::new(Kind::And(Box::new(a), Box::new(b))))
            .unwrap_or(Formula::new(Kind::True))
    }

    /// Every atom name, in first-occurrence order.
    pub fn atoms(&self) -> Vec<&str> {
        let mut out: Vec<&str> = Vec::new();
        self.walk(&mut |f| {
            if let Kind::Atom(a) = &f.kind
                && !out.contains(&a.as_str())
            {
                out.push(a);
            }
        });
        out
    }

    /// Visits every node, parents first.
    pub fn walk<'a>(&'a self, visit: &mut dyn FnMut(&'a Formula)) {
        visit(self);
        match &self.kind {
            Kind::True | Kind::False | Kind::Atom(_) => {}
            Kind::Not(a)
            | Kind::Next(a)
            | Kind::WeakNext(a)
            | Kind::Eventually(a)
            | Kind::Always(a) => a.walk(visit),
            Kind::And(a, b)
            | Kind::Or(a, b)
            | Kind::Implies(a, b)
            | Kind::Iff(a, b)
            | Kind::Until(a, b)
            | Kind::Release(a, b)
            | Kind::WeakUntil(a, b) => {
                a.walk(visit);
                b.walk(visit);
            }
        }
    }

    /// Shifts every span by `offset` (a formula parsed out of a string literal).
    pub fn offset(&mut self, offset: usize) {
        self.span = Span::new(self.span.start + offset, self.span.end + offset);
        match &mut self.kind {
            Kind::True | Kind::False | Kind::Atom(_) => {}
            Kind::Not(a)
            | Kind::Next(a)
            | Kind::WeakNext(a)
            | Kind::Eventually(a)
            | Kind::Always(a) => a.offset(offset),
            Kind::And(a, b)
            | Kind::Or(a, b)
            | Kind::Implies(a, b)
            | Kind::Iff(a, b)
            | Kind::Until(a, b)
            | Kind::Release(a, b)
            | Kind::WeakUntil(a, b) => {
                a.offset(offset);
                b.offset(offset);
            }
        }
    }

    /// Binding strength for printing: 0 `->`, 1 `|`, 2 `&`, 3 `U R W`, 4 prefix and atoms.
    fn level(&self) -> u8 {
        match &self.kind {
            Kind::Implies(..) | Kind::Iff(..) => 0,
            Kind::Or(..) => 1,
            Kind::And(..) => 2,
            Kind::Until(..) | Kind::Release(..) | Kind::WeakUntil(..) => 3,
            _ => 4,
        }
    }

    fn print(&self, out: &mut String) {
        let child = |f: &Formula, min: u8, out: &mut String| {
            if f.level() < min {
                out.push('(');
                f.print(out);
                out.push(')');
            } else {
                f.print(out);
            }
        };
        let prefix = |op: &str, a: &Formula, out: &mut String| {
            out.push_str(op);
            // `F(x)` reads better than `F x` for compound operands; atoms stay bare.
            if a.level() < 4 {
                out.push('(');
                a.print(out);
                out.push(')');
            } else {
                if op != "!" {
                    out.push(' ');
                }
                a.print(out);
            }
        };
        match &self.kind {
            Kind::True => out.push_str("true"),
            Kind::False => out.push_str("false"),
            Kind::Atom(a) => out.push_str(a),
            Kind::Not(a) => prefix("!", a, out),
            Kind::Next(a) => prefix("X", a, out),
            Kind::WeakNext(a) => prefix("WX", a, out),
            Kind::Eventually(a) => prefix("F", a, out),
            Kind::Always(a) => prefix("G", a, out),
            Kind::And(a, b) => {
                child(a, 2, out);
                out.push_str(" & ");
                child(b, 2, out);
            }
            Kind::Or(a, b) => {
                child(a, 1, out);
                out.push_str(" | ");
                child(b, 1, out);
            }
            Kind::Implies(a, b) | Kind::Iff(a, b) => {
                child(a, 1, out);
                let _ = write!(
                    out,
                    " {} ",
                    if matches!(self.kind, Kind::Implies(..)) {
                        "->"
                    } else {
                        "<->"
                    }
                );
                child(b, 0, out);
            }
            Kind::Until(a, b) | Kind::Release(a, b) | Kind::WeakUntil(a, b) => {
                let op = match self.kind {
                    Kind::Until(..) => "U",
                    Kind::Release(..) => "R",
                    _ => "W",
                };
                child(a, 4, out);
                let _ = write!(out, " {op} ");
                child(b, 3, out);
            }
        }
    }
}

impl std::fmt::Display for Formula {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut s = String::new();
        self.print(&mut s);
        f.write_str(&s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round(s: &str) -> String {
        parse(s).unwrap().to_string()
    }

    #[test]
    fn precedence_and_synonyms() {
        assert_eq!(round("a & b U c"), "a & b U c");
        assert_eq!(round("(a & b) U c"), "(a & b) U c");
        assert_eq!(round("<>(a && []~b)"), "F(a & G !b)");
        assert_eq!(round("◇(a ∧ □¬b) → c ∨ d"), "F(a & G !b) -> c | d");
        assert_eq!(round("a -> b -> c"), "a -> b -> c");
        assert_eq!(round("(a -> b) -> c"), "(a -> b) -> c");
        assert_eq!(round("F(a & F(b & F c))"), "F(a & F(b & F c))");
        assert_eq!(round("!a U b R c"), "!a U b R c");
        assert_eq!(round("X !a"), "X !a");
        assert_eq!(round("!F a"), "!F a");
    }

    #[test]
    fn printing_round_trips() {
        for s in [
            "F(a & F(b)) & G !c",
            "(!c & !a) U (a & !c & F b)",
            "a | b & c",
            "(a | b) & c",
            "WX(a) W b",
            "!(a U b)",
            "a <-> !b",
        ] {
            let f = parse(s).unwrap();
            let printed = f.to_string();
            let again = parse(&printed).unwrap();
            assert_eq!(strip(&again), strip(&f), "{s} -> {printed}");
        }
    }

    fn strip(f: &Formula) -> String {
        format!("{:?}", f.kind)
            .split("span")
            .next()
            .unwrap_or("")
            .to_string()
    }

    #[test]
    fn errors_have_kinds_and_spans() {
        let e = parse("F(a & b").unwrap_err();
        assert_eq!(e.kind, SyntaxErrorKind::Unbalanced);
        assert_eq!(e.span, Span::new(1, 2));
        let e = parse("a & b)").unwrap_err();
        assert_eq!(e.kind, SyntaxErrorKind::Unbalanced);
        assert_eq!(e.span, Span::new(5, 6));
        let e = parse("a S b").unwrap_err();
        assert_eq!(e.kind, SyntaxErrorKind::Unsupported);
        assert_eq!(e.span, Span::new(2, 3));
        let e = parse("a ^ b").unwrap_err();
        assert_eq!(e.fix.as_deref(), Some("&"));
        let e = parse("a &").unwrap_err();
        assert_eq!(e.kind, SyntaxErrorKind::Syntax);
        assert!(parse("").is_err());
        assert!(parse("a b").is_err());
        assert!(parse("()").is_err());
    }
}
