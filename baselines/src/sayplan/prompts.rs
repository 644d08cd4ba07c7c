//! SayPlan's prompts, in m2rc's words after the adaptation's layout (role, environment functions,
//! state predicates, API, rules, output format, then the instruction, the visible scene graph,
//! the memory and the feedback), and the reading of its JSON replies.

use crate::iln::reply::{json_object, string_field};
use m2rc_compiler::lower::Message;
use serde_json::{Value, json};

pub const SYSTEM: &str = "You are an excellent graph planning agent. Return only JSON.";

const PREAMBLE: &str = "\
Agent role: you are a mobile robot in a building. You see a 3D scene graph of it, collapsed to \
its rooms; you can expand a room to see the objects it contains and contract it to hide them \
again. Find the part of the graph the instruction needs, then write a plan.

Environment functions:
- goto(node): drive to a room or an object of the scene graph.
- done(): the task is finished.

State predicates:
- located_at(agent, room): where the agent is.
- reachable(node): the node can be driven to.
- contains(room, object): the room holds the object.
- adjacent_to(room, room): the two rooms are joined by a doorway or an opening.

API:
- expand_node(node): show the nodes a room contains.
- contract_node(node): hide them again.
- verify_plan(plan): a simulator checks the plan and gives feedback.

Rules:
- Use only node ids that are visible in the scene graph.
- Expand a room when its hidden children may matter to the instruction.
- Contract rooms that do not matter, to keep the graph small.
- Never invent nodes.
- Switch to planning mode when enough of the graph is visible.
- Never output coordinates or dense paths; the plan is a list of goto(node) and done().
";

const OUTPUT: &str = "\
Output format (one JSON object):
{\"reasoning\": \"<text>\", \"mode\": \"exploring\" | \"planning\", \"command\": \
{\"command_name\": \"expand_node\" | \"contract_node\" | \"none\", \"node_name\": \"<node id or empty>\", \
\"plan\": null | [\"goto(<node id>)\", ..., \"done()\"]}}
";

/// The memory shown with each prompt.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Memory {
    pub expanded: Vec<String>,
    pub contracted: Vec<String>,
    pub history: Vec<String>,
}

/// The semantic-search step's messages.
pub fn search_messages(
    instruction: &str,
    graph: &Value,
    memory: &Memory,
    feedback: &str,
) -> Vec<Message> {
    let user = format!(
        "{PREAMBLE}\n{OUTPUT}\nYou are in semantic search: explore with expand_node and \
         contract_node (plan stays null), or set mode to \"planning\" when the graph shows enough.\n\
         \nInstruction: {instruction}\n\n3D Scene Graph:\n{}\n\nMemory:\n{}\n\nFeedback: {}\n",
        serde_json::to_string(graph).unwrap_or_default(),
        memory_text(memory),
        if feedback.is_empty() {
            "none"
        } else {
            feedback
        }
    );
    vec![Message::system(SYSTEM), Message::user(user)]
}

/// The planning round's messages.
pub fn plan_messages(
    instruction: &str,
    graph: &Value,
    memory: &Memory,
    previous: Option<&[String]>,
    feedback: &str,
) -> Vec<Message> {
    let user = format!(
        "{PREAMBLE}\n{OUTPUT}\nYou are in planning mode: set mode to \"planning\", command_name to \
         \"none\", and give the plan.\n\nInstruction: {instruction}\n\n3D Scene Graph (task \
         subgraph):\n{}\n\nMemory:\n{}\n\nPrevious plan: {}\nVerifier feedback: {}\n",
        serde_json::to_string(graph).unwrap_or_default(),
        memory_text(memory),
        previous.map_or("none".to_string(), |p| json!(p).to_string()),
        if feedback.is_empty() {
            "none"
        } else {
            feedback
        }
    );
    vec![Message::system(SYSTEM), Message::user(user)]
}

fn memory_text(m: &Memory) -> String {
    format!(
        "expanded nodes: {}\ncontracted nodes: {}\ncommand history: {}",
        json!(m.expanded),
        json!(m.contracted),
        json!(m.history)
    )
}

/// The message that re-asks after an unusable reply.
pub fn reask(reason: &str) -> String {
    format!(
        "Your reply could not be used: {reason}. Reply again with only the JSON object in the \
         output format."
    )
}

/// A search step's command.
#[derive(Clone, Debug, PartialEq)]
pub enum SearchCommand {
    Expand(String),
    Contract(String),
    /// Switch to planning (mode `planning`, or command `none`).
    Plan,
}

/// Reads a search reply.
pub fn read_search(reply: &str) -> Result<SearchCommand, String> {
    let obj = json_object(reply)?;
    let mode = string_field(&obj, "mode")?;
    if mode == "planning" {
        return Ok(SearchCommand::Plan);
    }
    if mode != "exploring" {
        return Err(format!(
            "field `mode` is `{mode}`, not `exploring` or `planning`"
        ));
    }
    let command = match obj.get("command") {
        Some(Value::Object(c)) => c,
        _ => return Err("field `command` is not an object".into()),
    };
    let name = string_field(command, "command_name")?;
    let node = || {
        string_field(command, "node_name")
            .map(|s| s.trim().to_string())
            .and_then(|s| {
                if s.is_empty() {
                    Err("field `command.node_name` is empty".to_string())
                } else {
                    Ok(s)
                }
            })
    };
    match name {
        "expand_node" => Ok(SearchCommand::Expand(node()?)),
        "contract_node" => Ok(SearchCommand::Contract(node()?)),
        "none" => Ok(SearchCommand::Plan),
        other => Err(format!(
            "`command.command_name` is `{other}`, not expand_node, contract_node or none"
        )),
    }
}

/// Reads a planning reply's plan (as written; `done()` appended when missing).
pub fn read_plan(reply: &str) -> Result<Vec<String>, String> {
    let obj = json_object(reply)?;
    let command = match obj.get("command") {
        Some(Value::Object(c)) => c,
        _ => return Err("field `command` is not an object".into()),
    };
    let plan = match command.get("plan") {
        Some(Value::Array(p)) => p,
        _ => return Err("field `command.plan` is not a list of actions".into()),
    };
    let mut out = Vec::new();
    for a in plan {
        match a {
            Value::String(s) => out.push(s.trim().to_string()),
            other => return Err(format!("plan action {other} is not a string")),
        }
    }
    if out.last().map(String::as_str) != Some("done()") {
        out.push("done()".into());
    }
    Ok(out)
}

/// The gold search reply: expand `room`, or switch to planning when `None`.
pub fn gold_search_reply(room: Option<&str>) -> String {
    match room {
        Some(r) => json!({
            "reasoning": "gold: a target lies in this room",
            "mode": "exploring",
            "command": {"command_name": "expand_node", "node_name": r, "plan": null},
        }),
        None => json!({
            "reasoning": "gold: every target is visible",
            "mode": "planning",
            "command": {"command_name": "none", "node_name": "", "plan": null},
        }),
    }
    .to_string()
}

/// The gold plan reply: go to each target node in order.
pub fn gold_plan_reply(targets: &[String]) -> String {
    let mut plan: Vec<String> = targets.iter().map(|t| format!("goto({t})")).collect();
    plan.push("done()".into());
    json!({
        "reasoning": "gold: the annotated targets in order",
        "mode": "planning",
        "command": {"command_name": "none", "node_name": "", "plan": plan},
    })
    .to_string()
}
