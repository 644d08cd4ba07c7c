//! The intent graph: the Schema grounding variant's representation. A model writes a typed JSON
//! graph of operators instead of a program; m2rc compiles it deterministically to `.m2r` and from
//! there through the ordinary compiler, so the graph and the language can never disagree on what
//! an operator means.
//!
//! * [`ops`]: the operator list, its JSON Schema and the model's operator reference, all
//!   generated from the built-in table.
//! * [`to_program`]: graph -> `.m2r`, with a source map from program spans to JSON pointers.
//! * [`from_program`]: `.m2r` -> graph (gold graphs, suggestions as patches).
//! * [`feedback`]: compiler diagnostics as [`GraphDiagnostic`]s that point into the graph, so the
//!   repair loop can run on it.
//!
//! Pure, like the rest of the compiler core: no file, network or environment access.

pub mod feedback;
pub mod from_program;
pub mod ops;
pub mod prompt;
pub mod repair;
pub mod to_program;

#[cfg(test)]
mod tests;

pub use feedback::{apply_fixes, graph_feedback, reply_json};
pub use from_program::{FromProgramError, expr_to_graph, program_to_graph};
pub use prompt::{json_repair_messages, schema_prompt};
pub use repair::{JsonVerdict, run_json_episode};
pub use to_program::{Compiled, graph_to_program};

use crate::diagnostic::{Code, Diagnostic};
use m2rc_grammar::ast::Span;
use serde_json::{Value, json};

/// A diagnostic about a JSON reply (an intent graph or a catalog-id grounding): where in the JSON
/// it is (a JSON pointer, RFC 6901; `""` is the whole document) and, when the fix is certain,
/// the JSON patch operation that makes it.
#[derive(Clone, Debug, PartialEq)]
pub struct GraphDiagnostic {
    pub diagnostic: Diagnostic,
    pub pointer: String,
    /// `{"op": "replace", "path": ..., "value": ...}` (RFC 6902), or `{"op": "append_text",
    /// "text": ...}` for a reply whose JSON is cut short.
    pub patch: Option<Value>,
}

impl GraphDiagnostic {
    pub fn new(
        code: Code,
        pointer: &str,
        message: impl Into<String>,
        help: Option<String>,
    ) -> Self {
        let mut diagnostic = Diagnostic::new(code, Span::default(), message);
        diagnostic.help = help;
        GraphDiagnostic {
            diagnostic,
            pointer: pointer.to_string(),
            patch: None,
        }
    }

    /// The form the model reads (and the records keep).
    pub fn to_json(&self) -> Value {
        let d = &self.diagnostic;
        let mut v = json!({
            "code": d.code.id(),
            "severity": d.severity,
            "message": d.message,
            "pointer": self.pointer,
        });
        if let Some(h) = &d.help {
            v["help"] = json!(h);
        }
        if !d.notes.is_empty() {
            v["notes"] = json!(d.notes);
        }
        if let Some(p) = &self.patch {
            v["fix"] = p.clone();
        }
        v
    }

    pub fn is_error(&self) -> bool {
        self.diagnostic.is_error()
    }
}
