//! The intent graph's operators and its JSON Schema, generated from the built-in table, so the
//! Schema variant can never offer an operator the language lacks or miss one it gained.
//!
//! Every built-in name is one operator (its overloads, told apart by whether `of` is given, share
//! it); the language's own operators (`and`, `==`, `|`, `if`, ...) come from the grammar and are
//! listed in [`LANGUAGE_OPS`], which a test holds to the grammar's operator set.

use m2rc_grammar::ast::BinOp;
use m2rc_stdlib::builtins::{BUILTINS, Builtin, CONSTANTS, ENUM_WORDS, Requirement};
use serde_json::{Map, Value, json};

/// One operator of the intent graph: a built-in name with every overload of it.
#[derive(Clone, Debug)]
pub struct Operator {
    pub name: &'static str,
    pub overloads: Vec<&'static Builtin>,
}

impl Operator {
    /// Whether some overload is called on a value (`of`), and whether some is not.
    pub fn of_use(&self) -> (bool, bool) {
        let method = self.overloads.iter().any(|b| b.is_method());
        let free = self.overloads.iter().any(|b| !b.is_method());
        (method, free)
    }

    /// The most positional arguments any overload takes.
    pub fn max_args(&self) -> usize {
        self.overloads
            .iter()
            .map(|b| b.params.len())
            .max()
            .unwrap_or(0)
    }

    /// Parameter names of every overload, in first-seen order.
    pub fn param_names(&self) -> Vec<&'static str> {
        let mut out: Vec<&'static str> = Vec::new();
        for b in &self.overloads {
            for p in b.params {
                if !out.contains(&p.name) {
                    out.push(p.name);
                }
            }
        }
        out
    }
}

/// The language's operators as the intent graph spells them, with their arity and the binary
/// operator each stands for (`None`: `not`, `neg` and `if`, which are not binary).
pub const LANGUAGE_OPS: &[(&str, usize, Option<BinOp>, &str)] = &[
    (
        "union",
        2,
        Some(BinOp::Union),
        "Union of two categories or two sets (`a | b`).",
    ),
    ("and", 2, Some(BinOp::And), "Both conditions hold."),
    ("or", 2, Some(BinOp::Or), "Either condition holds."),
    ("not", 1, None, "The condition does not hold."),
    ("==", 2, Some(BinOp::Eq), "Equal."),
    ("!=", 2, Some(BinOp::Ne), "Not equal."),
    ("<", 2, Some(BinOp::Lt), "Less than."),
    ("<=", 2, Some(BinOp::Le), "Less than or equal."),
    (">", 2, Some(BinOp::Gt), "Greater than."),
    (">=", 2, Some(BinOp::Ge), "Greater than or equal."),
    ("+", 2, Some(BinOp::Add), "Sum of two numbers or distances."),
    (
        "-",
        2,
        Some(BinOp::Sub),
        "Difference of two numbers or distances.",
    ),
    (
        "*",
        2,
        Some(BinOp::Mul),
        "Product (a distance times a number).",
    ),
    ("neg", 1, None, "The negated number."),
    (
        "if",
        3,
        None,
        "`[condition, then, otherwise]`: the value of one branch.",
    ),
];

/// The language operator spelling a binary operator.
pub fn bin_op_name(op: BinOp) -> &'static str {
    LANGUAGE_OPS
        .iter()
        .find(|(_, _, b, _)| *b == Some(op))
        .map(|(n, ..)| *n)
        .unwrap_or("union")
}

/// Every built-in operator, in table order (first row of each name).
pub fn operators() -> Vec<Operator> {
    let mut out: Vec<Operator> = Vec::new();
    for b in BUILTINS {
        match out.iter_mut().find(|o| o.name == b.name) {
            Some(o) => o.overloads.push(b),
            None => out.push(Operator {
                name: b.name,
                overloads: vec![b],
            }),
        }
    }
    out
}

