//! Client configuration: where the server is, which model, sampling and retry parameters, and the
//! API key (held so that it cannot be printed).

use serde::{Deserialize, Serialize};
use std::time::Duration;

/// Where `m2rc run` keeps its response cache unless `--llm-cache` says otherwise:
/// `$XDG_CACHE_HOME/m2rc/llm-cache`, else `$HOME/.cache/m2rc/llm-cache` (the XDG base-directory
/// rule; a relative `XDG_CACHE_HOME` is ignored, as the rule says), else `.m2rc/llm-cache` in the
/// working directory when neither variable is set. A user's cache, not a project's: running in a
/// checkout must not leave a directory behind in it.
pub fn default_run_cache() -> std::path::PathBuf {
    default_run_cache_from(
        std::env::var_os("XDG_CACHE_HOME").as_deref(),
        std::env::var_os("HOME").as_deref(),
    )
}

fn default_run_cache_from(
    xdg: Option<&std::ffi::OsStr>,
    home: Option<&std::ffi::OsStr>,
) -> std::path::PathBuf {
    use std::path::{Path, PathBuf};
    let absolute = |v: Option<&std::ffi::OsStr>| {
        v.map(Path::new)
            .filter(|p| p.is_absolute())
            .map(Path::to_path_buf)
    };
    let base = absolute(xdg).or_else(|| absolute(home).map(|h| h.join(".cache")));
    match base {
        Some(b) => b.join("m2rc").join("llm-cache"),
        None => PathBuf::from(".m2rc").join("llm-cache"),
    }
}

/// A credential. It has no `Display`, its `Debug` prints `ApiKey(***)`, and it is not
/// serialisable, so it cannot end up in a record, a cache entry or a log line by accident.
#[derive(Clone, PartialEq, Eq)]
pub struct ApiKey(String);

impl ApiKey {
    pub fn new(key: impl Into<String>) -> Option<ApiKey> {
        let k = key.into().trim().to_string();
        (!k.is_empty()).then_some(ApiKey(k))
    }

    /// The key itself, for the `Authorization` header only.
    pub(crate) fn expose(&self) -> &str {
        &self.0
    }

    /// `text` with every occurrence of the key replaced by `***`.
    pub fn redact(&self, text: &str) -> String {
        text.replace(&self.0, "***")
    }
}

impl std::fmt::Debug for ApiKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("ApiKey(***)")
    }
}

/// `--llm simulated[:fault_rate[:seed]]`: the gold program with injected faults.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SimulatedSpec {
    /// Probability of a fault in the first answer (and of each further fault).
    pub fault_rate: f64,
    pub seed: u64,
}

impl Default for SimulatedSpec {
    fn default() -> Self {
        SimulatedSpec {
            fault_rate: 0.5,
            seed: 0,
        }
    }
}

impl SimulatedSpec {
    /// The label every output touched by the simulated model carries.
    pub fn label(&self) -> String {
        format!(
            "SIMULATED model (gold program with injected faults, fault rate {}, seed {}); not a language model",
            self.fault_rate, self.seed
        )
    }

    /// The model name in cache keys and records.
    pub fn model_name(&self) -> String {
        format!("simulated:{}:{}", self.fault_rate, self.seed)
    }
}

/// Which model answers.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "backend", rename_all = "snake_case")]
pub enum Backend {
    /// An OpenAI-compatible server.
    Http,
    Simulated(SimulatedSpec),
    /// Every call answered by the method's own oracle built from the episode's gold annotations
    /// (the baselines' `--llm gold`); never a language model, and labelled `[GOLD replies]`.
    Gold,
}

impl std::str::FromStr for Backend {
    type Err = String;
    fn from_str(s: &str) -> Result<Backend, String> {
        if s == "http" || s == "openai" {
            return Ok(Backend::Http);
        }
        if s == "gold" {
            return Ok(Backend::Gold);
        }
        let mut parts = s.split(':');
        if parts.next() != Some("simulated") {
            return Err(format!(
                "--llm `{s}` is not `http`, `gold` or `simulated[:fault_rate[:seed]]`"
            ));
        }
        let mut spec = SimulatedSpec::default();
        if let Some(r) = parts.next() {
            spec.fault_rate = r
                .parse()
                .ok()
                .filter(|r: &f64| (0.0..=1.0).contains(r))
                .ok_or_else(|| format!("--llm `{s}`: fault rate `{r}` is not a number in 0..1"))?;
        }
        if let Some(seed) = parts.next() {
            spec.seed = seed
                .parse()
                .map_err(|_| format!("--llm `{s}`: seed `{seed}` is not a whole number"))?;
        }
        if parts.next().is_some() {
            return Err(format!("--llm `{s}`: too many `:` parts"));
        }
        Ok(Backend::Simulated(spec))
    }
}

