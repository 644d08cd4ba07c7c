//! An intent graph compiled deterministically to `.m2r`, with a source map from every span of the
//! program back to the JSON pointer of the graph node it came from.
//!
//! The graph is read into the surface AST (each node's span temporarily holds its index in the
//! pointer table), printed by the canonical printer, and the printed text parsed again: walking the
//! two trees in the same order pairs each printed span with its pointer. The printer's guarantee
//! that its output re-parses to the same tree is what makes the walk exact.

use super::GraphDiagnostic;
use super::ops::{DISTANCE_PATTERN, LANGUAGE_OPS, operator_names, operators};
use crate::diagnostic::Code;
use m2rc_grammar::ast::*;
use m2rc_grammar::{parse, print};
use serde_json::Value;

/// Deepest nesting of graph values read: bounds the recursion of every later walk.
pub const MAX_DEPTH: usize = 64;

/// A compiled graph: the program and, for each node, its printed span and JSON pointer.
#[derive(Clone, Debug)]
pub struct Compiled {
    pub program: String,
    pub map: Vec<(Span, String)>,
}

impl Compiled {
    /// The pointer of the smallest node whose span covers `span`, and that node's span.
    pub fn locate(&self, span: Span) -> Option<(&str, Span)> {
        self.map
            .iter()
            .filter(|(s, _)| s.start <= span.start && span.end <= s.end)
            .min_by_key(|(s, _)| (s.end - s.start, std::cmp::Reverse(s.start)))
            .map(|(s, p)| (p.as_str(), *s))
    }
}

struct Reader {
    pointers: Vec<String>,
    errors: Vec<GraphDiagnostic>,
}

fn escape(key: &str) -> String {
    key.replace('~', "~0").replace('/', "~1")
}

impl Reader {
    /// A span that names pointer `p` until the program is printed.
    fn mark(&mut self, p: &str) -> Span {
        self.pointers.push(p.to_string());
        let i = self.pointers.len() - 1;
        Span::new(i, i)
    }

    fn fail(&mut self, code: Code, p: &str, msg: impl Into<String>, help: Option<String>) {
        self.errors.push(GraphDiagnostic::new(code, p, msg, help));
    }

    fn ident(&mut self, v: Option<&Value>, p: &str, what: &str) -> Option<Ident> {
        match v.and_then(Value::as_str) {
            Some(s) if is_name(s) => Some(Ident {
                name: s.to_string(),
                span: Span::default(),
            }),
            Some(s) => {
                self.fail(
                    Code::GraphShape,
                    p,
                    format!("`{s}` is not a valid {what}"),
                    Some("names are letters, digits and `_`, not starting with a digit".into()),
                );
                None
            }
            None => {
                self.fail(
                    Code::GraphShape,
                    p,
                    format!("expected {what} (a string)"),
                    None,
                );
                None
            }
        }
    }

