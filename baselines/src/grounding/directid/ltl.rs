//! Catalog-LTL: the reference code's `ltl` grounding row. The model names catalog ids as
//! propositions and writes the hard part of the route as a restricted LTL formula: one nested
//! eventuality chain of visits `F(v1 & F(v2 & ...))` and `G(!a)` for avoids that hold all the way;
//! a scoped avoid names its segments in `during`, and soft propositions stay beside the formula.
//! The reply is read into Direct ID's grounding and compiled through the Direct ID path (RouteIR
//! and CaG's planner). It is not `m2rc ablate`'s `gold+ltl` / `llm+ltl` rows, which plan `.m2r`
//! programs through m2rc's LTL backend.

use super::validate::{Grounding, escape, validate};
use super::{Form, prompt};
use m2rc_compiler::diagnostic::Code;
use m2rc_compiler::intent::GraphDiagnostic;
use m2rc_compiler::lower::Prompt;
use m2rc_stdlib::query::MapQuery;
use serde_json::{Map, Value, json};

pub const NAME: &str = "catalog-ltl";

/// Longest formula read (characters) and deepest nesting: a reply is user input.
pub const MAX_FORMULA_CHARS: usize = 4096;
pub const MAX_DEPTH: usize = 64;

pub const FORM: Form = Form {
    name: NAME,
    what: "catalog-LTL grounding",
    prompt: ltl_prompt,
    read,
    write: from_direct_id,
};

pub const FORMAT: &str = "\
Reply with one JSON object {formula, propositions}.
- propositions: [{name, kind, ref_ids, during?, spatial_scope_ids?, within_m?, relation?, \
path_shape?, source_text?}]; `name` is a short identifier used in the formula.
  - kind `visit`: a destination, exactly one id in `ref_ids` (a room or an object).
  - kind `avoid`: never enter any of `ref_ids` (with `within_m`: the area that many metres around \
them). An avoid for the whole route appears in the formula as `G(!name)`; an avoid for some \
destinations only lists their visit names in `during` and stays out of the formula.
  - kinds `prefer_near`, `prefer_far` (one id), `prefer_relative` (two ids, `relation` \
`closer_to` or `farther_from` the first), `prefer_path_shape` (`path_shape` {type: circle | \
follow_wall | through, direction?: clockwise | counterclockwise}): soft; never in the formula; \
`during` and `spatial_scope_ids` limit them.
- formula: operators F G X ! & | ( ). The visits form exactly one nested chain \
`F(v1 & F(v2 & F(v3)))` in visiting order, each visit used once; conjoin `G(!a)` for each global \
avoid: `F(v1 & F(v2)) & G(!a1)`.
- Every id must appear verbatim in the catalog. Resolve references yourself from the catalog. \
Do not invent ids, coordinates, paths or planner parameters.
";

pub const EXAMPLE: &str = r#"Instruction: "Go to the bed in the small bedroom, staying away from the TV while in the living room, then walk around the dining table to the fridge. Never enter the bathroom."
{"formula":"F(bed & F(fridge)) & G(!bath)","propositions":[{"name":"bed","kind":"visit","ref_ids":["object_31"]},{"name":"fridge","kind":"visit","ref_ids":["object_7"]},{"name":"bath","kind":"avoid","ref_ids":["room_4"]},{"name":"tv","kind":"prefer_far","ref_ids":["object_12"],"during":["bed"],"spatial_scope_ids":["room_2"]},{"name":"table","kind":"prefer_path_shape","ref_ids":["object_9"],"during":["fridge"],"path_shape":{"type":"circle"}}]}"#;

pub fn ltl_prompt(catalog: &Value, instruction: &str) -> Prompt {
    prompt::prompt_with(catalog, instruction, FORMAT, EXAMPLE)
}

#[derive(Clone, Debug, PartialEq)]
enum F {
    Atom(String),
    Not(Box<F>),
    Eventually(Box<F>),
    Always(Box<F>),
    Next(Box<F>),
    And(Box<F>, Box<F>),
    Or(Box<F>, Box<F>),
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Id(String),
    Op(char),
}

