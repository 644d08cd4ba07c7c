//! Lowering: natural language in, `.m2r` out, through a language model steered by the compiler's
//! own diagnostics (the Grounding2Route method, rebuilt on a typed language).
//!
//! Everything here is pure: the prompt is built from the built-in table, the map's categories and
//! worked examples compiled into the binary; replies are parsed into a program or a named reason
//! why there is none; the repair policy decides what to fix locally and what to send back. The
//! model itself is behind [`ChatModel`], so the HTTP client, its cache and batch files live in the
//! `m2rc-llm` shell crate and tests can script a conversation without a network.
//!
//! * [`prompt`]: the first prompt and the repair prompt, and their size.
//! * [`reference`]: the language reference the model reads, generated from `stdlib::builtins`.
//! * [`catalog`]: the scene catalog (categories and counts, never ids or coordinates).
//! * [`examples`]: instruction + program pairs from `tests/ui/real/`.
//! * [`extract`]: the program out of a reply (fenced, bare), or why there is none.
//! * [`repair`]: the bounded repair loop with local machine-applicable fixes.

pub mod catalog;
pub mod examples;
pub mod extract;
pub mod prompt;
pub mod reference;
pub mod repair;

use serde::{Deserialize, Serialize};

pub use catalog::{CatalogMode, SceneCatalog};
pub use extract::{Extracted, extract};
pub use prompt::{Prompt, PromptOptions, estimate_tokens};
pub use repair::{
    Attempt, EpisodeOutcome, Phase, RepairOptions, Trace, Verdict, Verifier, run_episode,
};

/// Who wrote a message of the conversation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Role {
    System,
    User,
    Assistant,
}

/// One chat message, as OpenAI-compatible servers take it.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Message {
    pub role: Role,
    pub content: String,
}

impl Message {
    pub fn system(content: impl Into<String>) -> Self {
        Message {
            role: Role::System,
            content: content.into(),
        }
    }

    pub fn user(content: impl Into<String>) -> Self {
        Message {
            role: Role::User,
            content: content.into(),
        }
    }
}

/// One request to the model. `custom_id` names the episode and the round
/// (`<map>/<instruction>/round<k>`), so batch files and records can be matched up.
#[derive(Clone, Debug, PartialEq)]
pub struct ChatRequest {
    pub custom_id: String,
    pub messages: Vec<Message>,
}

/// Token counts as the server reports them (`usage`); zero when it reports none, `None`
/// (unknown, recorded as `null`) when it reports something that is not a token count (negative,
/// fractional, 1e300), so a bad figure is never summed as if it were one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Usage {
    pub prompt_tokens: Option<u64>,
    pub completion_tokens: Option<u64>,
}

impl Default for Usage {
    fn default() -> Self {
        Usage {
            prompt_tokens: Some(0),
            completion_tokens: Some(0),
        }
    }
}

impl Usage {
    /// Whether either count is unknown.
    pub fn is_unknown(&self) -> bool {
        self.prompt_tokens.is_none() || self.completion_tokens.is_none()
    }
}

/// What the model answered: the first choice (if any), why it stopped, and the accounting.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ChatReply {
    /// Number of choices in the response; 0 is the "empty choices" outcome.
    pub choices: usize,
    /// The first choice's text.
    pub content: Option<String>,
    /// The first choice's `finish_reason` (`stop`, `length`, `content_filter`, ...).
    pub finish_reason: Option<String>,
    /// The first choice's `refusal` field, when the server sets one.
    pub refusal: Option<String>,
    pub usage: Usage,
    /// Wall time of the request that produced the reply (kept with a cached reply, so a resumed
    /// run records the same figure).
    pub latency_ms: f64,
}

/// Why a request produced no reply.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ChatError {
    /// The request was written to a batch file; the episode waits for its answer.
    #[error("waiting for the reply to `{0}` (batch exchange)")]
    Pending(String),
    /// The request failed for good (after the client's retries), or the cache could not answer
    /// it in cache-only mode. The message never contains a credential.
    #[error("{0}")]
    Failed(String),
}

/// A chat-completion model. `&self` so one client serves every worker thread.
pub trait ChatModel {
    /// Answers one request.
    fn complete(&self, request: &ChatRequest) -> Result<ChatReply, ChatError>;
}

impl<M: ChatModel + ?Sized> ChatModel for &M {
    fn complete(&self, request: &ChatRequest) -> Result<ChatReply, ChatError> {
        (**self).complete(request)
    }
}
