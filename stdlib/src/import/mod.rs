//! Importers that build semantic maps from other sources: ProcTHOR house JSON (with or without
//! the asset database), one file or one line of a `.jsonl.gz`.

pub mod assets;
pub mod bounds;
pub mod check;
pub mod house;
pub mod naming;
pub mod nav2;
mod placement;
pub mod procthor;
pub mod raster;
pub mod sizes;
mod walls;

pub use assets::AssetDb;
pub use procthor::{
    DEFAULT_PADDING_M, DEFAULT_RESOLUTION_M, DEFAULT_ROBOT_RADIUS_M, ImportOptions, import_house,
    import_house_document, import_warnings,
};
