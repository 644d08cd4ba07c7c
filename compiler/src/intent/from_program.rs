//! A `.m2r` program as an intent graph: the gold graph of an episode is its gold program read
//! this way, and a suggestion of the compiler becomes a JSON patch by reading the fixed
//! expression back.

use super::ops::bin_op_name;
use m2rc_grammar::ast::*;
use m2rc_grammar::{format_f64, parse};
use serde_json::{Map, Value, json};

/// Why a program has no intent graph.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FromProgramError {
    #[error("the program does not parse: {0}")]
    Syntax(String),
    #[error("{0} has no form in the intent graph")]
    Unsupported(&'static str),
}

/// The intent graph of a program's source.
pub fn program_to_graph(source: &str) -> Result<Value, FromProgramError> {
    let parsed = parse(source);
    if let Some(e) = parsed.errors.first() {
        return Err(FromProgramError::Syntax(e.message.clone()));
    }
    let mut bindings = Vec::new();
    let mut route: Option<&Route> = None;
    for item in &parsed.program.items {
        match item {
            Item::Let(l) => bindings.push(binding(l)?),
            Item::Route(r) if route.is_none() => route = Some(r),
            Item::Route(_) => return Err(FromProgramError::Unsupported("a second route block")),
            Item::Error(_) => return Err(FromProgramError::Unsupported("unreadable source")),
        }
    }
    let route = route.ok_or(FromProgramError::Unsupported("a program without a route"))?;
    let (segments, constraints) = route_items(&route.items)?;
    let mut out = Map::new();
    if !bindings.is_empty() {
        out.insert("bindings".into(), Value::Array(bindings));
    }
    out.insert("segments".into(), Value::Array(segments));
    if !constraints.is_empty() {
        out.insert("constraints".into(), Value::Array(constraints));
    }
    Ok(Value::Object(out))
}

fn binding(l: &Let) -> Result<Value, FromProgramError> {
    Ok(json!({"name": l.name.name, "value": expr_to_graph(&l.value)?}))
}

type Items = (Vec<Value>, Vec<Value>);

fn route_items(items: &[RouteItem]) -> Result<Items, FromProgramError> {
    let mut segments = Vec::new();
    let mut constraints = Vec::new();
    for item in items {
        match item {
            RouteItem::Stage(s) => segments.push(stage(s)?),
            RouteItem::Constraint(c) => constraints.push(constraint(c)?),
            RouteItem::Let(l) => {
                segments.push(json!({"let": l.name.name, "value": expr_to_graph(&l.value)?}))
            }
            RouteItem::For(f) => {
                let (inner, cons) = route_items(&f.body)?;
                let mut o = Map::new();
                o.insert("for".into(), json!(f.var.name));
                o.insert("in".into(), expr_to_graph(&f.iter)?);
                o.insert("segments".into(), Value::Array(inner));
                if !cons.is_empty() {
                    o.insert("constraints".into(), Value::Array(cons));
                }
                segments.push(Value::Object(o));
            }
            RouteItem::Ltl(_) => return Err(FromProgramError::Unsupported("an LTL route")),
            RouteItem::Error(_) => return Err(FromProgramError::Unsupported("unreadable source")),
        }
    }
    Ok((segments, constraints))
}

fn stage(s: &Stage) -> Result<Value, FromProgramError> {
    let mut o = Map::new();
    if let Some(n) = &s.name {
        o.insert("id".into(), json!(n.name));
    }
    o.insert("to".into(), expr_to_graph(&s.target)?);
    let mut lets = Vec::new();
    let mut cons = Vec::new();
    for item in &s.body {
        match item {
            StageItem::Constraint(c) => cons.push(constraint(c)?),
            StageItem::Let(l) => lets.push(binding(l)?),
            StageItem::Error(_) => return Err(FromProgramError::Unsupported("unreadable source")),
        }
    }
    if !lets.is_empty() {
        o.insert("bindings".into(), Value::Array(lets));
    }
    if !cons.is_empty() {
        o.insert("constraints".into(), Value::Array(cons));
    }
    Ok(Value::Object(o))
}

