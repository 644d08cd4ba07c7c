//! One grounding conversation's state: the handles made so far, the failing queries and the
//! route being built. A query is answered by the compiler itself: its intent-graph expression
//! is printed as the one binding of a program, checked against the map's vocabulary and grounded
//! by [`evaluate_lets`], so a tool and the same built-in in a program can never disagree.

#[path = "builders.rs"]
mod builders;

use super::preview::preview;
use super::spec::{ToolKind, ToolSpec, tool_specs};
use crate::check::check;
use crate::diagnostic::Diagnostic;
use crate::eval::{GroundOptions, Value as Val, evaluate_lets};
use crate::intent::graph_to_program;
use crate::intent::ops::operators;
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use m2rc_stdlib::query::MapQuery;
use m2rc_stdlib::vocab::Vocabulary;
use serde_json::{Map, Value, json};
use std::collections::BTreeMap;

/// Bounds of one session, whoever drives it (a model or an external agent).
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Handles one session may hold; a call past it fails.
    pub max_handles: usize,
    /// The largest query (its expression with every handle written out), in bytes.
    pub max_query_bytes: usize,
    /// Failures of one identical query before it is blocked without being run.
    pub retry_limit: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_handles: 1024,
            max_query_bytes: 64 * 1024,
            retry_limit: 3,
        }
    }
}

/// What one call answered.
#[derive(Clone, Debug, PartialEq)]
pub struct ToolOutcome {
    /// The call produced a handle (or, for the builders, did what was asked).
    pub ok: bool,
    /// The tool message's content: `{handle, value}` or `{error, ...}`.
    pub content: Value,
    /// Refused without being run: the same query failed `retry_limit` times.
    pub blocked: bool,
}

/// The route a `task` call submitted.
#[derive(Clone, Debug, PartialEq)]
pub struct Finished {
    /// The route as an intent graph.
    pub graph: Value,
    /// The same route as `.m2r`, which the ordinary compiler grounds and plans.
    pub program: String,
}

#[derive(Clone, Debug)]
enum Stored {
    /// An expression of the language (intent-graph form, every handle written out).
    Expr(Value),
    Constraint {
        graph: Value,
        during: Option<Vec<String>>,
    },
    Segment {
        id: Option<String>,
        target: Value,
        constraints: Vec<usize>,
    },
}

#[derive(Clone, Debug)]
struct Handle {
    name: String,
    stored: Stored,
}

/// The read-only query session over one map.
pub struct ToolSession<'m> {
    q: MapQuery<'m>,
    vocab: Vocabulary,
    start: Option<Cell>,
    limits: Limits,
    specs: Vec<ToolSpec>,
    handles: Vec<Handle>,
    failures: BTreeMap<String, usize>,
    context: Option<String>,
    pub finished: Option<Finished>,
    /// Calls run (blocked ones not included).
    pub executed: usize,
    /// Calls refused by the retry rule.
    pub blocked: usize,
    /// Calls that ran and failed.
    pub failed: usize,
}

type Outcome = Result<Value, String>;

impl<'m> ToolSession<'m> {
    pub fn new(map: &'m SemanticMap, start: Option<Cell>, limits: Limits) -> Self {
        ToolSession {
            q: MapQuery::new(map),
            vocab: Vocabulary::from_map(map),
            start,
            limits,
            specs: tool_specs(),
            handles: Vec::new(),
            failures: BTreeMap::new(),
            context: None,
            finished: None,
            executed: 0,
            blocked: 0,
            failed: 0,
        }
    }

    /// Handles made so far.
    pub fn handle_count(&self) -> usize {
        self.handles.len()
    }

