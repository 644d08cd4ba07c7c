//! The canonical pretty-printer: two-space indentation, one statement per line, parentheses
//! only where precedence needs them, and method chains broken one `.method()` per line when a
//! statement would not fit in [`LINE_WIDTH`] columns.
//!
//! The output re-parses to the same tree (modulo spans), and printing is idempotent; both are
//! property-tested. [`print_with_comments`] also re-attaches the source's `//` comments: a
//! comment on the same line as the end of a statement stays there, any other comment goes on its
//! own line before the next statement that starts after it (or before the closing `}` of its
//! block), and single blank lines between statements are kept.

use crate::ast::*;

/// Statements longer than this have their top-level method chain broken across lines.
pub const LINE_WIDTH: usize = 100;

/// Prints a program without comments (for generated programs).
pub fn print(program: &Program) -> String {
    let mut p = Printer::new(None, &[]);
    p.program(program);
    p.out
}

/// Prints a parsed program with the comments and blank lines of `source`, the text it was
/// parsed from (`comments` as returned by [`crate::parse()`]).
pub fn print_with_comments(program: &Program, comments: &[(Span, String)], source: &str) -> String {
    let mut p = Printer::new(Some(source), comments);
    p.program(program);
    p.out
}

/// Prints one expression on one line.
pub fn print_expr(expr: &Expr) -> String {
    expr_at(expr, LAMBDA)
}

/// Formats a number so that it lexes back to the same `f64`: Rust's `Display` gives the
/// shortest round-tripping digits and never an exponent; a `.0` keeps it a number, not an integer.
pub fn format_f64(v: f64) -> String {
    let s = format!("{v}");
    if v.is_finite() && !s.contains('.') {
        format!("{s}.0")
    } else {
        s
    }
}

fn format_distance(value: f64, unit: DistanceUnit) -> String {
    let unit = match unit {
        DistanceUnit::M => "m",
        DistanceUnit::Cm => "cm",
    };
    format!("{value}{unit}")
}

