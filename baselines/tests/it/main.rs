//! The baselines crate's integration tests: the shared LLM-call helper against a mock server and
//! through the batch round trip, and each method's pipeline.

mod calls;
mod gold;
mod grounding;
mod methods;
mod planners;
mod support;
