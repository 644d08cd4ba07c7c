//! RouteIR → [`PlanProblem`]: the only place the planner knows about the compiler's IR and the map.
//!
//! * Each RouteIR stage (one `go`) becomes a segment. Its planned stages are its `pass` places and
//!   the waypoints of its active path-shape preferences, in source order, then its destination.
//!   Shape waypoints charge turns inside the room of the shape (the reference smoothness mask).
//! * Active `avoid` constraints become the segment's forbidden cells, restricted to their spatial
//!   scope when they have one (the RouteIR's documented semantics; the reference drops hard scopes).
//! * Active soft preferences become soft terms with their spatial scope as the mask.
//! * Clearance obstacles are the non-free occupancy cells plus every cell of the object layer whose
//!   object is not a door (`doorway`, `doorframe`), as in the reference.
//!
//! Every stage, avoid region and term carries an [`Origin`]; [`span_of`] maps it back to the
//! `.m2r` source span for diagnostics.

use crate::context::MapContext;
use crate::problem::{
    Area, CostProfile, Fallback, Forbid, Origin, PlanProblem, RelativeMode, SegmentSpec, SoftKind,
    SoftTerm, StageRole, StageSpec, Target,
};
use m2rc_compiler::ir::{Constraint, ConstraintKind, Place, PlaceKind, RouteIr, Shape, SourceSpan};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;

/// Builds the planning problem for `ir` on `map` with cost `profile`. Indexes the map on every call;
/// a caller planning on the same map more than once should build a [`MapContext`] once and call
/// [`lower_with`].
pub fn lower(ir: &RouteIr, map: &SemanticMap, profile: CostProfile) -> Result<PlanProblem, String> {
    check_ir(ir, map)?;
    lower_with(ir, map, &MapContext::new(map)?, profile)
}

/// [`lower`] with the per-map data of `ctx` (built from `map`), shared with every other problem
/// lowered from it, including the obstacle distance and clearance fields once computed.
pub fn lower_with(
    ir: &RouteIr,
    map: &SemanticMap,
    ctx: &MapContext,
    profile: CostProfile,
) -> Result<PlanProblem, String> {
    check_ir(ir, map)?;
    let n = map.n();
    if ctx.n() != n || ctx.map_id != map.map_id {
        return Err(format!(
            "the planning context was built for map `{}` ({1}×{1}), not for map `{2}` ({n}×{n})",
            ctx.map_id,
            ctx.n(),
            map.map_id
        ));
    }
    let traversable = ctx.traversable.clone();
    let obstacles = ctx.obstacles.clone();
    let resolution = if ir.resolution_m.is_finite() && ir.resolution_m > 0.0 {
        ir.resolution_m
    } else {
        map.resolution()
    };

    let mut segments = Vec::with_capacity(ir.stages.len());
    for (si, stage) in ir.stages.iter().enumerate() {
        let active: Vec<(usize, &Constraint)> = ir
            .constraints
            .iter()
            .enumerate()
            .filter(|(_, c)| c.active_in(si))
            .collect();
        // Must-pass places and shape waypoints, ordered by where they are written.
        let mut ordered: Vec<(bool, usize, Vec<StageSpec>)> = Vec::new();
        for (pi, pass) in stage.passes.iter().enumerate() {
            let spec = StageSpec {
                target: target_of(&pass.place, map, ctx),
                role: StageRole::Pass,
                smoothness: None,
                origin: Origin::Pass {
                    stage: si,
                    index: pi,
                },
            };
            ordered.push((within(pass.span, stage.span), pass.span.start, vec![spec]));
        }
        let mut forbidden = Vec::new();
        let mut soft = Vec::new();
        for &(ci, c) in &active {
            let scope = c
                .spatial_scope
                .as_ref()
                .map(|p| Area::Cells(p.cells.cells().to_vec()));
            let origin = Origin::Constraint { index: ci, part: 0 };
            let term = |kind| SoftTerm {
                kind,
                weight: None,
                scope: scope.clone(),
                origin,
            };
            match &c.kind {
                ConstraintKind::Avoid { place } => {
                    let mut cells = place.cells.cells().to_vec();
                    if let Some(sc) = &c.spatial_scope {
                        cells.retain(|cell| sc.cells.contains(*cell));
                    }
                    forbidden.push(Forbid {
                        cells: Area::Cells(cells),
                        origin,
                    });
                }
                ConstraintKind::Near { reference } => soft.push(term(SoftKind::Near {
                    reference: area(reference),
                })),
                ConstraintKind::Far { reference } => soft.push(term(SoftKind::Far {
                    reference: area(reference),
                })),
                ConstraintKind::Relative { closer, farther } => {
                    soft.push(term(SoftKind::Relative {
                        closer: area(closer),
                        farther: area(farther),
                        mode: RelativeMode::Ratio,
                    }))
                }
                ConstraintKind::Clearance { distance_m } => soft.push(term(SoftKind::Clearance {
                    radius_m: *distance_m,
                })),
                ConstraintKind::PathShape {
                    shape,
                    around,
                    waypoints,
                    ..
                } => {
                    // Only loops charge turns: a `through` chain may cross rooms and has no
                    // curve of its own to keep smooth (the reference's relative waypoints too).
                    let smooth = match shape {
                        Shape::Through => None,
                        _ => room_area_of(around, map, ctx),
                    };
                    let specs = waypoints
                        .iter()
                        .enumerate()
                        .map(|(j, wp)| StageSpec {
                            target: target_of(wp, map, ctx),
                            role: StageRole::Waypoint,
                            smoothness: smooth.clone(),
                            origin: Origin::Constraint { index: ci, part: j },
                        })
                        .collect();
                    ordered.push((within(c.span, stage.span), c.span.start, specs));
                }
            }
        }
        // Written inside the stage: source order; route-level shapes: after them, in IR order.
        ordered.sort_by_key(|(inside, at, _)| (!*inside, if *inside { *at } else { 0 }));
        let mut stages: Vec<StageSpec> = ordered.into_iter().flat_map(|(_, _, s)| s).collect();
        stages.push(StageSpec {
            target: target_of(&stage.target, map, ctx),
            role: StageRole::Destination,
            smoothness: None,
            origin: Origin::Target { stage: si },
        });
        segments.push(SegmentSpec {
            stages,
            forbidden,
            soft,
        });
    }
    Ok(PlanProblem {
        traversable,
        obstacles: Some(obstacles),
        resolution,
        start: ir.start,
        segments,
        profile,
        map_fields: Some(ctx.fields()),
    })
}

