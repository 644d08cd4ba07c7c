//! Helpers shared by the tests: model setups over a mock server, a cache or gold replies.

use m2rc_baselines::ModelSetup;
use m2rc_baselines::calls::embed::EmbedMode;
use m2rc_llm::{Backend, BatchOut, HttpClient, LlmConfig, ResponseCache, Store};
use serde_json::{Value, json};
use std::path::Path;
use std::time::Duration;

pub fn client(url: &str, model: &str) -> HttpClient {
    HttpClient::new(LlmConfig {
        base_url: format!("{url}/v1"),
        model: model.into(),
        timeout: Duration::from_secs(10),
        max_attempts: 2,
        backoff_base: Duration::from_millis(1),
        backoff_max: Duration::from_millis(5),
        ..LlmConfig::default()
    })
    .unwrap()
}

/// A setup against `url` with server embeddings, caching under `cache` (and exporting to
/// `batch`, when given).
pub fn server_setup(url: &str, cache: &Path, batch: Option<&Path>) -> ModelSetup {
    ModelSetup {
        backend: Backend::Http,
        store: Store::new(
            Some(ResponseCache::new(cache)),
            batch.map(BatchOut::new),
            false,
        ),
        http: Some(client(url, "mock")),
        embed_http: Some(client(url, "mock-embed")),
        model: "mock".into(),
        base_url: Some(format!("{url}/v1")),
        temperature: 0.0,
        max_tokens: Some(512),
        embeddings: EmbedMode::Server {
            model: "mock-embed".into(),
        },
    }
}

pub fn gold_setup() -> ModelSetup {
    ModelSetup {
        backend: Backend::Gold,
        store: Store::default(),
        http: None,
        embed_http: None,
        model: "default".into(),
        base_url: None,
        temperature: 0.0,
        max_tokens: None,
        embeddings: EmbedMode::Lexical,
    }
}

pub fn completion(text: &str) -> Value {
    json!({"choices": [{"message": {"role": "assistant", "content": text}, "finish_reason": "stop"}],
           "usage": {"prompt_tokens": 10, "completion_tokens": 5}})
}

pub fn embeddings(vectors: &[Vec<f32>]) -> Value {
    json!({"object": "list", "data": vectors.iter().enumerate().map(|(i, v)| json!({"index": i, "embedding": v})).collect::<Vec<_>>()})
}
