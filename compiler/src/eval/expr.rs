//! Expressions: names, literals, operators, conditionals, lambdas, and argument binding for calls.

use super::codes;
use super::value::{Lambda, PlaceVal, Value};
use super::{Grounder, Problem};
use crate::check::Resolution;
use crate::ir::Direction;
use m2rc_grammar::ast::{Arg, BinOp, DistanceUnit, Expr, ExprKind, UnOp};
use m2rc_stdlib::builtins::{self, Builtin, DefaultValue, Elem, Metric, Requirement, Ty, Type};
use std::rc::Rc;

impl Grounder<'_, '_> {
    pub(super) fn eval(&mut self, e: &Expr) -> Value {
        if self.memo.active() && matches!(e.kind, ExprKind::Call { .. } | ExprKind::Method { .. }) {
            let info = self.memo.free_info(e);
            if let Some(key) = self.memo_key(e, &info) {
                if let Some(v) = self.memo.get(&key) {
                    return v;
                }
                let v = self.eval_uncached(e);
                self.memo.insert(key, v.clone());
                return v;
            }
        }
        self.eval_uncached(e)
    }

    fn eval_uncached(&mut self, e: &Expr) -> Value {
        match &e.kind {
            ExprKind::Name(id) => self.name(&id.name),
            ExprKind::Int(i) => Value::Int(*i),
            ExprKind::Number(x) => Value::Number(*x),
            ExprKind::Distance { value, unit } => Value::Distance(match unit {
                DistanceUnit::M => *value,
                DistanceUnit::Cm => *value / 100.0,
            }),
            ExprKind::Bool(b) => Value::Bool(*b),
            ExprKind::Str(s) => Value::Str(s.clone()),
            ExprKind::Call { func, args } => self.call(e, &func.name, None, args),
            ExprKind::Method {
                receiver,
                method,
                args,
                ..
            } => {
                let recv = self.eval(receiver);
                if matches!(recv, Value::Unknown) {
                    return Value::Unknown;
                }
                self.call(e, &method.name, Some(recv), args)
            }
            ExprKind::Lambda { param, body } => Value::Lambda(Rc::new(Lambda {
                param: param.name.clone(),
                body: self.memo.lambda_body(body),
            })),
            ExprKind::Binary { op, lhs, rhs, .. } => self.binary(e, *op, lhs, rhs),
            ExprKind::Unary { op, operand, .. } => match (op, self.eval(operand)) {
                (UnOp::Not, Value::Bool(b)) => Value::Bool(!b),
                (UnOp::Neg, Value::Int(i)) => Value::Int(i.saturating_neg()),
                (UnOp::Neg, Value::Number(x)) => Value::Number(-x),
                (UnOp::Neg, Value::Distance(x)) => Value::Distance(-x),
                (_, Value::Unknown) => Value::Unknown,
                _ => self.unsupported(e),
            },
            ExprKind::If {
                cond,
                then,
                otherwise,
            } => match self.eval(cond) {
                Value::Bool(true) => self.eval(then),
                Value::Bool(false) => self.eval(otherwise),
                Value::Unknown => Value::Unknown,
                _ => self.unsupported(cond),
            },
            ExprKind::Error => Value::Unknown,
        }
    }

    pub(super) fn unsupported(&mut self, e: &Expr) -> Value {
        self.report(Problem::error(codes::UNSUPPORTED, e.span, "this expression cannot be evaluated").note(
            "the checker accepted it, so this is a bug in m2rc: please report it with the program",
        ))
    }

    fn name(&mut self, name: &str) -> Value {
        if let Some(v) = self.lookup(name) {
            return v.clone();
        }
        match name {
            "start" => Value::Place(self.start.clone()),
            "here" => Value::Place(self.here.clone()),
            "clockwise" => Value::Direction(Direction::Clockwise),
            "counterclockwise" => Value::Direction(Direction::Counterclockwise),
            "straight" => Value::Travel(false),
            "travel" => Value::Travel(true),
            other => Value::Category(vec![other.to_string()]),
        }
    }

