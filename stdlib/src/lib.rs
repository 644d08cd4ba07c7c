//! The semantic map model, geometry and distance fields, map formats and importers, rendering, and
//! the table of the `.m2r` language's built-in functions with their type signatures.

pub mod builtins;
pub mod demo;
pub mod export;
pub mod field;
pub mod grid;
pub mod import;
pub mod load;
pub mod map;
pub mod query;
pub mod render;
pub mod vocab;
