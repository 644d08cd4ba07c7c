//! A picture of one episode that explains its scores: the map, the annotation's regions
//! (destinations, must-avoids, preference scopes and their reference objects), the path-shape
//! reference route nDTW is measured against, a method's route, and as the caption the
//! instruction and every score the report counts (HCS, segment-wise SPL, PL, each preference's
//! raw value). Regions are named with the map's room names (`bedroom_3`), as everywhere else.

use crate::episode::{ConstraintKind, Episode, PreferenceType, Shape, SoftConstraint};
use crate::methods::shortest::{RegionView, inside_mask};
use crate::metrics::evaluate::{EpisodeMetrics, evaluate_or_worst_case};
use crate::metrics::map::EvalMap;
use crate::metrics::soft::{EvalOptions, SoftDetail, path_reference};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use m2rc_stdlib::render::{Overlay, RegionKind, RenderOptions, render_map};

fn cells_of(region: &RegionView<'_>, n: usize) -> Vec<Cell> {
    match region.shape {
        Some(Shape::Freeform) => to_cells(region.cells, n),
        _ => inside_mask(region, n)
            .iter()
            .enumerate()
            .filter(|(_, m)| **m)
            .map(|(i, _)| Cell::new((i / n) as u32, (i % n) as u32))
            .collect(),
    }
}

fn to_cells(raw: &[[i64; 2]], n: usize) -> Vec<Cell> {
    raw.iter()
        .filter(|c| c[0] >= 0 && c[1] >= 0 && (c[0] as usize) < n && (c[1] as usize) < n)
        .map(|c| Cell::new(c[0] as u32, c[1] as u32))
        .collect()
}

/// Renders the episode with `route` (cells outside the map are dropped) to PNG bytes. The scores
/// are computed here exactly as the runner computes a record's (`report::score`).
pub fn episode_png(
    map: &SemanticMap,
    episode: &Episode,
    route: &[[i64; 2]],
    label: &str,
) -> Result<Vec<u8>, String> {
    let opts = episode_render_options(map, episode, route, label);
    // The picture's start is the episode's, not the map's own start pose.
    let mut shown = map.clone();
    shown.start = crate::methods::start_cell(map, episode).ok();
    render_map(&shown, &opts)
        .map(|o| o.png)
        .map_err(|e| e.to_string())
}

/// What [`episode_png`] draws, for tests and other renderers.
pub fn episode_render_options(
    map: &SemanticMap,
    episode: &Episode,
    route: &[[i64; 2]],
    label: &str,
) -> RenderOptions {
    let n = map.n();
    let metrics = evaluate_or_worst_case(
        route,
        episode,
        &EvalMap::from_semantic_map(map),
        &EvalOptions::default(),
    );
    let mut overlays = Vec::new();
    let mut caption = Vec::new();
    if let Some(text) = episode
        .instruction
        .as_deref()
        .filter(|t| !t.trim().is_empty())
    {
        caption.push(format!("Instruction: {}", text.trim()));
    }
    caption.push(headline(&metrics));
    for (i, s) in episode.soft_constraints.iter().enumerate() {
        let cells = cells_of(&RegionView::of_soft(s), n);
        let name = soft_name(i, s, &cells, map);
        let detail = metrics
            .details
            .soft_constraints
            .iter()
            .find(|d| d.constraint_id == s.constraint_id.clone().unwrap_or_default())
            .or_else(|| metrics.details.soft_constraints.get(i));
        caption.push(format!(
            "{name}: {}",
            detail.map_or("not scored".into(), score_text)
        ));
        if !cells.is_empty() {
            overlays.push(Overlay::Region {
                cells,
                kind: RegionKind::Scope,
                label: Some(name.clone()),
            });
        }
        let mut refs: Vec<[i64; 2]> = Vec::new();
        if let Some(r) = &s.reference_region {
            refs.extend(r.cells.iter().flatten().copied());
        }
        for r in s.reference_regions.iter().flatten() {
            refs.extend(r.cells.iter().flatten().copied());
        }
        let refs = to_cells(&refs, n);
        if !refs.is_empty() {
            overlays.push(Overlay::Region {
                cells: refs,
                kind: RegionKind::PreferenceRef,
                label: None,
            });
        }
        if s.preference() == Some(PreferenceType::PathShape)
            && let Ok(reference) = path_reference(i, s, episode, n)
            && let Some(points) = reference.points
        {
            let cells: Vec<[i64; 2]> = points
                .iter()
                .map(|p| [p[0].round() as i64, p[1].round() as i64])
                .collect();
            overlays.push(Overlay::Reference {
                cells: to_cells(&cells, n),
                label: Some(format!("{}. nDTW reference route", i + 1)),
            });
        }
    }
    let mut order = 0;
    for c in &episode.hard_constraints {
        let cells = cells_of(&RegionView::of_hard(c), n);
        if cells.is_empty() {
            continue;
        }
        let text = c.label.clone().unwrap_or_default();
        match c.kind {
            ConstraintKind::MustPass => {
                order += 1;
                // The first must-pass is the start region the evaluator records; the others are
                // the destinations, numbered as the summary and the caption number them.
                let (kind, label) = if order == 1 {
                    let start = match text.trim() {
                        "" | "start" => "start region".to_string(),
                        t => format!("start region: {t}"),
                    };
                    (RegionKind::Pass, start)
                } else {
                    (RegionKind::Destination, format!("{}: {text}", order - 1))
                };
                overlays.push(Overlay::Region {
                    cells,
                    kind,
                    label: Some(label),
                });
            }
            ConstraintKind::MustAvoid => {
                overlays.push(Overlay::Region {
                    cells,
                    kind: RegionKind::Avoid,
                    label: Some(format!("avoid {text}").trim().to_string()),
                });
            }
        }
    }
    let route = to_cells(route, n);
    if !route.is_empty() {
        overlays.push(Overlay::Route {
            cells: route,
            label: Some(label.to_string()),
            color: None,
        });
    }
    RenderOptions {
        overlays,
        title: Some(label.to_string()),
        caption,
        ..RenderOptions::default()
    }
}