    /// A name in a `Category` slot is a category even when a binding has the same name.
    fn category(&mut self, e: &Expr) -> Value {
        match &e.kind {
            ExprKind::Name(id) => match self.resolutions.and_then(|r| r.get(&id.span)) {
                Some(Resolution::Category { name, .. }) => Value::Category(vec![name.clone()]),
                _ => Value::Category(vec![id.name.clone()]),
            },
            ExprKind::Binary {
                op: BinOp::Union,
                lhs,
                rhs,
                ..
            } => match (self.category(lhs), self.category(rhs)) {
                (Value::Category(mut a), Value::Category(b)) => {
                    for c in b {
                        if !a.contains(&c) {
                            a.push(c);
                        }
                    }
                    Value::Category(a)
                }
                _ => Value::Unknown,
            },
            _ => self.eval(e),
        }
    }

    /// Enumeration words in their slots, even when shadowed by a binding.
    fn enum_word(&mut self, e: &Expr) -> Value {
        if let ExprKind::Name(id) = &e.kind {
            match id.name.as_str() {
                "clockwise" => return Value::Direction(Direction::Clockwise),
                "counterclockwise" => return Value::Direction(Direction::Counterclockwise),
                "straight" => return Value::Travel(false),
                "travel" => return Value::Travel(true),
                _ => {}
            }
        }
        self.eval(e)
    }

    fn binary(&mut self, e: &Expr, op: BinOp, lhs: &Expr, rhs: &Expr) -> Value {
        // Short-circuit logic, so `r.exists() and r.only() ...` patterns do not fail needlessly.
        if matches!(op, BinOp::And | BinOp::Or) {
            return match (op, self.eval(lhs)) {
                (BinOp::And, Value::Bool(false)) => Value::Bool(false),
                (BinOp::Or, Value::Bool(true)) => Value::Bool(true),
                (_, Value::Bool(_)) => match self.eval(rhs) {
                    Value::Bool(b) => Value::Bool(b),
                    Value::Unknown => Value::Unknown,
                    _ => self.unsupported(rhs),
                },
                (_, Value::Unknown) => Value::Unknown,
                _ => self.unsupported(lhs),
            };
        }
        let (a, b) = (self.eval(lhs), self.eval(rhs));
        if matches!(a, Value::Unknown) || matches!(b, Value::Unknown) {
            return Value::Unknown;
        }
        use Value::*;
        match op {
            BinOp::Eq | BinOp::Ne => {
                let eq = match (&a, &b) {
                    (Place(x), Place(y)) => Some(x.same(y)),
                    (Bool(x), Bool(y)) => Some(x == y),
                    (Category(x), Category(y)) => Some(x == y),
                    (Direction(x), Direction(y)) => Some(x == y),
                    (Set(x), Set(y)) => {
                        Some(x.len() == y.len() && x.iter().zip(y).all(|(p, q)| p.same(q)))
                    }
                    _ => match (a.number(), b.number()) {
                        (Some(x), Some(y)) => Some((x - y).abs() <= 1e-9),
                        _ => None,
                    },
                };
                match eq {
                    Some(v) => Bool(if op == BinOp::Eq { v } else { !v }),
                    None => self.unsupported(e),
                }
            }
            BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge => match (a.number(), b.number()) {
                (Some(x), Some(y)) => Bool(match op {
                    BinOp::Lt => x < y,
                    BinOp::Le => x <= y,
                    BinOp::Gt => x > y,
                    _ => x >= y,
                }),
                _ => self.unsupported(e),
            },
            BinOp::Union => match (a, b) {
                (Category(mut x), Category(y)) => {
                    x.extend(y.into_iter().filter(|c| !x.contains(c)).collect::<Vec<_>>());
                    Category(x)
                }
                (x, y) => match (x.places(), y.places()) {
                    (Some(mut x), Some(y)) => {
                        for p in y {
                            if !x.iter().any(|q| q.same(&p)) {
                                x.push(p);
                            }
                        }
                        Set(x)
                    }
                    _ => self.unsupported(e),
                },
            },
            BinOp::Add | BinOp::Sub => {
                let sign = if op == BinOp::Add { 1.0 } else { -1.0 };
                match (a, b) {
                    (Int(x), Int(y)) => Int(if op == BinOp::Add {
                        x.saturating_add(y)
                    } else {
                        x.saturating_sub(y)
                    }),
                    (Distance(x), Distance(y)) => Distance(x + sign * y),
                    (x, y) => match (x.number(), y.number()) {
                        (Some(x), Some(y)) => Number(x + sign * y),
                        _ => self.unsupported(e),
                    },
                }
            }
            BinOp::Mul => match (a, b) {
                (Int(x), Int(y)) => Int(x.saturating_mul(y)),
                (Distance(x), y) | (y, Distance(x)) => match y.number() {
                    Some(k) => Distance(x * k),
                    None => self.unsupported(e),
                },
                (x, y) => match (x.number(), y.number()) {
                    (Some(x), Some(y)) => Number(x * y),
                    _ => self.unsupported(e),
                },
            },
            BinOp::And | BinOp::Or => Value::Unknown,
        }
    }

