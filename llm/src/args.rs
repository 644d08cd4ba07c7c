//! The `--llm-*` flags shared by `m2rc run`, `m2rc prompt` and `m2rc bench run`, and what they
//! build. The API key comes only from `M2R_LLM_API_KEY` or the file named by
//! `--llm-api-key-file`; there is deliberately no flag for it (a flag ends up in shell history and
//! process listings).

use crate::batch::{BatchOut, import_batch_files};
use crate::cache::ResponseCache;
use crate::client::HttpClient;
use crate::config::{ApiKey, Backend, LlmConfig};
use crate::exchange::Store;
use clap::Args;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Environment variable holding the API key.
pub const API_KEY_ENV: &str = "M2R_LLM_API_KEY";

#[derive(Args, Clone, Debug)]
pub struct LlmArgs {
    /// Which model answers: `http` (an OpenAI-compatible server),
    /// `simulated[:fault_rate[:seed]]` (the gold program with injected faults; benchmark only) or
    /// `gold` (a baseline's calls answered from the episode's gold annotations; baselines only).
    #[arg(long = "llm", default_value = "http")]
    pub backend: Backend,
    /// Server base URL, e.g. http://127.0.0.1:8080/v1 (llama.cpp), http://127.0.0.1:8000/v1
    /// (vLLM), http://127.0.0.1:11434/v1 (Ollama).
    #[arg(long, env = "M2R_LLM_BASE_URL")]
    pub llm_base_url: Option<String>,
    /// Model name sent in each request.
    #[arg(long, env = "M2R_LLM_MODEL", default_value = "default")]
    pub llm_model: String,
    /// Sampling temperature sent to the model (0 = greedy, the reproducible default).
    #[arg(long, default_value_t = 0.0)]
    pub llm_temperature: f64,
    /// Most tokens the model may write in one reply (a longer reply is recorded as cut off).
    #[arg(long, default_value_t = 2048)]
    pub llm_max_tokens: u32,
    /// Seconds before a request is abandoned (and retried).
    #[arg(long, default_value_t = 90.0)]
    pub llm_timeout: f64,
    /// Most requests in flight at once.
    #[arg(long, default_value_t = 4)]
    pub llm_concurrency: usize,
    /// Tries per request, the first included.
    #[arg(long, default_value_t = 5)]
    pub llm_max_attempts: u32,
    /// First retry wait in milliseconds (doubled per retry, with jitter).
    #[arg(long, default_value_t = 500)]
    pub llm_backoff_ms: u64,
    /// Longest wait between tries in milliseconds (also caps `Retry-After`).
    #[arg(long, default_value_t = 60_000)]
    pub llm_max_backoff_ms: u64,
    /// Largest response body read, in MiB (a longer one is not read and the request fails).
    #[arg(long, default_value_t = 4)]
    pub llm_max_response_mb: u64,
    /// Read the API key from this file (otherwise from M2R_LLM_API_KEY, if set).
    #[arg(long)]
    pub llm_api_key_file: Option<PathBuf>,
    /// Response cache directory (default: <run dir>/llm-cache for `bench run`; for `m2rc run`
    /// $XDG_CACHE_HOME/m2rc/llm-cache, else ~/.cache/m2rc/llm-cache).
    #[arg(long)]
    pub llm_cache: Option<PathBuf>,
    /// Do not read or write the response cache.
    #[arg(long, conflicts_with_all = ["llm_cache", "llm_cache_only"])]
    pub llm_no_cache: bool,
    /// Never call the server: answer from the cache only; a miss is a recorded failure.
    #[arg(long)]
    pub llm_cache_only: bool,
    /// Write every request the cache cannot answer to this file (OpenAI Batch input format)
    /// instead of sending it; those episodes are pending.
    #[arg(long)]
    pub llm_batch_out: Option<PathBuf>,
    /// Import replies in the OpenAI Batch output format into the cache before running (repeatable).
    #[arg(long)]
    pub llm_batch_in: Vec<PathBuf>,
    /// Let --llm-batch-out replace a file that already holds something (it may be an earlier
    /// export, or a provider's output that cost money).
    #[arg(long)]
    pub force: bool,
}

