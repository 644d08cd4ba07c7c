//! The legend box beside the map and the scale bar under it.
//!
//! The legend lists only what the picture shows (room types present, structure kinds present,
//! overlays present), so it doubles as a summary of the map.

use super::RenderOptions;
use super::layers;
use super::overlay::{self, Overlay, RegionKind};
use super::style::{self, Structure};
use super::svg::{self, Anchor, TextStyle, num};
use crate::map::{FREE, SemanticMap, UNKNOWN};
use std::collections::BTreeSet;
use std::fmt::Write;

enum Swatch {
    Fill {
        fill: String,
        stroke: Option<String>,
        opacity: f64,
        dash: Option<&'static str>,
    },
    Line(String),
    /// A thin dashed line: a reference route.
    Dashed(String),
    Dot(String),
    Marker,
}

struct Section {
    title: &'static str,
    entries: Vec<(Swatch, String)>,
}

pub(super) struct Legend {
    sections: Vec<Section>,
}

const PAD: f64 = 10.0;
const ROW: f64 = 20.0;
const HEAD: f64 = 22.0;
const SWATCH_W: f64 = 22.0;
const TEXT_SIZE: f64 = 12.0;
/// Labelled regions listed one by one; past this the rest are counted, so a path shape's many
/// waypoints do not make the legend taller than the picture needs.
const MAX_REGION_ENTRIES: usize = 16;

fn fill(c: &str) -> Swatch {
    Swatch::Fill {
        fill: c.to_string(),
        stroke: None,
        opacity: 1.0,
        dash: None,
    }
}

impl Legend {
    pub fn build(map: &SemanticMap, opts: &RenderOptions) -> Legend {
        let mut sections = Vec::new();

        let cats: BTreeSet<&str> = map.rooms.iter().map(|r| r.category.as_str()).collect();
        let rooms: Vec<(Swatch, String)> = cats
            .iter()
            .map(|c| (fill(&style::room_fill(c).hex()), c.replace('_', " ")))
            .collect();
        if !rooms.is_empty() {
            sections.push(Section {
                title: "Rooms",
                entries: rooms,
            });
        }

        let mut things = Vec::new();
        let kinds: BTreeSet<Structure> = map
            .objects
            .iter()
            .filter_map(|o| style::structure_kind(&o.category))
            .collect();
        for k in &kinds {
            let (c, name) = match k {
                Structure::Wall => (style::WALL, "wall"),
                Structure::Window => (style::WINDOW, "window"),
                Structure::Doorway => (style::DOORWAY, "doorway"),
            };
            things.push((fill(c), name.to_string()));
        }
        if !map.open_boundaries.is_empty() {
            things.push((
                Swatch::Line(style::OPEN_BOUNDARY.into()),
                "open boundary".to_string(),
            ));
        }
        let res = map.resolution();
        let furniture = map
            .objects
            .iter()
            .filter(|o| style::structure_kind(&o.category).is_none());
        let (mut big, mut small) = (false, false);
        for o in furniture {
            if layers::is_small(o, res) {
                small = true;
            } else {
                big = true;
            }
        }
        if big {
            let sw = Swatch::Fill {
                fill: style::FURNITURE_FILL.into(),
                stroke: Some(style::FURNITURE_STROKE.into()),
                opacity: 1.0,
                dash: None,
            };
            things.push((sw, "furniture".into()));
        }
        if small {
            let sw = Swatch::Fill {
                fill: style::SMALL_FILL.into(),
                stroke: Some(style::SMALL_STROKE.into()),
                opacity: 1.0,
                dash: None,
            };
            things.push((sw, "small object".into()));
        }
        let mut obstacle = false;
        let mut unknown = false;
        for (cell, &occ) in map.occupancy.iter_cells() {
            if occ == UNKNOWN {
                unknown = true;
            } else if occ != FREE && map.room_layer.get(cell).is_some_and(|&r| r != 0) {
                obstacle = true;
            }
        }
        if obstacle {
            let sw = Swatch::Fill {
                fill: style::OBSTACLE.into(),
                stroke: None,
                opacity: style::OBSTACLE_OPACITY,
                dash: None,
            };
            things.push((sw, "not traversable".into()));
        }
        if unknown {
            things.push((fill(style::UNKNOWN), "unknown".into()));
        }
        if map.n() > 0 {
            things.push((fill(style::OUTSIDE), "outside".into()));
        }
        if map.start.is_some() {
            things.push((Swatch::Dot(style::START.into()), "start".into()));
        }
        if !things.is_empty() {
            sections.push(Section {
                title: "Map",
                entries: things,
            });
        }

        let mut ovs = Vec::new();
        let colors = overlay::line_colors(&opts.overlays);
        let mut route_no = 0;
        let mut kinds: BTreeSet<RegionKind> = BTreeSet::new();
        let mut regions: Vec<(RegionKind, &str)> = Vec::new();
        let mut markers = false;
        for (ov, color) in opts.overlays.iter().zip(&colors) {
            match ov {
                Overlay::Route { label, .. } => {
                    route_no += 1;
                    let name = label.clone().unwrap_or_else(|| format!("route {route_no}"));
                    let c = color.first().copied().unwrap_or(style::ROUTE_PALETTE[0]);
                    ovs.push((Swatch::Line(c.hex()), name));
                }
                Overlay::StagedRoute { stages, label } => {
                    for (i, c) in color.iter().enumerate().take(stages.len()) {
                        let name = match label {
                            Some(l) => format!("{l}: stage {}", i + 1),
                            None => format!("stage {}", i + 1),
                        };
                        ovs.push((Swatch::Line(c.hex()), name));
                    }
                }
                Overlay::Region { kind, label, .. } => {
                    kinds.insert(*kind);
                    if let Some(l) = label.as_deref()
                        && !regions.contains(&(*kind, l))
                    {
                        regions.push((*kind, l));
                    }
                }
                Overlay::Reference { label, .. } => {
                    let name = label.clone().unwrap_or_else(|| "reference route".into());
                    ovs.push((Swatch::Dashed(overlay::REFERENCE.hex()), name));
                }
                // Numbered markers are stage destinations; others (`S`, a note) say what
                // they are on the picture itself.
                Overlay::Marker { label, .. } => {
                    markers |= !label.is_empty() && label.chars().all(|c| c.is_ascii_digit());
                }
            }
        }
        for k in kinds {
            ovs.push((region_swatch(k), k.name().to_string()));
        }
        if markers {
            ovs.push((Swatch::Marker, "stage destination".into()));
        }
        if !ovs.is_empty() {
            sections.push(Section {
                title: "Overlays",
                entries: ovs,
            });
        }
        // Each labelled region by its own name, as the map and the summary name it.
        let mut named: Vec<(Swatch, String)> = regions
            .iter()
            .take(MAX_REGION_ENTRIES)
            .map(|(k, l)| (region_swatch(*k), l.to_string()))
            .collect();
        if regions.len() > MAX_REGION_ENTRIES {
            named.push((
                Swatch::Line("#ffffff".into()),
                format!("… and {} more", regions.len() - MAX_REGION_ENTRIES),
            ));
        }
        if !named.is_empty() {
            sections.push(Section {
                title: "Regions",
                entries: named,
            });
        }
        Legend { sections }
    }

