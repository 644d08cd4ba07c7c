//! Pictures of semantic maps: a floor plan with rooms tinted by type, walls, doorways, windows,
//! furniture footprints, the start pose, a legend and a scale bar, with routes, regions and stage
//! markers drawn on top.
//!
//! The SVG is the primary output and is written as text, deterministically, so that a picture can be
//! diffed and snapshot-tested; the PNG is that SVG rasterized by resvg, so both always show the same
//! thing. Cell layers are drawn as outlines of merged cell sets ([`outline`]), which keeps the SVG
//! of a 700×700 map small.

mod layers;
mod legend;
mod outline;
mod overlay;
mod raster;
mod style;
mod svg;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_explain;

pub use overlay::{Overlay, RegionKind};
pub use style::Rgb;

use crate::grid::Cell;
use crate::map::SemanticMap;
use std::fmt::Write;

/// How to draw a map.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    /// Write the category of each piece of furniture at its centre (where there is room for it).
    pub labels: bool,
    /// Pixels per grid cell. `0` (the default) picks a scale from the map size so that the picture
    /// is about 1400 pixels across.
    pub scale: f64,
    /// Layers drawn on top of the map, in order.
    pub overlays: Vec<Overlay>,
    /// Heading above the picture; `None` uses the map id, `Some("")` draws no heading.
    pub title: Option<String>,
    /// Paragraphs under the heading (an episode's instruction, its scores), wrapped to the
    /// picture's width; they never widen it.
    pub caption: Vec<String>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            labels: false,
            scale: 0.0,
            overlays: Vec::new(),
            title: None,
            caption: Vec::new(),
        }
    }
}

/// The rendered picture in both formats.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOutput {
    pub svg: String,
    pub png: Vec<u8>,
}

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error("render scale must be a finite number of pixels per cell, got {0}")]
    InvalidScale(f64),
    #[error(
        "picture would be {width}×{height} pixels (limit {MAX_SIDE} per side); pass a smaller scale"
    )]
    TooLarge { width: u64, height: u64 },
    #[error("overlay {index}: cell [{}, {}] lies outside the {n}×{n} map", cell.row, cell.col)]
    OverlayOutOfMap { index: usize, cell: Cell, n: usize },
    #[error("rasterizing the SVG failed: {0}")]
    Raster(String),
}

/// Longest side, in pixels, of a picture; beyond this tiny-skia allocations get unreasonable.
pub const MAX_SIDE: u64 = 16_384;

/// Font size and line height of the caption under the title.
const CAPTION_SIZE: f64 = 13.0;
const CAPTION_LINE: f64 = 18.0;

/// Target width of the map area when the scale is automatic.
const AUTO_TARGET_PX: f64 = 1400.0;

/// Renders `map` to SVG and PNG.
pub fn render_map(map: &SemanticMap, opts: &RenderOptions) -> Result<RenderOutput, RenderError> {
    let svg = render_svg(map, opts)?;
    let png = raster::rasterize(&svg)?;
    Ok(RenderOutput { svg, png })
}

