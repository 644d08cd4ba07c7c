//! The tool list, generated from the built-in table (through the Schema variant's
//! [`operators`](crate::intent::ops::operators)) and the grammar's operators, plus the four
//! RouteIR builders. A test holds it to the table: one tool per built-in name, none more.

use crate::intent::ops::{NAME_PATTERN, Operator, operators};
use m2rc_stdlib::builtins::signature::display_alternatives;
use m2rc_stdlib::builtins::{Receiver, Requirement, Ty};
use serde_json::{Map, Value, json};

/// What a tool does.
#[derive(Clone, Debug, PartialEq)]
pub enum ToolKind {
    /// A built-in of the language, by name (every overload of it).
    Builtin(&'static str),
    /// Operators of the language: `(tool argument's operator spelling, graph op)`. One entry is
    /// a tool of one operator (`not`); several share a tool with an `operator` argument
    /// (`compare`).
    Language(&'static [&'static str]),
    /// One of the RouteIR builders.
    Builder,
}

/// One tool: its name, what the model reads about it, and its JSON-Schema parameters.
#[derive(Clone, Debug)]
pub struct ToolSpec {
    pub name: &'static str,
    pub description: String,
    pub parameters: Value,
    pub kind: ToolKind,
}

/// Language operators grouped into tools, with the argument names they take (in order).
pub const LANGUAGE_TOOLS: &[(&str, &[&str], &[&str], &str)] = &[
    (
        "union",
        &["union"],
        &["left", "right"],
        "Union of two categories or two sets (`a | b`).",
    ),
    ("and", &["and"], &["left", "right"], "Both conditions hold."),
    ("or", &["or"], &["left", "right"], "Either condition holds."),
    ("not", &["not"], &["value"], "The condition does not hold."),
    (
        "compare",
        &["==", "!=", "<", "<=", ">", ">="],
        &["left", "operator", "right"],
        "Compares two numbers, counts or distances; a condition (usable in a lambda).",
    ),
    (
        "arithmetic",
        &["+", "-", "*"],
        &["left", "operator", "right"],
        "Sum, difference or product of numbers or distances.",
    ),
    ("neg", &["neg"], &["value"], "The negated number."),
    (
        "if_else",
        &["if"],
        &["condition", "then", "otherwise"],
        "The value of `then` when the condition holds, else of `otherwise`.",
    ),
];

/// Where a handle goes: what the model reads about handle arguments.
const HANDLE_NOTE: &str = "a handle from an earlier result (e.g. `set#3`), `start`, `here`, a category \
     name, a word (`clockwise`, `travel`), a number or a distance (`1.5m`)";

fn value_schema(description: String) -> Value {
    json!({
        "type": ["string", "number", "boolean"],
        "description": description,
    })
}

fn lambda_schema(description: String) -> Value {
    json!({
        "type": "object",
        "description": format!(
            "{description}. A lambda in the intent-graph form: {{\"lambda\": \"r\", \"body\": \
             EXPR}}, where EXPR is a handle, a name, a literal or {{\"op\": NAME, \"of\": EXPR, \
             \"args\": [EXPR...], \"kwargs\": {{NAME: EXPR}}}} over the same operators as the \
             tools; handles may appear in the body"
        ),
        "properties": {
            "lambda": {"type": "string", "pattern": NAME_PATTERN},
            "body": {},
        },
        "required": ["lambda", "body"],
        "additionalProperties": false,
    })
}

fn is_lambda(alts: &[Ty]) -> bool {
    alts.iter().any(|t| matches!(t, Ty::PredT | Ty::KeyT))
}

fn builtin_tool(o: &Operator) -> ToolSpec {
    let mut props = Map::new();
    let method = o.overloads.iter().any(|b| b.is_method());
    let free = o.overloads.iter().any(|b| !b.is_method());
    if method {
        let alts: Vec<String> = o
            .overloads
            .iter()
            .filter_map(|b| match b.receiver {
                Receiver::Method(a) => Some(display_alternatives(a, None)),
                Receiver::Free => None,
            })
            .collect();
        props.insert(
            "of".into(),
            value_schema(format!(
                "The value the query is applied to ({}): {HANDLE_NOTE}",
                alts.join(" | ")
            )),
        );
    }
    // A parameter is required when every overload requires it.
    let mut required: Vec<&str> = Vec::new();
    for name in o.param_names() {
        let rows: Vec<_> = o
            .overloads
            .iter()
            .filter_map(|b| b.params.iter().find(|p| p.name == name))
            .collect();
        let tys: Vec<String> = rows
            .iter()
            .map(|p| display_alternatives(p.ty, None))
            .collect();
        let mut tys_d = tys.clone();
        tys_d.dedup();
        let default = rows.iter().find_map(|p| match p.req {
            Requirement::Default(d) => Some(format!(" (default {d})")),
            _ => None,
        });
        let desc = format!("{}{}", tys_d.join(" | "), default.unwrap_or_default());
        let schema = if rows.iter().any(|p| is_lambda(p.ty)) {
            lambda_schema(desc)
        } else {
            value_schema(format!("{desc}: {HANDLE_NOTE}"))
        };
        props.insert(name.into(), schema);
        let everywhere = o.overloads.iter().all(|b| {
            b.params
                .iter()
                .any(|p| p.name == name && p.req == Requirement::Required)
        });
        if everywhere {
            required.push(name);
        }
    }
    if method && !free {
        required.insert(0, "of");
    }
    let sigs: Vec<String> = o.overloads.iter().map(|b| b.signature(None)).collect();
    ToolSpec {
        name: o.name,
        description: format!("{}. {}", sigs.join(" ; "), o.overloads[0].doc),
        parameters: json!({
            "type": "object",
            "properties": props,
            "required": required,
            "additionalProperties": false,
        }),
        kind: ToolKind::Builtin(o.name),
    }
}