    pub fn width(&self) -> f64 {
        let widest = self
            .sections
            .iter()
            .flat_map(|s| {
                s.entries
                    .iter()
                    .map(|e| svg::text_width(&e.1, TEXT_SIZE, false))
            })
            .fold(0.0f64, f64::max);
        (PAD + SWATCH_W + 8.0 + widest + PAD).clamp(130.0, 320.0)
    }

    pub fn height(&self) -> f64 {
        if self.sections.is_empty() {
            return 0.0;
        }
        let rows: usize = self.sections.iter().map(|s| s.entries.len()).sum();
        PAD + self.sections.len() as f64 * HEAD + rows as f64 * ROW + PAD
    }

    pub fn draw(&self, out: &mut String, x: f64, y: f64) {
        if self.sections.is_empty() {
            return;
        }
        let _ = writeln!(
            out,
            "<g id=\"legend\"><rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" rx=\"4\" fill=\"#ffffff\" stroke=\"#bdbdbd\"/>",
            num(x),
            num(y),
            num(self.width()),
            num(self.height())
        );
        let mut cy = y + PAD;
        let max_chars =
            ((self.width() - PAD * 2.0 - SWATCH_W - 8.0) / (TEXT_SIZE * 0.6) + 0.01) as usize;
        for sec in &self.sections {
            let st = TextStyle {
                size: 12.5,
                fill: style::TEXT,
                bold: true,
                anchor: Anchor::Start,
                halo: false,
            };
            svg::text(out, x + PAD, cy + 15.0, sec.title, st);
            cy += HEAD;
            for (sw, label) in &sec.entries {
                let (sx, sy) = (x + PAD, cy + 3.0);
                draw_swatch(out, sw, sx, sy);
                let st = TextStyle {
                    size: TEXT_SIZE,
                    fill: style::TEXT,
                    bold: false,
                    anchor: Anchor::Start,
                    halo: false,
                };
                let shown = truncate(label, max_chars.max(4));
                svg::text(out, sx + SWATCH_W + 8.0, cy + 14.0, &shown, st);
                cy += ROW;
            }
        }
        out.push_str("</g>\n");
    }
}