    fn object<'v>(
        &mut self,
        v: &'v Value,
        p: &str,
        what: &str,
        keys: &[&str],
    ) -> Option<&'v serde_json::Map<String, Value>> {
        let Some(o) = v.as_object() else {
            self.fail(
                Code::GraphShape,
                p,
                format!("expected {what} (an object)"),
                None,
            );
            return None;
        };
        for k in o.keys() {
            if !keys.contains(&k.as_str()) {
                let help = crate::suggest::best(k, keys.iter().copied())
                    .map(|b| format!("write `{b}`"))
                    .or_else(|| Some(format!("{what} has the fields {}", keys.join(", "))));
                self.fail(
                    Code::GraphShape,
                    &format!("{p}/{}", escape(k)),
                    format!("unknown field `{k}` in {what}"),
                    help,
                );
            }
        }
        Some(o)
    }

    fn array<'v>(&mut self, v: Option<&'v Value>, p: &str, what: &str) -> &'v [Value] {
        match v {
            None => &[],
            Some(Value::Array(a)) => a,
            Some(_) => {
                self.fail(
                    Code::GraphShape,
                    p,
                    format!("expected {what} (an array)"),
                    None,
                );
                &[]
            }
        }
    }

    fn expr(&mut self, v: &Value, p: &str, depth: usize) -> Expr {
        let span = self.mark(p);
        let kind = self.expr_kind(v, p, depth);
        Expr { kind, span }
    }

    fn expr_kind(&mut self, v: &Value, p: &str, depth: usize) -> ExprKind {
        if depth > MAX_DEPTH {
            self.fail(
                Code::GraphShape,
                p,
                format!("the graph nests deeper than {MAX_DEPTH} levels"),
                None,
            );
            return ExprKind::Error;
        }
        match v {
            Value::String(s) if is_name(s) => ExprKind::Name(Ident {
                name: s.clone(),
                span: Span::default(),
            }),
            Value::String(s) => match distance(s) {
                Some((value, unit)) => ExprKind::Distance { value, unit },
                None => {
                    self.fail(
                        Code::GraphShape,
                        p,
                        format!("`{s}` is neither a name nor a distance"),
                        Some("a name is letters, digits and `_`; a distance is written `1.5m` or `30cm`".into()),
                    );
                    ExprKind::Error
                }
            },
            Value::Bool(b) => ExprKind::Bool(*b),
            Value::Number(n) => match n.as_i64() {
                Some(i) => ExprKind::Int(i),
                None => ExprKind::Number(n.as_f64().unwrap_or(0.0)),
            },
            Value::Object(o) if o.contains_key("lambda") => {
                let Some(o) = self.object(v, p, "a lambda", &["lambda", "body"]) else {
                    return ExprKind::Error;
                };
                let param = self.ident(o.get("lambda"), &format!("{p}/lambda"), "parameter name");
                let body = match o.get("body") {
                    Some(b) => self.expr(b, &format!("{p}/body"), depth + 1),
                    None => {
                        self.fail(Code::GraphShape, p, "a lambda needs a `body`", None);
                        return ExprKind::Error;
                    }
                };
                match param {
                    Some(param) => ExprKind::Lambda {
                        param,
                        body: Box::new(body),
                    },
                    None => ExprKind::Error,
                }
            }
            Value::Object(_) => self.op(v, p, depth),
            Value::Null | Value::Array(_) => {
                self.fail(
                    Code::GraphShape,
                    p,
                    "expected an expression: a name, a distance, a number, a lambda or `{op, of?, args?, kwargs?}`",
                    None,
                );
                ExprKind::Error
            }
        }
    }

    fn op(&mut self, v: &Value, p: &str, depth: usize) -> ExprKind {
        let Some(o) = self.object(v, p, "an operator", &["op", "of", "args", "kwargs"]) else {
            return ExprKind::Error;
        };
        let Some(name) = o.get("op").and_then(Value::as_str) else {
            self.fail(
                Code::GraphShape,
                p,
                "an operator needs `op` (a string)",
                None,
            );
            return ExprKind::Error;
        };
        let args_v = self.array(o.get("args"), &format!("{p}/args"), "`args`");
        let args: Vec<Expr> = args_v
            .iter()
            .enumerate()
            .map(|(i, a)| self.expr(a, &format!("{p}/args/{i}"), depth + 1))
            .collect();
        if let Some(&(_, arity, bin, _)) = LANGUAGE_OPS.iter().find(|(n, ..)| *n == name) {
            if o.contains_key("of") || o.contains_key("kwargs") {
                self.fail(
                    Code::GraphShape,
                    p,
                    format!("`{name}` takes only `args`"),
                    None,
                );
            }
            if args.len() != arity {
                self.fail(
                    Code::GraphShape,
                    &format!("{p}/args"),
                    format!("`{name}` takes {arity} argument(s), not {}", args.len()),
                    None,
                );
                return ExprKind::Error;
            }
            let mut it = args.into_iter();
            let mut next = || {
                Box::new(it.next().unwrap_or(Expr {
                    kind: ExprKind::Error,
                    span: Span::default(),
                }))
            };
            return match (name, bin) {
                (_, Some(op)) => {
                    let (lhs, rhs) = (next(), next());
                    ExprKind::Binary {
                        op,
                        op_span: Span::default(),
                        lhs,
                        rhs,
                    }
                }
                ("not", _) => ExprKind::Unary {
                    op: UnOp::Not,
                    op_span: Span::default(),
                    operand: next(),
                },
                ("neg", _) => ExprKind::Unary {
                    op: UnOp::Neg,
                    op_span: Span::default(),
                    operand: next(),
                },
                _ => {
                    let (cond, then, otherwise) = (next(), next(), next());
                    ExprKind::If {
                        cond,
                        then,
                        otherwise,
                    }
                }
            };
        }
        if !operators().iter().any(|op| op.name == name) {
            let names = operator_names();
            let help = crate::suggest::best(name, names.iter().copied())
                .map(|b| format!("write `{b}`"))
                .or_else(|| Some("use only the listed operators".into()));
            self.fail(
                Code::GraphUnknownOperator,
                &format!("{p}/op"),
                format!("unknown operator `{name}`"),
                help,
            );
            return ExprKind::Error;
        }
        let mut all: Vec<Arg> = args
            .into_iter()
            .map(|value| Arg {
                name: None,
                span: value.span,
                value,
            })
            .collect();
        if let Some(kw) = o.get("kwargs") {
            match kw.as_object() {
                Some(kw) => {
                    for (k, val) in kw {
                        let kp = format!("{p}/kwargs/{}", escape(k));
                        let value = self.expr(val, &kp, depth + 1);
                        let name =
                            self.ident(Some(&Value::String(k.clone())), &kp, "argument name");
                        all.push(Arg {
                            name,
                            span: value.span,
                            value,
                        });
                    }
                }
                None => self.fail(
                    Code::GraphShape,
                    &format!("{p}/kwargs"),
                    "expected `kwargs` (an object)",
                    None,
                ),
            }
        }
        let func = Ident {
            name: name.to_string(),
            span: Span::default(),
        };
        match o.get("of") {
            Some(of) => {
                let receiver = self.expr(of, &format!("{p}/of"), depth + 1);
                ExprKind::Method {
                    receiver: Box::new(receiver),
                    method: func,
                    args: all,
                    parens: true,
                }
            }
            None => ExprKind::Call { func, args: all },
        }
    }

    fn constraint(&mut self, v: &Value, p: &str, in_stage: bool) -> Option<Constraint> {
        let o = self.object(
            v,
            p,
            "a constraint",
            &["kind", "place", "preference", "within", "during"],
        )?;
        let kind = o.get("kind").and_then(Value::as_str);
        let (kind, field) = match kind {
            Some("require_visit") => (ConstraintKind::Pass, "place"),
            Some("forbid") => (ConstraintKind::Avoid, "place"),
            Some("prefer") => (ConstraintKind::Prefer, "preference"),
            other => {
                let help = other
                    .and_then(|k| crate::suggest::best(k, ["require_visit", "forbid", "prefer"]))
                    .map(|b| format!("write `{b}`"))
                    .or_else(|| Some("`kind` is `require_visit`, `forbid` or `prefer`".into()));
                self.fail(
                    Code::GraphShape,
                    &format!("{p}/kind"),
                    "unknown constraint kind",
                    help,
                );
                return None;
            }
        };
        let span = self.mark(p);
        let Some(value) = o.get(field) else {
            self.fail(
                Code::GraphShape,
                p,
                format!(
                    "a `{}` constraint needs `{field}`",
                    o["kind"].as_str().unwrap_or("")
                ),
                None,
            );
            return None;
        };
        let value = self.expr(value, &format!("{p}/{field}"), 1);
        let mut scopes = Vec::new();
        if let Some(w) = o.get("within") {
            let place = self.expr(w, &format!("{p}/within"), 1);
            scopes.push(Scope::Within {
                span: place.span,
                place,
            });
        }
        if let Some(d) = o.get("during") {
            if in_stage {
                self.fail(
                    Code::GraphShape,
                    &format!("{p}/during"),
                    "`during` belongs on a route-wide constraint, not on one inside a segment",
                    Some("move the constraint to the top-level `constraints`".into()),
                );
            }
            let items = self.array(Some(d), &format!("{p}/during"), "`during`");
            let stages: Vec<Ident> = items
                .iter()
                .enumerate()
                .filter_map(|(i, s)| self.ident(Some(s), &format!("{p}/during/{i}"), "segment id"))
                .collect();
            scopes.push(Scope::During {
                stages,
                span: Span::default(),
            });
        }
        Some(Constraint {
            kind,
            kind_span: span,
            value,
            scopes,
            span,
        })
    }

    fn constraints(&mut self, v: Option<&Value>, p: &str, in_stage: bool) -> Vec<Constraint> {
        let items = self.array(v, p, "`constraints`");
        items
            .iter()
            .enumerate()
            .filter_map(|(i, c)| self.constraint(c, &format!("{p}/{i}"), in_stage))
            .collect()
    }

    fn binding(&mut self, v: &Value, p: &str, name_key: &str) -> Option<Let> {
        let keys: &[&str] = if name_key == "let" {
            &["let", "value"]
        } else {
            &["name", "value"]
        };
        let o = self.object(v, p, "a binding", keys)?;
        let span = self.mark(p);
        let name = self.ident(o.get(name_key), &format!("{p}/{name_key}"), "binding name")?;
        let Some(value) = o.get("value") else {
            self.fail(Code::GraphShape, p, "a binding needs `value`", None);
            return None;
        };
        let value = self.expr(value, &format!("{p}/value"), 1);
        Some(Let { name, value, span })
    }

    fn segments(&mut self, v: Option<&Value>, p: &str) -> Vec<RouteItem> {
        let items = self.array(v, p, "`segments`");
        let mut out = Vec::new();
        for (i, s) in items.iter().enumerate() {
            let sp = format!("{p}/{i}");
            if s.get("let").is_some() {
                out.extend(self.binding(s, &sp, "let").map(RouteItem::Let));
            } else if s.get("for").is_some() {
                let Some(o) = self.object(
                    s,
                    &sp,
                    "a loop segment",
                    &["for", "in", "segments", "constraints"],
                ) else {
                    continue;
                };
                let span = self.mark(&sp);
                let var = self.ident(o.get("for"), &format!("{sp}/for"), "loop variable");
                let Some(iter) = o.get("in") else {
                    self.fail(Code::GraphShape, &sp, "a loop segment needs `in`", None);
                    continue;
                };
                let iter = self.expr(iter, &format!("{sp}/in"), 1);
                let mut body = self.segments(o.get("segments"), &format!("{sp}/segments"));
                body.extend(
                    self.constraints(o.get("constraints"), &format!("{sp}/constraints"), false)
                        .into_iter()
                        .map(RouteItem::Constraint),
                );
                if let Some(var) = var {
                    out.push(RouteItem::For(ForStages {
                        var,
                        iter,
                        body,
                        span,
                    }));
                }
            } else {
                let Some(o) = self.object(
                    s,
                    &sp,
                    "a segment",
                    &["id", "to", "bindings", "constraints"],
                ) else {
                    continue;
                };
                let span = self.mark(&sp);
                let name = match o.get("id") {
                    Some(id) => self.ident(Some(id), &format!("{sp}/id"), "segment id"),
                    None => None,
                };
                let Some(to) = o.get("to") else {
                    self.fail(
                        Code::GraphShape,
                        &sp,
                        "a segment needs `to`, its destination",
                        None,
                    );
                    continue;
                };
                let target = self.expr(to, &format!("{sp}/to"), 1);
                let mut body: Vec<StageItem> = Vec::new();
                let lets = self.array(o.get("bindings"), &format!("{sp}/bindings"), "`bindings`");
                for (j, l) in lets.iter().enumerate() {
                    body.extend(
                        self.binding(l, &format!("{sp}/bindings/{j}"), "name")
                            .map(StageItem::Let),
                    );
                }
                body.extend(
                    self.constraints(o.get("constraints"), &format!("{sp}/constraints"), true)
                        .into_iter()
                        .map(StageItem::Constraint),
                );
                out.push(RouteItem::Stage(Stage {
                    target,
                    name,
                    body,
                    span,
                }));
            }
        }
        out
    }
}