    /// Runs one call. Never panics, whatever the arguments.
    pub fn call(&mut self, name: &str, args: &Value) -> ToolOutcome {
        let key = format!("{name}{}", canonical(args));
        let seen = self.failures.get(&key).copied().unwrap_or(0);
        if seen >= self.limits.retry_limit {
            self.blocked += 1;
            return ToolOutcome {
                ok: false,
                content: json!({
                    "error": "QUERY_RETRY_LIMIT_REACHED",
                    "message": format!(
                        "this exact query failed {seen} times and was not run again; change the \
                         query or stop"
                    ),
                }),
                blocked: true,
            };
        }
        self.executed += 1;
        match self.execute(name, args) {
            Ok(content) => ToolOutcome {
                ok: true,
                content,
                blocked: false,
            },
            Err(message) => {
                self.failed += 1;
                let n = seen + 1;
                self.failures.insert(key, n);
                let mut content = json!({"error": message});
                if n >= self.limits.retry_limit {
                    content["blocked"] = json!(format!(
                        "this exact query has now failed {n} times; it will not be run again"
                    ));
                }
                ToolOutcome {
                    ok: false,
                    content,
                    blocked: false,
                }
            }
        }
    }

    fn execute(&mut self, name: &str, args: &Value) -> Outcome {
        if self.finished.is_some() {
            return Err("the task was already submitted; no further calls are taken".into());
        }
        let empty = Map::new();
        let args = match args {
            Value::Object(o) => o,
            Value::Null => &empty,
            other => {
                return Err(format!(
                    "the arguments must be a JSON object, not {}",
                    kind_of(other)
                ));
            }
        };
        let Some(spec) = self.specs.iter().find(|s| s.name == name).cloned() else {
            return Err(format!(
                "there is no tool `{}`; the tools are listed in the request",
                clip(name)
            ));
        };
        let props = spec.parameters["properties"]
            .as_object()
            .cloned()
            .unwrap_or_default();
        if let Some(k) = args.keys().find(|k| !props.contains_key(k.as_str())) {
            let names: Vec<&str> = props.keys().map(String::as_str).collect();
            return Err(format!(
                "`{name}` takes no argument `{}`; it takes {}",
                clip(k),
                names.join(", ")
            ));
        }
        if let Some(r) = spec.parameters["required"]
            .as_array()
            .into_iter()
            .flatten()
            .filter_map(Value::as_str)
            .find(|r| !args.contains_key(*r))
        {
            return Err(format!("`{name}` needs the argument `{r}`"));
        }
        if self.handles.len() >= self.limits.max_handles {
            return Err(format!(
                "this session holds {} handles, its limit; submit the task with the handles made",
                self.limits.max_handles
            ));
        }
        match spec.kind {
            ToolKind::Builtin(op) => {
                let expr = self.builtin_expr(op, args)?;
                self.query(expr)
            }
            ToolKind::Language(ops) => {
                let expr = self.language_expr(name, ops, args)?;
                self.query(expr)
            }
            ToolKind::Builder => self.build(name, args),
        }
    }

    fn builtin_expr(&self, op: &str, args: &Map<String, Value>) -> Result<Value, String> {
        let o = operators()
            .into_iter()
            .find(|o| o.name == op)
            .ok_or_else(|| format!("no built-in `{op}`"))?;
        let of = args.get("of").map(|v| self.resolve(v)).transpose()?;
        let given: Vec<&str> = args
            .keys()
            .map(String::as_str)
            .filter(|k| *k != "of")
            .collect();
        let row = o
            .overloads
            .iter()
            .filter(|b| b.is_method() == of.is_some())
            .find(|b| given.iter().all(|g| b.params.iter().any(|p| p.name == *g)))
            .ok_or_else(|| {
                let sigs: Vec<String> = o.overloads.iter().map(|b| b.signature(None)).collect();
                format!(
                    "no form of `{op}` takes {}{}; its forms: {}",
                    if of.is_some() { "`of` and " } else { "" },
                    if given.is_empty() {
                        "no arguments".to_string()
                    } else {
                        given.join(", ")
                    },
                    sigs.join(" ; ")
                )
            })?;
        let mut node = Map::new();
        node.insert("op".into(), json!(op));
        if let Some(of) = of {
            node.insert("of".into(), of);
        }
        let mut positional = Vec::new();
        let mut named = Map::new();
        let mut gap = false;
        for p in row.params {
            match args.get(p.name) {
                Some(v) if !gap => positional.push(self.resolve(v)?),
                Some(v) => {
                    named.insert(p.name.into(), self.resolve(v)?);
                }
                None => gap = true,
            }
        }
        if !positional.is_empty() {
            node.insert("args".into(), Value::Array(positional));
        }
        if !named.is_empty() {
            node.insert("kwargs".into(), Value::Object(named));
        }
        Ok(Value::Object(node))
    }

