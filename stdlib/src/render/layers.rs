//! The map itself: room tints, exterior, obstacles, walls, windows, doorways, furniture, room and
//! object labels, and the start pose.

use super::outline::{self, Pt};
use super::style::{self, Structure};
use super::svg::{self, Anchor, TextStyle, num};
use super::{Crop, View};
use crate::field::distance_field;
use crate::grid::{Cell, Grid};
use crate::map::{FREE, OBSTACLE, Object, SemanticMap, UNKNOWN};
use std::collections::BTreeMap;
use std::fmt::Write;

/// Cell classes of the base layer that are not room ids.
const OUTSIDE: u32 = u32::MAX;
const FREE_NO_ROOM: u32 = u32::MAX - 1;

/// Objects smaller than this (m²) count as small things (cups, remotes) and are drawn lighter.
const SMALL_AREA_M2: f64 = 0.09;

/// An axis-aligned box on the canvas, used to keep labels from overlapping.
#[derive(Clone, Copy, Debug)]
pub(super) struct LabelBox {
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
}

impl LabelBox {
    pub(super) fn around(cx: f64, cy: f64, w: f64, h: f64) -> Self {
        LabelBox {
            x0: cx - w / 2.0,
            y0: cy - h / 2.0,
            x1: cx + w / 2.0,
            y1: cy + h / 2.0,
        }
    }

    pub(super) fn overlaps(&self, o: &LabelBox) -> bool {
        self.x0 < o.x1 && o.x0 < self.x1 && self.y0 < o.y1 && o.y0 < self.y1
    }
}

/// Open boundaries (no wall between open-plan rooms) as a dashed line along the cell edges where
/// one room's floor meets the other's, so the picture shows the rooms as open to each other.
fn draw_open_boundaries(out: &mut String, map: &SemanticMap, view: &View) {
    if map.open_boundaries.is_empty() {
        return;
    }
    let width = (view.s * 0.6).clamp(1.0, 2.5);
    let _ = writeln!(
        out,
        "<g id=\"open-boundaries\" fill=\"none\" stroke=\"{}\" stroke-width=\"{}\" stroke-dasharray=\"{} {}\" stroke-linecap=\"butt\">",
        style::OPEN_BOUNDARY,
        num(width),
        num(width * 2.5),
        num(width * 1.5)
    );
    for o in &map.open_boundaries {
        let (a, b) = o.rooms;
        let mut d = String::new();
        for &c in &o.cells {
            let here = map.room_at(c);
            if here != a && here != b {
                continue;
            }
            let (r, k) = (c.row as i64, c.col as i64);
            // Edges to the right and below, each drawn once, where the label switches a <-> b.
            for (dr, dc) in [(0i64, 1i64), (1, 0)] {
                let Some(q) = (r + dr >= 0 && k + dc >= 0)
                    .then(|| Cell::new((r + dr) as u32, (k + dc) as u32))
                else {
                    continue;
                };
                let there = map.room_at(q);
                if there == here || (there != a && there != b) {
                    continue;
                }
                let (p0, p1) = if dc == 1 {
                    ((k + 1, r), (k + 1, r + 1))
                } else {
                    ((k, r + 1), (k + 1, r + 1))
                };
                let (x0, y0) = view.corner(p0);
                let (x1, y1) = view.corner(p1);
                let _ = write!(d, "M{} {}L{} {}", num(x0), num(y0), num(x1), num(y1));
            }
        }
        if !d.is_empty() {
            let _ = writeln!(out, "<path d=\"{d}\"/>");
        }
    }
    out.push_str("</g>\n");
}

/// What the base layer leaves for the end of the picture: its labels and the start marker (drawn
/// after the overlays, so that routes never cover them), and the boxes they take.
pub(super) struct BaseLabels {
    pub labels: String,
    pub placed: Vec<LabelBox>,
}

