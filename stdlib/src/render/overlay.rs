//! Layers drawn on top of a map: routes, regions (destinations, avoid zones, scopes, ...) and
//! numbered stage markers. Regions are drawn first (translucent), then routes, then markers, so
//! the most specific information is always on top whatever order the caller lists them in.

use super::View;
use super::layers::{self, LabelBox};
use super::outline;
use super::style::{self, Rgb};
use super::svg::{self, Anchor, TextStyle, num};
use crate::grid::Cell;
use std::fmt::Write;

/// Something drawn on top of the map.
#[derive(Clone, Debug, PartialEq)]
pub enum Overlay {
    /// A route as a polyline through cell centres, with an arrowhead at its end. Without a colour,
    /// routes take the next colour of the route palette.
    Route {
        cells: Vec<Cell>,
        label: Option<String>,
        color: Option<Rgb>,
    },
    /// A multi-stage route, each stage in its own palette colour, with a dot where a stage ends.
    StagedRoute {
        stages: Vec<Vec<Cell>>,
        label: Option<String>,
    },
    /// A set of cells drawn as a translucent area with its merged outline.
    Region {
        cells: Vec<Cell>,
        kind: RegionKind,
        label: Option<String>,
    },
    /// A numbered (or otherwise labelled) point, e.g. a stage destination.
    Marker { cell: Cell, label: String },
    /// A route a score is measured against (the path-shape reference of nDTW): a thin dashed
    /// dark line, so it reads as a yardstick and not as a route driven.
    Reference {
        cells: Vec<Cell>,
        label: Option<String>,
    },
}

/// What a region means, which decides how it is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum RegionKind {
    Destination,
    Avoid,
    Pass,
    Scope,
    PreferenceRef,
    /// A doorway an avoid region closes, where a failed plan is cut off.
    Blocked,
}

impl RegionKind {
    pub fn name(self) -> &'static str {
        match self {
            RegionKind::Destination => "destination",
            RegionKind::Avoid => "avoid",
            RegionKind::Pass => "pass through",
            RegionKind::Scope => "scope",
            RegionKind::PreferenceRef => "preference reference",
            RegionKind::Blocked => "blocked doorway",
        }
    }

    /// Colour, fill opacity and stroke dash pattern.
    pub(super) fn look(self) -> (Rgb, f64, Option<&'static str>) {
        match self {
            RegionKind::Destination => (Rgb(0x14, 0x9e, 0x8c), 0.35, None),
            RegionKind::Avoid => (Rgb(0xd6, 0x28, 0x28), 0.22, Some("6 4")),
            RegionKind::Pass => (Rgb(0x1d, 0x4e, 0xd8), 0.22, None),
            RegionKind::Scope => (Rgb(0x7b, 0x2c, 0xbf), 0.08, Some("10 5")),
            RegionKind::PreferenceRef => (Rgb(0xf7, 0x7f, 0x00), 0.25, Some("2 3")),
            RegionKind::Blocked => (Rgb(0x8b, 0x00, 0x00), 0.75, None),
        }
    }
}

impl Overlay {
    /// Every cell the overlay refers to.
    pub fn cells(&self) -> Box<dyn Iterator<Item = &Cell> + '_> {
        match self {
            Overlay::Route { cells, .. }
            | Overlay::Region { cells, .. }
            | Overlay::Reference { cells, .. } => Box::new(cells.iter()),
            Overlay::StagedRoute { stages, .. } => Box::new(stages.iter().flatten()),
            Overlay::Marker { cell, .. } => Box::new(std::iter::once(cell)),
        }
    }
}

/// The colours of each overlay's lines, in overlay order: a `Route` gets its own colour or the
/// next palette entry, each stage of a `StagedRoute` the next palette entry, so no two lines
/// share a colour by accident. Shared with the legend so both agree.
pub(super) fn line_colors(overlays: &[Overlay]) -> Vec<Vec<Rgb>> {
    let mut k = 0;
    let mut next = || {
        let c = style::ROUTE_PALETTE[k % style::ROUTE_PALETTE.len()];
        k += 1;
        c
    };
    overlays
        .iter()
        .map(|ov| match ov {
            Overlay::Route { color, .. } => vec![color.unwrap_or_else(&mut next)],
            Overlay::StagedRoute { stages, .. } => stages.iter().map(|_| next()).collect(),
            _ => Vec::new(),
        })
        .collect()
}

