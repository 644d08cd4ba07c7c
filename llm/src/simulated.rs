//! The simulated model, for offline evaluation of the repair loop: it is NOT a language model and
//! every output it touches says so.
//!
//! The first answer is the episode's gold program with realistic faults injected at the configured
//! rate ([`faults`]). A repair answer is computed from the repair prompt alone: the program shown
//! there and what the diagnostics say (their suggestions, and `help: write `...``), never from the
//! gold program, so faults the diagnostics cannot explain (a dropped constraint, a lost scope)
//! survive, as they would with a model that only reads the compiler.

pub mod faults;

use crate::config::SimulatedSpec;
use crate::exchange::{Fetch, Fetched};
use crate::wire::completion_body;
use m2rc_compiler::lower::{ChatError, ChatRequest, Usage, estimate_tokens};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde_json::Value;

/// The version of the simulated model's replies, part of every cache key: bump it whenever the
/// fault classes or the repairer change, so a cache never serves replies the current code would
/// not give (a stale cache would silently mix two models in one table).
pub const SIMULATED_REPLIES_VERSION: u32 = 2;

pub struct SimulatedModel {
    spec: SimulatedSpec,
    name: String,
    gold: String,
    /// The episode key (`<map>/<instruction>`): faults are seeded by it, and it is part of the
    /// cache key because the answer depends on the episode's gold program.
    episode: String,
}

fn fnv1a(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

impl SimulatedModel {
    pub fn new(spec: SimulatedSpec, gold: &str, episode: &str) -> Self {
        SimulatedModel {
            spec,
            name: spec.model_name(),
            gold: gold.to_string(),
            episode: episode.to_string(),
        }
    }

    fn rng(&self) -> ChaCha8Rng {
        ChaCha8Rng::seed_from_u64(self.spec.seed ^ fnv1a(&self.episode))
    }

    /// The first answer's program and the faults injected into it.
    pub fn first_program(&self) -> (String, Vec<&'static str>) {
        faults::inject(&self.gold, self.spec.fault_rate, &mut self.rng())
    }

    /// The repaired program for a repair prompt (its last user message).
    pub fn repair_program(prompt: &str) -> String {
        let program = block(prompt, "m2r").unwrap_or_default();
        let diags: Vec<Value> = block(prompt, "json")
            .and_then(|j| serde_json::from_str(&j).ok())
            .unwrap_or_default();
        faults::apply_diagnostics(&program, &diags)
    }
}

/// The body of the first fenced block tagged `lang`.
fn block(text: &str, lang: &str) -> Option<String> {
    let open = format!("```{lang}\n");
    let start = text.find(&open)? + open.len();
    let end = text[start..].find("```")? + start;
    Some(text[start..end].to_string())
}

impl Fetch for SimulatedModel {
    fn model(&self) -> &str {
        &self.name
    }

    fn temperature(&self) -> f64 {
        0.0
    }

    fn max_tokens(&self) -> Option<u32> {
        None
    }

    fn key_extra(&self, _request: &ChatRequest) -> String {
        format!(
            "simulated v{SIMULATED_REPLIES_VERSION} episode {}",
            self.episode
        )
    }

    fn fetch(&self, request: &ChatRequest, _body: &Value) -> Result<Fetched, ChatError> {
        let program = if request.messages.len() <= 2 {
            self.first_program().0
        } else {
            let last = request.messages.last().map_or("", |m| m.content.as_str());
            Self::repair_program(last)
        };
        let content = format!("```m2r\n{program}```");
        let usage = Usage {
            prompt_tokens: Some(
                request
                    .messages
                    .iter()
                    .map(|m| estimate_tokens(&m.content) as u64)
                    .sum(),
            ),
            completion_tokens: Some(estimate_tokens(&content) as u64),
        };
        Ok(Fetched {
            response: completion_body(&self.name, &content, usage),
            latency_ms: 0.0,
        })
    }
}