fn is_name(s: &str) -> bool {
    let mut c = s.chars();
    c.next()
        .is_some_and(|f| f.is_ascii_alphabetic() || f == '_')
        && c.all(|x| x.is_ascii_alphanumeric() || x == '_')
}

fn distance(s: &str) -> Option<(f64, DistanceUnit)> {
    debug_assert!(DISTANCE_PATTERN.ends_with("(m|cm)$"));
    let (num, unit) = if let Some(n) = s.strip_suffix("cm") {
        (n, DistanceUnit::Cm)
    } else {
        (s.strip_suffix('m')?, DistanceUnit::M)
    };
    let ok = !num.is_empty()
        && num.chars().all(|c| c.is_ascii_digit() || c == '.')
        && num.matches('.').count() <= 1
        && !num.starts_with('.')
        && !num.ends_with('.');
    ok.then(|| num.parse().ok()).flatten().map(|v| (v, unit))
}

/// Reads a graph into a program AST (spans are pointer indices) or the graph's shape errors.
fn read(graph: &Value) -> Result<(Program, Vec<String>), Vec<GraphDiagnostic>> {
    let mut r = Reader {
        pointers: Vec::new(),
        errors: Vec::new(),
    };
    let Some(o) = r.object(
        graph,
        "",
        "the intent graph",
        &["bindings", "segments", "constraints"],
    ) else {
        return Err(r.errors);
    };
    let mut items = Vec::new();
    let lets = r.array(o.get("bindings"), "/bindings", "`bindings`");
    for (i, l) in lets.iter().enumerate() {
        if let Some(l) = r.binding(l, &format!("/bindings/{i}"), "name") {
            items.push(Item::Let(l));
        }
    }
    let mut route = r.segments(o.get("segments"), "/segments");
    if !route
        .iter()
        .any(|i| matches!(i, RouteItem::Stage(_) | RouteItem::For(_)))
        && r.errors.is_empty()
    {
        r.fail(
            Code::GraphShape,
            "/segments",
            "the graph has no segment",
            Some("add a segment `{\"to\": ...}` for each destination, in order".into()),
        );
    }
    route.extend(
        r.constraints(o.get("constraints"), "/constraints", false)
            .into_iter()
            .map(RouteItem::Constraint),
    );
    items.push(Item::Route(Route {
        items: route,
        span: Span::default(),
    }));
    if !r.errors.is_empty() {
        return Err(r.errors);
    }
    Ok((
        Program {
            items,
            span: Span::default(),
        },
        r.pointers,
    ))
}

