//! A validated grounding into RouteIR, building each place as the compiler's grounding does
//! (`m2rc_compiler::eval`): the same labels, cells, unions, `area_near` halos, through-waypoints
//! and loop waypoints, so Direct ID and a program naming the same places give equal RouteIR.

use super::places::{Ref, area_near, ir_place, start_place, union_place, value};
use super::validate::{Grounding, IdConstraint, Kind, ShapeType};
use m2rc_compiler::diagnostic::Code;
use m2rc_compiler::eval::{PlaceVal, THROUGH_REACH_M};
use m2rc_compiler::intent::GraphDiagnostic;
use m2rc_compiler::ir::{
    CellSet, Constraint, ConstraintKind, Construction, Direction, Pass, Place, PlaceKind,
    ROUTE_IR_VERSION, RouteIr, Shape, SourceSpan, Stage, StageScope,
};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::{MapQuery, WaypointShape, loop_waypoints};

fn empty(pointer: &str, message: String) -> Box<GraphDiagnostic> {
    Box::new(GraphDiagnostic::new(
        Code::EmptyPlace,
        pointer,
        message,
        None,
    ))
}

/// The RouteIR of `g` on `q`'s map from `start`.
pub fn build(g: &Grounding, q: &MapQuery, start: Cell) -> Result<RouteIr, Vec<GraphDiagnostic>> {
    let mut errors = Vec::new();
    let mut stages: Vec<Stage> = g
        .segments
        .iter()
        .map(|(name, r)| Stage {
            name: name.clone(),
            target: ir_place(q, &value(*r, start)),
            passes: vec![],
            span: SourceSpan::default(),
        })
        .collect();
    let mut constraints = Vec::new();
    for c in &g.constraints {
        let places: Vec<PlaceVal> = c.refs.iter().map(|r| value(*r, start)).collect();
        if c.kind == Kind::RequireVisit {
            if let Some(&i) = c.segments.as_ref().and_then(|s| s.first())
                && let Some(stage) = stages.get_mut(i)
            {
                stage.passes.extend(places.iter().map(|p| Pass {
                    place: ir_place(q, p),
                    span: SourceSpan::default(),
                }));
            }
            continue;
        }
        // The place where the constraint's first segment starts, for loops.
        let here = match c.segments.as_ref().and_then(|s| s.first()) {
            Some(&i) if i > 0 => value(g.segments[i - 1].1, start),
            _ => start_place(start),
        };
        let kind = match kind(c, &places, q, &here) {
            Ok(k) => k,
            Err(d) => {
                errors.push(*d);
                continue;
            }
        };
        let scope: Vec<PlaceVal> = c.scope.iter().map(|r| value(*r, start)).collect();
        constraints.push(Constraint {
            id: format!("c{}", constraints.len()),
            kind,
            stage_scope: match &c.segments {
                None => StageScope::Global,
                Some(s) => StageScope::Stages(s.clone()),
            },
            spatial_scope: (!scope.is_empty()).then(|| union_place(q, &scope)),
            span: SourceSpan::default(),
        });
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let map = q.map();
    Ok(RouteIr {
        version: ROUTE_IR_VERSION,
        map_id: map.map_id.clone(),
        grid_size: map.n(),
        resolution_m: q.res(),
        start,
        stages: std::mem::take(&mut stages),
        constraints,
        route_bindings: vec![],
    })
}

/// The constraint's place list as one place, through `area_near` when `within_m` is given.
fn reference(
    c: &IdConstraint,
    places: &[PlaceVal],
    q: &MapQuery,
) -> Result<Place, Box<GraphDiagnostic>> {
    let Some(w) = c.within_m else {
        return Ok(union_place(q, places));
    };
    let mut halos = Vec::new();
    for p in places {
        match area_near(q, p, w) {
            Some(h) => halos.push(h),
            None => {
                return Err(empty(
                    &format!("{}/within_m", c.pointer),
                    format!(
                        "the area within {w} m of {} covers no cell of the map",
                        p.label(q)
                    ),
                ));
            }
        }
    }
    Ok(union_place(q, &halos))
}

fn kind(
    c: &IdConstraint,
    places: &[PlaceVal],
    q: &MapQuery,
    here: &PlaceVal,
) -> Result<ConstraintKind, Box<GraphDiagnostic>> {
    Ok(match c.kind {
        Kind::Forbid => ConstraintKind::Avoid {
            place: reference(c, places, q)?,
        },
        Kind::PreferNear => ConstraintKind::Near {
            reference: reference(c, places, q)?,
        },
        Kind::PreferFar => ConstraintKind::Far {
            reference: reference(c, places, q)?,
        },
        Kind::PreferRelative => {
            let (a, b) = (ir_place(q, &places[0]), ir_place(q, &places[1]));
            let (closer, farther) = if c.closer_to_first { (a, b) } else { (b, a) };
            ConstraintKind::Relative { closer, farther }
        }
        Kind::PreferPathShape => match c.shape {
            Some((ShapeType::Through, _)) => through(c, places, q)?,
            Some((t, dir)) => loop_shape(c, t, dir, &places[0], q, here)?,
            None => unreachable_shape(c)?,
        },
        Kind::RequireVisit => unreachable_shape(c)?,
    })
}

fn unreachable_shape(c: &IdConstraint) -> Result<ConstraintKind, Box<GraphDiagnostic>> {
    Err(Box::new(GraphDiagnostic::new(
        Code::GraphShape,
        &c.pointer,
        "constraint without a shape",
        None,
    )))
}

fn waypoint(cells: Vec<Cell>, from: String, radius_m: Option<f64>, label: String) -> Place {
    Place {
        kind: PlaceKind::Region {
            construction: Construction {
                kind: "waypoint".into(),
                from: vec![from],
                radius_m,
            },
        },
        label,
        cells: CellSet::new(cells),
    }
}

/// `through(a, b, ...)`: free floor within reach of each place, a room's own free floor.
fn through(
    c: &IdConstraint,
    places: &[PlaceVal],
    q: &MapQuery,
) -> Result<ConstraintKind, Box<GraphDiagnostic>> {
    let mut waypoints = Vec::new();
    for (i, p) in places.iter().enumerate() {
        let t = p.target(q);
        let room = matches!(p, PlaceVal::Room(_));
        let mut cells: Vec<Cell> = if room {
            q.cells(t).to_vec()
        } else {
            q.area_near(t, THROUGH_REACH_M)
        };
        cells.retain(|&x| q.is_traversable(x));
        let label = p.label(q);
        if cells.is_empty() {
            return Err(empty(
                &format!("{}/ref_ids/{i}", c.pointer),
                format!("no free floor by {label} to pass"),
            ));
        }
        waypoints.push(waypoint(
            cells,
            label.clone(),
            (!room).then_some(THROUGH_REACH_M),
            format!("waypoint {}: by {label}", i + 1),
        ));
    }
    Ok(ConstraintKind::PathShape {
        shape: Shape::Through,
        direction: None,
        around: union_place(q, places),
        waypoints,
    })
}

fn polyline_m(q: &MapQuery, from: Option<Cell>, wps: &[Vec<Cell>]) -> f64 {
    let mut pts: Vec<[f64; 2]> = from
        .map(|c| [c.row as f64, c.col as f64])
        .into_iter()
        .collect();
    pts.extend(wps.iter().filter_map(|w| MapQuery::centroid(w)));
    pts.windows(2)
        .map(|w| (w[0][0] - w[1][0]).hypot(w[0][1] - w[1][1]))
        .sum::<f64>()
        * q.res()
}

/// A circle or wall-following loop, from the free cell of the segment's start nearest its
/// centre; with no direction, the shorter way (ties: counterclockwise), as the compiler does.
fn loop_shape(
    c: &IdConstraint,
    t: ShapeType,
    dir: Option<Direction>,
    x: &PlaceVal,
    q: &MapQuery,
    here: &PlaceVal,
) -> Result<ConstraintKind, Box<GraphDiagnostic>> {
    let centre = here.center(q).unwrap_or([0.0, 0.0]);
    let from = q.band(here.target(q)).into_iter().min_by(|a, b| {
        let d = |c: &Cell| (c.row as f64 - centre[0]).hypot(c.col as f64 - centre[1]);
        d(a).total_cmp(&d(b)).then(a.cmp(b))
    });
    let (shape, wshape) = match t {
        ShapeType::FollowWall => (Shape::FollowWall, WaypointShape::Walls),
        _ => (Shape::Circle, WaypointShape::Circle),
    };
    let room = match x {
        PlaceVal::Room(r) if t == ShapeType::FollowWall => Some(*r),
        _ => x.room_of(q),
    };
    let dirs = match dir {
        Some(d) => vec![d],
        None => vec![Direction::Clockwise, Direction::Counterclockwise],
    };
    let mut options: Vec<(Direction, Vec<Vec<Cell>>, f64)> = dirs
        .into_iter()
        .map(|d| {
            let w = loop_waypoints(
                q,
                wshape,
                x.target(q),
                room,
                d == Direction::Clockwise,
                from,
            );
            let len = polyline_m(q, from, &w);
            (d, w, len)
        })
        .collect();
    let pick = if options.len() == 2 && options[0].2 < options[1].2 - 1e-9 {
        0
    } else {
        options.len() - 1
    };
    let (d, wps, _) = options.swap_remove(pick);
    let wps: Vec<Vec<Cell>> = wps.into_iter().filter(|w| !w.is_empty()).collect();
    let al = x.label(q);
    if wps.len() < 2 {
        return Err(empty(
            &format!("{}/ref_ids/0", c.pointer),
            format!("no room to move around {al}: fewer than two free waypoints"),
        ));
    }
    let waypoints = wps
        .into_iter()
        .enumerate()
        .map(|(i, cells)| {
            waypoint(
                cells,
                al.clone(),
                Some(0.25),
                format!("waypoint {} around {al}", i + 1),
            )
        })
        .collect();
    Ok(ConstraintKind::PathShape {
        shape,
        direction: Some(d),
        around: ir_place(q, x),
        waypoints,
    })
}

/// Whether a place of the RouteIR is one the catalog names (for gold ids).
pub fn catalog_ref(p: &Place) -> Option<Ref> {
    match p.kind {
        PlaceKind::Object { id, .. } => Some(Ref::Object(id)),
        PlaceKind::Room { id, .. } => Some(Ref::Room(id)),
        PlaceKind::Region { ref construction } if construction.kind == "start" => Some(Ref::Start),
        _ => None,
    }
}
