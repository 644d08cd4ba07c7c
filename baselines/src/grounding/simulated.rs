//! The simulated model for the JSON grounding variants: NOT a language model, and labelled so.
//!
//! The first answer is the episode's gold program with the `.m2r` simulated model's fault classes
//! injected (`m2rc_llm::simulated::faults`), at the same rate and with the same limit of three,
//! then written in the variant's JSON. A syntax slip has no `.m2r` text to slip in, so it is the
//! JSON's own: the reply loses its last closing brackets. A repair answer is computed from the
//! repair prompt alone, as the `.m2r` model's is: the previous reply with each error's certain fix
//! (`fix`) applied, or the name its `help: write `X`` gives at its pointer; faults no diagnostic
//! explains (a dropped constraint, a lost scope) survive.

use m2rc_compiler::lower::{ChatError, ChatRequest, Role, Usage, estimate_tokens};
use m2rc_llm::simulated::faults::FAULTS;
use m2rc_llm::wire::completion_body;
use m2rc_llm::{Fetch, Fetched, SimulatedSpec};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::Value;

/// Most faults in one answer, as the `.m2r` model.
const MAX_FAULTS: usize = 3;

fn fnv1a(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The first answer: the gold program with faults (each kind at most once, each further one with
/// probability `rate`), turned into JSON by `write`; the names of the faults, in order.
pub fn first_answer(
    gold: &str,
    spec: SimulatedSpec,
    episode: &str,
    write: &dyn Fn(&str) -> Option<String>,
) -> (String, Vec<&'static str>) {
    let mut rng = ChaCha8Rng::seed_from_u64(spec.seed ^ fnv1a(episode) ^ fnv1a("json"));
    let mut program = gold.to_string();
    let mut applied: Vec<&'static str> = Vec::new();
    let mut kinds: Vec<usize> = (0..FAULTS.len()).collect();
    let mut slip = false;
    while applied.len() < MAX_FAULTS && rng.random::<f64>() < spec.fault_rate {
        let mut done = false;
        while !kinds.is_empty() {
            let i = rng.random_range(0..kinds.len());
            let k = kinds.swap_remove(i);
            let (name, f) = FAULTS[k];
            if name == "syntax_slip" {
                slip = true;
                applied.push(name);
                done = true;
                break;
            }
            // A fault that leaves a program the variant cannot write is not a fault it can make.
            if let Some(p) = f(&program, &mut rng).filter(|p| write(p).is_some()) {
                program = p;
                applied.push(name);
                done = true;
                break;
            }
        }
        if !done {
            break;
        }
    }
    let mut text = write(&program).or_else(|| write(gold)).unwrap_or_default();
    if slip {
        let keep = text.trim_end().len().saturating_sub(2);
        text.truncate(keep);
    }
    (text, applied)
}

/// The repaired reply for a repair request: the previous reply with the diagnostics' edits.
pub fn repair_answer(previous: &str, prompt: &str) -> String {
    let diags: Vec<Value> = block(prompt, "json")
        .and_then(|j| serde_json::from_str(&j).ok())
        .unwrap_or_default();
    let mut text = previous.trim_end().to_string();
    for d in &diags {
        if d["severity"] == "error" && d["fix"]["op"] == "append_text" {
            text.push_str(d["fix"]["text"].as_str().unwrap_or(""));
        }
    }
    let Ok(mut json) = serde_json::from_str::<Value>(&text) else {
        return text;
    };
    for d in diags.iter().filter(|d| d["severity"] == "error") {
        let pointer = d["pointer"].as_str().unwrap_or("");
        let edit = if d["fix"]["op"] == "replace" {
            d["fix"]["path"]
                .as_str()
                .map(|p| (p.to_string(), d["fix"]["value"].clone()))
        } else {
            d["help"].as_str().and_then(|h| {
                let rest = &h[h.find("write `")? + 7..];
                let word = &rest[..rest.find('`')?];
                // A help names a value only where the pointer names a string.
                json.pointer(pointer)
                    .filter(|v| v.is_string())
                    .map(|_| (pointer.to_string(), Value::String(word.to_string())))
            })
        };
        if let Some((path, value)) = edit
            && let Some(slot) = json.pointer_mut(&path)
        {
            *slot = value;
        }
    }
    serde_json::to_string(&json).unwrap_or(text)
}

/// The body of the first fenced block tagged `lang`.
fn block(text: &str, lang: &str) -> Option<String> {
    let open = format!("```{lang}\n");
    let start = text.find(&open)? + open.len();
    let end = text[start..].find("```")? + start;
    Some(text[start..end].to_string())
}

/// The simulated model of one episode of a JSON variant.
pub struct SimulatedJson {
    pub spec: SimulatedSpec,
    pub name: String,
    /// The variant (`schema`), part of the cache key with the episode.
    pub variant: &'static str,
    pub episode: String,
    pub first: String,
}

impl SimulatedJson {
    pub fn new(
        spec: SimulatedSpec,
        variant: &'static str,
        episode: &str,
        gold: &str,
        write: &dyn Fn(&str) -> Option<String>,
    ) -> (Self, Vec<&'static str>) {
        let (first, faults) = first_answer(gold, spec, episode, write);
        (
            SimulatedJson {
                spec,
                name: spec.model_name(),
                variant,
                episode: episode.to_string(),
                first,
            },
            faults,
        )
    }
}

impl Fetch for SimulatedJson {
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
            "simulated v{} {} episode {}",
            m2rc_llm::simulated::SIMULATED_REPLIES_VERSION,
            self.variant,
            self.episode
        )
    }

    fn fetch(&self, request: &ChatRequest, _body: &Value) -> Result<Fetched, ChatError> {
        let content = if request.messages.len() <= 2 {
            self.first.clone()
        } else {
            let last = request.messages.last().map_or("", |m| m.content.as_str());
            let previous = request
                .messages
                .iter()
                .rev()
                .find(|m| m.role == Role::Assistant)
                .map_or("", |m| m.content.as_str());
            repair_answer(previous, last)
        };
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
