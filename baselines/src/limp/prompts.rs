//! LIMP's prompts, in our words after the adaptation's: stage 1 writes plain LTL over concrete
//! nouns, stage 2 rewrites it with `near[...]` navigation predicates whose arguments are composable
//! referent descriptors, and one repair resends stage 2 with the validation error. The model sees
//! no map information.

use m2rc_compiler::lower::Message;

const STAGE1: &str = "\
You translate navigation instructions for a mobile robot into concise linear temporal logic, \
using the operators F (eventually), G (always), X (next), U (until), & (and), | (or), ! (not) and \
parentheses, over the concrete nouns of the instruction as propositions.
Keep every waypoint the robot must visit, in the order it must visit them, and every place it \
must never enter. Do not encode optional preferences (\"try to\", \"prefer\", \"stay closer to\", \
\"keep farther from\", \"if possible\").
Examples:
Input: Visit the sofa, then the sink. Output: F ( sofa & F sink )
Input: Go to the sink and avoid the sofa. Output: G ( !sofa ) & F sink
Input: Go to the bed, then to the lamp, never enter the kitchen. Output: F ( bed & F lamp ) & G ( !kitchen )
Input: Reach the fridge; try to stay close to the table on the way. Output: F fridge
Input: Go to the chair between the sofa and the table. Output: F chair
Input: Go to the toilet in the bathroom, then the bed. Output: F ( toilet & F bed )
Return only the formula.";

/// The stage-1 request.
pub fn stage1(instruction: &str) -> Vec<Message> {
    vec![
        Message::system(STAGE1),
        Message::user(format!("Input: {instruction}\nOutput:")),
    ]
}

const STAGE2: &str = "\
You rewrite a robot's navigation formula with lifted predicates. The only robot predicate is \
near[referent]: be near the referent. Do not use pick, release or any other robot predicate.
A referent is a concrete noun from the instruction, optionally refined by one spatial predicate \
in the form noun::predicate(argument, ...), where the predicate is one of isbetween, isabove, \
isbelow, isleftof, isrightof, isnextto, isinfrontof, isbehind, isinside, contains, and the \
arguments are nouns.
Rules: use the nouns of the instruction; keep every mandatory waypoint, in order; encode only \
mandatory constraints; keep the operators F G X U & | ! and parentheses.
Examples:
F ( chair & F sink ) -> F ( near[chair] & F near[sink] )
Go to the chair between the sofa and the table -> F near[chair::isbetween(sofa,table)]
G ( !sofa ) & F sink -> G ( !near[sofa] ) & F near[sink]
Go to the bed in the bedroom -> F near[bed::isinside(bedroom)]
Return only the formula.";

fn stage2_user(instruction: &str, ltl: &str) -> String {
    format!("Input_instruction: {instruction}\nInput_ltl: {ltl}\nOutput:")
}

/// The stage-2 request.
pub fn stage2(instruction: &str, ltl: &str) -> Vec<Message> {
    vec![
        Message::system(STAGE2),
        Message::user(stage2_user(instruction, ltl)),
    ]
}

/// The one repair: stage 2 again, with the invalid output and why it is invalid.
pub fn repair(instruction: &str, ltl: &str, bad: &str, error: &str) -> Vec<Message> {
    vec![
        Message::system(STAGE2),
        Message::user(format!(
            "{}\nYour previous output `{bad}` is invalid: {error}. Write the formula again, every \
             proposition as a complete near[...] predicate.",
            stage2_user(instruction, ltl)
        )),
    ]
}
