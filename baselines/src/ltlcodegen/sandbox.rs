//! The interpreter for LTLCodeGen's `question()` programs: our own, never a host language.
//!
//! The model writes Python; we read a small subset of it and evaluate that subset ourselves:
//!
//! * exactly one function, `def question():`, with no parameters; comment lines, blank lines and
//!   docstrings anywhere;
//! * in its body: `name = expression`, `return expression`, `pass`, a bare string (docstring);
//! * expressions: string literals, names bound earlier, list literals, `True`/`False`/`None`,
//!   and calls of the operator library: `ap("room_3")`, `ltl_not(f)`, `ltl_eventually(f)`,
//!   `ltl_always(f)`, `ltl_until(f, g)`, `ltl_imply(f, g)`, `ltl_and(f, g, ...)`,
//!   `ltl_or(f, g, ...)` (a list argument of `ltl_and`/`ltl_or` is spread);
//! * brackets join lines, as in Python.
//!
//! Everything else (imports, other functions, loops, conditionals, attribute access, keyword
//! arguments, arithmetic, other calls) is refused with its line. Budgets bound the work: the
//! source length and token count, the expression nesting, the evaluation steps, and the size of
//! every formula built (a name used twice in a formula counts twice, so doubling a formula thirty
//! times is refused instead of growing to a billion nodes).

use m2rc_compiler::ltl::Formula;
use m2rc_compiler::ltl::syntax::Kind;
use std::collections::HashMap;

pub const MAX_SOURCE_BYTES: usize = 32 * 1024;
pub const MAX_TOKENS: usize = 8_000;
pub const MAX_DEPTH: usize = 64;
pub const MAX_STEPS: usize = 20_000;
pub const MAX_FORMULA_NODES: usize = 2_000;

/// Why a program was refused; `line` is 1-based (0 when the whole program is at fault).
#[derive(Clone, Debug, PartialEq)]
pub struct SandboxError {
    pub line: usize,
    pub message: String,
}

impl std::fmt::Display for SandboxError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.line == 0 {
            f.write_str(&self.message)
        } else {
            write!(f, "line {}: {}", self.line, self.message)
        }
    }
}

fn err<T>(line: usize, message: impl Into<String>) -> Result<T, SandboxError> {
    Err(SandboxError {
        line,
        message: message.into(),
    })
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Name(String),
    Str(String),
    Num(String),
    Punct(char),
    Op(String),
    /// End of a logical line, with the indentation of the line it ends.
    Newline,
}

#[derive(Clone, Debug)]
struct Token {
    tok: Tok,
    line: usize,
    /// Indentation of the logical line this token starts (only meaningful for its first token).
    indent: usize,
}