pub(super) fn draw_base(
    out: &mut String,
    map: &SemanticMap,
    crop: &Crop,
    view: &View,
    labels: bool,
) -> BaseLabels {
    let to_px = |p: Pt| view.corner(p);
    let (w, h) = (crop.cols as usize, crop.rows as usize);
    let mut base = vec![OUTSIDE; w * h];
    let mut blocked = vec![0u32; w * h];
    let mut room_cells: BTreeMap<u32, Vec<Cell>> = BTreeMap::new();
    for r in 0..h {
        for c in 0..w {
            let cell = Cell::new((crop.r0 + r as i64) as u32, (crop.c0 + c as i64) as u32);
            let occ = map.occupancy.get(cell).copied().unwrap_or(OBSTACLE);
            let room = map.room_layer.get(cell).copied().unwrap_or(0);
            let i = r * w + c;
            base[i] = if room != 0 {
                room_cells.entry(room).or_default().push(cell);
                room
            } else if occ == FREE {
                FREE_NO_ROOM
            } else {
                OUTSIDE
            };
            blocked[i] = if occ == UNKNOWN {
                2
            } else if occ != FREE && room != 0 {
                1
            } else {
                0
            };
        }
    }

    out.push_str("<g id=\"base\" shape-rendering=\"crispEdges\">\n");
    for (label, loops) in outline::trace_labels(&base, w, h, (crop.r0, crop.c0), None) {
        let fill = match label {
            OUTSIDE => style::OUTSIDE.to_string(),
            FREE_NO_ROOM => style::FREE_NO_ROOM.to_string(),
            id => style::room_fill(map.room(id).map_or("", |r| r.category.as_str())).hex(),
        };
        let _ = writeln!(
            out,
            "<path d=\"{}\" fill=\"{fill}\"/>",
            outline::path_data(&loops, to_px)
        );
    }
    for (label, loops) in outline::trace_labels(&blocked, w, h, (crop.r0, crop.c0), Some(0)) {
        let (fill, opacity) = if label == 2 {
            (style::UNKNOWN, 1.0)
        } else {
            (style::OBSTACLE, style::OBSTACLE_OPACITY)
        };
        let _ = writeln!(
            out,
            "<path d=\"{}\" fill=\"{fill}\" fill-opacity=\"{}\"/>",
            outline::path_data(&loops, to_px),
            num(opacity)
        );
    }
    out.push_str("</g>\n");

    let n = map.n();
    let in_grid = |c: &&Cell| (c.row as usize) < n && (c.col as usize) < n;
    let res = map.resolution();
    let is_small = |o: &Object| is_small(o, res);

    // Furniture, larger first so that things standing on others stay visible.
    let mut furniture: Vec<&Object> = map
        .objects
        .iter()
        .filter(|o| style::structure_kind(&o.category).is_none())
        .collect();
    furniture.sort_by_key(|o| (is_small(o), std::cmp::Reverse(o.footprint.len()), o.id));
    let stroke_w = (view.s * 0.35).clamp(0.6, 1.5);
    out.push_str("<g id=\"objects\" stroke-linejoin=\"round\">\n");
    for o in &furniture {
        let (fill, stroke, sw) = if is_small(o) {
            (style::SMALL_FILL, style::SMALL_STROKE, stroke_w * 0.7)
        } else {
            (style::FURNITURE_FILL, style::FURNITURE_STROKE, stroke_w)
        };
        let cells: Vec<Cell> = o.footprint.iter().filter(in_grid).copied().collect();
        if cells.is_empty() {
            let (x, y) = view.point(o.center[0], o.center[1]);
            let _ = writeln!(
                out,
                "<circle cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"{fill}\" stroke=\"{stroke}\" stroke-width=\"{}\"/>",
                num(x),
                num(y),
                num((view.s * 0.5).max(2.0)),
                num(sw)
            );
            continue;
        }
        let _ = writeln!(
            out,
            "<path d=\"{}\" fill=\"{fill}\" stroke=\"{stroke}\" stroke-width=\"{}\"/>",
            outline::path_data(&outline::trace_cells(&cells), to_px),
            num(sw)
        );
    }
    out.push_str("</g>\n");

    // Structure, merged per kind: doorways last so they visibly cut through the walls.
    let mut structure: BTreeMap<Structure, Vec<Cell>> = BTreeMap::new();
    for o in &map.objects {
        if let Some(kind) = style::structure_kind(&o.category) {
            structure
                .entry(kind)
                .or_default()
                .extend(o.footprint.iter().filter(in_grid));
        }
    }
    out.push_str("<g id=\"structure\" shape-rendering=\"crispEdges\">\n");
    for (kind, cells) in &structure {
        let fill = match kind {
            Structure::Wall => style::WALL,
            Structure::Window => style::WINDOW,
            Structure::Doorway => style::DOORWAY,
        };
        let _ = writeln!(
            out,
            "<path d=\"{}\" fill=\"{fill}\"/>",
            outline::path_data(&outline::trace_cells(cells), to_px)
        );
    }
    out.push_str("</g>\n");
    draw_open_boundaries(out, map, view);

    let out = &mut String::new();
    out.push_str("<g id=\"labels\">\n");
    let start_cell = map.start.filter(|c| in_grid(&c));
    let start_r = (view.s * 1.2).clamp(5.0, 9.0);
    let avoid = start_cell.map(|c| {
        let (x, y) = view.center(c);
        LabelBox::around(x, y, start_r * 3.6, start_r * 3.6)
    });
    let mut placed = room_labels(out, map, &room_cells, view, avoid);
    // The start marker and its word outrank furniture labels; the word is left out where it
    // would cover a room name.
    let start = start_cell.map(|cell| {
        let (x, y) = view.center(cell);
        let r = start_r;
        let word = LabelBox {
            x0: x + r * 1.7 + 2.0,
            y0: y - 7.0,
            x1: x + r * 1.7 + 38.0,
            y1: y + 7.0,
        };
        let with_word = word.x1 <= view.ox + view.w && !placed.iter().any(|p| p.overlaps(&word));
        placed.push(LabelBox::around(x, y, r * 3.6, r * 3.6));
        if with_word {
            placed.push(word);
        }
        (x, y, r, with_word)
    });
    if labels {
        object_labels(out, &furniture, view, &mut placed, &is_small);
    }
    out.push_str("</g>\n");

    if let Some((x, y, r, with_word)) = start {
        let _ = writeln!(
            out,
            "<g id=\"start\"><circle cx=\"{x}\" cy=\"{y}\" r=\"{}\" fill=\"none\" stroke=\"{c}\" stroke-width=\"2\"/><circle cx=\"{x}\" cy=\"{y}\" r=\"{}\" fill=\"{c}\" stroke=\"#ffffff\" stroke-width=\"1.5\"/></g>",
            num(r * 1.7),
            num(r),
            x = num(x),
            y = num(y),
            c = style::START
        );
        if with_word {
            let st = TextStyle {
                size: 11.0,
                fill: style::START,
                bold: true,
                anchor: Anchor::Start,
                halo: true,
            };
            svg::text(out, x + r * 1.7 + 3.0, y + 4.0, "start", st);
        }
    }
    BaseLabels {
        labels: std::mem::take(out),
        placed,
    }
}

