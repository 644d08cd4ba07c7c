//! Lang2LTL's two prompts, in our words after the adaptation's: the referring-expression
//! recogniser, and the LLM translation of the lifted command (the mode both authors offer in
//! place of the fine-tuned T5, which cannot be fetched here), with its repair message.

use m2rc_compiler::lower::Message;

const RER_SYSTEM: &str = "\
You are the referring-expression recogniser of Lang2LTL, a system that turns navigation commands \
for a mobile robot into temporal logic.
From the command, copy out every noun phrase that names a place the robot has to reach or has to \
keep out of: rooms, objects, regions or landmarks. Copy each phrase exactly as it is written, and \
list them in the order they appear.
Do not list bare relation or order words (left, right, near, before, after, then), and do not \
list phrases about where the robot starts (\"the start\", \"where you are\", \"beside you\").
Answer with JSON only, of the form {\"referring_expressions\": [\"...\", \"...\"]}.";

/// The recogniser's request for `instruction`.
pub fn rer(instruction: &str) -> Vec<Message> {
    vec![Message::system(RER_SYSTEM), Message::user(instruction)]
}

const TRANSLATE_SYSTEM: &str = "\
You translate navigation commands for a mobile robot into linear temporal logic. In each command \
every landmark has been replaced by a single lower-case letter.
Write one formula in prefix (Polish) notation over those letters only. Operators: ! (not), \
& (and), | (or), F (eventually), G (always), X (next), U (until), i (implies), e (if and only \
if). Separate every token by a space; do not use parentheses.
Encode only what the robot must do and must never do. Leave out preferences (staying close to or \
away from something, \"try to\", \"if possible\"); they are not part of the formula.
Examples:
go to a -> F a
go to a, and after that b -> F & a F b
reach b, but not before a -> & U ! b a F b
never enter a -> G ! a
go to a and never enter b -> & F a G ! b
go to a or b -> | F a F b
Answer with the formula only.";

fn translate_user(letters: &[String], lifted: &str) -> String {
    format!("Letters: {}\nCommand: {lifted}", letters.join(", "))
}

/// The translation request for the lifted command.
pub fn translate(letters: &[String], lifted: &str) -> Vec<Message> {
    vec![
        Message::system(TRANSLATE_SYSTEM),
        Message::user(translate_user(letters, lifted)),
    ]
}

/// The repair request after a reply the parser could not read.
pub fn repair(letters: &[String], lifted: &str, bad: &str, error: &str) -> Vec<Message> {
    vec![
        Message::system(TRANSLATE_SYSTEM),
        Message::user(format!(
            "{}\nYour previous answer was `{bad}`, which is not a formula: {error}.\nAnswer with \
             one complete prefix formula over the allowed letters ({}), and nothing else.",
            translate_user(letters, lifted),
            letters.join(", ")
        )),
    ]
}
