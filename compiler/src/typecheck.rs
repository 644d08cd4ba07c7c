//! Type checking of expressions: names in context, literals, operators, lambdas and `if`.
//! Calls live in `calls.rs`, category words in `categories.rs`.
//!
//! Checking is bidirectional: every expression is checked against a [`Slot`], which decides how a
//! bare name reads and lets a lambda know its parameter's type. One mistake gives one
//! diagnostic: an expression with an error gets [`Type::Error`], which fits every slot.

use crate::check::{Checker, Resolution};
use crate::diagnostic::{Code, Diagnostic};
use crate::resolve::{BindingKind, FrameKind};
use crate::slot::Slot;
use crate::suggest;
use m2rc_grammar::ast::{BinOp, Expr, ExprKind, Ident, UnOp};
use m2rc_stdlib::builtins::{self, Direction, Elem, Metric, Scalar, Type};
use m2rc_stdlib::vocab::{CategoryKind, Lookup};

impl Checker<'_> {
    /// Checks `e` against `slot`, reporting a mismatch; returns the expression's own type.
    pub(crate) fn check_expr(&mut self, e: &Expr, slot: Slot) -> Type {
        let ty = self.expr(e, slot);
        if !slot.accepts(ty) {
            self.mismatch(e, ty, slot);
        }
        ty
    }

    /// Infers the type of `e` in `slot` and records it, without judging the fit.
    pub(crate) fn expr(&mut self, e: &Expr, slot: Slot) -> Type {
        let ty = self.expr_inner(e, slot);
        self.types.insert(e.span, ty);
        ty
    }

    fn expr_inner(&mut self, e: &Expr, slot: Slot) -> Type {
        match &e.kind {
            ExprKind::Name(id) => self.name(id, slot),
            ExprKind::Int(_) => Type::Int,
            ExprKind::Number(_) => Type::Number,
            ExprKind::Distance { .. } => Type::Distance,
            ExprKind::Bool(_) => Type::Bool,
            ExprKind::Str(s) => {
                self.string_literal(e, s, slot);
                Type::Error
            }
            ExprKind::Call { func, args } => self.call(e, func, args),
            ExprKind::Method {
                receiver,
                method,
                args,
                ..
            } => self.method(e, receiver, method, args),
            ExprKind::Lambda { param, body } => self.lambda(e, param, body, slot),
            ExprKind::Binary {
                op,
                op_span,
                lhs,
                rhs,
            } => self.binary(e, *op, *op_span, lhs, rhs, slot),
            ExprKind::Unary {
                op,
                op_span,
                operand,
            } => self.unary(*op, *op_span, operand),
            ExprKind::If {
                cond,
                then,
                otherwise,
            } => {
                let c = self.expr(cond, Slot::Exact(Type::Bool));
                if c != Type::Bool && c != Type::Error {
                    self.report(
                        Diagnostic::new(
                            Code::ConditionNotBool,
                            cond.span,
                            format!("an `if` condition must be a Bool, found `{c}`"),
                        )
                        .help(condition_help(c)),
                    );
                }
                let a = self.expr(then, slot);
                let b = self.expr(otherwise, slot);
                match join(a, b) {
                    Some(t) => t,
                    None => {
                        self.report(
                            Diagnostic::new(
                                Code::IfBranchesDiffer,
                                e.span,
                                format!("`if` branches have different types: `{a}` and `{b}`"),
                            )
                            .label(then.span, format!("this is `{a}`"))
                            .label(otherwise.span, format!("this is `{b}`")),
                        );
                        Type::Error
                    }
                }
            }
            ExprKind::Error => Type::Error,
        }
    }

    /// Reports that `e` of type `actual` does not fit `slot`, with the most specific code.
    pub(crate) fn mismatch(&mut self, e: &Expr, actual: Type, slot: Slot) {
        if actual == Type::Error {
            return;
        }
        let want = slot.describe();
        if let Type::Set(el) = actual
            && slot.accepts(el.ty())
        {
            let d = set_where_single(e, actual, &want);
            self.report(d);
            return;
        }
        if matches!(actual, Type::Int | Type::Number) && slot.accepts(Type::Distance) {
            let mut d = Diagnostic::new(
                Code::NumberWhereDistance,
                e.span,
                format!("expected a distance, found a `{actual}` without a unit"),
            )
            .note("lengths are always written with a unit: `1.5m`, `30cm`");
            if matches!(e.kind, ExprKind::Int(_) | ExprKind::Number(_)) {
                let t = self.text(e.span).to_string();
                d = d
                    .help(format!("write `{t}m`"))
                    .suggest(e.span, format!("{t}m"));
            } else {
                d = d.help("multiply by a unit: `x * 1m`");
            }
            self.report(d);
            return;
        }
        let mut d = Diagnostic::new(
            Code::TypeMismatch,
            e.span,
            format!("expected `{want}`, found `{actual}`"),
        );
        // A room where only objects and regions fit (`next_to(kitchen)`): no other built-in says
        // the same of a whole room, so the help names what the argument takes, nothing more.
        let room = matches!(actual, Type::Room | Type::Set(Elem::Room));
        if room && (slot.accepts(Type::Object) || slot.accepts(Type::Region)) {
            let kinds = match (slot.accepts(Type::Object), slot.accepts(Type::Region)) {
                (true, true) => "an object, or a region such as a corner, a doorway or an area",
                (true, false) => "an object",
                _ => "a region such as a corner, a doorway or an area",
            };
            d = d.help(format!(
                "a room is not accepted here; this argument takes `{want}`: {kinds}"
            ));
        }
        self.report(d);
    }

    fn string_literal(&mut self, e: &Expr, s: &str, slot: Slot) {
        let word: String = s
            .trim()
            .chars()
            .map(|c| {
                if c == ' ' || c == '-' {
                    '_'
                } else {
                    c.to_ascii_lowercase()
                }
            })
            .collect();
        let ident_like = !word.is_empty()
            && word.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
            && !word.starts_with(|c: char| c.is_ascii_digit());
        let mut d = Diagnostic::new(
            Code::StringLiteral,
            e.span,
            if slot.category().is_some() {
                "categories are bare names, not strings".to_string()
            } else {
                "no built-in takes a string".to_string()
            },
        );
        if ident_like {
            d = d
                .help(format!("drop the quotes: `{word}`"))
                .suggest(e.span, word);
        }
        self.report(d);
    }

    /// A bare name, read according to its slot (see `resolve.rs` for the rules).
    fn name(&mut self, id: &Ident, slot: Slot) -> Type {
        if let Some(ctx) = slot.category() {
            let binding_is_category = self.peek_binding(&id.name) == Some(Type::Category);
            if !binding_is_category {
                return self.category_name(id, ctx);
            }
        }
        if let Some(want) = slot.enum_type()
            && let Some(w) = builtins::enum_word(&id.name)
            && w.ty == want
        {
            self.resolutions.insert(id.span, enum_resolution(&id.name));
            return w.ty;
        }
        if let Some((def, ty, kind)) = self.lookup_binding(&id.name) {
            self.resolve_binding(id, def, kind);
            return ty;
        }
        if let Some(c) = builtins::constant(&id.name) {
            if c.name == "here" && self.ctx.route_wide {
                self.report(
                    Diagnostic::new(
                        Code::HereOutsideStage,
                        id.span,
                        "`here` means nothing in a constraint that spans the whole route",
                    )
                    .note("`here` is where the current stage starts; a route-wide constraint has no current stage")
                    .help("write `start` for the start of the route, or move the constraint into a stage")
                    .suggest(id.span, "start"),
                );
            }
            self.resolutions
                .insert(id.span, Resolution::Constant(c.name));
            return c.ty;
        }
        if let Some(w) = builtins::enum_word(&id.name) {
            self.resolutions.insert(id.span, enum_resolution(&id.name));
            return w.ty;
        }
        self.unknown_name(id, slot);
        Type::Error
    }

    fn unknown_name(&mut self, id: &Ident, slot: Slot) {
        let name = id.name.as_str();
        if self.lenient && !matches!(self.vocab.lookup(name), Lookup::Unknown) {
            return;
        }
        if let Some(b) = builtins::functions(name).next() {
            let mut d = Diagnostic::new(
                Code::FunctionAsValue,
                id.span,
                format!("`{name}` is a built-in function; call it"),
            )
            .note(format!("signature: `{}`", b.signature(None)));
            // `objects` -> `objects()` only where the call's result fits: otherwise the fix would
            // trade this error for another (a set where one place is expected).
            let result = b.ret.instantiate(Elem::Place);
            if let Some(t) = result.filter(|&t| !slot.accepts(t)) {
                d = d.help(format!("`{name}()` gives a `{t}`, which does not fit here"));
            } else if b
                .params
                .iter()
                .all(|p| p.req != builtins::Requirement::Required)
            {
                d = d
                    .help(format!("write `{name}()`"))
                    .suggest(id.span, format!("{name}()"));
            }
            self.report(d);
            return;
        }
        // A category word where a place or set is expected: the classic `go bed`.
        let cat = match self.vocab.lookup(name) {
            Lookup::Found(k) => Some((name.to_string(), k)),
            Lookup::Synonym(c, k) | Lookup::NotInMap(c, k) => Some((c, k)),
            _ => None,
        };
        if let Some((cat, kind)) = cat {
            let (query, what) = match kind {
                CategoryKind::Object => ("objects", "an object category"),
                CategoryKind::Room => ("rooms", "a room category"),
            };
            let set = format!("{query}({cat})");
            let mut d = Diagnostic::new(
                Code::CategoryAsValue,
                id.span,
                format!("`{name}` is {what}, not a place: write `{set}`"),
            );
            if slot.wants_single_place() {
                d = d
                    .help(format!(
                        "`{set}` is the set of all of them; pick one with `.only()` (exactly one must exist) or `.nearest()`"
                    ))
                    .suggest(id.span, format!("{set}.only()"))
                    .suggest(id.span, format!("{set}.nearest()"));
            } else {
                d = d.help(format!("write `{set}`")).suggest(id.span, set);
            }
            self.report(d);
            return;
        }
        if let Some((def, frame)) = self.retired_binding(name) {
            let region = match frame {
                FrameKind::Stage => "the stage body",
                FrameKind::For => "the `for` body",
                _ => "its block",
            };
            self.report(
                Diagnostic::new(
                    Code::OutOfScope,
                    id.span,
                    format!("`{name}` is not visible here"),
                )
                .label(def, format!("`{name}` is bound here, inside {region}"))
                .note(format!(
                    "a binding made inside {region} is visible only there"
                ))
                .help("move the `let` before the route (or to the route level) to share it"),
            );
            return;
        }
        let visible = self.visible_names();
        let mut cands: Vec<&str> = visible.iter().map(String::as_str).collect();
        cands.extend(builtins::CONSTANTS.iter().map(|c| c.name));
        let mut d = Diagnostic::new(Code::UnknownName, id.span, format!("unknown name `{name}`"));
        if let Some(best) = suggest::best(name, cands.iter().copied()) {
            // The fix will use that binding: do not also call it unused.
            let best = best.to_string();
            self.lookup_binding(&best);
            d = d
                .help(format!("did you mean `{best}`?"))
                .suggest(id.span, best);
        } else if let Some(cat) = suggest::best(name, self.vocab.all().map(|(c, _)| c)) {
            let query = match self.vocab.kind(cat) {
                Some(CategoryKind::Room) => "rooms",
                _ => "objects",
            };
            d = d
                .help(format!(
                    "did you mean the category `{cat}`? write `{query}({cat})`"
                ))
                .suggest(id.span, format!("{query}({cat})"));
        } else if visible.is_empty() {
            d = d.note("names are bound with `let name = ...` before they are used");
        }
        self.report(d);
    }

    fn lambda(&mut self, e: &Expr, param: &Ident, body: &Expr, slot: Slot) -> Type {
        let Some((elem, pred)) = slot.lambda() else {
            self.report(
                Diagnostic::new(
                    Code::UnexpectedLambda,
                    e.span,
                    format!(
                        "a lambda is not allowed here: expected `{}`",
                        slot.describe()
                    ),
                )
                .note("lambdas are arguments of `where`, `max_by`, `min_by` and `sorted_by`"),
            );
            self.push_frame(FrameKind::Lambda);
            self.bind(param, param.span, Type::Error, BindingKind::LambdaParam);
            self.expr(body, Slot::Any);
            self.pop_frame();
            return Type::Error;
        };
        self.push_frame(FrameKind::Lambda);
        self.bind(param, param.span, elem.ty(), BindingKind::LambdaParam);
        self.resolutions.insert(
            param.span,
            Resolution::Binding {
                def: param.span,
                kind: BindingKind::LambdaParam,
            },
        );
        let body_slot = if pred {
            Slot::Exact(Type::Bool)
        } else {
            Slot::Any
        };
        let b = self.expr(body, body_slot);
        self.pop_frame();
        if b == Type::Error {
            return Type::Error;
        }
        let ok = if pred {
            b == Type::Bool
        } else {
            b.is_orderable()
        };
        if !ok {
            let (want, help) = if pred {
                ("Bool", condition_help(b))
            } else {
                (
                    "Int, Number or Distance",
                    "a ranking key is a number: a count, an area or a distance".to_string(),
                )
            };
            self.report(
                Diagnostic::new(
                    Code::LambdaBody,
                    body.span,
                    format!("the lambda body must be {want}, found `{b}`"),
                )
                .note(format!("`{}` is a `{}` here", param.name, elem.name()))
                .help(help),
            );
            return Type::Error;
        }
        Type::Fn(elem, Scalar::from_type(b).unwrap_or(Scalar::Bool))
    }

    fn unary(&mut self, op: UnOp, op_span: m2rc_grammar::ast::Span, operand: &Expr) -> Type {
        match op {
            UnOp::Not => {
                let t = self.expr(operand, Slot::Exact(Type::Bool));
                if t == Type::Bool || t == Type::Error {
                    return Type::Bool;
                }
                self.report(
                    Diagnostic::new(
                        Code::OperatorTypes,
                        operand.span,
                        format!("`not` needs a Bool, found `{t}`"),
                    )
                    .label(op_span, "this operator"),
                );
                Type::Error
            }
            UnOp::Neg => {
                let t = self.expr(operand, Slot::Any);
                if t.is_orderable() || t == Type::Error {
                    return t;
                }
                self.report(
                    Diagnostic::new(
                        Code::OperatorTypes,
                        operand.span,
                        format!("cannot negate a `{t}`"),
                    )
                    .label(op_span, "this operator"),
                );
                Type::Error
            }
        }
    }

    fn binary(
        &mut self,
        e: &Expr,
        op: BinOp,
        op_span: m2rc_grammar::ast::Span,
        lhs: &Expr,
        rhs: &Expr,
        slot: Slot,
    ) -> Type {
        if op == BinOp::Union {
            return self.union(e, op_span, lhs, rhs, slot);
        }
        let operand_slot = match op {
            BinOp::And | BinOp::Or => Slot::Exact(Type::Bool),
            _ => Slot::Any,
        };
        let a = self.expr(lhs, operand_slot);
        let b = self.expr(rhs, operand_slot);
        if a == Type::Error || b == Type::Error {
            return match op {
                BinOp::And
                | BinOp::Or
                | BinOp::Eq
                | BinOp::Ne
                | BinOp::Lt
                | BinOp::Le
                | BinOp::Gt
                | BinOp::Ge => Type::Bool,
                _ => Type::Error,
            };
        }
        let sym = op_symbol(op);
        match op {
            BinOp::And | BinOp::Or => {
                for (side, t) in [(lhs, a), (rhs, b)] {
                    if t != Type::Bool {
                        self.report(
                            Diagnostic::new(
                                Code::OperatorTypes,
                                side.span,
                                format!("`{sym}` needs Bool operands, found `{t}`"),
                            )
                            .label(op_span, "this operator")
                            .help(condition_help(t)),
                        );
                    }
                }
                Type::Bool
            }
            BinOp::Eq | BinOp::Ne | BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge => {
                let ordered = !matches!(op, BinOp::Eq | BinOp::Ne);
                let comparable = if ordered {
                    (numeric(a) && numeric(b)) || (a == Type::Distance && b == Type::Distance)
                } else {
                    a.is_subtype_of(b) || b.is_subtype_of(a) || (numeric(a) && numeric(b))
                };
                if !comparable {
                    let mut d = Diagnostic::new(
                        Code::IncomparableTypes,
                        e.span,
                        format!("cannot compare `{a}` with `{b}` using `{sym}`"),
                    )
                    .label(lhs.span, format!("this is `{a}`"))
                    .label(rhs.span, format!("this is `{b}`"));
                    if let Some((lit, _)) = [(rhs, a), (lhs, b)].into_iter().find(|(x, other)| {
                        *other == Type::Distance
                            && matches!(x.kind, ExprKind::Int(_) | ExprKind::Number(_))
                    }) {
                        let t = self.text(lit.span).to_string();
                        d = d
                            .help(format!("give the number a unit: `{t}m`"))
                            .suggest(lit.span, format!("{t}m"));
                    } else if ordered && !(a.is_orderable() && b.is_orderable()) {
                        d = d.note("only numbers and distances can be ordered");
                    }
                    self.report(d);
                }
                Type::Bool
            }
            BinOp::Add | BinOp::Sub | BinOp::Mul => match arith(op, a, b) {
                Some(t) => t,
                None => {
                    let mut d = Diagnostic::new(
                        Code::OperatorTypes,
                        e.span,
                        format!("cannot apply `{sym}` to `{a}` and `{b}`"),
                    )
                    .label(op_span, "this operator");
                    if (a == Type::Distance && numeric(b)) || (b == Type::Distance && numeric(a)) {
                        d = d.help("give the number a unit, e.g. `0.5m`");
                    } else if a.is_set() || b.is_set() {
                        d = d.help("to combine sets write `a | b`; to count, `.count()`");
                    }
                    self.report(d);
                    Type::Error
                }
            },
            BinOp::Union => Type::Error,
        }
    }

    /// `a | b`: a union of categories in a category slot (or when a side is a bare category
    /// word), otherwise a union of sets.
    fn union(
        &mut self,
        e: &Expr,
        op_span: m2rc_grammar::ast::Span,
        lhs: &Expr,
        rhs: &Expr,
        slot: Slot,
    ) -> Type {
        let is_category_word = |c: &Self, x: &Expr| match &x.kind {
            ExprKind::Name(id) => {
                c.peek_binding(&id.name).is_none()
                    && !matches!(c.vocab.lookup(&id.name), Lookup::Unknown)
            }
            _ => false,
        };
        let (lhs_cat, rhs_cat) = (is_category_word(self, lhs), is_category_word(self, rhs));
        let cat_ctx = slot.category().or_else(|| {
            (lhs_cat && rhs_cat).then_some(crate::slot::CatCtx {
                want: None,
                func: None,
            })
        });
        let any_cat = crate::slot::CatCtx {
            want: None,
            func: None,
        };
        let word_slot = |ctx: crate::slot::CatCtx| Slot::Alts {
            alts: &[m2rc_stdlib::builtins::Ty::Is(Type::Category)],
            t: Elem::Place,
            cat: Some(crate::slot::CatCtx { func: None, ..ctx }),
        };
        if let Some(ctx) = cat_ctx {
            let a = self.check_expr(lhs, word_slot(ctx));
            let b = self.check_expr(rhs, word_slot(ctx));
            if a == Type::Error || b == Type::Error {
                return Type::Error;
            }
            return Type::Category;
        }
        // One side is a category word, the other something else: read the word as a category
        // and let the types decide (a set on the other side is E0215).
        let a = if lhs_cat {
            self.expr(lhs, word_slot(any_cat))
        } else {
            self.expr(lhs, Slot::Any)
        };
        let b = if rhs_cat {
            self.expr(rhs, word_slot(any_cat))
        } else {
            self.expr(rhs, Slot::Any)
        };
        // Places and sets of places unite into a set: `kitchen_room | living`, `[a, b]`.
        let elem = |t: Type| match t {
            Type::Set(e) => Some(e),
            other => other.as_place(),
        };
        match (a, b) {
            (Type::Error, _) | (_, Type::Error) => Type::Error,
            (Type::Set(x), Type::Set(y)) => Type::Set(x.join(y)),
            (Type::Category, Type::Category) => Type::Category,
            (x, y) if elem(x).is_some() && elem(y).is_some() => match (elem(x), elem(y)) {
                (Some(p), Some(q)) => Type::Set(p.join(q)),
                _ => Type::Error,
            },
            _ => {
                let mixed =
                    (a == Type::Category && b.is_set()) || (b == Type::Category && a.is_set());
                let code = if mixed {
                    Code::UnionMismatch
                } else {
                    Code::OperatorTypes
                };
                let mut d = Diagnostic::new(
                    code,
                    e.span,
                    format!("cannot take the union of `{a}` and `{b}`"),
                )
                .label(lhs.span, format!("this is `{a}`"))
                .label(rhs.span, format!("this is `{b}`"))
                .label(op_span, "this operator");
                if mixed {
                    d = d.help("unite categories inside the query, `objects(a | b)`, or unite two sets, `objects(a) | objects(b)`");
                } else if a.is_place() || b.is_place() {
                    d = d.help("`|` unites sets and categories; single places cannot be united");
                }
                self.report(d);
                Type::Error
            }
        }
    }
}

