//! Every request goes through an [`Exchange`]: the cache first; on a miss, the batch file (the
//! episode is then pending), or, unless the run is cache-only, the backend, whose reply is cached
//! before it is used. [`Store`] is shared by all episodes of a run; the backend ([`Fetch`]) may be
//! made per episode (the simulated model knows its episode's gold program).

use crate::batch::{BatchOut, export_id};
use crate::cache::{ResponseCache, cache_key};
use crate::wire::{check_reply_size, parse_completion, request_body};
use m2rc_compiler::lower::{ChatError, ChatModel, ChatReply, ChatRequest};
use serde::Serialize;
use serde_json::Value;
use std::sync::Mutex;

/// A completion body as the backend returned it, with the request's wall time.
#[derive(Clone, Debug, PartialEq)]
pub struct Fetched {
    pub response: Value,
    pub latency_ms: f64,
}

/// A backend that answers requests the cache could not.
pub trait Fetch: Send + Sync {
    /// The `model` of the request body (and so of the cache key).
    fn model(&self) -> &str;
    fn temperature(&self) -> f64;
    fn max_tokens(&self) -> Option<u32>;
    /// Key material beyond the body (the simulated model's episode, whose answer depends on it).
    fn key_extra(&self, _request: &ChatRequest) -> String {
        String::new()
    }
    fn fetch(&self, request: &ChatRequest, body: &Value) -> Result<Fetched, ChatError>;
}

/// Counts of a run's requests, printed at the end (not written into records: a resumed run
/// answers from the cache what the first run fetched, and its records must not differ).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct ExchangeStats {
    pub cache_hits: usize,
    pub fetched: usize,
    pub pending: usize,
    pub failed: usize,
    pub corrupt_cache_entries: usize,
    /// Replies whose `usage` was not a token count (recorded as unknown).
    pub invalid_usage: usize,
    /// Replies refused for their size (longer than a program may be).
    pub oversized: usize,
}

/// What every episode of a run shares: the cache, the batch file, the mode.
#[derive(Debug, Default)]
pub struct Store {
    pub cache: Option<ResponseCache>,
    pub batch: Option<BatchOut>,
    /// Never call the backend; a miss is a recorded failure naming the request.
    pub cache_only: bool,
    stats: Mutex<ExchangeStats>,
}

impl Store {
    pub fn new(cache: Option<ResponseCache>, batch: Option<BatchOut>, cache_only: bool) -> Self {
        Store {
            cache,
            batch,
            cache_only,
            stats: Mutex::new(ExchangeStats::default()),
        }
    }

    pub fn stats(&self) -> ExchangeStats {
        self.stats.lock().map(|s| s.clone()).unwrap_or_default()
    }

    pub(crate) fn count(&self, f: impl FnOnce(&mut ExchangeStats)) {
        if let Ok(mut s) = self.stats.lock() {
            f(&mut s);
        }
    }

    /// What the user should hear about the replies (invalid token counts, oversized replies),
    /// one line each, for the command to print at the end.
    pub fn warnings(&self) -> Vec<String> {
        let s = self.stats();
        let mut out = Vec::new();
        if s.invalid_usage > 0 {
            out.push(format!(
                "{} model repl{} had a `usage` that is not a token count (negative, fractional \
                 or absurdly large); recorded as unknown (null), not as 0",
                s.invalid_usage,
                if s.invalid_usage == 1 { "y" } else { "ies" }
            ));
        }
        if s.oversized > 0 {
            out.push(format!(
                "{} model repl{} longer than the {} byte program limit; recorded as model_failed",
                s.oversized,
                if s.oversized == 1 {
                    "y was"
                } else {
                    "ies were"
                },
                crate::wire::MAX_REPLY_BYTES
            ));
        }
        out
    }

    /// A parsed reply, counted and checked before the repair loop sees it: a reply too long to
    /// hold a program fails the request (so it is never compiled or stored in a record).
    fn admit(&self, request: &ChatRequest, reply: ChatReply) -> Result<ChatReply, ChatError> {
        if reply.usage.is_unknown() {
            self.count(|s| s.invalid_usage += 1);
        }
        if let Err(e) = check_reply_size(&reply) {
            self.count(|s| s.oversized += 1);
            return Err(ChatError::Failed(format!("{}: {e}", request.custom_id)));
        }
        Ok(reply)
    }
}

