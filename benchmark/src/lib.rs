//! placeholder
pub mod atomic;
pub mod ablate;
pub mod episode;
pub mod episode_check;
pub mod limits;
pub mod methods;
pub mod metrics;
pub mod pipeline;
mod pipeline_ltl;
pub mod report;
pub mod route;
pub mod rundir;
pub mod runner;
pub mod suite;
