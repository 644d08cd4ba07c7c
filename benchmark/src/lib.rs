//! placeholder
pub mod ablate;
pub mod episode;
pub mod methods;
pub mod metrics;
pub mod pipeline;
mod pipeline_ltl;
pub mod report;
pub mod route;
pub mod runner;
pub mod suite;
