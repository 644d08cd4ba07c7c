//! The compiler's diagnostics on a compiled graph, said in terms of the graph: each points at the
//! JSON node its span came from, and a suggestion becomes a JSON patch that replaces that node
//! with the fixed expression (read back from the fixed text), so that the model (or a repair
//! loop that applies certain fixes itself) edits the graph, never the program it never saw.

use super::GraphDiagnostic;
use super::from_program::expr_to_graph;
use super::to_program::Compiled;
use crate::diagnostic::{Code, Diagnostic};
use m2rc_grammar::parse_expr;
use serde_json::{Value, json};

/// The JSON object in a reply: a fenced ```json block, or the text from its first `{` to its
/// last `}`. A reply cut short gets a fix that appends the missing closing brackets.
pub fn reply_json(text: &str) -> Result<Value, Box<GraphDiagnostic>> {
    let body = fenced(text).unwrap_or(text);
    let start = body.find('{');
    let Some(start) = start else {
        return Err(Box::new(GraphDiagnostic::new(
            Code::GraphNotJson,
            "",
            "the reply holds no JSON object",
            Some("answer with one JSON object and nothing else".into()),
        )));
    };
    let end = body.rfind('}').map_or(body.len(), |e| e + 1).max(start);
    let candidate = &body[start..end];
    match serde_json::from_str::<Value>(candidate) {
        Ok(v) if v.is_object() => Ok(v),
        Ok(_) => Err(Box::new(GraphDiagnostic::new(
            Code::GraphNotJson,
            "",
            "the reply's JSON is not an object",
            None,
        ))),
        Err(e) => {
            // Only a document that ends too early has a certain fix: the brackets still open.
            let whole = &body[start..];
            let closing = match serde_json::from_str::<Value>(whole) {
                Err(e2) if e2.is_eof() => missing_closers(whole),
                _ => None,
            };
            let mut d = GraphDiagnostic::new(
                Code::GraphNotJson,
                "",
                format!("the reply's JSON does not parse: {e}"),
                closing
                    .as_ref()
                    .map(|c| format!("the JSON ends early: close it with `{c}`")),
            );
            d.patch = closing.map(|c| json!({"op": "append_text", "text": c}));
            Err(Box::new(d))
        }
    }
}

fn fenced(text: &str) -> Option<&str> {
    let open = text.find("```")?;
    let rest = &text[open + 3..];
    let body_start = rest.find('\n')? + 1;
    let body = &rest[body_start..];
    let end = body.find("```").unwrap_or(body.len());
    Some(&body[..end])
}

/// The brackets left open at the end of `text` (outside strings), innermost first.
fn missing_closers(text: &str) -> Option<String> {
    let mut stack = Vec::new();
    let mut in_str = false;
    let mut escaped = false;
    for c in text.chars() {
        if in_str {
            match (escaped, c) {
                (true, _) => escaped = false,
                (false, '\\') => escaped = true,
                (false, '"') => in_str = false,
                _ => {}
            }
            continue;
        }
        match c {
            '"' => in_str = true,
            '{' => stack.push('}'),
            '[' => stack.push(']'),
            '}' | ']' if stack.pop() != Some(c) => return None,
            _ => {}
        }
    }
    if in_str || stack.is_empty() {
        return None;
    }
    let closers: String = stack.iter().rev().collect();
    // The closers must really finish the document, else the fix is not certain.
    serde_json::from_str::<Value>(&format!("{text}{closers}"))
        .ok()
        .map(|_| closers)
}

/// The compiler's diagnostics on `compiled.program` as graph diagnostics.
pub fn graph_feedback(compiled: &Compiled, diags: &[Diagnostic]) -> Vec<GraphDiagnostic> {
    diags
        .iter()
        .map(|d| {
            let pointer = compiled
                .locate(d.span)
                .map_or(String::new(), |(p, _)| p.to_string());
            let mut diagnostic = d.clone();
            // Spans and edits of the program mean nothing to a graph's writer.
            diagnostic.suggestions.clear();
            diagnostic.labels.clear();
            let patch = d.suggestions.first().and_then(|s| patch_for(compiled, s));
            if let Some(h) = &d.help
                && h.contains("write `")
                && patch.is_none()
            {
                // A `write `...`` help quotes program text; keep it, it reads as an expression.
                diagnostic.help = Some(h.clone());
            }
            GraphDiagnostic {
                diagnostic,
                pointer,
                patch,
            }
        })
        .collect()
}

/// A suggestion as a JSON patch: the smallest expression node around the edit, with the edit
/// applied to its text, read back into a graph value.
fn patch_for(compiled: &Compiled, s: &crate::diagnostic::Suggestion) -> Option<Value> {
    let src = &compiled.program;
    if s.span.end > src.len() || s.span.start > s.span.end {
        return None;
    }
    let mut around: Vec<&(m2rc_grammar::ast::Span, String)> = compiled
        .map
        .iter()
        .filter(|(n, p)| n.start <= s.span.start && s.span.end <= n.end && is_expr_pointer(p))
        .collect();
    around.sort_by_key(|(n, _)| (n.end - n.start, std::cmp::Reverse(n.start)));
    // The smallest node whose edited text is still an expression (deleting an argument leaves
    // nothing of the argument, but a whole call).
    around.into_iter().find_map(|(node, pointer)| {
        let text = src.get(node.start..node.end)?;
        let new = format!(
            "{}{}{}",
            src.get(node.start..s.span.start)?,
            s.replacement,
            src.get(s.span.end..node.end)?
        );
        if new == text {
            return None;
        }
        let expr = parse_expr(&new).ok()?;
        let value = expr_to_graph(&expr).ok()?;
        Some(json!({"op": "replace", "path": pointer, "value": value}))
    })
}

/// Whether a pointer names an expression (not a statement such as a segment or a constraint).
fn is_expr_pointer(p: &str) -> bool {
    let last = p.rsplit('/').next().unwrap_or("");
    let parent = p.rsplit('/').nth(1).unwrap_or("");
    matches!(
        last,
        "to" | "value" | "place" | "preference" | "within" | "in" | "of" | "body"
    ) || parent == "args"
        || parent == "kwargs"
}

/// Applies the certain fixes (`fix` of each error) to a reply: text appends to the raw text,
/// replacements to the parsed graph. Returns the new reply text, or `None` when no fix applied.
pub fn apply_fixes(reply: &str, diags: &[GraphDiagnostic]) -> Option<String> {
    let fixes: Vec<&Value> = diags
        .iter()
        .filter(|d| d.is_error())
        .filter_map(|d| d.patch.as_ref())
        .collect();
    if fixes.is_empty() {
        return None;
    }
    let mut text = reply.to_string();
    for f in &fixes {
        if f["op"] == "append_text"
            && let Some(t) = f["text"].as_str()
        {
            let body = fenced(&text).unwrap_or(&text).trim_end().to_string();
            text = format!("{body}{t}");
        }
    }
    let mut graph = reply_json(&text).ok()?;
    let mut changed = text != reply;
    for f in fixes.iter().filter(|f| f["op"] == "replace") {
        let (Some(path), Some(value)) = (f["path"].as_str(), f.get("value")) else {
            continue;
        };
        if let Some(slot) = graph.pointer_mut(path) {
            *slot = value.clone();
            changed = true;
        }
    }
    changed.then(|| serde_json::to_string(&graph).unwrap_or_default())
}
