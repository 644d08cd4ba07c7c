//! The messages the model sees: a system message with the output contract, and a user message with
//! the language reference, worked examples, the scene catalog and the instruction. A repair request
//! repeats them, then shows the model its previous answer and, in a new user message, the program
//! as the compiler last saw it (after local fixes) with every remaining diagnostic, rendered as
//! text with the source snippet and as JSON.

use super::catalog::{CatalogMode, SceneCatalog};
use super::examples;
use super::extract::Extracted;
use super::reference::language_reference;
use super::{Message, Role};
use crate::diagnostic::{Diagnostic, render_text, to_json};
use serde::{Deserialize, Serialize};

/// The system message: what the model is and the output contract.
pub const SYSTEM: &str = "You translate natural-language route instructions for a mobile robot \
into programs in .m2r, a small typed route language. The program is checked by a compiler, \
grounded on a semantic map of the building and planned; you never plan the path yourself. Reply \
with exactly one fenced code block tagged m2r that holds the complete program, and nothing else.";

/// The closing lines of the first prompt.
pub const CONTRACT: &str = "Write the .m2r program for this instruction. Use only categories \
from the scene catalog and only the built-ins above; never write ids, coordinates or cells. Reply \
with one fenced ```m2r block containing the complete program and nothing else.";

/// The closing lines of a repair prompt.
pub const REPAIR_CONTRACT: &str = "Fix every error with the smallest change that makes the \
program mean what the instruction says: keep the bindings, stages and constraints that are not \
wrong, follow the help and suggestions when they fit the instruction, and never replace a failing \
reference with `start` or an arbitrary element. Reply with the complete corrected program in one \
fenced ```m2r block and nothing else.";

/// What goes into the first prompt besides the instruction.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PromptOptions {
    pub catalog: CatalogMode,
    /// Worked examples to include (from `tests/ui/real/`, never from the scene being solved).
    pub examples: usize,
}

impl Default for PromptOptions {
    fn default() -> Self {
        PromptOptions {
            catalog: CatalogMode::Counts,
            examples: 5,
        }
    }
}

/// The first request's messages.
#[derive(Clone, Debug, PartialEq)]
pub struct Prompt {
    pub messages: Vec<Message>,
}

impl Prompt {
    /// Builds the first prompt for `instruction` on the map `map_id` with its catalog.
    pub fn new(
        map_id: &str,
        catalog: &SceneCatalog,
        instruction: &str,
        opts: &PromptOptions,
    ) -> Prompt {
        let mut user = String::new();
        user.push_str("# The .m2r language\n\n");
        user.push_str(&language_reference());
        let picked = examples::select(map_id, opts.examples);
        if !picked.is_empty() {
            user.push_str("\n# Worked examples (other buildings)\n");
            for e in picked {
                user.push_str(&format!(
                    "\nInstruction: \"{}\"\n```m2r\n{}```\n",
                    e.instruction, e.program
                ));
            }
        }
        user.push_str("\n# Scene catalog\n\n");
        user.push_str(&catalog.render());
        user.push_str("\n# Instruction\n\n");
        user.push_str(instruction.trim());
        user.push_str("\n\n# Output\n\n");
        user.push_str(CONTRACT);
        user.push('\n');
        Prompt {
            messages: vec![Message::system(SYSTEM), Message::user(user)],
        }
    }

    /// Total characters of all messages.
    pub fn chars(&self) -> usize {
        self.messages
            .iter()
            .map(|m| m.content.chars().count())
            .sum()
    }

    /// Estimated tokens of all messages (see [`estimate_tokens`]).
    pub fn estimated_tokens(&self) -> usize {
        self.messages
            .iter()
            .map(|m| estimate_tokens(&m.content))
            .sum()
    }
}

/// A token estimate: one token per four characters, rounded up, the usual rule of thumb for
/// English and code with BPE tokenisers (the server's `usage` gives the real count).
pub fn estimate_tokens(text: &str) -> usize {
    text.chars().count().div_ceil(4)
}

/// What the previous round produced, for the repair prompt.
#[derive(Clone, Debug)]
pub enum Feedback<'a> {
    /// A program the compiler rejected; `program` is the text after local fixes.
    Diagnostics {
        program: &'a str,
        diagnostics: &'a [Diagnostic],
    },
    /// A reply without a usable program; `last_program` is the last program seen, if any.
    NoProgram {
        outcome: &'a Extracted,
        last_program: Option<&'a str>,
    },
}

/// Fenced block helper.
fn fence(lang: &str, body: &str) -> String {
    let mut b = body.to_string();
    if !b.ends_with('\n') {
        b.push('\n');
    }
    format!("```{lang}\n{b}```\n")
}

