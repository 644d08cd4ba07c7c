//! The LLM-call helper every baseline uses. A call goes through `m2rc_llm::Exchange` and its
//! [`Store`] exactly as `grounding2route`'s do: the response cache first, then the batch file (the
//! episode is then `pending`), then the server unless the run is cache-only, with the client's
//! retries, timeouts and concurrency gate. A multi-call method simply re-runs from its first call
//! each time: earlier calls are answered from the cache, and the first call the cache cannot
//! answer in a batch run makes the episode pending, so R layers of calls are R batch rounds.
//!
//! With `--llm gold` each call is answered by the method's own oracle (a closure it passes with
//! the call) from the episode's gold annotations, never by a model; such runs are labelled
//! `[GOLD replies]`. Every call, gold or not, is recorded for the prediction record.

pub mod embed;

use crate::common::failure::{Failure, PENDING};
use embed::EmbedMode;
use m2rc_benchmark::episode::Episode;
use m2rc_compiler::lower::{ChatError, ChatModel, ChatReply, ChatRequest, Message};
use m2rc_llm::{Backend, Exchange, Fetch, Fetched, HttpClient, Store};
use serde_json::{Value, json};

/// The label of every output made with gold replies.
pub const GOLD_LABEL: &str = "[GOLD replies]";

/// The model side of a baseline run, shared by all its episodes: backend, store, client, and
/// where embeddings come from.
pub struct ModelSetup {
    pub backend: Backend,
    pub store: Store,
    pub http: Option<HttpClient>,
    /// A second client for embeddings (its own model name), when embeddings come from a server.
    pub embed_http: Option<HttpClient>,
    pub model: String,
    pub base_url: Option<String>,
    pub temperature: f64,
    pub max_tokens: Option<u32>,
    pub embeddings: EmbedMode,
}

impl ModelSetup {
    pub fn is_gold(&self) -> bool {
        self.backend == Backend::Gold
    }

    /// What answered the calls, for records and messages.
    pub fn label(&self) -> String {
        format!("{}; {}", self.chat_label(), self.embeddings.label())
    }

    /// What answered the chat calls alone, for the methods that never embed text.
    pub fn chat_label(&self) -> String {
        match &self.backend {
            Backend::Gold => GOLD_LABEL.to_string(),
            Backend::Http => format!(
                "{} at {}",
                self.model,
                self.base_url.as_deref().unwrap_or("?")
            ),
            Backend::Simulated(s) => s.label(),
        }
    }

    /// What decides the replies (not the caches, batch files, timeouts or concurrency), for the
    /// run's fingerprint. A method adds its own settings beside it.
    pub fn config(&self) -> Value {
        json!({
            "backend": self.backend,
            "model": if self.is_gold() { Value::Null } else { json!(self.model) },
            "temperature": self.temperature,
            "max_tokens": self.max_tokens,
            "embeddings": self.embeddings,
        })
    }
}

/// A backend with the method's own sampling temperature (LIMP samples at 0.2).
struct Tuned<'a> {
    inner: &'a HttpClient,
    temperature: f64,
}

impl Fetch for Tuned<'_> {
    fn model(&self) -> &str {
        self.inner.model()
    }
    fn temperature(&self) -> f64 {
        self.temperature
    }
    fn max_tokens(&self) -> Option<u32> {
        self.inner.max_tokens()
    }
    fn fetch(&self, request: &ChatRequest, body: &Value) -> Result<Fetched, ChatError> {
        self.inner.fetch(request, body)
    }
}

/// The gold oracle as a backend, so its replies are cached like a model's. Its model name is
/// part of every cache key, so a server's replies and the oracle's never answer for each other.
struct GoldOracle {
    /// `None` in a cache-only run: a miss there must fail, not be answered.
    reply: Option<String>,
    temperature: f64,
}

/// The version of the gold oracles' replies, part of every cache key: bump it whenever an oracle
/// changes what it answers, so a cached ceiling is never one the current code would not reach.
pub const GOLD_REPLIES_VERSION: u32 = 1;

/// The model name under which gold replies are cached.
pub const GOLD_MODEL: &str = "m2rc-gold-oracle";

impl Fetch for GoldOracle {
    fn model(&self) -> &str {
        GOLD_MODEL
    }
    fn temperature(&self) -> f64 {
        self.temperature
    }
    fn max_tokens(&self) -> Option<u32> {
        None
    }
    fn key_extra(&self, _request: &ChatRequest) -> String {
        format!("gold v{GOLD_REPLIES_VERSION}")
    }
    fn fetch(&self, request: &ChatRequest, _body: &Value) -> Result<Fetched, ChatError> {
        let text = self.reply.as_ref().ok_or_else(|| {
            ChatError::Failed(format!("no gold reply for `{}`", request.custom_id))
        })?;
        Ok(Fetched {
            response: json!({
                "model": GOLD_MODEL,
                "choices": [{
                    "index": 0,
                    "message": {"role": "assistant", "content": text},
                    "finish_reason": "stop",
                }],
                "usage": {"prompt_tokens": 0, "completion_tokens": 0},
            }),
            latency_ms: 0.0,
        })
    }
}

