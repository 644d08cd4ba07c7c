//! The OpenAI-compatible chat-completions client (`POST {base}/chat/completions`), blocking, over
//! reqwest with rustls. Works with vLLM, llama.cpp's server, Ollama, LM Studio and hosted APIs.
//!
//! Retries: connection errors, timeouts, HTTP 429 and 5xx, and 200 responses whose body is not a
//! chat completion are retried up to `max_attempts` tries in all, waiting `backoff_base · 2^k` with
//! ±50 % jitter, or the server's `Retry-After` (seconds) when it sends one, both capped at
//! `backoff_max`. Other 4xx answers fail at once. The final failure names the request and the last
//! cause, with the API key redacted.
//!
//! Redirects are never followed: a redirected POST would send the request (and, to the same
//! origin, the key) somewhere the user did not name; a 3xx answer fails at once and names the
//! location to put into `--llm-base-url`. A response body is read only up to
//! [`LlmConfig::max_response_bytes`] (`--llm-max-response-mb`); a longer one fails the request
//! without being read to its end.

use crate::config::LlmConfig;
use crate::exchange::{Fetch, Fetched};
use crate::wire::parse_completion;
use m2rc_compiler::lower::{ChatError, ChatRequest};
use reqwest::header::{AUTHORIZATION, CONTENT_LENGTH, CONTENT_TYPE, LOCATION, RETRY_AFTER};
use serde_json::Value;
use std::io::Read;
use std::sync::{Condvar, Mutex};
use std::time::{Duration, Instant};

/// A counting semaphore: at most `n` requests in flight across threads.
#[derive(Debug)]
struct Gate {
    free: Mutex<usize>,
    cv: Condvar,
}

impl Gate {
    fn new(n: usize) -> Self {
        Gate {
            free: Mutex::new(n.max(1)),
            cv: Condvar::new(),
        }
    }

    fn enter(&self) -> GateGuard<'_> {
        let mut free = self.free.lock().unwrap_or_else(|p| p.into_inner());
        while *free == 0 {
            free = self.cv.wait(free).unwrap_or_else(|p| p.into_inner());
        }
        *free -= 1;
        GateGuard(self)
    }
}

struct GateGuard<'a>(&'a Gate);

impl Drop for GateGuard<'_> {
    fn drop(&mut self) {
        let mut free = self.0.free.lock().unwrap_or_else(|p| p.into_inner());
        *free += 1;
        self.0.cv.notify_one();
    }
}

pub struct HttpClient {
    cfg: LlmConfig,
    http: reqwest::blocking::Client,
    gate: Gate,
}

/// Why one try failed, and whether another may succeed.
struct TryError {
    message: String,
    retry: bool,
    retry_after: Option<Duration>,
}

impl HttpClient {
    pub fn new(cfg: LlmConfig) -> Result<HttpClient, String> {
        if cfg.base_url.trim().is_empty() {
            return Err(
                "no LLM server: pass --llm-base-url or set M2R_LLM_BASE_URL (e.g. http://127.0.0.1:8080/v1)"
                    .into(),
            );
        }
        if !(cfg.base_url.starts_with("http://") || cfg.base_url.starts_with("https://")) {
            return Err(format!(
                "--llm-base-url `{}` must start with http:// or https://",
                cfg.base_url
            ));
        }
        let http = reqwest::blocking::Client::builder()
            .timeout(cfg.timeout)
            .connect_timeout(cfg.timeout.min(Duration::from_secs(10)))
            .redirect(reqwest::redirect::Policy::none())
            .build()
            .map_err(|e| format!("cannot start the HTTP client: {e}"))?;
        let gate = Gate::new(cfg.concurrency);
        Ok(HttpClient { cfg, http, gate })
    }

    pub fn config(&self) -> &LlmConfig {
        &self.cfg
    }

    fn redact(&self, text: String) -> String {
        match &self.cfg.api_key {
            Some(k) => k.redact(&text),
            None => text,
        }
    }

    fn backoff(&self, attempt: u32) -> Duration {
        let base = self.cfg.backoff_base.as_secs_f64() * 2f64.powi(attempt.min(20) as i32);
        let jitter = 0.5 + rand::random::<f64>();
        Duration::from_secs_f64((base * jitter).min(self.cfg.backoff_max.as_secs_f64()))
    }

