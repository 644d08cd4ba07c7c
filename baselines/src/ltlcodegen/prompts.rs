//! LTLCodeGen's prompt, paraphrased from what the adaptation asks (reference §7), and the code
//! the gold oracle writes in the same form.

use m2rc_compiler::ltl::Formula;
use m2rc_compiler::ltl::syntax::Kind;
use serde_json::Value;

pub const SYSTEM: &str = "\
You follow the LTLCodeGen method: turn a navigation instruction into Python code. Write a \
function `def question():` that builds and returns a linear temporal logic formula with the \
operator library only: ap(\"name\"), ltl_and(a, b), ltl_or(a, b), ltl_not(a), ltl_until(a, b), \
ltl_eventually(a), ltl_always(a), ltl_imply(a, b).
- Use only AP names from the inventory.
- When a category has several instances, use the first matching AP in the listed order.
- Do not try to resolve nearest, farthest, relational, room-content, midpoint or comparative \
references; pick the AP as the rules above say.
- Ignore soft preferences (stay close to, keep away from, prefer, clearance, shapes).
- Do not encode the start pose or the start room.
- Output only the code.";

const START_RULE: &str = "The robot's start pose and start room are given by the planner: do \
not put them in the formula.";

const EXAMPLE: &str =
    "def question():\n    target = ap(\"object_12\")\n    return ltl_eventually(target)";

/// The user message of attempt `previous.len() + 1`; `previous` is the last attempt's code and
/// why it failed.
pub fn user(instruction: &str, inventory: &Value, previous: Option<(&str, &str)>) -> String {
    let mut s = format!(
        "{START_RULE}\n\nInstruction: {instruction}\n\nAP inventory (JSON):\n{}\n\nExample:\n{EXAMPLE}\n",
        serde_json::to_string_pretty(inventory).unwrap_or_default()
    );
    if let Some((code, why)) = previous {
        s.push_str(&format!(
            "\nYour previous code failed.\nPrevious code:\n{code}\nFailure: {why}\nWrite corrected code.\n"
        ));
    }
    s
}

/// The code inside the reply's first fenced block, or the whole reply.
pub fn extract_code(reply: &str) -> String {
    if let Some(start) = reply.find("```") {
        let body = &reply[start + 3..];
        let body = body.split_once('\n').map_or("", |(_, rest)| rest);
        return body.split("```").next().unwrap_or("").to_string();
    }
    reply.to_string()
}

/// `formula` as a `question()` program over the library (atoms are AP names).
pub fn code_of(formula: &Formula) -> String {
    format!("def question():\n    return {}\n", expr(formula))
}

fn expr(f: &Formula) -> String {
    let call = |name: &str, parts: &[&Formula]| {
        let args: Vec<String> = parts.iter().map(|p| expr(p)).collect();
        format!("{name}({})", args.join(", "))
    };
    match &f.kind {
        Kind::Atom(a) => format!("ap({})", Value::String(a.clone())),
        Kind::Not(a) => call("ltl_not", &[a]),
        Kind::Eventually(a) => call("ltl_eventually", &[a]),
        Kind::Always(a) => call("ltl_always", &[a]),
        Kind::And(a, b) => call("ltl_and", &[a, b]),
        Kind::Or(a, b) => call("ltl_or", &[a, b]),
        Kind::Until(a, b) => call("ltl_until", &[a, b]),
        Kind::Implies(a, b) => call("ltl_imply", &[a, b]),
        // The gold formulas use none of these; `None` makes the sandbox refuse the program.
        _ => "None".into(),
    }
}
