//! Reading OSG-LLM's three replies. Each is one JSON object, found in the reply text even when
//! the model wraps it in a code fence or a sentence; anything that does not validate is an error
//! whose message goes into the record (the episode then fails as `ltl_translation_failed`, as in
//! the adaptation, which has no retry).

use super::graph::SceneGraph;
use super::prefix::{MAX_DEPTH, alias, parse_prefix};
use m2rc_compiler::ltl::Formula;
use m2rc_compiler::ltl::syntax::Kind;
use serde_json::Value;

/// The first JSON object in `text`.
pub fn json_object(text: &str) -> Result<serde_json::Map<String, Value>, String> {
    for (i, _) in text.match_indices('{').take(32) {
        let mut it = serde_json::Deserializer::from_str(&text[i..]).into_iter::<Value>();
        if let Some(Ok(Value::Object(m))) = it.next() {
            return Ok(m);
        }
    }
    Err("the reply holds no JSON object".into())
}

fn strings(m: &serde_json::Map<String, Value>, key: &str) -> Result<Vec<String>, String> {
    match m.get(key) {
        None | Some(Value::Null) => Ok(Vec::new()),
        Some(Value::Array(a)) => a
            .iter()
            .map(|v| match v {
                Value::String(s) => Ok(s.trim().to_string()),
                Value::Number(n) => Ok(n.to_string()),
                other => Err(format!("`{key}` holds {other}, not an id")),
            })
            .collect(),
        Some(other) => Err(format!("`{key}` is {other}, not a list")),
    }
}

/// The grounding call's answer.
#[derive(Clone, Debug, PartialEq)]
pub struct Grounding {
    /// Node ids, in visiting order.
    pub goals: Vec<String>,
    pub avoids: Vec<String>,
    pub unsupported: Vec<String>,
    pub bindings: Value,
}

/// Reads and validates the grounding reply: every id must be a node of `graph`, and there must be
/// a goal.
pub fn parse_grounding(text: &str, graph: &SceneGraph) -> Result<Grounding, String> {
    let m = json_object(text)?;
    let goals = strings(&m, "ordered_goal_entities")?;
    let avoids = strings(&m, "avoid_entities")?;
    for id in goals.iter().chain(&avoids) {
        if graph.node(id).is_none() {
            return Err(format!("`{id}` is not an id of the scene graph"));
        }
    }
    if goals.is_empty() {
        return Err("the grounding names no goal entity".into());
    }
    Ok(Grounding {
        goals,
        avoids,
        unsupported: strings(&m, "unsupported_phrases").unwrap_or_default(),
        bindings: m.get("entity_bindings").cloned().unwrap_or(Value::Null),
    })
}

/// Where the formula came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FormulaSource {
    Prefix,
    Ast,
    /// Neither key was present: built from the grounded goals and avoids.
    Built,
}

impl FormulaSource {
    pub fn as_str(self) -> &'static str {
        match self {
            FormulaSource::Prefix => "ltl_prefix",
            FormulaSource::Ast => "ltl_ast",
            FormulaSource::Built => "built_from_grounding",
        }
    }
}

/// Reads the translation reply over the allowed APs (`allowed`): `ltl_prefix`, else `ltl_ast`,
/// else the formula built from `goals` and `avoids`.
pub fn parse_ltl(
    text: &str,
    allowed: &[String],
    goals: &[String],
    avoids: &[String],
) -> Result<(Formula, FormulaSource), String> {
    let m = json_object(text)?;
    match m.get("ltl_prefix") {
        Some(Value::String(s)) if !s.trim().is_empty() => {
            return parse_prefix(s, allowed)
                .map(|f| (f, FormulaSource::Prefix))
                .map_err(|e| format!("ltl_prefix: {e}"));
        }
        Some(Value::Null) | Some(Value::String(_)) | None => {}
        Some(other) => return Err(format!("ltl_prefix is {other}, not a string")),
    }
    if let Some(ast) = m.get("ltl_ast").filter(|v| !v.is_null()) {
        return from_ast(ast, allowed, 0)
            .map(|f| (f, FormulaSource::Ast))
            .map_err(|e| format!("ltl_ast: {e}"));
    }
    Ok((built(allowed, goals, avoids), FormulaSource::Built))
}