    /// Applies a lambda to one element. A lambda is only ever an argument of the call that
    /// applies it, so the scopes it was written in are still the current ones: the parameter is
    /// pushed on top of them.
    pub(super) fn apply(&mut self, f: &Lambda, arg: PlaceVal) -> Value {
        self.scopes.push((f.param.clone(), Value::Place(arg)));
        self.memo.params.push(f.param.clone());
        let body = f.body.clone();
        let v = self.eval(&body);
        self.memo.params.pop();
        self.scopes.pop();
        v
    }

    /// Finds the built-in row and binds the arguments to its parameters (defaults filled in).
    pub(super) fn bind_args(
        &mut self,
        name: &str,
        recv: Option<&Value>,
        args: &[Arg],
    ) -> Option<(&'static Builtin, Vec<Option<Value>>)> {
        let row = match recv {
            None => builtins::functions(name).next()?,
            Some(v) => {
                receiver_types(v)
                    .into_iter()
                    .find_map(|t| builtins::method_for(name, t))?
                    .0
            }
        };
        let mut slots: Vec<Option<&Expr>> = vec![None; row.params.len()];
        let mut next = 0;
        for a in args {
            let i = match &a.name {
                Some(n) => row.params.iter().position(|p| p.name == n.name)?,
                None => {
                    let i = next;
                    next += 1;
                    i
                }
            };
            if i < slots.len() {
                slots[i] = Some(&a.value);
            }
        }
        let mut out = Vec::with_capacity(slots.len());
        for (p, slot) in row.params.iter().zip(slots) {
            let v = match slot {
                Some(e) if p.ty.contains(&Ty::Is(Type::Category)) => Some(self.category(e)),
                Some(e)
                    if p.ty
                        .iter()
                        .any(|t| matches!(t, Ty::Is(Type::Direction | Type::Metric))) =>
                {
                    Some(self.enum_word(e))
                }
                Some(e) => Some(self.eval(e)),
                None => match p.req {
                    Requirement::Default(DefaultValue::Here) => {
                        Some(Value::Place(self.here.clone()))
                    }
                    Requirement::Default(DefaultValue::Distance(d)) => Some(Value::Distance(d)),
                    Requirement::Default(DefaultValue::Direction(d)) => {
                        Some(Value::Direction(match d {
                            builtins::Direction::Clockwise => Direction::Clockwise,
                            builtins::Direction::Counterclockwise => Direction::Counterclockwise,
                        }))
                    }
                    Requirement::Default(DefaultValue::Metric(m)) => {
                        Some(Value::Travel(m == Metric::Travel))
                    }
                    _ => None,
                },
            };
            out.push(v);
        }
        Some((row, out))
    }
}

/// The static types a runtime value may have, most specific first (an empty set fits any set type).
fn receiver_types(v: &Value) -> Vec<Type> {
    let elem = |p: &PlaceVal| match p {
        PlaceVal::Object(_) => Elem::Object,
        PlaceVal::Room(_) => Elem::Room,
        PlaceVal::Region(_) => Elem::Region,
    };
    match v {
        Value::Place(p) => vec![elem(p).ty(), Type::Place],
        Value::Set(s) if s.is_empty() => [Elem::Object, Elem::Room, Elem::Region, Elem::Place]
            .into_iter()
            .map(Type::Set)
            .collect(),
        Value::Set(s) => {
            let e = s.iter().map(elem).reduce(Elem::join).unwrap_or(Elem::Place);
            vec![Type::Set(e), Type::Set(Elem::Place)]
        }
        Value::Int(_) => vec![Type::Int],
        Value::Number(_) => vec![Type::Number],
        Value::Distance(_) => vec![Type::Distance],
        Value::Bool(_) => vec![Type::Bool],
        _ => vec![],
    }
}