    fn language_expr(
        &self,
        tool: &str,
        ops: &[&str],
        args: &Map<String, Value>,
    ) -> Result<Value, String> {
        let op = if ops.len() == 1 {
            ops[0].to_string()
        } else {
            let o = args.get("operator").and_then(Value::as_str).unwrap_or("");
            if !ops.contains(&o) {
                return Err(format!(
                    "`{tool}`'s `operator` is one of {}, not `{}`",
                    ops.join(" "),
                    clip(o)
                ));
            }
            o.to_string()
        };
        let names: &[&str] = match tool {
            "not" | "neg" => &["value"],
            "if_else" => &["condition", "then", "otherwise"],
            _ => &["left", "right"],
        };
        let mut operands = Vec::new();
        for n in names {
            let v = args
                .get(*n)
                .ok_or_else(|| format!("`{tool}` needs the argument `{n}`"))?;
            operands.push(self.resolve(v)?);
        }
        Ok(json!({"op": op, "args": operands}))
    }

    fn handle(&self, s: &str) -> Option<(usize, &Handle)> {
        self.handles.iter().enumerate().find(|(_, h)| h.name == s)
    }

    /// An argument as an expression: a handle is written out, anything else is kept as it is
    /// (a name, a word, a distance or a number), and a lambda's body gets its handles written out.
    fn resolve(&self, v: &Value) -> Result<Value, String> {
        match v {
            Value::String(s) => match self.handle(s) {
                Some((_, h)) => match &h.stored {
                    Stored::Expr(e) => Ok(e.clone()),
                    _ => Err(format!(
                        "`{s}` is a route builder's handle; queries take value handles"
                    )),
                },
                None if s.contains('#') => Err(format!(
                    "there is no handle `{}`; use one a result gave",
                    clip(s)
                )),
                None => Ok(v.clone()),
            },
            Value::Number(_) | Value::Bool(_) => Ok(v.clone()),
            Value::Object(o) if o.contains_key("lambda") => {
                let mut out = o.clone();
                if let Some(b) = o.get("body") {
                    out.insert("body".into(), self.resolve_deep(b)?);
                }
                Ok(Value::Object(out))
            }
            other => Err(format!(
                "an argument is a handle, a name, a number or a distance, not {}",
                kind_of(other)
            )),
        }
    }

    fn resolve_deep(&self, v: &Value) -> Result<Value, String> {
        Ok(match v {
            Value::String(_) => self.resolve(v)?,
            Value::Array(a) => Value::Array(
                a.iter()
                    .map(|x| self.resolve_deep(x))
                    .collect::<Result<_, _>>()?,
            ),
            Value::Object(o) => {
                let mut out = Map::new();
                for (k, x) in o {
                    let keep = k == "op" || k == "lambda";
                    out.insert(
                        k.clone(),
                        if keep {
                            x.clone()
                        } else {
                            self.resolve_deep(x)?
                        },
                    );
                }
                Value::Object(out)
            }
            other => other.clone(),
        })
    }