/// Everything the HTTP client needs.
#[derive(Clone, Debug)]
pub struct LlmConfig {
    /// `http://host:port/v1`; requests go to `{base_url}/chat/completions`.
    pub base_url: String,
    pub model: String,
    pub temperature: f64,
    pub max_tokens: Option<u32>,
    pub timeout: Duration,
    /// Most requests in flight at once (across all worker threads).
    pub concurrency: usize,
    /// Most tries per request (the first one included).
    pub max_attempts: u32,
    /// First retry wait; doubled per retry, with ±50 % jitter.
    pub backoff_base: Duration,
    /// Longest wait between tries, also the cap on a server's `Retry-After`.
    pub backoff_max: Duration,
    /// Largest response body read, in bytes; a longer body is not read to its end and the
    /// request fails (`model_failed`), so a runaway or hostile server cannot exhaust memory.
    pub max_response_bytes: usize,
    pub api_key: Option<ApiKey>,
}

/// Default of [`LlmConfig::max_response_bytes`]: 4 MiB, far above any chat completion that can
/// hold a program within the 256 KiB program limit ([`crate::wire::MAX_REPLY_BYTES`]), with room
/// for the JSON around it and for servers that return the prompt or log-probabilities.
pub const DEFAULT_MAX_RESPONSE_BYTES: usize = 4 * 1024 * 1024;

impl Default for LlmConfig {
    fn default() -> Self {
        LlmConfig {
            base_url: String::new(),
            model: "default".into(),
            temperature: 0.0,
            max_tokens: Some(2048),
            timeout: Duration::from_secs(90),
            concurrency: 4,
            max_attempts: 5,
            backoff_base: Duration::from_millis(500),
            backoff_max: Duration::from_secs(60),
            max_response_bytes: DEFAULT_MAX_RESPONSE_BYTES,
            api_key: None,
        }
    }
}

impl LlmConfig {
    /// `{base_url}/chat/completions`, tolerating a trailing slash or a full endpoint URL.
    pub fn endpoint(&self) -> String {
        let b = self.base_url.trim_end_matches('/');
        if b.ends_with("/chat/completions") {
            b.to_string()
        } else {
            format!("{b}/chat/completions")
        }
    }

    /// `{base_url}/embeddings` (a base URL given as the chat endpoint is cut back to its base).
    pub fn embeddings_endpoint(&self) -> String {
        let b = self.base_url.trim_end_matches('/');
        let b = b.strip_suffix("/chat/completions").unwrap_or(b);
        if b.ends_with("/embeddings") {
            b.to_string()
        } else {
            format!("{b}/embeddings")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn backends_parse() {
        assert_eq!("http".parse::<Backend>(), Ok(Backend::Http));
        assert_eq!(
            "simulated:0.3:7".parse::<Backend>(),
            Ok(Backend::Simulated(SimulatedSpec {
                fault_rate: 0.3,
                seed: 7
            }))
        );
        assert!("simulated:2".parse::<Backend>().is_err());
        assert!("gpt".parse::<Backend>().is_err());
        assert_eq!("gold".parse::<Backend>(), Ok(Backend::Gold));
    }

    #[test]
    fn the_key_never_prints() {
        let k = ApiKey::new("sk-secret-123").unwrap();
        assert_eq!(format!("{k:?}"), "ApiKey(***)");
        assert_eq!(k.redact("bearer sk-secret-123 x"), "bearer *** x");
        assert!(ApiKey::new("  ").is_none());
    }

    #[test]
    fn the_run_cache_lives_in_the_user_cache_directory() {
        use std::ffi::OsStr;
        use std::path::PathBuf;
        let c = |x: Option<&str>, h: Option<&str>| {
            default_run_cache_from(x.map(OsStr::new), h.map(OsStr::new))
        };
        assert_eq!(
            c(Some("/x/cache"), Some("/home/u")),
            PathBuf::from("/x/cache/m2rc/llm-cache")
        );
        assert_eq!(
            c(None, Some("/home/u")),
            PathBuf::from("/home/u/.cache/m2rc/llm-cache")
        );
        assert_eq!(
            c(Some("rel"), Some("/home/u")),
            PathBuf::from("/home/u/.cache/m2rc/llm-cache")
        );
        assert_eq!(c(None, None), PathBuf::from(".m2rc/llm-cache"));
    }

    #[test]
    fn endpoints_are_joined() {
        let mut c = LlmConfig {
            base_url: "http://h:1/v1/".into(),
            ..LlmConfig::default()
        };
        assert_eq!(c.endpoint(), "http://h:1/v1/chat/completions");
        assert_eq!(c.embeddings_endpoint(), "http://h:1/v1/embeddings");
        c.base_url = "http://h:1/v1/chat/completions".into();
        assert_eq!(c.endpoint(), "http://h:1/v1/chat/completions");
        assert_eq!(c.embeddings_endpoint(), "http://h:1/v1/embeddings");
    }
}
