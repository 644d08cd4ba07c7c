//! The semantic map model and its file formats.

pub mod error;
pub mod format;
pub mod frame;
pub mod legend;
pub mod model;
mod open;
pub mod prepared;
pub mod pyjson;
pub mod vocab;
mod write;

pub use error::MapError;
pub use format::{read_map_document, read_map_document_json, read_map_json, read_map_value};
pub use model::*;
pub use write::{
    write_map_document, write_map_document_json, write_map_document_to, write_map_json,
    write_map_value,
};