/// Draws the overlays' lines and labels into `out`; returns their markers, which go on top of
/// everything else.
pub(super) fn draw_overlays(
    out: &mut String,
    overlays: &[Overlay],
    view: &View,
    placed: &mut Vec<LabelBox>,
) -> String {
    if overlays.is_empty() {
        return String::new();
    }
    out.push_str("<g id=\"overlays\">\n");
    // Region and route labels go on top of every line, under the markers.
    let mut texts = String::new();
    // Markers are drawn last; reserve their spots so that labels do not hide under them.
    for ov in overlays {
        if let Overlay::Marker { cell, .. } = ov {
            let (x, y) = view.center(*cell);
            placed.push(LabelBox::around(x, y, 22.0, 22.0));
        }
    }
    for ov in overlays {
        if let Overlay::Region { cells, kind, label } = ov {
            draw_region(
                out,
                &mut texts,
                cells,
                *kind,
                label.as_deref(),
                view,
                placed,
            );
        }
    }
    let colors = line_colors(overlays);
    for (ov, color) in overlays.iter().zip(&colors) {
        match ov {
            Overlay::Route { cells, label, .. } => {
                let c = color.first().copied().unwrap_or(style::ROUTE_PALETTE[0]);
                draw_route(out, cells, c, view);
                if let (Some(l), Some(first)) = (label, cells.first()) {
                    route_label(&mut texts, l, view.center(*first), c, view, placed);
                }
            }
            Overlay::StagedRoute { stages, label } => {
                for (st, &c) in stages.iter().zip(color) {
                    draw_route(out, st, c, view);
                }
                if let (Some(l), Some(first), Some(&c)) =
                    (label, stages.iter().flatten().next(), color.first())
                {
                    route_label(&mut texts, l, view.center(*first), c, view, placed);
                }
            }
            Overlay::Reference { cells, label } => {
                draw_reference(out, cells, view);
                if let (Some(l), Some(last)) = (label, cells.last()) {
                    route_label(&mut texts, l, view.center(*last), REFERENCE, view, placed);
                }
            }
            _ => {}
        }
    }
    out.push_str(&texts);
    out.push_str("</g>\n");
    let mut markers = String::from("<g id=\"markers\">\n");
    for ov in overlays {
        if let Overlay::Marker { cell, label } = ov {
            draw_marker(&mut markers, *cell, label, view);
        }
    }
    markers.push_str("</g>\n");
    markers
}

/// Places a label of `w`×`h` pixels centred near `(x, y)`: there if free, else just above or
/// below the labels in the way, else there anyway (an overlay label is never dropped).
fn place(x: f64, y: f64, w: f64, h: f64, view: &View, placed: &mut Vec<LabelBox>) -> (f64, f64) {
    let mut candidates = vec![view.keep_inside(x, y, w, h)];
    for step in 1..=3 {
        let dy = step as f64 * (h + 4.0);
        candidates.push(view.keep_inside(x, y + dy, w, h));
        candidates.push(view.keep_inside(x, y - dy, w, h));
    }
    let (x, y) = candidates[0];
    let (cx, cy) = candidates
        .into_iter()
        .find(|&(cx, cy)| {
            !placed
                .iter()
                .any(|p| p.overlaps(&LabelBox::around(cx, cy, w, h)))
        })
        .unwrap_or((x, y));
    placed.push(LabelBox::around(cx, cy, w, h));
    (cx, cy)
}

fn route_label(
    out: &mut String,
    label: &str,
    (x, y): (f64, f64),
    c: Rgb,
    view: &View,
    placed: &mut Vec<LabelBox>,
) {
    let hex = c.hex();
    let w = svg::text_width(label, 12.0, true);
    let (cx, cy) = place(x + 9.0 + w / 2.0, y - 13.0, w, 15.0, view, placed);
    let st = TextStyle {
        size: 12.0,
        fill: &hex,
        bold: true,
        anchor: Anchor::Middle,
        halo: true,
    };
    svg::text(out, cx, cy + 4.0, label, st);
}

fn draw_region(
    out: &mut String,
    texts: &mut String,
    cells: &[Cell],
    kind: RegionKind,
    label: Option<&str>,
    view: &View,
    placed: &mut Vec<LabelBox>,
) {
    if cells.is_empty() {
        return;
    }
    let (c, opacity, dash) = kind.look();
    let hex = c.hex();
    let d = outline::path_data(&outline::trace_cells(cells), |p| view.corner(p));
    let _ = write!(
        out,
        "<path d=\"{d}\" fill=\"{hex}\" fill-opacity=\"{}\" stroke=\"{hex}\" stroke-width=\"2\" stroke-linejoin=\"round\"",
        num(opacity)
    );
    if let Some(dash) = dash {
        let _ = write!(out, " stroke-dasharray=\"{dash}\"");
    }
    out.push_str("/>\n");
    if let Some(l) = label
        && let Some((spot, _)) = layers::pole(cells)
    {
        let (x, y) = view.center(spot);
        let (x, y) = place(x, y, svg::text_width(l, 12.0, true), 15.0, view, placed);
        let st = TextStyle {
            size: 12.0,
            fill: &hex,
            bold: true,
            anchor: Anchor::Middle,
            halo: true,
        };
        svg::text(texts, x, y + 4.0, l, st);
    }
}

/// Route vertices in canvas pixels, without repeated cells and without the points where the route
/// goes straight on (lossless, and it keeps long grid routes short in the SVG).
fn route_points(cells: &[Cell], view: &View) -> Vec<(f64, f64)> {
    let mut pts: Vec<Cell> = Vec::with_capacity(cells.len());
    for &c in cells {
        if pts.last() != Some(&c) {
            pts.push(c);
        }
    }
    let mut keep: Vec<Cell> = Vec::with_capacity(pts.len());
    for (i, &q) in pts.iter().enumerate() {
        if i > 0 && i + 1 < pts.len() {
            let p = pts[i - 1];
            let r = pts[i + 1];
            let (ax, ay) = (q.col as i64 - p.col as i64, q.row as i64 - p.row as i64);
            let (bx, by) = (r.col as i64 - q.col as i64, r.row as i64 - q.row as i64);
            if ax * by - ay * bx == 0 && ax * bx + ay * by > 0 {
                continue;
            }
        }
        keep.push(q);
    }
    keep.iter().map(|&c| view.center(c)).collect()
}

