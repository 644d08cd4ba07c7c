//! The JSON object in a model's reply, for the graph baselines (ILN, and SayPlan through `crate::iln::reply`), whose prompts ask
//! for "only JSON": models still wrap it in a code fence or a sentence, so the reply is read from
//! its first `{` to the matching last `}`.

use serde_json::{Map, Value};

/// The reply's JSON object, or why there is none (said so the model can be told).
pub fn json_object(text: &str) -> Result<Map<String, Value>, String> {
    let start = text
        .find('{')
        .ok_or_else(|| "the reply holds no JSON object (no `{`)".to_string())?;
    let end = text
        .rfind('}')
        .filter(|&e| e > start)
        .ok_or_else(|| "the reply's JSON object is not closed (no `}`)".to_string())?;
    match serde_json::from_str::<Value>(&text[start..=end]) {
        Ok(Value::Object(m)) => Ok(m),
        Ok(_) => Err("the reply is not a JSON object".into()),
        Err(e) => Err(format!("the reply is not valid JSON: {e}")),
    }
}

/// A string field of `obj`, or why it is missing.
pub fn string_field<'a>(obj: &'a Map<String, Value>, key: &str) -> Result<&'a str, String> {
    match obj.get(key) {
        Some(Value::String(s)) => Ok(s.as_str()),
        Some(other) => Err(format!("field `{key}` is not a string (got {other})")),
        None => Err(format!("field `{key}` is missing")),
    }
}