fn region_swatch(k: RegionKind) -> Swatch {
    let (c, opacity, dash) = k.look();
    Swatch::Fill {
        fill: c.hex(),
        stroke: Some(c.hex()),
        opacity,
        dash,
    }
}

fn truncate(s: &str, max: usize) -> String {
    if s.chars().count() <= max {
        s.to_string()
    } else {
        let mut t: String = s.chars().take(max.saturating_sub(1)).collect();
        t.push('…');
        t
    }
}

fn draw_swatch(out: &mut String, sw: &Swatch, x: f64, y: f64) {
    let (w, h) = (SWATCH_W, 14.0);
    match sw {
        Swatch::Fill {
            fill,
            stroke,
            opacity,
            dash,
        } => {
            let _ = write!(
                out,
                "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"{fill}\" fill-opacity=\"{}\" stroke=\"{}\" stroke-width=\"1.2\"",
                num(x),
                num(y),
                num(w),
                num(h),
                num(*opacity),
                stroke.as_deref().unwrap_or("#9e9e9e")
            );
            if let Some(d) = dash {
                let _ = write!(out, " stroke-dasharray=\"{d}\"");
            }
            out.push_str("/>\n");
        }
        Swatch::Line(c) => {
            let _ = writeln!(
                out,
                "<path d=\"M{} {}H{}\" stroke=\"{c}\" stroke-width=\"4\" stroke-linecap=\"round\"/>",
                num(x + 2.0),
                num(y + h / 2.0),
                num(x + w - 2.0)
            );
        }
        Swatch::Dashed(c) => {
            let _ = writeln!(
                out,
                "<path d=\"M{} {}H{}\" stroke=\"{c}\" stroke-width=\"2.5\" stroke-dasharray=\"6 4\"/>",
                num(x + 1.0),
                num(y + h / 2.0),
                num(x + w - 1.0)
            );
        }
        Swatch::Dot(c) => {
            let _ = writeln!(
                out,
                "<circle cx=\"{}\" cy=\"{}\" r=\"5\" fill=\"{c}\" stroke=\"#ffffff\" stroke-width=\"1.5\"/>",
                num(x + w / 2.0),
                num(y + h / 2.0)
            );
        }
        Swatch::Marker => {
            let _ = writeln!(
                out,
                "<circle cx=\"{}\" cy=\"{}\" r=\"7\" fill=\"#1d1d1d\"/>",
                num(x + w / 2.0),
                num(y + h / 2.0)
            );
            let st = TextStyle {
                size: 9.0,
                fill: "#ffffff",
                bold: true,
                anchor: Anchor::Middle,
                halo: false,
            };
            svg::text(out, x + w / 2.0, y + h / 2.0 + 3.2, "1", st);
        }
    }
}

/// A black-and-white bar of a round length in metres, so distances can be read off the picture.
/// Left out when the map has no usable resolution.
pub(super) fn draw_scale_bar(out: &mut String, res: f64, s: f64, x: f64, y: f64) {
    if !(res.is_finite() && res > 0.0 && s > 0.0) {
        return;
    }
    let px_per_m = s / res;
    const NICE: [f64; 13] = [
        0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0, 1000.0,
    ];
    let len_m = NICE
        .iter()
        .copied()
        .rev()
        .find(|l| l * px_per_m <= 260.0)
        .unwrap_or(NICE[0]);
    let len_px = len_m * px_per_m;
    let seg = len_px / 4.0;
    out.push_str("<g id=\"scale\">\n");
    for i in 0..4 {
        let fill = if i % 2 == 0 { "#1d1d1d" } else { "#ffffff" };
        let _ = writeln!(
            out,
            "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"6\" fill=\"{fill}\" stroke=\"#1d1d1d\" stroke-width=\"1\"/>",
            num(x + seg * i as f64),
            num(y),
            num(seg)
        );
    }
    let st = TextStyle {
        size: 11.0,
        fill: style::TEXT,
        bold: false,
        anchor: Anchor::Middle,
        halo: false,
    };
    svg::text(out, x, y + 20.0, "0", st);
    svg::text(out, x + len_px, y + 20.0, &format!("{} m", num(len_m)), st);
    out.push_str("</g>\n");
}