/// Every operator name the graph accepts: built-ins, then the language's operators.
pub fn operator_names() -> Vec<&'static str> {
    let mut v: Vec<&'static str> = operators().iter().map(|o| o.name).collect();
    v.extend(LANGUAGE_OPS.iter().map(|(n, ..)| *n));
    v
}

/// Pattern of a name: a binding, category, constant or word.
pub const NAME_PATTERN: &str = "^[A-Za-z_][A-Za-z0-9_]*$";
/// Pattern of a distance literal.
pub const DISTANCE_PATTERN: &str = "^[0-9]+(\\.[0-9]+)?(m|cm)$";

fn expr_ref() -> Value {
    json!({"$ref": "#/$defs/expr"})
}

fn op_schema(o: &Operator) -> Value {
    let (method, free) = o.of_use();
    let mut props = Map::new();
    props.insert("op".into(), json!({"const": o.name}));
    if method {
        props.insert("of".into(), expr_ref());
    }
    props.insert(
        "args".into(),
        json!({"type": "array", "items": expr_ref(), "maxItems": o.max_args()}),
    );
    let names = o.param_names();
    props.insert(
        "kwargs".into(),
        json!({
            "type": "object",
            "propertyNames": {"enum": names},
            "additionalProperties": expr_ref(),
        }),
    );
    let required: Vec<&str> = if method && !free {
        vec!["op", "of"]
    } else {
        vec!["op"]
    };
    let sigs: Vec<String> = o.overloads.iter().map(|b| b.signature(None)).collect();
    json!({
        "type": "object",
        "description": format!("{} {}", sigs.join(" ; "), o.overloads[0].doc),
        "properties": props,
        "required": required,
        "additionalProperties": false,
    })
}

fn language_op_schema(name: &str, arity: usize, doc: &str) -> Value {
    json!({
        "type": "object",
        "description": doc,
        "properties": {
            "op": {"const": name},
            "args": {"type": "array", "items": expr_ref(), "minItems": arity, "maxItems": arity},
        },
        "required": ["op", "args"],
        "additionalProperties": false,
    })
}

fn constraint_schema() -> Value {
    let scopes = json!({
        "within": expr_ref(),
        "during": {"type": "array", "items": {"type": "string", "pattern": NAME_PATTERN}},
    });
    let with = |kind: &str, field: &str| {
        let mut props = Map::new();
        props.insert("kind".into(), json!({"const": kind}));
        props.insert(field.into(), expr_ref());
        if let Value::Object(s) = &scopes {
            for (k, v) in s {
                props.insert(k.clone(), v.clone());
            }
        }
        json!({
            "type": "object",
            "properties": props,
            "required": ["kind", field],
            "additionalProperties": false,
        })
    };
    json!({"oneOf": [
        with("require_visit", "place"),
        with("forbid", "place"),
        with("prefer", "preference"),
    ]})
}

