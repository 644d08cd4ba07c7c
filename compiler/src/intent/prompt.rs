//! The Schema variant's messages: the operator reference and the graph's format (generated),
//! worked examples as graphs (the CaG prompt's own examples, read into graphs), the scene's
//! categories only (no counts, ids or coordinates, as the reference's Schema prompt), and the
//! instruction. A repair request shows the previous reply and the graph diagnostics as JSON.

use super::GraphDiagnostic;
use super::ops::operator_reference;
use super::program_to_graph;
use crate::lower::{Message, Prompt, SceneCatalog, examples};

pub const SYSTEM: &str = "You ground natural-language route instructions for a mobile robot into \
a JSON intent graph. The graph is compiled deterministically and grounded on a semantic map of the \
building; you never name instances, ids or coordinates. Reply with one JSON object and nothing else.";

/// How an intent graph is written, for the model.
pub const FORMAT: &str = "\
An intent graph is one JSON object {bindings?, segments, constraints?}.
- bindings: [{name, value}] names values used later (\"it\", \"that room\", \"the other one\").
- segments: the destinations in visiting order, from the start. A segment is {id?, to, bindings?, \
constraints?}; its constraints hold only while heading to `to`. {for, in, segments} visits each \
element of an ordered set; {let, value} binds a name between segments.
- constraints (top level): hold for the whole route, or only during the segments named in `during`.
- A constraint is {kind: require_visit | forbid | prefer, place | preference, within?, during?}: \
require_visit (only inside a segment) passes `place` before the destination, forbid never enters \
`place`, prefer takes a preference operator (near, far, closer, circle, follow_wall, patrol, \
through, clearance); `within` limits it to a place.
- A value is a binding name, a category, a constant or a word (a string), a distance (\"1.5m\", \
\"30cm\"), a number, {lambda, body} with the parameter name, or an operator \
{op, of?, args?, kwargs?}: `of` is the value the operator applies to (the receiver), `args` the \
positional arguments, `kwargs` the named ones.
- A set never silently becomes one element: rank it (nearest, largest, ...) or assert `only`.
";

/// The first prompt of the Schema variant.
pub fn schema_prompt(
    map_id: &str,
    catalog: &SceneCatalog,
    instruction: &str,
    n_examples: usize,
) -> Prompt {
    let mut user = String::new();
    user.push_str("# Intent graph\n\n");
    user.push_str(FORMAT);
    user.push_str("\n# Operators\n\n");
    user.push_str(&operator_reference());
    let picked = examples::select(map_id, n_examples);
    let mut shown = false;
    for e in picked {
        let Ok(g) = program_to_graph(&e.program) else {
            continue;
        };
        if !shown {
            user.push_str("\n# Worked examples (other buildings)\n");
            shown = true;
        }
        user.push_str(&format!(
            "\nInstruction: \"{}\"\n```json\n{}\n```\n",
            e.instruction,
            serde_json::to_string(&g).unwrap_or_default()
        ));
    }
    user.push_str("\n# Scene categories\n\n");
    let keys = |m: &std::collections::BTreeMap<String, usize>| {
        m.keys().cloned().collect::<Vec<_>>().join(", ")
    };
    user.push_str(&format!(
        "Room categories: {}\nObject categories: {}\n",
        keys(&catalog.room_counts),
        keys(&catalog.object_counts)
    ));
    user.push_str("\n# Instruction\n\n");
    user.push_str(instruction.trim());
    user.push_str(
        "\n\n# Output\n\nWrite the intent graph for this instruction. Use only the categories \
above and only the listed operators. Reply with one JSON object and nothing else.\n",
    );
    Prompt {
        messages: vec![Message::system(SYSTEM), Message::user(user)],
    }
}

/// The repair request after a rejected reply: the first prompt, the model's reply, and the
/// diagnostics (each with the JSON pointer of the node at fault and, when certain, its fix).
pub fn json_repair_messages(
    first: &Prompt,
    reply: &str,
    diagnostics: &[GraphDiagnostic],
    what: &str,
) -> Vec<Message> {
    let mut messages = first.messages.clone();
    messages.push(Message {
        role: crate::lower::Role::Assistant,
        content: reply.to_string(),
    });
    let diags: Vec<serde_json::Value> = diagnostics.iter().map(|d| d.to_json()).collect();
    messages.push(Message::user(format!(
        "The {what} was rejected. Each diagnostic names the JSON pointer of the node at fault; \
`fix`, when present, is the certain edit.\n```json\n{}\n```\nFix every error with the smallest \
change that keeps the meaning of the instruction, and reply with the complete corrected JSON \
object and nothing else.\n",
        serde_json::to_string_pretty(&diags).unwrap_or_default()
    )));
    messages
}
