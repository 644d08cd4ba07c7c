//! OSG-LLM's three prompts, paraphrased from what the adaptation asks (reference §4): ground
//! the instruction to the scene graph, translate the grounded goals to prefix LTL, and name the
//! rooms a search should try first. Each user message is JSON, as in the adaptation.

use serde_json::{Value, json};

pub const GROUNDING_SYSTEM: &str = "\
You connect a navigation instruction to the nodes of an indoor scene graph (a floor, its rooms, \
the objects in each room). Read the instruction and the graph, and answer with one JSON object \
and nothing else:
{\"ordered_goal_entities\": [ids], \"avoid_entities\": [ids], \
\"entity_bindings\": [{\"text_span\": \"...\", \"entity_id\": \"...\", \"reason\": \"...\"}], \
\"unsupported_phrases\": [\"...\"]}
- ordered_goal_entities: the rooms and objects the robot must reach, in the order it must reach them.
- avoid_entities: rooms and objects the robot must never enter or approach.
- Use only ids that appear in the graph; never invent one.
- Preferences (stay close to, keep away from, prefer, follow a shape, keep clear) are not goals \
or avoids: list their words in unsupported_phrases.";

pub const LTL_SYSTEM: &str = "\
You translate a grounded navigation task into linear temporal logic in prefix notation. Use only \
the operators F G ! & | U -> and only the atomic propositions listed in \
allowed_atomic_propositions. Goals to reach in order a, then b are written F & a F b; an avoided \
proposition c is conjoined as G ! c. Ignore soft preferences. Answer with one JSON object and \
nothing else: {\"ltl_prefix\": \"...\", \"notes\": \"...\"}";

pub const HEURISTIC_SYSTEM: &str = "\
You guide a planner through an indoor scene graph. Given the instruction, the propositions the \
route must satisfy and the rooms with their connections, name the rooms and objects a good route \
is likely to pass through, most useful first. Answer with one JSON object and nothing else: \
{\"preferred_nodes\": [ids], \"reason\": \"...\"}";

pub fn grounding_user(instruction: &str, scene_graph: &Value) -> String {
    json!({"instruction": instruction, "scene_graph": scene_graph}).to_string()
}

pub fn ltl_user(
    instruction: &str,
    goals: &[String],
    avoids: &[String],
    allowed: &[String],
) -> String {
    json!({
        "instruction": instruction,
        "ordered_goal_aps": goals,
        "avoid_aps": avoids,
        "allowed_atomic_propositions": allowed,
    })
    .to_string()
}

pub fn heuristic_user(instruction: &str, goals: &[String], graph: &Value) -> String {
    json!({"instruction": instruction, "required_goal_aps": goals, "scene_graph": graph})
        .to_string()
}
