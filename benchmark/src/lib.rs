//! placeholder
pub mod episode;