    /// One POST of `body` to `url`; `check` says whether a 200 body is the kind of answer asked
    /// for (a chat completion, a list of embeddings), and a body that is not is retried.
    fn try_once(
        &self,
        url: &str,
        body: &[u8],
        check: fn(&Value) -> Result<(), String>,
    ) -> Result<Value, TryError> {
        let mut req = self
            .http
            .post(url)
            .header(CONTENT_TYPE, "application/json")
            .body(body.to_vec());
        if let Some(k) = &self.cfg.api_key {
            req = req.header(AUTHORIZATION, format!("Bearer {}", k.expose()));
        }
        let transport = |e: reqwest::Error| TryError {
            message: if e.is_timeout() {
                format!("timed out after {:.1} s", self.cfg.timeout.as_secs_f64())
            } else if e.is_connect() {
                format!("cannot connect to {url}")
            } else {
                format!("request failed: {}", e.without_url())
            },
            retry: true,
            retry_after: None,
        };
        let resp = req.send().map_err(transport)?;
        let status = resp.status();
        let retry_after = resp
            .headers()
            .get(RETRY_AFTER)
            .and_then(|v| v.to_str().ok())
            .and_then(|s| s.trim().parse::<f64>().ok())
            .filter(|s| s.is_finite() && *s >= 0.0)
            .map(Duration::from_secs_f64);
        if status.is_redirection() {
            let to = resp
                .headers()
                .get(LOCATION)
                .and_then(|v| v.to_str().ok())
                .map(|l| l.chars().take(200).collect::<String>())
                .unwrap_or_else(|| "an unnamed location".into());
            return Err(TryError {
                message: format!(
                    "HTTP {status}: the server redirects to {to}; redirects are not followed for \
                     a POST (set --llm-base-url to the server's own address)"
                ),
                retry: false,
                retry_after: None,
            });
        }
        if status.as_u16() == 429 || status.is_server_error() {
            return Err(TryError {
                message: format!("HTTP {status}"),
                retry: true,
                retry_after,
            });
        }
        let bytes = self.read_body(resp).map_err(|e| match e {
            BodyError::Transport(e) => transport(e),
            BodyError::Io(message) => TryError {
                message: format!("cannot read the response: {message}"),
                retry: true,
                retry_after: None,
            },
            BodyError::TooLarge(declared) => TryError {
                message: format!(
                    "the response body is {}more than the limit of {} bytes \
                     (--llm-max-response-mb); it was not read",
                    declared.map_or(String::new(), |n| format!("{n} bytes, ")),
                    self.cfg.max_response_bytes
                ),
                retry: false,
                retry_after: None,
            },
        })?;
        if !status.is_success() {
            let snippet: String = String::from_utf8_lossy(&bytes).chars().take(300).collect();
            return Err(TryError {
                message: format!("HTTP {status}: {snippet}"),
                retry: false,
                retry_after: None,
            });
        }
        let value: Value = serde_json::from_slice(&bytes).map_err(|e| TryError {
            message: format!("the response is not JSON: {e}"),
            retry: true,
            retry_after: None,
        })?;
        check(&value).map_err(|e| TryError {
            message: e,
            retry: true,
            retry_after: None,
        })?;
        Ok(value)
    }
}

/// Why a body was not read.
enum BodyError {
    Transport(reqwest::Error),
    Io(String),
    /// Past the limit; the length the server declared, if it did.
    TooLarge(Option<u64>),
}

impl HttpClient {
    /// The body, read up to the configured limit: a `Content-Length` past it is refused before
    /// reading, and a body without one is read to one byte past the limit at most.
    fn read_body(&self, resp: reqwest::blocking::Response) -> Result<Vec<u8>, BodyError> {
        let cap = self.cfg.max_response_bytes;
        let declared = resp
            .headers()
            .get(CONTENT_LENGTH)
            .and_then(|v| v.to_str().ok())
            .and_then(|s| s.trim().parse::<u64>().ok());
        if let Some(n) = declared.filter(|n| *n > cap as u64) {
            return Err(BodyError::TooLarge(Some(n)));
        }
        let mut bytes = Vec::new();
        let mut limited = resp.take(cap as u64 + 1);
        if let Err(e) = limited.read_to_end(&mut bytes) {
            // reqwest's reader wraps its own error; keep it so a timeout is reported as one.
            let text = e.to_string();
            return match e
                .into_inner()
                .and_then(|b| b.downcast::<reqwest::Error>().ok())
            {
                Some(r) => Err(BodyError::Transport(*r)),
                None => Err(BodyError::Io(text)),
            };
        }
        if bytes.len() > cap {
            return Err(BodyError::TooLarge(None));
        }
        Ok(bytes)
    }
}

impl Fetch for HttpClient {
    fn model(&self) -> &str {
        &self.cfg.model
    }

    fn temperature(&self) -> f64 {
        self.cfg.temperature
    }

    fn max_tokens(&self) -> Option<u32> {
        self.cfg.max_tokens
    }

    fn fetch(&self, request: &ChatRequest, body: &Value) -> Result<Fetched, ChatError> {
        self.post(&request.custom_id, &self.cfg.endpoint(), body, |v| {
            parse_completion(v, 0.0).map(|_| ())
        })
    }
}

impl HttpClient {
    /// Sends an embeddings request (`POST {base}/embeddings`) with the same retries, timeouts,
    /// concurrency gate and key handling as a chat request.
    pub fn fetch_embeddings(&self, custom_id: &str, body: &Value) -> Result<Fetched, ChatError> {
        self.post(custom_id, &self.cfg.embeddings_endpoint(), body, |v| {
            crate::wire::parse_embeddings(v).map(|_| ())
        })
    }

    fn post(
        &self,
        custom_id: &str,
        url: &str,
        body: &Value,
        check: fn(&Value) -> Result<(), String>,
    ) -> Result<Fetched, ChatError> {
        let bytes = serde_json::to_vec(body).unwrap_or_default();
        let attempts = self.cfg.max_attempts.max(1);
        let mut last = String::new();
        let mut tries = 0;
        for attempt in 0..attempts {
            tries += 1;
            let started = Instant::now();
            let result = {
                let _slot = self.gate.enter();
                self.try_once(url, &bytes, check)
            };
            match result {
                Ok(response) => {
                    return Ok(Fetched {
                        response,
                        latency_ms: (started.elapsed().as_secs_f64() * 1e3 * 1e3).round() / 1e3,
                    });
                }
                Err(e) => {
                    last = e.message;
                    if !e.retry || attempt + 1 == attempts {
                        break;
                    }
                    let wait = e
                        .retry_after
                        .map(|w| w.min(self.cfg.backoff_max))
                        .unwrap_or_else(|| self.backoff(attempt));
                    std::thread::sleep(wait);
                }
            }
        }
        Err(ChatError::Failed(self.redact(format!(
            "{custom_id}: the model request failed after {tries} attempt(s): {last}"
        ))))
    }
}