/// One episode's calls.
pub struct Session<'a> {
    setup: &'a ModelSetup,
    /// `<map>/<instruction>/<method>`: the prefix of every call's `custom_id`.
    prefix: String,
    /// `<map>/<method>`: the prefix of calls that are the same for every episode of a map.
    map_prefix: String,
    temperature: f64,
    /// Every call made, in order, as recorded in the prediction record.
    pub calls: Vec<Value>,
    /// The length of the first embedding seen, which every later one must share.
    dims: Option<usize>,
}

impl<'a> Session<'a> {
    pub fn new(setup: &'a ModelSetup, method: &str, map_id: &str, episode: &Episode) -> Self {
        let map = episode.map_id.as_deref().unwrap_or(map_id);
        let key = format!(
            "{map}/{}/{method}",
            episode
                .instruction_id()
                .unwrap_or_else(|| "instruction".into())
        );
        Session::with_key(setup, key, format!("{map}/{method}"))
    }

    /// A session whose calls are named `<key>/<step>`, and map-level calls `<map_key>/<step>`
    /// (`m2rc baseline explain` has no episode).
    pub fn with_key(setup: &'a ModelSetup, key: String, map_key: String) -> Self {
        Session {
            setup,
            prefix: key,
            map_prefix: map_key,
            temperature: setup.temperature,
            calls: Vec::new(),
            dims: None,
        }
    }

    /// Samples this session's calls at `t` instead of `--llm-temperature`.
    pub fn with_temperature(mut self, t: f64) -> Self {
        self.temperature = t;
        self
    }

    pub fn is_gold(&self) -> bool {
        self.setup.is_gold()
    }

    pub fn setup(&self) -> &ModelSetup {
        self.setup
    }

    /// One chat call named `step`. The reply's text, or the failure that ends the episode:
    /// `pending` (batch), `llm_failed` (transport, cache-only miss, malformed response),
    /// `llm_refused` (a refusal or a content filter), `llm_empty` (no text), `gold_unavailable`
    /// (the oracle cannot say this step in the method's format).
    pub fn chat(
        &mut self,
        step: &str,
        messages: Vec<Message>,
        gold: &dyn Fn() -> Result<String, String>,
    ) -> Result<String, Failure> {
        let custom_id = format!("{}/{step}", self.prefix);
        let user = messages
            .iter()
            .rev()
            .find(|m| matches!(m.role, m2rc_compiler::lower::Role::User))
            .map(|m| m.content.clone())
            .unwrap_or_default();
        if self.is_gold() {
            let reply = self.gold_reply(&custom_id, messages, gold);
            self.calls.push(json!({
                "step": step,
                "custom_id": custom_id,
                "gold": true,
                "user": user,
                "reply": reply.as_ref().ok(),
                "error": reply.as_ref().err(),
            }));
            return reply.map_err(|e| Failure::new("gold_unavailable", format!("{step}: {e}")));
        }
        let Some(http) = &self.setup.http else {
            return Err(Failure::new("llm_failed", "no LLM client configured"));
        };
        let tuned = Tuned {
            inner: http,
            temperature: self.temperature,
        };
        let exchange = Exchange {
            store: &self.setup.store,
            fetch: &tuned,
        };
        let request = ChatRequest {
            custom_id: custom_id.clone(),
            messages,
        };
        let result = exchange.complete(&request);
        let mut record = json!({"step": step, "custom_id": custom_id, "user": user});
        let out = match result {
            Err(ChatError::Pending(_)) => Err(Failure::new(
                PENDING,
                format!("{step}: waiting for the batch reply"),
            )),
            Err(ChatError::Failed(e)) => Err(Failure::new("llm_failed", format!("{step}: {e}"))),
            Ok(reply) => {
                record["finish_reason"] = json!(reply.finish_reason);
                record["prompt_tokens"] = json!(reply.usage.prompt_tokens);
                record["completion_tokens"] = json!(reply.usage.completion_tokens);
                record["latency_ms"] = json!(reply.latency_ms);
                record["reply"] = json!(reply.content);
                text_of(step, &reply)
            }
        };
        if let Err(f) = &out {
            record["error"] = json!(f.to_string());
        }
        self.calls.push(record);
        out
    }