fn enum_resolution(word: &str) -> Resolution {
    match word {
        "clockwise" => Resolution::Direction(Direction::Clockwise),
        "counterclockwise" => Resolution::Direction(Direction::Counterclockwise),
        "travel" => Resolution::Metric(Metric::Travel),
        _ => Resolution::Metric(Metric::Straight),
    }
}

pub(crate) fn set_where_single(e: &Expr, actual: Type, want: &str) -> Diagnostic {
    Diagnostic::new(
        Code::SetWhereSingle,
        e.span,
        format!("expected `{want}`, found the set `{actual}`"),
    )
    .note("a set never stands for one of its elements: choose one explicitly")
    .help("take the only element with `.only()` (grounding fails unless exactly one exists), or rank with `.nearest()`, `.farthest()`, `.largest()`, ...")
    .suggest(m2rc_grammar::ast::Span::new(e.span.end, e.span.end), ".only()")
    .suggest(m2rc_grammar::ast::Span::new(e.span.end, e.span.end), ".nearest()")
}

fn condition_help(t: Type) -> String {
    match t {
        Type::Set(_) => "test a set with `.exists()`, `.is_empty()` or `.count() > 0`".to_string(),
        Type::Int | Type::Number => "compare the number, e.g. `n > 0`".to_string(),
        _ => "a condition is a comparison or a predicate such as `o.near(x)`".to_string(),
    }
}