/// Renders `map` to SVG only (no rasterization; cheaper when only the vector picture is wanted).
pub fn render_svg(map: &SemanticMap, opts: &RenderOptions) -> Result<String, RenderError> {
    if !opts.scale.is_finite() {
        return Err(RenderError::InvalidScale(opts.scale));
    }
    let n = map.n();
    for (index, ov) in opts.overlays.iter().enumerate() {
        if let Some(&cell) = ov
            .cells()
            .find(|c| c.row as usize >= n || c.col as usize >= n)
        {
            return Err(RenderError::OverlayOutOfMap { index, cell, n });
        }
    }

    let crop = crop_window(map, opts);
    let extent = crop.rows.max(crop.cols).max(1) as f64;
    let s = if opts.scale > 0.0 {
        opts.scale
    } else {
        // Two decimals keep the SVG numbers short; the cell layers are drawn crisp, so a
        // fractional scale leaves no seams.
        ((AUTO_TARGET_PX / extent) * 100.0)
            .floor()
            .clamp(100.0, 4000.0)
            / 100.0
    };

    let title = match &opts.title {
        Some(t) => t.clone(),
        None => map.map_id.clone(),
    };
    let legend = legend::Legend::build(map, opts);
    let margin = 16.0;
    let map_w = (crop.cols as f64 * s).max(if n == 0 { 240.0 } else { 0.0 });
    let map_h = (crop.rows as f64 * s).max(if n == 0 { 160.0 } else { 0.0 });
    let scalebar_h = 40.0;
    let legend_x = margin + map_w + 20.0;
    let width = (legend_x + legend.width() + margin).ceil();
    let caption: Vec<String> = opts
        .caption
        .iter()
        .flat_map(|p| svg::wrap(p, width - 2.0 * margin, CAPTION_SIZE))
        .collect();
    let caption_h = caption.len() as f64 * CAPTION_LINE;
    let title_h = if title.is_empty() { 0.0 } else { 52.0 }
        + caption_h
        + if caption.is_empty() { 0.0 } else { 8.0 };
    let height = (margin + title_h + (map_h + scalebar_h).max(legend.height()) + margin).ceil();
    if width as u64 > MAX_SIDE || height as u64 > MAX_SIDE {
        return Err(RenderError::TooLarge {
            width: width as u64,
            height: height as u64,
        });
    }

    let view = View {
        s,
        r0: crop.r0,
        c0: crop.c0,
        ox: margin,
        oy: margin + title_h,
        w: map_w,
        h: map_h,
    };

    let mut out = String::with_capacity(64 * 1024);
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" font-family=\"{}\">",
        svg::FONT,
        w = svg::num(width),
        h = svg::num(height),
    );
    let _ = writeln!(
        out,
        "<rect width=\"100%\" height=\"100%\" fill=\"{}\"/>",
        style::BACKGROUND
    );
    if !title.is_empty() {
        let st = svg::TextStyle {
            size: 18.0,
            fill: style::TEXT,
            bold: true,
            anchor: svg::Anchor::Start,
            halo: false,
        };
        svg::text(&mut out, margin, margin + 18.0, &title, st);
        let facts = summary(map);
        let st = svg::TextStyle {
            size: 12.0,
            fill: style::TEXT_MUTED,
            bold: false,
            ..st
        };
        svg::text(&mut out, margin, margin + 37.0, &facts, st);
    }
    let caption_top = margin + if title.is_empty() { 0.0 } else { 52.0 };
    for (i, line) in caption.iter().enumerate() {
        let st = svg::TextStyle {
            size: CAPTION_SIZE,
            fill: style::TEXT,
            bold: false,
            anchor: svg::Anchor::Start,
            halo: false,
        };
        let y = caption_top + (i as f64 + 1.0) * CAPTION_LINE - 4.0;
        svg::text(&mut out, margin, y, line, st);
    }
    if n == 0 {
        let _ = writeln!(
            out,
            "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"{}\" stroke=\"#999999\"/>",
            svg::num(view.ox),
            svg::num(view.oy),
            svg::num(map_w),
            svg::num(map_h),
            style::OUTSIDE
        );
        let st = svg::TextStyle {
            size: 14.0,
            fill: style::TEXT_MUTED,
            bold: false,
            anchor: svg::Anchor::Middle,
            halo: false,
        };
        svg::text(
            &mut out,
            view.ox + map_w / 2.0,
            view.oy + map_h / 2.0,
            "empty map",
            st,
        );
    } else {
        // Lines first, then every label, then the markers: no label is ever drawn under a route,
        // and no marker under a label.
        let mut base = layers::draw_base(&mut out, map, &crop, &view, opts.labels);
        let markers = overlay::draw_overlays(&mut out, &opts.overlays, &view, &mut base.placed);
        out.push_str(&base.labels);
        out.push_str(&markers);
        legend::draw_scale_bar(
            &mut out,
            map.resolution(),
            s,
            view.ox,
            view.oy + map_h + 14.0,
        );
    }
    legend.draw(&mut out, legend_x, margin + title_h);
    out.push_str("</svg>\n");
    Ok(out)
}

/// One line of facts beside the title: grid size, resolution, rooms, objects.
fn summary(map: &SemanticMap) -> String {
    let n = map.n();
    let res = map.resolution();
    let mut s = format!("{n}×{n} cells");
    if res.is_finite() && res > 0.0 {
        let _ = write!(s, " · {} m/cell", res);
    }
    let _ = write!(
        s,
        " · {} rooms · {} objects",
        map.rooms.len(),
        map.objects.len()
    );
    s
}