/// Every node span of a program in one fixed order (statements before their expressions,
/// receivers before arguments), so that two trees of the same shape list matching nodes.
fn spans(p: &Program) -> Vec<Span> {
    let mut out = Vec::new();
    for item in &p.items {
        match item {
            Item::Let(l) => let_spans(l, &mut out),
            Item::Route(r) => route_spans(&r.items, &mut out),
            Item::Error(_) => {}
        }
    }
    out
}

fn let_spans(l: &Let, out: &mut Vec<Span>) {
    out.push(l.span);
    expr_spans(&l.value, out);
}

fn route_spans(items: &[RouteItem], out: &mut Vec<Span>) {
    for item in items {
        match item {
            RouteItem::Stage(s) => {
                out.push(s.span);
                expr_spans(&s.target, out);
                for b in &s.body {
                    match b {
                        StageItem::Let(l) => let_spans(l, out),
                        StageItem::Constraint(c) => constraint_spans(c, out),
                        StageItem::Error(_) => {}
                    }
                }
            }
            RouteItem::Constraint(c) => constraint_spans(c, out),
            RouteItem::Let(l) => let_spans(l, out),
            RouteItem::For(f) => {
                out.push(f.span);
                expr_spans(&f.iter, out);
                route_spans(&f.body, out);
            }
            RouteItem::Error(_) | RouteItem::Ltl(_) => {}
        }
    }
}