fn format_str(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

// Precedence levels, loosest first; mirrors the grammar.
const LAMBDA: u8 = 0;
const OR: u8 = 1;
const AND: u8 = 2;
const NOT: u8 = 3;
const CMP: u8 = 4;
const UNION: u8 = 5;
const ADD: u8 = 6;
const MUL: u8 = 7;
const NEG: u8 = 8;
const POSTFIX: u8 = 9;
const ATOM: u8 = 10;

fn binop(op: BinOp) -> (&'static str, u8) {
    match op {
        BinOp::Or => ("or", OR),
        BinOp::And => ("and", AND),
        BinOp::Eq => ("==", CMP),
        BinOp::Ne => ("!=", CMP),
        BinOp::Lt => ("<", CMP),
        BinOp::Le => ("<=", CMP),
        BinOp::Gt => (">", CMP),
        BinOp::Ge => (">=", CMP),
        BinOp::Union => ("|", UNION),
        BinOp::Add => ("+", ADD),
        BinOp::Sub => ("-", ADD),
        BinOp::Mul => ("*", MUL),
    }
}

fn prec(e: &Expr) -> u8 {
    match &e.kind {
        ExprKind::Lambda { .. } => LAMBDA,
        ExprKind::Binary { op, .. } => binop(*op).1,
        ExprKind::Unary { op: UnOp::Not, .. } => NOT,
        ExprKind::Unary { op: UnOp::Neg, .. } => NEG,
        ExprKind::Method { .. } => POSTFIX,
        // A negative literal prints with a leading `-`, which reads back as a negation.
        ExprKind::Int(v) if *v < 0 => NEG,
        ExprKind::Number(v) | ExprKind::Distance { value: v, .. } if v.is_sign_negative() => NEG,
        _ => ATOM,
    }
}

fn expr_at(e: &Expr, min: u8) -> String {
    let s = raw(e);
    if prec(e) < min { format!("({s})") } else { s }
}

fn raw(e: &Expr) -> String {
    match &e.kind {
        ExprKind::Name(id) => id.name.clone(),
        ExprKind::Int(v) => v.to_string(),
        ExprKind::Number(v) => format_f64(*v),
        ExprKind::Distance { value, unit } => format_distance(*value, *unit),
        ExprKind::Bool(b) => b.to_string(),
        ExprKind::Str(s) => format_str(s),
        ExprKind::Call { func, args } => format!("{}({})", func.name, args_text(args)),
        ExprKind::Method {
            receiver,
            method,
            args,
            parens,
        } => {
            let recv = expr_at(receiver, POSTFIX);
            format!("{recv}.{}", method_suffix(method, args, *parens))
        }
        ExprKind::Lambda { param, body } => format!("{} => {}", param.name, expr_at(body, LAMBDA)),
        ExprKind::Binary { op, lhs, rhs, .. } => {
            let (text, p) = binop(*op);
            let (lmin, rmin) = if p == CMP { (p + 1, p + 1) } else { (p, p + 1) };
            format!("{} {text} {}", expr_at(lhs, lmin), expr_at(rhs, rmin))
        }
        ExprKind::Unary {
            op: UnOp::Not,
            operand,
            ..
        } => format!("not {}", expr_at(operand, NOT)),
        ExprKind::Unary {
            op: UnOp::Neg,
            operand,
            ..
        } => format!("-{}", expr_at(operand, NEG)),
        ExprKind::If {
            cond,
            then,
            otherwise,
        } => {
            let tail = match &otherwise.kind {
                ExprKind::If { .. } => raw(otherwise),
                _ => format!("{{ {} }}", expr_at(otherwise, LAMBDA)),
            };
            format!(
                "if {} {{ {} }} else {tail}",
                expr_at(cond, LAMBDA),
                expr_at(then, LAMBDA)
            )
        }
        ExprKind::Error => "<error>".to_string(),
    }
}

fn method_suffix(method: &Ident, args: &[Arg], parens: bool) -> String {
    if parens || !args.is_empty() {
        format!("{}({})", method.name, args_text(args))
    } else {
        method.name.clone()
    }
}

fn args_text(args: &[Arg]) -> String {
    let parts: Vec<String> = args
        .iter()
        .map(|a| match &a.name {
            Some(n) => format!("{}: {}", n.name, expr_at(&a.value, LAMBDA)),
            None => expr_at(&a.value, LAMBDA),
        })
        .collect();
    parts.join(", ")
}

struct Printer<'a> {
    out: String,
    indent: usize,
    source: Option<&'a str>,
    comments: &'a [(Span, String)],
    next_comment: usize,
    /// Source offset where the last emitted statement or comment ended (for blank lines).
    last_end: usize,
    /// Nothing emitted yet in the current block, so no blank line goes here.
    block_start: bool,
}

impl<'a> Printer<'a> {
    fn new(source: Option<&'a str>, comments: &'a [(Span, String)]) -> Self {
        Printer {
            out: String::new(),
            indent: 0,
            source,
            comments,
            next_comment: 0,
            last_end: 0,
            block_start: true,
        }
    }

    fn pad(&self) -> String {
        "  ".repeat(self.indent)
    }

    /// One output line at the current indentation (continuation lines of a broken chain carry
    /// their own indentation).
    fn line(&mut self, text: &str) {
        self.out.push_str(&self.pad());
        self.out.push_str(text);
        self.out.push('\n');
    }

    /// A blank line before something starting at `pos`, if the source had one there.
    fn gap(&mut self, pos: usize) {
        if self.block_start {
            return;
        }
        let Some(src) = self.source else { return };
        let between = src.get(self.last_end..pos).unwrap_or("");
        let mut newlines = 0;
        for c in between.chars() {
            if c == '\n' {
                newlines += 1;
                if newlines >= 2 {
                    self.out.push('\n');
                    return;
                }
            } else if !c.is_whitespace() {
                newlines = 0;
            }
        }
    }

    /// Emits, on their own lines, the comments that start before `pos`.
    fn comments_before(&mut self, pos: usize) {
        while let Some((span, text)) = self.comments.get(self.next_comment) {
            if span.start >= pos {
                break;
            }
            self.gap(span.start);
            self.line(text);
            self.next_comment += 1;
            self.last_end = span.end;
            self.block_start = false;
        }
    }

