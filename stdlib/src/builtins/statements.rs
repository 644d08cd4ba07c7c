//! The route statements that take a place (`go`, `pass`, `avoid`): what each accepts and what each
//! form means. One table feeds the checker (the accepted operand types), the generated language
//! reference and the LLM prompt, so a form the checker accepts is a form the model is told about.

use super::signature::Ty;

const PLACES: &[Ty] = &[Ty::PLACE, Ty::SET_PLACE];

/// One form of a statement: the operand as written, its meaning, an example.
pub struct Form {
    pub operand: &'static str,
    pub doc: &'static str,
    pub example: &'static str,
}

pub struct Statement {
    pub keyword: &'static str,
    /// The operand types the checker accepts, every form.
    pub operand: &'static [Ty],
    pub forms: &'static [Form],
}

impl Statement {
    /// `go <Set<Place>>` for form `i`.
    pub fn form_line(&self, f: &Form) -> String {
        format!("{} <{}>", self.keyword, f.operand)
    }
}

pub const STATEMENTS: &[Statement] = &[
    Statement {
        keyword: "go",
        operand: PLACES,
        forms: &[
            Form {
                operand: "Place",
                doc: "A stage: head to this place.",
                example: "go objects(bed).nearest()",
            },
            Form {
                operand: "Set<Place>",
                doc: "A stage to any one of the places, whichever the planned route reaches at least cost (\"go to a box\", \"any toilet\"); for \"the box\", choose one instead.",
                example: "go objects(box).in(bedroom)",
            },
        ],
    },
    Statement {
        keyword: "pass",
        operand: PLACES,
        forms: &[
            Form {
                operand: "Place",
                doc: "Inside a stage: the route must go through this place before the destination.",
                example: "pass kitchen",
            },
            Form {
                operand: "Set<Place>",
                doc: "Inside a stage: the route must go through any one of the places before the destination.",
                example: "pass kitchen.doorways()",
            },
        ],
    },
    Statement {
        keyword: "avoid",
        operand: PLACES,
        forms: &[Form {
            operand: "Place | Set<Place>",
            doc: "The route never enters it (every one of the places, for a set).",
            example: "avoid objects(rug)",
        }],
    },
];

/// The row of a statement keyword.
pub fn statement(keyword: &str) -> Option<&'static Statement> {
    STATEMENTS.iter().find(|s| s.keyword == keyword)
}

/// The operand types `keyword` accepts (none for an unknown keyword).
pub fn operand(keyword: &str) -> &'static [Ty] {
    statement(keyword).map_or(&[], |s| s.operand)
}
