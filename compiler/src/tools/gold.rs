//! A gold program as the tool calls that build it: every operator node of its intent graph
//! becomes one query (identical nodes once), each binding is the handle of its value, and the
//! route is put together with the builders. The `--llm gold` ToolCall row replays it, so the row's
//! ceiling is what this representation can say under the reference's budgets.

use super::session::canonical;
use super::spec::LANGUAGE_TOOLS;
use crate::intent::from_program::{FromProgramError, program_to_graph};
use crate::intent::ops::operators;
use serde_json::{Map, Value, json};
use std::collections::BTreeMap;

/// One call of the gold sequence. Arguments that are earlier results are written `@@k` (the
/// k-th call's handle), which [`GoldCall::bind`] replaces with the handle the session gave.
#[derive(Clone, Debug, PartialEq)]
pub struct GoldCall {
    pub name: String,
    pub args: Value,
    /// The calls whose handles this one takes.
    pub deps: Vec<usize>,
    /// 0 for a call that needs no earlier result, else one more than its deepest dependency:
    /// the gold model sends all calls of one level in one turn.
    pub level: usize,
}

/// An argument of a gold call before binding.
pub type GoldArg = Value;

fn reference(k: usize) -> Value {
    json!(format!("@@{k}"))
}

fn refs(v: &Value, out: &mut Vec<usize>) {
    match v {
        Value::String(s) => {
            if let Some(k) = s.strip_prefix("@@").and_then(|n| n.parse().ok())
                && !out.contains(&k)
            {
                out.push(k);
            }
        }
        Value::Array(a) => a.iter().for_each(|x| refs(x, out)),
        Value::Object(o) => o.values().for_each(|x| refs(x, out)),
        _ => {}
    }
}

impl GoldCall {
    /// The arguments with every `@@k` replaced by `handles[k]`; `None` when one is missing (that
    /// call failed).
    pub fn bind(&self, handles: &[Option<String>]) -> Option<Value> {
        fn go(v: &Value, h: &[Option<String>]) -> Option<Value> {
            Some(match v {
                Value::String(s) => {
                    match s.strip_prefix("@@").and_then(|n| n.parse::<usize>().ok()) {
                        Some(k) => json!(h.get(k)?.as_ref()?),
                        None => v.clone(),
                    }
                }
                Value::Array(a) => Value::Array(a.iter().map(|x| go(x, h)).collect::<Option<_>>()?),
                Value::Object(o) => {
                    let mut out = Map::new();
                    for (k, x) in o {
                        out.insert(k.clone(), go(x, h)?);
                    }
                    Value::Object(out)
                }
                other => other.clone(),
            })
        }
        go(&self.args, handles)
    }
}

#[derive(Default)]
struct Builder {
    calls: Vec<GoldCall>,
    seen: BTreeMap<String, usize>,
    env: BTreeMap<String, Value>,
}

impl Builder {
    fn push(&mut self, name: &str, args: Value, dedupe: bool) -> Value {
        let key = format!("{name}{}", canonical(&args));
        if dedupe && let Some(&k) = self.seen.get(&key) {
            return reference(k);
        }
        let mut deps = Vec::new();
        refs(&args, &mut deps);
        let level = deps
            .iter()
            .map(|&d| self.calls[d].level + 1)
            .max()
            .unwrap_or(0);
        let k = self.calls.len();
        self.calls.push(GoldCall {
            name: name.to_string(),
            args,
            deps,
            level,
        });
        self.seen.insert(key, k);
        reference(k)
    }

    /// A lambda body keeps its graph form; bindings named in it become their handles.
    fn body(&self, v: &Value) -> Value {
        match v {
            Value::String(s) => self.env.get(s).cloned().unwrap_or_else(|| v.clone()),
            Value::Array(a) => Value::Array(a.iter().map(|x| self.body(x)).collect()),
            Value::Object(o) => {
                let mut out = Map::new();
                for (k, x) in o {
                    let keep = k == "op" || k == "lambda";
                    out.insert(k.clone(), if keep { x.clone() } else { self.body(x) });
                }
                Value::Object(out)
            }
            other => other.clone(),
        }
    }

