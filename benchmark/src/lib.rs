//! placeholder
pub mod episode;
pub mod methods;
pub mod metrics;
pub mod pipeline;
pub mod report;
pub mod route;
pub mod runner;
pub mod suite;