fn normalise(c: char) -> char {
    match c {
        '◇' | '◊' => 'F',
        '□' | '◻' => 'G',
        '○' => 'X',
        '¬' => '!',
        '∧' => '&',
        '∨' => '|',
        c => c,
    }
}

fn lex(text: &str) -> Result<Vec<Tok>, String> {
    let text = text.replace("&&", "&").replace("||", "|");
    let chars: Vec<char> = text.chars().map(normalise).collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() {
            i += 1;
        } else if "!&|()".contains(c) {
            out.push(Tok::Op(c));
            i += 1;
        } else if c.is_ascii_alphabetic() || c == '_' {
            let s = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            let w: String = chars[s..i].iter().collect();
            match w.as_str() {
                "F" | "G" | "X" => out.push(Tok::Op(w.chars().next().unwrap_or('F'))),
                _ => out.push(Tok::Id(w)),
            }
        } else {
            return Err(format!(
                "`{c}` is not an operator of the formula (F G X ! & | ( ))"
            ));
        }
    }
    Ok(out)
}

struct Parser {
    toks: Vec<Tok>,
    at: usize,
}

impl Parser {
    fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.at)
    }

    fn or(&mut self, depth: usize) -> Result<F, String> {
        let mut l = self.and(depth)?;
        while self.peek() == Some(&Tok::Op('|')) {
            self.at += 1;
            l = F::Or(Box::new(l), Box::new(self.and(depth)?));
        }
        Ok(l)
    }

    fn and(&mut self, depth: usize) -> Result<F, String> {
        let mut l = self.unary(depth)?;
        while self.peek() == Some(&Tok::Op('&')) {
            self.at += 1;
            l = F::And(Box::new(l), Box::new(self.unary(depth)?));
        }
        Ok(l)
    }

    fn unary(&mut self, depth: usize) -> Result<F, String> {
        if depth > MAX_DEPTH {
            return Err(format!("the formula nests deeper than {MAX_DEPTH}"));
        }
        let t = self.peek().cloned();
        self.at += 1;
        match t {
            Some(Tok::Op('!')) => Ok(F::Not(Box::new(self.unary(depth + 1)?))),
            Some(Tok::Op('F')) => Ok(F::Eventually(Box::new(self.unary(depth + 1)?))),
            Some(Tok::Op('G')) => Ok(F::Always(Box::new(self.unary(depth + 1)?))),
            Some(Tok::Op('X')) => Ok(F::Next(Box::new(self.unary(depth + 1)?))),
            Some(Tok::Op('(')) => {
                let inner = self.or(depth + 1)?;
                if self.peek() != Some(&Tok::Op(')')) {
                    return Err("a `(` is not closed".into());
                }
                self.at += 1;
                Ok(inner)
            }
            Some(Tok::Id(s)) => Ok(F::Atom(s)),
            Some(Tok::Op(c)) => Err(format!("`{c}` where a proposition or `(` was expected")),
            None => Err("the formula ends where a proposition was expected".into()),
        }
    }
}

fn parse(text: &str) -> Result<F, String> {
    if text.chars().count() > MAX_FORMULA_CHARS {
        return Err(format!(
            "the formula is longer than {MAX_FORMULA_CHARS} characters"
        ));
    }
    let mut p = Parser {
        toks: lex(text)?,
        at: 0,
    };
    let f = p.or(0)?;
    if p.at < p.toks.len() {
        return Err("the formula goes on after a complete expression".into());
    }
    Ok(f)
}

fn conjuncts(f: F, out: &mut Vec<F>) {
    match f {
        F::And(a, b) => {
            conjuncts(*a, out);
            conjuncts(*b, out);
        }
        f => out.push(f),
    }
}

/// The visits of `F(v1 & F(v2 & ...))`, in order.
fn chain(f: &F) -> Option<Vec<String>> {
    let F::Eventually(inner) = f else { return None };
    match inner.as_ref() {
        F::Atom(v) => Some(vec![v.clone()]),
        F::And(a, b) => {
            let F::Atom(v) = a.as_ref() else { return None };
            let mut rest = chain(b)?;
            rest.insert(0, v.clone());
            Some(rest)
        }
        _ => None,
    }
}