    /// The oracle's reply. With a reply cache (and no batch file) it goes through the exchange
    /// like a model's, under a model name no server has, so a second gold run is answered from
    /// the cache: that is how the whole table is measured "with every reply cached" offline, and
    /// `--llm-cache-only` proves it. An oracle that cannot answer is never cached.
    fn gold_reply(
        &self,
        custom_id: &str,
        messages: Vec<Message>,
        gold: &dyn Fn() -> Result<String, String>,
    ) -> Result<String, String> {
        let store = &self.setup.store;
        if store.cache.is_none() || store.batch.is_some() {
            return gold();
        }
        let oracle = GoldOracle {
            reply: if store.cache_only {
                None
            } else {
                Some(gold()?)
            },
            temperature: self.temperature,
        };
        let exchange = Exchange {
            store,
            fetch: &oracle,
        };
        let request = ChatRequest {
            custom_id: custom_id.to_string(),
            messages,
        };
        match exchange.complete(&request) {
            Ok(reply) => reply
                .content
                .ok_or_else(|| format!("{custom_id}: the cached gold reply has no text")),
            Err(ChatError::Failed(m)) => match gold() {
                // A cache-only run whose oracle cannot answer fails as the oracle would.
                Err(e) => Err(e),
                Ok(_) => Err(m),
            },
            Err(ChatError::Pending(_)) => gold(),
        }
    }

    /// Embeddings of `texts`, named `step`; the same lengths as every earlier embedding of the
    /// episode, or the failure `embedding_failed`.
    pub fn embed(&mut self, step: &str, texts: &[String]) -> Result<Vec<Vec<f32>>, Failure> {
        let custom_id = format!("{}/{step}", self.prefix);
        self.embed_as(step, custom_id, texts)
    }

    /// [`Session::embed`] for a request that is the same for every episode of the map (the
    /// landmarks' descriptions): one name, so a batch file holds it once.
    pub fn embed_map_level(
        &mut self,
        step: &str,
        texts: &[String],
    ) -> Result<Vec<Vec<f32>>, Failure> {
        let custom_id = format!("{}/{step}", self.map_prefix);
        self.embed_as(step, custom_id, texts)
    }

    fn embed_as(
        &mut self,
        step: &str,
        custom_id: String,
        texts: &[String],
    ) -> Result<Vec<Vec<f32>>, Failure> {
        if texts.is_empty() {
            return Ok(vec![]);
        }
        let out = match &self.setup.embeddings {
            EmbedMode::Lexical => Ok(texts.iter().map(|t| embed::lexical(t)).collect()),
            EmbedMode::Server { model } => m2rc_llm::embed(
                &self.setup.store,
                self.setup.embed_http.as_ref(),
                model,
                &custom_id,
                texts,
            )
            .map(|r| r.vectors)
            .map_err(|e| match e {
                ChatError::Pending(_) => {
                    Failure::new(PENDING, format!("{step}: waiting for the batch reply"))
                }
                ChatError::Failed(m) => Failure::new("embedding_failed", m),
            }),
        };
        let out = out.and_then(|v: Vec<Vec<f32>>| {
            let d = v.first().map_or(0, Vec::len);
            match self.dims {
                Some(prev) if prev != d => Err(Failure::new(
                    "embedding_failed",
                    format!(
                        "{step}: the embeddings have {d} dimensions, earlier ones of this \
                         episode {prev}; they cannot be compared"
                    ),
                )),
                _ => {
                    self.dims = Some(d);
                    Ok(v)
                }
            }
        });
        self.calls.push(json!({
            "step": step,
            "custom_id": custom_id,
            "embeddings": self.setup.embeddings.label(),
            "inputs": texts.len(),
            "dims": out.as_ref().ok().and_then(|v| v.first()).map(Vec::len),
            "error": out.as_ref().err().map(|f| f.to_string()),
        }));
        out
    }
}

/// The text of a reply, or why there is none.
fn text_of(step: &str, reply: &ChatReply) -> Result<String, Failure> {
    if let Some(r) = reply.refusal.as_deref().filter(|r| !r.trim().is_empty()) {
        return Err(Failure::new(
            "llm_refused",
            format!("{step}: the model refused: {r}"),
        ));
    }
    if reply.finish_reason.as_deref() == Some("content_filter") {
        return Err(Failure::new(
            "llm_refused",
            format!("{step}: the reply was stopped by a content filter"),
        ));
    }
    match reply.content.as_deref().map(str::trim) {
        Some(t) if !t.is_empty() => Ok(t.to_string()),
        _ => Err(Failure::new(
            "llm_empty",
            format!("{step}: the reply has no text ({} choices)", reply.choices),
        )),
    }
}
