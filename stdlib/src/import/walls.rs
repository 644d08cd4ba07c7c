//! Walls of a house: faces merged into walls, open (`"empty"`) boundaries, and door and window
//! holes cut along the face they belong to.
//!
//! ProcTHOR lists every interior wall twice, once per room, and the two faces often run in
//! opposite directions. A hole's `holePolygon` x is measured along its own face `wall0`, from the
//! face's first bottom corner (`polygon[0]`) in the face's direction (the generator's
//! `doors.py` / `wall_objects.py` flip the position when `polygon[0]` is the larger end). So the
//! importer keeps each face's own direction beside the merged wall and cuts holes along the face.

use super::house::{House, HouseHole, wall_segment_from_id};
use super::raster::Raster;
use crate::grid::Cell;
use crate::map::error::{ErrCtx, MapError};
use std::collections::HashMap;

/// Tolerance for a hole reaching past its wall's end, metres (ids round endpoints to 1 cm).
const HOLE_END_TOLERANCE_M: f64 = 0.02;

/// One physical wall: the faces sharing a segment.
pub(super) struct Wall {
    pub ids: Vec<String>,
    pub a: [f64; 2],
    pub b: [f64; 2],
    pub height: f64,
    /// Every face is `"empty"`: the wall is not built.
    pub open: bool,
    /// The rooms of its faces (`room|n`), in face order, without repeats.
    pub rooms: Vec<String>,
}

/// A face as ProcTHOR lists it: its own start and end.
#[derive(Clone, Copy)]
pub(super) struct Face {
    pub a: [f64; 2],
    pub b: [f64; 2],
}

impl Face {
    pub fn len(&self) -> f64 {
        (self.b[0] - self.a[0]).hypot(self.b[1] - self.a[1])
    }
}

pub(super) struct WallSet {
    pub walls: Vec<Wall>,
    /// Face id -> the face and the index of its wall.
    pub faces: HashMap<String, (Face, usize)>,
    /// Whether the faces came from `walls[]` (else from floor-polygon edges).
    pub listed: bool,
}

fn seg_key(a: [f64; 2], b: [f64; 2]) -> [i64; 4] {
    let q = |v: f64| (v * 100.0).round() as i64;
    let (p, r) = ([q(a[0]), q(a[1])], [q(b[0]), q(b[1])]);
    if p <= r {
        [p[0], p[1], r[0], r[1]]
    } else {
        [r[0], r[1], p[0], p[1]]
    }
}

/// Merges faces into walls. `warn` hears about walls whose faces disagree on `empty`.
pub(super) fn collect_walls(house: &House, warn: &mut Vec<(String, String)>) -> WallSet {
    let mut walls: Vec<Wall> = Vec::new();
    let mut faces = HashMap::new();
    let mut index: HashMap<[i64; 4], usize> = HashMap::new();
    // Per wall: (empty faces, solid faces, first listed face path).
    let mut votes: Vec<(usize, usize, String)> = Vec::new();
    let mut add = |id: &str,
                   a: [f64; 2],
                   b: [f64; 2],
                   height: f64,
                   empty: bool,
                   room: Option<&str>,
                   path: String| {
        let key = seg_key(a, b);
        let i = *index.entry(key).or_insert_with(|| {
            walls.push(Wall {
                ids: Vec::new(),
                a,
                b,
                height,
                open: false,
                rooms: Vec::new(),
            });
            votes.push((0, 0, path));
            walls.len() - 1
        });
        let w = &mut walls[i];
        w.ids.push(id.to_string());
        w.height = w.height.max(height);
        if let Some(r) = room
            && !w.rooms.iter().any(|x| x == r)
        {
            w.rooms.push(r.to_string());
        }
        if empty {
            votes[i].0 += 1;
        } else {
            votes[i].1 += 1;
        }
        faces.entry(id.to_string()).or_insert((Face { a, b }, i));
    };
    let listed = !house.walls.is_empty();
    if listed {
        for (k, w) in house.walls.iter().enumerate() {
            add(
                &w.id,
                w.a,
                w.b,
                w.height,
                w.empty,
                w.room_id.as_deref(),
                format!("walls[{k}]"),
            );
        }
    } else {
        for (i, room) in house.rooms.iter().enumerate() {
            let p = &room.polygon;
            for k in 0..p.len() {
                let (a, b) = (p[k], p[(k + 1) % p.len()]);
                if a != b {
                    let id = format!(
                        "wall|{}|{:.2}|{:.2}|{:.2}|{:.2}",
                        i + 1,
                        a[0],
                        a[1],
                        b[0],
                        b[1]
                    );
                    add(&id, a, b, 2.5, false, Some(&room.id), String::new());
                }
            }
        }
    }
    for (w, (empty, solid, path)) in walls.iter_mut().zip(votes) {
        w.open = empty > 0 && solid == 0;
        if empty > 0 && solid > 0 {
            warn.push((
                format!("{path}.empty"),
                format!(
                    "wall {} is empty on one face and solid on the other; it is built as a wall",
                    w.ids[0]
                ),
            ));
        }
    }
    WallSet {
        walls,
        faces,
        listed,
    }
}

impl WallSet {
    /// The face a hole is cut in, measured along it. A house that lists its walls must list the
    /// hole's `wall0`; one without `walls[]` may name any segment by id.
    pub fn face_of(&self, hole: &HouseHole, path: &str, ctx: &ErrCtx) -> Result<Face, MapError> {
        if let Some((f, _)) = self.faces.get(&hole.wall0) {
            return Ok(*f);
        }
        if !self.listed
            && let Some((a, b)) = wall_segment_from_id(&hole.wall0)
        {
            return Ok(Face { a, b });
        }
        Err(ctx.err(
            format!("{path}.wall0"),
            format!(
                "names no wall of the house: {:?} is not the id of any face in walls[], so the {} \
                 cannot be placed (check the id against walls[].id)",
                hole.wall0,
                if path.starts_with("windows") {
                    "window"
                } else {
                    "door"
                }
            ),
        ))
    }

    /// The cells of a hole: the wall band along its face between the hole's ends. A hole reaching
    /// past the face's end is cut to it (with a warning); one starting beyond it is an error.
    pub fn hole_cells(
        &self,
        hole: &HouseHole,
        ras: &Raster,
        half_width: f64,
        path: &str,
        ctx: &ErrCtx,
        warn: &mut Vec<(String, String)>,
    ) -> Result<Vec<Cell>, MapError> {
        let face = self.face_of(hole, path, ctx)?;
        let len = face.len();
        if hole.along[0] >= len - HOLE_END_TOLERANCE_M || hole.along[1] <= HOLE_END_TOLERANCE_M {
            return Err(ctx.err(
                format!("{path}.holePolygon"),
                format!(
                    "spans {:.2}..{:.2} m along wall {}, which is {len:.2} m long: the hole is \
                     not on its wall",
                    hole.along[0], hole.along[1], hole.wall0
                ),
            ));
        }
        if hole.along[1] > len + HOLE_END_TOLERANCE_M || hole.along[0] < -HOLE_END_TOLERANCE_M {
            warn.push((
                format!("{path}.holePolygon"),
                format!(
                    "spans {:.2}..{:.2} m along wall {}, which is {len:.2} m long; the hole is \
                     cut to the wall's ends",
                    hole.along[0], hole.along[1], hole.wall0
                ),
            ));
        }
        Ok(ras
            .segment_cells(face.a, face.b, half_width)
            .into_iter()
            .filter(|&(_, t)| t >= hole.along[0] - 1e-9 && t <= hole.along[1] + 1e-9)
            .map(|(c, _)| c)
            .collect())
    }
}