    /// Appends to the last line a comment that follows `end` on the same source line.
    fn trailing_comment(&mut self, end: usize) {
        let Some(src) = self.source else { return };
        let Some((span, text)) = self.comments.get(self.next_comment) else {
            return;
        };
        if span.start < end
            || src
                .get(end..span.start)
                .is_none_or(|between| between.contains('\n'))
        {
            return;
        }
        if self.out.ends_with('\n') {
            self.out.pop();
        }
        self.out.push(' ');
        self.out.push_str(text);
        self.out.push('\n');
        self.next_comment += 1;
        self.last_end = span.end;
    }

    /// Everything that comes before a statement spanning `span`: comments, then a blank line if
    /// the source had one.
    fn begin(&mut self, span: Span) {
        self.comments_before(span.start);
        self.gap(span.start);
        self.block_start = false;
    }

    fn end(&mut self, span: Span) {
        self.last_end = self.last_end.max(span.end);
        self.trailing_comment(span.end);
    }

    fn open_block(&mut self) {
        self.indent += 1;
        self.block_start = true;
    }

    fn close_block(&mut self, block_end: usize) {
        self.comments_before(block_end);
        self.indent -= 1;
        self.block_start = false;
    }

    fn program(&mut self, program: &Program) {
        let mut prev: Option<&Item> = None;
        for item in &program.items {
            if self.source.is_none()
                && let Some(p) = prev
                && (matches!(p, Item::Route(_)) || matches!(item, Item::Route(_)))
            {
                self.out.push('\n');
            }
            match item {
                Item::Let(l) => self.let_stmt(l),
                Item::Route(r) => self.route(r),
                Item::Error(span) => self.error(*span),
            }
            prev = Some(item);
        }
        self.comments_before(usize::MAX);
    }

    fn error(&mut self, span: Span) {
        self.begin(span);
        let text = self
            .source
            .and_then(|s| s.get(span.start..span.end))
            .unwrap_or("<error>");
        let text = text.trim().to_string();
        self.line(&text);
        while self
            .comments
            .get(self.next_comment)
            .is_some_and(|(s, _)| s.start < span.end)
        {
            self.next_comment += 1;
        }
        self.end(span);
    }

    /// A statement-level expression after `prefix` (which is already on the line): flat if it
    /// fits, otherwise its method chain one call per line.
    fn stmt_expr(&self, prefix_len: usize, e: &Expr, suffix_len: usize) -> String {
        let flat = expr_at(e, LAMBDA);
        if self.indent * 2 + prefix_len + flat.len() + suffix_len <= LINE_WIDTH {
            return flat;
        }
        let mut calls = Vec::new();
        let mut base = e;
        while let ExprKind::Method {
            receiver,
            method,
            args,
            parens,
        } = &base.kind
        {
            calls.push(method_suffix(method, args, *parens));
            base = receiver;
        }
        if calls.len() < 2 {
            return flat;
        }
        let mut s = expr_at(base, POSTFIX);
        let pad = "  ".repeat(self.indent + 1);
        for call in calls.iter().rev() {
            s.push('\n');
            s.push_str(&pad);
            s.push('.');
            s.push_str(call);
        }
        s
    }

    fn let_stmt(&mut self, l: &Let) {
        self.begin(l.span);
        let prefix = format!("let {} = ", l.name.name);
        let value = self.stmt_expr(prefix.len(), &l.value, 0);
        self.line(&format!("{prefix}{value}"));
        self.end(l.span);
    }

    fn route(&mut self, r: &Route) {
        self.begin(r.span);
        if let Some(RouteItem::Ltl(f)) = r.items.first() {
            let head = format!("route {} {}", f.keyword.name, format_str(&f.formula));
            if r.items.len() == 1 && !self.has_comment_before(r.span.end) {
                self.line(&head);
            } else {
                self.line(&format!("{head} {{"));
                self.open_block();
                self.route_items(&r.items[1..]);
                self.close_block(r.span.end);
                self.line("}");
            }
            self.end(r.span);
            return;
        }
        if r.items.is_empty() && !self.has_comment_before(r.span.end) {
            self.line("route {}");
        } else {
            self.line("route {");
            self.open_block();
            self.route_items(&r.items);
            self.close_block(r.span.end);
            self.line("}");
        }
        self.end(r.span);
    }