/// The part of the grid that is drawn: the house plus a small margin, not the padding that makes
/// Map2Route grids square.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Crop {
    pub r0: i64,
    pub c0: i64,
    pub rows: i64,
    pub cols: i64,
}

fn crop_window(map: &SemanticMap, opts: &RenderOptions) -> Crop {
    let n = map.n() as i64;
    let mut bb: Option<(i64, i64, i64, i64)> = None;
    let mut add = |r: i64, c: i64| {
        if r < 0 || c < 0 || r >= n || c >= n {
            return;
        }
        bb = Some(match bb {
            None => (r, c, r, c),
            Some((a, b, x, y)) => (a.min(r), b.min(c), x.max(r), y.max(c)),
        });
    };
    for (cell, &occ) in map.occupancy.iter_cells() {
        let room = map.room_layer.get(cell).copied().unwrap_or(0);
        let obj = map.object_layer.get(cell).copied().unwrap_or(0);
        if occ == crate::map::FREE || room != 0 || obj != 0 {
            add(cell.row as i64, cell.col as i64);
        }
    }
    for o in &map.objects {
        for c in &o.footprint {
            add(c.row as i64, c.col as i64);
        }
    }
    if let Some(c) = map.start {
        add(c.row as i64, c.col as i64);
    }
    for ov in &opts.overlays {
        for c in ov.cells() {
            add(c.row as i64, c.col as i64);
        }
    }
    let Some((r0, c0, r1, c1)) = bb else {
        return Crop {
            r0: 0,
            c0: 0,
            rows: n,
            cols: n,
        };
    };
    let pad = (((r1 - r0).max(c1 - c0) as f64) * 0.03).ceil().max(2.0) as i64;
    let (r0, c0) = ((r0 - pad).max(0), (c0 - pad).max(0));
    let (r1, c1) = ((r1 + pad).min(n - 1), (c1 + pad).min(n - 1));
    Crop {
        r0,
        c0,
        rows: r1 - r0 + 1,
        cols: c1 - c0 + 1,
    }
}

/// Where cells land on the canvas.
#[derive(Clone, Copy, Debug)]
pub(crate) struct View {
    /// Pixels per cell.
    pub s: f64,
    pub r0: i64,
    pub c0: i64,
    /// Canvas position of the crop's top-left corner.
    pub ox: f64,
    pub oy: f64,
    /// Size of the map area on the canvas, pixels.
    pub w: f64,
    pub h: f64,
}

impl View {
    /// Canvas position of a lattice corner `(x = col, y = row)`.
    pub fn corner(&self, p: outline::Pt) -> (f64, f64) {
        (
            self.ox + (p.0 - self.c0) as f64 * self.s,
            self.oy + (p.1 - self.r0) as f64 * self.s,
        )
    }

    /// Canvas position of a point given in cell units (`row`, `col` of a cell centre).
    pub fn point(&self, row: f64, col: f64) -> (f64, f64) {
        (
            self.ox + (col - self.c0 as f64 + 0.5) * self.s,
            self.oy + (row - self.r0 as f64 + 0.5) * self.s,
        )
    }

    pub fn center(&self, c: Cell) -> (f64, f64) {
        self.point(c.row as f64, c.col as f64)
    }

    /// The centre nearest `(cx, cy)` at which a `w`×`h` label lies wholly inside the map area, so
    /// that no label is cut off at the picture's edge or runs into the legend (a label wider than
    /// the map starts at its left edge).
    pub fn keep_inside(&self, cx: f64, cy: f64, w: f64, h: f64) -> (f64, f64) {
        let fit = |c: f64, size: f64, lo: f64, span: f64| {
            if size >= span {
                // Wider than the map: start at its edge, so the text runs on into the margin
                // rather than off the picture.
                lo + size / 2.0
            } else {
                c.clamp(lo + size / 2.0, lo + span - size / 2.0)
            }
        };
        (fit(cx, w, self.ox, self.w), fit(cy, h, self.oy, self.h))
    }
}