/// The colour of reference routes (their legend swatch uses it too).
pub(super) const REFERENCE: Rgb = Rgb(0x26, 0x26, 0x26);

fn draw_reference(out: &mut String, cells: &[Cell], view: &View) {
    let pts = route_points(cells, view);
    let Some(&(x0, y0)) = pts.first() else { return };
    let mut d = format!("M{} {}", num(x0), num(y0));
    for &(x, y) in &pts[1..] {
        let _ = write!(d, "L{} {}", num(x), num(y));
    }
    let lw = (view.s * 0.25).clamp(2.0, 3.5);
    let _ = writeln!(
        out,
        "<path d=\"{d}\" fill=\"none\" stroke=\"{}\" stroke-width=\"{}\" stroke-dasharray=\"{} {}\" stroke-linejoin=\"round\" stroke-linecap=\"round\"/>",
        REFERENCE.hex(),
        num(lw),
        num(lw * 3.0),
        num(lw * 2.0)
    );
}

fn draw_route(out: &mut String, cells: &[Cell], color: Rgb, view: &View) {
    let pts = route_points(cells, view);
    let Some(&(x0, y0)) = pts.first() else { return };
    let hex = color.hex();
    let lw = (view.s * 0.45).clamp(3.5, 7.0);
    if pts.len() == 1 {
        let _ = writeln!(
            out,
            "<circle cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"{hex}\" stroke=\"#ffffff\" stroke-width=\"1.5\"/>",
            num(x0),
            num(y0),
            num(lw * 1.4)
        );
        return;
    }
    let mut d = format!("M{} {}", num(x0), num(y0));
    for &(x, y) in &pts[1..] {
        let _ = write!(d, "L{} {}", num(x), num(y));
    }
    let _ = writeln!(
        out,
        "<path d=\"{d}\" fill=\"none\" stroke=\"#ffffff\" stroke-opacity=\"0.85\" stroke-width=\"{}\" stroke-linejoin=\"round\" stroke-linecap=\"round\"/>",
        num(lw + 3.0)
    );
    let _ = writeln!(
        out,
        "<path d=\"{d}\" fill=\"none\" stroke=\"{hex}\" stroke-width=\"{}\" stroke-linejoin=\"round\" stroke-linecap=\"round\"/>",
        num(lw)
    );
    // Start dot and arrowhead at the end.
    let _ = writeln!(
        out,
        "<circle cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"#ffffff\" stroke=\"{hex}\" stroke-width=\"{}\"/>",
        num(x0),
        num(y0),
        num(lw * 1.1),
        num(lw * 0.6)
    );
    let (xe, ye) = pts[pts.len() - 1];
    let (xp, yp) = pts[pts.len() - 2];
    let len = ((xe - xp).powi(2) + (ye - yp).powi(2)).sqrt();
    if len > 0.0 {
        let (ux, uy) = ((xe - xp) / len, (ye - yp) / len);
        let (al, aw) = (lw * 3.2, lw * 1.8);
        let (bx, by) = (xe - ux * al, ye - uy * al);
        let _ = writeln!(
            out,
            "<path d=\"M{} {}L{} {}L{} {}Z\" fill=\"{hex}\" stroke=\"#ffffff\" stroke-width=\"1\" stroke-linejoin=\"round\"/>",
            num(xe + ux * lw * 0.8),
            num(ye + uy * lw * 0.8),
            num(bx - uy * aw),
            num(by + ux * aw),
            num(bx + uy * aw),
            num(by - ux * aw)
        );
    }
}

fn draw_marker(out: &mut String, cell: Cell, label: &str, view: &View) {
    let (x, y) = view.center(cell);
    let short = label.chars().count() <= 2;
    let r = if short { 10.0 } else { 6.0 };
    let _ = writeln!(
        out,
        "<circle cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"#1d1d1d\" stroke=\"#ffffff\" stroke-width=\"2\"/>",
        num(x),
        num(y),
        num(r)
    );
    if short {
        let st = TextStyle {
            size: 11.0,
            fill: "#ffffff",
            bold: true,
            anchor: Anchor::Middle,
            halo: false,
        };
        svg::text(out, x, y + 4.0, label, st);
    } else {
        let st = TextStyle {
            size: 12.0,
            fill: "#1d1d1d",
            bold: true,
            anchor: Anchor::Start,
            halo: true,
        };
        // On the left of the marker when the right side would run off the map.
        let w = svg::text_width(label, 12.0, true);
        let lx = if x + r + 4.0 + w > view.ox + view.w {
            x - r - 4.0 - w
        } else {
            x + r + 4.0
        };
        svg::text(out, lx, y + 4.0, label, st);
    }
}