    fn has_comment_before(&self, pos: usize) -> bool {
        self.comments
            .get(self.next_comment)
            .is_some_and(|(s, _)| s.start < pos)
    }

    fn route_items(&mut self, items: &[RouteItem]) {
        for item in items {
            match item {
                RouteItem::Stage(s) => self.stage(s),
                RouteItem::Constraint(c) => self.constraint(c),
                RouteItem::Let(l) => self.let_stmt(l),
                RouteItem::For(f) => self.for_stages(f),
                RouteItem::Error(span) => self.error(*span),
                // Printed by `route` as the block's head.
                RouteItem::Ltl(_) => {}
            }
        }
    }

    fn stage(&mut self, s: &Stage) {
        self.begin(s.span);
        let name = s
            .name
            .as_ref()
            .map(|n| format!(" as {}", n.name))
            .unwrap_or_default();
        let has_body = !s.body.is_empty() || self.has_comment_before(s.span.end);
        let suffix_len = name.len() + if has_body { 2 } else { 0 };
        let target = self.stmt_expr(3, &s.target, suffix_len);
        if !has_body {
            self.line(&format!("go {target}{name}"));
        } else {
            self.line(&format!("go {target}{name} {{"));
            self.open_block();
            for item in &s.body {
                match item {
                    StageItem::Constraint(c) => self.constraint(c),
                    StageItem::Let(l) => self.let_stmt(l),
                    StageItem::Error(span) => self.error(*span),
                }
            }
            self.close_block(s.span.end);
            self.line("}");
        }
        self.end(s.span);
    }

    fn for_stages(&mut self, f: &ForStages) {
        self.begin(f.span);
        let prefix = format!("for {} in ", f.var.name);
        let iter = self.stmt_expr(prefix.len(), &f.iter, 2);
        if f.body.is_empty() && !self.has_comment_before(f.span.end) {
            self.line(&format!("{prefix}{iter} {{}}"));
        } else {
            self.line(&format!("{prefix}{iter} {{"));
            self.open_block();
            self.route_items(&f.body);
            self.close_block(f.span.end);
            self.line("}");
        }
        self.end(f.span);
    }

    fn constraint(&mut self, c: &Constraint) {
        self.begin(c.span);
        let kw = match c.kind {
            ConstraintKind::Pass => "pass ",
            ConstraintKind::Avoid => "avoid ",
            ConstraintKind::Prefer => "prefer ",
        };
        let mut text = format!("{kw}{}", self.stmt_expr(kw.len(), &c.value, 0));
        for scope in &c.scopes {
            match scope {
                Scope::Within { place, .. } => {
                    let last_line = text.rsplit('\n').next().map_or(0, str::len);
                    let place = self.stmt_expr(last_line + 8, place, 0);
                    text.push_str(" within ");
                    text.push_str(&place);
                }
                Scope::During { stages, .. } => {
                    let names: Vec<&str> = stages.iter().map(|s| s.name.as_str()).collect();
                    text.push_str(" during ");
                    text.push_str(&names.join(", "));
                }
            }
        }
        self.line(&text);
        self.end(c.span);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_keep_a_decimal_point_and_round_trip() {
        assert_eq!(format_f64(1.0), "1.0");
        assert_eq!(format_f64(0.1), "0.1");
        assert_eq!(format_f64(1e20), "100000000000000000000.0");
        assert_eq!(format_f64(1e-7), "0.0000001");
        for v in [0.1, 1.0 / 3.0, 123456.789, 5e-324, f64::MAX] {
            assert_eq!(format_f64(v).parse::<f64>().ok(), Some(v));
        }
    }

    #[test]
    fn distances_and_strings() {
        assert_eq!(format_distance(2.0, DistanceUnit::M), "2m");
        assert_eq!(format_distance(30.5, DistanceUnit::Cm), "30.5cm");
        assert_eq!(format_str("a\"b\\\n"), r#""a\"b\\\n""#);
    }
}
