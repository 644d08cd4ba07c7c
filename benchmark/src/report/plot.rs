//! Grouped bar charts of the difficulty analysis, drawn as SVG and rasterized to PNG with resvg
//! (the same route the map renderer takes, so text uses the system fonts when there are any).

use super::difficulty::Factor;
use resvg::{tiny_skia, usvg};
use std::fmt::Write;
use std::sync::{Arc, OnceLock};

const PALETTE: [&str; 6] = [
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b",
];

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The chart of one factor: bins on the x axis, one bar per method, HCS on the y axis (0..1).
pub fn factor_svg(f: &Factor) -> String {
    let (w, h) = (720.0, 420.0);
    let (left, right, top, bottom) = (60.0, 20.0, 50.0, 80.0);
    let plot_w = w - left - right;
    let plot_h = h - top - bottom;
    let groups = f.bins.len().max(1) as f64;
    let methods = f.rows.len().max(1) as f64;
    let group_w = plot_w / groups;
    let bar_w = (group_w * 0.8) / methods;
    let mut s = String::new();
    let _ = write!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="DejaVu Sans, sans-serif"><rect width="{w}" height="{h}" fill="white"/>"#
    );
    let _ = write!(
        s,
        r#"<text x="{}" y="28" font-size="16" text-anchor="middle">Mean HCS by {}</text>"#,
        w / 2.0,
        esc(&f.name.to_lowercase())
    );
    for i in 0..=4 {
        let v = i as f64 / 4.0;
        let y = top + plot_h * (1.0 - v);
        let _ = write!(
            s,
            r##"<line x1="{left}" y1="{y}" x2="{}" y2="{y}" stroke="#dddddd"/><text x="{}" y="{}" font-size="11" text-anchor="end">{v:.2}</text>"##,
            w - right,
            left - 6.0,
            y + 4.0
        );
    }
    for (g, bin) in f.bins.iter().enumerate() {
        let gx = left + group_w * g as f64 + group_w * 0.1;
        for (m, (_, cells)) in f.rows.iter().enumerate() {
            let (n, v) = cells.get(g).copied().unwrap_or((0, None));
            let v = v.unwrap_or(0.0).clamp(0.0, 1.0);
            let bh = plot_h * v;
            let x = gx + bar_w * m as f64;
            let _ = write!(
                s,
                r#"<rect x="{x:.2}" y="{:.2}" width="{:.2}" height="{bh:.2}" fill="{}"><title>n={n}</title></rect>"#,
                top + plot_h - bh,
                bar_w * 0.95,
                PALETTE[m % PALETTE.len()]
            );
        }
        let _ = write!(
            s,
            r#"<text x="{:.2}" y="{}" font-size="12" text-anchor="middle">{}</text>"#,
            left + group_w * (g as f64 + 0.5),
            top + plot_h + 18.0,
            esc(bin)
        );
    }
    let _ = write!(
        s,
        r##"<line x1="{left}" y1="{}" x2="{}" y2="{}" stroke="#333333"/>"##,
        top + plot_h,
        w - right,
        top + plot_h
    );
    for (m, (method, _)) in f.rows.iter().enumerate() {
        let x = left + 140.0 * m as f64;
        let y = h - 24.0;
        let _ = write!(
            s,
            r#"<rect x="{x}" y="{}" width="12" height="12" fill="{}"/><text x="{}" y="{}" font-size="12">{}</text>"#,
            y - 10.0,
            PALETTE[m % PALETTE.len()],
            x + 16.0,
            y,
            esc(method)
        );
    }
    s.push_str("</svg>");
    s
}

fn fonts() -> Arc<usvg::fontdb::Database> {
    static FONTS: OnceLock<Arc<usvg::fontdb::Database>> = OnceLock::new();
    FONTS
        .get_or_init(|| {
            let mut db = usvg::fontdb::Database::new();
            db.load_system_fonts();
            Arc::new(db)
        })
        .clone()
}

/// Rasterizes an SVG document to PNG bytes.
pub fn svg_to_png(svg: &str) -> Result<Vec<u8>, String> {
    let opt = usvg::Options {
        fontdb: fonts(),
        ..usvg::Options::default()
    };
    let tree = usvg::Tree::from_str(svg, &opt).map_err(|e| e.to_string())?;
    let size = tree.size().to_int_size();
    let mut pixmap = tiny_skia::Pixmap::new(size.width(), size.height())
        .ok_or_else(|| "cannot allocate the picture".to_string())?;
    resvg::render(&tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
    pixmap.encode_png().map_err(|e| e.to_string())
}