/// The user message of a repair round.
pub fn repair_message(feedback: &Feedback<'_>) -> String {
    let mut out = String::from("# Repair\n\n");
    match feedback {
        Feedback::Diagnostics {
            program,
            diagnostics,
        } => {
            let errors = diagnostics.iter().filter(|d| d.is_error()).count();
            out.push_str(&format!(
                "The compiler rejected your program with {errors} error(s). This is the program \
as it was checked (unambiguous fixes the compiler could apply itself are already applied):\n\n"
            ));
            out.push_str(&fence("m2r", program));
            out.push_str("\n## Diagnostics\n\n");
            out.push_str(&fence(
                "text",
                &render_text(diagnostics, "program.m2r", program),
            ));
            out.push_str("\n## Diagnostics as JSON\n\n");
            out.push_str(&fence("json", &to_json(diagnostics, program)));
        }
        Feedback::NoProgram {
            outcome,
            last_program,
        } => {
            let why = match outcome {
                Extracted::Empty => "Your previous reply was empty.".to_string(),
                Extracted::Refusal { .. } => "Your previous reply declined the task. The task \
is only to translate a route instruction into a program."
                    .to_string(),
                Extracted::NoCode { .. } => {
                    "Your previous reply contained no ```m2r block.".to_string()
                }
                Extracted::CutOff { .. } => "Your previous reply was cut off at the length \
limit before the program ended. Write a shorter complete program: no comments, no prose."
                    .to_string(),
                Extracted::Code { .. } => String::new(),
            };
            out.push_str(&why);
            out.push('\n');
            if let Some(p) = last_program {
                out.push_str("\nThe last program you wrote:\n\n");
                out.push_str(&fence("m2r", p));
            }
        }
    }
    out.push('\n');
    out.push_str(REPAIR_CONTRACT);
    out.push('\n');
    out
}

/// The messages of a repair request: the first prompt, the model's previous reply (the program it
/// wrote, or its text) as the assistant turn, and the repair message.
pub fn repair_messages(
    first: &Prompt,
    previous_reply: &str,
    feedback: &Feedback<'_>,
) -> Vec<Message> {
    let mut messages = first.messages.clone();
    let assistant = if previous_reply.trim().is_empty() {
        "(empty reply)".to_string()
    } else {
        previous_reply.to_string()
    };
    messages.push(Message {
        role: Role::Assistant,
        content: assistant,
    });
    messages.push(Message::user(repair_message(feedback)));
    messages
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lower::catalog::SceneCatalog;

    fn demo_prompt() -> Prompt {
        let map = m2rc_stdlib::demo::demo_map().expect("demo");
        let cat = SceneCatalog::from_map(&map, CatalogMode::Counts);
        Prompt::new(
            &map.map_id,
            &cat,
            "Go to the bed.",
            &PromptOptions::default(),
        )
    }

    #[test]
    fn the_first_prompt_has_every_part_in_order() {
        let p = demo_prompt();
        assert_eq!(p.messages.len(), 2);
        assert_eq!(p.messages[0].role, Role::System);
        let u = &p.messages[1].content;
        let at = |s: &str| u.find(s).unwrap_or_else(|| panic!("missing {s}"));
        assert!(at("# The .m2r language") < at("# Worked examples"));
        assert!(at("# Worked examples") < at("# Scene catalog"));
        assert!(at("# Scene catalog") < at("# Instruction"));
        assert!(at("Go to the bed.") < at("# Output"));
        assert_eq!(u.matches("Instruction: \"").count(), 5);
        assert!(p.estimated_tokens() > 1000);
    }

    #[test]
    fn the_repair_prompt_carries_text_and_json_diagnostics() {
        let vocab = m2rc_stdlib::vocab::Vocabulary::benchmark();
        let src = "route {\n  go area_near(objects(bed))\n}\n";
        let r = crate::check(src, &vocab);
        assert!(r.has_errors());
        let fb = Feedback::Diagnostics {
            program: src,
            diagnostics: &r.diagnostics,
        };
        let msgs = repair_messages(&demo_prompt(), "```m2r\nx\n```", &fb);
        assert_eq!(msgs.len(), 4);
        assert_eq!(msgs[2].role, Role::Assistant);
        let last = &msgs[3].content;
        let code = r.diagnostics[0].code.id();
        assert!(last.contains(&format!("error[{code}]")), "{last}");
        assert!(last.contains(&format!("\"code\": \"{code}\"")), "{last}");
        assert!(last.contains("go area_near(objects(bed))"));
    }
}
