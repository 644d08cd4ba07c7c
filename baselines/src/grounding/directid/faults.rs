//! The simulated model's faults in catalog ids: NOT a language model, and labelled so. The
//! `.m2r` simulated model's fault classes (`m2rc_llm::simulated::faults`) where they mean
//! something for ids, at the same rate and with the same limit of three, each kind at most once:
//!
//! | `.m2r` class | here |
//! |---|---|
//! | misspelled_category | an id's kind word misspelled (`obejct_12`): the diagnostic's help names the id |
//! | unknown_category | an id the catalog does not have (a number past the map's largest) |
//! | wrong_argument_type | `task_start` where a place to avoid, pass through or scope to is asked (a kind the slot cannot take) |
//! | wrong_argument_count | one id too many on a one-id or two-id constraint |
//! | missing_scope | a constraint's `spatial_scope_ids` left out |
//! | dropped_constraint | a constraint left out |
//! | syntax_slip | the reply loses its last closing brackets |
//!
//! `synonym` and `set_as_object` have no id form (ids have no synonyms, an id is one place).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::Value;

/// Most faults in one answer, as the `.m2r` model.
const MAX_FAULTS: usize = 3;

type Fault = fn(&mut Value, &mut ChaCha8Rng, u32) -> bool;

pub const FAULTS: &[(&str, Fault)] = &[
    ("misspelled_category", misspell),
    ("unknown_category", unknown),
    ("wrong_argument_type", wrong_type),
    ("wrong_argument_count", extra_id),
    ("missing_scope", drop_scope),
    ("dropped_constraint", drop_constraint),
    ("syntax_slip", |_, _, _| true),
];

