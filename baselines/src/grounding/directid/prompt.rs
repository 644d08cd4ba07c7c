//! Direct ID's messages: the reply's format, the compact catalog of the map (ids, centres,
//! boxes, sizes, adjacency) and the instruction. The model resolves every reference itself by
//! reading the catalog; nothing is computed for it.

use m2rc_compiler::lower::{Message, Prompt};
use serde_json::Value;

pub const SYSTEM: &str =
    "You ground route instructions to IDs in a compact semantic scene catalog. Return JSON only.";

/// How a reply is written, for the model.
pub const FORMAT: &str = "\
Reply with one JSON object {segments, constraints}.
- segments: every destination in visiting order, from `task_start`: [{id, target_id}]. `id` is \
your name for the segment (\"s1\", \"s2\", ...); `target_id` is a room or object id (`task_start` to go back to the start).
- constraints: [{kind, ref_ids, segment_ids?, spatial_scope_ids?, within_m?, relation?, \
path_shape?, source_text?}].
  - kind `require_visit`: pass `ref_ids[0]` on the way to the one segment in `segment_ids`.
  - kind `forbid`: never enter any of `ref_ids`; with `within_m`, never come within that many \
metres of them (\"keep out of the area around the bed\": 0.5).
  - kind `prefer_near` / `prefer_far`: stay close to / away from exactly one id (`within_m` makes \
it the area around it).
  - kind `prefer_relative`: exactly two ids, `relation` `closer_to` (stay closer to the first \
than to the second) or `farther_from` (farther from the first than from the second).
  - kind `prefer_path_shape`: `path_shape` {type: circle | follow_wall | through, direction?: \
clockwise | counterclockwise}; circle goes round one room or object, follow_wall along the walls \
of one room, through passes 2 to 4 ids in order.
  - `segment_ids`: the segments during which it holds; leave it out for the whole route.
  - `spatial_scope_ids`: where it holds (a room, usually); leave it out for everywhere.
- Every id must appear verbatim in the catalog. Resolve references (\"the lamp next to the \
sofa\", \"the largest bedroom\") yourself from the catalog's rooms, centres, boxes and sizes. \
Do not invent ids, coordinates, paths or planner parameters.
";

/// An example of the format (an invented building, not this one).
pub const EXAMPLE: &str = r#"Instruction: "Go to the bed in the small bedroom, staying away from the TV while in the living room, then walk around the dining table to the fridge. Never enter the bathroom."
{"segments":[{"id":"s1","target_id":"object_31"},{"id":"s2","target_id":"object_7"}],"constraints":[{"kind":"prefer_far","ref_ids":["object_12"],"segment_ids":["s1"],"spatial_scope_ids":["room_2"],"source_text":"staying away from the TV while in the living room"},{"kind":"prefer_path_shape","ref_ids":["object_9"],"segment_ids":["s2"],"path_shape":{"type":"circle"},"source_text":"walk around the dining table"},{"kind":"forbid","ref_ids":["room_4"],"source_text":"Never enter the bathroom"}]}"#;

/// The first prompt: format, example, catalog (minified JSON), instruction. `what` names the
/// reply's form in the output line; `format` and `example` are Direct ID's or catalog-LTL's.
pub fn prompt_with(catalog: &Value, instruction: &str, format: &str, example: &str) -> Prompt {
    let mut user = String::new();
    user.push_str("# Output format\n\n");
    user.push_str(format);
    user.push_str("\n# Example (another building)\n\n");
    user.push_str(example);
    user.push_str("\n\n# Scene catalog\n\n");
    user.push_str(&serde_json::to_string(catalog).unwrap_or_default());
    user.push_str("\n\n# Instruction\n\n");
    user.push_str(instruction.trim());
    user.push_str(
        "\n\n# Output\n\nReply with the JSON object for this instruction and nothing else.\n",
    );
    Prompt {
        messages: vec![Message::system(SYSTEM), Message::user(user)],
    }
}

/// Direct ID's first prompt.
pub fn direct_id_prompt(catalog: &Value, instruction: &str) -> Prompt {
    prompt_with(catalog, instruction, FORMAT, EXAMPLE)
}
