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

/// The request body of `POST {base}/embeddings` for `inputs`, in order.
pub fn embeddings_body(model: &str, inputs: &[String]) -> Value {
    json!({"model": model, "input": inputs})
}

/// Reads an embeddings response body: one vector per input, ordered by each item's `index` (a
/// server may return them in any order), and the prompt tokens it reports (0 when none).
pub fn parse_embeddings(body: &Value) -> Result<(Vec<Vec<f32>>, Option<u64>), String> {
    let obj = body
        .as_object()
        .ok_or_else(|| "the response is not a JSON object".to_string())?;
    if let Some(err) = obj.get("error").filter(|e| !e.is_null()) {
        return Err(format!("the server answered with an error: {err}"));
    }
    let data = obj
        .get("data")
        .and_then(Value::as_array)
        .ok_or_else(|| "the response has no `data` array of embeddings".to_string())?;
    let mut items: Vec<(u64, Vec<f32>)> = Vec::with_capacity(data.len());
    for (i, item) in data.iter().enumerate() {
        let index = item
            .get("index")
            .and_then(Value::as_u64)
            .unwrap_or(i as u64);
        let vector = item
            .get("embedding")
            .and_then(Value::as_array)
            .ok_or_else(|| format!("`data[{i}]` has no `embedding` list"))?
            .iter()
            .map(|x| x.as_f64().filter(|f| f.is_finite()).map(|f| f as f32))
            .collect::<Option<Vec<f32>>>()
            .ok_or_else(|| {
                format!("`data[{i}].embedding` holds a value that is not a finite number")
            })?;
        items.push((index, vector));
    }
    items.sort_by_key(|(i, _)| *i);
    if items.iter().enumerate().any(|(k, (i, _))| *i != k as u64) {
        return Err("the embeddings' `index` values are not 0, 1, 2, ...".into());
    }
    let tokens = obj
        .get("usage")
        .map_or(Some(0), |u| token_count(u.get("prompt_tokens")));
    Ok((items.into_iter().map(|(_, v)| v).collect(), tokens))
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
    let usage = match obj.get("usage") {
        None | Some(Value::Null) => Usage::default(),
        Some(u) => Usage {
            prompt_tokens: token_count(u.get("prompt_tokens")),
            completion_tokens: token_count(u.get("completion_tokens")),
        },
    };
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

/// The largest reply content taken from a model, in bytes: the program limit
/// (`m2rc_benchmark::limits::MAX_PROGRAM_BYTES`, 256 KiB). A longer reply cannot hold an
/// acceptable program, so it is refused before it is extracted, compiled or stored in a record.
pub const MAX_REPLY_BYTES: usize = 256 * 1024;

/// The most tokens one reply can plausibly account for (a billion); a larger figure is a broken
/// or hostile server's, not a count.
pub const MAX_TOKEN_COUNT: u64 = 1_000_000_000;

/// A `usage` token count: absent is 0 (the server reports none); anything but a whole number in
/// `0..=MAX_TOKEN_COUNT` is unknown.
fn token_count(v: Option<&Value>) -> Option<u64> {
    match v {
        None | Some(Value::Null) => Some(0),
        Some(v) => v.as_u64().filter(|n| *n <= MAX_TOKEN_COUNT),
    }
}

/// Why a reply is refused before its content is used: too long to hold a program.
pub fn check_reply_size(reply: &ChatReply) -> Result<(), String> {
    let n = reply.content.as_ref().map_or(0, String::len);
    if n > MAX_REPLY_BYTES {
        return Err(format!(
            "the reply is {n} bytes, more than the limit of {MAX_REPLY_BYTES} bytes of a program; \
             it was not compiled"
        ));
    }
    Ok(())
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
            "total_tokens": usage.prompt_tokens.zip(usage.completion_tokens).map(|(p, c)| p + c),
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
        assert_eq!(r.usage.completion_tokens, Some(4));
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

    #[test]
    fn invalid_usage_is_unknown_not_zero() {
        let with = |usage: Value| {
            parse_completion(&json!({"choices": [], "usage": usage}), 0.0)
                .unwrap()
                .usage
        };
        for bad in [
            json!(-5),
            json!(1e300),
            json!(2.5),
            json!("12"),
            json!(u64::MAX),
        ] {
            let u = with(json!({"prompt_tokens": bad, "completion_tokens": 3}));
            assert_eq!(u.prompt_tokens, None, "{bad}");
            assert_eq!(u.completion_tokens, Some(3));
            assert!(u.is_unknown());
        }
        assert_eq!(with(json!({"prompt_tokens": 7})).completion_tokens, Some(0));
        let none = parse_completion(&json!({"choices": []}), 0.0)
            .unwrap()
            .usage;
        assert!(!none.is_unknown());
    }
}
