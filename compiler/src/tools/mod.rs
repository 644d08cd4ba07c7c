//! m2rc's read-only semantic queries as function-calling tools: the ToolCall grounding variant
//! (issue 31) and `m2rc tools`, which serves the same set over MCP.
//!
//! A model (or an external agent) grounds an instruction one query at a time. Each query is one
//! built-in of the language (or one of its operators), its arguments are earlier results named by
//! opaque handles, categories, words and literals; each result is stored under a new handle and
//! answered with a short preview. The RouteIR builders (`constraint`, `segment`, `task`) then put
//! the handles together into a route, which is written as an intent graph and compiled by the
//! ordinary compiler. So a tool means exactly what the built-in means in a program:
//!
//! * [`spec`]: the tool list, generated from the built-in table like the Schema variant's
//!   operator list, so it cannot drift from the language.
//! * [`session`]: handles, evaluation (a query is compiled as a one-binding program and grounded
//!   by the compiler's own evaluator), the retry rule and the builders.
//! * [`gold`]: a gold program as the sequence of tool calls that builds it (the `--llm gold`
//!   ceiling of the representation).
//!
//! Pure, like the rest of the compiler core: no file, network or environment access.

pub mod gold;
mod preview;
pub mod session;
pub mod spec;

#[cfg(test)]
mod tests;

pub use gold::{GoldArg, GoldCall, gold_calls};
pub use session::{Finished, Limits, ToolOutcome, ToolSession};
pub use spec::{ToolKind, ToolSpec, mcp_tools, openai_tools, tool_specs};

/// The builder that ends a conversation: its route is the answer.
pub const TASK_TOOL: &str = "task";
