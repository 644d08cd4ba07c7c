//! The built-in demo house, so every m2rc command runs on a fresh machine with `--map demo`.
//!
//! A 12 x 10 m, seven-room house written for this project (`demo/house.json`): a living room with
//! the entrance, a kitchen, three bedrooms and two bathrooms, joined by doorways and doorframes,
//! with windows and furniture carrying items on and inside them (a mug in the microwave, eggs in
//! the fridge, an apple in a bowl on the dining table). The description is a ProcTHOR-style house
//! without walls and with explicit `objectType`s; it goes through the same importer as real
//! houses, using the built-in size table.

use crate::import::{ImportOptions, import_house_document};
use crate::map::{MapDocument, MapError, SemanticMap};

/// The demo house description (ProcTHOR house JSON, m2rc dialect).
pub const DEMO_HOUSE_JSON: &str = include_str!("demo/house.json");

/// The name that stands for the demo map wherever a map path is accepted.
pub const DEMO_NAME: &str = "demo";

/// Builds the demo map with the default import options.
pub fn demo_map() -> Result<SemanticMap, MapError> {
    demo_map_with(&ImportOptions::default())
}

/// Builds the demo map at another resolution or robot radius.
pub fn demo_map_with(opts: &ImportOptions) -> Result<SemanticMap, MapError> {
    demo_document(opts).map(|d| d.map)
}

/// The demo map with the metadata written beside it.
pub fn demo_document(opts: &ImportOptions) -> Result<MapDocument, MapError> {
    let doc: serde_json::Value = serde_json::from_str(DEMO_HOUSE_JSON).map_err(|e| {
        MapError::new(
            DEMO_NAME,
            "",
            format!("built-in demo house is not valid JSON: {e}"),
        )
    })?;
    let mut opts = opts.clone();
    opts.map_id = Some(opts.map_id.unwrap_or_else(|| DEMO_NAME.to_string()));
    let mut map = import_house_document(&doc, DEMO_NAME, None, &opts)?;
    map.extra
        .metadata
        .insert("name".into(), serde_json::json!("m2rc demo house"));
    map.extra.metadata.insert(
        "description".into(),
        serde_json::json!(
            "Built-in 12 x 10 m demo house: living room, kitchen, three bedrooms, two bathrooms"
        ),
    );
    map.extra
        .metadata
        .insert("source".into(), serde_json::json!("m2rc_demo"));
    Ok(map)
}