/// Small things (cups, remotes, anything standing on or inside another object) are drawn lighter
/// and labelled smaller than furniture.
pub(super) fn is_small(o: &Object, res: f64) -> bool {
    o.parent.is_some()
        || (res.is_finite() && (o.footprint.len() as f64) * res * res < SMALL_AREA_M2)
}

/// Writes each room's name and area at the point deepest inside it; returns the label boxes.
fn room_labels(
    out: &mut String,
    map: &SemanticMap,
    room_cells: &BTreeMap<u32, Vec<Cell>>,
    view: &View,
    avoid: Option<LabelBox>,
) -> Vec<LabelBox> {
    let mut boxes = Vec::new();
    for (&id, cells) in room_cells {
        let Some((spot, depth)) = pole(cells) else {
            continue;
        };
        let (name, area) = match map.room(id) {
            Some(r) => {
                let name = if r.name.is_empty() {
                    r.category.clone()
                } else {
                    r.name.clone()
                };
                (name, r.area_m2)
            }
            None => (format!("room {id}"), f64::NAN),
        };
        // Shrink the text in rooms too narrow for it.
        let room_px = depth * 2.0 * view.s;
        let size = if room_px < 60.0 { 10.0 } else { 13.0 };
        let (x, mut y) = view.center(spot);
        let area_text = (area.is_finite() && area > 0.0).then(|| format!("{area:.1} m²"));
        let lines = if area_text.is_some() { 2.0 } else { 1.0 };
        let label_h = size * 1.2 * lines + 2.0;
        let mut wdt = svg::text_width(&name, size, true);
        if let Some(a) = &area_text {
            wdt = wdt.max(svg::text_width(a, size * 0.85, false));
        }
        let (x, y_inside) = view.keep_inside(x, y, wdt + 4.0, label_h);
        y = y_inside;
        // Step out of the way of the start marker, away from it vertically.
        if let Some(a) = avoid
            && LabelBox::around(x, y, wdt + 4.0, label_h).overlaps(&a)
        {
            let (ay, half) = ((a.y0 + a.y1) / 2.0, (a.y1 - a.y0) / 2.0);
            y = if y >= ay {
                ay + half + label_h / 2.0 + 2.0
            } else {
                ay - half - label_h / 2.0 - 2.0
            };
        }
        let (_, y) = view.keep_inside(x, y, wdt + 4.0, label_h);
        let y0 = y - (lines - 1.0) * size * 0.6 + size * 0.35;
        let st = TextStyle {
            size,
            fill: style::TEXT,
            bold: true,
            anchor: Anchor::Middle,
            halo: true,
        };
        svg::text(out, x, y0, &name, st);
        if let Some(a) = &area_text {
            let st2 = TextStyle {
                size: size * 0.85,
                fill: style::TEXT_MUTED,
                bold: false,
                anchor: Anchor::Middle,
                halo: true,
            };
            svg::text(out, x, y0 + size * 1.15, a, st2);
        }
        boxes.push(LabelBox::around(x, y, wdt + 4.0, label_h));
    }
    boxes
}