fn language_tool(
    name: &'static str,
    ops: &'static [&'static str],
    params: &[&str],
    doc: &str,
) -> ToolSpec {
    let mut props = Map::new();
    for p in params {
        let s = if *p == "operator" {
            json!({"type": "string", "enum": ops})
        } else {
            value_schema(HANDLE_NOTE.to_string())
        };
        props.insert((*p).into(), s);
    }
    ToolSpec {
        name,
        description: doc.to_string(),
        parameters: json!({
            "type": "object",
            "properties": props,
            "required": params,
            "additionalProperties": false,
        }),
        kind: ToolKind::Language(ops),
    }
}

fn builder(name: &'static str, description: &str, parameters: Value) -> ToolSpec {
    ToolSpec {
        name,
        description: description.to_string(),
        parameters,
        kind: ToolKind::Builder,
    }
}

fn handle_list(what: &str) -> Value {
    json!({"type": "array", "items": {"type": "string"}, "description": what})
}

/// The RouteIR builders, as the reference's ToolCall has them.
fn builders() -> Vec<ToolSpec> {
    let id =
        json!({"type": "string", "pattern": NAME_PATTERN, "description": "A segment id (`s1`)."});
    vec![
        builder(
            "set_segment_context",
            "Makes `segment_id` the segment that later `constraint` calls without `segments` \
             belong to; inside a segment, `here` means where that segment starts.",
            json!({
                "type": "object",
                "properties": {"segment_id": id},
                "required": ["segment_id"],
                "additionalProperties": false,
            }),
        ),
        builder(
            "constraint",
            "A constraint: `require_visit` (pass through a place), `forbid` (never enter a place) \
             or `prefer` (a preference handle from `near`, `far`, `closer`, `through`, ...), \
             optionally only `within` a place and only during some segments (default: the \
             segment context, else the whole route). Returns a constraint handle.",
            json!({
                "type": "object",
                "properties": {
                    "kind": {"type": "string", "enum": ["require_visit", "forbid", "prefer"]},
                    "value": value_schema(format!("The place or preference: {HANDLE_NOTE}")),
                    "within": value_schema(format!("The area it applies in: {HANDLE_NOTE}")),
                    "segments": {"type": "array", "items": {"type": "string", "pattern": NAME_PATTERN},
                                 "description": "Segment ids it applies during."},
                },
                "required": ["kind", "value"],
                "additionalProperties": false,
            }),
        ),
        builder(
            "segment",
            "One leg of the route: from where the previous one ended to `target` (a single \
             place), with its constraints. Returns a segment handle.",
            json!({
                "type": "object",
                "properties": {
                    "segment_id": id,
                    "target": value_schema(format!("The destination: {HANDLE_NOTE}")),
                    "constraints": handle_list("Constraint handles of this segment."),
                },
                "required": ["target"],
                "additionalProperties": false,
            }),
        ),
        builder(
            "task",
            "Submits the route: its segments in order and the route-wide constraints. Call it \
             exactly once, last; it is the only valid answer.",
            json!({
                "type": "object",
                "properties": {
                    "segments": handle_list("Segment handles, in visiting order."),
                    "constraints": handle_list("Constraint handles that apply to the whole route."),
                },
                "required": ["segments"],
                "additionalProperties": false,
            }),
        ),
    ]
}

/// Every tool: one per built-in name (table order), the language's operators, the builders.
pub fn tool_specs() -> Vec<ToolSpec> {
    let mut out: Vec<ToolSpec> = operators().iter().map(builtin_tool).collect();
    for (name, ops, params, doc) in LANGUAGE_TOOLS {
        out.push(language_tool(name, ops, params, doc));
    }
    out.extend(builders());
    out
}

/// The graph ops every language tool stands for, so a test can hold them to the grammar's.
pub fn language_ops_covered() -> Vec<&'static str> {
    let mut v: Vec<&str> = LANGUAGE_TOOLS
        .iter()
        .flat_map(|(_, ops, ..)| ops.iter().copied())
        .collect();
    v.sort_unstable();
    v
}

/// The tools as an OpenAI chat-completions request carries them.
pub fn openai_tools() -> Vec<Value> {
    tool_specs()
        .into_iter()
        .map(|t| {
            json!({"type": "function", "function": {
                "name": t.name,
                "description": t.description,
                "parameters": t.parameters,
            }})
        })
        .collect()
}

/// The tools as MCP's `tools/list` answers them.
pub fn mcp_tools() -> Vec<Value> {
    tool_specs()
        .into_iter()
        .map(|t| json!({"name": t.name, "description": t.description, "inputSchema": t.parameters}))
        .collect()
}

/// The tool list as `docs/tools.md` shows it (a test holds the page to it): one line per tool,
/// its arguments (`?` for optional ones) and its description.
pub fn tool_list_markdown() -> String {
    let mut out = String::new();
    for t in tool_specs() {
        let required: Vec<&str> = t.parameters["required"]
            .as_array()
            .into_iter()
            .flatten()
            .filter_map(Value::as_str)
            .collect();
        let args: Vec<String> = t.parameters["properties"]
            .as_object()
            .into_iter()
            .flatten()
            .map(|(k, _)| {
                if required.contains(&k.as_str()) {
                    k.clone()
                } else {
                    format!("{k}?")
                }
            })
            .collect();
        let desc = t.description.replace('\n', " ").replace('|', "\\|");
        out.push_str(&format!("- `{}({})`: {desc}\n", t.name, args.join(", ")));
    }
    out
}
