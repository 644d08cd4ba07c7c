//! placeholder
pub mod atomic;
pub mod episode;
pub mod episode_check;
pub mod limits;
pub mod methods;
pub mod metrics;
pub mod pipeline;
pub mod report;
pub mod route;
pub mod rundir;
pub mod runner;
pub mod suite;