/// The JSON Schema (2020-12) of an intent graph. An operator node is dispatched on its `op` by
/// `if`/`then` (never `oneOf` over every operator), so validating a graph costs time linear in
/// its size, not exponential in its depth.
pub fn json_schema() -> Value {
    let mut branches: Vec<Value> = Vec::new();
    let mut names: Vec<&str> = Vec::new();
    for o in operators() {
        names.push(o.name);
        branches.push(json!({
            "if": {"properties": {"op": {"const": o.name}}, "required": ["op"]},
            "then": op_schema(&o),
        }));
    }
    for (n, a, _, d) in LANGUAGE_OPS {
        names.push(n);
        branches.push(json!({
            "if": {"properties": {"op": {"const": n}}, "required": ["op"]},
            "then": language_op_schema(n, *a, d),
        }));
    }
    let expr_alts = vec![
        json!({"type": "string", "pattern": NAME_PATTERN,
               "description": "A binding, a category, a constant or a word."}),
        json!({"type": "string", "pattern": DISTANCE_PATTERN, "description": "A distance."}),
        json!({"type": "number"}),
        json!({"type": "boolean"}),
        json!({
            "type": "object",
            "properties": {
                "lambda": {"type": "string", "pattern": NAME_PATTERN},
                "body": expr_ref(),
            },
            "required": ["lambda", "body"],
            "additionalProperties": false,
        }),
        json!({
            "type": "object",
            "properties": {"op": {"enum": names}},
            "required": ["op"],
            "allOf": branches,
        }),
    ];
    let binding = json!({
        "type": "object",
        "properties": {"name": {"type": "string", "pattern": NAME_PATTERN}, "value": expr_ref()},
        "required": ["name", "value"],
        "additionalProperties": false,
    });
    json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "m2rc intent graph",
        "type": "object",
        "properties": {
            "bindings": {"type": "array", "items": {"$ref": "#/$defs/binding"}},
            "segments": {"type": "array", "minItems": 1, "items": {"$ref": "#/$defs/segment"}},
            "constraints": {"type": "array", "items": {"$ref": "#/$defs/constraint"}},
        },
        "required": ["segments"],
        "additionalProperties": false,
        "$defs": {
            "expr": {"anyOf": expr_alts},
            "binding": binding,
            "constraint": constraint_schema(),
            "segment": {"oneOf": [
                {
                    "type": "object",
                    "properties": {
                        "id": {"type": "string", "pattern": NAME_PATTERN},
                        "to": expr_ref(),
                        "bindings": {"type": "array", "items": {"$ref": "#/$defs/binding"}},
                        "constraints": {"type": "array", "items": {"$ref": "#/$defs/constraint"}},
                    },
                    "required": ["to"],
                    "additionalProperties": false,
                },
                {
                    "type": "object",
                    "properties": {
                        "for": {"type": "string", "pattern": NAME_PATTERN},
                        "in": expr_ref(),
                        "segments": {"type": "array", "items": {"$ref": "#/$defs/segment"}},
                        "constraints": {"type": "array", "items": {"$ref": "#/$defs/constraint"}},
                    },
                    "required": ["for", "in", "segments"],
                    "additionalProperties": false,
                },
                {
                    "type": "object",
                    "properties": {"let": {"type": "string", "pattern": NAME_PATTERN}, "value": expr_ref()},
                    "required": ["let", "value"],
                    "additionalProperties": false,
                },
            ]},
        },
    })
}

fn requirement(r: Requirement) -> String {
    match r {
        Requirement::Required => String::new(),
        Requirement::Optional => "?".into(),
        Requirement::Default(d) => format!(" = {d}"),
    }
}

/// The operator list as the model reads it: one operator form per line with its meaning.
pub fn operator_reference() -> String {
    let mut out = String::new();
    for o in operators() {
        for b in &o.overloads {
            let params: Vec<String> = b
                .params
                .iter()
                .map(|p| {
                    format!(
                        "{}: {}{}",
                        p.name,
                        m2rc_stdlib::builtins::signature::display_alternatives(p.ty, None),
                        requirement(p.req)
                    )
                })
                .collect();
            let of = match b.receiver {
                m2rc_stdlib::builtins::Receiver::Method(alts) => format!(
                    ", of: {}",
                    m2rc_stdlib::builtins::signature::display_alternatives(alts, None)
                ),
                m2rc_stdlib::builtins::Receiver::Free => String::new(),
            };
            out.push_str(&format!(
                "{{op: {}{of}, args: [{}]}} -> {}  // {}\n",
                b.name,
                params.join(", "),
                b.ret.display(None),
                b.doc
            ));
        }
    }
    for (n, a, _, d) in LANGUAGE_OPS {
        out.push_str(&format!("{{op: \"{n}\", args: [{a} values]}}  // {d}\n"));
    }
    for c in CONSTANTS {
        out.push_str(&format!("\"{}\": {}  // {}\n", c.name, c.ty, c.doc));
    }
    for w in ENUM_WORDS {
        out.push_str(&format!("\"{}\": {}  // {}\n", w.name, w.ty, w.doc));
    }
    out
}
