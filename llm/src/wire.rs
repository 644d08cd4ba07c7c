//! The OpenAI chat-completions wire format: the request body we send and the parts of a response
//! we read. Shared by the live client, the cache and the batch files, so a reply parses the same
//! whichever way it arrived.

use m2rc_compiler::lower::{ChatReply, Message, Usage};
use serde_json::{Value, json};

/// The request body for `messages` (`model`, `messages`, `temperature`, `max_tokens`).
pub fn request_body(
    model: &str,
    messages: &[Message],
    temperature: f64,
    max_tokens: Option<u32>,
) -> Value {
    let mut body = json!({
        "model": model,
        "messages": messages,
        "temperature": temperature,
    });
    if let Some(m) = max_tokens {
        body["max_tokens"] = json!(m);
    }
    body
}

/// Reads a chat-completion response body. An error names what is missing or malformed.
pub fn parse_completion(body: &Value, latency_ms: f64) -> Result<ChatReply, String> {
    let obj = body
        .as_object()
        .ok_or_else(|| "the response is not a JSON object".to_string())?;
    if let Some(err) = obj.get("error").filter(|e| !e.is_null()) {
        let msg = err
            .get("message")
            .and_then(Value::as_str)
            .map(str::to_string)
            .unwrap_or_else(|| err.to_string());
        return Err(format!("the server answered with an error: {msg}"));
    }
    let choices = obj
        .get("choices")
        .and_then(Value::as_array)
        .ok_or_else(|| "the response has no `choices` array".to_string())?;
    let usage = obj.get("usage").map_or(Usage::default(), |u| Usage {
        prompt_tokens: u.get("prompt_tokens").and_then(Value::as_u64).unwrap_or(0),
        completion_tokens: u
            .get("completion_tokens")
            .and_then(Value::as_u64)
            .unwrap_or(0),
    });
    let first = choices.first();
    let message = first.and_then(|c| c.get("message"));
    let text = |v: Option<&Value>| v.and_then(Value::as_str).map(str::to_string);
    Ok(ChatReply {
        choices: choices.len(),
        content: text(message.and_then(|m| m.get("content"))),
        finish_reason: text(first.and_then(|c| c.get("finish_reason"))),
        refusal: text(message.and_then(|m| m.get("refusal"))),
        usage,
        latency_ms,
    })
}

/// A completion body holding one assistant message (used by the simulated model, so its replies
/// are cached and parsed exactly like a server's).
pub fn completion_body(model: &str, content: &str, usage: Usage) -> Value {
    json!({
        "object": "chat.completion",
        "model": model,
        "choices": [{
            "index": 0,
            "message": {"role": "assistant", "content": content},
            "finish_reason": "stop",
        }],
        "usage": {
            "prompt_tokens": usage.prompt_tokens,
            "completion_tokens": usage.completion_tokens,
            "total_tokens": usage.prompt_tokens + usage.completion_tokens,
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn completions_parse_and_errors_are_named() {
        let b = json!({"choices": [{"message": {"content": "hi", "refusal": null}, "finish_reason": "length"}],
                       "usage": {"prompt_tokens": 3, "completion_tokens": 4}});
        let r = parse_completion(&b, 1.5).unwrap();
        assert_eq!(r.content.as_deref(), Some("hi"));
        assert_eq!(r.finish_reason.as_deref(), Some("length"));
        assert_eq!(r.usage.completion_tokens, 4);
        assert_eq!(
            parse_completion(&json!({"choices": []}), 0.0)
                .unwrap()
                .choices,
            0
        );
        assert!(
            parse_completion(&json!({"id": 1}), 0.0)
                .unwrap_err()
                .contains("choices")
        );
        assert!(parse_completion(&json!([1]), 0.0).is_err());
        let e = parse_completion(&json!({"error": {"message": "bad"}}), 0.0).unwrap_err();
        assert!(e.contains("bad"));
    }
}
