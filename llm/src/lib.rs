//! The I/O shell around the pure lowering core of `m2rc_compiler::lower`: an OpenAI-compatible
//! chat-completions client (retries, backoff, timeouts, token and latency accounting), an on-disk
//! response cache, batch exchange files in the OpenAI Batch formats, and the simulated model used
//! for offline evaluation. The CLI (`m2rc run`, `m2rc prompt`) and the benchmark's
//! `grounding2route` method use it.
//!
//! Every request goes through an [`Exchange`]: cache first; on a miss, either the request is
//! written to the batch file and the episode is pending, or (unless `--llm-cache-only`) it is sent
//! to the backend and the reply is cached before it is used. The API key is read only from the
//! environment or a key file, is sent only in the `Authorization` header, and is never written,
//! logged or put into an error message ([`ApiKey`] has no `Display` and a redacting `Debug`).

pub mod args;
pub mod batch;
pub mod cache;
pub mod client;
pub mod config;
pub mod embeddings;
pub mod exchange;
pub mod simulated;
pub mod tools;
pub mod wire;

pub use args::{LlmArgs, LowerArgs};
pub use batch::{BatchImport, BatchOut, import_batch_files};
pub use cache::ResponseCache;
pub use client::HttpClient;
pub use config::{ApiKey, Backend, LlmConfig, SimulatedSpec};
pub use embeddings::{EmbedReply, embed};
pub use exchange::{Exchange, ExchangeStats, Fetch, Fetched, Store};
pub use simulated::SimulatedModel;
pub use tools::{ToolCall, ToolReply};
