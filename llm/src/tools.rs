//! Function calling on the chat-completions wire: `tools` in the request, `tool_calls` in the
//! reply (several in one turn), `role: tool` messages answering them by `tool_call_id`. The
//! request body carries the tools, so the cache key and a batch line cover them like the
//! messages; a conversation is re-run from its start, each earlier turn answered by the cache.

use m2rc_compiler::lower::ChatReply;
use serde_json::{Value, json};

/// The most tool calls one reply may ask for; more is a broken or hostile server.
pub const MAX_CALLS_PER_TURN: usize = 64;
/// The largest `arguments` text of one call, in bytes.
pub const MAX_ARGUMENT_BYTES: usize = 64 * 1024;

/// One call the model asked for: its id, the tool's name and the arguments (parsed; a text that
/// is not JSON is kept as `Err` with the parse error, so the tool message can say so).
#[derive(Clone, Debug, PartialEq)]
pub struct ToolCall {
    pub id: String,
    pub name: String,
    pub arguments: Result<Value, String>,
    /// The arguments as the model wrote them, to send back in the assistant message.
    pub raw_arguments: String,
}

/// A reply of a function-calling turn: the text part (with usage and finish reason) and the
/// calls.
#[derive(Clone, Debug)]
pub struct ToolReply {
    pub reply: ChatReply,
    pub tool_calls: Vec<ToolCall>,
}

impl ToolReply {
    /// The assistant message to append to the conversation before the tool messages.
    pub fn assistant_message(&self) -> Value {
        let mut m = json!({"role": "assistant", "content": self.reply.content});
        if !self.tool_calls.is_empty() {
            m["tool_calls"] = Value::Array(
                self.tool_calls
                    .iter()
                    .map(|c| {
                        json!({"id": c.id, "type": "function", "function": {
                            "name": c.name, "arguments": c.raw_arguments,
                        }})
                    })
                    .collect(),
            );
        }
        m
    }
}

/// The `role: tool` message answering call `id`.
pub fn tool_message(id: &str, content: &Value) -> Value {
    json!({"role": "tool", "tool_call_id": id, "content": content.to_string()})
}

/// The request body of a function-calling turn.
pub fn tool_request_body(
    model: &str,
    messages: &[Value],
    tools: &[Value],
    temperature: f64,
    max_tokens: Option<u32>,
) -> Value {
    let mut body = json!({
        "model": model,
        "messages": messages,
        "tools": tools,
        "tool_choice": "auto",
        "temperature": temperature,
    });
    if let Some(m) = max_tokens {
        body["max_tokens"] = json!(m);
    }
    body
}

/// The tool calls of a completion's first choice (none when it has no `tool_calls`). An error
/// names what is malformed.
pub fn parse_tool_calls(body: &Value) -> Result<Vec<ToolCall>, String> {
    let Some(calls) = body.pointer("/choices/0/message/tool_calls") else {
        return Ok(Vec::new());
    };
    let calls = match calls {
        Value::Null => return Ok(Vec::new()),
        Value::Array(a) => a,
        _ => return Err("`tool_calls` is not a list".into()),
    };
    if calls.len() > MAX_CALLS_PER_TURN {
        return Err(format!(
            "the reply asks for {} tool calls in one turn, more than the limit of {MAX_CALLS_PER_TURN}",
            calls.len()
        ));
    }
    calls
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let id = c
                .get("id")
                .and_then(Value::as_str)
                .filter(|s| !s.is_empty() && s.len() <= 256)
                .map(str::to_string)
                .unwrap_or_else(|| format!("call_{i}"));
            let name = c
                .pointer("/function/name")
                .and_then(Value::as_str)
                .filter(|s| s.len() <= 64)
                .ok_or_else(|| format!("`tool_calls[{i}]` has no function name (of at most 64 bytes)"))?
                .to_string();
            let raw = match c.pointer("/function/arguments") {
                Some(Value::String(s)) => s.clone(),
                // Some servers send the arguments as an object rather than its text.
                Some(v @ Value::Object(_)) => v.to_string(),
                None | Some(Value::Null) => "{}".to_string(),
                Some(_) => return Err(format!("`tool_calls[{i}].function.arguments` is not a JSON text")),
            };
            if raw.len() > MAX_ARGUMENT_BYTES {
                return Err(format!(
                    "`tool_calls[{i}]`'s arguments are {} bytes, more than the limit of {MAX_ARGUMENT_BYTES}",
                    raw.len()
                ));
            }
            let arguments = serde_json::from_str::<Value>(&raw)
                .map_err(|e| format!("the arguments are not JSON: {e}"));
            Ok(ToolCall {
                id,
                name,
                arguments,
                raw_arguments: raw,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn several_calls_parse_and_malformed_ones_are_named() {
        let body = json!({"choices": [{"message": {"content": null, "tool_calls": [
            {"id": "a", "type": "function", "function": {"name": "rooms", "arguments": "{\"category\":\"bedroom\"}"}},
            {"id": "b", "type": "function", "function": {"name": "objects", "arguments": "{oops"}},
        ]}, "finish_reason": "tool_calls"}]});
        let calls = parse_tool_calls(&body).unwrap();
        assert_eq!(calls.len(), 2);
        assert_eq!(calls[0].arguments, Ok(json!({"category": "bedroom"})));
        assert!(
            calls[1]
                .arguments
                .as_ref()
                .unwrap_err()
                .contains("not JSON")
        );
        let none = json!({"choices": [{"message": {"content": "hi"}}]});
        assert!(parse_tool_calls(&none).unwrap().is_empty());
        let bad = json!({"choices": [{"message": {"tool_calls": [{"id": "x", "function": {}}]}}]});
        assert!(
            parse_tool_calls(&bad)
                .unwrap_err()
                .contains("no function name")
        );
        let many: Vec<Value> = (0..65)
            .map(|i| json!({"id": format!("c{i}"), "function": {"name": "rooms", "arguments": "{}"}}))
            .collect();
        let body = json!({"choices": [{"message": {"tool_calls": many}}]});
        assert!(parse_tool_calls(&body).unwrap_err().contains("limit"));
    }

    #[test]
    fn the_body_carries_the_tools() {
        let tools = vec![json!({"type": "function", "function": {"name": "rooms"}})];
        let b = tool_request_body(
            "m",
            &[json!({"role": "user", "content": "x"})],
            &tools,
            0.0,
            None,
        );
        assert_eq!(b["tools"][0]["function"]["name"], "rooms");
        let other = tool_request_body(
            "m",
            &[json!({"role": "user", "content": "x"})],
            &[],
            0.0,
            None,
        );
        assert_ne!(
            crate::cache::cache_key(&b, ""),
            crate::cache::cache_key(&other, ""),
            "the cache key covers the tools"
        );
    }
}