fn fnv1a(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Every id string in a reply, as JSON pointers.
fn id_slots(reply: &Value) -> Vec<String> {
    let mut out = Vec::new();
    for (i, s) in reply["segments"]
        .as_array()
        .into_iter()
        .flatten()
        .enumerate()
    {
        if s["target_id"].is_string() {
            out.push(format!("/segments/{i}/target_id"));
        }
    }
    for (i, c) in reply["constraints"]
        .as_array()
        .into_iter()
        .flatten()
        .enumerate()
    {
        for (j, _) in c["ref_ids"].as_array().into_iter().flatten().enumerate() {
            out.push(format!("/constraints/{i}/ref_ids/{j}"));
        }
    }
    out
}

fn pick<T: Clone>(items: &[T], rng: &mut ChaCha8Rng) -> Option<T> {
    (!items.is_empty()).then(|| items[rng.random_range(0..items.len())].clone())
}

fn misspell(reply: &mut Value, rng: &mut ChaCha8Rng, _: u32) -> bool {
    let Some(p) = pick(&id_slots(reply), rng) else {
        return false;
    };
    let Some(slot) = reply.pointer_mut(&p) else {
        return false;
    };
    let id = slot.as_str().unwrap_or("").to_string();
    let wrong = if let Some(n) = id.strip_prefix("object_") {
        format!("obejct_{n}")
    } else if let Some(n) = id.strip_prefix("room_") {
        format!("roon_{n}")
    } else {
        return false;
    };
    *slot = Value::String(wrong);
    true
}

fn unknown(reply: &mut Value, rng: &mut ChaCha8Rng, largest: u32) -> bool {
    let Some(p) = pick(&id_slots(reply), rng) else {
        return false;
    };
    let Some(slot) = reply.pointer_mut(&p) else {
        return false;
    };
    let id = slot.as_str().unwrap_or("").to_string();
    let word = if id.starts_with("room_") {
        "room"
    } else {
        "object"
    };
    *slot = Value::String(format!(
        "{word}_{}",
        largest + 1 + rng.random_range(0..50u32)
    ));
    true
}

fn wrong_type(reply: &mut Value, rng: &mut ChaCha8Rng, _: u32) -> bool {
    // Slots that cannot hold the start: an avoided place, a through-waypoint, a scope.
    let mut slots = Vec::new();
    for (i, c) in reply["constraints"]
        .as_array()
        .into_iter()
        .flatten()
        .enumerate()
    {
        if c["kind"] == "forbid" || c["path_shape"]["type"] == "through" {
            slots.push(format!("/constraints/{i}/ref_ids/0"));
        }
        if c["spatial_scope_ids"].is_array() {
            slots.push(format!("/constraints/{i}/spatial_scope_ids/0"));
        }
    }
    let Some(p) = pick(&slots, rng) else {
        return false;
    };
    match reply.pointer_mut(&p) {
        Some(slot) => {
            *slot = Value::String("task_start".into());
            true
        }
        None => false,
    }
}

fn constraints_where(reply: &Value, ok: impl Fn(&Value) -> bool) -> Vec<usize> {
    reply["constraints"]
        .as_array()
        .into_iter()
        .flatten()
        .enumerate()
        .filter(|(_, c)| ok(c))
        .map(|(i, _)| i)
        .collect()
}

fn extra_id(reply: &mut Value, rng: &mut ChaCha8Rng, _: u32) -> bool {
    let fixed = |c: &Value| {
        matches!(
            c["kind"].as_str(),
            Some("prefer_near" | "prefer_far" | "prefer_relative")
        )
    };
    let Some(i) = pick(&constraints_where(reply, fixed), rng) else {
        return false;
    };
    // The extra id is one the reply already names elsewhere (the model's confusion, not a new place).
    let others: Vec<Value> = id_slots(reply)
        .iter()
        .filter_map(|p| reply.pointer(p).cloned())
        .collect();
    let Some(extra) = pick(&others, rng) else {
        return false;
    };
    match reply["constraints"][i]["ref_ids"].as_array_mut() {
        Some(ids) => {
            ids.push(extra);
            true
        }
        None => false,
    }
}

fn drop_scope(reply: &mut Value, rng: &mut ChaCha8Rng, _: u32) -> bool {
    let Some(i) = pick(
        &constraints_where(reply, |c| c.get("spatial_scope_ids").is_some()),
        rng,
    ) else {
        return false;
    };
    reply["constraints"][i]
        .as_object_mut()
        .is_some_and(|o| o.remove("spatial_scope_ids").is_some())
}

fn drop_constraint(reply: &mut Value, rng: &mut ChaCha8Rng, _: u32) -> bool {
    let n = reply["constraints"].as_array().map_or(0, Vec::len);
    if n == 0 {
        return false;
    }
    let i = rng.random_range(0..n);
    reply["constraints"].as_array_mut().is_some_and(|a| {
        a.remove(i);
        true
    })
}

/// The first answer: `gold` with faults, written by `write` (Direct ID's own form or another);
/// the names of the faults, in order. `largest` is the map's largest id (for unknown ids).
pub fn first_answer(
    gold: &Value,
    rate: f64,
    seed: u64,
    episode: &str,
    largest: u32,
    write: &dyn Fn(&Value) -> String,
) -> (String, Vec<&'static str>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ fnv1a(episode) ^ fnv1a("catalog ids"));
    let mut reply = gold.clone();
    let mut applied: Vec<&'static str> = Vec::new();
    let mut kinds: Vec<usize> = (0..FAULTS.len()).collect();
    let mut slip = false;
    while applied.len() < MAX_FAULTS && rng.random::<f64>() < rate {
        let mut done = false;
        while !kinds.is_empty() {
            let k = kinds.swap_remove(rng.random_range(0..kinds.len()));
            let (name, f) = FAULTS[k];
            if f(&mut reply, &mut rng, largest) {
                slip |= name == "syntax_slip";
                applied.push(name);
                done = true;
                break;
            }
        }
        if !done {
            break;
        }
    }
    let mut text = write(&reply);
    if slip {
        let keep = text.trim_end().len().saturating_sub(2);
        text.truncate(keep);
    }
    (text, applied)
}
