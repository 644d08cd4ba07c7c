//! The ProcTHOR asset database (`asset-database.json`): `{objectType: [{assetId, boundingBox,
//! objectType, ...}]}`. Only the object type and the bounding box of each asset are kept.

use crate::map::error::MapError;
use serde_json::Value;
use std::collections::HashMap;
use std::path::Path;

#[derive(Clone, Debug, PartialEq)]
pub struct AssetInfo {
    pub object_type: String,
    /// Bounding box `(x, y, z)` in metres, in the asset's own frame.
    pub size: [f64; 3],
}

/// Asset id -> type and size.
#[derive(Clone, Debug, Default)]
pub struct AssetDb {
    assets: HashMap<String, AssetInfo>,
}

impl AssetDb {
    pub fn get(&self, asset_id: &str) -> Option<&AssetInfo> {
        self.assets.get(asset_id)
    }

    pub fn len(&self) -> usize {
        self.assets.len()
    }

    pub fn is_empty(&self) -> bool {
        self.assets.is_empty()
    }

    pub fn load(path: &Path) -> Result<AssetDb, MapError> {
        let file = path.display().to_string();
        let bytes = std::fs::read(path)
            .map_err(|e| MapError::new(&file, "", format!("cannot read: {e}")))?;
        let v: Value = serde_json::from_slice(&bytes)
            .map_err(|e| MapError::new(&file, "", format!("not valid JSON: {e}")))?;
        AssetDb::from_value(&v, &file)
    }

    pub fn from_value(v: &Value, file: &str) -> Result<AssetDb, MapError> {
        let err = |path: String, msg: &str| MapError::new(file, path, msg);
        let root = v
            .as_object()
            .ok_or_else(|| err(String::new(), "expected an object of object types"))?;
        let mut assets = HashMap::new();
        for (ty, list) in root {
            let list = list
                .as_array()
                .ok_or_else(|| err(ty.clone(), "expected an array of assets"))?;
            for (i, a) in list.iter().enumerate() {
                let path = format!("{ty}[{i}]");
                let id = a
                    .get("assetId")
                    .and_then(Value::as_str)
                    .ok_or_else(|| err(format!("{path}.assetId"), "missing or not a string"))?;
                let bb = a
                    .get("boundingBox")
                    .ok_or_else(|| err(format!("{path}.boundingBox"), "missing required key"))?;
                let mut size = [0.0; 3];
                for (k, axis) in ["x", "y", "z"].iter().enumerate() {
                    size[k] = bb
                        .get(axis)
                        .and_then(Value::as_f64)
                        .filter(|x| x.is_finite() && *x >= 0.0)
                        .ok_or_else(|| {
                            err(
                                format!("{path}.boundingBox.{axis}"),
                                "expected a finite non-negative number",
                            )
                        })?;
                }
                let object_type = a
                    .get("objectType")
                    .and_then(Value::as_str)
                    .unwrap_or(ty)
                    .to_string();
                assets.insert(id.to_string(), AssetInfo { object_type, size });
            }
        }
        Ok(AssetDb { assets })
    }
}