fn check_ir(ir: &RouteIr, map: &SemanticMap) -> Result<(), String> {
    let n = map.n();
    if ir.grid_size != n {
        return Err(format!(
            "the RouteIR was grounded on a {0}×{0} grid (map `{1}`), but the map `{2}` is {n}×{n}",
            ir.grid_size, ir.map_id, map.map_id
        ));
    }
    if ir.stages.is_empty() {
        return Err("the RouteIR has no stages: nothing to plan".into());
    }
    Ok(())
}

/// The source span an origin points at.
pub fn span_of(ir: &RouteIr, origin: Origin) -> Option<SourceSpan> {
    match origin {
        Origin::Unknown => None,
        Origin::Target { stage } => ir.stages.get(stage).map(|s| s.span),
        Origin::Pass { stage, index } => ir.stages.get(stage)?.passes.get(index).map(|p| p.span),
        Origin::Constraint { index, .. } => ir.constraints.get(index).map(|c| c.span),
    }
}

fn within(inner: SourceSpan, outer: SourceSpan) -> bool {
    inner.start >= outer.start && inner.end <= outer.end
}

fn area(p: &Place) -> Area {
    Area::Cells(p.cells.cells().to_vec())
}

fn centroid(cells: &[Cell]) -> Option<[f64; 2]> {
    if cells.is_empty() {
        return None;
    }
    let k = cells.len() as f64;
    Some([
        cells.iter().map(|c| c.row as f64).sum::<f64>() / k,
        cells.iter().map(|c| c.col as f64).sum::<f64>() / k,
    ])
}

fn room_mask(map: &SemanticMap, ctx: &MapContext, id: u32) -> Area {
    Area::Mask(ctx.room_mask(map, id))
}

/// The room under a point, if any.
fn room_at(map: &SemanticMap, at: [f64; 2]) -> Option<u32> {
    let cell = Cell::new(at[0].round().max(0.0) as u32, at[1].round().max(0.0) as u32);
    map.room_layer.get(cell).copied().filter(|&r| r != 0)
}

/// The room a shape is drawn in: the room itself, an object's room, or the room under a region's
/// centre.
fn room_area_of(p: &Place, map: &SemanticMap, ctx: &MapContext) -> Option<Area> {
    match &p.kind {
        PlaceKind::Room { .. } => Some(area(p)),
        PlaceKind::Object { room, .. } => room.map(|r| room_mask(map, ctx, r)),
        PlaceKind::Region { .. } => {
            room_at(map, centroid(p.cells.cells())?).map(|r| room_mask(map, ctx, r))
        }
        PlaceKind::AnyOf { .. } => None,
    }
}

fn target_of(p: &Place, map: &SemanticMap, ctx: &MapContext) -> Target {
    let cells = p.cells.cells();
    match &p.kind {
        PlaceKind::Room { .. } => Target::Room(area(p)),
        PlaceKind::Object { id, room, .. } => {
            let center = map
                .object(*id)
                .map(|o| o.center)
                .or_else(|| centroid(cells))
                .unwrap_or([0.0, 0.0]);
            Target::Object {
                footprint: cells.to_vec(),
                room: room.map(|r| room_mask(map, ctx, r)),
                center,
            }
        }
        PlaceKind::Region { construction } => {
            let fallback = (construction.kind == "area_near")
                .then(|| centroid(cells))
                .flatten()
                .map(|center| Fallback {
                    room: room_at(map, center).map(|r| room_mask(map, ctx, r)),
                    center,
                });
            Target::Region {
                cells: area(p),
                fallback,
            }
        }
        PlaceKind::AnyOf { members } => {
            Target::AnyOf(members.iter().map(|m| target_of(m, map, ctx)).collect())
        }
    }
}