/// `HCS 1.00 · segment-wise SPL 0.87 · PL 24.9 m`, with why HCS is not 1 when it is not.
fn headline(m: &EpisodeMetrics) -> String {
    let mut s = format!(
        "HCS {:.2} · segment-wise SPL {:.2} · PL {:.1} m",
        m.hcs, m.segment_wise_spl, m.pl
    );
    let h = &m.details.hcs;
    if h.must_pass_count > 0 {
        s.push_str(&format!(
            " · {} of {} destinations reached in order",
            h.valid_completed_count, h.must_pass_count
        ));
    }
    if let Some(f) = &h.failure_type {
        s.push_str(&format!(" · HCS failure: {}", f.replace('_', " ")));
    }
    if let Some(f) = &m.details.evaluation_fallback {
        s.push_str(&format!(" · evaluation failed ({}): worst case", f.error));
    }
    s
}

/// `2. near in bedroom_3`: the preference's number (as the caption counts them), its kind and
/// the room its region lies in, by the map's name for it.
fn soft_name(i: usize, s: &SoftConstraint, cells: &[Cell], map: &SemanticMap) -> String {
    let kind = match s.preference() {
        Some(PreferenceType::Near) => "near",
        Some(PreferenceType::Far) => "far",
        Some(PreferenceType::Relative) => "relative",
        Some(PreferenceType::PathShape) => "path shape",
        Some(PreferenceType::Clearance) => "clearance",
        None => s.preference_type.as_deref().unwrap_or("preference"),
    };
    let room = m2rc_stdlib::map::format::dominant_room(cells, &map.room_layer)
        .and_then(|r| map.room(r))
        .map(m2rc_compiler::eval::room_name);
    match room {
        Some(r) => format!("{}. {kind} in {r}", i + 1),
        None => format!("{}. {kind}", i + 1),
    }
}

/// What a preference scored, in the report's terms: the raw value with its unit and which way
/// is better, nDTW against the drawn reference route for path shapes.
fn score_text(d: &SoftDetail) -> String {
    let Some(v) = d.raw_value else {
        return format!("not scored ({})", d.status.replace('_', " "));
    };
    let better = match d.direction.as_deref() {
        Some("larger_is_better") => " (larger is better)",
        Some("smaller_is_better") => " (smaller is better)",
        _ => "",
    };
    if let Some(ndtw) = d.ndtw {
        return format!("nDTW {ndtw:.2} against the dashed reference route{better}");
    }
    let what = match d.preference_type.as_deref() {
        Some("near_preference") | Some("far_preference") => "mean distance ",
        Some("relative_preference") => "distance ratio ",
        Some("clearance") => "mean clearance ",
        _ => "",
    };
    match d.unit.as_deref() {
        Some("m") => format!("{what}{v:.2} m{better}"),
        _ => format!("{what}{v:.2}{better}"),
    }
}