fn numeric(t: Type) -> bool {
    matches!(t, Type::Int | Type::Number)
}

fn arith(op: BinOp, a: Type, b: Type) -> Option<Type> {
    match (op, a, b) {
        (_, Type::Int, Type::Int) => Some(Type::Int),
        (_, x, y) if numeric(x) && numeric(y) => Some(Type::Number),
        (BinOp::Add | BinOp::Sub, Type::Distance, Type::Distance) => Some(Type::Distance),
        (BinOp::Mul, Type::Distance, y) if numeric(y) => Some(Type::Distance),
        (BinOp::Mul, x, Type::Distance) if numeric(x) => Some(Type::Distance),
        _ => None,
    }
}

/// The least common type of two branches, if they have one.
pub(crate) fn join(a: Type, b: Type) -> Option<Type> {
    if a == Type::Error {
        return Some(b);
    }
    if b == Type::Error || b.is_subtype_of(a) {
        return Some(a);
    }
    if a.is_subtype_of(b) {
        return Some(b);
    }
    match (a, b) {
        (Type::Set(x), Type::Set(y)) => Some(Type::Set(x.join(y))),
        (x, y) if x.is_place() && y.is_place() => Some(Type::Place),
        _ => None,
    }
}

fn op_symbol(op: BinOp) -> &'static str {
    match op {
        BinOp::Or => "or",
        BinOp::And => "and",
        BinOp::Eq => "==",
        BinOp::Ne => "!=",
        BinOp::Lt => "<",
        BinOp::Le => "<=",
        BinOp::Gt => ">",
        BinOp::Ge => ">=",
        BinOp::Union => "|",
        BinOp::Add => "+",
        BinOp::Sub => "-",
        BinOp::Mul => "*",
    }
}