/// A [`ChatModel`] over a store and a backend.
pub struct Exchange<'a> {
    pub store: &'a Store,
    pub fetch: &'a dyn Fetch,
}

impl ChatModel for Exchange<'_> {
    fn complete(&self, request: &ChatRequest) -> Result<ChatReply, ChatError> {
        let f = self.fetch;
        let body = request_body(
            f.model(),
            &request.messages,
            f.temperature(),
            f.max_tokens(),
        );
        let (response, latency) = self.exchange(request, &body)?;
        let reply = parse_completion(&response, latency).map_err(|e| {
            self.store.count(|s| s.failed += 1);
            ChatError::Failed(format!("{}: {e}", request.custom_id))
        })?;
        self.store.admit(request, reply)
    }
}

impl Exchange<'_> {
    /// One function-calling turn: `messages` (the whole conversation so far, as the wire carries
    /// it) and `tools` go into the body, so the cache key and the batch file cover both.
    pub fn complete_tools(
        &self,
        custom_id: &str,
        messages: &[Value],
        tools: &[Value],
    ) -> Result<crate::tools::ToolReply, ChatError> {
        let f = self.fetch;
        let body = crate::tools::tool_request_body(
            f.model(),
            messages,
            tools,
            f.temperature(),
            f.max_tokens(),
        );
        let request = ChatRequest {
            custom_id: custom_id.to_string(),
            messages: Vec::new(),
        };
        let (response, latency) = self.exchange(&request, &body)?;
        let parsed = parse_completion(&response, latency)
            .and_then(|reply| Ok((reply, crate::tools::parse_tool_calls(&response)?)));
        let (reply, calls) = parsed.map_err(|e| {
            self.store.count(|s| s.failed += 1);
            ChatError::Failed(format!("{custom_id}: {e}"))
        })?;
        let reply = self.store.admit(&request, reply)?;
        Ok(crate::tools::ToolReply {
            reply,
            tool_calls: calls,
        })
    }

    /// The response body for `body`: from the cache; else written to the batch file (pending);
    /// else, unless cache-only, fetched and cached before it is used.
    fn exchange(&self, request: &ChatRequest, body: &Value) -> Result<(Value, f64), ChatError> {
        let f = self.fetch;
        let key = cache_key(body, &f.key_extra(request));
        let store = self.store;
        if let Some(cache) = &store.cache
            && let Some((response, latency)) = cache.get(&key)
        {
            match parse_completion(&response, latency) {
                Ok(_) => {
                    store.count(|s| s.cache_hits += 1);
                    return Ok((response, latency));
                }
                Err(_) => store.count(|s| s.corrupt_cache_entries += 1),
            }
        }
        if let (Some(batch), Some(cache)) = (&store.batch, &store.cache) {
            let recorded = cache
                .put_pending(&request.custom_id, &key, f.model())
                .and_then(|()| batch.add(&export_id(&request.custom_id, &key), body));
            return match recorded {
                Ok(()) => {
                    store.count(|s| s.pending += 1);
                    Err(ChatError::Pending(request.custom_id.clone()))
                }
                Err(e) => {
                    store.count(|s| s.failed += 1);
                    Err(ChatError::Failed(format!(
                        "{}: cannot write the batch request: {e}",
                        request.custom_id
                    )))
                }
            };
        }
        if store.cache_only {
            store.count(|s| s.failed += 1);
            return Err(ChatError::Failed(format!(
                "no cached reply for `{}` and --llm-cache-only is set",
                request.custom_id
            )));
        }
        let fetched = match f.fetch(request, body) {
            Ok(x) => x,
            Err(e) => {
                store.count(|s| s.failed += 1);
                return Err(e);
            }
        };
        if let Err(e) = parse_completion(&fetched.response, fetched.latency_ms) {
            store.count(|s| s.failed += 1);
            return Err(ChatError::Failed(format!("{}: {e}", request.custom_id)));
        }
        if let Some(cache) = &store.cache {
            // A cache that cannot be written costs a refetch next time, not this episode.
            let _ = cache.put(
                &key,
                &request.custom_id,
                &fetched.response,
                fetched.latency_ms,
            );
        }
        store.count(|s| s.fetched += 1);
        Ok((fetched.response, fetched.latency_ms))
    }
}