/// Refuses a batch export that would destroy a file the user may still need: one of the
/// `--llm-batch-in` files (the provider's output), or, without `--force`, any non-empty file.
fn check_batch_out(out: &Path, inputs: &[PathBuf], force: bool) -> Result<(), String> {
    let same = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    };
    if let Some(input) = inputs.iter().find(|i| same(out, i)) {
        return Err(format!(
            "--llm-batch-out {} is the file --llm-batch-in {} reads: writing the new requests \
             there would destroy the replies; name another output file",
            out.display(),
            input.display()
        ));
    }
    if let Ok(meta) = std::fs::metadata(out)
        && meta.is_file()
        && meta.len() > 0
        && !force
    {
        return Err(format!(
            "--llm-batch-out {} already holds {} bytes (an earlier export, or replies?); name \
             another file, or pass --force to replace it",
            out.display(),
            meta.len()
        ));
    }
    Ok(())
}

impl LlmArgs {
    /// The cache directory: the flag, else `default` (none with --llm-no-cache).
    pub fn cache_dir(&self, default: &Path) -> Option<PathBuf> {
        if self.llm_no_cache {
            return None;
        }
        Some(
            self.llm_cache
                .clone()
                .unwrap_or_else(|| default.to_path_buf()),
        )
    }

    /// The API key from the key file or the environment.
    pub fn api_key(&self) -> Result<Option<ApiKey>, String> {
        if let Some(path) = &self.llm_api_key_file {
            let text = std::fs::read_to_string(path)
                .map_err(|e| format!("--llm-api-key-file {}: {e}", path.display()))?;
            return ApiKey::new(text).map(Some).ok_or_else(|| {
                format!("--llm-api-key-file {}: the file is empty", path.display())
            });
        }
        Ok(std::env::var(API_KEY_ENV).ok().and_then(ApiKey::new))
    }

    pub fn config(&self) -> Result<LlmConfig, String> {
        if !(self.llm_timeout.is_finite() && self.llm_timeout > 0.0) {
            return Err(format!(
                "--llm-timeout {} must be a positive number of seconds",
                self.llm_timeout
            ));
        }
        if !(0.0..=2.0).contains(&self.llm_temperature) {
            return Err(format!(
                "--llm-temperature {} is not within 0..2",
                self.llm_temperature
            ));
        }
        if self.llm_concurrency == 0 {
            return Err("--llm-concurrency must be at least 1".into());
        }
        if !(1..=1024).contains(&self.llm_max_response_mb) {
            return Err(format!(
                "--llm-max-response-mb {} is not within 1..1024",
                self.llm_max_response_mb
            ));
        }
        Ok(LlmConfig {
            base_url: self.llm_base_url.clone().unwrap_or_default(),
            model: self.llm_model.clone(),
            temperature: self.llm_temperature,
            max_tokens: Some(self.llm_max_tokens),
            timeout: Duration::from_secs_f64(self.llm_timeout),
            concurrency: self.llm_concurrency,
            max_attempts: self.llm_max_attempts.max(1),
            backoff_base: Duration::from_millis(self.llm_backoff_ms),
            backoff_max: Duration::from_millis(self.llm_max_backoff_ms),
            max_response_bytes: (self.llm_max_response_mb as usize) << 20,
            api_key: self.api_key()?,
        })
    }

    /// The HTTP client, unless the backend is simulated.
    pub fn http_client(&self) -> Result<Option<HttpClient>, String> {
        match self.backend {
            Backend::Http if self.llm_cache_only || self.llm_batch_out.is_some() => {
                // No request leaves the machine; the client is still built for its parameters.
                let mut cfg = self.config()?;
                if cfg.base_url.is_empty() {
                    cfg.base_url = "http://offline.invalid/v1".into();
                }
                HttpClient::new(cfg).map(Some)
            }
            Backend::Http => HttpClient::new(self.config()?).map(Some),
            Backend::Simulated(_) | Backend::Gold => Ok(None),
        }
    }