fn tokenize(src: &str) -> Result<Vec<Token>, SandboxError> {
    let chars: Vec<char> = src.chars().collect();
    let mut out: Vec<Token> = Vec::new();
    let (mut i, mut line, mut depth) = (0usize, 1usize, 0usize);
    let mut at_line_start = true;
    let mut indent = 0usize;
    while i < chars.len() {
        if out.len() > MAX_TOKENS {
            return err(
                line,
                format!("the program has more than {MAX_TOKENS} tokens"),
            );
        }
        let c = chars[i];
        if at_line_start {
            indent = 0;
            while i < chars.len() && (chars[i] == ' ' || chars[i] == '\t') {
                indent += if chars[i] == '\t' { 4 } else { 1 };
                i += 1;
            }
            at_line_start = false;
            continue;
        }
        match c {
            '\n' => {
                if depth == 0 && out.last().is_some_and(|t| t.tok != Tok::Newline) {
                    out.push(Token {
                        tok: Tok::Newline,
                        line,
                        indent,
                    });
                }
                line += 1;
                i += 1;
                at_line_start = depth == 0;
            }
            ' ' | '\t' | '\r' => i += 1,
            '#' => {
                while i < chars.len() && chars[i] != '\n' {
                    i += 1;
                }
            }
            '\\' if chars.get(i + 1) == Some(&'\n') => {
                line += 1;
                i += 2;
            }
            '"' | '\'' => {
                let triple = chars.get(i + 1) == Some(&c) && chars.get(i + 2) == Some(&c);
                let start_line = line;
                let q = if triple { 3 } else { 1 };
                i += q;
                let mut s = String::new();
                loop {
                    let Some(&d) = chars.get(i) else {
                        return err(start_line, "unterminated string");
                    };
                    if d == c
                        && (!triple
                            || (chars.get(i + 1) == Some(&c) && chars.get(i + 2) == Some(&c)))
                    {
                        i += q;
                        break;
                    }
                    if d == '\n' {
                        if !triple {
                            return err(start_line, "unterminated string");
                        }
                        line += 1;
                    }
                    if d == '\\'
                        && let Some(&e) = chars.get(i + 1)
                    {
                        s.push(match e {
                            'n' => '\n',
                            't' => '\t',
                            other => other,
                        });
                        i += 2;
                        continue;
                    }
                    s.push(d);
                    i += 1;
                }
                push(&mut out, Tok::Str(s), start_line, indent);
            }
            '(' | '[' | '{' => {
                depth += 1;
                if depth > MAX_DEPTH {
                    return err(line, format!("brackets nest deeper than {MAX_DEPTH}"));
                }
                push(&mut out, Tok::Punct(c), line, indent);
                i += 1;
            }
            ')' | ']' | '}' => {
                depth = depth.saturating_sub(1);
                push(&mut out, Tok::Punct(c), line, indent);
                i += 1;
            }
            ',' | ':' | '.' | ';' => {
                push(&mut out, Tok::Punct(c), line, indent);
                i += 1;
            }
            c if c.is_alphabetic() || c == '_' => {
                let s: String = chars[i..]
                    .iter()
                    .take_while(|x| x.is_alphanumeric() || **x == '_')
                    .collect();
                i += s.chars().count();
                push(&mut out, Tok::Name(s), line, indent);
            }
            c if c.is_ascii_digit() => {
                let s: String = chars[i..]
                    .iter()
                    .take_while(|x| x.is_ascii_alphanumeric() || **x == '.')
                    .collect();
                i += s.chars().count();
                push(&mut out, Tok::Num(s), line, indent);
            }
            _ => {
                let s: String = chars[i..]
                    .iter()
                    .take_while(|x| "=+-*/%<>!&|^~@".contains(**x))
                    .collect();
                if s.is_empty() {
                    return err(line, format!("unexpected character `{c}`"));
                }
                i += s.chars().count();
                push(&mut out, Tok::Op(s), line, indent);
            }
        }
    }
    if out.last().is_some_and(|t| t.tok != Tok::Newline) {
        out.push(Token {
            tok: Tok::Newline,
            line,
            indent,
        });
    }
    Ok(out)
}

fn push(out: &mut Vec<Token>, tok: Tok, line: usize, indent: usize) {
    out.push(Token { tok, line, indent });
}

/// What the program returned, and the APs it named.
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluated {
    pub formula: Formula,
    /// Every `ap(...)` argument, in first-use order.
    pub aps: Vec<String>,
    pub steps: usize,
}

#[derive(Clone, Debug)]
enum Val {
    F(Formula, usize),
    Str(String),
    List(Vec<Val>),
    Const,
}

struct Eval<'a> {
    toks: &'a [Token],
    pos: usize,
    steps: usize,
    vars: HashMap<String, Val>,
    listed: &'a dyn Fn(&str) -> bool,
    aps: Vec<String>,
}

/// Runs `src` (a `question()` program) and returns its formula; `listed` says which AP names the
/// inventory lists (any other is an error).
pub fn run(src: &str, listed: &dyn Fn(&str) -> bool) -> Result<Evaluated, SandboxError> {
    if src.len() > MAX_SOURCE_BYTES {
        return err(
            0,
            format!("the program is longer than {MAX_SOURCE_BYTES} bytes"),
        );
    }
    let toks = tokenize(src)?;
    let mut e = Eval {
        toks: &toks,
        pos: 0,
        steps: 0,
        vars: HashMap::new(),
        listed,
        aps: Vec::new(),
    };
    e.program()
}