    /// Evaluates an expression through the compiler and stores its value under a new handle.
    fn query(&mut self, expr: Value) -> Outcome {
        let text = serde_json::to_string(&expr).unwrap_or_default();
        if text.len() > self.limits.max_query_bytes {
            return Err(format!(
                "the query is {} bytes with its handles written out, more than the limit of {}; \
                 build it from fewer nested results",
                text.len(),
                self.limits.max_query_bytes
            ));
        }
        let value = self.evaluate(&expr)?;
        if let Val::Set(s) = &value
            && s.is_empty()
        {
            return Err(
                "the result is empty: nothing on this map matches; it was not stored".into(),
            );
        }
        let n = self.handles.len() + 1;
        let (kind, text) = preview(&value, &self.q);
        let name = format!("{kind}#{n}");
        self.handles.push(Handle {
            name: name.clone(),
            stored: Stored::Expr(expr),
        });
        Ok(json!({"handle": name, "value": format!("{name}: {text}")}))
    }

    fn evaluate(&self, expr: &Value) -> Result<Val, String> {
        let graph = json!({
            "bindings": [{"name": "query", "value": expr}],
            "segments": [{"to": "start"}],
        });
        let src = graph_program(&graph)?;
        let route_at = src.find("\nroute").unwrap_or(src.len());
        let checked = check(&src, &self.vocab);
        let errors: Vec<String> = checked
            .errors()
            .filter(|d| d.span.start < route_at)
            .map(describe)
            .collect();
        if !errors.is_empty() {
            return Err(errors.join("; "));
        }
        let opts = GroundOptions {
            start: self.start,
            ..GroundOptions::default()
        };
        let (values, problems) = evaluate_lets(&checked, &src, &self.q, &opts);
        let errors: Vec<String> = problems
            .into_iter()
            .filter(|p| p.is_error())
            .map(|p| describe(&p.into_diagnostic()))
            .collect();
        if !errors.is_empty() {
            return Err(errors.join("; "));
        }
        match values.into_iter().find(|(n, _)| n == "query") {
            Some((_, Val::Unknown)) | None => Err("the query has no value on this map".into()),
            Some((_, v)) => Ok(v),
        }
    }
}

/// The `.m2r` program of an intent graph, or its diagnostics in the form a model reads.
fn graph_program(graph: &Value) -> Result<String, String> {
    graph_to_program(graph).map(|c| c.program).map_err(|ds| {
        ds.iter()
            .map(|d| describe(&d.diagnostic))
            .collect::<Vec<_>>()
            .join("; ")
    })
}

/// `E0201: message (help: ...)`, the form a model reads.
fn describe(d: &Diagnostic) -> String {
    match &d.help {
        Some(h) => format!("{}: {} (help: {h})", d.code.id(), d.message),
        None => format!("{}: {}", d.code.id(), d.message),
    }
}

fn is_name(s: &str) -> bool {
    let mut c = s.chars();
    c.next()
        .is_some_and(|f| f.is_ascii_alphabetic() || f == '_')
        && c.all(|x| x.is_ascii_alphanumeric() || x == '_')
        && s.len() <= 64
}

/// A value as a short text for messages (never more than 80 characters).
fn clip(s: &str) -> String {
    if s.chars().count() <= 80 {
        s.to_string()
    } else {
        format!("{}…", s.chars().take(80).collect::<String>())
    }
}

fn short(v: Option<&Value>) -> String {
    match v {
        Some(Value::String(s)) => clip(s),
        Some(other) => clip(&other.to_string()),
        None => "?".into(),
    }
}

fn kind_of(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "a list",
        Value::Object(_) => "an object",
    }
}

/// A JSON value with object keys sorted, so two spellings of one query are one key.
pub fn canonical(v: &Value) -> String {
    fn sort(v: &Value) -> Value {
        match v {
            Value::Object(o) => {
                let mut keys: Vec<&String> = o.keys().collect();
                keys.sort();
                let mut out = Map::new();
                for k in keys {
                    out.insert(k.clone(), sort(&o[k]));
                }
                Value::Object(out)
            }
            Value::Array(a) => Value::Array(a.iter().map(sort).collect()),
            other => other.clone(),
        }
    }
    serde_json::to_string(&sort(v)).unwrap_or_default()
}