/// `G(!a)`'s `a`.
fn global_avoid(f: &F) -> Option<String> {
    match f {
        F::Always(inner) => match inner.as_ref() {
            F::Not(a) => match a.as_ref() {
                F::Atom(a) => Some(a.clone()),
                _ => None,
            },
            _ => None,
        },
        _ => None,
    }
}

fn err(pointer: &str, message: impl Into<String>, help: Option<&str>) -> GraphDiagnostic {
    GraphDiagnostic::new(Code::GraphShape, pointer, message, help.map(str::to_string))
}

const SKELETON: &str = "write one chain `F(v1 & F(v2 & ...))` of the visits in order, conjoined with `G(!a)` for each global avoid";

/// A catalog-LTL reply as a Direct ID reply, and where each of its segments and constraints
/// came from (`/propositions/k`).
/// A Direct ID reply and, per segment and constraint, the proposition it came from.
type Translated = (Value, Vec<(String, String)>);

fn to_direct_id(reply: &Value) -> Result<Translated, Vec<GraphDiagnostic>> {
    let mut errors = Vec::new();
    for k in reply.as_object().into_iter().flat_map(Map::keys) {
        if k != "formula" && k != "propositions" {
            errors.push(err(
                &format!("/{}", escape(k)),
                format!("unknown key `{k}`"),
                Some("the keys here are: formula, propositions"),
            ));
        }
    }
    let props: Vec<Value> = match reply.get("propositions").and_then(Value::as_array) {
        Some(p) => p.clone(),
        None => {
            errors.push(err(
                "/propositions",
                "the reply needs `propositions`: an array",
                None,
            ));
            return Err(errors);
        }
    };
    let name_of = |p: &Value| {
        p.get("name")
            .and_then(Value::as_str)
            .unwrap_or("")
            .to_string()
    };
    let index = |name: &str| props.iter().position(|p| name_of(p) == name);
    for (k, p) in props.iter().enumerate() {
        let n = name_of(p);
        if n.is_empty()
            || !n.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
            || matches!(n.as_str(), "F" | "G" | "X")
        {
            errors.push(err(
                &format!("/propositions/{k}/name"),
                "a proposition needs a `name`: letters, digits and `_`, not F, G or X",
                None,
            ));
        } else if index(&n) != Some(k) {
            errors.push(err(
                &format!("/propositions/{k}/name"),
                format!("proposition `{n}` is named twice"),
                None,
            ));
        }
    }
    let formula = reply.get("formula").and_then(Value::as_str).unwrap_or("");
    let f = match parse(formula) {
        Ok(f) => f,
        Err(m) => {
            errors.push(err("/formula", m, Some(SKELETON)));
            return Err(errors);
        }
    };
    let mut parts = Vec::new();
    conjuncts(f, &mut parts);
    let mut visits: Option<Vec<String>> = None;
    let mut global: Vec<String> = Vec::new();
    for part in &parts {
        if let Some(c) = chain(part) {
            if visits.is_some() {
                errors.push(err(
                    "/formula",
                    "the formula has more than one chain of visits",
                    Some(SKELETON),
                ));
            }
            visits = Some(c);
        } else if let Some(a) = global_avoid(part) {
            global.push(a);
        } else {
            errors.push(err(
                "/formula",
                "the formula is outside the skeleton",
                Some(SKELETON),
            ));
        }
    }
    let visits = visits.unwrap_or_default();
    if visits.is_empty() && errors.is_empty() {
        errors.push(err(
            "/formula",
            "the formula has no chain of visits",
            Some(SKELETON),
        ));
    }
    for (i, v) in visits.iter().enumerate() {
        if visits[..i].contains(v) {
            errors.push(err(
                "/formula",
                format!("visit `{v}` is used twice in the chain"),
                Some("each visit appears once"),
            ));
        }
    }
    for name in visits.iter().chain(&global) {
        match index(name) {
            None => errors.push(err(
                "/formula",
                format!("`{name}` is not the name of a proposition"),
                None,
            )),
            Some(k) => {
                let kind = props[k].get("kind").and_then(Value::as_str).unwrap_or("");
                let want = if visits.contains(name) {
                    "visit"
                } else {
                    "avoid"
                };
                if kind != want {
                    errors.push(err(
                        &format!("/propositions/{k}/kind"),
                        format!("`{name}` is a {want} in the formula, and its kind is `{kind}`"),
                        None,
                    ));
                }
            }
        }
    }
    let mut segments = Vec::new();
    let mut constraints = Vec::new();
    let mut sources: Vec<(String, String)> = Vec::new();
    for (i, v) in visits.iter().enumerate() {
        let Some(k) = index(v) else { continue };
        let ids = props[k].get("ref_ids").and_then(Value::as_array);
        if ids.is_none_or(|a| a.len() != 1) {
            errors.push(GraphDiagnostic::new(
                Code::CatalogArity,
                &format!("/propositions/{k}/ref_ids"),
                format!("visit `{v}` takes exactly one id"),
                None,
            ));
            continue;
        }
        segments.push(json!({"id": v, "target_id": ids.map_or(Value::Null, |a| a[0].clone())}));
        sources.push((format!("/segments/{i}"), format!("/propositions/{k}")));
    }
    for (k, p) in props.iter().enumerate() {
        let n = name_of(p);
        let kind = p.get("kind").and_then(Value::as_str).unwrap_or("");
        let mut c = Map::new();
        match kind {
            "visit" => {
                if !visits.contains(&n) {
                    errors.push(err(
                        &format!("/propositions/{k}"),
                        format!("visit `{n}` is not in the formula's chain"),
                        Some(SKELETON),
                    ));
                }
                continue;
            }
            "avoid" => {
                let scoped = p.get("during").is_some_and(|d| !d.is_null());
                if global.contains(&n) == scoped {
                    errors.push(err(
                        &format!("/propositions/{k}"),
                        format!("avoid `{n}` must be either `G(!{n})` in the formula or limited by `during`, and only one"),
                        None,
                    ));
                    continue;
                }
                c.insert("kind".into(), json!("forbid"));
            }
            "prefer_near" | "prefer_far" | "prefer_relative" | "prefer_path_shape" => {
                c.insert("kind".into(), json!(kind));
            }
            _ => {
                errors.push(err(&format!("/propositions/{k}/kind"), format!("`{kind}` is not a proposition kind"), Some("the kinds are: visit, avoid, prefer_near, prefer_far, prefer_relative, prefer_path_shape")));
                continue;
            }
        }
        for (from, to) in [
            ("ref_ids", "ref_ids"),
            ("during", "segment_ids"),
            ("spatial_scope_ids", "spatial_scope_ids"),
            ("within_m", "within_m"),
            ("relation", "relation"),
            ("path_shape", "path_shape"),
        ] {
            if let Some(x) = p.get(from) {
                c.insert(to.into(), x.clone());
            }
        }
        for key in p.as_object().into_iter().flat_map(Map::keys) {
            if ![
                "name",
                "kind",
                "ref_ids",
                "during",
                "spatial_scope_ids",
                "within_m",
                "relation",
                "path_shape",
                "source_text",
            ]
            .contains(&key.as_str())
            {
                errors.push(err(
                    &format!("/propositions/{k}/{}", escape(key)),
                    format!("unknown key `{key}`"),
                    None,
                ));
            }
        }
        sources.push((
            format!("/constraints/{}", constraints.len()),
            format!("/propositions/{k}"),
        ));
        constraints.push(Value::Object(c));
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    Ok((
        json!({"segments": segments, "constraints": constraints}),
        sources,
    ))
}

/// A pointer into the Direct ID reply, said in the catalog-LTL reply.
fn back(pointer: &str, sources: &[(String, String)]) -> String {
    for (from, to) in sources {
        if let Some(rest) = pointer.strip_prefix(from.as_str())
            && (rest.is_empty() || rest.starts_with('/'))
        {
            let rest = if let Some(r) = rest.strip_prefix("/target_id") {
                format!("/ref_ids/0{r}")
            } else if let Some(r) = rest.strip_prefix("/segment_ids") {
                format!("/during{r}")
            } else {
                rest.to_string()
            };
            return format!("{to}{rest}");
        }
    }
    if pointer.starts_with("/segments") {
        return "/formula".into();
    }
    pointer.to_string()
}

/// Reads a catalog-LTL reply; every diagnostic points into it.
pub fn read(reply: &Value, q: &MapQuery) -> Result<Grounding, Vec<GraphDiagnostic>> {
    let (direct, sources) = to_direct_id(reply)?;
    validate(&direct, q).map_err(|ds| {
        ds.into_iter()
            .map(|mut d| {
                d.pointer = back(&d.pointer, &sources);
                d
            })
            .collect()
    })
}

/// A Direct ID reply as catalog-LTL (gold and simulated replies). A must-pass place has no form
/// in the skeleton (each visit is a destination): it is left out and said.
pub fn from_direct_id(direct: &Value) -> (Value, Vec<String>) {
    let mut lossy = Vec::new();
    let mut props = Vec::new();
    let mut chain: Vec<String> = Vec::new();
    let mut taken: Vec<String> = Vec::new();
    let fresh = |base: &str, taken: &mut Vec<String>| {
        let mut n = base.to_string();
        let mut k = 1;
        while taken.contains(&n) || matches!(n.as_str(), "F" | "G" | "X") || n.is_empty() {
            k += 1;
            n = format!("{base}_{k}");
        }
        taken.push(n.clone());
        n
    };
    let mut renamed: Vec<(String, String)> = Vec::new();
    for s in direct["segments"].as_array().into_iter().flatten() {
        let id = s["id"].as_str().unwrap_or("v");
        let safe: String = id
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '_' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        let n = fresh(&safe, &mut taken);
        renamed.push((id.to_string(), n.clone()));
        chain.push(n.clone());
        props.push(json!({"name": n, "kind": "visit", "ref_ids": [s["target_id"].clone()]}));
    }
    let mut global = Vec::new();
    for (i, c) in direct["constraints"]
        .as_array()
        .into_iter()
        .flatten()
        .enumerate()
    {
        let kind = c["kind"].as_str().unwrap_or("");
        if kind == "require_visit" {
            lossy.push(format!(
                "must-pass {} has no catalog-LTL form; dropped",
                c["ref_ids"]
            ));
            continue;
        }
        let base = if kind == "forbid" { "avoid" } else { "p" };
        let n = fresh(&format!("{base}{}", i + 1), &mut taken);
        let mut p = json!({"name": n, "kind": if kind == "forbid" { "avoid" } else { kind }});
        for (from, to) in [
            ("ref_ids", "ref_ids"),
            ("segment_ids", "during"),
            ("spatial_scope_ids", "spatial_scope_ids"),
            ("within_m", "within_m"),
            ("relation", "relation"),
            ("path_shape", "path_shape"),
        ] {
            if let Some(x) = c.get(from) {
                p[to] = x.clone();
            }
        }
        if let Some(d) = p.get_mut("during").and_then(Value::as_array_mut) {
            for x in d.iter_mut() {
                if let Some((_, n)) = renamed.iter().find(|(o, _)| Some(o.as_str()) == x.as_str()) {
                    *x = json!(n);
                }
            }
        }
        if kind == "forbid" && c.get("segment_ids").is_none() {
            global.push(n.clone());
        }
        props.push(p);
    }
    let mut formula = String::new();
    for v in &chain {
        if !formula.is_empty() {
            formula.push_str(" & ");
        }
        formula.push_str(&format!("F({v}"));
    }
    formula.push_str(&")".repeat(chain.len()));
    for a in &global {
        formula.push_str(&format!(" & G(!{a})"));
    }
    (json!({"formula": formula, "propositions": props}), lossy)
}

/// The registry's catalog-LTL: one-shot, as the reference's code runs it.
pub fn make(
    setup: std::sync::Arc<crate::calls::ModelSetup>,
) -> Box<dyn m2rc_benchmark::methods::Method> {
    Box::new(super::CatalogIds::new(setup, 0, &FORM))
}