fn constraint(c: &Constraint) -> Result<Value, FromProgramError> {
    let (kind, field) = match c.kind {
        ConstraintKind::Pass => ("require_visit", "place"),
        ConstraintKind::Avoid => ("forbid", "place"),
        ConstraintKind::Prefer => ("prefer", "preference"),
    };
    let mut o = Map::new();
    o.insert("kind".into(), json!(kind));
    o.insert(field.into(), expr_to_graph(&c.value)?);
    for scope in &c.scopes {
        match scope {
            Scope::Within { place, .. } => {
                o.insert("within".into(), expr_to_graph(place)?);
            }
            Scope::During { stages, .. } => {
                let names: Vec<&str> = stages.iter().map(|s| s.name.as_str()).collect();
                o.insert("during".into(), json!(names));
            }
        }
    }
    Ok(Value::Object(o))
}

fn args_to_graph(args: &[Arg], o: &mut Map<String, Value>) -> Result<(), FromProgramError> {
    let mut pos = Vec::new();
    let mut named = Map::new();
    for a in args {
        let v = expr_to_graph(&a.value)?;
        match &a.name {
            Some(n) => {
                named.insert(n.name.clone(), v);
            }
            None => pos.push(v),
        }
    }
    if !pos.is_empty() {
        o.insert("args".into(), Value::Array(pos));
    }
    if !named.is_empty() {
        o.insert("kwargs".into(), Value::Object(named));
    }
    Ok(())
}

/// One expression as an intent-graph value.
pub fn expr_to_graph(e: &Expr) -> Result<Value, FromProgramError> {
    Ok(match &e.kind {
        ExprKind::Name(id) => json!(id.name),
        ExprKind::Int(i) => json!(i),
        ExprKind::Number(x) => {
            // Keep a float a float (`2.0` is a Number, `2` an Int).
            let text = format_f64(*x);
            serde_json::from_str(&text).unwrap_or(json!(x))
        }
        ExprKind::Distance { value, unit } => {
            let u = match unit {
                DistanceUnit::M => "m",
                DistanceUnit::Cm => "cm",
            };
            json!(format!("{value}{u}"))
        }
        ExprKind::Bool(b) => json!(b),
        ExprKind::Str(_) => return Err(FromProgramError::Unsupported("a string literal")),
        ExprKind::Call { func, args } => {
            let mut o = Map::new();
            o.insert("op".into(), json!(func.name));
            args_to_graph(args, &mut o)?;
            Value::Object(o)
        }
        ExprKind::Method {
            receiver,
            method,
            args,
            ..
        } => {
            let mut o = Map::new();
            o.insert("op".into(), json!(method.name));
            o.insert("of".into(), expr_to_graph(receiver)?);
            args_to_graph(args, &mut o)?;
            Value::Object(o)
        }
        ExprKind::Lambda { param, body } => {
            json!({"lambda": param.name, "body": expr_to_graph(body)?})
        }
        ExprKind::Binary { op, lhs, rhs, .. } => {
            json!({"op": bin_op_name(*op), "args": [expr_to_graph(lhs)?, expr_to_graph(rhs)?]})
        }
        ExprKind::Unary { op, operand, .. } => {
            let name = match op {
                UnOp::Not => "not",
                UnOp::Neg => "neg",
            };
            json!({"op": name, "args": [expr_to_graph(operand)?]})
        }
        ExprKind::If {
            cond,
            then,
            otherwise,
        } => json!({"op": "if", "args": [
            expr_to_graph(cond)?, expr_to_graph(then)?, expr_to_graph(otherwise)?
        ]}),
        ExprKind::Error => return Err(FromProgramError::Unsupported("unreadable source")),
    })
}
