//! ILN's two calls, written for m2rc from the adaptation's description: the destination selector
//! (one area for the whole command) and the passage cost evaluator (a cost per passage, 10 when
//! there is no evidence). Each reply is read into a typed answer or a reason it cannot be used.

use super::graph::AreaGraph;
use super::reply::{json_object, string_field};
use super::route::BASE_PASSAGE_COST;
use m2rc_compiler::lower::Message;
use serde_json::{Value, json};
use std::collections::BTreeMap;

pub const SYSTEM: &str = "You are the language copilot of a mobile robot that navigates a \
building by its area-passage graph. Answer with one JSON object and nothing else.";

/// The destination selector's messages.
pub fn destination_messages(g: &AreaGraph, instruction: &str) -> Vec<Message> {
    let user = format!(
        "Choose the destination area of a navigation command.\n\
         \n\
         Rules:\n\
         - Select exactly one destination area (an id from the list below) for the whole command.\n\
         - If the command mentions several places, select the final destination.\n\
         - Objects only help you find the area; do not pick object instances.\n\
         - Do not create ordered stages, do not interpret route constraints, do not output cells.\n\
         \n\
         Output format: {{\"destination_area\": \"room_<id>\", \"reason\": \"<one sentence>\"}}\n\
         \n\
         Area-passage graph:\n{}\n\
         Command: {}\n",
        g.serialise(),
        instruction
    );
    vec![Message::system(SYSTEM), Message::user(user)]
}

/// The passage cost evaluator's messages.
pub fn cost_messages(g: &AreaGraph, instruction: &str, current: &str, dest: &str) -> Vec<Message> {
    let input = json!({
        "human_command": instruction,
        "current_area": current,
        "destination_area": dest,
        "area_passage_graph": g.serialise(),
        "experience_file": "no experience",
    });
    let user = format!(
        "You are the passage cost evaluator. Rate the cost of going through each passage for \
         this navigation task, from experience and event notifications. The base cost of a \
         passage is {BASE_PASSAGE_COST}; keep it when you have no evidence. Higher costs make the \
         planner avoid a passage.\n\
         \n\
         Output format: {{\"door_costs\": {{\"passage_<k>\": {{\"cost\": <number>}}}}, \
         \"navigation_task\": [\"<current area>\", \"<destination area>\"], \"notes\": \"<text>\"}}\n\
         \n\
         Input:\n{}\n",
        serde_json::to_string_pretty(&input).unwrap_or_default()
    );
    vec![Message::system(SYSTEM), Message::user(user)]
}

/// Why a reply cannot be used, with the status it gives the episode.
#[derive(Clone, Debug, PartialEq)]
pub struct Rejected {
    /// `grounding_failed` (an area that is not in the graph) or `llm_output_invalid`.
    pub status: &'static str,
    pub reason: String,
}

fn invalid(reason: String) -> Rejected {
    Rejected {
        status: "llm_output_invalid",
        reason,
    }
}

/// The destination area's index, from the selector's reply.
pub fn read_destination(g: &AreaGraph, reply: &str) -> Result<usize, Rejected> {
    let obj = json_object(reply).map_err(invalid)?;
    let area = string_field(&obj, "destination_area").map_err(invalid)?;
    g.area(area.trim()).ok_or_else(|| Rejected {
        status: "grounding_failed",
        reason: format!("destination_area `{area}` is not an area of the graph"),
    })
}

/// Each rated passage's cost (by passage index), from the evaluator's reply, and notes about
/// entries that were left out (ids that are not passages). A cost that is not a finite,
/// non-negative number makes the whole reply invalid.
pub fn read_costs(
    g: &AreaGraph,
    reply: &str,
) -> Result<(BTreeMap<usize, f64>, Vec<String>), Rejected> {
    let obj = json_object(reply).map_err(invalid)?;
    let costs = match obj.get("door_costs") {
        Some(Value::Object(m)) => m,
        Some(other) => {
            return Err(invalid(format!(
                "`door_costs` is not an object (got {other})"
            )));
        }
        None => return Err(invalid("field `door_costs` is missing".into())),
    };
    let mut out = BTreeMap::new();
    let mut notes = Vec::new();
    for (id, entry) in costs {
        let cost = match entry {
            Value::Object(e) => e.get("cost"),
            number @ Value::Number(_) => Some(number),
            _ => None,
        };
        let Some(cost) = cost
            .and_then(Value::as_f64)
            .filter(|c| c.is_finite() && *c >= 0.0)
        else {
            return Err(invalid(format!(
                "door_costs.{id} is not {{\"cost\": <non-negative number>}} (got {entry})"
            )));
        };
        match g.passage(id) {
            Some(k) => {
                out.insert(k, cost);
            }
            None => notes.push(format!(
                "door_costs names `{id}`, which is not a passage; ignored"
            )),
        }
    }
    Ok((out, notes))
}

/// The gold destination reply: the area of the episode's final must-pass target.
pub fn gold_destination_reply(area_id: &str) -> String {
    json!({"destination_area": area_id, "reason": "gold: the area of the final annotated target"})
        .to_string()
}

/// The gold cost reply: every passage at the base cost (neutral).
pub fn gold_cost_reply(current: &str, dest: &str) -> String {
    json!({
        "door_costs": {},
        "navigation_task": [current, dest],
        "notes": "gold: neutral passage costs",
    })
    .to_string()
}