fn constraint_spans(c: &Constraint, out: &mut Vec<Span>) {
    out.push(c.span);
    expr_spans(&c.value, out);
    for s in &c.scopes {
        if let Scope::Within { place, .. } = s {
            expr_spans(place, out);
        }
    }
}

fn expr_spans(e: &Expr, out: &mut Vec<Span>) {
    out.push(e.span);
    match &e.kind {
        ExprKind::Call { args, .. } => args.iter().for_each(|a| expr_spans(&a.value, out)),
        ExprKind::Method { receiver, args, .. } => {
            // The reader marks positional and named arguments before the receiver.
            args.iter().for_each(|a| expr_spans(&a.value, out));
            expr_spans(receiver, out);
        }
        ExprKind::Lambda { body, .. } => expr_spans(body, out),
        ExprKind::Binary { lhs, rhs, .. } => {
            expr_spans(lhs, out);
            expr_spans(rhs, out);
        }
        ExprKind::Unary { operand, .. } => expr_spans(operand, out),
        ExprKind::If {
            cond,
            then,
            otherwise,
        } => {
            expr_spans(cond, out);
            expr_spans(then, out);
            expr_spans(otherwise, out);
        }
        _ => {}
    }
}

/// Compiles an intent graph to `.m2r`: the program and its source map, or the graph's errors
/// (each with the JSON pointer of the node at fault).
pub fn graph_to_program(graph: &Value) -> Result<Compiled, Vec<GraphDiagnostic>> {
    let (ast, pointers) = read(graph)?;
    let program = print(&ast);
    let reparsed = parse(&program);
    let marked = spans(&ast);
    let real = spans(&reparsed.program);
    let map = if reparsed.errors.is_empty() && marked.len() == real.len() {
        marked
            .iter()
            .zip(real)
            .filter_map(|(m, r)| pointers.get(m.start).map(|p| (r, p.clone())))
            .collect()
    } else {
        // The printed program does not read back (a name the grammar reserves, `let route = ...`):
        // the compiler's own diagnostics say why; they then point at the whole graph.
        Vec::new()
    };
    Ok(Compiled { program, map })
}