    /// The argument form of an expression, making a call for every operator node in it.
    fn expr(&mut self, v: &Value) -> Result<Value, FromProgramError> {
        match v {
            Value::String(s) => Ok(self.env.get(s).cloned().unwrap_or_else(|| v.clone())),
            Value::Object(o) if o.contains_key("lambda") => {
                let mut out = o.clone();
                if let Some(b) = o.get("body") {
                    out.insert("body".into(), self.body(b));
                }
                Ok(Value::Object(out))
            }
            Value::Object(o) => {
                let op = o.get("op").and_then(Value::as_str).unwrap_or("");
                let pos: Vec<Value> = o
                    .get("args")
                    .and_then(Value::as_array)
                    .cloned()
                    .unwrap_or_default();
                let pos: Vec<Value> = pos.iter().map(|a| self.expr(a)).collect::<Result<_, _>>()?;
                if let Some((tool, ops, params, _)) =
                    LANGUAGE_TOOLS.iter().find(|(_, ops, ..)| ops.contains(&op))
                {
                    let mut args = Map::new();
                    let mut it = pos.into_iter();
                    for p in params.iter() {
                        if *p == "operator" {
                            args.insert("operator".into(), json!(op));
                        } else {
                            args.insert((*p).into(), it.next().unwrap_or(Value::Null));
                        }
                    }
                    let _ = ops;
                    return Ok(self.push(tool, Value::Object(args), true));
                }
                let of = o.get("of").map(|x| self.expr(x)).transpose()?;
                let operator = operators().into_iter().find(|x| x.name == op).ok_or(
                    FromProgramError::Unsupported("an operator outside the built-in table"),
                )?;
                let row = operator
                    .overloads
                    .iter()
                    .find(|b| b.is_method() == of.is_some() && b.params.len() >= pos.len())
                    .ok_or(FromProgramError::Unsupported(
                        "a call no built-in row takes",
                    ))?;
                let mut args = Map::new();
                if let Some(of) = of {
                    args.insert("of".into(), of);
                }
                for (p, a) in row.params.iter().zip(pos) {
                    args.insert(p.name.into(), a);
                }
                if let Some(Value::Object(kw)) = o.get("kwargs") {
                    for (k, x) in kw {
                        let a = self.expr(x)?;
                        args.insert(k.clone(), a);
                    }
                }
                Ok(self.push(op, Value::Object(args), true))
            }
            other => Ok(other.clone()),
        }
    }

    fn binding(&mut self, b: &Value, name_key: &str) -> Result<(), FromProgramError> {
        let name = b.get(name_key).and_then(Value::as_str).unwrap_or("");
        let v = self.expr(b.get("value").unwrap_or(&Value::Null))?;
        self.env.insert(name.to_string(), v);
        Ok(())
    }

    fn constraint(&mut self, c: &Value) -> Result<Value, FromProgramError> {
        let kind = c.get("kind").and_then(Value::as_str).unwrap_or("");
        let field = if kind == "prefer" {
            "preference"
        } else {
            "place"
        };
        let mut args = Map::new();
        args.insert("kind".into(), json!(kind));
        args.insert(
            "value".into(),
            self.expr(c.get(field).unwrap_or(&Value::Null))?,
        );
        if let Some(w) = c.get("within") {
            args.insert("within".into(), self.expr(w)?);
        }
        if let Some(d) = c.get("during") {
            args.insert("segments".into(), d.clone());
        }
        Ok(self.push("constraint", Value::Object(args), false))
    }
}

/// The tool calls that build `program`, in an order where every call's dependencies come
/// first; or why the program has no such sequence (a `for` loop: the builders have no loop).
pub fn gold_calls(program: &str) -> Result<Vec<GoldCall>, FromProgramError> {
    let graph = program_to_graph(program)?;
    let mut b = Builder::default();
    for l in graph["bindings"].as_array().into_iter().flatten() {
        b.binding(l, "name")?;
    }
    let mut segments = Vec::new();
    for s in graph["segments"].as_array().into_iter().flatten() {
        if s.get("for").is_some() {
            return Err(FromProgramError::Unsupported("a `for` loop over segments"));
        }
        if s.get("let").is_some() {
            b.binding(s, "let")?;
            continue;
        }
        for l in s["bindings"].as_array().into_iter().flatten() {
            b.binding(l, "name")?;
        }
        let mut cons = Vec::new();
        for c in s["constraints"].as_array().into_iter().flatten() {
            cons.push(b.constraint(c)?);
        }
        let target = b.expr(&s["to"])?;
        let mut args = json!({"target": target});
        if let Some(id) = s.get("id") {
            args["segment_id"] = id.clone();
        }
        if !cons.is_empty() {
            args["constraints"] = Value::Array(cons);
        }
        segments.push(b.push("segment", args, false));
    }
    let mut route = Vec::new();
    for c in graph["constraints"].as_array().into_iter().flatten() {
        route.push(b.constraint(c)?);
    }
    let mut args = json!({"segments": segments});
    if !route.is_empty() {
        args["constraints"] = Value::Array(route);
    }
    b.push(super::TASK_TOOL, args, false);
    Ok(b.calls)
}
