//! The Map2Route benchmark: episodes, the reference metrics, suite generation, methods, the resumable runner, reports and ablations.
pub mod ablate;
pub mod atomic;
pub mod budget;
pub mod episode;
pub mod episode_check;
pub mod import;
pub mod limits;
pub mod methods;
pub mod metrics;
pub mod pipeline;
mod pipeline_ltl;
pub mod plan_failure;
pub mod report;
pub mod route;
pub mod route_read;
pub mod rundir;
pub mod runner;
pub mod suite;