/// `F & g1 F & g2 ... F gk`, conjoined with `G ! a` for every avoid.
pub fn built(allowed: &[String], goals: &[String], avoids: &[String]) -> Formula {
    let atom = |ap: &String| {
        Formula::atom(&alias(
            allowed.iter().position(|x| x == ap).unwrap_or(usize::MAX),
        ))
    };
    let mut chain: Option<Formula> = None;
    for g in goals.iter().rev() {
        let inner = match chain.take() {
            Some(rest) => Formula::new(Kind::And(Box::new(atom(g)), Box::new(rest))),
            None => atom(g),
        };
        chain = Some(Formula::new(Kind::Eventually(Box::new(inner))));
    }
    let mut parts: Vec<Formula> = chain.into_iter().collect();
    for a in avoids {
        parts.push(Formula::new(Kind::Always(Box::new(Formula::negation(
            atom(a),
        )))));
    }
    Formula::and_all(parts)
}

/// `{"op": "F", "args": [..]}` or `{"ap": "enter(room_3)"}`.
fn from_ast(v: &Value, allowed: &[String], depth: usize) -> Result<Formula, String> {
    if depth > MAX_DEPTH {
        return Err(format!("nests deeper than {MAX_DEPTH}"));
    }
    if let Some(ap) = v.get("ap").and_then(Value::as_str) {
        return match allowed.iter().position(|x| x == ap) {
            Some(i) => Ok(Formula::atom(&alias(i))),
            None => Err(format!("`{ap}` is not an allowed atomic proposition")),
        };
    }
    let op = v
        .get("op")
        .and_then(Value::as_str)
        .ok_or_else(|| format!("{v} has neither `ap` nor `op`"))?;
    let args: Vec<Formula> = v
        .get("args")
        .and_then(Value::as_array)
        .map(|a| a.iter().map(|x| from_ast(x, allowed, depth + 1)).collect())
        .transpose()?
        .unwrap_or_default();
    let mut it = args.into_iter().map(Box::new);
    let arity = |k: usize,
                 it: &mut dyn Iterator<Item = Box<Formula>>|
     -> Result<Vec<Box<Formula>>, String> {
        let got: Vec<Box<Formula>> = it.collect();
        if got.len() == k {
            Ok(got)
        } else {
            Err(format!("`{op}` takes {k} operand(s), got {}", got.len()))
        }
    };
    let kind = match op {
        "F" | "G" | "!" => {
            let mut a = arity(1, &mut it)?;
            let x = a.remove(0);
            match op {
                "F" => Kind::Eventually(x),
                "G" => Kind::Always(x),
                _ => Kind::Not(x),
            }
        }
        "&" | "|" | "U" | "->" => {
            let mut a = arity(2, &mut it)?;
            let (x, y) = (a.remove(0), a.remove(0));
            match op {
                "&" => Kind::And(x, y),
                "|" => Kind::Or(x, y),
                "U" => Kind::Until(x, y),
                _ => Kind::Implies(x, y),
            }
        }
        other => {
            return Err(format!(
                "`{other}` is not one of the operators F G ! & | U ->"
            ));
        }
    };
    Ok(Formula::new(kind))
}

/// The heuristic call's preferred rooms (ids of rooms, and the rooms of named objects), in the
/// model's order; ids the graph does not have are returned apart and otherwise ignored.
pub fn parse_heuristic(text: &str, graph: &SceneGraph) -> Result<(Vec<u32>, Vec<String>), String> {
    let m = json_object(text)?;
    let ids = strings(&m, "preferred_nodes")?;
    let (mut rooms, mut unknown) = (Vec::new(), Vec::new());
    for id in ids {
        match graph.node(&id).and_then(|x| x.room) {
            Some(r) if !rooms.contains(&r) => rooms.push(r),
            Some(_) => {}
            None => unknown.push(id),
        }
    }
    Ok((rooms, unknown))
}
