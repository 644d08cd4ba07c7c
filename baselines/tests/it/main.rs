//! The baselines crate's integration tests: the shared LLM-call helper against a mock server and
//! through the batch round trip, and each method's pipeline.

mod calls;
mod directid;
mod gold;
mod graphs_mock;
mod grounding;
mod iln_graph;
mod ltlcodegen;
mod methods;
mod osgllm;
mod planners;
mod sayplan_loop;
mod support;
mod toolcall;