impl Eval<'_> {
    fn peek(&self) -> Option<&Token> {
        self.toks.get(self.pos)
    }

    fn line(&self) -> usize {
        self.peek().or(self.toks.last()).map_or(0, |t| t.line)
    }

    fn next(&mut self) -> Option<Token> {
        let t = self.toks.get(self.pos).cloned();
        self.pos += 1;
        t
    }

    fn expect(&mut self, want: Tok, what: &str) -> Result<(), SandboxError> {
        let line = self.line();
        match self.next() {
            Some(t) if t.tok == want => Ok(()),
            Some(t) => err(t.line, format!("expected {what}, found {}", show(&t.tok))),
            None => err(line, format!("expected {what} at the end of the program")),
        }
    }

    fn program(&mut self) -> Result<Evaluated, SandboxError> {
        // Leading docstrings.
        while let Some(Tok::Str(_)) = self.peek().map(|t| t.tok.clone()) {
            self.next();
            self.expect(Tok::Newline, "the end of the line")?;
        }
        let line = self.line();
        match self.next().map(|t| t.tok) {
            Some(Tok::Name(n)) if n == "def" => {}
            Some(Tok::Name(n)) if n == "import" || n == "from" => {
                return err(
                    line,
                    "imports are not allowed: the operator library is already there",
                );
            }
            Some(t) => {
                return err(
                    line,
                    format!("expected `def question():`, found {}", show(&t)),
                );
            }
            None => return err(0, "the program is empty; define `def question():`"),
        }
        match self.next().map(|t| t.tok) {
            Some(Tok::Name(n)) if n == "question" => {}
            Some(t) => {
                return err(
                    line,
                    format!("the function must be `question`, not {}", show(&t)),
                );
            }
            None => return err(line, "expected `question`"),
        }
        self.expect(Tok::Punct('('), "`(`")?;
        self.expect(Tok::Punct(')'), "`)` (question() takes no parameters)")?;
        self.expect(Tok::Punct(':'), "`:`")?;
        self.expect(Tok::Newline, "a new line after `def question():`")?;
        let mut result: Option<Formula> = None;
        while let Some(t) = self.peek().cloned() {
            if t.indent == 0 {
                return err(
                    t.line,
                    format!(
                        "{} outside question(): only question() may be defined, and nothing may run outside it",
                        show(&t.tok)
                    ),
                );
            }
            if result.is_some() {
                // After `return` nothing runs, as in Python: skip the rest of the body.
                while let Some(t) = self.next() {
                    if t.tok == Tok::Newline {
                        break;
                    }
                }
                continue;
            }
            result = self.statement()?;
        }
        match result {
            Some(formula) => Ok(Evaluated {
                formula,
                aps: std::mem::take(&mut self.aps),
                steps: self.steps,
            }),
            None => err(0, "question() does not return a formula"),
        }
    }

    /// One statement; `Some` for the formula of a `return`.
    fn statement(&mut self) -> Result<Option<Formula>, SandboxError> {
        let t = self.next().ok_or(SandboxError {
            line: 0,
            message: "unexpected end".into(),
        })?;
        let line = t.line;
        let out = match &t.tok {
            Tok::Str(_) => None,
            Tok::Name(n) if n == "pass" => None,
            Tok::Name(n) if n == "return" => match self.expr(0)? {
                Val::F(f, _) => Some(f),
                other => {
                    return err(
                        line,
                        format!("question() must return a formula, not {}", kind(&other)),
                    );
                }
            },
            Tok::Name(n)
                if matches!(
                    n.as_str(),
                    "for"
                        | "while"
                        | "if"
                        | "elif"
                        | "else"
                        | "def"
                        | "lambda"
                        | "import"
                        | "from"
                        | "class"
                        | "with"
                        | "try"
                        | "except"
                        | "global"
                        | "nonlocal"
                        | "del"
                        | "yield"
                        | "assert"
                        | "raise"
                        | "async"
                        | "await"
                ) =>
            {
                return err(
                    line,
                    format!(
                        "`{n}` is not part of the sandbox's subset (assignments, calls of the operator library, return)"
                    ),
                );
            }
            Tok::Name(n) => {
                if self.peek().map(|t| &t.tok) != Some(&Tok::Op("=".into())) {
                    return err(
                        line,
                        format!(
                            "a statement must be `name = ...` or `return ...`; `{n}` is neither"
                        ),
                    );
                }
                self.next();
                let v = self.expr(0)?;
                if reserved(n) {
                    return err(
                        line,
                        format!("`{n}` is a library name and cannot be assigned"),
                    );
                }
                self.vars.insert(n.clone(), v);
                None
            }
            other => {
                return err(
                    line,
                    format!("unexpected {} at the start of a statement", show(other)),
                );
            }
        };
        match self.next() {
            Some(Token {
                tok: Tok::Newline, ..
            })
            | None => Ok(out),
            Some(t) => err(
                t.line,
                format!("unexpected {} (one statement per line)", show(&t.tok)),
            ),
        }
    }

    fn step(&mut self, line: usize) -> Result<(), SandboxError> {
        self.steps += 1;
        if self.steps > MAX_STEPS {
            return err(
                line,
                format!("the program takes more than {MAX_STEPS} evaluation steps"),
            );
        }
        Ok(())
    }

    fn expr(&mut self, depth: usize) -> Result<Val, SandboxError> {
        let line = self.line();
        if depth > MAX_DEPTH {
            return err(line, format!("expressions nest deeper than {MAX_DEPTH}"));
        }
        self.step(line)?;
        let t = self.next().ok_or(SandboxError {
            line,
            message: "an expression is missing".into(),
        })?;
        let v = match t.tok {
            Tok::Str(s) => Val::Str(s),
            Tok::Punct('[') => {
                let items = self.args(']', depth)?;
                Val::List(items)
            }
            Tok::Name(n) if matches!(n.as_str(), "True" | "False" | "None") => Val::Const,
            Tok::Name(n) if self.peek().map(|t| &t.tok) == Some(&Tok::Punct('(')) => {
                self.next();
                let args = self.args(')', depth)?;
                self.call(&n, args, t.line)?
            }
            Tok::Name(n) => match self.vars.get(&n) {
                Some(v) => v.clone(),
                None if reserved(&n) => {
                    return err(t.line, format!("`{n}` must be called"));
                }
                None => return err(t.line, format!("`{n}` is not defined")),
            },
            other => {
                return err(
                    t.line,
                    format!("{} is not part of the sandbox's subset", show(&other)),
                );
            }
        };
        match self.peek().map(|t| t.tok.clone()) {
            Some(Tok::Punct('.')) => {
                err(line, "attribute access is not part of the sandbox's subset")
            }
            Some(Tok::Punct('(')) | Some(Tok::Punct('[')) => err(
                line,
                "only the operator library's functions may be called, by name",
            ),
            Some(Tok::Op(o)) if o != "=" => err(
                line,
                format!(
                    "the operator `{o}` is not part of the sandbox's subset; use ltl_and, ltl_or, ltl_not, ..."
                ),
            ),
            _ => Ok(v),
        }
    }

    fn args(&mut self, close: char, depth: usize) -> Result<Vec<Val>, SandboxError> {
        let mut out = Vec::new();
        loop {
            if self.peek().map(|t| &t.tok) == Some(&Tok::Punct(close)) {
                self.next();
                return Ok(out);
            }
            if let (Some(Tok::Name(_)), Some(Tok::Op(o))) = (
                self.peek().map(|t| t.tok.clone()),
                self.toks.get(self.pos + 1).map(|t| t.tok.clone()),
            ) && o == "="
            {
                return err(
                    self.line(),
                    "keyword arguments are not part of the sandbox's subset",
                );
            }
            out.push(self.expr(depth + 1)?);
            let line = self.line();
            match self.next().map(|t| t.tok) {
                Some(Tok::Punct(',')) => {}
                Some(Tok::Punct(c)) if c == close => return Ok(out),
                Some(t) => {
                    return err(
                        line,
                        format!("expected `,` or `{close}`, found {}", show(&t)),
                    );
                }
                None => return err(line, format!("`{close}` is missing")),
            }
        }
    }

    fn call(&mut self, name: &str, args: Vec<Val>, line: usize) -> Result<Val, SandboxError> {
        let formulas = |args: Vec<Val>,
                        spread: bool|
         -> Result<Vec<(Formula, usize)>, SandboxError> {
            let mut out = Vec::new();
            for a in args {
                match a {
                    Val::F(f, n) => out.push((f, n)),
                    Val::List(items) if spread => {
                        for i in items {
                            match i {
                                Val::F(f, n) => out.push((f, n)),
                                other => {
                                    return err(
                                        line,
                                        format!("`{name}` takes formulas, not {}", kind(&other)),
                                    );
                                }
                            }
                        }
                    }
                    other => {
                        return err(
                            line,
                            format!("`{name}` takes formulas, not {}", kind(&other)),
                        );
                    }
                }
            }
            Ok(out)
        };
        let arity = |got: usize, want: usize| -> Result<(), SandboxError> {
            if got == want {
                Ok(())
            } else {
                err(
                    line,
                    format!("`{name}` takes {want} argument(s), got {got}"),
                )
            }
        };
        let b = Box::new;
        let (kind, size) = match name {
            "ap" => {
                arity(args.len(), 1)?;
                let Val::Str(s) = &args[0] else {
                    return err(
                        line,
                        format!(
                            "`ap` takes the AP's name as a string, not {}",
                            kind(&args[0])
                        ),
                    );
                };
                if !(self.listed)(s) {
                    return err(
                        line,
                        format!("`{s}` is not an AP of the inventory; use only listed AP names"),
                    );
                }
                if !self.aps.contains(s) {
                    self.aps.push(s.clone());
                }
                (Kind::Atom(s.clone()), 1)
            }
            "ltl_not" | "ltl_eventually" | "ltl_always" => {
                let mut f = formulas(args, false)?;
                arity(f.len(), 1)?;
                let (x, n) = f.remove(0);
                let k = match name {
                    "ltl_not" => Kind::Not(b(x)),
                    "ltl_eventually" => Kind::Eventually(b(x)),
                    _ => Kind::Always(b(x)),
                };
                (k, n + 1)
            }
            "ltl_until" | "ltl_imply" => {
                let mut f = formulas(args, false)?;
                arity(f.len(), 2)?;
                let (x, n) = f.remove(0);
                let (y, m) = f.remove(0);
                let k = if name == "ltl_until" {
                    Kind::Until(b(x), b(y))
                } else {
                    Kind::Implies(b(x), b(y))
                };
                (k, n + m + 1)
            }
            "ltl_and" | "ltl_or" => {
                let f = formulas(args, true)?;
                if f.is_empty() {
                    return err(line, format!("`{name}` needs at least one formula"));
                }
                let size = f.iter().map(|x| x.1).sum::<usize>() + f.len() - 1;
                let joined = f
                    .into_iter()
                    .map(|x| x.0)
                    .reduce(|a, c| {
                        Formula::new(if name == "ltl_and" {
                            Kind::And(b(a), b(c))
                        } else {
                            Kind::Or(b(a), b(c))
                        })
                    })
                    .map(|f| f.kind)
                    .unwrap_or(Kind::True);
                (joined, size)
            }
            other => {
                return err(
                    line,
                    format!(
                        "`{other}` is not a function of the operator library (ap, ltl_and, ltl_or, ltl_not, ltl_until, ltl_eventually, ltl_always, ltl_imply)"
                    ),
                );
            }
        };
        if size > MAX_FORMULA_NODES {
            return err(
                line,
                format!("the formula grows past {MAX_FORMULA_NODES} nodes"),
            );
        }
        Ok(Val::F(Formula::new(kind), size))
    }
}

fn reserved(n: &str) -> bool {
    matches!(
        n,
        "ap" | "ltl_and"
            | "ltl_or"
            | "ltl_not"
            | "ltl_until"
            | "ltl_eventually"
            | "ltl_always"
            | "ltl_imply"
    )
}

fn kind(v: &Val) -> &'static str {
    match v {
        Val::F(..) => "a formula",
        Val::Str(_) => "a string",
        Val::List(_) => "a list",
        Val::Const => "a constant",
    }
}

fn show(t: &Tok) -> String {
    match t {
        Tok::Name(n) => format!("`{n}`"),
        Tok::Str(_) => "a string".into(),
        Tok::Num(n) => format!("the number `{n}`"),
        Tok::Punct(c) => format!("`{c}`"),
        Tok::Op(o) => format!("`{o}`"),
        Tok::Newline => "the end of the line".into(),
    }
}
