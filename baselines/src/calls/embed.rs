//! Text embeddings for the baselines that ground by similarity (Lang2LTL, Lang2LTL-2): from a
//! server (`--embeddings server`, `POST {base}/embeddings` with `--embed-model`, cached and
//! batched like chat calls) or from `--embeddings lexical`, a deterministic encoder of our own
//! (hashed character trigrams and words). The lexical encoder is not a neural model; every record
//! and label it touches says so.

use serde::{Deserialize, Serialize};

/// Where embeddings come from.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "embeddings")]
pub enum EmbedMode {
    /// The OpenAI-compatible server of `--llm-base-url`, with this model.
    Server { model: String },
    /// [`lexical`]: hashed character trigrams and words.
    Lexical,
}

impl EmbedMode {
    pub fn label(&self) -> String {
        match self {
            EmbedMode::Server { model } => format!("embeddings from {model}"),
            EmbedMode::Lexical => LEXICAL_LABEL.into(),
        }
    }
}

/// The label of every output the lexical encoder touches.
pub const LEXICAL_LABEL: &str =
    "[LEXICAL embeddings: hashed character trigrams, not a neural model]";

/// Dimensions of the lexical encoder.
pub const LEXICAL_DIMS: usize = 256;

fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= *b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The lexical embedding of `text`: lower-cased, `_` read as a space; every character trigram of
/// each word (padded with spaces) and every word hashed into [`LEXICAL_DIMS`] signed buckets, then
/// L2-normalised. Same text, same vector, on every machine.
pub fn lexical(text: &str) -> Vec<f32> {
    let mut v = vec![0f32; LEXICAL_DIMS];
    let lower = text.to_lowercase().replace('_', " ");
    let mut add = |feature: &str, weight: f32| {
        let h = fnv1a(feature.as_bytes());
        let sign = if h >> 63 == 0 { 1.0 } else { -1.0 };
        v[(h % LEXICAL_DIMS as u64) as usize] += sign * weight;
    };
    for word in lower
        .split(|c: char| !c.is_alphanumeric())
        .filter(|w| !w.is_empty())
    {
        add(&format!("w:{word}"), 2.0);
        let padded: Vec<char> = format!(" {word} ").chars().collect();
        for tri in padded.windows(3) {
            add(&tri.iter().collect::<String>(), 1.0);
        }
    }
    let norm = v.iter().map(|x| x * x).sum::<f32>().sqrt();
    if norm > 0.0 {
        v.iter_mut().for_each(|x| *x /= norm);
    }
    v
}

/// Cosine similarity (0 when either vector is zero; the caller checks the lengths agree).
pub fn cosine(a: &[f32], b: &[f32]) -> f64 {
    let (mut dot, mut na, mut nb) = (0f64, 0f64, 0f64);
    for (x, y) in a.iter().zip(b) {
        dot += *x as f64 * *y as f64;
        na += *x as f64 * *x as f64;
        nb += *y as f64 * *y as f64;
    }
    if na == 0.0 || nb == 0.0 {
        0.0
    } else {
        dot / (na.sqrt() * nb.sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lexical_is_deterministic_and_ranks_shared_words_higher() {
        assert_eq!(lexical("the red sofa"), lexical("the red sofa"));
        let q = lexical("the sofa");
        assert!(
            cosine(&q, &lexical("a sofa located in a living room"))
                > cosine(&q, &lexical("a toilet located in a bathroom"))
        );
        assert_eq!(cosine(&lexical(""), &q), 0.0);
    }
}
