//! A picture of one episode: the map, the annotation's regions (destinations, must-avoids,
//! preference scopes and their reference objects) and a method's route, drawn by the map renderer.

use crate::episode::{ConstraintKind, Episode, Shape};
use crate::methods::shortest::{RegionView, inside_mask};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use m2rc_stdlib::render::{Overlay, RegionKind, RenderOptions, render_map};

fn cells_of(region: &RegionView<'_>, n: usize) -> Vec<Cell> {
    match region.shape {
        Some(Shape::Freeform) => region
            .cells
            .iter()
            .filter(|c| c[0] >= 0 && c[1] >= 0 && (c[0] as usize) < n && (c[1] as usize) < n)
            .map(|c| Cell::new(c[0] as u32, c[1] as u32))
            .collect(),
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

/// Renders the episode with `route` (cells outside the map are dropped) to PNG bytes.
pub fn episode_png(
    map: &SemanticMap,
    episode: &Episode,
    route: &[[i64; 2]],
    label: &str,
) -> Result<Vec<u8>, String> {
    let n = map.n();
    let mut overlays = Vec::new();
    for s in &episode.soft_constraints {
        let cells = cells_of(&RegionView::of_soft(s), n);
        if !cells.is_empty() {
            overlays.push(Overlay::Region {
                cells,
                kind: RegionKind::Scope,
                label: s.label.clone(),
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
    }
    let mut order = 0;
    for c in &episode.hard_constraints {
        let cells = cells_of(&RegionView::of_hard(c), n);
        if cells.is_empty() {
            continue;
        }
        match c.kind {
            ConstraintKind::MustPass => {
                order += 1;
                let kind = if order == 1 {
                    RegionKind::Pass
                } else {
                    RegionKind::Destination
                };
                overlays.push(Overlay::Region {
                    cells,
                    kind,
                    label: c.label.clone(),
                });
            }
            ConstraintKind::MustAvoid => {
                overlays.push(Overlay::Region {
                    cells,
                    kind: RegionKind::Avoid,
                    label: c.label.clone(),
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
    let opts = RenderOptions {
        overlays,
        title: Some(label.to_string()),
        ..RenderOptions::default()
    };
    // The picture's start is the episode's, not the map's own start pose.
    let mut shown = map.clone();
    shown.start = crate::methods::start_cell(map, episode).ok();
    render_map(&shown, &opts)
        .map(|o| o.png)
        .map_err(|e| e.to_string())
}
