//! Embeddings through the same [`Store`] as chat requests: `POST {base}/embeddings` (llama.cpp,
//! vLLM, Ollama and the OpenAI Batch API serve it), cache first, then the batch file (the episode
//! is pending), then the server unless the run is cache-only. Used by the baselines whose
//! grounding compares text embeddings (Lang2LTL, Lang2LTL-2).

use crate::batch::export_id;
use crate::cache::cache_key;
use crate::client::HttpClient;
use crate::exchange::Store;
use crate::wire::{embeddings_body, parse_embeddings};
use m2rc_compiler::lower::ChatError;

/// Key material that keeps embeddings entries apart from chat entries of the same cache.
const KEY_EXTRA: &str = "embeddings";

/// Vectors for a request's inputs, in order.
#[derive(Clone, Debug, PartialEq)]
pub struct EmbedReply {
    pub vectors: Vec<Vec<f32>>,
    /// As the server reported it; `None` when it was not a token count.
    pub prompt_tokens: Option<u64>,
    pub latency_ms: f64,
}

/// Embeds `inputs` with `model`. `custom_id` names the request in batch files and errors. A reply
/// with another number of vectors than inputs, or vectors of different lengths, fails the request.
pub fn embed(
    store: &Store,
    client: Option<&HttpClient>,
    model: &str,
    custom_id: &str,
    inputs: &[String],
) -> Result<EmbedReply, ChatError> {
    let body = embeddings_body(model, inputs);
    let key = cache_key(&body, KEY_EXTRA);
    let check = |response: &serde_json::Value, latency_ms: f64| {
        let (vectors, prompt_tokens) =
            parse_embeddings(response).map_err(|e| format!("{custom_id}: {e}"))?;
        if vectors.len() != inputs.len() {
            return Err(format!(
                "{custom_id}: the server returned {} embedding(s) for {} input(s)",
                vectors.len(),
                inputs.len()
            ));
        }
        if let Some(first) = vectors.first()
            && (first.is_empty() || vectors.iter().any(|v| v.len() != first.len()))
        {
            return Err(format!(
                "{custom_id}: the embeddings do not all have the same, non-zero length"
            ));
        }
        Ok(EmbedReply {
            vectors,
            prompt_tokens,
            latency_ms,
        })
    };
    if let Some(cache) = &store.cache
        && let Some((response, latency)) = cache.get(&key)
    {
        match check(&response, latency) {
            Ok(r) => {
                store.count(|s| s.cache_hits += 1);
                return Ok(r);
            }
            Err(_) => store.count(|s| s.corrupt_cache_entries += 1),
        }
    }
    if let (Some(batch), Some(cache)) = (&store.batch, &store.cache) {
        let recorded = cache
            .put_pending(custom_id, &key, model)
            .and_then(|()| batch.add_to(&export_id(custom_id, &key), "/v1/embeddings", &body));
        return match recorded {
            Ok(()) => {
                store.count(|s| s.pending += 1);
                Err(ChatError::Pending(custom_id.to_string()))
            }
            Err(e) => {
                store.count(|s| s.failed += 1);
                Err(ChatError::Failed(format!(
                    "{custom_id}: cannot write the batch request: {e}"
                )))
            }
        };
    }
    if store.cache_only {
        store.count(|s| s.failed += 1);
        return Err(ChatError::Failed(format!(
            "no cached embeddings for `{custom_id}` and --llm-cache-only is set"
        )));
    }
    let Some(client) = client else {
        store.count(|s| s.failed += 1);
        return Err(ChatError::Failed(format!(
            "{custom_id}: no embeddings server configured"
        )));
    };
    let fetched = client.fetch_embeddings(custom_id, &body).inspect_err(|_| {
        store.count(|s| s.failed += 1);
    })?;
    let reply = check(&fetched.response, fetched.latency_ms).map_err(|e| {
        store.count(|s| s.failed += 1);
        ChatError::Failed(e)
    })?;
    if let Some(cache) = &store.cache {
        let _ = cache.put(&key, custom_id, &fetched.response, fetched.latency_ms);
    }
    store.count(|s| s.fetched += 1);
    Ok(reply)
}
