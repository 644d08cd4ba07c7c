//! SVG to PNG through resvg, with the system fonts loaded once per process.
//!
//! Text needs a font; without any installed font resvg simply leaves text out, which is the
//! graceful degradation we want (the drawing stays correct, only the words are missing).

use super::RenderError;
use resvg::{tiny_skia, usvg};
use std::sync::{Arc, OnceLock};

/// The font the SVG asks for first; made the generic sans-serif family when installed.
const PREFERRED_FAMILY: &str = "DejaVu Sans";

fn fonts() -> Arc<usvg::fontdb::Database> {
    static FONTS: OnceLock<Arc<usvg::fontdb::Database>> = OnceLock::new();
    FONTS
        .get_or_init(|| {
            let mut db = usvg::fontdb::Database::new();
            db.load_system_fonts();
            let has_preferred = db
                .faces()
                .any(|f| f.families.iter().any(|(name, _)| name == PREFERRED_FAMILY));
            if has_preferred {
                db.set_sans_serif_family(PREFERRED_FAMILY);
            }
            Arc::new(db)
        })
        .clone()
}

/// Rasterizes SVG text at its own pixel size and encodes it as PNG.
pub(super) fn rasterize(svg: &str) -> Result<Vec<u8>, RenderError> {
    let opt = usvg::Options {
        fontdb: fonts(),
        font_family: PREFERRED_FAMILY.to_string(),
        ..usvg::Options::default()
    };
    let tree = usvg::Tree::from_str(svg, &opt).map_err(|e| RenderError::Raster(e.to_string()))?;
    let size = tree.size().to_int_size();
    let mut pixmap = tiny_skia::Pixmap::new(size.width(), size.height()).ok_or_else(|| {
        RenderError::Raster(format!(
            "cannot allocate {}×{} pixels",
            size.width(),
            size.height()
        ))
    })?;
    resvg::render(&tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
    pixmap
        .encode_png()
        .map_err(|e| RenderError::Raster(e.to_string()))
}
