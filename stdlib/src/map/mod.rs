//! The semantic map model and its file formats.

pub mod model;

pub use model::*;