    /// The shared store: imports `--llm-batch-in` files into the cache first. Returns the store
    /// and a line about the import for the user, if any.
    pub fn store(&self, default_cache: &Path) -> Result<(Store, Option<String>), String> {
        let cache = self.cache_dir(default_cache).map(ResponseCache::new);
        if let Some(out) = &self.llm_batch_out {
            check_batch_out(out, &self.llm_batch_in, self.force)?;
        }
        let mut note = None;
        if !self.llm_batch_in.is_empty() {
            let Some(c) = &cache else {
                return Err("--llm-batch-in needs the response cache (drop --llm-no-cache)".into());
            };
            let r = import_batch_files(&self.llm_batch_in, c)?;
            let mut line = format!(
                "imported {} batch replies into {}",
                r.imported,
                c.dir().display()
            );
            if !r.already.is_empty() {
                line.push_str(&format!("; {} already imported", r.already.len()));
            }
            if !r.unknown.is_empty() {
                line.push_str(&format!(
                    "; {} reply(s) to requests this run never exported skipped",
                    r.unknown.len()
                ));
            }
            // The first few of each kind, each naming its line; the counts say the rest.
            for (label, list) in [
                ("batch reply not imported", &r.failed),
                ("batch reply of an unknown request", &r.unknown),
                ("warning", &r.warnings),
            ] {
                for f in list.iter().take(20) {
                    line.push_str(&format!("\n  {label}: {f}"));
                }
                if list.len() > 20 {
                    line.push_str(&format!("\n  {label}: ... and {} more", list.len() - 20));
                }
            }
            note = Some(line);
        }
        let batch = match &self.llm_batch_out {
            Some(p) if cache.is_none() => {
                return Err(format!(
                    "--llm-batch-out {} needs the response cache (drop --llm-no-cache)",
                    p.display()
                ));
            }
            Some(p) => Some(BatchOut::new(p)),
            None => None,
        };
        Ok((Store::new(cache, batch, self.llm_cache_only), note))
    }
}

/// The lowering and repair flags (`--repair-rounds R`, ...), shared by `m2rc run`, `m2rc bench
/// run --method grounding2route` and the repair-rounds ablation.
#[derive(Args, Clone, Debug)]
pub struct LowerArgs {
    /// Repair rounds after the first answer (R; the paper's default is 3).
    #[arg(long, default_value_t = 3)]
    pub repair_rounds: usize,
    /// Also send planning failures back to the model (the paper ends the episode).
    #[arg(long)]
    pub repair_on_plan_failure: bool,
    /// Send every error to the model, even those the compiler can fix itself.
    #[arg(long)]
    pub no_local_fixes: bool,
    /// Scene catalog in the prompt: `counts` (room and object categories with counts, as the
    /// reference) or `per-room` (also the object categories of each room).
    #[arg(long, default_value = "counts")]
    pub catalog: m2rc_compiler::lower::CatalogMode,
    /// Worked examples in the prompt (from tests/ui/real, never from the scene being solved).
    #[arg(long, default_value_t = 5)]
    pub examples: usize,
    #[command(flatten)]
    pub budget: BudgetArgs,
}

/// The per-episode budget of compiling and planning a model's programs (`m2rc run`, `bench run
/// --method grounding2route`): see `m2rc_benchmark::budget`. An episode over it is recorded as
/// `budget_exceeded` and the run goes on.
#[derive(Args, Clone, Debug)]
pub struct BudgetArgs {
    /// Planner expansions one episode may use over all its programs and plans (0 = no limit);
    /// reproducible.
    #[arg(long, default_value_t = 20_000_000)]
    pub episode_max_expansions: u64,
    /// Estimated memory one product-graph (LTL) search of an episode may take, in MiB (0 = no
    /// limit); reproducible.
    #[arg(long, default_value_t = 2048)]
    pub episode_max_product_mb: u64,
    /// Wall time one episode's compiling and planning may take, in seconds (default: no limit);
    /// checked between phases, and not reproducible (the record says "wall time").
    #[arg(long)]
    pub episode_max_seconds: Option<f64>,
}

impl LowerArgs {
    pub fn repair_options(&self) -> m2rc_compiler::lower::RepairOptions {
        m2rc_compiler::lower::RepairOptions {
            rounds: self.repair_rounds,
            repair_on_plan_failure: self.repair_on_plan_failure,
            local_fixes: !self.no_local_fixes,
        }
    }

    pub fn prompt_options(&self) -> m2rc_compiler::lower::PromptOptions {
        m2rc_compiler::lower::PromptOptions {
            catalog: self.catalog,
            examples: self.examples,
        }
    }
}