/// Category labels at object centres, larger objects first; a label that would overlap one
/// already placed is left out, so the picture never turns into a smear of text.
fn object_labels(
    out: &mut String,
    objects: &[&Object],
    view: &View,
    placed: &mut Vec<LabelBox>,
    is_small: &dyn Fn(&Object) -> bool,
) {
    for o in objects {
        let small = is_small(o);
        let size = if small { 8.5 } else { 10.0 };
        let (w, h) = (svg::text_width(&o.category, size, false) + 2.0, size * 1.15);
        let (x, y) = view.point(o.center[0], o.center[1]);
        let (x, y) = view.keep_inside(x, y, w, h);
        let b = LabelBox::around(x, y, w, h);
        if placed.iter().any(|p| p.overlaps(&b)) {
            continue;
        }
        placed.push(b);
        let st = TextStyle {
            size,
            fill: if small {
                style::SMALL_STROKE
            } else {
                style::TEXT_MUTED
            },
            bold: false,
            anchor: Anchor::Middle,
            halo: true,
        };
        svg::text(out, x, y + size * 0.35, &o.category, st);
    }
}

/// The member cell deepest inside a cell set (largest distance to a non-member), preferring the
/// one nearest the centroid among near-ties so labels sit in the middle of long rooms rather than
/// at one end; also returns that depth in cells.
pub(super) fn pole(cells: &[Cell]) -> Option<(Cell, f64)> {
    let first = cells.first()?;
    let (mut r0, mut c0, mut r1, mut c1) = (first.row, first.col, first.row, first.col);
    let (mut sr, mut sc) = (0.0, 0.0);
    for c in cells {
        r0 = r0.min(c.row);
        c0 = c0.min(c.col);
        r1 = r1.max(c.row);
        c1 = c1.max(c.col);
        sr += c.row as f64;
        sc += c.col as f64;
    }
    let (cr, cc) = (sr / cells.len() as f64, sc / cells.len() as f64);
    let m = ((r1 - r0).max(c1 - c0) + 3) as usize;
    let mut outside = Grid::new(m, true);
    for c in cells {
        outside.set(Cell::new(c.row - r0 + 1, c.col - c0 + 1), false);
    }
    let dist = distance_field(&outside);
    let deepest = cells
        .iter()
        .map(|c| {
            dist.get(Cell::new(c.row - r0 + 1, c.col - c0 + 1))
                .copied()
                .unwrap_or(0.0)
        })
        .fold(0.0f64, f64::max);
    let key = |c: &Cell| {
        let d2 = (c.row as f64 - cr).powi(2) + (c.col as f64 - cc).powi(2);
        (d2, c.row, c.col)
    };
    let mut best: Option<Cell> = None;
    for c in cells {
        let d = dist
            .get(Cell::new(c.row - r0 + 1, c.col - c0 + 1))
            .copied()
            .unwrap_or(0.0);
        if d < deepest * 0.8 - 0.5 {
            continue;
        }
        if best.is_none_or(|b| key(c).partial_cmp(&key(&b)) == Some(std::cmp::Ordering::Less)) {
            best = Some(*c);
        }
    }
    best.map(|b| (b, deepest))
}
